"""The contour cycles CYCLE95, CYCLE94 and CYCLE96 with a tool nose radius
(docs/dialects/sinumerik-turning.md, "CYCLE95" rule 5 and the cycles' "cutsim assumes"): the nose is
kept tangent to the contour, as the controller's cycles do with G41/G42, so slopes and arcs come out
on the contour.

Numbers by hand. A tool of cutting edge position 3 (outside, hand R) has its theoretical tip at the
nose centre + (-rho, -rho) (radius, z). Run uncompensated with the tip on the contour, the nose centre
runs on the contour moved by (rho, rho), and the part is the envelope of the nose circles:
- on a 45 degree chamfer rising towards -Z (r + z = const) the centre lies rho sqrt(2) from the line,
  the part's surface rho (sqrt 2 - 1) off it, radially rho (sqrt 2 - 1) sqrt 2 = rho (2 - sqrt 2) too
  high (0.2343 for 0.4, 0.4686 for 0.8);
- on an arc (centre c, radius R) the centres run on the circle about c + (rho, rho) of radius R; a
  convex arc (the part inside) leaves the circle of radius R - rho about it, a concave one (the part
  outside) the circle of radius R + rho;
- on the 30 degree flank of CYCLE96 (falling towards the face at -Z, its outward normal (cos 30,
  -sin 30) in (radius, z)) the centre is rho (cos 30 - sin 30) from the line, the nose reaches
  rho (1 - cos 30 + sin 30) into the part, radially that / cos 30 = 0.7321 rho too deep.
Compensated, the part is the contour: measured on the chamfer, the arcs and the flank within the
tolerance, the volume by Pappus.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import cutsim
from cutsim.reports.measure import plane_section, radii_at
from cutsim.testing import assert_matches_design

SETUP = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [60.0, 0.0, 20.0]
[stock]
shape = "revolve"
profile = {profile}
[[tool]]
number = 1
kind = "turning"
insert = "V"
size = 9.525
tip_radius = {rho}
approach = 93.0
hand = "R"
[[tool]]
number = 2
kind = "turning"
insert = "V"
size = 6.35
tip_radius = {rho}
approach = 93.0
hand = "R"
side = "inside"
[[tool]]
number = 3
kind = "turning"
insert = "V"
size = 9.525
tip_radius = {rho}
approach = 93.0
hand = "L"
[simulation]
tolerance = 0.005
"""
BAR = "[[0, 0], [20, 0], [20, -40], [0, -40]]"  # a bar of 40, its face at Z0
# the shaft: a 45 degree chamfer (radius 6 at Z0 to 10 at Z-4), the cylinder of 20, a concave fillet
# R4 about (14, -10) up to the cylinder of 28, a convex rounding R4 about (14, -24) up to the
# cylinder of 36, the shoulder to the bar's 40 at Z-30
SHAFT = """KONT_A: G1 X12 Z0
X20 Z-4
Z-10
G2 X28 Z-14 CR=4
G1 Z-20
G3 X36 Z-24 CR=4
G1 Z-30
KONT_E: X40
"""
# the same contour run by the tip itself (the old uncompensated path): a deliberately wrong part
OLD = ("N10 G18 G90 G95 DIAMON\nN20 T1 D1\nN30 S500 M3 F0.2\nN40 G0 X12 Z2\nN50 G1 Z0\nN60 X20 Z-4\n"
       "N70 Z-10\nN80 G2 X28 Z-14 CR=4\nN90 G1 Z-20\nN100 G3 X36 Z-24 CR=4\nN110 G1 Z-30\nN120 X42\n"
       "N130 G0 X60 Z20\nN140 M30\n")
ROOT = math.sqrt(16.0 - 4.0)  # an arc R4 two mm (along Z) from its centre


def program(vari: int) -> str:
    call = f'CYCLE95("KONT_A:KONT_E", 2, 0, 0, 0, 0.25, 0.15, 0.1, {vari}, 0, 0, 1)'
    return (f"N10 G18 G90 G95 DIAMON\nN20 T1 D1\nN30 S500 M3 F0.2\nN40 G0 X44 Z5\nN50 {call}\n"
            f"N60 G0 X60 Z20\nN70 M30\n{SHAFT}")


