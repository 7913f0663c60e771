"""G70, G71, G72 (LinuxCNC's lathe cycles) against positions worked out by hand from their rules
(docs/dialects/rs274ngc.md, "G70, G71, G72"); test_rs274ngc_oracle.py compares them with rs274
move by move (tests/data/programs/rs274ngc/lathe-g7x.ngc and the random programs)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main
from cutsim.interp import interpret
from cutsim.interp.canon import Arc, Feed, Rapid
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.modal import InterpConfig

# a shaft profile: diameter-free radii, P0 (5, 0), a 45 degree taper from (5, -10) to (10, -15)
PROFILE = "o100 sub\nG1 X5 Z0\nG1 Z-10\nG1 X10 Z-15\nG1 Z-25\nG1 X20\no100 endsub\n"
START = "G18 G21 G90 G8\nF100\n"


def moves(text: str):
    prog = interpret("t.ngc", START + text + "\nM2\n", InterpConfig(dialect="rs274ngc", machine_kind="lathe"))
    return [r for r in prog.records if isinstance(r, (Rapid, Feed, Arc)) and math.dist(r.start, r.end) > 1e-9]


def xz(r):
    return (round(r.end[0], 6), round(r.end[2], 6))


def test_g71_passes_step_i_from_s_and_run_from_the_line_s_p0_to_the_profile():
    ms = moves(PROFILE + "G0 X22 Z3\nG71 Q100 I2 R0.5")
    feeds = [r for r in ms if isinstance(r, Feed)]
    # pass at X = 22 - 2k while X > 5 (P0): 22, 20, ..., 6 (9 passes), then the profile (4 feeds) and
    # the closing line from its end (20, -25) out to S's X 22
    assert [round(r.end[0], 6) for r in feeds[:9]] == [22, 20, 18, 16, 14, 12, 10, 8, 6]
    for r in feeds[:9]:
        x = r.end[0]
        assert r.start[2] == pytest.approx(3 - 3 * (22 - x) / 17)  # on the line S (22, 3) - P0 (5, 0)
        # the end: Z-25 (profile end, closing line) above X10, the taper z = -10 - (x - 5) below
        assert r.end[2] == pytest.approx(-25 if x > 10 else -10 - (x - 5))
    assert [xz(r) for r in feeds[9:]] == [(5, -10), (10, -15), (10, -25), (20, -25), (22, -25)]
    # after each pass: back R in both axes, along Z to R past its start, to its start
    first = ms.index(feeds[0])
    assert [xz(r) for r in ms[first + 1:first + 4]] == [(22.5, -24.5), (22.5, 2.5), (22, 3)]


def test_g71_d_offsets_the_profile_with_an_arc_about_the_convex_corner():
    ms = moves(PROFILE + "G0 X20 Z2\nG71 Q100 D0.5 I2 R0.5")
    arcs = [r for r in ms if isinstance(r, Arc)]
    assert len(arcs) == 1  # the corner (10, -15) the offset goes round; (5, -10) is concave
    a = arcs[0]
    assert (a.center[0], a.center[2]) == pytest.approx((10, -15))
    s = 0.5 / math.sqrt(2)  # the taper's offset ends 0.5 along its normal (1, 1)/sqrt 2
    assert (a.start[0], a.start[2]) == pytest.approx((10 + s, -15 + s))
    assert (a.end[0], a.end[2]) == pytest.approx((10.5, -15))
    feeds = [r for r in ms if isinstance(r, Feed)]
    # the concave corner: X5.5 meets the taper's offset x - 5 = -(z + 10) + 0.5 sqrt 2
    contour = feeds[-4:]  # to the taper, along it, Z-run, out at Z-24.5 (the arc between)
    assert xz(contour[0]) == pytest.approx((5.5, -10 - 0.5 + 0.5 * math.sqrt(2)))
    # the pass at X10 ends on the taper's offset: z = -10 - 5 + 0.5 sqrt 2
    at10 = next(r for r in feeds if abs(r.end[0] - 10) < 1e-9 and abs(r.start[0] - 10) < 1e-9)
    assert at10.end[2] == pytest.approx(-15 + 0.5 * math.sqrt(2))


def test_a_short_pass_retracts_half_its_length():
    # a convex arc about (4, -4) of radius 4, offset 0.4: radius 4.4; the pass at X5 starts on the line
    # S (11, 2) - P0' (4, 0.4) and ends on the arc at z = -4 + sqrt(4.4^2 - 1)
    prof = "o101 sub\nG0 X4 Z0\nG3 X8 Z-4 K-4\nG1 Z-10\nG1 X11\no101 endsub\n"
    ms = moves(prof + "G0 X11 Z2\nG71 Q101 I1.5 R0.3 D0.4")
    i = next(k for k, r in enumerate(ms) if isinstance(r, Feed) and abs(r.end[0] - 5) < 1e-9)
    zs, ze = ms[i].start[2], ms[i].end[2]
    assert zs == pytest.approx(2 - 1.6 * 6 / 7)
    assert ze == pytest.approx(-4 + math.sqrt(4.4 ** 2 - 1))
    r = (zs - ze) / 2  # less than R0.3
    assert xz(ms[i + 1]) == pytest.approx((5 + r, ze + r))


def test_g72_steps_in_z_and_cuts_along_x():
    prof = "o103 sub\nG1 X13 Z-7\nG1 X8\nG1 X6 Z-3\nG1 X0\no103 endsub\n"
    ms = moves(prof + "G0 X14 Z1\nG72 Q103 I2 R0.3")
    feeds = [r for r in ms if isinstance(r, Feed)]
    # passes at Z 1, -1, -3, -5 (above P0's Z-7), from the line S (14, 1) - P0 (13, -7) to X0 (the
    # closing line) at Z1 and Z-1, to the corner (6, -3), to the taper x = 8 - (z + 7) / 2 at Z-5
    assert [(round(r.end[2], 6), round(r.end[0], 6)) for r in feeds[:4]] == [(1, 0), (-1, 0), (-3, 6), (-5, 7)]
    assert [round(r.start[0], 6) for r in feeds[:4]] == [14, 13.75, 13.5, 13.25]


def test_g70_passes_at_the_distances_e_plus_d_minus_e_times_passes_left():
    prof = "o100 sub\nG1 X6 Z0\nG1 Z-10\nG1 X10 Z-12\no100 endsub\n"
    ms = moves(prof + "G0 X11 Z2\nG70 Q100 D1 E0.2 P3")
    starts = [r.end[0] for r in ms if isinstance(r, Rapid) and abs(r.end[2]) < 1e-9]
    assert starts == pytest.approx([6 + 0.2 + 0.8 * 2 / 3, 6 + 0.2 + 0.8 / 3, 6.2])


@pytest.mark.parametrize("d, arc", [(0.0101, True), (0.01, False)])
def test_a_corner_gets_its_arc_only_when_d_sin_turn_is_over_a_hundredth(d, arc):
    # a square convex corner at (5, -5): sin 90 = 1
    prof = "o100 sub\nG1 X2 Z0\nG1 Z-5\nG1 X5\nG1 Z-12\nG1 X8\no100 endsub\n"
    ms = moves(prof + f"G0 X11 Z2\nG71.2 Q100 D{d}")
    assert any(isinstance(r, Arc) for r in ms) == arc
    if not arc:  # the two offset lines meet at (5 + d, -5 + d)
        assert any(xz(r) == pytest.approx((5 + d, -5 + d)) for r in ms)


# a V pocket: P0 (6, 0) down to (5, -10), up to the end (10, -12); S (11, 2)
POCKET = "o200 sub\nG1 X6 Z0\nG1 X5 Z-10\nG1 X10 Z-12\no200 endsub\nG0 X11 Z2\n"


def climb_z(x: float) -> float:  # the line (5, -10) - (10, -12)
    return -10 - 2 * (x - 5) / 5


def test_g71_roughs_a_pocket_on_the_levels_from_s_down_to_its_bottom():
    ms = moves(POCKET + "G71 Q200 I0.5 R0.5")
    passes = [r for r in ms if isinstance(r, Feed) and r.start[0] == r.end[0] and r.end[2] < r.start[2] - 1]
    # levels 11 - 0.5 k down to 5.5 (at 5, the bottom, the pass has no length)
    assert [round(r.end[0], 6) for r in passes] == [11 - 0.5 * k for k in range(12)]
    for r in passes:
        x = r.end[0]
        # from the line S-P0 above P0, from the dive (6, 0) - (5, -10) inside the pocket
        assert r.start[2] == pytest.approx(2 * (x - 6) / 5 if x > 6 else -10 * (6 - x))
        assert r.end[2] == pytest.approx(-12 if x > 10 else climb_z(x))
    # inside the pocket the tool goes back to the pass's start at feed, then down the dive at feed
    last = ms.index(passes[-1])
    assert [type(r) for r in ms[last + 1:last + 4]] == [Rapid, Rapid, Feed]
    assert xz(ms[last + 3]) == (5.5, -5.0) and isinstance(ms[last + 4], Feed) and xz(ms[last + 4]) == (5, -10)
    assert [xz(r) for r in ms[-2:]] == [(10, -12), (11, -12)]


def test_g71_1_leaves_the_pocket_and_g71_2_cuts_only_the_contour_here():
    # I2: levels 11, 9, 7 above P0; the next (5) is the bottom: G71.1 and G71 alike
    rough = [xz(r) for r in moves(POCKET + "G71.1 Q200 I2") if isinstance(r, Feed)]
    assert rough == [(11, -12), (9, climb_z(9)), (7, climb_z(7)), (5, -10), (10, -12), (11, -12)]
    # G71.2: down the profile to the bottom and up it (one pocket: no passes)
    assert [xz(r) for r in moves(POCKET + "G71.2 Q200 I0.5")][-4:] == [(6, 0), (5, -10), (10, -12), (11, -12)]


@pytest.mark.parametrize("prof, start, code", [
    # G71 cutting towards +Z: a concave G2 arc, up a taper, a G3 arc (a pocket between them)
    ("G1 X6 Z-20\nG2 X6 Z-12 R6\nG1 X8 Z-10\nG3 X8 Z-4 R4\nG1 X10 Z-2", "X11 Z-22", "G71.2"),
    # G72 with P0 below the profile's end in Z: a pocket between a G3 and a G2 arc
    ("G1 X13 Z-7\nG1 X10 Z-6\nG1 X8 Z-7.5\nG3 X5 Z-5.5 R2.5\nG1 X3 Z-6\nG2 X1 Z-4 R2\nG1 X0 Z-3", "X14 Z1", "G72.2"),
])
def test_a_pockets_arcs_keep_their_sense_in_every_frame(prof, start, code):
    # without D every arc cut is a part of one of the profile's (told by its radius R), in its sense:
    # G2 clockwise
    ms = moves(f"o300 sub\n{prof}\no300 endsub\nG0 {start}\n{code} Q300 I0.3")
    sense = {float(line.split("R")[1]): line.startswith("G2") for line in prof.splitlines() if "R" in line}
    arcs = [r for r in ms if isinstance(r, Arc)]
    assert len(arcs) >= 2
    for r in arcs:
        radius = math.dist((r.start[0], r.start[2]), (r.center[0], r.center[2]))
        assert r.clockwise == sense[min(sense, key=lambda k: abs(k - radius))]
        assert min(abs(k - radius) for k in sense) < 1e-6


@pytest.mark.parametrize("text, message", [
    ("G0 X11 Z2\nG71 I2", "subroutine number Q"),
    ("G17 G0 X11 Z2\nG71 Q100", "ZX plane"),
    ("G0 X22 Z3\nG71 Q100 I0", "more than 0"),
    ("G0 X22 Z3\nG71 Q100 I1 E2", "E word"),
    ("G0 X22 Z3\nG71 Q7", "not defined"),
    ("G0 X22 Z3\nG42.1 D1\nG71 Q100", "G71.0 cannot be used with cutter compensation enabled"),  # rs274's words
    ("G0 X22 Z3\nG41.1 D1\nG72.2 Q100", "G72.2 cannot be used with cutter compensation enabled"),
])
def test_refused_blocks(text, message):
    with pytest.raises(CutsimError, match=message):
        moves(PROFILE + text)


def test_the_motion_mode_after_the_cycle_is_the_profiles_last_g0_as_g1():
    ms = moves(PROFILE + "G0 X22 Z3\nG71 Q100 I2\nX30")
    assert isinstance(ms[-1], Feed) and xz(ms[-1]) == (30, -25)


EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rs274ngc" / "g71-shaft"


def test_the_example_fails_its_checks_without_the_finishing_pass(tmp_path):
    # the example's own checks pass (tests/app/test_examples.py); without G70 the roughing leaves
    # D0.2 on the profile: every turned diameter and the volume fail, the bar beyond stays
    text = EXAMPLE.with_suffix(".nc").read_text().replace("G70 Q100 X32 Z2", "")
    prog = tmp_path / "g71-shaft.nc"
    prog.write_text(text)
    setup = tmp_path / "g71-shaft.toml"
    setup.write_text(EXAMPLE.with_suffix(".toml").read_text()
                     .replace('"tools-turn.tbl"', f'"{EXAMPLE.parent / "tools-turn.tbl"}"'))
    res = CliRunner().invoke(main, ["simulate", str(prog), "--setup", str(setup), "--out", str(tmp_path / "out"), "-q"])
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    failed = {c["name"] for c in report["checks"] if not c["passed"]}
    assert failed == {"journal 12", "taper", "journal 20", "quarter round", "collar 26", "volume #7"}, res.output


def test_a_fillet_rounds_the_corner_at_the_end_of_its_move_with_an_arc_of_radius_a():
    # G70 on X4 Z1 / Z-5 / X8 A0.5 / Z-10: the corner (Z-5, X8) between the step out along X and the
    # run along -Z; the circle of radius 0.5 inside it touches the step at X 8 - 0.5 and the run at
    # Z -5 - 0.5, its centre (Z-5.5, X7.5); from +X to -Z is a left turn in G18's (Z, X): a G3
    ms = moves("o100 sub\nG1 X4 Z1\nG1 Z-5\nG1 X8 A0.5\nG1 Z-10\no100 endsub\nG0 X12 Z2\nG70 Q100 X12 Z2")
    feeds = [r for r in ms if isinstance(r, (Feed, Arc))]
    assert [xz(r) for r in feeds] == [(4, -5), (7.5, -5), (8, -5.5), (8, -10)]
    arc = feeds[2]
    assert isinstance(arc, Arc) and not arc.clockwise
    assert arc.center[0] == pytest.approx(7.5) and arc.center[2] == pytest.approx(-5.5)


@pytest.mark.parametrize("turn", [90, 45])
def test_a_chamfer_is_the_chord_of_the_fillet_circle(turn):
    # C0.5 after the run along -Z, the next line turning `turn` degrees towards +X: the circle of radius
    # 0.5 tangent to both touches each line 0.5 * tan(turn / 2) from the corner (0.5 on a right angle)
    t = math.radians(turn)
    end = (-5 - 4 * math.cos(t), 4 + 4 * math.sin(t))  # (z, x) 4 mm along the turned line
    prog = f"o100 sub\nG1 X4 Z1\nG1 Z-5 C0.5\nG1 X{end[1]:.6f} Z{end[0]:.6f}\no100 endsub\nG0 X12 Z2\nG70 Q100 X12 Z2"
    feeds = [r for r in moves(prog) if isinstance(r, (Feed, Arc))]
    cut = 0.5 * math.tan(t / 2)
    assert all(isinstance(r, Feed) for r in feeds)
    assert xz(feeds[0]) == pytest.approx((4, -5 + cut))
    assert xz(feeds[1]) == pytest.approx((4 + cut * math.sin(t), -5 - cut * math.cos(t)))


# the profile for G70 under compensation: P0 (z 0, x 2), the end E (z -12, x 10)
STEPS = "o100 sub\nG0 X2 Z0\nG1 X5 Z-1\nG1 Z-10\nG1 X8 Z-12\nG1 X10\no100 endsub\n"


def _right(d):  # the unit normal to the right of a direction (dz, dx) in G18's (Z, X)
    n = math.hypot(*d)
    return (d[1] / n, -d[0] / n)


def _meet(p, d, q, e):  # where the line p + t d meets the line q + s e
    t = ((q[0] - p[0]) * e[1] - (q[1] - p[1]) * e[0]) / (d[0] * e[1] - d[1] * e[0])
    return (p[0] + t * d[0], p[1] + t * d[1])


def _offset_meet(a, b, c, r):  # the corner b of a -> b -> c, both lines moved r to their right
    d1, d2 = (b[0] - a[0], b[1] - a[1]), (c[0] - b[0], c[1] - b[1])
    n1, n2 = _right(d1), _right(d2)
    return _meet((a[0] + r * n1[0], a[1] + r * n1[1]), d1, (b[0] + r * n2[0], b[1] + r * n2[1]), d2)


def test_g70_under_compensation_joins_its_first_corner_from_the_profiles_end():
    # rs274 2.9: the move to S (z 2, x 12) is the entry; after reading the profile the nose is taken to
    # be at the profile's end E, the program position still S; the move S -> P0 then trims the moves
    # waiting to the meeting of the two "offset lines" through E: E moved, perpendicular to E -> S and
    # to its left, by r tan(theta / 2), theta = angle(E -> S) - angle(S -> P0) - 90 degrees (measured)
    r, e, s, p0 = 0.5, (-12.0, 10.0), (2.0, 12.0), (0.0, 2.0)
    ms = moves(STEPS + "G0 X20 Z10\nG42.1 D1\nG70 Q100 X12 Z2\nG40\nG0 X20")
    es = math.atan2(s[1] - e[1], s[0] - e[0])
    theta = es - math.atan2(p0[1] - s[1], p0[0] - s[0]) - math.pi / 2
    t = r * math.tan(theta / 2)
    first = (e[0] - t * math.sin(es), e[1] + t * math.cos(es))
    assert isinstance(ms[1], Rapid) and (ms[1].end[0], ms[1].end[2]) == pytest.approx((first[1], first[0]), abs=1e-9)
    # then as usual: the move S -> P0 ends where its offset meets the first feed's (P0 -> z -1, x 5)
    corner = _offset_meet(s, p0, (-1.0, 5.0), r)
    assert isinstance(ms[2], Rapid) and (ms[2].end[0], ms[2].end[2]) == pytest.approx((corner[1], corner[0]), abs=1e-9)
    feeds = [r_ for r_ in ms if isinstance(r_, Feed)]
    assert feeds[1].end[0] == pytest.approx(5.5)  # the run along Z at X5, r to its right (above)
    assert xz(feeds[-1]) == pytest.approx((10, -11.5))  # the last step out along X, r towards +Z
    assert xz(ms[-1]) == pytest.approx((20, -12))  # after G40 from the program's point E (rs274 too)


def test_g70_under_compensation_takes_the_nose_to_the_end_whatever_the_tool_stood():
    # the first corner depends on S, P0, E and r only: the tool before the cycle changes nothing after it
    a = moves(STEPS + "G0 X20 Z10\nG42.1 D1\nG70 Q100 X12 Z2")
    b = moves(STEPS + "G0 X30 Z15\nG42.1 D1\nG70 Q100 X12 Z2")
    assert [xz(r) for r in a[1:]] == [xz(r) for r in b[1:]]


# two arcs meeting tangent but for the program's decimals (LinuxCNC's sample lathe_g70_71_demo): a convex
# G3 of radius 2.5 about c1 into a concave G2 about c2, meeting at j; their circles offset by D cross
# twice, 0.03 mm either side of j
TANGENT_ARCS = "G3 X6.285 Z-12.982 I0 K-2.5\nG2 Z-19.982 I3.57071 K-3.5\nG1 X10\no100 endsub\n"
C1, C2, J = (-11.232, 4.5), (-16.482, 9.85571), (-12.982, 6.285)


def _crossings(c0, r0, c1, r1):
    d = math.dist(c0, c1)
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h = math.sqrt(r0 * r0 - a * a)
    m = (c0[0] + a * (c1[0] - c0[0]) / d, c0[1] + a * (c1[1] - c0[1]) / d)
    return [(m[0] - s * h * (c1[1] - c0[1]) / d, m[1] + s * h * (c1[0] - c0[0]) / d) for s in (1, -1)]


@pytest.mark.parametrize("d", [0.1, 0.25, 0.5])
def test_near_tangent_offset_arcs_meet_at_the_crossing_the_first_reaches_first(d):
    # after a step out along X tangent to the G3 (as in the sample), the arcs meet where the circles of
    # radius 2.5 + d about c1 and |j c2| - d about c2 cross, the one the G3 (running towards -Z) meets
    # first: the larger Z (rs274 2.9; mirrored as a bore the same)
    ms = moves(f"o100 sub\nG0 X4 Z-6\nG1 Z-8.732\nG1 X4.5\n{TANGENT_ARCS}G0 X20 Z0\nG70 Q100 X12 Z-5 D{d} E{d}")
    arcs = [r for r in ms if isinstance(r, Arc)]
    meet = max(_crossings(C1, 2.5 + d, C2, math.dist(J, C2) - d), key=lambda p: p[0])
    assert (arcs[0].end[0], arcs[0].end[2]) == pytest.approx((meet[1], meet[0]), abs=1e-9)
    assert (arcs[1].start[0], arcs[1].start[2]) == pytest.approx((meet[1], meet[0]), abs=1e-9)
    radial = (C1[0] + (J[0] - C1[0]) * (1 + d / 2.5), C1[1] + (J[1] - C1[1]) * (1 + d / 2.5))
    assert math.dist(radial, meet) > 0.02  # not merely moved out from j


def test_near_tangent_offset_arcs_after_a_corner_stay_where_their_ends_moved():
    # the G3 right after a corner (from the run along Z): rs274 cuts its start back on the circle through
    # its end (moved out as its start: scaled by 2.75 / 2.5), the circles then pass each other by 3e-6
    # and the arcs keep their moved ends, 3e-4 apart
    ms = moves(f"o100 sub\nG0 X4.5 Z-6\nG1 Z-8.732\n{TANGENT_ARCS}G0 X20 Z0\nG70 Q100 X12 Z-5 D0.25 E0.25")
    arcs = [r for r in ms if isinstance(r, Arc)]
    moved = (C1[0] + (J[0] - C1[0]) * 2.75 / 2.5, C1[1] + (J[1] - C1[1]) * 2.75 / 2.5)
    assert xz(arcs[0]) == pytest.approx((moved[1], moved[0]), abs=1e-3)
    start = ms[ms.index(arcs[0]) - 1].end  # the run along Z at X 4.75 meets the circle through the end
    radius = math.dist(J, C1) * 2.75 / 2.5
    assert start[2] == pytest.approx(C1[0] + math.sqrt(radius ** 2 - 0.25 ** 2), abs=1e-9)
