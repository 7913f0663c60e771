"""CYCLE95 stock removal (interp/sinumerik/stockremoval.py, docs/dialects/sinumerik-turning.md
"CYCLE95"): every machining type, relief cuts, the allowances, and the parts -- their volumes by
Pappus (frustums of the profile) and the design compare against the contour.

The numbers are derived by hand from the contour and the parameters: the levels spread evenly from
the blank's surface down to the contour's start moved by the allowances, ceil(depth / MID) of them;
each cut ends where it meets the contour moved by FALX (radially) and FALZ (axially, towards the
side the face looks to); the roughed part is the region under that moved contour, the finished
part the contour itself. Volumes are compared as part / stock against the exact ratio (the solids
are revolved with the same segments, so the chordal error cancels in the ratio).
"""
from __future__ import annotations

import math
from pathlib import Path

import manifold3d as m3d
import numpy as np
import pytest

import cutsim
from cutsim.interp.canon import Arc, Feed, Rapid
from cutsim.kinematics.paths import circle_segments
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
tip_radius = 0.0
approach = 93.0
hand = "R"
[[tool]]
number = 2
kind = "turning"
insert = "V"
size = 6.35
tip_radius = 0.0
approach = 93.0
hand = "R"
side = "inside"
[simulation]
tolerance = 0.005
"""
BAR = "[[0, 0], [15, 0], [15, -40], [0, -40]]"  # a bar of 30, 40 long, its face at Z0
TUBE = "[[10, 0], [25, 0], [25, -40], [10, -40]]"  # a tube 50 / 20
TOL = 0.005


def prog(contour: str, call: str, tool: int = 1, start: str = "X40 Z5") -> str:
    return (f"N10 G18 G90 G95 DIAMON\nN20 T{tool} D1\nN30 S500 M3 F0.2\nN40 G0 {start}\nN50 {call}\n"
            f"N60 G0 X60 Z20\nN70 M30\n{contour}")


def c95(vari, mid=2.0, falz=0.1, falx=0.2, fal=0.0, vrt=1.0):
    return f'CYCLE95("KONT_A:KONT_E", {mid:g}, {falz:g}, {falx:g}, {fal:g}, 0.25, 0.15, 0.1, {vari}, 0, 0, {vrt:g})'


def sim(tmp_path: Path, text: str, profile: str = BAR):
    (tmp_path / "setup.toml").write_text(SETUP.format(profile=profile))
    return cutsim.simulate("c95.mpf", str(tmp_path / "setup.toml"), text=text)


def frustums(profile) -> float:
    """The volume of revolution under the radius profile [(r, z), ...] (Pappus for each piece: a
    frustum pi h (r1^2 + r1 r2 + r2^2) / 3)."""
    return sum(math.pi * abs(z2 - z1) * (r1 * r1 + r1 * r2 + r2 * r2) / 3
               for (r1, z1), (r2, z2) in zip(profile, profile[1:]))


def ratio(res) -> float:
    return res.report["part_volume"] / res.report["stock_volume"]


def design(outline, r_max: float):
    """The design solid: the region between the axis and the radius outline [(r, z)...] (from the
    top Z down), revolved with the stock's segments."""
    pts = [(0.0, outline[0][1])] + list(outline) + [(0.0, outline[-1][1])]
    region = m3d.CrossSection([pts[::-1]])  # counter-clockwise
    assert region.area() > 0
    return m3d.Manifold.revolve(region, circular_segments=circle_segments(r_max, TOL))


def cuts(res, feed):
    return [r for r in res.program.records if r.src.line == 5 and isinstance(r, (Feed, Arc)) and r.feed == feed]


# ---------------------------------------------------------------------------------------------
# a shaft with a relief cut: the cylinder of 20, a 1:3 flank down to the floor of 16, a rising
# flank to 26, the collar of 26 and the shoulder to the blank's 30
RELIEF = """KONT_A: G1 X20 Z0
Z-10
X16 Z-16
Z-22
X26 Z-28
Z-35
KONT_E: X30
"""
EXACT = [(10, 0), (10, -10), (8, -16), (8, -22), (13, -28), (13, -35), (15, -35), (15, -40)]
# moved by FALX 0.2 / FALZ 0.1: the falling flank towards -Z (its face looks to -Z), the rising
# flank towards +Z; the floor's corners where the moved flanks meet it: (8.2, -16.1), (8.2, -21.9)
ROUGH = [(10.2, 0), (10.2, -10.1), (8.2, -16.1), (8.2, -21.9), (13.2, -27.9), (13.2, -34.9), (15, -34.9),
         (15, -40)]
STOCK = math.pi * 15 ** 2 * 40


