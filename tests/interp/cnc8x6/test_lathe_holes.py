"""Drilling and tapping on a lathe's spindle axis in CNC8x6 and ISG: neither manual has a drilling
cycle on the lathe, so a hole is a G01 along Z at X0 with a drill and a thread a G33 along Z at X0
with a tap (docs/dialects/cnc8x6.md, isg.md). The holes are measured on the part's mesh, sliced
by trimesh (tests/support/geometry.py), against values derived by hand:

- a twist drill of diameter d with a 118 degree point fed to Z = -depth leaves a bore of radius
  d/2 down to -depth + cone, cone = (d/2) / tan(59 deg), then the point's cone down to -depth,
  whose radius at height h above the tip is h tan(59 deg);
- an ISO metric tap M10x1.5 (its crest at D/2 = 5) under G33 from Z3 makes the nut's groove with
  its root at r = 5, centred where a thread tool's point would be: z = 3 + P rho phi / 360 (mod P),
  rho = +1 under M03, -1 under M04 (as tests/stock/test_axial_tools.py).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import cutsim
from support.geometry import load, section, wrap

TOL = 0.002
D_DRILL, DEPTH = 8.5, 25.0
CONE = D_DRILL / 2.0 / math.tan(math.radians(59.0))  # 2.5537 mm
SETUP = """[machine]
kind = "lathe"
dialect = "{dialect}"
start = [40.0, 0.0, 50.0]
[stock]
shape = "cylinder"
diameter = 40
z = [-50, 0]
[[tool]]
number = 1
kind = "drill"
diameter = 8.5
point_angle = 118
length = 60
[[tool]]
number = 2
kind = "tap"
diameter = 10
pitch = {pitch}
length = 25
[simulation]
tolerance = 0.002
"""
# 19.5 mm from Z3 to Z-16.5: 13 leads of 1.5, so the return (M04, along the same helix) starts at
# the zero pulse where the cut ended
PROGRAMS = {
    "cnc8x6": ("N10 G00 T1 S800 M03\nN20 X0 Z5.\nN30 G01 Z-25. F0.1\nN40 G00 Z5.\n"
               "N50 T2 S200 {spindle}\nN60 Z3.\nN70 G33 Z-16.5 F{lead}\nN80 {back}\nN90 G33 Z3. F{lead}\n"
               "N100 M05\nN110 G00 X80. Z50.\nN120 M30\n"),
    "isg": ("%holes\nN10 G51\nN15 T1 S800 M03\nN20 G00 X0 Z5\nN30 G01 Z-25 F80\nN40 G00 Z5\n"
            "N50 T2 S200 {spindle}\nN60 Z3\nN70 G33 Z-16.5 K{lead}\nN80 {back}\nN90 G33 Z3 K{lead}\n"
            "N100 M05\nN110 G00 X80 Z50\nN120 M30\n"),
}


def simulate(tmp_path, dialect: str, spindle: str = "M03", lead: float = 1.5, pitch: float = 1.5,
             until: str = ""):
    """The program of ``dialect``; ``until``: cut off before that block (an M30 there instead)."""
    back = "M04" if spindle == "M03" else "M03"
    setup = tmp_path / f"{dialect}.toml"
    setup.write_text(SETUP.format(dialect=dialect, pitch=pitch))
    text = PROGRAMS[dialect].format(spindle=spindle, lead=lead, back=back)
    if until:
        text = text.split(until)[0] + "N999 M30\n"
    return cutsim.simulate("p.nc", str(setup), text=text)


def inner_radius(segs: np.ndarray, z: float) -> float:
    """Smallest r where the section's boundary crosses height ``z`` (nan where none does)."""
    z0, z1, r0, r1 = segs[:, 0, 1], segs[:, 1, 1], segs[:, 0, 0], segs[:, 1, 0]
    hit = (np.minimum(z0, z1) <= z) & (np.maximum(z0, z1) >= z) & (np.abs(z1 - z0) > 1e-12)
    if not np.any(hit):
        return float("nan")
    t = (z - z0[hit]) / (z1[hit] - z0[hit])
    return float(np.min(r0[hit] + t * (r1[hit] - r0[hit])))