def run(tmp_path: Path, text: str, rho: float, profile: str = BAR):
    (tmp_path / "setup.toml").write_text(SETUP.format(profile=profile, rho=rho))
    return cutsim.simulate("nose.mpf", str(tmp_path / "setup.toml"), text=text, checks=False)


# (z, the contour's radius there, the radius the uncompensated tip leaves for nose rho)
PROBES = [
    (-2.0, 8.0, lambda rho: 8.0 + rho * (2.0 - math.sqrt(2.0))),  # the chamfer
    (-12.0, 14.0 - ROOT, lambda rho: 14.0 + rho - math.sqrt((4.0 + rho) ** 2 - (2.0 + rho) ** 2)),  # concave
    (-22.0, 14.0 + ROOT, lambda rho: 14.0 + rho + math.sqrt((4.0 - rho) ** 2 - (2.0 - rho) ** 2)),  # convex
]


def off_contour(part, tol: float) -> list[str]:
    """Where the part is not the shaft's contour (the smallest radius at each probe)."""
    bad = []
    for z, r, _ in PROBES:
        got = float(radii_at(part, z).min())
        if abs(got - r) > tol:
            bad.append(f"Z{z:g}: radius {got:.4f}, contour {r:.4f}")
    return bad


def pappus(rho: float = 0.0) -> float:
    """The finished shaft's volume (the bar from Z0 to -40): frustums and cylinders, and the quarter
    arcs r = 14 -/+ sqrt(16 - u^2), u in [0, 4]: pi (4 (196 + 16) - 64 / 3 -/+ 28 * 4 pi) (the integral
    of sqrt(16 - u^2) over [0, 4] is a quarter disc, 4 pi). A nose of radius rho cannot reach into
    the two square inner corners (radius 14 at Z-20, 18 at Z-30): each keeps the spandrel between the
    corner and the nose, area (1 - pi / 4) rho^2, its centroid (10 - 3 pi) / (3 (4 - pi)) rho from
    the corner along each leg, revolved (Pappus)."""
    chamfer = math.pi * 4.0 * (36.0 + 60.0 + 100.0) / 3.0
    cylinders = math.pi * 6.0 * (100.0 + 196.0 + 324.0) + math.pi * 400.0 * 10.0
    arcs = 2.0 * math.pi * (4.0 * 212.0 - 64.0 / 3.0)  # the +-28 * 4 pi terms cancel
    k = (10.0 - 3.0 * math.pi) / (3.0 * (4.0 - math.pi))
    spandrels = sum(2.0 * math.pi * (r + k * rho) * (1.0 - math.pi / 4.0) * rho * rho for r in (14.0, 18.0))
    return chamfer + cylinders + arcs + spandrels


STOCK = math.pi * 400.0 * 40.0


@pytest.mark.parametrize("rho", [0.4, 0.8])
@pytest.mark.parametrize("vari", [9, 5])  # complete; finishing only
def test_cycle95_finishes_the_chamfer_and_arcs_on_the_contour(tmp_path, rho, vari):
    res = run(tmp_path, program(vari), rho)
    assert off_contour(res.part, 0.01) == []
    assert not [w for w in res.program.warnings if "nose" in w[1]]
    # Pappus: the part's share of the bar (the chordal error of the revolved solids cancels mostly)
    assert res.report["part_volume"] / res.report["stock_volume"] == pytest.approx(pappus(rho) / STOCK, rel=1e-4)


@pytest.mark.parametrize("rho", [0.4, 0.8])
def test_the_old_uncompensated_path_is_off_by_the_derived_amounts(tmp_path, rho):
    # the tip run on the contour: the probes find the envelopes derived above, and the check fails
    res = run(tmp_path, OLD, rho)
    for z, _, old in PROBES:
        assert float(radii_at(res.part, z).min()) == pytest.approx(old(rho), abs=0.01), z
    bad = off_contour(res.part, 0.01)
    assert len(bad) == 3, bad
    assert abs(res.report["part_volume"] / res.report["stock_volume"] - pappus(rho) / STOCK) > 1e-3