def test_relief_cut_roughing_levels_and_the_pocket(tmp_path):
    res = sim(tmp_path, prog(RELIEF, c95(201)))
    rough = cuts(res, 0.25)
    # the levels from radius 15 down to the start's 10 + 0.2: ceil(4.8 / 2) = 3 cuts of 1.6 from
    # Z 0 + 0.1 + 1; 13.4 meets the shoulder (Z-35 + 0.1), 11.8 and 10.2 the rising flank
    # (8.2 + 5 t = level, Z = -21.9 - 6 t), passing over the relief cut
    lines = [(r.start[0], r.end[2]) for r in rough if r.start[2] == pytest.approx(1.1) and r.start[0] == r.end[0]]
    want = [(13.4, -34.9), (11.8, -21.9 - 6 * 0.72), (10.2, -21.9 - 6 * 0.4)]
    assert lines == [pytest.approx(w) for w in want]
    # the relief cut: reached along the moved contour at FF2 0.15, down the falling flank to the
    # floor's corner (8.2, -16.1), the floor at FF1 to (8.2, -21.9), up the flank to the level 10.2
    plunge = cuts(res, 0.15)
    assert (plunge[-1].end[0], plunge[-1].end[2]) == pytest.approx((8.2, -16.1))
    floor = [r for r in rough if r.start[0] == pytest.approx(8.2) and r.end[0] == pytest.approx(8.2)]
    assert len(floor) == 1 and floor[0].end[2] == pytest.approx(-21.9)
    assert (rough[-1].end[0], rough[-1].end[2]) == pytest.approx((10.2, -24.3))
    # the roughed part is the moved contour's solid
    assert ratio(res) == pytest.approx(frustums(ROUGH) / STOCK, rel=1e-6)
    assert not res.warnings


@pytest.mark.parametrize("vari", [9, 209])
def test_relief_cut_complete_is_the_contour_and_matches_its_design(tmp_path, vari):
    res = sim(tmp_path, prog(RELIEF, c95(vari)))
    assert ratio(res) == pytest.approx(frustums(EXACT) / STOCK, rel=1e-6)
    for z, d in ((-5, 20), (-19, 16), (-31, 26), (-38, 30)):
        assert 2 * radii_at(res.part, z).min() == pytest.approx(d, abs=0.01)
    assert_matches_design(res, design(EXACT, 15), tol=0.01, max_gouge=0.01, max_excess=0.01)


def test_roughed_part_matches_its_design_within_the_allowance(tmp_path):
    res = sim(tmp_path, prog(RELIEF, c95(1)))
    target = design(EXACT, 15)
    # the farthest the moved contour gets from the design: at the outer corners, where the allowance
    # box's corner (FALX 0.2, FALZ 0.1) is hypot(0.2, 0.1) away; nothing of the design removed
    far = math.hypot(0.2, 0.1)
    rec = assert_matches_design(res, target, tol=far + 2e-3, max_gouge=0.01)
    assert rec["details"]["worst_deviation"] == pytest.approx(far, abs=2e-3)
    assert rec["details"]["excess_volume"] == pytest.approx(frustums(ROUGH) - frustums(EXACT), rel=1e-3)
    with pytest.raises(AssertionError):  # the allowance is left: not the finished part
        assert_matches_design(res, target, tol=0.05)


@pytest.mark.parametrize("wrong", [("X16 Z-16\nZ-22", "X14 Z-16\nZ-22"), ("X26 Z-28\nZ-35", "X24 Z-28\nZ-35")])
def test_a_wrong_contour_fails_the_design_compare(tmp_path, wrong):
    # a contour point moved in the program (the floor 1 mm deeper, the collar 1 mm smaller): the
    # finished part gouges the design
    res = sim(tmp_path, prog(RELIEF.replace(*wrong), c95(9)))
    with pytest.raises(AssertionError):
        assert_matches_design(res, design(EXACT, 15), tol=0.01, max_gouge=0.01)


def test_the_rounding_digit(tmp_path):
    # hundreds digit 0: the rounding of a cut runs over the intersection before it up to the one
    # before that (two levels up); 2: up to the intersection before (the level 11.8 ends at 13.4)
    ups = {}
    for vari in (1, 201):
        res = sim(tmp_path, prog(RELIEF, c95(vari)))
        rough = cuts(res, 0.25)
        k = next(i for i, r in enumerate(rough) if r.start[0] == pytest.approx(11.8) and r.end[0] == r.start[0])
        ups[vari] = rough[k + 3].end
        assert ratio(res) == pytest.approx(frustums(ROUGH) / STOCK, rel=1e-6)
    assert ups[201][0] == pytest.approx(13.4) and ups[1][0] == pytest.approx(15.0)


