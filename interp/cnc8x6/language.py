"""The MEFI CNC8x6 language: its code tables and limits, the line scanner (with the plain-line
reader of core.fast first) and the parse of a whole program into blocks."""
from __future__ import annotations

import math
import re

from ..core import ISO_G_CODES, ISO_M_CODES, Code, Group
from ..core.fast import PlainReader
from ..core.lexer import (CODE_LIMIT, COORD_LIMIT, SPEED_LIMIT, Block, Word, block_lines, block_number, check_length,
                          digits_end, foreign_digit, iter_lines, parse_number, read_whole)
from ..errors import CutsimError

# The double quote opens a comment; OCR'd manuals show it as one of these.
COMMENT_CHARS = '"\u201c\u201d\u201e\u00cd\u0148'
LETTERS = set("GMSTDFXYZIJKERLQ")
# The dialect's codes: {code: Code(modal group, addresses it takes, meaning)} (core.Code). The
# helix and jump codes are each a group of their own.
G_CODES = {
    0: Code(Group.MOTION, "XYZ", "rapid"),
    1: Code(Group.MOTION, "XYZF", "linear feed"),
    2: Code(Group.MOTION, "XYZIJKF", "clockwise arc (helix with G09), centre I/J/K from the start"),
    3: Code(Group.MOTION, "XYZIJKF", "counter-clockwise arc (helix with G09), centre I/J/K from the start"),
    9: Code(Group.HELIX_ON, "", "helix on"),
    10: Code(Group.HELIX_PITCH, "XYZ", "helix pitch"),
    33: Code(Group.MOTION, "XYZFIJE", "thread: lead F, start angle I, runout J, lead-in E"),
    73: Code(Group.JUMP, "LQ", "jump"),
    98: Code(Group.HELIX_OFF, "", "helix off"),
    **ISO_G_CODES,
}
# G codes a reader of other controls expects, which the CNC8x6 manual extracts do not describe:
# exit 2 with the way the manual's programs do the job (docs/dialects/cnc8x6.md)
_CYCLE = ("a drilling cycle, which the CNC8x6 manual does not describe: on a lathe drill with G01 along Z at X0 "
          "and tap with G33 at X0 (a tap in the setup)")
NOT_DESCRIBED = {
    **{code: _CYCLE for code in (81, 82, 83, 85, 86, 87, 88, 89)},
    84: "the thread cutting cycle the manual names but does not describe: program the passes with G33 (the "
        "manual's example 1), or tap with G33 along Z at X0",
    41: "tool nose radius compensation, which the CNC8x6 manual does not describe: program the tool tip path",
    42: "tool nose radius compensation, which the CNC8x6 manual does not describe: program the tool tip path",
}
# M words: spindle, program end, stops, coolant and gear ranges (the last ones have no geometric effect).
M_CODES = {
    **ISO_M_CODES,
    5: Code(Group.SPINDLE, "", "spindle stop"),
    8: Code(Group.COOLANT, "", "coolant on"),
    9: Code(Group.COOLANT, "", "coolant off"),
    30: Code(Group.END, "", "program end"),
    **{m: Code(Group.GEAR, "", f"gear range {m - 40}") for m in (41, 42, 43, 44)},
}
MAX_DIRECT_LEAD = 99.99
MIN_LEAD = 0.001  # mm/rev
RESERVED_PARAMS = (0, 80)
MAX_PARAM = 99  # R00..R99
# The largest magnitude each address accepts (docs/dialects/cnc8x6.md, "Limits"); the words' own
# rules (F of G33 at most 99.99, I of G33 0..360, signs, whole numbers) are checked where they act.
LIMITS = {**{a: (COORD_LIMIT, "mm") for a in "XYZIJKE"}, "F": (COORD_LIMIT, "mm/min or mm/rev"),
          "S": (SPEED_LIMIT, "rpm"), **{a: (CODE_LIMIT, "") for a in "GMTDLQ"}}


# The happy path of ``scan`` (core.fast): a line of plain words ``<letter><number>`` (no comment, no
# R, no &, no parameter values) with an optional block number first; any number, read atomically.
# Only blanks and tabs separate words here.
READER = PlainReader("GMSTDFXYZIJKELQ", {k: v[0] for k, v in LIMITS.items()}, None, r"[Nn]([0-9]+)")


def scan_plain(lineno: int, text: str) -> Block | None | bool:
    """``text`` as a Block when it is a plain line whose words all pass their checks; None for an
    empty line; False when the line needs the full scanner."""
    r = READER.read(text)
    if r is None:
        return False
    number, words = r
    if number is None:
        if not words:
            return None if not text.strip() else False
        return Block(lineno, 1, "", words)
    if len(number) > 8 and len(number.lstrip("0")) > 8:  # beyond 99 999 999: the long way says so
        return False
    return Block(lineno, 1, "N" + number, words)