def test_cycle95_roughing_levels_end_where_the_nose_touches_the_allowance(tmp_path):
    # VARI 1 with FALX 0.2 / FALZ 0.1 and nose 0.8: the level cuts stay axis-parallel (the tip is the
    # nose's lowest point for edge 3) and the roughed chamfer lies the allowance box's corner above
    # the contour: (r - 0.2) + (z - 0.1) = 6 there (the box corner (0.2, 0.1) moves the line r + z = 6),
    # radially 0.3 above the contour at Z-2 (8.3), nothing of the contour cut
    call = 'CYCLE95("KONT_A:KONT_E", 2, 0.1, 0.2, 0, 0.25, 0.15, 0.1, 1, 0, 0, 1)'
    text = program(9).replace('CYCLE95("KONT_A:KONT_E", 2, 0, 0, 0, 0.25, 0.15, 0.1, 9, 0, 0, 1)', call)
    res = run(tmp_path, text, 0.8)
    got = float(radii_at(res.part, -2.0).min())
    assert got == pytest.approx(8.3, abs=0.01)


def bore_radius(part, z: float) -> float:
    pts = np.concatenate(plane_section(part, "z", z))
    return float(np.hypot(pts[:, 0], pts[:, 1]).min())


@pytest.mark.parametrize("rho", [0.4, 0.8])
def test_cycle95_inside_chamfer_with_a_nose(tmp_path, rho):
    # VARI 11 in the tube 50 / 20: the bore's mouth chamfered 45 degrees from radius 18 at Z0 to 16 at
    # Z-2, the bore 32 to Z-15, 24 to Z-30 (an inside tool: edge 2, its tip the centre + (rho, -rho));
    # uncompensated the chamfer would be rho (2 - sqrt 2) radially short of the contour
    bore = "KONT_A: G1 X36 Z0\nX32 Z-2\nZ-15\nX24\nZ-30\nKONT_E: X20\n"
    call = 'CYCLE95("KONT_A:KONT_E", 2, 0, 0, 0, 0.25, 0.15, 0.1, 11, 0, 0, 1)'
    text = (f"N10 G18 G90 G95 DIAMON\nN20 T2 D1\nN30 S500 M3 F0.2\nN40 G0 X10 Z5\nN50 {call}\n"
            f"N60 G0 X10 Z20\nN70 M30\n{bore}")
    res = run(tmp_path, text, rho, "[[10, 0], [25, 0], [25, -40], [10, -40]]")
    for z, r in ((-1.0, 17.0), (-8.0, 16.0), (-20.0, 12.0)):
        assert bore_radius(res.part, z) == pytest.approx(r, abs=0.01), z
    assert rho * (2.0 - math.sqrt(2.0)) > 0.2


@pytest.mark.parametrize("rho", [0.4, 0.8])
def test_cycle95_face_chamfer_with_a_nose(tmp_path, rho):
    # VARI 10 (face, outside) on the bar of 40: the spigot of 20, 8 long, its chamfer from radius 10 at
    # Z-2 to 5 at Z0 (radius 7.5 at Z-1); the outside tool cuts towards the axis
    face = "KONT_A: G1 X40 Z-8\nX20\nZ-2\nX10 Z0\nKONT_E: X0\n"
    call = 'CYCLE95("KONT_A:KONT_E", 2, 0, 0, 0, 0.25, 0.15, 0.1, 10, 0, 0, 1)'
    text = (f"N10 G18 G90 G95 DIAMON\nN20 T1 D1\nN30 S500 M3 F0.2\nN40 G0 X44 Z5\nN50 {call}\n"
            f"N60 G0 X60 Z20\nN70 M30\n{face}")
    res = run(tmp_path, text, rho)
    for z, r in ((-1.0, 7.5), (-5.0, 10.0), (-20.0, 20.0)):
        assert float(radii_at(res.part, z).min()) == pytest.approx(r, abs=0.01), z