def test_the_contour_programmed_backwards_is_the_same_cycle(tmp_path):
    back = """KONT_A: G1 X30 Z-35
X26
Z-28
X16 Z-22
Z-16
X20 Z-10
KONT_E: Z0
"""
    fwd = sim(tmp_path, prog(RELIEF, c95(9)))
    rev = sim(tmp_path, prog(back, c95(9)))
    pos = [(round(r.end[0], 9), round(r.end[2], 9)) for r in fwd.program.records if r.src.line == 5]
    assert pos == [(round(r.end[0], 9), round(r.end[2], 9)) for r in rev.program.records if r.src.line == 5]


# ---------------------------------------------------------------------------------------------
# inside: a bore from the pre-drilled 20: the mouth 36 with a 1 x 45 degree chamfer to 32, a
# shoulder at Z-15 down to 24, the end face at Z-30 down to the bore's 20
BORE = """KONT_A: G1 X36 Z0
X32 Z-2
Z-15
X24
Z-30
KONT_E: X20
"""
BORE_EXACT = [(18, 0), (16, -2), (16, -15), (12, -15), (12, -30), (10, -30), (10, -40)]
TUBE_VOL = math.pi * (25 ** 2 - 10 ** 2) * 40


def _tube(profile) -> float:
    return math.pi * 25 ** 2 * 40 - frustums(profile)


def test_inside_roughing_levels(tmp_path):
    res = sim(tmp_path, prog(BORE, c95(3), tool=2, start="X10 Z5"), TUBE)
    # from the bore's radius 10 out to the start's 18 - 0.2: ceil(7.8 / 2) = 4 cuts of 1.95; the
    # two inner ones meet the shoulder moved to Z-15 + 0.1, the outer two the chamfer moved by
    # (-0.2, +0.1): radius 17.8 - 2 t at Z 0.1 - 2 t
    rough = cuts(res, 0.25)
    lines = [(r.start[0], r.end[2]) for r in rough if r.start[2] == pytest.approx(1.1) and r.start[0] == r.end[0]]
    want = [(11.95, -14.9), (13.9, -14.9), (15.85, 0.1 - 2 * 0.975), (17.8, 0.1)]
    assert lines == [pytest.approx(w) for w in want]
    rough_profile = [(17.8, 0), (17.7, -0.1 + 0.0), (15.8, -1.9), (15.8, -14.9), (11.8, -14.9), (11.8, -29.9),
                     (10, -29.9), (10, -40)]
    # the chamfer moved: through (17.8, 0.1) and (15.8, -1.9): at Z0 radius 17.7
    rough_profile = [(17.7, 0), (15.8, -1.9)] + rough_profile[3:]
    assert ratio(res) == pytest.approx(_tube(rough_profile) / TUBE_VOL, rel=1e-6)


def test_inside_complete_is_the_bore(tmp_path):
    res = sim(tmp_path, prog(BORE, c95(11), tool=2, start="X10 Z5"), TUBE)
    assert ratio(res) == pytest.approx(_tube(BORE_EXACT) / TUBE_VOL, rel=1e-6)
    for z, d in ((-8, 32), (-20, 24), (-35, 20)):  # the bore's diameters (the section's inner ring)
        pts = np.concatenate(plane_section(res.part, "z", z))
        assert 2 * float(np.hypot(pts[:, 0], pts[:, 1]).min()) == pytest.approx(d, abs=0.01)
    tube = design([(25, 0), (25, -40)], 25) - design(BORE_EXACT, 25)
    assert_matches_design(res, tube, tol=0.01, max_gouge=0.01)


# ---------------------------------------------------------------------------------------------
# face: the end of a bar of 30 turned to a spigot of 20, 8 long, with a 2 x 2.5 chamfer to Z0
FACE = """KONT_A: G1 X30 Z-8
X20
Z-2
X10 Z0
KONT_E: X0
"""


def test_face_roughing_levels(tmp_path):
    res = sim(tmp_path, prog(FACE, c95(2), start="X40 Z5"))
    # infeed along Z from the face Z0 down to the start's -8 + FALZ 0.1: ceil(7.9 / 2) = 4 cuts of
    # 1.975, each along -X from radius 15 + FALX 0.2 + 1 to the spigot moved by FALX: radius 10.2
    rough = cuts(res, 0.25)
    lines = [(r.start[2], r.end[0]) for r in rough if r.start[0] == pytest.approx(16.2) and r.start[2] == r.end[2]]
    assert lines == [pytest.approx((-1.975 * k, 10.2)) for k in range(1, 5)]
    # the roughed part: the bar to Z-7.9, the spigot of 10.2 to Z-1.9, the chamfer moved by
    # (0.2, 0.1) from (10.2, -1.9) towards (5.2, 0.1): radius 5.45 at the face Z0
    prof = [(5.45, 0), (10.2, -1.9), (10.2, -7.9), (15, -7.9), (15, -40)]
    assert ratio(res) == pytest.approx(frustums(prof) / STOCK, rel=1e-6)


