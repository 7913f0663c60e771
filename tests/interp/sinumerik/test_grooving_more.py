"""CYCLE93 face grooves and grooves on an inclined contour (interp/sinumerik/grooving.py,
docs/dialects/sinumerik-turning.md "CYCLE93 grooving"): every number derived here by hand from the
cycle's parameters (walls and floor from SPD, SPL, WIDG, DIAG; flanks from depth x tan(angle); an
inclined groove turned with its contour line about the starting point), the solids measured after
the cut.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

import cutsim
from cutsim.interp.canon import Feed
from cutsim.reports.measure import depth_at, radii_at

SETUP = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [80.0, 0.0, 10.0]
[stock]
shape = "revolve"
profile = {profile}
[[tool]]
number = 2
kind = "grooving"
width = 3.0
corner_radius = 0.0
side = "{side}"
hand = "{hand}"
[simulation]
tolerance = 0.005
"""
BAR = "[[0, 0], [30, 0], [30, -30], [0, -30]]"  # a bar of 60, its end face at Z0


def run(tmp_path: Path, call: str, *, side: str = "face", hand: str = "R", profile: str = BAR, start="X80 Z5"):
    (tmp_path / "setup.toml").write_text(SETUP.format(profile=profile, side=side, hand=hand))
    text = f"N10 T2 D1\nN20 G18 G95 S300 M3 F0.1\nN30 G0 {start}\nN40 {call}\nN50 M30\n"
    return cutsim.simulate("groove.mpf", str(tmp_path / "setup.toml"), text=text)


def feeds(res):
    return [r for r in res.program.records if isinstance(r, Feed) and r.src.line == 4]


# ---------------------------------------------------------------------------------------------
# face grooves: the groove in the end face, its width along X, plunged along -Z
@pytest.mark.parametrize("vari, spd, hand", [(2, 20.0, "R"), (6, 32.0, "R"), (2, 20.0, "L"), (6, 32.0, "L")])
def test_face_groove_walls_and_floor(tmp_path, vari, spd, hand):
    # VARI 2 (starting point "left": the groove runs from SPD towards +X), 6 (towards -X): either way
    # the groove spans the radii 10 .. 16 (SPD/2 and SPD/2 +- WIDG), its floor at SPL - DIAG = -3.
    # The face tool of hand R has its control point on the -X corner, hand L on the +X corner.
    res = run(tmp_path, f"CYCLE93({spd:g}, 0, 6, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, {vari}, 1)", hand=hand)
    assert not [m for _, m in res.program.warnings if "CYCLE93" in m]
    fs = feeds(res)
    # two plunges (ceil((6 - 3) / 3) + 1) to Z-3, the tool spanning 10..13 and 13..16 (radius)
    k = 0.0 if hand == "R" else 3.0
    plunges = sorted(round(f.end[0], 6) for f in fs if f.start[2] > -1e-9 and f.end[2] == pytest.approx(-3.0)
                     and f.start[0] == pytest.approx(f.end[0]))
    assert set(plunges) >= {10.0 + k, 13.0 + k}
    assert min(f.end[2] for f in fs) == pytest.approx(-3.0)
    for r, z in ((10.2, -3.0), (13.0, -3.0), (15.8, -3.0), (9.8, 0.0), (16.2, 0.0), (5.0, 0.0), (25.0, 0.0)):
        assert depth_at(res.part, r, 0.0) == pytest.approx(z, abs=0.01), r


def test_face_groove_flank_angles(tmp_path):
    # VARI 2 from radius 10 with ANG1 30 and ANG2 20, DIAG 3, WIDG 4 at the base: flank 1 from
    # (r 10, Z0) to (10 + 3 tan 30, -3), the base to 10 + 3 tan 30 + 4, flank 2 up to that + 3 tan 20.
    t1, t2 = math.tan(math.radians(30)), math.tan(math.radians(20))
    res = run(tmp_path, "CYCLE93(20, 0, 4, 3, 0, 30, 20, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1)")
    b1, b2 = 10 + 3 * t1, 10 + 3 * t1 + 4
    for depth in (0.8, 1.5, 2.2):  # a point of each flank at that depth
        assert depth_at(res.part, 10 + depth * t1 + 0.02, 0.0) == pytest.approx(-depth - 0.02 / t1, abs=0.01)
        assert depth_at(res.part, b2 + (3 - depth) * t2 - 0.02, 0.0) == pytest.approx(-depth - 0.02 / t2, abs=0.01)
    for r in (b1 + 0.05, (b1 + b2) / 2, b2 - 0.05):
        assert depth_at(res.part, r, 0.0) == pytest.approx(-3.0, abs=0.01)
    # a wrong flank (10 degrees off) would put the wall elsewhere: the measured one is 30 degrees
    wrong = math.tan(math.radians(40))
    assert abs(depth_at(res.part, 10 + 1.5 * wrong, 0.0) - (-1.5)) > 0.2