def scan(name: str, lineno: int, text: str) -> Block | None:
    """One CNC8x6 line -> Block (None for a blank line)."""
    block = scan_plain(lineno, text)
    if block is not False:
        return block
    block = Block(line=lineno, col=1)
    i, n = 0, len(text)
    seen: dict[str, int] = {}
    while i < n:
        c = text[i]
        if c in " \t\f\v":
            i += 1
            continue
        if c in COMMENT_CHARS:
            break  # the comment's text is not kept: a comment-only line is an (empty) block anyway
        col = i + 1
        if c == "&":
            if digits_end(text, i + 1) == i + 1:
                foreign_digit(name, lineno, text, i + 1)
                raise CutsimError(name, lineno, col, "'&' must be followed by a number")
            value, j = read_whole(name, lineno, text, i + 1, "&")
            block.words.append(Word("&", float(value), text[i + 1:j], col))
            i = j
            continue
        if not c.isalpha() or not c.isascii():
            raise CutsimError(name, lineno, col, f"unexpected character '{c}'")
        letter = c.upper()
        i += 1
        if letter == "N":
            i = block_number(name, lineno, text, i, block, must_open=True)
            continue
        if letter == "R":  # parameter assignment R<nn>=<value>
            j = digits_end(text, i)
            foreign_digit(name, lineno, text, j)
            k = j
            while k < n and text[k] in " \t":
                k += 1
            if j == i or k >= n or text[k] != "=":
                raise CutsimError(name, lineno, col, "R must be written R<number>=<value> (a parameter assignment)")
            num = param_number(name, lineno, col, text[i:j])
            k += 1
            while k < n and text[k] in " \t":
                k += 1
            value, _raw, i = parse_number(name, lineno, text, k, f"R{text[i:j]}=", COORD_LIMIT, col=col)
            block.assigns.append((num, value, col))
            continue
        if letter not in LETTERS:
            raise CutsimError(name, lineno, col, f"address '{letter}' is not used by the CNC8x6 dialect")
        if letter in seen and letter not in "GM":
            raise CutsimError(name, lineno, col, f"address {letter} appears twice in one block")
        seen[letter] = col
        if i < n and text[i] in "rR" and digits_end(text, i + 1) > i + 1:  # FR10: value from a parameter
            j = digits_end(text, i + 1)
            foreign_digit(name, lineno, text, j)
            block.words.append(Word(letter, None, text[i:j], col, param=param_number(name, lineno, col, text[i + 1:j])))
            i = j
            continue
        value, raw, i = parse_number(name, lineno, text, i, letter, *LIMITS[letter], col=col)
        block.words.append(Word(letter, value, raw, col))
    if not block.label and not block.words and not block.assigns and not text.strip():
        return None
    return block


def param_number(name: str, lineno: int, col: int, digits: str) -> int:
    """``04`` of ``R04`` -> 4; parameters are R00..R99."""
    if len(digits.lstrip("0")) > 2 or int(digits.lstrip("0") or "0") > MAX_PARAM:
        raise CutsimError(name, lineno, col, f"parameter number R{digits if len(digits) <= 12 else digits[:12] + '...'} "
                          f"is outside R00..R{MAX_PARAM}")
    return int(digits.lstrip("0") or "0")


# Every line that is not blank is a block (also a comment alone: an empty block).
BLOCK_LINES = block_lines(r"[^\s]")
# Where a program may jump (a G73 word in any spelling: g73, G073, G+73.0, also inside a comment):
# a program without one runs streamed (Cnc8x6.stream).
JUMP = re.compile(r"[Gg]\+?0*73")


def parse(name: str, text: str, max_blocks: int | None = None) -> list[Block]:
    """The program's blocks. With ``max_blocks`` a program with more blocks than that is refused
    before any line is scanned (lexer.check_length)."""
    if max_blocks is not None:
        check_length(name, text, max_blocks, BLOCK_LINES)
    blocks = []
    for lineno, line in iter_lines(text):
        b = scan(name, lineno, line)
        if b is not None:
            blocks.append(b)
    return blocks


def decode_angle_code(value: float) -> tuple[int, int, float]:
    """An angle code (machine constant 8 in angle mode, or an R parameter) -> (sign, axis, degrees).

    The code has eight decades: 8-7 zero, 6 the axis number, 5..1 the angle in thousandths of a
    degree. A parameter holds it as a decimal whose integer part is decades 8..4 and whose three
    decimals are decades 3..1 (``R04=-00120.000``: minus, axis 1, 20.000 degrees).
    """
    if not math.isfinite(value):
        raise ValueError("not a finite number")
    sign = -1 if value < 0 else 1
    digits = f"{round(abs(value) * 1000):08d}"
    if len(digits) > 8:
        raise ValueError("more than eight decades")
    return sign, int(digits[2]), int(digits[3:]) / 1000.0
