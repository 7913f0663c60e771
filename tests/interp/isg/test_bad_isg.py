"""Bad ISG programs (tests/data/bad/isg/*.nc on a mill, tests/data/bad/isg/lathe/*.nc on a lathe,
each folder with its setup.toml): each stops the CLI at once with exit status 2 and
``PROGRAM:LINE:COL: error: TEXT`` at the offending statement, word or command, nothing written,
no traceback. The first line of each file says what is expected: ``; EXPECT LINE:COL fragment``
(its line 1 is that comment, so the program's lines count from 2)."""
from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main
from support.bad import assert_stops_at_its_line

BAD = Path(__file__).resolve().parents[2] / "data" / "bad" / "isg"
SETUP = BAD / "setup.toml"
PROGRAMS = sorted(BAD.glob("*.nc")) + sorted((BAD / "lathe").glob("*.nc"))
SUBPROGRAMS = {"cyc.isg"}  # called by a program beside it, not run on its own
RULES = {  # one program per rule of docs/dialects/isg.md that a real program can break
    "if-not-closed", "endif-alone", "else-after-else", "endwhile-for-if", "break-outside-loop",
    "words-after-endif", "goto-missing-label", "for-step-zero", "division-by-zero", "sqrt-negative",
    "unknown-function", "bracket-not-closed", "param-unset", "vp-undeclared", "array-index-outside",
    "external-unset", "machine-m-undeclared", "axis-undeclared", "trafo-on", "rtcp-on", "cs-rotation",
    "mcs-on", "radius-comp", "mirroring", "unknown-command", "global-file-missing", "implicit-call-missing",
    "macro-undefined", "comment-not-closed", "var-not-closed", "string-as-coordinate", "g70-inch",
    "expression-nesting", "modal-block", "modal-cycle-twice", "cs-circle-tilted", "rotation-bad-key",
    "mirror-under-compensation", "zero-offset-index", "local-header-text", "delete-missing",
    # the limits on a lathe: numbers out of range, foreign digits, nesting
    "lathe/lead-309-digits", "lathe/coordinate-over-range", "lathe/fullwidth-digit", "lathe/arabic-indic-digit",
    "lathe/lead-below-resolution", "lathe/calls-deeper-than-20",
    "lathe/g63-on-a-lathe", "lathe/nose-radius-plane", "lathe/g332-without-g331", "lathe/g331-with-m03",
    "lathe/g331-without-pitch", "g331-tapping",
}


def name(program: Path) -> str:
    return program.relative_to(BAD).with_suffix("").as_posix()


def test_every_rule_has_a_program():
    assert {name(p) for p in PROGRAMS} >= RULES


def test_every_file_is_a_program_a_setup_or_a_subprogram():
    """A file the glob above does not find (a wrong extension, a folder of its own) fails here."""
    files = {p.relative_to(BAD).as_posix() for p in BAD.rglob("*") if p.is_file()}
    known = {p.relative_to(BAD).as_posix() for p in PROGRAMS} | SUBPROGRAMS | {"setup.toml", "lathe/setup.toml"}
    assert files == known


@pytest.mark.parametrize("program", PROGRAMS, ids=name)
def test_bad_isg_program_exits_2_at_its_line(program, tmp_path):
    assert_stops_at_its_line(program, program.parent / "setup.toml", tmp_path)


def test_a_jump_loop_that_never_ends_stops_at_max_blocks(tmp_path):
    setup = tmp_path / "setup.toml"
    setup.write_text(SETUP.read_text() + "\n[simulation]\nmax_blocks = 500\n")
    prog = tmp_path / "loop.nc"
    prog.write_text("%P\nN10: G01 X1 F100\n$GOTO N10\nM30\n")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 2
    assert "more than 500 blocks executed" in res.output and "max_blocks" in res.output