def test_cycle95_refuses_a_fillet_narrower_than_the_nose(tmp_path):
    # the fillet R4 replaced by one of 0.7 (from the cylinder at Z-13.3 to the face at radius 10.7)
    text = program(9).replace("Z-10\nG2 X28 Z-14 CR=4", "Z-13.3\nG2 X21.4 Z-14 CR=0.7\nG1 X28")
    (tmp_path / "setup.toml").write_text(SETUP.format(profile=BAR, rho=0.8))
    with pytest.raises(cutsim.CutsimError) as e:
        cutsim.simulate("nose.mpf", str(tmp_path / "setup.toml"), text=text, checks=False)
    assert "narrower than the tool's nose radius 0.8" in str(e.value)


# ---------------------------------------------------------------------------------------------
# CYCLE96 form A, M16 (pitch 2: dd 3, g2 7, r 1) at the face Z-30 and CYCLE94 form E, D 20 (DIN 509:
# r 0.6, t1 0.3, f 2.5, ramp 15 degrees)
FACE = -30.0


def undercut_part(tmp_path, call: str, d: float, rho: float):
    profile = f"[[0, 0], [{d / 2}, 0], [{d / 2}, {FACE}], [{d / 2 + 10}, {FACE}], [{d / 2 + 10}, -50], [0, -50]]"
    text = f"N10 G18 G90 G95 T1 D1\nN20 S500 M3 F0.1\nN30 G0 X{d + 10} Z5\nN40 {call}\nN50 G0 Z20\nN60 M30\n"
    return run(tmp_path, text, rho, profile).part


@pytest.mark.parametrize("rho", [0.4, 0.8])
def test_cycle96_flank_and_floor_with_a_nose(tmp_path, rho):
    part = undercut_part(tmp_path, 'CYCLE96(16, -30, "A", 3)', 16.0, rho)
    tan30 = math.tan(math.radians(30.0))
    run_z = 1.5 / tan30  # the flank's length along Z: depth 1.5 at 30 degrees
    z = FACE + 7.0 - run_z / 2.0
    flank = 8.0 - 0.75  # halfway down the flank
    got = float(radii_at(part, z).min())
    assert got == pytest.approx(flank, abs=0.01)
    # uncompensated the nose would leave it rho (1 - cos 30 + sin 30) / cos 30 deeper (0.2928 for
    # 0.4, 0.5857 for 0.8; measured so on the old path): far outside the tolerance
    old = flank - rho * (1 - math.cos(math.radians(30)) + 0.5) / math.cos(math.radians(30))
    assert abs(got - old) > 0.25
    assert float(radii_at(part, FACE + 1.0 + (7.0 - run_z - 1.0) / 2.0).min()) == pytest.approx(6.5, abs=0.01)
    assert float(radii_at(part, FACE + 7.5).min()) == pytest.approx(8.0, abs=0.01)  # the cylinder beyond


@pytest.mark.parametrize("rho", [0.4])
def test_cycle94_ramp_with_a_nose(tmp_path, rho):
    # form E, D 20: the ramp from radius 10 at Z-27.5 down at 15 degrees to the floor 9.7
    part = undercut_part(tmp_path, 'CYCLE94(20, -30, "E", 3)', 20.0, rho)
    run_z = 0.3 / math.tan(math.radians(15.0))
    z = FACE + 2.5 - run_z / 2.0
    got = float(radii_at(part, z).min())
    assert got == pytest.approx(10.0 - 0.15, abs=0.01)
    # uncompensated: rho (1 - cos 15 + sin 15) / cos 15 = 0.1218 deeper (measured so on the old path)
    assert abs(got - (9.85 - rho * (1 - math.cos(math.radians(15)) + math.sin(math.radians(15)))
                      / math.cos(math.radians(15)))) > 0.1
    assert float(radii_at(part, FACE + 0.6 + (2.5 - run_z - 0.6) / 2.0).min()) == pytest.approx(9.7, abs=0.01)


def test_cycle94_refuses_a_fillet_narrower_than_the_nose(tmp_path):
    with pytest.raises(cutsim.CutsimError) as e:
        undercut_part(tmp_path, 'CYCLE94(20, -30, "E", 3)', 20.0, 0.8)
    assert "smaller than the tool's nose radius 0.8" in str(e.value)


