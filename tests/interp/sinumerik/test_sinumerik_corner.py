"""Sinumerik chamfers and roundings at contour corners: CHF=, CHR=, RND=, RNDM=, FRC=, FRCM=
(docs/dialects/sinumerik.md, "Chamfers and roundings"). Every corner point below is worked out by
hand from the geometry:

- RND=r between two lines meeting at a deflection angle phi (the angle between their directions):
  the tangent points lie r tan(phi/2) from the corner, the centre r from both lines on the inner side.
- CHR=c: the chamfer's ends lie c from the corner on each element; CHF=L: its length is L, so
  between lines the legs are c = L / (2 cos(phi/2)).
- A rounding next to an arc of radius R: its centre lies on the arc's concentric circle R - r
  (inside) or R + r (outside) and on the other element's offset, the tangent point on the arc is
  where the line from the arc's centre through the fillet's centre meets the arc.
"""
from __future__ import annotations

import math

import pytest

from cutsim import CutsimError
from cutsim.interp import InterpConfig, canon, interpret

S3 = math.sqrt(3.0)
HEAD = "T1 D1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\n"  # the contour starts at (0, 0, -1)


def run(text, radius=5.0, kind="mill"):
    cfg = InterpConfig(dialect="sinumerik", machine_kind=kind, start=(0.0, 0.0, 50.0), tool_radii={1: radius})
    return interpret("t.mpf", text, cfg)


def contour(prog):
    """The moves at Z-1 (the contour) as (kind, start xy, end xy, centre xy or None, cw or None, feed)."""
    out = []
    for r in prog.moves:
        if abs(r.start[2] + 1) > 1e-9 or abs(r.end[2] + 1) > 1e-9:
            continue
        centre = (r.center[0], r.center[1]) if isinstance(r, canon.Arc) else None
        out.append((type(r).__name__, r.start[:2], r.end[:2], centre, getattr(r, "clockwise", None),
                    getattr(r, "feed", None)))
    return out


def close(a, b, tol=1e-6):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def assert_path(got, expected):
    """``expected``: (kind, start, end, centre or None) per move."""
    assert len(got) == len(expected), got
    for g, e in zip(got, expected):
        assert g[0] == e[0], (g, e)
        assert close(g[1], e[1]) and close(g[2], e[2]), (g, e)
        if e[3] is not None:
            assert close(g[3], e[3]), (g, e)


def error_of(text, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, **kw)
    return e.value


# -- between lines ---------------------------------------------------------------------------------------
def test_rnd_at_a_right_angle():
    """phi = 90: the tangent points r tan 45 = r = 5 from (20, 0): (15, 0) and (20, 5); centre (15, 5),
    counter-clockwise (the path turns left)."""
    got = contour(run(HEAD + "G1 X20 RND=5\nY20\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (15, 0), None), ("Arc", (15, 0), (20, 5), (15, 5)),
                      ("Feed", (20, 5), (20, 20), None)])
    assert got[1][4] is False  # counter-clockwise


def test_rnd_at_sixty_degrees_and_a_right_turn():
    """To (20, 0), then 10 at -60 degrees (a right turn of phi = 60): r = 3 gives r tan 30 = sqrt 3;
    the points (20 - sqrt 3, 0) and (20 + sqrt3 cos 60, -sqrt 3 sin 60) = (20 + sqrt3/2, -1.5); the
    centre 3 below the first, (20 - sqrt 3, -3), clockwise."""
    end = (20 + 10 * math.cos(math.radians(60)), -10 * math.sin(math.radians(60)))
    got = contour(run(HEAD + f"G1 X20 RND=3\nX{end[0]:.9f} Y{end[1]:.9f}\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (20 - S3, 0), None), ("Arc", (20 - S3, 0), (20 + S3 / 2, -1.5), (20 - S3, -3)),
                      ("Feed", (20 + S3 / 2, -1.5), end, None)])
    assert got[1][4] is True  # clockwise
    centre = (20 - S3, -3)  # 3 from both lines: y = 0 and the line through (20, 0) at -60 degrees
    assert abs(math.sin(math.radians(60)) * (centre[0] - 20) + math.cos(math.radians(60)) * centre[1]) == \
        pytest.approx(3)