def test_face_groove_with_roundings(tmp_path):
    # RCO1 0.5 (a rounding at edge 1 on the face: tangent to the face and to the radial wall at
    # r 10) and RCI2 -0.6 (a chamfer of legs 0.6 / (2 sin 45) at the base's corner on side 2, CHF)
    res = run(tmp_path, "CYCLE93(20, 0, 6, 3, 0, 0, 0, 0.5, 0, 0, -0.6, 0, 0, 0, 0, 2, 1)")
    leg = 0.6 / (2 * math.sin(math.radians(45)))
    # the rounding's centre (r 9.5, Z-0.5): at r 9.8 the face lies at -0.5 + sqrt(0.25 - 0.09)
    assert depth_at(res.part, 9.8, 0.0) == pytest.approx(-0.5 + math.sqrt(0.25 - 0.3 ** 2), abs=0.01)
    # the chamfer from (16 - leg, -3) to (16, -3 + leg): at r 16 - leg / 2 it is at -3 + leg / 2
    assert depth_at(res.part, 16 - leg / 2, 0.0) == pytest.approx(-3 + leg / 2, abs=0.01)
    assert depth_at(res.part, 13.0, 0.0) == pytest.approx(-3.0, abs=0.01)


# ---------------------------------------------------------------------------------------------
# a groove on an inclined contour: STA1 turns the groove with the contour line about the
# starting point; the plunges stay paraxial (along X), from the line down to the groove
def _taper(sta: float) -> str:
    t = math.tan(math.radians(sta))
    return f"[[0, 0], [{15 + 10 * t:.6f}, 0], [{15 - 20 * t:.6f}, -30], [0, -30]]"  # the line through (15, -10)


def _at(sta, u, w, s=-1.0, d=-1.0):
    """The groove's point u along the line (in the groove's direction), w deep across it: (r, z)."""
    c, sn = math.cos(math.radians(sta)), math.sin(math.radians(sta))
    return 15.0 + u * s * sn + w * d * c, -10.0 + u * s * c - w * d * sn


def test_inclined_groove_floor_and_flanks(tmp_path):
    # a taper rising 10 degrees towards +Z through (r 15, Z-10); VARI 5 (outside, from the right:
    # the groove runs towards -Z), WIDG 8, DIAG 3 across the line, ANG1 15 (at least STA1, else flank
    # 1 would lean over the paraxial plunges), ANG2 0 (square to the line)
    sta, a1 = 10.0, 15.0
    res = run(tmp_path, f"CYCLE93(30, -10, 8, 3, {sta:g}, {a1:g}, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5, 1)",
              side="outside", profile=_taper(sta), start="X50 Z5")
    t1 = math.tan(math.radians(a1))
    u_base = 3 * t1
    # the floor, parallel to the line 3 below it: measured where the base lies well clear of its ends
    for u in (u_base + 1.0, u_base + 3.0, u_base + 4.5):
        r, z = _at(sta, u, 3.0)
        assert radii_at(res.part, z).min() == pytest.approx(r, abs=0.01), u
    # flank 1 at half depth: the point 1.5 tan 15 along, 1.5 deep
    r, z = _at(sta, 1.5 * t1, 1.5)
    assert radii_at(res.part, z).min() == pytest.approx(r, abs=0.01)
    # flank 2 square to the line, at 1.5 deep: it rises cot(STA1) per mm towards -Z (it leans outwards)
    r, z = _at(sta, u_base + 8.0, 1.5)
    assert radii_at(res.part, z - 0.02).min() == pytest.approx(r + 0.02 / math.tan(math.radians(sta)), abs=0.01)
    # beside the groove the taper is untouched
    for z in (-9.5, -22.0):
        assert radii_at(res.part, z).min() == pytest.approx(15 + (z + 10) * math.tan(math.radians(sta)), abs=0.01)
    # the deepest feed: the flat edge bridging the base's deep corner (at the base's end, square flank
    # 2) where both its corners touch, w sin(STA1) cos(STA1) above the corner (w = 3)
    fs = feeds(res)
    h = 3.0 * math.sin(math.radians(sta)) * math.cos(math.radians(sta))
    assert min(f.end[0] for f in fs) == pytest.approx(_at(sta, u_base + 8, 3.0)[0] + h, abs=1e-6)


