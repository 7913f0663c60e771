"""Bad Sinumerik programs (tests/data/bad/sinumerik/*.mpf on a mill, tests/data/bad/sinumerik/lathe/*.mpf on
a lathe, each folder with its setup.toml, and a few generated here): each must stop the
CLI at once with exit status 2 and ``PROGRAM:LINE:COL: error: TEXT`` naming the offending word,
parameter or block, nothing written, no traceback. The first line of each file says what is
expected: ``; EXPECT LINE:COL fragment``. Inputs too big to keep in the repository (a block of 600
characters, a subprogram file of 10 MB) and files that cannot be committed (a directory or a
dangling link named like a subprogram) are built by the tests below.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main

BAD = Path(__file__).resolve().parents[2] / "data" / "bad" / "sinumerik"
SETUP = BAD / "setup.toml"
PROGRAMS = sorted(BAD.glob("*.mpf")) + sorted((BAD / "lathe").glob("*.mpf"))  # lathe/: its own setup.toml
RULES = {  # every limit of docs/dialects/sinumerik.md ("Limits") has its program
    "non-ascii-letter", "fullwidth-digit", "arabic-indic-digit", "number-321-digits", "coordinate-over-range",
    "incremental-over-range", "arc-centre-over-range", "arc-centre-ac-over-range", "feed-negative",
    "speed-over-range", "tool-over-range", "r-parameter-over-range", "r-index-over-range", "expression-nesting",
    "signs-nesting", "expression-overflow", "product-overflow", "division-by-zero", "pass-count-over-range", "repeat-inside-itself",
    "slot1-inda-over-range", "slot1-num-over-range", "pocket1-rad-over-range", "pocket1-path-out-of-range",
    "pocket2-tiny-tool-too-many-moves", "pocket1-mid-too-many-moves", "pocket3-helix-too-many-moves",
    "cycle71-mida-too-many-moves", "cycle72-contour-bottleneck", "cycle72-contour-concave-arc",
    "axis-spi-not-whole",
    # the lathe's (docs/dialects/sinumerik-turning.md): SF, DITS/DITE, LIMS, the lead's axis, G35's lead
    "sf-over-range", "dits-below-minus-one", "dits-longer-than-block", "dite-longer-than-block", "lims-zero",
    "g33-taper-lead-on-k", "g33-taper-lead-on-i", "g35-lead-reaches-zero",
}


def expectation(path: Path) -> tuple[int, int, str]:
    m = re.match(r"; EXPECT (\d+):(\d+) (.+)", path.read_text(encoding="utf-8").splitlines()[0])
    assert m, f"{path.name}: first line must be '; EXPECT LINE:COL text'"
    return int(m.group(1)), int(m.group(2)), m.group(3).strip()


def simulate(program: Path, out: Path):
    setup = program.parent / "setup.toml" if (program.parent / "setup.toml").is_file() else SETUP
    return CliRunner().invoke(main, ["simulate", str(program), "--setup", str(setup), "--out", str(out), "-q"])


def assert_error(res, out: Path, where: str, text: str) -> None:
    """Exit 2, the message at ``where`` (PROGRAM:LINE:COL) containing ``text``, nothing written."""
    assert res.exit_code == 2, res.output
    msg = res.stderr.strip() if hasattr(res, "stderr") else res.output.strip()
    assert msg.startswith(f"{where}: error: "), msg
    assert text in msg, msg
    assert "Traceback" not in res.output
    assert not out.exists() or not any(out.iterdir())


def test_every_rule_has_a_program():
    assert {p.stem for p in PROGRAMS} >= RULES


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_bad_program_exits_2_at_its_word(program, tmp_path):
    line, col, text = expectation(program)
    out = tmp_path / "out"
    assert_error(simulate(program, out), out, f"{program}:{line}:{col}", text)


def write(tmp_path: Path, body: str) -> Path:
    prog = tmp_path / "p.mpf"
    prog.write_text("G17 G90 T1 D1 M6 F300\n" + body + "\nM30\n", encoding="utf-8")
    return prog


def test_block_longer_than_512_characters(tmp_path):
    prog = write(tmp_path, "G1 X1" + " Y1" * 200)
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{prog}:2:513", "longer than 512 characters")


def test_a_long_comment_is_no_long_block(tmp_path):
    prog = write(tmp_path, "G1 X10 Y10 Z5 ; " + "x" * 2000)
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(SETUP)])
    assert res.exit_code == 0, res.output
    assert "(10 10 5)" in res.output


def test_deep_parentheses_in_a_long_block_stop_at_the_length(tmp_path):
    # 3000 nested parentheses used to end in a RecursionError (exit 3)
    prog = write(tmp_path, "R1=" + "(" * 3000 + "1" + ")" * 3000)
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{prog}:2:513", "longer than 512 characters")


def test_subprogram_file_that_is_a_directory(tmp_path):
    (tmp_path / "SUBX.spf").mkdir()
    prog = write(tmp_path, "G0 X10\nSUBX")
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{prog}:3:1", f"subprogram SUBX: {tmp_path / 'SUBX.spf'} is a directory")


def test_subprogram_file_that_cannot_be_read(tmp_path):
    os.symlink(tmp_path / "nowhere.spf", tmp_path / "SUBY.spf")  # a dangling link: listed, not readable
    prog = write(tmp_path, "G0 X10 SUBY")
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{prog}:2:8", "SUBY.spf cannot be read")


def test_subprogram_file_over_10_mb(tmp_path):
    with open(tmp_path / "SUBZ.spf", "wb") as f:  # sparse: costs no disk
        f.truncate(10_000_001)
    prog = write(tmp_path, "SUBZ")
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{prog}:2:1", "more than the 10,000,000 a subprogram file may have")


def test_contour_subprogram_file_that_is_a_directory(tmp_path):
    # CYCLE72 names the contour by a subprogram: the same check, at the cycle's call
    (tmp_path / "KONT.spf").mkdir()
    prog = write(tmp_path, 'S2000 M3\nCYCLE72("KONT", 10, 0, 2, -5)')
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{prog}:3:1", "is a directory")


def test_non_ascii_in_a_subprogram_file_is_reported_in_that_file(tmp_path):
    (tmp_path / "SUBW.spf").write_text("G1 X10\nG1 Y１0\nRET\n", encoding="utf-8")
    prog = write(tmp_path, "SUBW")
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{tmp_path / 'SUBW.spf'}:2:5", "ASCII digits 0-9")


def test_non_utf8_byte_is_reported_at_its_column(tmp_path):
    (tmp_path / "SUBV.spf").write_bytes(b"G1 X10\nG1 Y\xff0\nRET\n")
    prog = write(tmp_path, "SUBV")
    out = tmp_path / "out"
    assert_error(simulate(prog, out), out, f"{tmp_path / 'SUBV.spf'}:2:5", "not UTF-8")


@pytest.mark.parametrize("text", ['MSG("Fräsen ž")', 'G1 X−10 Y10 Z5'])
def test_non_ascii_where_allowed(tmp_path, text):
    # inside a string (MSG texts in the operator's language) and the Unicode minus of OCR'd listings
    prog = write(tmp_path, text)
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(SETUP)])
    assert res.exit_code == 0, res.output


def test_the_move_limit_is_the_max_blocks_setting(tmp_path):
    # the same POCKET1 that is refused with MID 0.000001 runs once max_blocks allows its moves,
    # and one whose estimate just exceeds a lowered max_blocks is refused: the limit is the setting
    setup = tmp_path / "setup.toml"
    setup.write_text(SETUP.read_text() + "\n[simulation]\nmax_blocks = 100\n")
    prog = write(tmp_path, "S2000 M3\nPOCKET1(10, 0, 2, -5, , 40, 24, 8, 50, 50, 30, 100, 300, 0.5, 0, 0, 0)")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 2
    assert "more than [simulation] max_blocks = 100" in res.output
    assert "infeeds of at most MID 0.5 over 5 mm" in res.output
    setup.write_text(SETUP.read_text() + "\n[simulation]\nmax_blocks = 1000\n")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 0, res.output
    moves = [ln for ln in res.output.splitlines() if re.match(r"\s*3 (RAPID|FEED|ARC)", ln)]
    assert 100 < len(moves) <= 1000
