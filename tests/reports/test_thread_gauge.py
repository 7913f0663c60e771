"""The thread gauge: ISO 965-1 limits against printed tables, the pitch diameter of a simulated
M24x1.5 nut against the value derived from its program, designations in a setup, and the two
examples (nut M24x1.5-6H, shaft M30x2-6g) passing and failing when made wrong."""
import math
from pathlib import Path

import pytest

import cutsim
from cutsim.interp.errors import CutsimError
from cutsim.reports.iso965 import DesignationError, limits

EX = Path(__file__).resolve().parents[2] / "examples" / "cnc8x6-lathe"

# Printed limits (mm) of ISO 965-2 / ASME B1.13M tables for 6g, 4g6g and 6H as public thread
# charts list them: (designation, quantity, low, high)
TABLE = [
    ("M6x1-6g", "major_diameter", 5.794, 5.974), ("M6x1-6g", "pitch_diameter", 5.212, 5.324),
    ("M8x1.25-6g", "major_diameter", 7.760, 7.972), ("M8x1.25-6g", "pitch_diameter", 7.042, 7.160),
    ("M10x1.5-6g", "major_diameter", 9.732, 9.968), ("M10x1.5-6g", "pitch_diameter", 8.862, 8.994),
    ("M10x1.5-6g", "minor_diameter", None, 8.344), ("M10x1.25-6g", "pitch_diameter", 9.042, 9.160),
    ("M6x0.75-6g", "pitch_diameter", 5.391, 5.491), ("M3x0.5-6g", "pitch_diameter", 2.580, 2.655),
    ("M5x0.8-6g", "major_diameter", 4.826, 4.976), ("M4x0.7-6g", "pitch_diameter", 3.433, 3.523),
    ("M10x1.5-4g6g", "pitch_diameter", 8.909, 8.994), ("M6x1-4g6g", "pitch_diameter", 5.253, 5.324),
    ("M10x1.5-6H", "minor_diameter", 8.376, 8.676), ("M10x1.5-6H", "pitch_diameter", 9.026, 9.206),
    ("M12x1.5-6H", "pitch_diameter", 11.026, 11.216), ("M12x1.25-6H", "pitch_diameter", 11.188, 11.368),
    ("M12x1.75-6H", "minor_diameter", 10.106, 10.441), ("M14x2-6H", "pitch_diameter", 12.701, 12.913),
    ("M12x1-6H", "minor_diameter", 10.917, 11.153), ("M10x0.5-6H", "minor_diameter", 9.459, 9.599),
    ("M10x1.5-6H", "major_diameter", 10.0, None),
]


@pytest.mark.parametrize("designation,quantity,low,high", TABLE)
def test_iso965_limits_match_the_printed_tables(designation, quantity, low, high):
    got = limits(designation)[quantity]
    for g, want in zip(got, (low, high)):
        assert (g is None) == (want is None), (designation, quantity, got)
        if want is not None:
            assert abs(g - want) <= 0.0006, (designation, quantity, got)  # printed to 0.001


@pytest.mark.parametrize("text", ["M24x1.5-6k", "M24-6g", "M24x1.5-6g6H", "M24x1.5-2g", "M24x1.5-9H", "UNC 1/4-20"])
def test_bad_designations(text):
    with pytest.raises(DesignationError):
        limits(text)


def _setup(tmp_path, table):
    text = (EX / "nut-m24x1.5.toml").read_text().split("[[check]]")[0] + "[[check]]\n" + table
    p = tmp_path / "s.toml"
    p.write_text(text)
    return p, text


@pytest.mark.parametrize("table,msg", [
    ('kind = "thread"\nz = [-15.0, -5.0]\ndesignation = "M24x1.5-6k"\n', "designation: 'M24x1.5-6k' is not"),
    ('kind = "thread"\nz = [-15.0, -5.0]\ndesignation = "M24x1.5-6H"\nlead = 2.0\n', "is not lead / starts"),
    ('kind = "thread"\nz = [-15.0, -5.0]\ndesignation = "M24x1.5-6g"\nside = "inside"\n', "is an outside thread"),
])
def test_a_bad_designation_is_a_setup_error_at_its_line(tmp_path, table, msg):
    p, text = _setup(tmp_path, table)
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(p))
    assert msg in str(e.value)
    line = int(str(e.value).split(":")[1])
    key = "side" if "side" in msg or "outside" in msg else ("lead" if "lead /" in msg else "designation")
    want = [i + 1 for i, t in enumerate(text.splitlines()) if t.startswith(key if key != "lead" else "designation")]
    assert line in want or line > text.count("\n") - table.count("\n"), str(e.value)


@pytest.fixture(scope="module")
def nut():
    return cutsim.simulate(str(EX / "nut-m24x1.5.nc"), str(EX / "nut-m24x1.5.toml"))


def test_nut_pitch_diameter_from_the_program(nut):
    """Last pass X24.1, full-profile inside insert P = 1.5: its flat tip P/8 wide forms the root at
    X; the groove widens by 2 tan 30 per mm towards the axis and is P/2 wide (groove = ridge)
    (P/4 - P/16) / tan 30 = 3 sqrt(3) P / 16 nearer the axis: D2 = X - 3 sqrt(3) P / 8. Three
    wires of d = P / (2 cos 30) touch the flanks there, so the wire formula gives the same."""
    x, p = 24.1, 1.5
    d2 = x - 3.0 * math.sqrt(3.0) / 8.0 * p
    rec = nut.check(kind="thread", side="inside", z=[-15.0, -5.0], lead=p, pitch_diameter=d2, major_diameter=x,
                    minor_diameter=x - 5.0 * math.sqrt(3.0) / 8.0 * p, tolerance=0.002)
    assert rec["passed"], rec
    assert abs(rec["details"]["wire_diameter"] - p / (2 * math.cos(math.radians(30)))) < 1e-6


def test_the_examples_pass(nut):
    assert nut.passed, nut.checks
    r = cutsim.simulate(str(EX / "shaft-m30x2.nc"), str(EX / "shaft-m30x2.toml"))
    assert r.passed, r.checks
    assert not r.warnings


@pytest.mark.parametrize("name,old,new,failed", [
    ("nut-m24x1.5", "N170 X24.1", "N170 X23.95", {"major_diameter", "pitch_diameter", "pitch_diameter_wires"}),
    ("nut-m24x1.5", "N80 X19. Z4.5", "N80 X19. Z5.", {"phase[1]"}),
    ("nut-m24x1.5", "S1500 M03", "S1500 M04", {"hand"}),
    ("shaft-m30x2", "N370 X27.712", "N370 X27.812", {"pitch_diameter", "pitch_diameter_wires"}),
    ("shaft-m30x2", "N240 G00 X32. Z4.", "N240 G00 X32. Z4.5", {"phase[1]"}),
    ("shaft-m30x2", "N230 T3 D3 S800", "N230 T3 D3 S800 M04", {"hand"}),
])
def test_the_examples_fail_when_made_wrong(name, old, new, failed):
    text = (EX / f"{name}.nc").read_text()
    assert old in text
    if "Z4.5" in old or "Z4." in old:  # every pass starts there: shift them all
        text = text.replace(old.split()[-1] + "\n", new.split()[-1] + "\n")
    text = text.replace(old, new)
    r = cutsim.simulate(f"{name}-wrong.nc", str(EX / f"{name}.toml"), text=text)
    rec = next(c for c in r.checks if c["kind"] == "thread")
    got = {i["quantity"] for i in rec["items"] if not i["passed"]}
    assert failed <= got, (got, rec)