def test_inclined_groove_deep_corner_keeps_the_flat_edges_wedge(tmp_path):
    # The base descends towards -Z (the groove's direction): the tool's flat edge cannot reach the
    # base's deep corner at flank 2 (square to the line); the wedge it leaves is w sin(STA1) cos(STA1)
    # high (w = 3: 0.513), measured just beside the corner: the floor there is the wedge's top.
    sta = 10.0
    res = run(tmp_path, f"CYCLE93(30, -10, 8, 3, {sta:g}, 15, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5, 1)",
              side="outside", profile=_taper(sta), start="X50 Z5")
    c, sn = math.cos(math.radians(sta)), math.sin(math.radians(sta))
    h = 3.0 * sn * c
    r3, z3 = _at(sta, 3 * math.tan(math.radians(15)) + 8.0, 3.0)  # the base's deep corner
    # the crossover level r3 + h: the flat edge spans from flank 2 (z3 + h tan 10 ... towards -Z)
    z = z3 + 0.5 * h / math.tan(math.radians(sta))  # between the corner and the base point at that level
    assert radii_at(res.part, z).min() == pytest.approx(r3 + h, abs=0.01)


def test_inclined_groove_falling_contour(tmp_path):
    # STA1 170: the line falls 10 degrees towards +Z (the same line as -10); VARI 5 from the right:
    # now flank 2 is the one that must open by at least 10 degrees (ANG2 12), flank 1 square (ANG1 0)
    sta, theta = 170.0, -10.0
    t = math.tan(math.radians(theta))
    profile = f"[[0, 0], [{15 + 10 * t:.6f}, 0], [{15 - 20 * t:.6f}, -30], [0, -30]]"
    res = run(tmp_path, f"CYCLE93(30, -10, 8, 3, {sta:g}, 0, 12, 0, 0, 0, 0, 0, 0, 0, 0, 5, 1)",
              side="outside", profile=profile, start="X50 Z5")
    for u in (3.5, 5.0, 7.0):  # the floor 3 below the line, clear of the wedge (u < 3 cos 10 = 2.95)
        r, z = _at(theta, u, 3.0)
        assert radii_at(res.part, z).min() == pytest.approx(r, abs=0.01), u
    # flank 1, square to the line through the starting point, at 1.5 deep
    r, z = _at(theta, 0.0, 1.5)
    assert radii_at(res.part, z - 0.02).min() == pytest.approx(r - 0.02 / math.tan(math.radians(10)), abs=0.01)


@pytest.mark.parametrize("sta, a1, a2, ok", [(10, 10, 0, True), (10, 9, 0, False), (170, 0, 10, True),
                                              (170, 0, 9, False), (0, 0, 0, True)])
def test_flank_leaning_over_is_refused(sta, a1, a2, ok):
    # VARI 5: flank 1 must open by at least STA1 (a line rising towards +Z), flank 2 by at least
    # 180 - STA1 (falling); one degree less leans over the paraxial plunges
    from cutsim.interp.sinumerik.grooving import GrooveParamError, ToolEdge, plan_cycle93

    v = dict(SPD=30, SPL=-10, WIDG=8, DIAG=3, STA1=sta, ANG1=a1, ANG2=a2, VARI=5, _VRT=1)
    tool = ToolEdge(3.0, 3, (50.0, 5.0))
    if ok:
        assert plan_cycle93(v, tool)
    else:
        with pytest.raises(GrooveParamError) as e:
            plan_cycle93(v, tool)
        assert e.value.param == ("ANG1" if sta < 90 else "ANG2")


