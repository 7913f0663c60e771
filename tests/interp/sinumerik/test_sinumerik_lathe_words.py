"""Words of real Sinumerik lathe programs the audit of public programs found refused
(docs/dialects/sinumerik-turning.md, "Real programs run"): skip levels ``/0`` .. ``/9``, a tool with
its spindle's address extension ``T<n>=``, and the programmable spindle speed limits ``G25 S`` /
``G26 S`` (SINUMERIK Fundamentals: "Skip blocks", "Tool change with T command", "Programmable
spindle speed limitation (G25, G26)").

Every expected value follows from those rules: a skipped-level block runs as if the ``/n`` were not
there (the levels are off); ``T1=5`` under master spindle 1 is ``T5``; a speed S above ``G26 S`` runs
at the limit, below ``G25 S`` at the lower limit; under G96 the speed stops rising at the lower of
LIMS and ``G26 S``. A cut of length L at f mm/rev and n rpm takes L / (f n) minutes; a facing cut
from r to the axis under G96 (v m/min) with the limit n_l takes pi (r^2 - r_l^2) / (1000 v f) + r_l /
(f n_l) minutes, r_l = 1000 v / (2 pi n_l) (the formula of test_sinumerik_lathe_solids).
"""
from __future__ import annotations

import math

import pytest

from cutsim.base.specs import MachineSpec, ToolSpec
from cutsim.interp import CutsimError, InterpConfig, canon, interpret
from cutsim.kinematics import plan


def run(text: str, kind: str = "lathe", start=(25.0, 0.0, 0.0), **kw) -> canon.Program:
    cfg = InterpConfig(dialect="sinumerik", machine_kind=kind, start=start, **kw)
    return interpret("t.mpf", text, cfg)


def fails(text: str, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, **kw)
    return e.value


def ends(prog) -> list[tuple[float, float]]:
    return [(round(r.end[0], 6) + 0.0, round(r.end[2], 6) + 0.0) for r in prog.moves]


def spindles(prog) -> list[canon.Spindle]:
    return [r for r in prog.records if isinstance(r, canon.Spindle)]


def tools(prog) -> list[int | None]:
    return [r.tool for r in prog.records if isinstance(r, canon.ToolChange)]


def cycle_time(text: str, start=(25.0, 0.0, 0.0)) -> float:
    return plan(run(text, start=start), MachineSpec(kind="lathe"), [ToolSpec(1, "thread")], 0.01).cycle_time


# -- skip levels -------------------------------------------------------------------------------------
@pytest.mark.parametrize("level", ["", "0", "1", "5", "9"])
@pytest.mark.parametrize("kind", ["lathe", "mill"])
def test_a_skip_level_block_runs_like_any_block(level, kind):
    """/<level> at the block's start (0 to 9, none: 0) is a skip level; with the levels off the block
    runs: /1 N70 G0 X12 Z2 moves to (12, 2) as N70 G0 X12 Z2 does, and /9G1Z-5 (packed) to Z-5."""
    prog = run(f"/{level} N70 G0 X12 Z2\n/{level}G1Z-5 F100\nM30\n", kind=kind)
    assert ends(prog) == [(12.0, 2.0), (12.0, -5.0)]


def test_a_skip_level_is_one_digit():
    """/12 is no skip level (0 .. 9): the 2 would be the block's first word, a number without an
    address: an error at the 2."""
    e = fails("/12 G0 X10\nM30\n")
    assert (e.line, e.col) == (1, 3)


# -- T<n>=: a tool for spindle n ---------------------------------------------------------------------
def test_tool_with_the_master_spindles_extension_is_a_tool_change():
    """T1=5 under the master spindle 1 (the reset state) is T5; after SETMS(2), T2=3 is T3; a name
    works as with T="..": T1="PART OFF" selects the tool of that name (7)."""
    prog = run('T1=5 D1\nSETMS(2)\nT2=3\nSETMS(1)\nT1="PART OFF"\nM30\n', tool_names={"PART OFF": 7})
    assert tools(prog) == [5, 3, 7]


def test_tool_for_another_spindle_changes_nothing_and_warns():
    """T2="PARTOFF" while spindle 1 is the master: a tool for spindle 2, not simulated: the tool in
    use (T1) stays, one warning naming T2=."""
    prog = run('T1 D1\nT2="PARTOFF" D1\nG1 X10 F0.1\nM30\n', tool_names={"PARTOFF": 6})
    assert tools(prog) == [1]
    assert any("T2=" in msg for _, msg in prog.warnings)