def test_chr_and_chf():
    """CHR=3 at (20, 0) (90 degrees): (17, 0) to (20, 3). CHF=3 at sixty degrees: legs 3 / (2 cos 30) =
    sqrt 3: (20 - sqrt 3, 0) to (20 + sqrt3/2, 1.5), a chamfer of length 3."""
    got = contour(run(HEAD + "G1 X20 CHR=3\nY20\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (17, 0), None), ("Feed", (17, 0), (20, 3), None),
                      ("Feed", (20, 3), (20, 20), None)])
    end = (25, 5 * S3)
    got = contour(run(HEAD + f"G1 X20 CHF=3\nX25 Y{end[1]:.12f}\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (20 - S3, 0), None), ("Feed", (20 - S3, 0), (20 + S3 / 2, 1.5), None),
                      ("Feed", (20 + S3 / 2, 1.5), end, None)])
    assert math.dist(got[1][1], got[1][2]) == pytest.approx(3)


def test_rndm_rounds_every_corner_until_rndm_0():
    """A 20 x 20 square under RNDM=2: the corners (20, 0), (20, 20), (0, 20) get arcs of radius 2;
    RNDM=0 in the block Y0 (the move leading to (0, 0)) leaves (0, 0) sharp, and (40, 0) too."""
    text = HEAD + "RNDM=2\nG1 X20\nY20\nX0\nY0 RNDM=0\nX40\nY5\nG0 Z5\nM30\n"
    got = contour(run(text))
    assert_path(got, [("Feed", (0, 0), (18, 0), None), ("Arc", (18, 0), (20, 2), (18, 2)),
                      ("Feed", (20, 2), (20, 18), None), ("Arc", (20, 18), (18, 20), (18, 18)),
                      ("Feed", (18, 20), (2, 20), None), ("Arc", (2, 20), (0, 18), (2, 18)),
                      ("Feed", (0, 18), (0, 0), None), ("Feed", (0, 0), (40, 0), None),
                      ("Feed", (40, 0), (40, 5), None)])