# ---------------------------------------------------------------------------------------------
# over the documented range: random face grooves and inclined grooves, the part measured where the
# hand-derived contour says; the same measurement against numbers 0.1 off must fail
def _face_case(seed: int):
    import random

    rng = random.Random(seed)
    right = rng.random() < 0.5
    widg = round(rng.uniform(3.2, 8.0), 2)
    diag = round(rng.uniform(0.8, 4.0), 2)
    r_in = round(rng.uniform(4.0, 14.0), 2)  # the groove's inner radius
    ang1, ang2 = round(rng.uniform(0.0, 25.0), 1), round(rng.uniform(0.0, 25.0), 1)
    idep = rng.choice([0.0, 0.9, 1.7])
    hand = rng.choice("RL")
    return right, widg, diag, r_in, ang1, ang2, idep, hand


@pytest.mark.parametrize("seed", range(4))
def test_face_grooves_over_the_range(tmp_path, seed):
    right, widg, diag, r_in, ang1, ang2, idep, hand = _face_case(seed)
    t1, t2 = math.tan(math.radians(ang1)), math.tan(math.radians(ang2))
    # "left" (VARI 2): from SPD towards +X, flank 1 at the inner edge; "right" (6): from SPD towards
    # the axis, flank 1 at the outer edge. The base lies DIAG below the face, WIDG wide.
    if right:
        r_out = r_in + diag * t2 + widg + diag * t1
        spd, vari, base = 2 * r_out, 6, (r_out - diag * t1 - widg, r_out - diag * t1)
        fl_in, fl_out = t2, t1
    else:
        spd, vari, base = 2 * r_in, 2, (r_in + diag * t1, r_in + diag * t1 + widg)
        fl_in, fl_out = t1, t2
        r_out = base[1] + diag * t2
    res = run(tmp_path, f"CYCLE93({spd:.4f}, 0, {widg:g}, {diag:g}, 0, {ang1:g}, {ang2:g}, 0, 0, 0, 0, 0, 0, "
                        f"{idep:g}, 0, {vari}, 1)", hand=hand)

    def expected(r):  # the face's Z at radius r from the hand-derived contour
        if r <= r_in or r >= r_out:
            return 0.0
        if r < base[0]:
            return -(r - r_in) / fl_in if fl_in > 0 else -diag
        if r > base[1]:
            return -(r_out - r) / fl_out if fl_out > 0 else -diag
        return -diag

    probes = [r_in - 0.3, (base[0] + base[1]) / 2, base[0] + 0.1, base[1] - 0.1, r_out + 0.3]
    probes += [r_in + 0.5 * diag * fl_in + 0.01, r_out - 0.5 * diag * fl_out - 0.01]
    for r in probes:
        assert depth_at(res.part, r, 0.0) == pytest.approx(expected(r), abs=0.01), r
    # deliberately wrong: the floor 0.1 deeper, the groove 0.1 further out
    assert depth_at(res.part, (base[0] + base[1]) / 2, 0.0) != pytest.approx(-diag - 0.1, abs=0.03)
    assert depth_at(res.part, base[1] + 0.05, 0.0) != pytest.approx(expected(base[1] + 0.05 + 0.1) - 0.1, abs=0.03)


@pytest.mark.parametrize("sta", [4.0, 12.0, 25.0, 160.0, 172.0])
def test_inclined_grooves_over_the_range(tmp_path, sta):
    # VARI 5 on the line through (15, -10) at STA1; the flank on the rising side opens by the line's
    # angle + 5 so no flank leans over; the floor is measured in the base's middle, clear of the
    # flat edge's wedge (w sin cos of the angle, at most 3 sin 25 cos 25 = 1.15 across, along the
    # base 3 cos(angle))
    theta = sta if sta <= 90 else sta - 180
    a1, a2 = (abs(theta) + 5, 0.0) if theta > 0 else (0.0, abs(theta) + 5)
    t = math.tan(math.radians(theta))
    profile = f"[[0, 0], [{15 + 10 * t:.6f}, 0], [{15 - 20 * t:.6f}, -30], [0, -30]]"
    widg, diag = 10.0, 2.5
    res = run(tmp_path, f"CYCLE93(30, -10, {widg:g}, {diag:g}, {sta:g}, {a1:g}, {a2:g}, 0, 0, 0, 0, 0, 0, 1, 0, 5, 1)",
              side="outside", profile=profile, start="X50 Z5")
    u0 = diag * math.tan(math.radians(a1))
    for u in (u0 + 4.0, u0 + 5.0, u0 + 6.5):
        r, z = _at(theta, u, diag)
        assert radii_at(res.part, z).min() == pytest.approx(r, abs=0.01), u
        assert radii_at(res.part, z).min() != pytest.approx(r - 0.1, abs=0.03)  # a floor 0.1 deeper: wrong
    for z in (-9.0, -10.0 - widg - 4.0):  # the line beside the groove, untouched
        assert radii_at(res.part, z).min() == pytest.approx(15 + (z + 10) * t, abs=0.01)


