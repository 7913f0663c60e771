"""Limits of the CNC8x6 and ISG interpreters (issue 10): numbers out of range, digits of other
scripts, nesting depth, and programs longer than ``[simulation] max_blocks``.

Hostile inputs are generated here (no megabyte files in the tree). Every case must end in a
``CutsimError`` at the stated line and column, never another exception (exit 3) or a hang. The
expected places and values are worked out from the program text and the documented limits
(docs/dialects/cnc8x6.md and isg.md, "Limits"), not taken from the code.
"""
from __future__ import annotations

import math
import re

import pytest

from cutsim.interp import CutsimError, InterpConfig, interpret

LIMIT = 99_999.9999  # |coordinate| in mm (both dialects' docs)


def cnc(text: str, max_blocks: int = 5_000_000, kind: str = "lathe", **kw):
    cfg = InterpConfig(dialect="cnc8x6", machine_kind=kind, diameter_programming=kind == "lathe",
                       start=(40.0, 0.0, 5.0), max_blocks=max_blocks, **kw)
    return interpret("t.nc", text, cfg)


def isg(text: str, max_blocks: int = 5_000_000, **kw):
    cfg = InterpConfig(dialect="isg", machine_kind="lathe", start=(40.0, 0.0, 5.0), max_blocks=max_blocks, **kw)
    return interpret("t.nc", text, cfg)