def test_a_collinear_or_tangent_transition_is_no_corner():
    got = contour(run(HEAD + "G1 X10 RND=2\nX20\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (10, 0), None), ("Feed", (10, 0), (20, 0), None)])


def test_two_roundings_share_an_element():
    """A 10 mm element with RND=5 at both of its right-angle corners is used up: (0, 0) -> (15, 0),
    arc to (20, 5), arc to (15, 10) (the element (20, 0) -> (20, 10) has no length left), back."""
    got = contour(run(HEAD + "G1 X20 RND=5\nY10 RND=5\nX0\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (15, 0), None), ("Arc", (15, 0), (20, 5), (15, 5)),
                      ("Arc", (20, 5), (15, 10), (15, 5)), ("Feed", (15, 10), (0, 10), None)])


# -- with arcs -----------------------------------------------------------------------------------------------
def test_rnd_between_a_line_and_an_arc():
    """(0, 0) -> (20, 0), then G3 about (30, 0), R 10, to (30, -10): at (20, 0) the arc heads -Y, a right
    turn. The centre lies 2 below the line (y = -2) and outside the circle, 12 from (30, 0): x = 30 -
    sqrt(144 - 4). Tangent points: (30 - sqrt 140, 0) on the line, (30 - 10 sqrt140/12, -10 * 2/12) on
    the arc."""
    x = 30 - math.sqrt(140)
    got = contour(run(HEAD + "G1 X20 RND=2\nG3 X30 Y-10 I10 J0\nG0 Z5\nM30\n"))
    on_arc = (30 - 10 * math.sqrt(140) / 12, -10 * 2 / 12)
    assert_path(got, [("Feed", (0, 0), (x, 0), None), ("Arc", (x, 0), on_arc, (x, -2)),
                      ("Arc", on_arc, (30, -10), (30, 0))])
    assert got[1][4] is True


def test_a_cusp_between_two_arcs_is_refused():
    """G2 about (0, -10) ends at (10, -10) heading -Y; G2 about (20, -10) starts there heading +Y: the
    contour turns back, there is no corner to round."""
    e = error_of(HEAD + "G2 X10 Y-10 I0 J-10 RND=2\nX20 Y-20 I10 J0\nG0 Z5\nM30\n")
    assert e.line == 4 and "turns back" in e.message


def test_rnd_between_two_arcs():
    """G3 about (0, 10) from (0, 0) to (10, 10) ends heading +Y. A G2 about (20, 10) starts there heading
    +Y too: tangent, nothing inserted. A G2 about (10, 20) starts heading -X: a left turn of 90. The
    fillet (r 2) lies on the left of both: inside the first arc (a CCW arc's left), its centre
    R - 2 = 8 from (0, 10), and outside the second (a CW arc's left), R + 2 = 12 from (10, 20); its
    ends lie on both circles and 2 from its centre."""
    got = contour(run(HEAD + "G3 X10 Y10 I0 J10 RND=2\nG2 X20 Y20 I10 J0\nG0 Z5\nM30\n"))
    assert [g[0] for g in got] == ["Arc", "Arc"]  # tangent: nothing inserted
    got = contour(run(HEAD + "G3 X10 Y10 I0 J10 RND=2\nG2 X0 Y20 I0 J10\nG0 Z5\nM30\n"))
    assert [g[0] for g in got] == ["Arc", "Arc", "Arc"]
    fil = got[1]
    q = fil[3]
    assert math.dist(q, (0, 10)) == pytest.approx(8) and math.dist(q, (10, 20)) == pytest.approx(12)
    assert math.dist(fil[1], (0, 10)) == pytest.approx(10) and math.dist(fil[2], (10, 20)) == pytest.approx(10)
    assert math.dist(fil[1], q) == pytest.approx(2) and math.dist(fil[2], q) == pytest.approx(2)
    assert close(got[0][2], fil[1]) and close(fil[2], got[2][1]) and close(got[2][2], (0, 20))


def test_chr_on_an_arc_is_a_chord():
    """CHR=5 from the line (0, 0) -> (20, 0) into a G3 about (30, 0) (R 10) starting at (20, 0) heading -Y
    (a right turn): on the line (15, 0); on the arc the point whose chord to (20, 0) is 5, which
    subtends 2 asin(5 / 20) past the start angle pi (counter-clockwise)."""
    got = contour(run(HEAD + "G1 X20 CHR=5\nG3 X30 Y-10 I10 J0\nG0 Z5\nM30\n"))
    a = math.pi + 2 * math.asin(0.25)
    b = (30 + 10 * math.cos(a), 10 * math.sin(a))
    assert_path(got, [("Feed", (0, 0), (15, 0), None), ("Feed", (15, 0), b, None), ("Arc", b, (30, -10), (30, 0))])
    assert math.dist(b, (20, 0)) == pytest.approx(5)


# -- feeds, other planes, units, compensation ------------------------------------------------------------------
def test_feed_of_the_element():
    """Without FRC the element takes the F of the block leading away from the corner (50); FRC=20 in
    the block with RND: 20; FRCM=30 modal until FRCM=0."""
    got = contour(run(HEAD + "G1 X20 F100 RND=5\nY20 F50\nG0 Z5\nM30\n"))
    assert [g[5] for g in got] == [100, 50, 50]
    got = contour(run(HEAD + "G1 X20 RND=5 FRC=20\nY20\nX0 RND=2\nY0\nG0 Z5\nM30\n"))
    assert [g[5] for g in got] == [100, 20, 100, 100, 100, 100]
    got = contour(run(HEAD + "FRCM=30\nG1 X20 RND=5\nY20 CHR=2\nFRCM=0\nX0 RND=2\nY0\nG0 Z5\nM30\n"))
    assert [g[5] for g in got] == [100, 30, 100, 30, 100, 100, 100]


def test_a_chamfer_with_g0_is_a_rapid():
    got = contour(run(HEAD + "G1 X20 CHR=3\nG0 Y20\nM30\n"))
    assert [g[0] for g in got] == ["Feed", "Rapid", "Rapid"]


def test_in_the_zx_plane():
    """G18: the corner in Z and X. From (0, 0, -1) along +X to X20, then along -Z to Z-21 with RND=5:
    the tangent points (15, -1) and (20, -6) in (X, Z), the centre (15, -6)."""
    prog = run("T1 D1 M6\nG0 X0 Y0 Z-1\nG18 G1 X20 F100 RND=5\nZ-21\nM30\n")
    recs = [r for r in prog.moves if isinstance(r, (canon.Feed, canon.Arc))]
    assert close(recs[0].end, (15, 0, -1)) and isinstance(recs[1], canon.Arc)
    assert close(recs[1].end, (20, 0, -6)) and close(recs[1].center, (15, 0, -6)) and recs[1].plane == "ZX"
    assert close(recs[2].start, (20, 0, -6)) and close(recs[2].end, (20, 0, -21))


def test_inch_units():
    """G70: RND=0.2 is 5.08 mm: from (0, 0) to X1 inch (25.4), then up: (20.32, 0) and (25.4, 5.08)."""
    got = contour(run(HEAD + "G70 G1 X1 RND=0.2\nY1\nG71 G0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (20.32, 0), None), ("Arc", (20.32, 0), (25.4, 5.08), (20.32, 5.08)),
                      ("Feed", (25.4, 5.08), (25.4, 25.4), None)])


def test_rounding_then_radius_compensation():
    """The rounding is part of the contour the tool is offset from: G42 (tool right of the path, 5 mm)
    around the rounded corner at (20, 0) with RND=5 runs the concentric arc of radius 5 + 5 about
    (15, 5), from (15, -5) to (25, 5)."""
    prog = run("T1 D1 M6\nG0 X-10 Y-10 Z-1\nG42 G1 X0 Y0 F100\nX20 RND=5\nY20\nG40 G1 X30 Y30\nM30\n")
    arcs = [r for r in prog.moves if isinstance(r, canon.Arc)]
    fil = [a for a in arcs if close(a.center[:2], (15, 5))]
    assert len(fil) == 1
    assert close(fil[0].start[:2], (15, -5)) and close(fil[0].end[:2], (25, 5)) and fil[0].clockwise is False


def test_the_element_waits_for_a_block_without_a_move():
    """M8, an assignment and S500 between the two moves (three blocks): the rounding is made."""
    got = contour(run(HEAD + "G1 X20 RND=5\nM8\nR1=2\nS500\nY20\nG0 Z5\nM30\n"))
    assert [g[0] for g in got] == ["Feed", "Arc", "Feed"]


def test_more_than_three_blocks_between_no_element():
    """Four blocks without a move in the plane: no rounding (the manual), one warning at RND."""
    prog = run(HEAD + "G1 X20 RND=5\nM8\nR1=2\nR2=3\nS500\nY20\nG0 Z5\nM30\n")
    assert [g[0] for g in contour(prog)] == ["Feed", "Feed"]
    assert [(s.line, s.col) for s, m in prog.warnings if "RND" in m] == [(4, 8)]


def test_the_next_move_leaving_the_plane_makes_no_element():
    """RND before a plunge along Z: no rounding, one warning; the moves as programmed."""
    prog = run(HEAD + "G1 X20 RND=5\nZ-3\nY20\nM30\n")
    moves = [(r.start, r.end) for r in prog.moves][-3:]
    assert moves == [((0, 0, -1), (20, 0, -1)), ((20, 0, -1), (20, 0, -3)), ((20, 0, -3), (20, 20, -3))]
    assert any("RND= inserts no rounding here: the next move leaves the plane" in m for _, m in prog.warnings)


def test_a_tool_change_between_waits_behind_the_element():
    """Records of the blocks between (a spindle change) come after the element, before the next move."""
    prog = run(HEAD + "G1 X20 RND=5\nS800 M3\nY20\nM30\n")
    kinds = [type(r).__name__ for r in prog.records]
    i = kinds.index("Arc")
    assert kinds[i + 1] == "Spindle" and kinds[i + 2] == "Feed"


# -- bad forms ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("text,line,col,fragment", [
    ("G1 X20 RND=5\nM30\n", 4, 8, "RND= on the last move: no move follows"),
    ("G1 X20 RND=5\n", 4, 8, "RND= on the last move"),
    ("G1 X20 CHF=2\nM5\nM30\n", 4, 8, "CHF= on the last move"),
    ("G1 X4 RND=5\nY20\nM30\n", 4, 7, "RND=5: the rounding of radius 5 is longer than an element"),
    ("G1 X20 RND=5\nY4\nM30\n", 4, 8, "longer than an element"),
    ("G1 X20 RND=5\nY10 RND=6\nX0\nM30\n", 5, 5, "longer than an element"),
    ("G1 X20 CHR=21\nY30\nM30\n", 4, 8, "the chamfer's legs of 21 are longer than an element"),
    ("G1 X20 CHF=30\nY30\nM30\n", 4, 8, "longer than an element"),
    ("G1 X20 RND=5\nX10\nM30\n", 4, 8, "turns back on itself"),
    ("RND=5\nG1 X20\nM30\n", 4, 1, "RND= goes in the block whose move in the plane leads to the corner"),
    ("G1 X20 RND=5 CHF=2\nY20\nM30\n", 4, 14, "CHF= and RND= in one block"),
    ("G1 X20 RND=-1\nY20\nM30\n", 4, 8, "RND=-1 must not be negative"),
    ("G1 X20 RND=2 FRC=0\nY20\nM30\n", 4, 14, "FRC=0: the feed of the chamfer or rounding must be more than 0"),
    ("G1 X20 RND=5\nX30 Y10 Z-3\nM30\n", 4, 8, "not in the plane G17 (a ramp, a helix"),
    ("G1 X20 Y5 Z-3 RND=5\nY20\nM30\n", 4, 15, "not in the plane"),
    ("G0 X20 RND=5\nG1 Y20\nM30\n", 4, 8, "a rounding next to a G0 move is not modelled"),
    ("G3 X20 Y0 I10 J0 RND=12\nG1 X0\nM30\n", 4, 18, "does not fit inside the arc of radius 10"),
    ("R1=RND\nM30\n", 4, 4, "RND is a corner's chamfer, rounding or feed"),
    ("G1 X20 RND=1000000\nY20\nM30\n", 4, 8, "RND = 1000000: value exceeds the permitted range 0 to 99"),
    ("G1 X20 RND=2 FRC=2000000\nY20\nM30\n", 4, 14, "FRC = 2000000: value exceeds the permitted range"),
    ("SCALE X2\nG1 X20 RND=5\nY20\nM30\n", 5, 8, "scales it unevenly"),
    ("G1 X20 RND=5\nG42 Y20\nM30\n", 4, 8, "where the radius compensation starts, changes or ends (G42)"),
    ("G41 G1 X20\nY20 CHR=2\nG40 X30 Y30\nM30\n", 5, 5, "(G40) is not modelled"),
    ("G41 G1 X20\nRNDM=2\nY20\nG40\nG0 Z5\nM30\n", 6, 1, "RNDM: a chamfer or rounding at a corner where"),
    ("G41 G1 X20 RND=2\nG42 Y20\nM30\n", 4, 12, "(G42) is not modelled"),
    ("G41 G1 X20\nG40 Y20 RND=2\nX0\nM30\n", 5, 9, "(G40) is not modelled"),
])
def test_bad_corners(text, line, col, fragment):
    e = error_of(HEAD + text)
    assert (e.line, e.col) == (line, col), e
    assert fragment in e.message, e.message


