"""G17.1-G19.1 (planes of U V W) and M19 (spindle orientation) on their own (no LinuxCNC needed);
tests/data/programs/rs274ngc/planes-uvw.ngc and orient.ngc compare them with rs274 itself."""
from __future__ import annotations

import pytest

from cutsim.interp import interpret
from cutsim.interp.canon import Feed, Rapid, Spindle
from cutsim.interp.core.modal import InterpConfig
from cutsim.interp.errors import CutsimError


def run(text: str):
    return interpret("t.ngc", text, InterpConfig(dialect="rs274ngc", machine_kind="mill"))


@pytest.mark.parametrize("code, value", [("17.1", 171), ("18.1", 181), ("19.1", 191), ("17", 170)])
def test_straight_moves_go_on_in_the_uvw_planes_and_plane_reads_the_code(code, value):
    prog = run(f"G21 F100\nG{code}\nG1 X1 Y2 Z3\nG0 X#<_plane>\nM2\n")
    moves = [r for r in prog.records if isinstance(r, (Feed, Rapid))]
    assert moves[0].end == (1.0, 2.0, 3.0)
    assert moves[1].end == (float(value), 2.0, 3.0)


@pytest.mark.parametrize("text, message", [
    ("G17.1 G2 X1 Y1 I1 F1\n", "arcs in plane G17.1 need the axes U V W"),
    ("G19.1\nG3 J1 F1\n", "arcs in plane G19.1 need the axes U V W"),
    ("G18.1\nG83 X1 Z-1 R1 Q1 F1\n", "canned cycles in plane G18.1 need the axes U V W"),
    ("G17.1 G41.1 D1\n", "cutter radius compensation works in G17 and G18 only"),
    ("G41.1 D1\nG1 X10 F1\nG19.1\n", "G19.1: cannot change the plane with cutter radius compensation on"),
])
def test_what_needs_u_v_w_is_refused(text, message):
    with pytest.raises(CutsimError, match=message):
        run("G21\n" + text + "M2\n")


def test_m19_stops_the_spindle_and_keeps_its_speed():
    prog = run("G21 F100 M3 S800\nM19 R90 Q2 P1\n#1 = #<_spindle_on>\n#2 = #<_rpm>\nG1 X#1 Y#2\nM4\nM2\n")
    spindles = [(r.direction, r.speed) for r in prog.records if isinstance(r, Spindle)]
    assert spindles[:3] == [(1, 800.0), (0, 800.0), (-1, 800.0)]  # M3 S800, M19, M4
    assert [r for r in prog.records if isinstance(r, Feed)][0].end == (0.0, 800.0, 0.0)


def test_m19_shares_its_words_with_the_block():
    prog = run("G21 M3 S800\nM19 R10 G4 P1\nM2\n")  # P is G4's dwell and M19's direction (rs274 alike)
    assert [r.direction for r in prog.records if isinstance(r, Spindle)][-1] == 0


@pytest.mark.parametrize("words, message", [
    ("R360.001", "the angle R must be within 0 to 360"), ("R-0.5", "the angle R"), ("Q0", "the time Q"),
    ("Q-1", "the time Q"), ("P3", "the direction P must be 0"), ("P-1", "the direction P must be 0"),
    ("P0.5", "the direction P must be a whole number"), ("L1", "L word with nothing that uses it"),
])
def test_m19_refusals(words, message):
    with pytest.raises(CutsimError, match=message):
        run(f"G21\nM19 {words}\nM2\n")
    for good in ("R0", "R360", "Q0.001", "P0", "P2"):
        run(f"G21\nM19 {good}\nM2\n")