def test_inclined_groove_roundings_sit_tangent_to_both_sides(tmp_path):
    # STA1 10, VARI 5, ANG1 15, ANG2 0 with RCI1 0.6 (the fillet between flank 1 and the base) and
    # RCO2 0.8 (the rounding at edge 2): each centre lies its radius from both lines it joins (the
    # lines from the hand-derived corners); the finishing arcs about them are offset along Z by the
    # tracing corner (the starting-side corner on side 1: 3 towards +Z of the control point)
    from cutsim.interp.canon import Arc

    sta = 10.0
    res = run(tmp_path, f"CYCLE93(30, -10, 8, 3, {sta:g}, 15, 0, 0, 0.8, 0.6, 0, 0, 0, 0, 0, 5, 1)",
              side="outside", profile=_taper(sta), start="X50 Z5")
    t1 = math.tan(math.radians(15))
    p1, p2 = _at(sta, 0, 0), _at(sta, 3 * t1, 3)  # flank 1
    p3, p4 = _at(sta, 3 * t1 + 8, 3), _at(sta, 3 * t1 + 8, 0)  # base end, edge 2
    p5 = _at(sta, 3 * t1 + 20, 0)  # the line beyond edge 2

    def dist(c, a, b):  # from point c (r, z) to the line through a and b
        return abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / math.dist(a, b)

    arcs = [r for r in res.program.records if isinstance(r, Arc) and r.src.line == 4]
    centres = [(a.center[0], a.center[2]) for a in arcs]
    # three arcs: the fillet (side 1) and the rounding in two pieces: it rises from the line (which
    # falls towards -Z beyond edge 2) to its top before it falls into the groove, so the far corner
    # (the control point) traces it from the top inwards and the near corner (3 towards +Z of the
    # control point) from the top out to the line; a flat edge on the rise would cut into it
    assert len(centres) == 3
    fillet = next(c for c in centres if abs(dist((c[0], c[1] + 3.0), p1, p2) - 0.6) < 1e-6)  # side 1: +3
    assert dist((fillet[0], fillet[1] + 3.0), p2, p3) == pytest.approx(0.6, abs=1e-6)
    rounding = next(c for c in centres if abs(dist(c, p3, p4) - 0.8) < 1e-6)
    assert dist(rounding, p4, p5) == pytest.approx(0.8, abs=1e-6)
    assert (rounding[0], rounding[1] - 3.0) == pytest.approx(next(c for c in centres if c not in (fillet, rounding)))
    # on the part: the rounding's outermost reach along the line's normal is its centre + 0.8 towards
    # the air; at the centre's Z the part lies on the circle (its top, as radii_at takes the outer radius)
    assert radii_at(res.part, rounding[1]).min() == pytest.approx(rounding[0] + 0.8, abs=0.01)