def test_rndm_on_the_last_move_is_no_error():
    got = contour(run(HEAD + "RNDM=2\nG1 X20\nM30\n"))
    assert [g[0] for g in got] == ["Feed"]


def test_a_cycle_after_the_held_move_under_a_frame():
    """TRANS X5: G1 X20 RND=5 ends at machine X25; CYCLE81 comes next (a cycle's move, run in the
    WCS and mapped): no rounding (one warning), the held move goes out once, not mapped a second
    time: it ends at (25, 0, -1), and the cycle drills at X25 too."""
    prog = run("T1 D1 M6\nTRANS X5\nG0 X0 Y0 Z-1\nG1 X20 F100 RND=5\nCYCLE81(10, 0, 2, -5)\nM30\n")
    ends = [tuple(round(v, 6) for v in r.end) for r in prog.moves]
    assert ends == [(5, 0, -1), (25, 0, -1), (25, 0, 2), (25, 0, -5), (25, 0, 10)]
    assert any("RND= inserts no rounding here: a cycle's move comes next" in m for _, m in prog.warnings)
    prog = run("T1 D1 M6\nG0 X0 Y0 Z-1\nG1 X20 F100 RND=5\nCYCLE81(10, 0, 2, -5)\nM30\n")  # no frame
    assert [tuple(round(v, 6) for v in r.end) for r in prog.moves][1:] == [(20, 0, -1), (20, 0, 2), (20, 0, -5),
                                                                           (20, 0, 10)]