@pytest.mark.parametrize("rho", [0.4, 0.8])
def test_cycle95_relief_shaft_with_a_nose_against_its_design(tmp_path, rho):
    # test_cycle95's relief cut shaft (its contour and design) complete with a nose: nothing of the
    # design removed (within the chords: the nose's polygon rolling round the outer corners, under
    # 0.02 mm^3), and the part's farthest point from the design is the nose's rounding in the square
    # inner corner at the collar (radius 13 to the face at Z-35): the spandrel's point on the
    # bisector, rho (sqrt 2 - 1) from the corner, lies rho (1 - 1 / sqrt 2) from each leg
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    import test_cycle95 as c95

    (tmp_path / "setup.toml").write_text(c95.SETUP.format(profile=c95.BAR).replace("tip_radius = 0.0",
                                                                                     f"tip_radius = {rho}"))
    res = cutsim.simulate("c95.mpf", str(tmp_path / "setup.toml"), text=c95.prog(c95.RELIEF, c95.c95(9)))
    rec = assert_matches_design(res, c95.design(c95.EXACT, 15), tol=rho + 0.01, max_gouge=0.02)
    assert rec["details"]["worst_deviation"] == pytest.approx(rho * (1 - 1 / math.sqrt(2)), abs=0.01)


@pytest.mark.parametrize("rho", [0.4, 0.8])
@pytest.mark.parametrize("form", ["A", "B", "C", "D"])
def test_cycle96_every_form_with_a_nose(tmp_path, form, rho):
    # test_cycle96's M16 (pitch 2, r 1) outside (edge 3) and inside (edge 2) with a nose: its hand
    # derived checks (floor, cylinder beyond, flank) within 0.01 and the ring by Pappus (the nose's
    # spandrel in the 150 degree corner of flank and floor, rho^2 (cot 75 - pi / 12) = 0.0062 rho^2
    # revolved, is under 1e-3 of the ring). The tip run on the contour fails the same checks (the
    # flank 0.29 / 0.59 mm off, measured so when the cycle's nose is taken as 0).
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    import test_cycle96 as c96

    setup = c96.SETUP
    c96.SETUP = setup.replace("tip_radius = 0.0", f"tip_radius = {rho}")
    try:
        res, u = c96.cut(tmp_path, 16, 2.0, form)
    finally:
        c96.SETUP = setup
    assert c96.verdict(res.part, u, 0.01) == []
    removed = 1.0 - res.report["part_volume"] / res.report["stock_volume"]
    assert removed == pytest.approx(c96.ring_volume(u) / c96.stock_volume(u, 16), rel=3e-3)


@pytest.mark.parametrize("rho", [0.2, 0.4])
def test_cycle94_form_f_towards_minus_z_with_a_hand_l_tool(tmp_path, rho):
    # _VARI 4 with a hand L tool (edge 4: its tip the centre + (-rho, +rho)): the shaft of 20 runs from
    # the shoulder's face at Z-30 towards -Z, the undercut D 20 form F (r 0.6, t1 0.3, f 2.5, t2 0.2)
    # below it: the ramp's middle at Z-30 - (2.5 - run / 2) radius 9.85, the floor 9.7 (the fillet
    # tangent to the face moved t2 into the shoulder, Z-29.8), the shaft 10 beyond the ramp
    profile = "[[0, 0], [20, 0], [20, -30], [10, -30], [10, -50], [0, -50]]"
    text = "N10 G18 G90 G95 T3 D1\nN20 S500 M3 F0.1\nN30 G0 X30 Z-60\nN40 CYCLE94(20, -30, \"F\", 4)\nN50 G0 X60\nN60 M30\n"
    part = run(tmp_path, text, rho, profile).part
    run_z = 0.3 / math.tan(math.radians(15.0))
    assert float(radii_at(part, FACE - 2.5 + run_z / 2.0).min()) == pytest.approx(9.85, abs=0.01)
    assert float(radii_at(part, FACE - 0.6 - (2.5 - run_z - 0.6) / 2.0).min()) == pytest.approx(9.7, abs=0.01)
    # (the 8 degree relief into the face is not measured: the 93 degree insert's major edge, 3 degrees
    # off the face, cuts the shoulder beyond it with or without a nose -- the tool's shape, not its path)
    assert float(radii_at(part, FACE - 3.0).min()) == pytest.approx(10.0, abs=0.01)