def test_face_complete_is_the_spigot(tmp_path):
    res = sim(tmp_path, prog(FACE, c95(10), start="X40 Z5"))
    prof = [(5, 0), (10, -2), (10, -8), (15, -8), (15, -40)]
    assert ratio(res) == pytest.approx(frustums(prof) / STOCK, rel=1e-6)
    assert_matches_design(res, design(prof, 15), tol=0.01, max_gouge=0.01)


# ---------------------------------------------------------------------------------------------
# FAL: the allowance along the contour's normal
def test_fal_moves_the_contour_along_its_normal(tmp_path):
    # the chamfer 1 x 45 from (9, 0) to (10, -1) moved by FAL 0.3 along its normal (1, 1) / sqrt 2,
    # the cylinder of 20 by 0.3 radially, the shoulder at Z-20 by 0.3 towards +Z; the outer corner
    # (10, -1) rounded with 0.3 about it
    text = prog("KONT_A: G1 X18 Z0\nX20 Z-1\nZ-20\nKONT_E: X30\n", c95(1, mid=2.5, falz=0, falx=0, fal=0.3))
    res = sim(tmp_path, text)
    rough = cuts(res, 0.25)
    s = 0.3 / math.sqrt(2)
    # levels from 15 to 9 + s (the moved start): ceil((6 - s) / 2.5) = 3 of (6 - s) / 3
    d = (6 - s) / 3
    lines = [(r.start[0], r.end[2]) for r in rough if r.start[0] == r.end[0] and r.start[2] > 1]
    assert [x[0] for x in lines] == pytest.approx([15 - d, 15 - 2 * d, 15 - 3 * d])
    assert lines[0][1] == pytest.approx(-19.7)  # the shoulder moved by 0.3 towards +Z
    # the last level meets the moved chamfer at its start: Z 0 + s
    assert lines[-1][1] == pytest.approx(s)
    arc = [r for r in rough if isinstance(r, Arc)]
    assert arc and arc[0].center[0] == pytest.approx(10) and arc[0].center[2] == pytest.approx(-1)


# ---------------------------------------------------------------------------------------------
# a round relief cut: an arc of radius 8 (G2 CR=8) from (10, -10) to (10, -20), its centre at
# (10 + sqrt 39, -15): the floor at 16.245 - 8 = 8.245 (diameter 16.49)
ROUND = """KONT_A: G1 X20 Z0
Z-10
G2 X20 Z-20 CR=8
G1 Z-30
KONT_E: X30
"""


def _round_part() -> float:
    # the cylinder of 20 to Z-30 less the ring the arc cuts (Pappus: the circular segment's area
    # times the path of its centroid), the bar of 30 behind
    R, half = 8.0, math.asin(5 / 8)
    area = R * R * (2 * half - math.sin(2 * half)) / 2
    centroid = 4 * R * math.sin(half) ** 3 / (3 * (2 * half - math.sin(2 * half)))
    ring = 2 * math.pi * (10 + math.sqrt(39) - centroid) * area
    return math.pi * 100 * 30 - ring + math.pi * 225 * 10


def test_round_relief_cut_complete_and_roughed(tmp_path):
    res = sim(tmp_path, prog(ROUND, c95(9)))
    # the arc is cut along chords at the tolerance 0.005: the groove's 2 pi 9 x 10.8 = 610 mm^2 keep
    # up to 2/3 x 0.005 x 610 = 2.0 mm^3 more
    assert ratio(res) * STOCK == pytest.approx(_round_part() + 1.0, abs=1.05)
    assert 2 * radii_at(res.part, -15).min() == pytest.approx(2 * (10 + math.sqrt(39) - 8), abs=0.01)
    outline = [(10, 0), (10, -10)] + [(10 + math.sqrt(39) - 8 * math.cos(a), -15 + 8 * math.sin(a))
                                      for a in np.linspace(math.asin(5 / 8), -math.asin(5 / 8), 400)[1:-1]] \
        + [(10, -20), (10, -30), (15, -30), (15, -40)]
    assert_matches_design(res, design(outline, 15), tol=0.02, max_gouge=0.5)
    rough = sim(tmp_path, prog(ROUND, c95(1)))
    # roughed: nothing of the design removed, the allowance left (at most the box's corner away,
    # plus the chords of the moved arcs at the tolerance 0.005)
    rec = assert_matches_design(rough, design(outline, 15), tol=math.hypot(0.2, 0.1) + TOL, max_gouge=0.5)
    # the floor of the relief cut: the two quarter arcs moved by (0.2, -0.1) and (0.2, +0.1) meet
    # at Z-15, 8.245 + 0.2 - (8 - sqrt(64 - 0.1^2)) out
    floor = 10 + math.sqrt(39) + 0.2 - math.sqrt(64 - 0.01)
    assert radii_at(rough.part, -15).min() == pytest.approx(floor, abs=0.01)
    assert rec["passed"]


