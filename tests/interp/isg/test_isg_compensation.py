"""ISG tool radius compensation (G40/G41/G42, G25/G26, G138/G139), circle radius programming (R)
and a transformation the setup declares Cartesian (#TRAFO ON).

Every expected point is derived by hand from the contour and the tool radius (docstrings), never
from the code under test: the tool centre path of a contour offset by r is made of the contour's
elements moved r to the left (G41) or right (G42) of the travel, inside corners meeting at the
offset lines' intersection, outside corners (G25, the default) by extending the elements along
their tangents (to their intersection for a turn up to 90 degrees, else by r each, joined by one
line) or (G26) by an arc of radius r about the corner.
"""
from __future__ import annotations

import math

import pytest
from click.testing import CliRunner

from cutsim.cli import main
from cutsim.interp import CutsimError, InterpConfig, interpret
from cutsim.interp import canon

R = 5.0  # tool radius: the setup's tool 1 has diameter 10


def run(text: str, **kw) -> canon.Program:
    base = dict(dialect="isg", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: R})
    base.update(kw)
    return interpret("t.nc", text, InterpConfig(**base))


def pts(prog) -> list[tuple[float, float]]:
    """The XY end points of the motions, rounded to 1e-4 mm."""
    return [(round(m.end[0], 4) + 0.0, round(m.end[1], 4) + 0.0) for m in prog.moves]


SQUARE = "%P\nG17 G00 X-20 Y-10 Z5\nG01 Z-2 F100\n{sel} X0 Y0\nY40\nX40\nY0\nX0\nG40 X-20 Y-10\nM30\n"
S5 = math.sqrt(5.0)


def test_square_g41_outside_sharp_corners():
    """A 40 mm square run clockwise (up X=0, along Y=40, down X=40, back along Y=0) with G41: the
    left of the travel is outside. The centre path is the square grown by r = 5 with sharp corners
    (90-degree turns: the extended lines meet): (-5, 45), (45, 45), (45, -5). The approach from
    (-20, -10) to (0, 0) runs along (2, 1)/sqrt(5); moved 5 to its left it meets x = -5 at
    y = -10 + 5*2/sqrt(5) + (15 - 5/sqrt(5))/2 = 3.0902 (an inside corner). The contour's last
    line (y = -5 after offset) meets the departure (direction (-2, -1), moved left) at
    x = 5/sqrt(5) - 2*(5 - 10/sqrt(5)) = 1.1803; the departure ends where programmed."""
    p = pts(run(SQUARE.format(sel="G41")))
    y0 = -10 + 2 * S5 + (15 + S5) / 2
    x1 = 5 / S5 - 2 * (5 - 10 / S5)
    assert p == [(-20, -10), (-20, -10), (-5, round(y0, 4)), (-5, 45), (45, 45), (45, -5), (round(x1, 4), -5),
                 (-20, -10)]


def test_square_g42_inside():
    """The same square with G42: the centre path is the square shrunk by 5, corners (5, 35), (35, 35),
    (35, 5) (inside corners: intersections). The approach is an outside corner of 63.4 degrees
    (up to 90: extended to the intersection): x = 5 on the approach line moved right,
    y = -5*2/sqrt(5) + (5 - 5/sqrt(5))/2 = -3.0902; the last line y = 5 is extended to
    x = -(5/sqrt(5)) + (5 - 10/sqrt(5))*2 = -1.1803 where it meets the moved departure line."""
    p = pts(run(SQUARE.format(sel="G42")))
    assert p[2:] == [(5, -3.0902), (5, 35), (35, 35), (35, 5), (-1.1803, 5), (-20, -10)]


def test_square_g26_arcs_about_the_corners():
    """G26: the outside corners are arcs of radius 5 about the square's corners (clockwise, as the
    travel): (-5, 40) -> (0, 45) about (0, 40), and so on."""
    prog = run(SQUARE.format(sel="G41 G26"))
    arcs = [m for m in prog.moves if isinstance(m, canon.Arc)]
    assert [(a.start[:2], a.end[:2], a.center[:2], a.clockwise) for a in arcs] == [
        ((-5, 40), (0, 45), (0, 40), True), ((40, 45), (45, 40), (40, 40), True), ((45, 0), (40, -5), (40, 0), True)]


def test_sharp_turn_over_90_degrees_g25_extends_by_the_radius():
    """Along +X to (10, 0), then to (0, 10) (a left turn of 135 degrees) with G42: the offset line
    y = -5 is extended by r to (15, -5), the next element's offset start (10, 0) + 5*(1, 1)/sqrt(2)
    moved back by r along (-1, 1)/sqrt(2) is (10 + 10/sqrt(2), 0) = (17.0711, 0); one line joins
    them. The last turn (45 degrees onto -X) is extended to the intersection of x + y = 17.0711
    with y = 15: (2.0711, 15)."""
    p = pts(run("%P\nG17 G00 X-10 Y0 Z-1\nG42 G01 X0 Y0 F100\nX10\nX0 Y10\nG40 X-10 Y10\nM30\n"))
    k = 10 + 10 / math.sqrt(2)
    assert p == [(-10, 0), (0, -5), (15, -5), (round(k, 4), 0), (round(k - 15, 4), 15), (-10, 10)]


