"""G38.2-G38.5 straight probing simulated without contact, by numbers worked out by hand from rs274's
rules (docs/dialects/rs274ngc.md; tests/data/programs/rs274ngc/probe.ngc compares with rs274 itself):
the probe move is a feed to the programmed point, #5061-#5063 hold that point in program units, #5070
is 0, and the tool then stands 0.01 in (0.254 mm) back along the move."""
from __future__ import annotations

import math
import random

import pytest

from cutsim.interp import interpret
from cutsim.interp.canon import Feed
from cutsim.interp.core.modal import InterpConfig
from cutsim.interp.errors import CutsimError

BACK = 0.254  # mm: 0.01 in


def run(text: str, kind: str = "mill"):
    return interpret("t.ngc", text, InterpConfig(dialect="rs274ngc", machine_kind=kind))


def probe_then_report(start, words: str, code: str = "38.3", units: str = "G21") -> tuple:
    """The feeds of a probe from ``start`` and a G0 to #5061-#5063 + (the position now - the probe point)
    x 1000 (so the back-off shows as a move), with #5070 as X of a last G0 move."""
    prog = run(f"{units} G90 G0 X{start[0]} Y{start[1]} Z{start[2]}\nF100\nG{code} {words}\n"
               "#1 = [#5420 - #5061]\n#2 = [#5421 - #5062]\n#3 = [#5422 - #5063]\n"
               "G1 X[#5061 + 1000 * #1] Y[#5062 + 1000 * #2] Z[#5063 + 1000 * #3]\nG0 X#5070 Y#5064 Z#5069\nM2\n")
    feeds = [r for r in prog.records if isinstance(r, Feed)]
    return feeds, prog.records[-2].end


def backed_off(start, end, back: float) -> tuple:
    """Where a tool stands ``back`` mm from ``end`` towards ``start`` (on the segment's line)."""
    d = math.dist(start, end)
    return tuple(e - back * (e - s) / d for s, e in zip(start, end))


def test_a_probe_is_a_feed_to_its_point_and_the_tool_stands_0_01_in_back():
    feeds, last = probe_then_report((1, 2, 3), "X4 Y6 Z3", "38.2")
    assert feeds[0].start == pytest.approx((1, 2, 3)) and feeds[0].end == pytest.approx((4, 6, 3))
    assert feeds[0].feed == 100.0
    # the 3-4-5 move: 0.254 back along (0.6, 0.8)
    assert feeds[1].end == pytest.approx((4 - 1000 * 0.6 * BACK, 6 - 1000 * 0.8 * BACK, 3))
    assert feeds[1].start == pytest.approx((4 - 0.6 * BACK, 6 - 0.8 * BACK, 3))
    assert last == pytest.approx((0, 0, 0))  # #5070 0 (no contact), #5064-#5069 0


def test_in_inches_the_back_off_is_0_01_in_and_5061_is_in_inches():
    feeds, _ = probe_then_report((0, 0, 0), "X2", "38.4", units="G20")
    assert feeds[0].end[0] == pytest.approx(2 * 25.4)
    assert feeds[1].start[0] == pytest.approx(2 * 25.4 - BACK)  # #5420 in inches: 1.99


@pytest.mark.parametrize("seed", range(40))
def test_the_back_off_lies_on_the_probe_move_0_254_from_its_point(seed):
    rng = random.Random(seed)
    start = tuple(round(rng.uniform(-50, 50), 3) for _ in range(3))
    end = tuple(round(rng.uniform(-50, 50), 3) for _ in range(3))
    feeds, _ = probe_then_report(start, f"X{end[0]} Y{end[1]} Z{end[2]}", rng.choice(["38.2", "38.3", "38.4", "38.5"]))
    at = feeds[1].start
    assert math.dist(at, end) == pytest.approx(BACK, abs=1e-9)
    assert math.dist(start, at) + math.dist(at, end) == pytest.approx(math.dist(start, end), abs=1e-9)  # between them
    assert at == pytest.approx(backed_off(start, end, BACK), abs=1e-9)
    # a wrong back-off (along X only, or past the point) fails the same checks
    wrong = (end[0] - BACK, end[1], end[2])
    assert abs(math.dist(start, wrong) + math.dist(wrong, end) - math.dist(start, end)) > 1e-9 or end[1:] == start[1:]
    past = backed_off(start, end, -BACK)
    assert math.dist(start, past) + math.dist(past, end) > math.dist(start, end) + 0.1


def test_g38_3_and_g38_5_of_zero_length_leave_the_tool_where_it_is():
    for code in ("38.3", "38.5"):
        feeds, _ = probe_then_report((5, 5, 5), "X5 Y5 Z5", code)
        assert feeds[-1].start == pytest.approx((5, 5, 5)) and feeds[-1].end == pytest.approx((5, 5, 5))


def test_the_probe_parameters_are_in_the_coordinate_system_in_effect():
    prog = run("G21 F100\nG10 L2 P1 X10 Y20 Z30\nG0 X2 Y3 Z4\nG92 X2 Y3 Z4\nG38.3 X5 Y-5 Z-5\nG0 X#5061 Y#5062 Z#5063\nM2\n")
    # G54 at (10 20 30), G92 of 0 where it is (2 3 4): the probe to program (5 -5 -5) is machine (15 15 25)
    assert prog.records[-2].end == pytest.approx((15, 15, 25))


def test_in_g93_the_probe_takes_the_rate_before_it():
    prog = run("G21 F40\nG93\nG38.3 X10\nG1 X20 F2\nG38.3 X30\nM2\n")
    feeds = [r.feed for r in prog.records if isinstance(r, Feed)]
    # F40 from G94; the G93 move of 10.254 mm at F2 sets 20.508 mm/min
    assert feeds == pytest.approx([40.0, 2 * (20 - (10 - BACK)), 2 * (20 - (10 - BACK))])


@pytest.mark.parametrize("text, message", [
    ("G21 F100\nG38.2 X0\nM2\n", "G38.2: the probe move has zero length"),
    ("G21 F100\nG38.4 X0\nM2\n", "G38.4: the probe move has zero length"),
    ("G21\nG38.3 X1\nM2\n", "G38.3: cannot probe with a zero feed rate"),
    ("G21 F10\nG93\nG94\nG38.3 X1\nM2\n", "cannot probe with a zero feed rate"),
    ("G21 G95 F1\nG38.3 X1\nM2\n", "cannot probe in feed per revolution mode"),
    ("G21 F10 G41.1 D2\nG1 X10\nG38.3 X20\nM2\n", "cannot probe with cutter radius compensation on"),
    ("G21 F10\nG38.2\nM2\n", "G38.2: all axes missing"),
    ("G21 F10\nG38.2 X5 R1\nM2\n", "R word with nothing that uses it"),
])
def test_probe_refusals(text, message):
    with pytest.raises(CutsimError, match=message):
        run(text)
