"""An inside tool's boring bar as a solid: where it meets material still there when the tool
moves, a warning at the move's line (docs/setup.md, "Boring bars"); the bar never cuts.

The nut of the examples: a tube bored Ø20 through, outside Ø36, Z0..-20, bored to Ø22.376 by an
inside V tool (60 degrees, 3 mm high, sharp: its profile reaches 3 tan 30 = 1.732 mm above the
tool point, where the bar starts). A bar of diameter D whose axis lies f from the tool point,
at tool point radius r, covers the radii up to |r - f| + D/2 as the part turns past it.
"""
from __future__ import annotations

import math

import pytest

import cutsim
from cutsim.interp.errors import CutsimError

R_TIP = 22.376 / 2
PROGRAM = """\
N10 G00 G95 T1 S1500 M03
N20 G00 X19. Z2.
N30 X22.376
N40 G01 Z-22. F0.1
N50 X19.
N60 G00 Z2.
N70 Z20.
N80 M05
"""


def _setup(bar: str) -> str:
    return f"""\
[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [19.0, 0.0, 20.0]

[stock]
shape = "revolve"
profile = [[10, 0], [18, 0], [18, -20], [10, -20]]

[[tool]]
number = 1
kind = "turning"
angle = 60.0
tip_radius = 0.0
height = 3.0
side = "inside"
{bar}

[simulation]
tolerance = 0.002
"""


def _run(tmp_path, bar: str):
    prog, setup = tmp_path / "p.nc", tmp_path / "s.toml"
    prog.write_text(PROGRAM)
    setup.write_text(_setup(bar))
    return cutsim.simulate(str(prog), str(setup))


def _bar_warnings(res) -> list:
    return [(w["line"], w["message"]) for w in res.warnings if "boring bar" in w["message"]]


def test_a_bar_too_thick_for_the_bore_warns_at_the_line(tmp_path):
    """D 20, f 13 (a bar for bores from 25): at the boring pass (line 4, tool point r = 11.188) it
    reaches r = 13 - 11.188 + 10 = 11.812 on the far side, beyond the bore just cut: the ring
    11.188..11.812 over the whole 20 mm. One warning for the tool (the retract after it is not
    repeated); the part is the same as without a bar."""
    res = _run(tmp_path, "bar_diameter = 20.0\nbar_reach = 13.0")
    got = _bar_warnings(res)
    assert [line for line, _ in got] == [4], got
    vol = float(got[0][1].split("stock: ")[1].split(" mm^3")[0])
    reach = 13.0 - R_TIP + 10.0
    expected = math.pi * (reach ** 2 - R_TIP ** 2) * 20.0
    assert vol == pytest.approx(expected, rel=5e-3)
    plain = _run(tmp_path, "")
    assert res.part.volume() == plain.part.volume()
    assert _bar_warnings(plain) == []


def test_a_right_size_bar_does_not_warn(tmp_path):
    """D 16, f 11 (a bar for bores from 20): it reaches at most |11.188 - 11| + 8 = 8.188 at the
    boring pass and |9.5 - 11| + 8 = 9.5 on the retract at X19, inside the Ø20 bore."""
    res = _run(tmp_path, "bar_diameter = 16.0\nbar_reach = 11.0")
    assert _bar_warnings(res) == []


def test_the_default_reach_is_seven_tenths_of_the_diameter(tmp_path):
    """bar_reach 0 is 0.7 D: D 20 reaches 14 - 11.188 + 10 = 12.812 at the boring pass."""
    got = _bar_warnings(_run(tmp_path, "bar_diameter = 20.0"))
    vol = float(got[0][1].split("stock: ")[1].split(" mm^3")[0])
    reach = 14.0 - R_TIP + 10.0
    assert vol == pytest.approx(math.pi * (reach ** 2 - R_TIP ** 2) * 20.0, rel=5e-3)


@pytest.mark.parametrize("bar, line, key", [
    ("bar_diameter = 20.0\nbar_reach = 10.0", 19, "bar_reach"),  # the tool point must stand out of the bar
    ("bar_diameter = -1.0", 18, "bar_diameter"),
    ("bar_reach = 12.0", 18, "bar_reach"),  # a reach without a bar
])
def test_bar_ranges_are_errors_at_the_key(tmp_path, bar, line, key):
    with pytest.raises(CutsimError) as e:
        _run(tmp_path, bar)
    assert e.value.line == line and f"{key}: " in e.value.message, e.value


def test_an_outside_tool_has_no_bar(tmp_path):
    prog, setup = tmp_path / "p.nc", tmp_path / "s.toml"
    prog.write_text(PROGRAM)
    setup.write_text(_setup("bar_diameter = 16.0").replace('side = "inside"', 'side = "outside"'))
    with pytest.raises(CutsimError) as e:
        cutsim.simulate(str(prog), str(setup))
    assert "bar_diameter" in e.value.message and "inside" in e.value.message