def test_arc_offset_and_direct_selection():
    """G138 (direct): the approach goes straight to the first element's offset start. A line along +X
    to (20, 0) and a counter-clockwise quarter about (20, 10) with G41 (left: the arc's centre side):
    the line moves to y = 5, the arc keeps its centre and shrinks to radius 10 - 5 = 5, ending at
    (25, 10). The departure leaves from there to the programmed (40, 10)."""
    prog = run("%P\nG17 G00 X0 Y-10 Z-1\nG138 G41 G01 X0 Y0 F100\nX20\nG03 X30 Y10 I0 J10\nG40 G01 X40\nM30\n")
    p = pts(prog)
    assert p == [(0, -10), (0, 5), (20, 5), (25, 10), (40, 10)]
    arc = [m for m in prog.moves if isinstance(m, canon.Arc)][0]
    assert arc.center[:2] == (20, 10) and not arc.clockwise


def test_plunges_inside_compensation_stay_where_the_tool_is():
    """A move along Z only between contour elements is made at the tool's offset position: the
    direct approach ends at the offset start (0, 5) of the line along +X, the plunge stays there."""
    prog = run("%P\nG17 G00 X0 Y-10 Z5\nG138 G41 G01 X0 Y0 F100\nZ-3\nX20\nG40 X20 Y-10\nM30\n")
    assert [m.end for m in prog.moves][1:3] == [(0.0, 5.0, 5.0), (0.0, 5.0, -3.0)]


def test_radius_zero_warns_and_is_not_offset():
    prog = run("%P\nG41 G01 X10 F100\nX20\nG40 X30\nM30\n", tool_radii={1: 0.0})
    assert pts(prog) == [(10, 0), (20, 0), (30, 0)]
    assert any("tool radius 0" in m for _, m in prog.warnings)


@pytest.mark.parametrize("text, line, what", [
    ("%P\nG41 G01 X10 F100\nT2\nG40 X0\nM30\n", 3, "tool change"),
    ("%P\nG41 G01 X10 F100\nV.G.WZ_AKT.R = 2\nG40 X0\nM30\n", 3, "changing the tool radius"),
    ("%P\nG41 G01 X10 F100\nG18\nX20\nM30\n", 3, "plane changed"),
    ("%P\nG41 G01 X10 Y0 F100\nG02 X10 Y0 I5 J0\nG40 G01 X0\nM30\n", 3, "full circle"),
    ("%P\nG01 X10 F100\nG05 G41 X20\nG40 X0\nM30\n", 3, "G41 under G5 (tangential"),
])
def test_what_compensation_does_not_model_is_exit_2(text, line, what):
    with pytest.raises(CutsimError) as e:
        run(text, tool_radii={1: R, 2: 3.0})
    assert e.value.line == line and what in e.value.message, str(e.value)


def test_lathe_g41_without_a_nose_radius():
    """On a lathe G41/G42 is nose radius compensation (tests/interp/isg/test_isg_lathe_nose.py): a
    tool the setup gives no nose radius is not offset, with one warning."""
    prog = run("%P\nG18 G00 X20 Z5\nG41 G01 Z0 F100\nX30\nG40 Z-5\nM30\n", machine_kind="lathe")
    assert [m.end for m in prog.moves] == [(20.0, 0.0, 5.0), (20.0, 0.0, 0.0), (30.0, 0.0, 0.0), (30.0, 0.0, -5.0)]
    assert [msg for _, msg in prog.warnings] == [
        "G41 with nose radius 0 (the setup gives none for the active tool, or D0): the path is not offset"]


# -- R: circle radius ---------------------------------------------------------------------------------
def test_radius_programming_short_and_long_arcs():
    """The manual's example: from (0, 0), G02 X100 R50 and G03 X200 R50 are half circles about (50, 0)
    and (150, 0). From (200, 0) to (200, -40) clockwise with R-30 (the longer arc): the centre is on
    the chord's perpendicular bisector y = -20 at sqrt(30^2 - 20^2) = 22.3607 from it, on the side
    that makes the clockwise arc longer than a half circle: x = 222.3607. R is modal: the last G02
    takes R-30 again (from (200, -40) to (200, 0), centre to the left of the chord: x = 177.6393)."""
    prog = run("%P\nG17 G01 X0 Y0 F100\nG02 X100 R50\nG03 X200 R50\nG02 X200 Y-40 R-30\nX200 Y0\nM30\n")
    arcs = [m for m in prog.moves if isinstance(m, canon.Arc)]
    h = math.sqrt(30 ** 2 - 20 ** 2)
    assert [tuple(round(c, 4) for c in a.center[:2]) for a in arcs] == [
        (50, 0), (150, 0), (round(200 + h, 4), -20), (round(200 - h, 4), -20)]
    assert [a.clockwise for a in arcs] == [True, False, True, True]


