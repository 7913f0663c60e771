"""ISG tool nose radius compensation on a lathe (G41/G42 with the tool's cutting edge position).

The program moves the tool's theoretical tip along the part's contour. Compensated, the nose's
centre runs on the contour offset by the nose radius r (to the right of the travel for G42, in the
ZX plane seen from +Y: X up, Z to the right), and the tip the control moves lies r from that
centre along each axis the cutting edge position points: edge position 3 (outside, hand R) puts
it at centre + (-r, -r) in (X radius, Z). Every expected point below is derived by hand from
that; the volumes by Pappus from the contour and the fillets the nose leaves in concave corners.

The contour, (X diameter, Z): approach from (12, 6) down to (12, 2), a 45 degree chamfer to
(20, -2), Z-20, a taper to (30, -30) (radius rising 1 in 2), Z-40, the shoulder up to X40.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import cutsim
from cutsim.interp import CutsimError, InterpConfig, interpret

R = 0.8
S2, S5 = math.sqrt(2.0), math.sqrt(5.0)
PROGRAM = """%nose
N10 {mode}
N15 T1 M03 S1000
N20 G00 X{x0} Z6
N30 {sel} G01 Z2 F200
N40 X{x1} Z-2
N50 Z-20
N60 X{x2} Z-30
N70 Z-40
N80 G40 X{x3}
N90 G00 X60 Z50
N100 M30
"""
DIAMETER = dict(mode="G51", x0=12, x1=20, x2=30, x3=40)
RADIUS = dict(mode="G52", x0=6, x1=10, x2=15, x3=20)


def run(text: str, edge: int = 3, r: float = R) -> list[tuple[float, float]]:
    """The (X, Z) end points of the motions, rounded to 1e-6 mm."""
    cfg = InterpConfig(dialect="isg", machine_kind="lathe", start=(30.0, 0.0, 50.0), tool_noses={1: (r, edge)})
    prog = interpret("t.nc", text, cfg)
    return [(round(m.end[0], 6) + 0.0, round(m.end[2], 6) + 0.0) for m in prog.moves]


def expected_g42_edge3(r: float) -> list[tuple[float, float]]:
    """Radius values (x, z). Offset lines (right of the travel): approach x = 6 + r; chamfer
    x + z = 8 + r sqrt2; cylinder x = 10 + r; taper z + 2x = r sqrt5; cylinder x = 15 + r; shoulder
    z = -40 + r. Corners (the lines' intersections: the inside ones, and the outside ones turning
    by less than 90 degrees under G25), then the tip = centre + (-r, -r):
    approach/chamfer z = 2 + r (sqrt2 - 1) -> tip (6, 2 + r (sqrt2 - 2));
    chamfer/cylinder z = -2 + r (sqrt2 - 1) -> tip (10, -2 + r (sqrt2 - 2));
    cylinder/taper z = -20 + r (sqrt5 - 2) -> tip (10, -20 + r (sqrt5 - 3));
    taper/cylinder z = -30 + r (sqrt5 - 2) -> tip (15, -30 + r (sqrt5 - 3));
    cylinder/shoulder centre (15 + r, -40 + r) -> tip (15, -40).
    The approach starts and the departure ends where programmed: (6, 6) and (20, -40)."""
    return [(6.0, 6.0), (6.0, 2 + r * (S2 - 2)), (10.0, -2 + r * (S2 - 2)), (10.0, -20 + r * (S5 - 3)),
            (15.0, -30 + r * (S5 - 3)), (15.0, -40.0), (20.0, -40.0)]


@pytest.mark.parametrize("modes,factor", [(DIAMETER, 2.0), (RADIUS, 1.0)])
def test_g42_edge3_corner_points(modes, factor):
    """r = 0.8: the chamfer's corners at Z1.531371 and Z-2.468629, the taper's at Z-20.611146 and
    Z-30.611146; in diameter (G51) and radius (G52) programming alike."""
    got = run(PROGRAM.format(sel="G42", **modes))[:-1]  # without the last rapid
    want = [(round(x * factor, 6) + 0.0, round(z, 6) + 0.0) for x, z in expected_g42_edge3(R)]
    assert got == want
    assert want[2] == (20.0 * factor / 2.0, -2.468629)


@pytest.mark.parametrize("r", [0.2, 0.4, 1.2])
def test_g42_edge3_other_radii(r):
    assert run(PROGRAM.format(sel="G42", **DIAMETER), r=r)[:-1] == [
        (round(2 * x, 6) + 0.0, round(z, 6) + 0.0) for x, z in expected_g42_edge3(r)]


def test_edge_position_9_is_the_centre():
    """Edge position 9 (no direction: the control point is the nose's centre): the points are the
    offset corners themselves, e.g. the chamfer/cylinder corner (10 + r, -2 + r (sqrt2 - 1))."""
    got = run(PROGRAM.format(sel="G42", **RADIUS), edge=9)
    assert got[2] == (round(10 + R, 6), round(-2 + R * (S2 - 1), 6))


def test_inside_g41_edge2():
    """A bore turned towards the chuck with a boring bar (edge position 2: tip at centre + (r, -r))
    under G41 (the left of a travel towards -Z is -X: the bar inside the bore). Contour (x radius,
    z): approach (7, 4) -> (7, 1), the entrance chamfer down to (6, 0), the bore x = 6 to Z-10.
    Offset lines (left of the travel): approach x = 7 - r; chamfer x - z = 6 - r sqrt2 (its left
    normal (1, -1)/sqrt2 in (z, x)); bore x = 6 - r. Corners: z = 1 + r (sqrt2 - 1) and
    z = r (sqrt2 - 1); the tip = centre + (r, -r): (7, 1 + r (sqrt2 - 2)) and (6, r (sqrt2 - 2))."""
    text = ("%b\nN10 G52\nN15 T1 M03 S800\nN20 G00 X7 Z4\nN30 G41 G01 Z1 F100\nN40 X6 Z0\nN50 Z-10\n"
            "N60 G40 X4\nN70 G00 Z5\nN80 M30\n")
    got = run(text, edge=2)
    assert got[1] == (7.0, round(1 + R * (S2 - 2), 6))
    assert got[2] == (6.0, round(R * (S2 - 2), 6))


def test_concave_fillet_arc():
    """Z-10 at X20, then a fillet of radius 2 (G02, centre (x 12, z -10), I2 a radius) into the
    shoulder face at Z-12, up to X30. The nose's centre runs the fillet at radius 2 - r = 1.2 about
    (12, -10), from (10.8, -10) to (12, -11.2); the tip, moved by (-r, -r), from (10, -10.8) to
    (11.2, -12) about (11.2, -10.8), clockwise as programmed; X20 = 2 x 10, X22.4 = 2 x 11.2."""
    cfg = InterpConfig(dialect="isg", machine_kind="lathe", start=(30.0, 0.0, 50.0), tool_noses={1: (R, 3)})
    text = ("%a\nN10 G51\nN15 T1 M03 S800\nN20 G00 X20 Z4\nN30 G42 G01 Z0 F100\nN40 Z-10\nN50 G02 X24 Z-12 K0 I2\n"
            "N60 G01 X30\nN70 G40 X40\nN80 M30\n")
    arc = [m for m in interpret("t.nc", text, cfg).moves if hasattr(m, "center")]
    assert len(arc) == 1 and arc[0].clockwise
    got = [tuple(round(v, 6) + 0.0 for v in p) for p in (arc[0].start, arc[0].end, arc[0].center)]
    assert got == [(20.0, 0.0, -10.8), (22.4, 0.0, -12.0), (22.4, 0.0, -10.8)]


def test_plane_other_than_zx_refused():
    with pytest.raises(CutsimError, match="turning plane"):
        run("%p\nG17\nT1 M03 S100\nG42 G01 X10 Z0 F100\nM30\n")


# -- the turned part: Pappus ---------------------------------------------------------------------
def _fillet(corner, d1, d2, r):
    """Area and centroid radius (the X coordinate) of what a nose of radius r leaves in a corner
    whose open side lies between the unit rays d1, d2 (in (x, z)): the kite corner - tangent point
    - centre - tangent point less the circular sector at the centre between the tangent points."""
    corner, d1, d2 = (np.asarray(v, dtype=float) for v in (corner, d1, d2))
    phi = math.acos(float(np.dot(d1, d2)))
    bis = (d1 + d2) / np.linalg.norm(d1 + d2)
    t = r / math.tan(phi / 2.0)
    c = corner + bis * r / math.sin(phi / 2.0)
    kite = [corner, corner + d1 * t, c, corner + d2 * t]
    a = 0.0
    cx = 0.0
    for p, q in zip(kite, kite[1:] + kite[:1]):
        w = p[0] * q[1] - q[0] * p[1]
        a += w / 2.0
        cx += (p[0] + q[0]) * w / 6.0
    a, cx = abs(a), abs(cx)
    theta = math.pi - phi
    sector = r * r * theta / 2.0
    sx = c[0] - bis[0] * 4.0 * r * math.sin(theta / 2.0) / (3.0 * theta)
    return a - sector, (cx - sector * sx) / (a - sector)


def test_fillet_closed_form():
    """The square corner's fillet is the spandrel: r^2 (1 - pi/4), centroid r (10 - 3 pi) / (12 - 3 pi)
    from each side."""
    area, x = _fillet((15.0, -40.0), (0.0, 1.0), (1.0, 0.0), 0.8)
    assert abs(area - 0.64 * (1 - math.pi / 4)) < 1e-12
    assert abs(x - (15.0 + 0.8 * (10 - 3 * math.pi) / (12 - 3 * math.pi))) < 1e-9


def removed_volume(r: float) -> float:
    """The bar r <= 16, z -60..0 loses, between z = -40 and 0, what lies outside the contour:
    pi integral (16^2 - r(z)^2) dz: chamfer (r = 8 - z, z -2..0) pi (512 - (10^3 - 8^3) / 3), Z-20
    18 pi (256 - 100), taper (r = 10 + v / 2, v 0..10) pi (2560 - 2 (15^3 - 10^3) / 3), Z-40
    10 pi (256 - 225); less the fillets the nose leaves in the two concave corners, 2 pi x A each
    (Pappus): cylinder/taper at (10, -20) between the rays (0, 1) and (1, -2)/sqrt5 in (x, z),
    shoulder at (15, -40) between (1, 0) and (0, 1)."""
    ideal = math.pi * ((512 - (1000 - 512) / 3) + 18 * 156 + (2560 - 2 * (3375 - 1000) / 3) + 10 * 31)
    left = 0.0
    for corner, d1, d2 in (((10.0, -20.0), (0.0, 1.0), (1 / S5, -2 / S5)), ((15.0, -40.0), (1.0, 0.0), (0.0, 1.0))):
        a, x = _fillet(corner, d1, d2, r)
        left += 2 * math.pi * x * a
    return ideal - left


SETUP = """[machine]
kind = "lathe"
dialect = "isg"
start = [30.0, 0.0, 50.0]
[stock]
shape = "cylinder"
diameter = 32
z = [-60, 0]
[[tool]]
number = 1
kind = "turning"
insert = "C"
tip_radius = {r}
[simulation]
tolerance = 0.002
"""


def _simulate(tmp_path, text: str, r: float = R):
    setup = tmp_path / "s.toml"
    setup.write_text(SETUP.format(r=r))
    return cutsim.simulate("p.nc", str(setup), text=text)


def test_turned_part_pappus(tmp_path):
    """The compensated program turns the contour: the removed volume is the contour's by Pappus
    (less the two fillets), to the revolved stock's polygon factor; no warning."""
    res = _simulate(tmp_path, PROGRAM.format(sel="G42", **DIAMETER))
    assert res.report["warnings"] == []
    k = res.report["stock_volume"] / (math.pi * 256.0 * 60.0)
    expect = k * removed_volume(R)
    assert abs(res.report["removed_volume"] - expect) <= 2e-4 * expect, (res.report["removed_volume"], expect)


def test_uncompensated_program_misses_the_contour(tmp_path):
    """The same contour without G42: the tip runs on the contour, which is right only where the
    contour is parallel to an axis; on the chamfer and the taper the nose stands off the slope
    (the tip is not the point that cuts there), so the part keeps more than the contour and the
    removed volume falls short by far more than the compensated run's error (about 290 mm^3
    against 1)."""
    res = _simulate(tmp_path, PROGRAM.format(sel="", **DIAMETER))
    k = res.report["stock_volume"] / (math.pi * 256.0 * 60.0)
    expect = k * removed_volume(R)
    assert expect - res.report["removed_volume"] > 5.0, (res.report["removed_volume"], expect)


# -- property: random turned contours --------------------------------------------------------------
def _random_profile(rng) -> list[tuple[float, float]]:
    """An outside contour (x radius, z) turned towards the chuck: z falls, x never falls, each
    element straight along Z or rising at 10..60 degrees (never a face: the corner moves stay
    within the contour's elements), at least 2 mm long; neighbours differ by 2 degrees or more (a
    join within the rounding of the coordinates is bridged by a short line instead of a corner)."""
    pts = [(round(float(rng.uniform(4, 8)), 4), 2.0)]
    last = 0.0
    for _ in range(int(rng.integers(2, 7))):
        x, z = pts[-1]
        length = float(rng.uniform(2.0, 8.0))
        a = 0.0 if rng.random() < 0.5 else math.radians(float(rng.uniform(10, 60)))
        if a and abs(a - last) < math.radians(2.0):  # (nearly) tangent joins are bridged, not cornered
            a = last + math.radians(3.0) if a < math.radians(57.0) else last - math.radians(3.0)
        last = a
        pts.append((round(x + length * math.sin(a), 4), round(z - length * math.cos(a), 4)))
    return pts


@pytest.mark.parametrize("seed", range(60))
def test_random_contours_nose_centre_on_the_offset(seed):
    """For a random contour, G42 and edge position 3: every compensated point moved back from the tip
    to the nose's centre (+r, +r) lies r from both contour elements it joins (on their outer side),
    except where an outside corner is extended (the turn is then at most 60 degrees here: the point
    lies r from each element's line, beyond its end). So each element's offset is exactly r: the
    nose touches the contour and never cuts into it."""
    rng = np.random.default_rng(seed)
    r = float(rng.uniform(0.1, 1.6))
    prof = _random_profile(rng)
    x0, z0 = prof[0]
    lines = [f"N{10 * (i + 4)} X{x:.4f} Z{z:.4f}" for i, (x, z) in enumerate(prof[1:])]
    text = (f"%p\nN10 G52\nN15 T1 M03 S800\nN20 G00 X{x0:.4f} Z{z0 + 4:.4f}\nN30 G42 G01 Z{z0:.4f} F100\n"
            + "\n".join(lines) + f"\nN90 G40 X{prof[-1][0] + 3:.4f}\nN95 M30\n")
    got = run(text, r=r)
    elems = [((x0, z0 + 4), (x0, z0))] + list(zip(prof[:-1], prof[1:])) + [(prof[-1], (prof[-1][0] + 3, prof[-1][1]))]
    for k, (x, z) in enumerate(got[1:-1], start=0):  # the end of element k joins k and k + 1
        cx, cz = x + r, z + r
        for (xa, za), (xb, zb) in elems[k:k + 2]:
            dz, dx = zb - za, xb - xa
            n = math.hypot(dz, dx)
            # signed distance to the right of the travel (seen with X up, Z to the right): (dx, -dz)/n
            side = ((cz - za) * dx - (cx - xa) * dz) / n
            assert abs(side - r) < 2e-6, (seed, k, side, r)


@pytest.mark.parametrize("change,failing", [
    ("", set()),
    ("N30 G01 Z2 F200", {"chamfer", "taper", "removed"}),  # no compensation: the nose stands off the slopes
    ("N30 G41 G01 Z2 F200", {"chamfer", "diameter 20", "taper", "diameter 30", "removed"}),  # the wrong side
])
def test_example_fails_when_made_wrong(change, failing):
    """examples/isg-lathe/nose-radius passes its checks (also tests/app/test_examples.py) and fails
    them without compensation or with it on the wrong side."""
    from conftest import REPO_EXAMPLES

    base = REPO_EXAMPLES / "isg-lathe" / "nose-radius"
    program = base.with_suffix(".nc").read_text()
    if change:
        program = program.replace("N30 G42 G01 Z2 F200", change)
        assert change in program
    res = cutsim.simulate("p.nc", str(base.with_suffix(".toml")), text=program)
    assert {c["name"] for c in res.report["checks"] if not c["passed"]} == failing
