"""bore, groove and shoulder checks on a turned part whose dimensions come from its program:
a bar of 40 turned to 25 up to a square shoulder at Z-30 (93 degree holder), grooved 3 wide to
X20 at Z-12..-9 (hand R: the corner towards -Z programmed), drilled 10 mm (118 degree point) on
the axis to Z-20. Each check passes, and fails when the program is made wrong."""
import math
from pathlib import Path

import pytest

import cutsim

EX = Path(__file__).resolve().parents[2] / "examples" / "cnc8x6-lathe"
# shoulder-93's machine, bar of 40 and CNMG 120408 in a 93 degree holder, with a grooving insert
# and a drill
SETUP = (EX / "shoulder-93.toml").read_text().split("[[check]]")[0] + """
[[tool]]
number = 2
kind = "grooving"
width = 3.0
corner_radius = 0.0
height = 8.0
hand = "R"

[[tool]]
number = 3
kind = "drill"
diameter = 10.0
point_angle = 118.0

[simulation]
tolerance = 0.005
"""

PROGRAM = """N10 G00 G95 T1 D1 S1200 M03
G00 X44. Z2.
X{x_turn}
G01 Z{z_shoulder} F0.2
X41.
G00 X50. Z20.
T2 D2 S600
G00 X28. Z-12.
G01 X{x_groove} F0.05
G00 X28.
X50. Z20.
T3 D3 S800
G00 X0 Z2.
G01 Z{z_drill} F0.1
G00 Z20.
M05
"""
GOOD = dict(x_turn="25.", z_shoulder="-30.", x_groove="20.", z_drill="-20.")
# the drill's point: the cone 5 / tan(59 deg) long below the full diameter
POINT = 5.0 / math.tan(math.radians(59.0))
CHECKS = {
    "bore": dict(kind="bore", face=0.0, diameter=10.0, depth=20.0 - POINT, tip_depth=20.0, tolerance=0.02),
    "groove": dict(kind="groove", at=-10.5, width=3.0, diameter=20.0, depth=2.5, center=-10.5, tolerance=0.02),
    "shoulder": dict(kind="shoulder", diameter=27.5, z=-30.0, tolerance=0.02),
}


def _run(tmp_path, **wrong):
    setup = tmp_path / "turned.toml"
    setup.write_text(SETUP)
    r = cutsim.simulate("turned.nc", str(setup), text=PROGRAM.format(**{**GOOD, **wrong}))
    return r


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("turned"))


@pytest.mark.parametrize("name", CHECKS)
def test_turned_checks_pass(good, name):
    rec = good.check(**CHECKS[name])
    assert rec["passed"], rec


@pytest.mark.parametrize("wrong,name,items", [
    (dict(z_drill="-19.9"), "bore", {"depth", "tip_depth"}),
    (dict(x_groove="20.1"), "groove", {"diameter", "depth"}),
    (dict(z_shoulder="-29.95"), "shoulder", {"z"}),
])
def test_turned_checks_fail_when_made_wrong(tmp_path, wrong, name, items):
    rec = _run(tmp_path, **wrong).check(**CHECKS[name])
    assert items <= {i["quantity"] for i in rec["items"] if not i["passed"]}, rec


def test_groove_width_and_bore_diameter_fail(good):
    rec = good.check(**{**CHECKS["groove"], "width": 3.1})
    assert {i["quantity"] for i in rec["items"] if not i["passed"]} == {"width"}
    rec = good.check(**{**CHECKS["bore"], "diameter": 10.1})
    assert "diameter" in {i["quantity"] for i in rec["items"] if not i["passed"]}