# ---------------------------------------------------------------------------------------------
# finishing only, and the face inside, in the records (no cutting)
def records(tmp_path, text):
    from cutsim import interp_config, load_setup
    from cutsim.interp import interpret

    (tmp_path / "setup.toml").write_text(SETUP.format(profile=BAR))
    s = load_setup(str(tmp_path / "setup.toml"))
    return [r for r in interpret("c95.mpf", text, interp_config(s, s.machine.start)).records if r.src.line == 5]


@pytest.mark.parametrize("vari, contour, tool, path", [
    (5, RELIEF, 1, [(10, 0), (10, -10), (8, -16), (8, -22), (13, -28), (13, -35), (15, -35)]),
    (7, BORE, 2, [(18, 0), (16, -2), (16, -15), (12, -15), (12, -30), (10, -30)]),
    (6, FACE, 1, [(15, -8), (10, -8), (10, -2), (5, 0), (0, 0)]),
])
def test_finishing_runs_the_contour_at_ff3(tmp_path, vari, contour, tool, path):
    recs = records(tmp_path, prog(contour, c95(vari), tool=tool))
    fin = [r for r in recs if isinstance(r, Feed) and r.feed == 0.1]
    assert not [r for r in recs if isinstance(r, Feed) and r.feed in (0.25, 0.15)]  # no roughing
    assert [(r.end[0], r.end[2]) for r in fin] == [pytest.approx(p) for p in path]
    # approached in G0 before the start on the cutting axis, _VRT 1 off
    before = [r for r in recs if isinstance(r, Rapid) and r.end == fin[0].start][0]
    assert before.end == pytest.approx(((fin[0].end[0], 0, 1.0) if vari != 6 else (16.0, 0, -8.0)))


@pytest.mark.parametrize("vari", [4, 8, 12])
def test_face_inside_levels(tmp_path, vari):
    # VARI 4: infeed towards +Z, the material on the -Z side of the contour (a back face): the
    # contour from radius 15 at Z-30 to the step of 10 at Z-30..-34 and the end at (0, -36);
    # levels from Z-36 up to -30 - FALZ 0.1: ceil(5.9 / 2) = 3 of 5.9 / 3, each along -X from
    # 15 + 0.2 + 1 to the step moved by FALX to radius 10.2
    contour = "KONT_A: G1 X30 Z-30\nX20\nZ-34\nKONT_E: X0 Z-36\n"
    recs = records(tmp_path, prog(contour, c95(vari), start="X40 Z-50"))
    rough = [r for r in recs if isinstance(r, Feed) and r.feed == 0.25]
    lines = [(r.start[2], r.end[0]) for r in rough if r.start[0] == pytest.approx(16.2) and r.start[2] == r.end[2]]
    assert lines == ([pytest.approx((-36 + 5.9 / 3 * k, 10.2)) for k in range(1, 4)] if vari != 8 else [])
    # finishing (8, 12): along the contour at FF3 from the start; 4 does not finish
    fin = [(r.end[0], r.end[2]) for r in recs if isinstance(r, Feed) and r.feed == 0.1]
    path = [(15, -30), (10, -30), (10, -34), (0, -36)]
    assert fin == ([pytest.approx(p) for p in path] if vari != 4 else [])


# ---------------------------------------------------------------------------------------------
# property: random shafts with relief cuts (falling flanks at most 1:2, which the 93 degree V
# insert's minor edge clears), random MID and allowances: the finished part is the contour (its
# volume and its design), the roughed part keeps the allowance (no design material removed, at
# most hypot(FALX, FALZ) away), a contour point moved 0.5 mm in the program fails the compare
def _shaft(seed: int):
    rng = np.random.default_rng(seed)
    r, z = float(rng.uniform(6, 9)), 0.0
    pts = [(r, z)]
    for _ in range(int(rng.integers(3, 6))):
        z -= float(rng.uniform(3, 6))
        if rng.random() < 0.4:  # a falling flank into a relief cut, then its floor
            nr = max(5.0, r - float(rng.uniform(1, 2)))
            pts.append((nr, z))
            r, z = nr, z - float(rng.uniform(3, 5))
            pts.append((r, z))
        else:  # a step up (a shoulder) and a cylinder
            r = min(13.0, r + float(rng.uniform(0.5, 3)))
            pts += [(r, pts[-1][1]), (r, z)]
    pts.append((15.0, z))
    pts = [(round(r, 3), round(z, 3)) for r, z in pts]
    mid, falx, falz = float(rng.uniform(1, 3)), float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.05, 0.3))
    return pts, mid, falx, falz


