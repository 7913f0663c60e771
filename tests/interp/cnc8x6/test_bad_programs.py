"""One bad program per rule (tests/data/bad/cnc8x6/*.nc, run with tests/data/bad/cnc8x6/setup.toml): each
must stop the CLI with exit status 2, the message ``PROGRAM:LINE:COL: error: TEXT`` naming the
offending line (and column), and nothing written. The first line of each file says what is
expected, as a CNC8x6 comment: ``"EXPECT LINE:COL fragment``.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main

BAD = Path(__file__).resolve().parents[2] / "data" / "bad" / "cnc8x6"
PROGRAMS = sorted(BAD.glob("*.nc"))
RULES = {  # every rule of the issue has its file
    "lead-over-99.99", "e-without-point", "missing-empty-block", "missing-axis", "assign-r00",
    "assign-r80", "angle-over-60", "unknown-g", "unknown-m", "malformed-number", "lead-zero",
    "start-angle-over-360", "start-angle-negative",
    "g73-missing-q", "g73-forward", "g73-nested-over-limit", "g73-overlapping-over-limit",
    # limits (issue 10): numbers out of range, foreign digits, nesting
    "number-309-digits", "coordinate-over-range", "fullwidth-digit", "g73-q-over-range", "g33-end-over-range",
    "incremental-over-range", "parameter-number-over-99", "lead-below-minimum", "tool-not-whole",
    # codes of other controls the manuals do not describe
    "g81-drilling-cycle", "g84-thread-cycle", "g42-nose-radius",
}


def expectation(path: Path) -> tuple[int, int, str]:
    m = re.match(r'"EXPECT (\d+):(\d+) (.+)', path.read_text(encoding="utf-8").splitlines()[0])
    assert m, f"{path.name}: first line must be '\"EXPECT LINE:COL text'"
    return int(m.group(1)), int(m.group(2)), m.group(3).strip()


def test_every_rule_has_a_program():
    assert {p.stem for p in PROGRAMS} >= RULES


def test_every_file_is_a_program_or_the_setup():
    """A file the glob above does not find (a wrong extension, a folder of its own) fails here."""
    assert {p.name for p in BAD.rglob("*") if p.is_file()} == {p.name for p in PROGRAMS} | {"setup.toml"}


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_bad_program_exits_2_with_its_line(program, tmp_path):
    line, col, text = expectation(program)
    out = tmp_path / "out"
    res = CliRunner().invoke(main, ["simulate", str(program), "--setup", str(BAD / "setup.toml"),
                                    "--out", str(out), "-q"])
    assert res.exit_code == 2, res.output
    msg = res.stderr.strip() if hasattr(res, "stderr") else res.output.strip()
    assert msg.startswith(f"{program}:{line}:{col}: error: "), msg
    assert text in msg
    assert "Traceback" not in res.output
    assert not out.exists() or not any(out.iterdir())
