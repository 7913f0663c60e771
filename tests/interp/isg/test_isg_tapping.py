"""ISG tapping on a lathe's spindle axis with G331/G332 (TwinCAT CNC turning functions): G331 Z.. K..
feeds the tap with the spindle following it, K > 0 a right-hand thread, K < 0 a left-hand one; G332
backs it out with the spindle reversed along the same helix, whatever the depth.

Measured on the part's mesh (trimesh sections, tests/support/geometry.py): an M10x1.5 tap leaves the
nut's groove with its root at r = D/2 = 5, centred where a thread tool's point would pass:
z = 3 + P rho phi / 360 (mod P) for a tap entering at Z3 at the zero pulse, rho = +1 right hand,
-1 left hand (tests/stock/test_axial_tools.py derives it).
"""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

import cutsim
from cutsim.interp import InterpConfig, interpret

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "cnc8x6"))
from test_lathe_holes import assert_m10_groove  # noqa: E402

SETUP = """[machine]
kind = "lathe"
dialect = "isg"
start = [40.0, 0.0, 50.0]
[stock]
shape = "cylinder"
diameter = 16
z = [-25, 0]
[[tool]]
number = 2
kind = "drill"
diameter = 8.5
length = 60
[[tool]]
number = 3
kind = "tap"
diameter = 10
pitch = 1.5
length = 25
[simulation]
tolerance = 0.002
"""
DRILL = "%t\nN10 G51\nN15 T2 S800 M03\nN20 G00 X0 Z5\nN30 G01 Z-25 F80\nN40 G00 Z3\nN45 M05\nN50 T3\n"


def simulate(tmp_path, tapping: str, out: bool = True):
    """The drilling, then ``tapping``; then (``out``) away to X80 Z50, else the program ends where the
    tap stands."""
    setup = tmp_path / "s.toml"
    setup.write_text(SETUP)
    return cutsim.simulate("p.nc", str(setup), text=DRILL + tapping + ("N90 G00 X80 Z50\n" if out else "") + "N95 M30\n")


def test_records():
    """G331 from Z3 to Z-16 (19 mm: 12 2/3 turns, ending 240 degrees past the zero pulse) under
    K1.5 turns the spindle as M03; G332 reverses it and starts 120 degrees past the zero pulse in
    its own direction: the same physical angle, so the same helix. The spindle stands after it (the
    first record: S200 read with the spindle still stopped by M05)."""
    cfg = InterpConfig(dialect="isg", machine_kind="lathe", start=(40.0, 0.0, 50.0))
    prog = interpret("t.nc", DRILL + "N60 G331 Z-16 K1.5 S200\nN70 G332 Z3\nN95 M30\n", cfg)
    tail = [r for r in prog.records if r.src.line >= 9]
    kinds = [(type(r).__name__, getattr(r, "direction", None), getattr(r, "start_angle", None)) for r in tail]
    assert kinds == [("Spindle", 0, None), ("Spindle", 1, None), ("SyncedFeed", None, 0.0),
                     ("Spindle", -1, None), ("SyncedFeed", None, pytest.approx(120.0)), ("Spindle", 0, None),
                     ("ProgramEnd", None, None)]
    feeds = [r for r in tail if type(r).__name__ == "SyncedFeed"]
    assert [(f.lead, f.lead_axis, f.start[2], f.end[2]) for f in feeds] == [(1.5, "Z", 3.0, -16.0), (1.5, "Z", -16.0, 3.0)]


@pytest.mark.parametrize("k,rho", [("1.5", 1), ("-1.5", -1)])
def test_thread_root_and_hand(tmp_path, k, rho):
    res = simulate(tmp_path, f"N60 G331 Z-16 K{k} S200\nN70 G332 Z3\n")
    assert res.report["warnings"] == []
    assert_m10_groove(res, rho)


def test_g332_follows_the_helix_at_any_depth(tmp_path):
    """To Z-16 (off the zero pulse's phase): G332 back removes nothing more; a G33 back under M04
    from there starts at the zero pulse, off the helix, and strips the thread."""
    cut = simulate(tmp_path, "N60 G331 Z-16 K1.5 S200\n", out=False).part.volume()
    back = simulate(tmp_path, "N60 G331 Z-16 K1.5 S200\nN70 G332 Z3\n")
    assert back.report["warnings"] == []
    assert abs(back.part.volume() - cut) < 1e-3
    g33 = simulate(tmp_path, "N60 G331 Z-16 K1.5 S200\nN65 M04\nN70 G33 Z3 K1.5\n", out=False).part.volume()
    assert cut - g33 > 10.0


def test_two_g331_blocks_keep_the_helix(tmp_path):
    """Tapping in two blocks (Z3 -> Z-7 -> Z-16) cuts what one block cuts: the second continues the
    first's helix (10 mm = 6 2/3 turns: it starts 240 degrees past the zero pulse)."""
    one = simulate(tmp_path, "N60 G331 Z-16 K1.5 S200\n", out=False).part.volume()
    two = simulate(tmp_path, "N60 G331 Z-7 K1.5 S200\nN62 Z-16\n", out=False).part.volume()
    assert abs(one - two) < 1e-3


@pytest.mark.parametrize("text,message", [
    ("N60 G331 X2 Z-16 K1.5\n", "taps along Z: X must stay"),
    ("N60 G331 Z-16 K0\n", "must not be zero"),
    ("N60 G331 Z-16 I1.5\n", "programmed on K"),
    ("N60 G331 Z-16 K1.5\nN70 G332 Z3 K1.25\n", "it must be the G331's, 1.5"),
    ("N60 G331 Z-16 K1.5\nN65 G00 Z-10\nN70 G332 Z3\n", "G332 backs out the tap from where a G331 stopped"),
])
def test_refused(text, message):
    cfg = InterpConfig(dialect="isg", machine_kind="lathe", start=(40.0, 0.0, 50.0))
    with pytest.raises(cutsim.CutsimError, match=message):
        interpret("t.nc", DRILL + text + "N95 M30\n", cfg)