def _kont(pts) -> str:
    lines = [f"G1 X{2 * r:.4f} Z{z:.4f}" for r, z in pts]
    return "KONT_A: " + "\n".join(lines[:-1]) + "\nKONT_E: " + lines[-1] + "\n"


@pytest.mark.parametrize("seed", range(5))
def test_random_shafts_against_their_design(tmp_path, seed):
    pts, mid, falx, falz = _shaft(seed)
    exact = pts + [(15.0, -40.0)]
    target = design(exact, 15)
    for vari in (9, 209):
        res = sim(tmp_path, prog(_kont(pts), c95(vari, mid=mid, falx=falx, falz=falz)))
        assert ratio(res) == pytest.approx(frustums(exact) / STOCK, rel=1e-6), vari
        assert_matches_design(res, target, tol=0.01, max_gouge=0.01)
        assert not res.warnings  # no rapid touches the stock
    for vari in (1, 201):
        res = sim(tmp_path, prog(_kont(pts), c95(vari, mid=mid, falx=falx, falz=falz)))
        rec = assert_matches_design(res, target, tol=math.hypot(falx, falz) + 2e-3, max_gouge=0.01)
        assert rec["details"]["excess_volume"] > 0 and not res.warnings
    k = 1 + seed % (len(pts) - 2)  # an inner point moved 0.5 towards the axis
    wrong = [(r - 0.5, z) if i == k else (r, z) for i, (r, z) in enumerate(pts)]
    res = sim(tmp_path, prog(_kont(wrong), c95(9, mid=mid, falx=falx, falz=falz)))
    with pytest.raises(AssertionError):
        assert_matches_design(res, target, tol=0.01, max_gouge=0.01)


# an inside relief cut: the bore of 36, a 1:2 flank out to the groove of 40, back in to 30, the
# end face at Z-30 down to the pre-drilled 20
BORE_RELIEF = """KONT_A: G1 X36 Z0
Z-8
X40 Z-12
Z-18
X30 Z-22
Z-30
KONT_E: X20
"""
BORE_RELIEF_EXACT = [(18, 0), (18, -8), (20, -12), (20, -18), (15, -22), (15, -30), (10, -30), (10, -40)]


@pytest.mark.parametrize("vari", [11, 211])
def test_inside_relief_cut_complete(tmp_path, vari):
    res = sim(tmp_path, prog(BORE_RELIEF, c95(vari), tool=2, start="X10 Z5"), TUBE)
    assert ratio(res) == pytest.approx(_tube(BORE_RELIEF_EXACT) / TUBE_VOL, rel=1e-6)
    assert not res.warnings
    tube = design([(25, 0), (25, -40)], 25) - design(BORE_RELIEF_EXACT, 25)
    assert_matches_design(res, tube, tol=0.01, max_gouge=0.01)
    # the relief cut: from the main section's last level (radius 18 - 0.2) out to the groove's
    # floor 20 - 0.2: one cut of 1.6 along the floor, entered at FF2 down the flank, which looks
    # to -Z: moved by (-FALX, -FALZ), it meets the moved floor at (19.8, -12.1); the floor cut at
    # FF1 to the far flank moved by (-0.2, +0.1): it starts at (19.8, -17.9), on the moved floor
    plunge = cuts(res, 0.15)
    assert (plunge[-1].end[0], plunge[-1].end[2]) == pytest.approx((19.8, -12.1))
    floor = [r for r in cuts(res, 0.25) if r.start[0] == pytest.approx(19.8) and r.end[0] == pytest.approx(19.8)]
    assert [r.end[2] for r in floor] == [pytest.approx(-17.9)]


def test_the_contour_from_a_subprogram(tmp_path):
    # NPP the name of a subprogram (KONTUR.spf beside the program): the same cycle as the labels
    (tmp_path / "setup.toml").write_text(SETUP.format(profile=BAR))
    body = "".join(line.split(": ", 1)[-1] + "\n" for line in RELIEF.splitlines()) + "M17\n"
    (tmp_path / "KONTUR.spf").write_text(body)
    main = prog("", c95(9).replace('"KONT_A:KONT_E"', '"KONTUR"'))
    (tmp_path / "c95.mpf").write_text(main)
    sub = cutsim.simulate(str(tmp_path / "c95.mpf"), str(tmp_path / "setup.toml"))
    lab = sim(tmp_path, prog(RELIEF, c95(9)))
    ends = [[(r.end[0], r.end[2]) for r in res.program.records if r.src.line == 5] for res in (sub, lab)]
    assert ends[0] == ends[1] and len(ends[0]) > 30
    assert ratio(sub) == pytest.approx(frustums(EXACT) / STOCK, rel=1e-6)