def test_rndm_on_the_departure_move_of_g40():
    """Under RNDM the G40 block's own move (the departure) is the last compensated move: it goes into
    the compensation as it is, and the path stays continuous."""
    prog = run(HEAD + "G41 X20\nY20\nG40 X30 Y30 RNDM=1\nX40\nRNDM=0\nG0 Z5\nM30\n", radius=1.0)
    moves = prog.moves
    assert all(math.dist(a.end, b.start) < 1e-9 for a, b in zip(moves, moves[1:]))
    assert close(moves[-2].end, (40, 30, -1)) or close(moves[-1].start, (40, 30, -1))


def test_a_chamfer_into_a_g0_move_is_a_rapid_chamfer():
    """CHR=3 at (20, 0) between G1 X20 and G0 Y20 (a right angle): the chamfer's ends lie 3 from the
    corner, (17, 0) and (20, 3); it is traversed at rapid like the block leading away (the manual:
    F, FRC, FRCM are not active for a chamfer at G0), FRC=20 is ignored."""
    got = contour(run(HEAD + "G1 X20 CHR=3 FRC=20\nG0 Y20\nG0 Z5\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (17, 0), None), ("Rapid", (17, 0), (20, 3), None),
                      ("Rapid", (20, 3), (20, 20), None)])
    assert got[0][5] == 100


