"""One bad program per rule (tests/data/bad/cnc8x6/*.nc): each must stop the CLI with exit status 2, the
message ``PROGRAM:LINE:COL: error: TEXT`` naming the offending line (and column), and nothing
written. The first line of each file says what is expected, as a comment of its dialect:
``"EXPECT LINE:COL fragment`` (CNC8x6, run with tests/data/bad/cnc8x6/setup.toml) or ``;EXPECT LINE:COL
fragment`` (ISG files, named ``isg-*.nc``, run with tests/data/bad/cnc8x6/isg-setup.toml).
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
    "isg-lead-309-digits", "isg-coordinate-over-range", "isg-fullwidth-digit", "isg-arabic-indic-digit",
    "isg-lead-below-resolution", "isg-calls-deeper-than-20",
    # codes of other controls the manuals do not describe, and lathe-only limits of ISG
    "g81-drilling-cycle", "g84-thread-cycle", "g42-nose-radius", "isg-g63-on-a-lathe", "isg-nose-radius-plane",
    "isg-g332-without-g331", "isg-g331-with-m03", "isg-g331-without-pitch",
}


def expectation(path: Path) -> tuple[int, int, str]:
    m = re.match(r'[";]EXPECT (\d+):(\d+) (.+)', path.read_text(encoding="utf-8").splitlines()[0])
    assert m, f"{path.name}: first line must be '\"EXPECT LINE:COL text' (';EXPECT' in ISG files)"
    return int(m.group(1)), int(m.group(2)), m.group(3).strip()


def test_every_rule_has_a_program():
    assert {p.stem for p in PROGRAMS} >= RULES


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_bad_program_exits_2_with_its_line(program, tmp_path):
    line, col, text = expectation(program)
    out = tmp_path / "out"
    setup = BAD / ("isg-setup.toml" if program.name.startswith("isg-") else "setup.toml")
    res = CliRunner().invoke(main, ["simulate", str(program), "--setup", str(setup),
                                    "--out", str(out), "-q"])
    assert res.exit_code == 2, res.output
    msg = res.stderr.strip() if hasattr(res, "stderr") else res.output.strip()
    assert msg.startswith(f"{program}:{line}:{col}: error: "), msg
    assert text in msg
    assert "Traceback" not in res.output
    assert not out.exists() or not any(out.iterdir())