# a face relief cut: the bar's end at Z-8 out to radius 12, a 1:2 flank down to the ring groove's
# floor Z-9 (radii 11..9), up to the spigot of 16 at Z-6, the spigot to Z-2, a chamfer to (5, 0)
FACE_RELIEF = """KONT_A: G1 X30 Z-8
X24
X22 Z-9
X18
X16 Z-6
Z-2
X10 Z0
KONT_E: X0
"""
FACE_RELIEF_EXACT = [(15, -8), (12, -8), (11, -9), (9, -9), (8, -6), (8, -2), (5, 0), (0, 0)]


def shells(profile, bottom: float = -40.0) -> float:
    """The volume of revolution under the face profile [(r, z), ...] (z the part's top at radius
    r, linear between the points) down to ``bottom``: the shells 2 pi r (z - bottom) dr."""
    v = 0.0
    for (r1, z1), (r2, z2) in zip(profile, profile[1:]):
        if abs(r2 - r1) < 1e-12:
            continue
        beta = (z2 - z1) / (r2 - r1)
        alpha = z1 - beta * r1 - bottom
        v += 2 * math.pi * abs(alpha * (r2 ** 2 - r1 ** 2) / 2 + beta * (r2 ** 3 - r1 ** 3) / 3)
    return v


def test_face_relief_cut(tmp_path):
    # in the records (the 93 degree hand R tool's minor edge would cut into the face beside the
    # groove: the cycle does not consult the tool's shape, docs "cutsim assumes" 5)
    assert shells(FACE_RELIEF_EXACT[::-1][:1] + [(15, 0)]) == pytest.approx(STOCK)  # the bar
    recs = records(tmp_path, prog(FACE_RELIEF, c95(10), start="X40 Z5"))
    # the main section: from the face Z0 down to Z-8 + 0.1 in ceil(7.9 / 2) = 4 cuts of 1.975 along
    # -X from 15 + 0.2 + 1; the deepest passes over the groove to its inner flank moved by
    # (+FALZ, +FALX): through (9.2, -8.9) and (8.2, -5.9), radius 9.2 - 1 / 3 at Z-7.9
    rough = [r for r in recs if isinstance(r, Feed) and r.feed == 0.25]
    lines = [(r.start[2], r.end[0]) for r in rough if r.start[0] == pytest.approx(16.2) and r.start[2] == r.end[2]]
    assert lines[-1] == pytest.approx((-7.9, 9.2 - 1 / 3))
    # the groove: its top the last level Z-7.9, its floor -9 + 0.1: one cut of 1, entered at FF2
    # down the outer flank, which looks to -X: moved by (+0.1 in Z, -0.2 in X) it meets the moved
    # floor at (10.8, -8.9); the floor cut at FF1 to the inner flank's (9.2, -8.9)
    plunge = [r for r in recs if isinstance(r, Feed) and r.feed == 0.15]
    assert (plunge[-1].end[0], plunge[-1].end[2]) == pytest.approx((10.8, -8.9))
    floor = [r for r in rough if r.start[2] == pytest.approx(-8.9) and r.end[2] == pytest.approx(-8.9)]
    assert [(r.start[0], r.end[0]) for r in floor] == [pytest.approx((10.8, 9.2))]
    fin = [(r.end[0], r.end[2]) for r in recs if isinstance(r, Feed) and r.feed == 0.1]
    assert fin == [pytest.approx(p) for p in FACE_RELIEF_EXACT]


def test_inside_arc_rounding_the_bore_mouth(tmp_path):
    # the bore's mouth rounded with R2 (G2 about (18, -2)) instead of the chamfer: the air beside
    # the bore of 32 at Z0..-2 is the square 2 x 2 less the quarter disc, by Pappus
    contour = BORE.replace("X32 Z-2", "G2 X32 Z-2 CR=2\nG1")
    res = sim(tmp_path, prog(contour, c95(11), tool=2, start="X10 Z5"), TUBE)
    fillet = 2 * math.pi * (17 * 4 - (18 - 8 / (3 * math.pi)) * math.pi)
    air = math.pi * 16 ** 2 * 2 + fillet + frustums([(16, -2), (16, -15)]) + frustums([(12, -15), (12, -30)]) \
        + frustums([(10, -30), (10, -40)])
    # the arc is cut along chords at 0.005 and the rounded edge is convex: the chords cut into it,
    # over its 2 pi 17 x pi = 335 mm^2 up to 2/3 x 0.005 x 335 = 1.1 mm^3
    assert ratio(res) * TUBE_VOL == pytest.approx(math.pi * 25 ** 2 * 40 - air - 0.55, abs=0.6)
    pts = np.concatenate(plane_section(res.part, "z", -1.0))  # r = 18 - sqrt(4 - 1) at Z-1
    assert float(np.hypot(pts[:, 0], pts[:, 1]).min()) == pytest.approx(18 - math.sqrt(3), abs=0.01)
    # roughed (VARI 3): nothing of the rounded bore removed, at most the allowance box's corner away
    arc = [(18 - 2 * math.sin(a), -2 + 2 * math.cos(a)) for a in np.linspace(0, math.pi / 2, 200)]
    outline = arc + [(16, -15), (12, -15), (12, -30), (10, -30), (10, -40)]
    tube = design([(25, 0), (25, -40)], 25) - design(outline, 25)
    assert_matches_design(res, tube, tol=0.01, max_gouge=1.2)
    rough = sim(tmp_path, prog(contour, c95(3), tool=2, start="X10 Z5"), TUBE)
    assert_matches_design(rough, tube, tol=math.hypot(0.2, 0.1) + TOL, max_gouge=0.01)
    assert not rough.warnings