@pytest.mark.parametrize("rco1", [0.8, -0.8])
def test_inclined_groove_edge_1_on_the_falling_side(tmp_path, rco1):
    # STA1 170 (falling 10 degrees towards +Z), VARI 5: beyond edge 1 (+Z) the line falls away, so
    # RCO1 (a rounding, or a chamfer of length 0.8) rises from the line before the groove; the part
    # keeps it whole: the rounding's top (centre + 0.8) measured at the centre's Z, the chamfer's
    # middle on its line
    from cutsim.interp.canon import Arc, Feed

    theta = -10.0
    t = math.tan(math.radians(theta))
    profile = f"[[0, 0], [{15 + 10 * t:.6f}, 0], [{15 - 20 * t:.6f}, -30], [0, -30]]"
    res = run(tmp_path, f"CYCLE93(30, -10, 8, 3, 170, 0, 12, {rco1:g}, 0, 0, 0, 0, 0, 0, 0, 5, 1)",
              side="outside", profile=profile, start="X50 Z5")
    p0, p1, p2 = _at(theta, -5, 0), _at(theta, 0, 0), _at(theta, 0, 3)  # the line, edge 1, flank 1 (square)
    if rco1 > 0:
        # the corner between the line and flank 1 (square to it) is 90 degrees: the centre lies 0.8 sqrt 2
        # from edge 1; the near corner's arcs are emitted 3 towards -Z (the control point)
        cs = [(a.center[0], a.center[2] + dz) for a in res.program.records if isinstance(a, Arc) and a.src.line == 4
              for dz in (0.0, 3.0)]
        c = next(c for c in cs if abs(math.dist(c, p1) - 0.8 * math.sqrt(2)) < 1e-6)
        assert radii_at(res.part, c[1]).min() == pytest.approx(c[0] + 0.8, abs=0.01)
    else:  # CHF: legs 0.8 / (2 sin(corner / 2)), the corner between the line and flank 1 is 90 degrees
        leg = 0.8 / (2 * math.sin(math.radians(45)))
        ua = (p0[0] - p1[0]) / 5, (p0[1] - p1[1]) / 5  # unit vectors from the corner along the line and flank
        ub = (p2[0] - p1[0]) / 3, (p2[1] - p1[1]) / 3
        a = (p1[0] + ua[0] * leg, p1[1] + ua[1] * leg)
        b = (p1[0] + ub[0] * leg, p1[1] + ub[1] * leg)
        mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        assert radii_at(res.part, mid[1]).min() == pytest.approx(mid[0], abs=0.01)
        assert any(isinstance(r, Feed) for r in res.program.records)


# ---------------------------------------------------------------------------------------------
# a property over the range (the planner alone, sharp corners): no position of the tool's flat
# edge, on any move, lies deeper than the hand-derived groove under it, and the finishing reaches
# the floor (halfway along the part of the base the flat edge can reach); a contour 0.1 off
# either way breaks one of the two
def _groove_polygon(theta, s, d, q0, p1, diag, widg, t1, t2, clear=1.0):
    c, sn = math.cos(math.radians(theta)), math.sin(math.radians(theta))

    def at(u, w):
        return q0 + u * s * sn + w * d * c, p1 + u * s * c - w * d * sn

    u2 = diag * t1
    u4 = u2 + widg + diag * t2
    return [at(-clear - 6.0, 0), at(0, 0), at(u2, diag), at(u2 + widg, diag), at(u4, 0), at(u4 + clear + 6.0, 0)]


def _shallowest(poly, p, d, q0):
    """The polygon's depth (d (q - q0)) at p: the shallowest where it crosses p (None outside)."""
    best = None
    for a, b in zip(poly, poly[1:]):
        lo, hi = sorted((a[1], b[1]))
        if not lo - 1e-12 <= p <= hi + 1e-12:
            continue
        qs = [a[0], b[0]] if abs(b[1] - a[1]) < 1e-12 else [a[0] + (b[0] - a[0]) * (p - a[1]) / (b[1] - a[1])]
        for q in qs:
            best = d * (q - q0) if best is None else min(best, d * (q - q0))
    return best