def test_a_chamfer_after_a_g0_move_takes_the_feed_leading_away():
    """CHF on a G0 move, G1 leading away: CHF=L between perpendicular lines has legs L / sqrt(2), so
    CHF=4.242640687 gives legs 3: rapid (0, 0) -> (17, 0), the chamfer (17, 0) -> (20, 3) at the F of the
    block leading away (F60), then (20, 3) -> (20, 20)."""
    got = contour(run(HEAD + "G0 X20 CHF=4.242640687\nG1 Y20 F60\nG0 Z5\nM30\n"))
    assert_path(got, [("Rapid", (0, 0), (17, 0), None), ("Feed", (17, 0), (20, 3), None),
                      ("Feed", (20, 3), (20, 20), None)])
    assert got[1][5] == got[2][5] == 60


def test_a_rounding_next_to_g0_is_no_error_where_no_element_is_inserted():
    """Under RNDM a G0 retract along Z leaves the plane, a G0 going straight on is a tangent
    transition, four blocks between are too many: no corner element, so no G0 error; the moves run."""
    got = contour(run(HEAD + "RNDM=2\nG1 X20\nG0 X30\nG0 Z5\nRNDM=0\nM30\n"))
    assert_path(got, [("Feed", (0, 0), (20, 0), None), ("Rapid", (20, 0), (30, 0), None)])
    prog = run(HEAD + "G0 X20 RND=5\nM8\nR1=1\nR2=2\nS500\nG1 Y20\nG0 Z5\nM30\n")
    assert [g[0] for g in contour(prog)] == ["Rapid", "Feed"]
    assert [(s.line, s.col) for s, m in prog.warnings if "RND" in m] == [(4, 8)]


def _files(tmp_path, main, **subs):
    for name, text in subs.items():
        (tmp_path / f"{name}.spf").write_text(text)
    path = tmp_path / "main.mpf"
    path.write_text(main)
    return str(path)


def _error_in_files(path):
    """The error of running ``path``, and the text of the line it names in the file it names."""
    with pytest.raises(CutsimError) as e:
        interpret(path, open(path).read(), InterpConfig(
            dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: 5.0}))
    lines = open(e.value.program).read().splitlines()
    assert 1 <= e.value.line <= len(lines), e.value  # a line that exists in the file named
    return e.value, lines[e.value.line - 1]