# ---------------------------------------------------------------------------------------------
# the example examples/sinumerik/relief-shaft: its design is what make_relief_design.py writes,
# its checks pass, and a contour point moved in the program fails the design check
EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "sinumerik"


def test_relief_shaft_design_is_what_the_script_writes():
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_relief_design", EXAMPLES / "make_relief_design.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.stl_bytes(mod.design()) == (EXAMPLES / "relief-shaft-design.stl").read_bytes()
    assert mod.design().volume() == pytest.approx(frustums(EXACT[:-1] + [(15, -45)]), rel=1e-3)


@pytest.mark.parametrize("spoil", [None, ("X16 Z-16", "X15 Z-16"), ("X26 Z-28", "X26.6 Z-28")])
def test_relief_shaft_example_fails_when_the_contour_is_moved(tmp_path, spoil):
    text = (EXAMPLES / "relief-shaft.mpf").read_text()
    if spoil:
        text = text.replace(*spoil)
    (tmp_path / "relief-shaft-design.stl").write_bytes((EXAMPLES / "relief-shaft-design.stl").read_bytes())
    (tmp_path / "setup.toml").write_text((EXAMPLES / "relief-shaft.toml").read_text())
    res = cutsim.simulate("relief-shaft.mpf", str(tmp_path / "setup.toml"), text=text, checks=True)
    design_ok = [c["passed"] for c in res.checks if c["kind"] == "design"]
    assert design_ok == [spoil is None]


def test_face_relief_with_the_turning_tool_cuts_beside_the_groove(tmp_path):
    # no clearance angle check (docs "cutsim assumes" 5): entering the face groove down its 1:2
    # flank, the 93 degree hand R tool's minor edge reaches into the face Z-8 outside the groove
    # (radii 11..15); the design compare finds the gouge there
    res = sim(tmp_path, prog(FACE_RELIEF, c95(10), start="X40 Z5"))
    poly = [(0.0, -40.0), (15.0, -40.0)] + [(float(r), float(z)) for r, z in FACE_RELIEF_EXACT]
    target = m3d.Manifold.revolve(m3d.CrossSection([poly]), circular_segments=circle_segments(15, TOL))
    assert target.volume() == pytest.approx(shells(FACE_RELIEF_EXACT), rel=1e-3)
    with pytest.raises(AssertionError):
        assert_matches_design(res, target, tol=0.01, max_gouge=0.01)
    from cutsim.reports.measure import compare_design

    c = compare_design(res.part, target, res.stock)
    x, y, z = c["worst_location"]
    assert c["worst_deviation"] < -0.1 and z == pytest.approx(-8, abs=0.05) and 11 < math.hypot(x, y) < 15


@pytest.mark.parametrize("seed", range(3))
def test_random_bores_against_their_design(tmp_path, seed):
    # the random shafts turned inside out: radius 25 - r, so the relief cuts go outwards into the
    # tube's wall and the contour ends at the pre-drilled bore's 10 (VARI 11 / 3 with the boring tool)
    pts, mid, falx, falz = _shaft(seed)
    bore = [(round(25 - r, 3), z) for r, z in pts]
    exact = bore + [(10.0, -40.0)]
    target = design([(25, 0), (25, -40)], 25) - design(exact, 25)
    res = sim(tmp_path, prog(_kont(bore), c95(11, mid=mid, falx=falx, falz=falz), tool=2, start="X10 Z5"), TUBE)
    assert ratio(res) == pytest.approx(_tube(exact) / TUBE_VOL, rel=1e-6)
    assert_matches_design(res, target, tol=0.01, max_gouge=0.01)
    assert not res.warnings
    res = sim(tmp_path, prog(_kont(bore), c95(3, mid=mid, falx=falx, falz=falz), tool=2, start="X10 Z5"), TUBE)
    assert_matches_design(res, target, tol=math.hypot(falx, falz) + 2e-3, max_gouge=0.01)
    assert not res.warnings
