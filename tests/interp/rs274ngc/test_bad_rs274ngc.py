"""Bad RS274NGC programs (tests/data/bad/rs274ngc/*.ngc): each stops the CLI with exit status 2 and
``PROGRAM:LINE:COL: error: TEXT`` at the offending word, nothing written, no traceback. The first
line of each file says what is expected: ``; EXPECT LINE:COL fragment`` (line 1 is that comment).
The codes LinuxCNC has and the simulator does not model are refused by name ("not simulated")."""
from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main
from support.bad import assert_stops_at_its_line

BAD = Path(__file__).resolve().parents[2] / "data" / "bad" / "rs274ngc"
SETUP = BAD / "setup.toml"
PROGRAMS = sorted(BAD.glob("*.ngc"))
RULES = {
    "cutter-comp", "g76-k-not-above-j", "divide-by-zero", "sqrt-negative", "named-undefined", "no-program-end",
    "zero-feed", "axis-a", "arc-radius-mismatch", "two-x-words", "if-not-closed", "endwhile-alone",
    "break-outside-loop", "sub-missing", "cycle-without-r", "cycle-bottom-above-r", "g33-no-spindle",
    "tool-not-in-table", "polar", "probe-zero-length", "probe-zero-feed", "probe-inverse-time", "probe-per-rev", "probe-comp", "plane-uv-arc", "plane-wu-cycle", "plane-vw-comp", "plane-uv-under-comp", "m19-angle", "m19-wait", "m19-direction", "m19-direction-whole", "m19-with-m3", "m19-stops-spindle", "m98-no-subprogram", "m98-with-motion", "unknown-g", "comment-not-closed", "axes-under-g80",
    "r-arc-too-small", "g71-fillet-and-chamfer", "g71-fillet-too-large", "g71-no-q", "g70-plane", "g72-increment", "g74-repeat", "g88-no-dwell", "g84-counter-clockwise", "polar-plane", "polar-g91-to-origin", "g87-no-k",
    "comp-entry-short", "comp-concave-gouge", "comp-arc-too-small", "comp-tool-change",
    "comp-arc-after-g40", "comp-on-when-on", "g71-comp",
}


def test_every_rule_has_a_program():
    assert {p.stem for p in PROGRAMS} >= RULES


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_bad_rs274ngc_program_exits_2_at_its_word(program, tmp_path):
    assert_stops_at_its_line(program, SETUP, tmp_path)


def test_a_loop_that_never_ends_stops_at_max_blocks(tmp_path):
    setup = tmp_path / "setup.toml"
    setup.write_text(SETUP.read_text() + "\n[simulation]\nmax_blocks = 500\n")
    prog = tmp_path / "loop.ngc"
    prog.write_text("G21 F100\no1 while [1]\nG91 G1 X0.1\no1 endwhile\nM2\n")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 2
    assert "more than 500 blocks executed" in res.output