@pytest.mark.parametrize("main,subs,file,line,text,fragment", [
    # the held move in the main program, the next move (too short for the rounding) in the subprogram
    ("T1 D1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X20 RND=5\nSUBA\nM30\n", {"SUBA": "G90\nG1 Y4\nM17\n"},
     "main.mpf", 4, "G1 X20 RND=5", "longer than an element"),
    # the held move the last of the subprogram, the next move back in the main program
    ("T1 D1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nSUBB\nG1 Y4\nM30\n", {"SUBB": "G1 X20 RND=5\nM17\n"},
     "SUBB.spf", 1, "G1 X20 RND=5", "longer than an element"),
    # RNDM (the fuzz case): a G0 move held in the main program, the G1 in the subprogram
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nRNDM=1\nG0 X20\nSUBC\nM30\n", {"SUBC": "G1 Y20 F100\nM17\n"},
     "main.mpf", 4, "G0 X20", "the corner at the end of this G0 move would be rounded at rapid traverse"),
    # RNDM: a G1 held in the main program, the G0 leading away in the subprogram: the G0 block
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nRNDM=1\nG1 X20 F100\nSUBD\nM30\n", {"SUBD": "G90\nG0 Y20\nM17\n"},
     "SUBD.spf", 2, "G0 Y20", "the corner at the start of this G0 move would be rounded"),
    # ... the hint names the block leading to the corner, in its file
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nRNDM=1\nG1 X20 F100\nSUBD\nM30\n", {"SUBD": "G90\nG0 Y20\nM17\n"},
     "SUBD.spf", 2, "G0 Y20", "write RNDM=0 in or before the block leading to it (line 4 of "),
    # RND= next to G0 across the return: at the word, in the subprogram
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nSUBE\nG0 Y20\nM30\n", {"SUBE": "G1 X20 F100 RND=2\nM17\n"},
     "SUBE.spf", 1, "G1 X20 F100 RND=2", "a rounding next to a G0 move is not modelled"),
    # a compensation change after the return
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nSUBF\nG42 G1 Y20\nM30\n", {"SUBF": "G1 X20 F100 CHR=2\nM17\n"},
     "SUBF.spf", 1, "G1 X20 F100 CHR=2", "(G42) is not modelled"),
    # a ramp after the return
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nSUBG\nG1 Y20 Z-3\nM30\n", {"SUBG": "G1 X20 F100 RND=2\nM17\n"},
     "SUBG.spf", 1, "G1 X20 F100 RND=2", "not in the plane G17"),
    # RND= on the last move of a subprogram that ends the program
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nSUBH\n", {"SUBH": "G1 X20 F100 RND=2\nM17\n"},
     "SUBH.spf", 1, "G1 X20 F100 RND=2", "on the last move"),
    # a GOTOF over lines: the held block's own line
    ("T1 D1 M6\nG0 X0 Y0 Z-1\nG1 X20 F100 RND=5\nGOTOF NEXT\nG1 X0\nNEXT: G1 Y4\nM30\n", {},
     "main.mpf", 3, "G1 X20 F100 RND=5", "longer than an element"),
])
def test_errors_of_a_corner_across_files_name_a_line_of_their_own_file(tmp_path, main, subs, file, line, text,
                                                                       fragment):
    e, got = _error_in_files(_files(tmp_path, main, **subs))
    assert (e.program, e.line) == (str(tmp_path / file), line), e
    assert got == text and fragment in e.message, (got, e.message)


def test_a_warning_of_a_corner_across_files_names_its_own_file(tmp_path):
    """RND= in the main program, the subprogram's first move plunges (leaves the plane): no rounding,
    the warning at the word in main.mpf."""
    path = _files(tmp_path, "T1 D1 M6\nG0 X0 Y0 Z-1\nG1 X20 F100 RND=5\nSUBA\nM30\n", SUBA="G1 Z-3\nY20\nM17\n")
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: 5.0})
    prog = interpret(path, open(path).read(), cfg)
    assert [(s.program, s.line, s.col) for s, m in prog.warnings if "RND=" in m] == [(path, 3, 13)]
