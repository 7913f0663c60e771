"""CNC8x6 programs without G73 run streamed (interp/cnc8x6.py, Cnc8x6.stream: each line scanned
and executed in turn, nothing kept), the others from the list of all their blocks (run_blocks,
which scans the whole file before the first block runs). Both must give the same records,
warnings, block count and final position, and the same error, for every program: a syntax error
anywhere in the file wins over an error that running an earlier block would raise, as it does
when the whole file is scanned first.

The plain-line scanner (scan_plain) must give the same Block, or hand over to the full scanner,
for every line.
"""
from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cutsim.interp import canon, cnc8x6
from cutsim.interp.core import lexer
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.modal import InterpConfig

TESTS = Path(__file__).resolve().parents[2]  # tests/
LATHE = InterpConfig("cnc8x6", "lathe", True, (40.0, 0.0, 5.0), parameters={4: -120.0}, constants={8: 4160000.0},
                     max_blocks=200)
MILL = InterpConfig("cnc8x6", "mill", False, (0.0, 0.0, 20.0), max_blocks=200)


def outcome(method: str, text: str, cfg: InterpConfig):
    try:
        p = getattr(cnc8x6.Cnc8x6("p.nc", cfg), method)(text)
    except CutsimError as e:
        return "error", str(e)
    return canon.transcript(p), p.warnings, p.blocks, p.final_position


def both(text: str, cfg: InterpConfig):
    return outcome("stream", text, cfg), outcome("run_blocks", text, cfg)


def programs() -> list[Path]:
    """Every CNC8x6 program of the tests without a G73 (the ISG and Sinumerik ones left out)."""
    out = []
    for p in sorted(TESTS.rglob("*.nc")):
        if p.name.startswith("isg-") or "isg" in p.parts or "sinumerik" in str(p):
            continue
        text = p.read_text(encoding="utf-8", errors="replace")
        if text.lstrip().startswith(("%", ";")):
            continue
        if cnc8x6.JUMP.search(text) is None:
            out.append(p)
    return out


def test_there_are_programs_to_compare():
    assert len(programs()) >= 20


@pytest.mark.parametrize("path", programs(), ids=lambda p: str(p.relative_to(TESTS)))
@pytest.mark.parametrize("cfg", [LATHE, MILL], ids=["lathe", "mill"])
def test_stream_equals_block_list(path, cfg):
    text = path.read_text(encoding="utf-8", errors="replace")
    streamed, listed = both(text, cfg)
    assert streamed == listed


def test_run_takes_the_stream_only_without_g73():
    assert cnc8x6.JUMP.search("N1 G01 X1\nN2 G073 L1 Q2\n")
    assert cnc8x6.JUMP.search("n1 g+73 l1 q2")
    assert cnc8x6.JUMP.search("N1 G01 X73 Z1") is None


@pytest.mark.parametrize("text, line, col", [
    # a block that fails when it runs (arc end off the circle), a malformed number later: the
    # malformed number is the error, as the full scan finds it before anything runs
    ("N1 G00 X20 Z0\nN2 G02 X20 Z-10 I5 K5 F0.1\nN3 G01 X1.2.3\n", 3, 9),
    # the syntax error after the program end is still found
    ("N1 G00 X20 Z0\nN2 M30\nN3 X1..2\n", 3, 5),
    # without a later syntax error the running error stands
    ("N1 G00 X20 Z0\nN2 G01 X20 Z-10 F0\nN3 X1\n", 2, 17),
])
def test_first_error_is_the_full_scans(text, line, col):
    streamed, listed = both(text, LATHE)
    assert streamed == listed
    assert streamed[0] == "error" and streamed[1].startswith(f"p.nc:{line}:{col}: error: ")


WORDS = ["G00", "G01", "G1", "G02", "G03", "G90", "G91", "G94", "G95", "G17", "G18", "G33", "G09", "G10", "G98",
         "X10", "X-5.5", "X20.", "Z-3", "Z.5", "Z1.2.3", "Y2", "I5", "K-2", "F0.1", "F100", "F0", "FR10", "S500",
         "M03", "M05", "M30", "M02", "M99", "T1", "D1", "J2", "E1.5", "E2", "&5", "R10=2.5", "R04=-00120.000",
         "N5", "A1", '"c', "X99999.9999", "X100000", "G01X1Z2", "Q3", "L5"]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.lists(st.sampled_from(WORDS), max_size=5), max_size=12), st.booleans())