@pytest.mark.parametrize("text, col, fragment", [
    ("T1=2.5\n", 1, "whole tool number"),
    ("T1=3 T4\n", 6, "address T appears twice"),
    ('T1="NOPE"\n', 1, 'tool "NOPE" is not in the setup'),
])
def test_tool_with_extension_errors(text, col, fragment):
    e = fails(text + "M30\n")
    assert (e.line, e.col) == (1, col) and fragment in str(e)


# -- G25 / G26: the programmable spindle speed limits ------------------------------------------------
def test_speeds_are_held_within_g25_and_g26():
    """G26 S1000: S2000 runs at 1000; G25 S800: S100 runs at 800; S900 lies between: 900. M5 stays a
    stop (speed 0 is no speed to limit)."""
    prog = run("G26 S1000\nG97 S2000 M3\nG25 S800\nS100\nS900\nM5\nM30\n")
    assert [r.speed for r in spindles(prog)] == [1000.0, 800.0, 900.0, 900.0]
    assert spindles(prog)[-1].direction == 0


def test_g26_limits_the_g96_speed_with_lims():
    """Under G96 the speed stops rising at the lower of LIMS and G26: LIMS=3000 with G26 S500 -> 500;
    G26 S4000 -> 3000 (LIMS); G26 alone (no LIMS) -> the G26 value."""
    assert spindles(run("G26 S500\nG96 S200 LIMS=3000 M3\nM30\n"))[-1].limit == 500.0
    assert spindles(run("G26 S4000\nG96 S200 LIMS=3000 M3\nM30\n"))[-1].limit == 3000.0
    assert spindles(run("G26 S2500\nG96 S200 M3\nM30\n"))[-1].limit == 2500.0


def test_a_new_limit_acts_on_the_running_spindle():
    """S2000 M3 then G26 S1200: the spindle slows to 1200 at once; under G96 the record takes the
    new limit."""
    assert spindles(run("G97 S2000 M3\nG26 S1200\nM30\n"))[-1].speed == 1200.0
    assert spindles(run("G96 S200 LIMS=3000 M3\nG26 S700\nM30\n"))[-1].limit == 700.0


def test_g26_times_the_cut():
    """A cut of 20 mm at 0.2 mm/rev: S2000 under G26 S1000 runs at 1000 rpm: 20 / (0.2 1000) min
    = 6 s (not the 3 s of 2000 rpm)."""
    assert cycle_time("G26 S1000\nG95 G97 S2000 M3\nG1 Z-20 F0.2\nM30\n") == pytest.approx(6.0, rel=1e-9)


def test_g26_times_a_g96_facing_cut_as_lims_does():
    """Facing from r 15 to the axis at 0.2 mm/rev and 200 m/min under G26 S5000: the speed stops
    rising at r_l = 1000 200 / (2 pi 5000): t = pi (15^2 - r_l^2) / 40000 + r_l / (0.2 5000) min."""
    rl = 200000.0 / (2 * math.pi * 5000.0)
    expected = 60.0 * (math.pi * (225.0 - rl * rl) / 40000.0 + rl / 1000.0)
    t = cycle_time("G26 S5000\nG95 G96 S200 M3\nG1 X0 F0.2\nM30\n", start=(15.0, 0.0, -1.0))
    assert t == pytest.approx(expected, rel=1e-9)


def test_g26_with_axes_is_the_working_area_limitation():
    """G26 X100 Z50 sets the working area limitation, a supervision: the block does not move, one
    warning; the next move starts where the tool was."""
    prog = run("G26 X100 Z50\nG0 X10 Z2\nM30\n")
    assert ends(prog) == [(10.0, 2.0)] and prog.moves[0].start == (25.0, 0.0, 0.0)
    assert any("working area limitation" in msg for _, msg in prog.warnings)


@pytest.mark.parametrize("text, line, col, fragment", [
    ("G26\n", 1, 1, "G26 needs S<rpm>"),
    ("G26 S0\n", 1, 5, "greater than 0"),
    ("G26 S500\nG25 S800\n", 2, 5, "lies above the upper G26 S500"),
    ("G25 G26 S100\n", 1, 5, "blocks of their own"),
])
def test_speed_limit_errors(text, line, col, fragment):
    e = fails(text + "M30\n")
    assert (e.line, e.col) == (line, col) and fragment in str(e)