def fails(fn, text: str, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        fn(text, **kw)
    return e.value


# -- numbers ---------------------------------------------------------------------------------------

def test_coordinates_up_to_the_limit_are_read_exactly():
    p = cnc("G01 X99999.9999 Z-99999.9999 F100\n")
    assert p.moves[-1].end == (LIMIT, 0.0, -LIMIT)
    p = isg("%m\nG01 X-99999.9999 F100\nM30\n")
    assert p.moves[-1].end == (-LIMIT, 0.0, 5.0)


@pytest.mark.parametrize("word", ["X100000", "X-100000", "Z99999.99991", "X1000000000000", "X" + "9" * 309,
                                  "Z-" + "1" * 5000 + ".5"])
def test_coordinates_beyond_the_limit(word):
    # "G01 " is 4 characters: the word is at column 5 in both dialects
    for fn, text, line in ((cnc, f"G01 {word} F100\n", 1), (isg, f"%m\nG01 {word} F100\nM30\n", 2)):
        e = fails(fn, text)
        assert (e.line, e.col) == (line, 5), e
        assert "exceeds the permitted range -99 999.9999 to 99 999.9999 mm" in e.message
        assert word[:12] in e.message  # the word is named (shortened when long)


def test_a_long_but_small_number_is_fine():
    p = cnc("G01 X0." + "0" * 5000 + "1 F100\n")
    assert p.moves[-1].end[0] == 0.0


@pytest.mark.parametrize("text,line,col,fragment", [
    ("N10 G01 X1 F100\nN20 G73 L10 Q" + "9" * 400 + "\n", 2, 13, "Q99999999999..."),  # was int(inf)
    ("N10 G01 X1 F100\nN20 G73 L10 Q100000000\n", 2, 13, "Q100000000: value exceeds the permitted range"),
    ("M03 S100\nG33 Z-1" + "0" * 400 + ". F2.\n", 2, 5, "exceeds the permitted range"),  # hung
    ("G01 X1 F100 &" + "9" * 20 + "\n", 1, 13, "0 to 99 999 999"),
    ("N" + "1" * 4400 + " G01 X1 F100\n", 1, 1, "0 to 99 999 999"),  # int() refuses > 4300 digits
    ("R1" + "0" * 4400 + "=1.\n", 1, 1, "outside R00..R99"),
    ("R10=100000.\n", 1, 1, "R10=100000.: value exceeds the permitted range"),
    ("S100000 M03\n", 1, 1, "-99 999 to 99 999 rpm"),
    ("G" + "9" * 400 + " X1\n", 1, 1, "exceeds the permitted range"),
])
def test_cnc8x6_words_beyond_their_range(text, line, col, fragment):
    e = fails(cnc, text, kind="mill")
    assert (e.line, e.col) == (line, col), e
    assert fragment in e.message, e.message


@pytest.mark.parametrize("text,line,col,fragment", [
    ("%m\nM03 S100\nG33 Z-10 K" + "9" * 400 + "\nM30\n", 3, 10, "K99999999999..."),  # lead inf: was exit 3
    ("%m\nM03 S100\nG33 Z-10 K0.00001\nM30\n", 3, 10, "below the programming resolution, 0.0001 mm"),
    ("%m\nG01 X1 F" + "9" * 400 + "\nM30\n", 2, 8, "mm/min"),
    ("%m\nS.OFFSET=" + "9" * 400 + "\nM30\n", 2, 1, "S.OFFSET=999"),
    ("%m\nG01 X1 F100 D1.5\nM30\n", 2, 13, "offset number D1.5 must be a whole number"),
])
def test_isg_words_beyond_their_range(text, line, col, fragment):
    e = fails(isg, text)
    assert (e.line, e.col) == (line, col), e
    assert fragment in e.message, e.message


def test_parameter_values_are_checked_where_they_are_used():
    # a setup may hand in any float; FR10 reads it at column 8
    for bad in (math.inf, -math.inf, math.nan, 1e6):
        e = fails(cnc, "G01 X1 FR10\n", parameters={10: bad})
        assert (e.line, e.col) == (1, 8) and "FR10 = " in e.message and "permitted range" in e.message
    e = fails(cnc, "M03 S100\nG33 Z-10. F2. J2.\nN1\nG0 X40 Z5\n", constants={8: math.inf})
    assert (e.line, e.col) == (2, 15) and "machine constant 8" in e.message
    e = fails(cnc, "M03 S100\nG33 Z-10. F2. J2.\nN1\nG0 X40 Z5\n", constants={8: 4000000},
              parameters={4: math.inf})  # the runout angle code in R04
    assert (e.line, e.col) == (2, 15) and "R04 = inf is not an angle code" in e.message


# Python's float() and int() read every script's decimal digits: float("１32") == 132.0. A
# controller reads 0-9 only, so each of these is an error at the character itself.
FOREIGN = ["\uff11", "\u0661", "\u0967", "\u09e7", "\u00b2", "\U0001d7cf"]  # fullwidth, Arabic-Indic,
# Devanagari, Bengali, superscript two, mathematical bold one


@pytest.mark.parametrize("digit", FOREIGN)
def test_only_ascii_digits_are_numbers(digit):
    cases = [
        (cnc, f"G01 X{digit}32 F100\n", 1, 6),  # first digit
        (cnc, f"G01 X1{digit}2 F100\n", 1, 7),  # inside a number
        (cnc, f"G01 X-1.{digit} F100\n", 1, 9),  # after the point
        (cnc, f"N{digit}0 G01 X1 F100\n", 1, 2),  # block number
        (cnc, f"R1{digit}=1.\n", 1, 3),  # parameter number
        (cnc, f"G01 X1 FR1{digit}\n", 1, 11),  # parameter read
        (cnc, f"G01 X1 F100 &1{digit}\n", 1, 15),
        (isg, f"%m\nG01 X14 Z{digit} F100\nM30\n", 2, 10),
        (isg, f"%m\nN{digit}5 G01 X14 F100\nM30\n", 2, 2),
    ]
    for fn, text, line, col in cases:
        e = fails(fn, text)
        assert (e.line, e.col) == (line, col), (text, e)
        assert f"'{digit}'" in e.message and "ASCII digits 0-9" in e.message


# -- positions reached by words that are each in range ---------------------------------------------

def test_incremental_moves_stop_at_the_limit():
    # from Z5: +50000 twice is 100005 > 99 999.9999, at the second Z word (line 3, column 1)
    e = fails(isg, "%m\nG91 G01 Z50000 F100\nZ50000\nM30\n")
    assert (e.line, e.col) == (3, 1) and "the Z position 100005.0000 exceeds" in e.message


def test_helix_repeats_stop_at_the_limit():
    # pitch 1000 per full circle, 200 circles by G73 from Z0: the circle that would end at
    # Z = 100 * 1000 = 100000 is refused at its line (column 1: Z is not a word of that block)
    text = "N5 X0 Y0 Z0 G00\nN10 Z1000. G10\nN20 G09 G02 X0 Y0 I10 F100 G73 L20 Q199\nN30 G98\n"
    e = fails(cnc, text, kind="mill")
    assert (e.line, e.col) == (3, 1) and "the Z position 100000.0000 exceeds" in e.message
    p = cnc(text.replace("Q199", "Q98"), kind="mill")  # 99 circles: Z99000
    assert p.final_position[2] == 99_000.0


# -- nesting ---------------------------------------------------------------------------------------

def chain(depth: int) -> str:
    """%L s1 calls s2 ... calls s<depth>, which moves to X14; the main program calls s1. The
    header of %L s<k> is at line 1 + 3(k-1), its LL one below."""
    subs = "".join(f"%L s{k}\nN10 LL s{k + 1}\nN20 M29\n" for k in range(1, depth))
    subs += f"%L s{depth}\nN10 G01 X14 F100\nN20 M29\n"
    return subs + "%main\nN10 LL s1\nN20 M30\n"


def test_twenty_nested_calls_run():
    text = chain(20)
    p = isg(text)
    assert p.final_position == (14.0, 0.0, 5.0)
    assert len(p.moves[-1].src.calls) == 20


@pytest.mark.parametrize("depth", [21, 500])
def test_deeper_calls_stop_at_the_twenty_first(depth):
    text = chain(depth)
    e = fails(isg, text)
    # the 21st open call is "LL s21" in %L s20: header line 1 + 3*19 = 58, LL at line 59, name at col 8
    assert (e.line, e.col) == (59, 8), e
    assert "nested more than 20 deep" in e.message and "s20 -> s21" in e.message


def test_parentheses_do_not_nest():
    # ISG comments run to the first ')': the rest is an unexpected character, not a recursion
    e = fails(isg, "%m\n" + "(" * 5000 + ")" * 5000 + "\nM30\n")
    assert (e.line, e.col) == (2, 5002) and "unexpected character ')'" in e.message
    e = fails(cnc, "(" * 5000 + ")" * 5000 + "\n")
    assert (e.line, e.col) == (1, 1) and "unexpected character '('" in e.message


# -- program length --------------------------------------------------------------------------------

def straight(n: int, dialect: str) -> str:
    """n blocks, each a feed move, with comment lines and blank lines between (not blocks in ISG;
    blank lines are not blocks in CNC8x6, comment lines are)."""
    lines = []
    for i in range(n):
        lines.append(f"G01 X{i % 50} Z-{i % 7}.5 F100")
        if dialect == "isg" and i % 3 == 0:
            lines += ["; a comment", "", "  "]
        elif i % 3 == 0:
            lines += ["", "  "]
    if dialect == "isg":
        return "%prog\n" + "\n".join(lines) + "\n"
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
def test_a_long_program_is_refused_up_front(dialect):
    fn = cnc if dialect == "cnc8x6" else isg
    assert fn(straight(50, dialect), max_blocks=50).blocks == 50
    text = straight(51, dialect)
    # the line of block 51: one line per block, plus the extra lines after blocks 0, 3, ..., 48
    # (17 of them), plus the ISG header
    extra = 3 if dialect == "isg" else 2
    line = 51 + 17 * extra + (1 if dialect == "isg" else 0)
    assert text.splitlines()[line - 1].startswith("G01 X0 Z-1.5")  # block 51 (i = 50)
    e = fails(fn, text, max_blocks=50)
    assert (e.line, e.col) == (line, 1), e
    assert "longer than the limit of 50 blocks set by [simulation] max_blocks" in e.message
    assert "loop" not in e.message
    # refused before the lines are scanned: a bad word after the limit is never reached
    e = fails(fn, text.replace("G01 X1 Z-1.5", "G01 X1 Z-1.5 Q#", 1) + "G01 X\uff11\n", max_blocks=50)
    assert "longer than the limit" in e.message


def test_a_moderately_big_program_is_refused_before_scanning():
    n = 200_000
    text = "".join(f"N{i} G01 X{i % 100}.5 Z-{i % 7}.25 F100\n" for i in range(n))
    e = fails(cnc, text, max_blocks=150_000)
    assert (e.line, e.col) == (150_001, 1) and "longer than the limit of 150,000 blocks" in e.message


def test_isg_subprogram_repeats_are_counted_before_running():
    # s2: a move and M29 (2 blocks); s1: ten calls of s2 and M29 (10*(1+2)+1 = 31); s0: ten calls
    # of s1 and M29 (10*(1+31)+1 = 321); main: G01, LL s0 (itself and s0's 321), M30: 324
    text = ("%L s2\nG01 X14 F100\nM29\n%L s1\n" + "LL s2\n" * 10 + "M29\n%L s0\n" + "LL s1\n" * 10 + "M29\n"
            "%main\nG01 X20 F100\nLL s0\nM30\n")
    assert isg(text, max_blocks=324).blocks == 324
    main_ll = text.splitlines().index("LL s0") + 1
    e = fails(isg, text, max_blocks=323)
    assert (e.line, e.col) == (main_ll, 4), e
    assert "LL s0 executes 321 blocks" in e.message and "the program would execute 324 blocks" in e.message
    assert "[simulation] max_blocks" in e.message


def test_cnc8x6_parameter_loops_are_caught_running_and_named():
    # Q from a parameter: not counted statically; the runtime guard names the G73, not "a program
    # longer than the limit"
    e = fails(cnc, "N10 R20=1000.\nN20 G01 X1 F100\nN30 G73 L20 QR20\n", max_blocks=100, kind="mill")
    assert (e.line, e.col) == (3, 5) and "G73 loops (QR20 at line 3)" in e.message


def test_counts_too_big_to_print_are_given_as_powers_of_ten():
    # 1000 loops, each G73 jumping back to N1 with Q99999999: every activation of the loop at
    # block k runs 1 + Q*(cost + 1) blocks, so the count is at least (Q+1)^1000 = 10^8000, far more
    # digits than Python converts to text (4300); the message gives its magnitude
    text = "N1 G01 X1 F100\n" + "".join(f"N{i + 2} G73 L1 Q99999999\n" for i in range(1000))
    e = fails(cnc, text, kind="mill")
    assert (e.line, e.col) == (1001, 7)
    m = re.search(r"would execute about (\d\.\d\d)e\+(\d+) blocks", e.message)
    assert m and int(m.group(2)) >= 8000, e.message


@pytest.mark.parametrize("fn", [cnc, isg], ids=["cnc8x6", "isg"])
def test_a_huge_number_or_a_word_repeated_thousands_of_times_fails_at_once(fn):
    """Lines the plain-line shortcut can't take must fall through in linear time: a 30,000-digit
    X (fuzz 20261124/11152) and 100,000 repeated G01 words (fuzz 20261124/8529) hung the CNC8x6
    reader's regular expression, which retried every split of the digits. Both are errors at the
    offending word: the X value past the range at column 5, the second G01 (column 5) conflicting
    with the first."""
    e = fails(fn, "G00 X5" + "1" * 30_000 + ". Z1\n")
    assert (e.line, e.col) == (1, 5) and "range" in e.message
    e = fails(fn, "G01 " + "G01 " * 100_000 + "X1 Z1 F0.1\n")
    assert (e.line, e.col) == (1, 5) and "G01 conflicts with G01" in e.message