def assert_m10_groove(res, rho: int, z0: float = 3.0) -> None:
    """The M10x1.5 groove between Z-2 and Z-10, seen in three half-planes: nothing beyond D/2 = 5,
    its roots at r 5 (within 3 tolerances) centred at z0 + 1.5 rho phi / 360 (mod 1.5), to the root
    flat's half-width P/16 and 0.01."""
    mesh = load(res)
    for phi in (37.3, 151.9, 263.1):
        pts = section(mesh, phi).reshape(-1, 2)
        near = pts[(pts[:, 1] < -2.0) & (pts[:, 1] > -10.0) & (pts[:, 0] < 7.0)]
        assert float(near[:, 0].max()) <= 5.0 + 1e-6
        root = near[near[:, 0] > 5.0 - 3 * TOL]
        assert len(root) >= 6, phi
        expect = z0 + 1.5 * rho * phi / 360.0
        assert np.all(np.abs(wrap(root[:, 1] - expect, 1.5)) < 1.5 / 16.0 + 0.01), (phi, root[:5])


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
def test_drilled_bore_diameter_and_depth(tmp_path, dialect):
    """The drill's bore (before the tap: only the drilling blocks run, M30 after N40)."""
    res = simulate(tmp_path, dialect, until="N50")
    assert res.report["warnings"] == []
    mesh = load(res)
    for phi in (17.3, 133.9, 251.1):
        segs = section(mesh, phi)
        for z in (-3.0, -12.0, -DEPTH + CONE + 0.2):  # the bore: d/2 within the tolerance (chords inside)
            assert abs(inner_radius(segs, z) - D_DRILL / 2.0) <= 2 * TOL, (phi, z)
        for h in (0.5, 1.2, 2.0):  # the point's cone: h tan(59 deg) above the tip at -25
            assert abs(inner_radius(segs, -DEPTH + h) - h * math.tan(math.radians(59.0))) <= 2 * TOL, (phi, h)
        assert inner_radius(segs, -DEPTH - 0.01) > 19.9  # below the tip: solid (only the outside)
    # Pappus: the bore and the cone, pi r^2 (25 - cone) + pi r^2 cone / 3, to the stock polygon's factor
    k = res.report["stock_volume"] / (math.pi * 400.0 * 50.0)
    r2 = (D_DRILL / 2.0) ** 2
    expect = k * math.pi * r2 * (DEPTH - CONE + CONE / 3.0)
    assert abs(res.report["removed_volume"] - expect) <= 1e-4 * expect, (res.report["removed_volume"], expect)


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
@pytest.mark.parametrize("spindle,rho", [("M03", 1), ("M04", -1)])
def test_tapped_thread_root_and_phase(tmp_path, dialect, spindle, rho):
    """Drilled 8.5, tapped M10x1.5 from Z3 to Z-16.5 and back: the groove's root at r = 5 centred at
    3 + 1.5 rho phi / 360 (mod 1.5); the return on the same helix removes nothing more."""
    res = simulate(tmp_path, dialect, spindle)
    assert res.report["warnings"] == []
    assert_m10_groove(res, rho)
    one_way = simulate(tmp_path, dialect, spindle, until="N80").part.volume()
    assert abs(res.part.volume() - one_way) < 1e-6


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
def test_tap_programmed_with_the_wrong_lead_strips_the_thread(tmp_path, dialect):
    """A tap of pitch 1.5 programmed with a lead of 1.25: its teeth cross their own groove every
    turn and the crests shave the bore out towards D/2 = 5 (the flanks no longer stand)."""
    good = simulate(tmp_path, dialect)
    bad = simulate(tmp_path, dialect, lead=1.25)
    assert good.part.volume() - bad.part.volume() > 50.0


# -- the example ----------------------------------------------------------------------------------
TAPPED = "tapped M10x1.5"


@pytest.mark.parametrize("folder,change,failing", [
    ("cnc8x6-lathe", {"G33 Z-21. F1.5": "G33 Z-21. F1.25", "G33 Z3. F1.5": "G33 Z3. F1.25"}, {"removed", TAPPED}),  # pitch
    ("cnc8x6-lathe", {"G33 Z-21.": "G33 Z-12."}, {"removed", TAPPED}),  # too shallow
    ("cnc8x6-lathe", {"N80 T3 S200": "N80 T3 S200 M04", "N100 M04": "N100 M03"}, {TAPPED}),  # wrong hand
    ("cnc8x6-lathe", {"N70 G00 Z3.": "N70 G00 Z3.5", "G33 Z3. F1.5": "G33 Z3.5 F1.5"}, {"removed", TAPPED}),  # start
    ("cnc8x6-lathe", {}, set()),
    ("isg-lathe", {"G331 Z-20 K1.5": "G331 Z-20 K1.25"}, {"removed", TAPPED}),
    ("isg-lathe", {"G331 Z-20": "G331 Z-12"}, {"removed", TAPPED}),
    ("isg-lathe", {"G331 Z-20 K1.5": "G331 Z-20 K-1.5"}, {TAPPED}),  # a left-hand thread
    ("isg-lathe", {"N45 G00 Z3": "N45 G00 Z3.5", "G332 Z3": "G332 Z3.5"}, {TAPPED}),  # started 0.5 higher
    ("isg-lathe", {}, set()),
])
def test_drill_tap_example_fails_when_made_wrong(folder, change, failing):
    """examples/{cnc8x6,isg}-lathe/drill-tap-m10 pass their checks (also in tests/app/test_examples.py)
    and fail them when made wrong: the tap at the wrong pitch or stopped short fails the removed
    volume and the tapped thread (lead), the tap under M04 (K < 0 on ISG) its hand, the tap started
    0.5 mm higher its phase (and, on CNC8x6, whose G33 back from there no longer follows the
    helix, the volume)."""
    from conftest import REPO_EXAMPLES

    base = REPO_EXAMPLES / folder / "drill-tap-m10"
    program = base.with_suffix(".nc").read_text()
    for old, new in change.items():
        assert old in program
        program = program.replace(old, new)
    res = cutsim.simulate("p.nc", str(base.with_suffix(".toml")), text=program)
    assert res.report["warnings"] == []
    assert {c["name"] for c in res.report["checks"] if not c["passed"]} == failing
