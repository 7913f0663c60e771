"""G84/G74 (tapping), G88 (manual-retract boring), G52 (local offsets) and G96, against positions
worked out by hand from docs/dialects/rs274ngc.md; test_rs274ngc_oracle.py compares them with rs274
(tests/data/programs/rs274ngc/cycles2.ngc)."""
from __future__ import annotations

import math

import pytest

from cutsim.interp import interpret
from cutsim.interp.canon import Feed, Rapid, Spindle
from cutsim.interp.core.modal import InterpConfig


def run(text: str):
    return interpret("t.ngc", "G21 G17 G90 F100\n" + text + "\nM2\n", InterpConfig(dialect="rs274ngc"))


def moves(prog):
    return [r for r in prog.records if isinstance(r, (Rapid, Feed))]


@pytest.mark.parametrize("code, spindle", [(84, "M3"), (74, "M4")])
def test_tapping_feeds_in_reverses_the_spindle_and_feeds_out_to_the_clear_level(code, spindle):
    # from Z10 with G98: R2, the hole to Z-6, out to the initial level Z10 at feed
    prog = run(f"S500 {spindle}\nG0 X0 Y0 Z10\nG98 G{code} X10 Y5 Z-6 R2")
    ms = moves(prog)[1:]
    assert [(type(r).__name__, r.end) for r in ms] == [
        ("Rapid", (10, 5, 10)), ("Rapid", (10, 5, 2)), ("Feed", (10, 5, -6)), ("Feed", (10, 5, 10))]
    turn = 1 if code == 84 else -1
    dirs = [r.direction for r in prog.records if isinstance(r, Spindle)]
    assert dirs[-4:] == [0, -turn, 0, turn]  # at the bottom: stop, reverse; at the top: stop, forward


def test_g88_leaves_the_tool_down_and_goes_on_from_the_clear_level():
    # G99: clear level R2; the hole to Z-3 at (2, 2), no move out; the next hole's rapid starts at Z2
    prog = run("S500 M3\nG0 X0 Y0 Z5\nG88 X2 Y2 Z-3 R2 P1\nX4 Y4")
    ms = moves(prog)
    assert ms[3].end == (2, 2, -3) and isinstance(ms[3], Feed)
    assert ms[4].start == (2, 2, 2) and ms[4].end == (4, 4, 2)
    assert sum("manual retract" in message for _, message in prog.warnings) == 1


def test_g52_sets_the_offsets_of_its_axes_in_g90_and_g91():
    prog = run("G0 X1 Y1 Z5\nG52 X10 Y-5\nG0 X0 Y0\nG91 G52 X2\nG90 G0 X0 Y0\nG52 X0 Y0\nG0 X0 Y0")
    ends = [r.end for r in moves(prog)]
    assert ends == [(1, 1, 5), (10, -5, 5), (2, -5, 5), (0, 0, 5)]


def test_g96_changes_no_move_and_warns_once():
    plain = moves(run("S500 M3\nG0 X0 Y0 Z5\nG1 X10\nG1 X20"))
    prog = run("S500 M3\nG0 X0 Y0 Z5\nG96 D2000 S120\nG1 X10\nG96 S100\nG1 X20")
    assert [r.end for r in moves(prog)] == [r.end for r in plain]
    assert sum("G96" in message for _, message in prog.warnings) == 1


def test_polar_words_name_x_and_y_from_the_origin_and_from_the_point_in_g91():
    # @5 ^30 from the XY zero: (5 cos 30, 5 sin 30); ^90 keeps the distance 5: (0, 5); G91 @2 adds to it: (0, 7)
    ends = [r.end for r in moves(run("G0 X1 Y1 Z0\nG0 @5 ^30\nG1 ^90\nG91 G1 @2"))]
    assert ends[1] == pytest.approx((5 * math.cos(math.radians(30)), 2.5, 0))
    assert ends[2] == pytest.approx((0, 5, 0), abs=1e-12)
    assert ends[3] == pytest.approx((0, 7, 0), abs=1e-12)


def test_a_bolt_circle_by_incremental_angle_and_l_repeats():
    # from (1.5, 0): G91 G81 ^60 L6 drills six holes 60 degrees apart on radius 1.5
    prog = run("G0 X1.5 Y0 Z1\nG91 G81 R0.1 Z-0.5 ^60 L6")
    holes = [r.end for r in prog.records if isinstance(r, Feed)]
    assert len(holes) == 6
    for k, h in enumerate(holes, start=1):
        assert (h[0], h[1]) == pytest.approx((1.5 * math.cos(math.radians(60 * k)), 1.5 * math.sin(math.radians(60 * k))))