def _check_moves(moves, poly, d, q0, w, k, face, shift):
    """(no gouge, the base's middle reached) for the moves against the polygon deepened by ``shift``:
    the flat edge sampled along every move; reached when the edge covers the base's middle at the
    floor's depth on a feed move."""
    lo_p, hi_p = min(pt[1] for pt in poly), max(pt[1] for pt in poly)
    pts = [((z, x / 2.0) if face else (x / 2.0, z)) for _, (x, z) in moves]
    gouge, reached = False, False
    # the probe on the base: halfway along the part a flat edge reaches (from the shallow end, the base
    # less the tool's width; the deep end's wedge is out of reach on an inclined base)
    lo, hi = sorted(poly[2:4], key=lambda pt: d * (pt[0] - q0))
    mid = lo[1] + (hi[1] - lo[1]) * 0.5 * (1.0 - w / math.dist(lo, hi))
    floor = _shallowest(poly, mid, d, q0) + shift
    g_lo, g_hi = sorted((poly[1][1], poly[4][1]))
    for (qa, pa), (qb, pb), mv in zip(pts, pts[1:], moves[1:]):
        if not all(g_lo - w - 1e-6 <= pp <= g_hi + w + 1e-6 for pp in (pa, pb)):
            continue  # coming from and going back to the start: its way is the programmer's (manual)
        for i in range(21):
            q, pc = qa + (qb - qa) * i / 20, pa + (pb - pa) * i / 20
            for j in range(17):  # the edge's inside (its sides may touch the walls)
                p = pc - k * w + 1e-6 + (w - 2e-6) * j / 16
                if lo_p <= p <= hi_p and d * (q - q0) > _shallowest(poly, p, d, q0) + shift + 1e-6:
                    gouge = True
        if mv[0] != "G1":
            continue
        da, db = d * (qa - q0) - floor, d * (qb - q0) - floor  # the edge's depth against the floor's
        if abs(da) < 1e-6 and abs(db) < 1e-6:  # along the floor: the spans it sweeps
            reached = reached or min(pa, pb) - k * w - 1e-6 <= mid <= max(pa, pb) + (1 - k) * w + 1e-6
        elif da * db <= 0 and abs(db - da) > 1e-12:  # through the floor's depth: the span there
            pc = pa + (pb - pa) * (-da / (db - da))
            reached = reached or pc - k * w - 1e-6 <= mid <= pc + (1 - k) * w + 1e-6
    return gouge, reached


@pytest.mark.parametrize("seed", range(40))  # 400 pass too (25 s)
def test_finishing_never_gouges_and_reaches_the_floor(seed):
    import random

    from cutsim.interp.sinumerik.grooving import GrooveParamError, ToolEdge, plan_cycle93

    rng = random.Random(seed)
    face = rng.random() < 0.3
    outside = face or rng.random() < 0.6
    right = rng.random() < 0.5
    sta = rng.choice([0.0, rng.uniform(1, 20), rng.uniform(160, 179)])
    theta = sta if sta <= 90 else sta - 180
    s, d = (-1.0 if right else 1.0), (-1.0 if outside else 1.0)
    # the flank on the line's rising side opens by at least the line's angle (no flank leans over)
    rise = abs(theta) + rng.uniform(0, 15)
    a1, a2 = (rise, rng.uniform(0, 20)) if s * d * theta > 0 else (rng.uniform(0, 20), rise)
    if theta == 0:
        a1, a2 = rng.uniform(0, 30), rng.uniform(0, 30)
    widg, diag = rng.uniform(4, 9), rng.uniform(1.5, 4)
    spd = rng.uniform(40, 60) if outside else rng.uniform(20, 30)
    spl = rng.uniform(-20, -5)
    vari = (2 if face else 1 if outside else 3) + (4 if right else 0)
    hand = rng.choice("RL")
    edge = {(True, "R"): 3, (True, "L"): 2}[(True, hand)] if face else \
        {(True, "R"): 3, (True, "L"): 4, (False, "R"): 2, (False, "L"): 1}[(outside, hand)]
    k = 0.0 if hand == "R" else 1.0
    tool = ToolEdge(3.0, edge, (100.0 if outside else 5.0, 20.0), face)
    v = dict(SPD=spd, SPL=spl, WIDG=widg, DIAG=diag, STA1=sta, ANG1=a1, ANG2=a2, IDEP=rng.choice([0, 1.2]),
             VARI=vari, _VRT=1.0)
    try:
        moves = plan_cycle93(v, tool)
    except GrooveParamError as e:
        assert e.param == "STA1"  # the one refusal left for these: a handover with no place
        return
    q0, p1 = (spl, spd / 2) if face else (spd / 2, spl)
    poly = _groove_polygon(theta, s, d, q0, p1, diag, widg, math.tan(math.radians(a1)), math.tan(math.radians(a2)))
    assert _check_moves(moves, poly, d, q0, 3.0, k, face, 0.0) == (False, True)
    assert _check_moves(moves, poly, d, q0, 3.0, k, face, -0.1)[0]  # a contour 0.1 shallower: cut into
    assert not _check_moves(moves, poly, d, q0, 3.0, k, face, 0.1)[1]  # 0.1 deeper: the floor not reached