# -- #TRAFO ON with the setup's declaration -----------------------------------------------------------
def test_trafo_declared_cartesian_passes(tmp_path):
    setup = tmp_path / "s.toml"
    setup.write_text('[machine]\nkind = "mill"\ndialect = "isg"\nstart = [0.0, 0.0, 50.0]\n'
                     'transformations = ["TRAFO"]\n[stock]\nshape = "box"\nx = [0.0, 10.0]\ny = [0.0, 10.0]\n'
                     'z = [-5.0, 0.0]\n[[tool]]\nnumber = 1\nkind = "endmill"\ndiameter = 2.0\nlength = 20.0\n')
    prog = tmp_path / "p.nc"
    prog.write_text("%P\n#TRAFO ON\nG01 X1 F100\n#TRAFO OFF\nM30\n")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 0, res.output
    assert "FEED (0 0 50) -> (1 0 50)" in res.output
    setup.write_text(setup.read_text().replace('transformations = ["TRAFO"]\n', ""))
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 2 and "[machine] transformations" in res.output


# -- property: the offset path of a convex polygon keeps exactly the tool radius -----------------------
from hypothesis import given, settings, strategies as hst  # noqa: E402

from cutsim.interp.core.compensation import Elem, offset_chain  # noqa: E402


def _seg_dist(p, a, b) -> float:
    ax, ay = b[0] - a[0], b[1] - a[1]
    if ax * ax + ay * ay < 1e-24:
        return math.dist(p, a)
    t = max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / (ax * ax + ay * ay)))
    return math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * ay)


def _samples(e, n=24):
    if e.kind == "L":
        return [(e.start[0] + (e.end[0] - e.start[0]) * k / n, e.start[1] + (e.end[1] - e.start[1]) * k / n)
                for k in range(n + 1)]
    c, r = e.centre, math.hypot(e.start[0] - e.centre[0], e.start[1] - e.centre[1])
    a0 = math.atan2(e.start[1] - c[1], e.start[0] - c[0])
    a1 = math.atan2(e.end[1] - c[1], e.end[0] - c[0])
    d = (a0 - a1) % (2 * math.pi) if e.cw else (a1 - a0) % (2 * math.pi)
    s = -1 if e.cw else 1
    return [(c[0] + r * math.cos(a0 + s * d * k / n), c[1] + r * math.sin(a0 + s * d * k / n)) for k in range(n + 1)]


@settings(max_examples=60, deadline=None)
@given(hst.lists(hst.floats(0.0, 2 * math.pi), min_size=3, max_size=8, unique=True),
       hst.sampled_from([1, -1]), hst.booleans(), hst.floats(0.5, 3.0))
def test_convex_polygon_offset_keeps_the_radius(angles, side, linear, r):
    """A convex polygon (corners on a circle of radius 40, run counter-clockwise) offset by r to the
    left (inside) or the right (outside): no point of the tool centre path comes closer than r to
    the polygon (no gouge), and the middle of every edge long enough for it is touched (distance r)
    by the path. Inside, the corners are the offset lines' intersections; outside, G25 extensions
    or G26 arcs, both at least r away."""
    angles = sorted(angles)
    pts = [(40 * math.cos(a), 40 * math.sin(a)) for a in angles]
    if min(math.dist(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))) < 8 * r:
        return  # an edge too short for the radius inside: a bottleneck (tested elsewhere)
    if any(b - a > math.pi - 0.05 for a, b in zip(angles, angles[1:] + [angles[0] + 2 * math.pi])):
        return  # not strictly convex around the centre
    closed = pts * 2 + [pts[0]]  # twice round: the open ends (first and last element) are left out
    elems = [Elem("L", closed[i], closed[i + 1]) for i in range(len(closed) - 1)]
    d = side * r
    chain = offset_chain(elems, d, linear)
    path = [p for e, i in chain if 0 < i < len(elems) - 1 for p in _samples(e)]
    edges = [(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    assert min(min(_seg_dist(p, a, b) for a, b in edges) for p in path) >= r - 1e-6
    for a, b in edges:
        mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        assert abs(min(math.dist(mid, p) for p in path) - r) < 1e-6 or \
            abs(min(_seg_dist(mid, *seg) for seg in zip(path, path[1:])) - r) < 1e-6