def test_random_programs_stream_as_listed(lines, mill):
    text = "\n".join((f"N{k + 1} " if k % 3 else "") + " ".join(ws) for k, ws in enumerate(lines))
    streamed, listed = both(text, MILL if mill else LATHE)
    assert streamed == listed


def full_scan(line: str):
    """The full scanner alone (the plain-line path switched off)."""
    mp = pytest.MonkeyPatch()
    mp.setattr(cnc8x6.language, "scan_plain", lambda lineno, text: False)
    try:
        return scanned(line)
    finally:
        mp.undo()


def scanned(line: str):
    try:
        b = cnc8x6.scan("p.nc", 7, line)
    except CutsimError as e:
        return "error", str(e)
    return None if b is None else (b.line, b.col, b.label, list(b.words), list(b.assigns))


PIECES = ["N", "n", "G", "X", "x", "Z", "F", "M", "S", "R", "I", "E", "Q", "A", "0", "1", "01", "7.", ".5", "-", "+",
          ".", "99999999", "123456789", "100000", " ", "\t", "\f", "=", "&", '"', "\u2212", "\uff11", "e3"]


@settings(max_examples=1000, deadline=None)
@given(st.lists(st.sampled_from(PIECES), max_size=14))
def test_plain_scanner_agrees_with_the_full_one(pieces):
    line = "".join(pieces)
    assert scanned(line) == full_scan(line)


def long_way(text: str, cfg: InterpConfig):
    """Every block through core.Interpreter.execute (the direct paths for plain lines and blocks off)."""
    mp = pytest.MonkeyPatch()
    mp.setattr(cnc8x6.Cnc8x6, "plain_block", lambda self, b: False)
    mp.setattr(cnc8x6.Cnc8x6, "plain_line", lambda self, lineno, text: False)
    try:
        return outcome("run", text, cfg)
    finally:
        mp.undo()


@settings(max_examples=200, deadline=None)
@given(st.lists(st.lists(st.sampled_from(WORDS + ["G1", "G0", "X-0", "G-0", "Y-7.25", "G91", "G90"] * 3), max_size=5),
                max_size=12), st.booleans())
def test_plain_blocks_run_as_the_long_way(lines, mill):
    text = "\n".join(f"N{k + 1} " + " ".join(ws) for k, ws in enumerate(lines))
    cfg = MILL if mill else LATHE
    assert outcome("run", text, cfg) == long_way(text, cfg)


@pytest.mark.parametrize("path", programs(), ids=lambda p: str(p.relative_to(TESTS)))
def test_test_programs_run_as_the_long_way(path):
    text = path.read_text(encoding="utf-8", errors="replace")
    assert outcome("run", text, LATHE) == long_way(text, LATHE)


def test_a_program_over_max_blocks_is_refused_alike():
    cfg = InterpConfig("cnc8x6", "lathe", True, (40.0, 0.0, 5.0), max_blocks=5)
    text = "".join(f"N{k} G01 X{k} Z-1 F0.1\n" for k in range(1, 9))
    streamed, listed = both(text, cfg)
    assert streamed == listed
    assert streamed[0] == "error" and streamed[1].startswith("p.nc:6:1: error: the program is longer than the limit of 5")


@settings(max_examples=300, deadline=None)
@given(st.lists(st.sampled_from(["a", "N1 X2", "\n", "\n\n", "\r", "\r\n", " ", "\u2028"]), max_size=30),
       st.sampled_from([1, 2, 3, 7, 1 << 16]))
def test_lines_are_those_of_split_lines(pieces, chunk):
    """lexer.iter_lines (chunks of str.split for LF text, a regular expression otherwise) gives
    the lines of split_lines, numbered from 1, whatever the chunk size."""
    text = "".join(pieces)
    assert list(lexer.iter_lines(text, chunk)) == list(enumerate(lexer.split_lines(text), 1))
