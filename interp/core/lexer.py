"""Pieces every dialect's block scanner uses: numbers with their written form, words, blocks, and
the limits every number and every program must stay within (docs/dialects/*.md, "Limits").

Numbers are read from ASCII digits only: Python's ``float()`` and ``int()`` also accept other
scripts' digits (``'１32'`` is 132 to them), which no controller reads. Every number is checked
where it is read: finite and within the range its address allows.
"""
from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass, field
from typing import NamedTuple

from ..errors import CutsimError

# A number as controllers write it: sign, digits, optional point, optional digits (``3.``, ``.5``,
# ``-00120.000``).  The Unicode minus sign appears in OCR'd manuals and is accepted.  ``[0-9]``,
# not ``\d``: the latter matches every script's digits.
NUMBER = re.compile(r"[+\-\u2212]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")
# The happy path of parse_number: an ASCII number not glued to a point, a digit or any non-ASCII
# character (those go the long way, which names what is wrong).
PLAIN_NUMBER = re.compile(r"[+\-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?![0-9.]|[^\x00-\x7f])")

# -- limits (documented in docs/dialects/cnc8x6.md and isg.md) ---------------------------------------
COORD_LIMIT = 99_999.9999  # |coordinate|, offsets, lengths, leads and feeds (mm, mm/rev, mm/min)
SPEED_LIMIT = 99_999.0  # spindle speed S (rpm)
CODE_LIMIT = 99_999_999  # whole-number words: block numbers, G/M codes, tools, offsets, repeat counts
NUMBER_LIMIT = 99_999_999.9999  # any number at all (the widest range of any address)


def is_digit(c: str) -> bool:
    """An ASCII digit 0-9 (``str.isdigit`` is true for every script's digits)."""
    return "0" <= c <= "9"


_DIGITS = re.compile(r"[0-9]*")


def digits_end(text: str, i: int) -> int:
    """The index after the run of ASCII digits starting at ``i``."""
    return _DIGITS.match(text, i).end()


def foreign_digit(program: str, line: int, text: str, i: int) -> None:
    """Refuse a digit of another script (fullwidth ``１``, Arabic-Indic ``١``, superscript ``²``) at
    ``text[i]``: it looks like a number but is not one to a controller."""
    if i < len(text) and text[i] >= "\x80":  # ASCII is never a foreign digit
        c = text[i]
        if c.isdigit() or unicodedata.numeric(c, None) is not None:
            name = unicodedata.name(c, f"U+{ord(c):04X}")
            raise CutsimError(program, line, i + 1, f"'{c}' ({name}) is not a digit a controller reads: "
                              "write numbers with the ASCII digits 0-9")


def _show(raw: str) -> str:
    """A number as written, shortened for a message when it is very long."""
    return raw if len(raw) <= 24 else f"{raw[:12]}...{raw[-6:]} ({len(raw)} characters)"


def fmt_limit(v: float) -> str:
    """99999.9999 -> '99 999.9999' (thin groups as in the docs)."""
    whole, _, frac = f"{v:.4f}".rstrip("0").rstrip(".").partition(".")
    sign = "-" if whole.startswith("-") else ""
    whole = whole.lstrip("-")
    groups = []
    while len(whole) > 3:
        groups.insert(0, whole[-3:])
        whole = whole[:-3]
    groups.insert(0, whole)
    return sign + " ".join(groups) + ("." + frac if frac else "")


def fmt_count(n: int) -> str:
    """A block count for a message: ``1,234,567``; from 10^15 on ``about 4.24e+1503`` (a count
    of nested loops can have thousands of digits, more than ``str(int)`` converts)."""
    if n < 10**15:
        return f"{n:,}"
    e = math.log10(n)
    return f"about {10 ** (e - int(e)):.2f}e+{int(e)}"


def permitted_range(lo: float, hi: float, unit: str = "") -> str:
    """The one wording of a range error (the controllers' "value exceeds permitted range"):
    'exceeds the permitted range -99 999.9999 to 99 999.9999 mm'."""
    u = f" {unit}" if unit else ""
    return f"exceeds the permitted range {fmt_limit(lo)} to {fmt_limit(hi)}{u}"


def out_of_range(program: str, line: int, col: int, word: str, lo: float, hi: float, unit: str = "") -> CutsimError:
    """The error for the word ``word`` whose value is beyond [lo, hi]."""
    return CutsimError(program, line, col, f"{_show(word)}: value {permitted_range(lo, hi, unit)}")


def check_range(program: str, line: int, col: int, word: str, value: float, lo: float, hi: float,
                unit: str = "") -> float:
    """``value`` (written as ``word``, e.g. ``X1e9`` or ``FR10``) if finite and within [lo, hi];
    else an error at ``col``."""
    if not (math.isfinite(value) and lo <= value <= hi):
        raise out_of_range(program, line, col, word, lo, hi, unit)
    return value


class Word(NamedTuple):
    """One address word. ``value`` is the number, ``param`` the R parameter it reads (``FR10``),
    ``raw`` the text as written (needed for rules like "E needs a decimal point"). Immutable; a
    named tuple because a program has millions of them (cheaper to make than a frozen dataclass)."""

    letter: str
    value: float | None
    raw: str
    col: int
    param: int | None = None


@dataclass(slots=True)
class Block:
    line: int
    col: int
    label: str = ""  # N word as written, e.g. "N330"
    words: list[Word] = field(default_factory=list)
    assigns: list[tuple[int, float, int]] = field(default_factory=list)  # (R number, value, col)

    @property
    def empty(self) -> bool:
        return not self.words and not self.assigns

    def find(self, letter: str) -> list[Word]:
        return [w for w in self.words if w.letter == letter]


def parse_number(program: str, line: int, text: str, i: int, what: str,
                 limit: float = NUMBER_LIMIT, unit: str = "", col: int | None = None) -> tuple[float, str, int]:
    """Read a number at ``text[i:]``; return (value, raw, next index). A number glued to another
    point or digit run (``1.2.3``) is malformed; a digit of another script is refused; a value
    beyond ``limit`` in magnitude (default: the widest any address allows) is an error naming
    ``what`` and the number, at ``col`` (the word's column; default the number's)."""
    m = PLAIN_NUMBER.match(text, i)
    if m is not None:  # the happy path: the same result without the checks' calls
        raw = m.group()
        value = float(raw)
        if -limit <= value <= limit:  # never true for NaN
            return value, raw, m.end()
    m = NUMBER.match(text, i)
    if not m:
        j = i + 1 if i < len(text) and text[i] in "+-\u2212" else i
        foreign_digit(program, line, text, j)
        raise CutsimError(program, line, i + 1, f"malformed number after {what}")
    raw = m.group(0)
    j = m.end()
    foreign_digit(program, line, text, j)
    if j < len(text) and (text[j] == "." or is_digit(text[j])):
        bad = re.match(r"[\w.+\-]*", text[i:]).group(0)
        raise CutsimError(program, line, i + 1, f"malformed number '{_show(bad)}' after {what}")
    value = float(raw.replace("\u2212", "-"))
    check_range(program, line, i + 1 if col is None else col, what + raw, value, -limit, limit, unit)
    return value, raw, j


def read_whole(program: str, line: int, text: str, i: int, what: str, limit: int = CODE_LIMIT) -> tuple[int, int]:
    """An unsigned whole number of ASCII digits at ``text[i:]`` (a parameter or block number):
    (value, next index). Refuses foreign digits and values above ``limit`` (checked on the digit
    count first, so no huge integer is ever built)."""
    j = digits_end(text, i)
    foreign_digit(program, line, text, j)
    digits = text[i:j].lstrip("0")
    if len(digits) > len(str(limit)) or (digits and int(digits) > limit):
        raise out_of_range(program, line, i, what + text[i:j], 0, limit)
    return (int(digits) if digits else 0), j


def block_number(program: str, line: int, text: str, i: int, block: Block, must_open: bool) -> int:
    """Read the block number after the ``N`` at ``text[i - 1]`` into ``block.label`` (``"N330"``);
    return the index after its digits. ``must_open``: N must be the first word of the block
    (CNC8x6); otherwise it may stand anywhere, once (ISG). Block numbers are 0..99 999 999."""
    col = i
    j = digits_end(text, i)
    if j == i:
        foreign_digit(program, line, text, i)
        raise CutsimError(program, line, col, "N must be followed by a block number")
    if must_open and (block.label or block.words or block.assigns):
        raise CutsimError(program, line, col, "the block number N must open the block")
    if block.label:
        raise CutsimError(program, line, col, "two block numbers N in one block")
    if j - i > 8 or (j < len(text) and text[j] >= "\x80"):  # the checks only where they can fail
        read_whole(program, line, text, i, "N")
    block.label = "N" + text[i:j]
    return j


def split_lines(text: str) -> list[str]:
    """Program lines without their line ends (CR LF, LF or CR)."""
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")


_EOL = re.compile(r"\r\n|\r|\n")


def iter_lines(text: str, chunk: int = 1 << 16):
    """(line number, line) without building a list of all lines: memory stays flat in the length
    of the program. The same lines as ``split_lines``. Text with LF line ends only (the usual) is
    split a ``chunk`` of characters at a time (str.split), other text by a regular expression."""
    if "\r" not in text:
        lineno, start, n = 0, 0, len(text)
        while True:
            end = text.find("\n", start + chunk) if start + chunk < n else -1
            for line in text[start:].split("\n") if end < 0 else text[start:end].split("\n"):
                lineno += 1
                yield lineno, line
            if end < 0:
                return
            start = end + 1
    lineno, i = 0, 0
    for m in _EOL.finditer(text):
        lineno += 1
        yield lineno, text[i:m.start()]
        i = m.end()
    yield lineno + 1, text[i:]


def block_lines(first: str) -> re.Pattern:
    """A pattern for ``check_length``: it matches at the start of every line whose first character
    after blanks is in the character class ``first`` (e.g. ``[^\\s]``: every non-blank line)."""
    return re.compile(r"(?:\A|(?<=\n)|(?<=\r)(?!\n))[ \t\f\v]*" + first)


def line_of(text: str, pos: int) -> int:
    """The 1-based line (as split_lines counts them) of the character at ``pos``."""
    head = text[:pos]
    return 1 + head.count("\r\n") + (head.count("\n") - head.count("\r\n")) + (head.count("\r") - head.count("\r\n"))


def check_length(program: str, text: str, max_blocks: int, blocks: re.Pattern) -> None:
    """Refuse, before anything is scanned, a program with more than ``max_blocks`` blocks (a program
    that is simply too long, not one that loops): the error names the line of the first block
    over the limit. ``blocks`` matches at the start of every line that is a block (block_lines).
    Lines are counted, not kept: memory stays flat in the length of the program. A count of line
    ends decides first whether they need counting at all."""
    if text.count("\n") + text.count("\r") < max_blocks:
        return
    count = 0
    for m in blocks.finditer(text):
        count += 1
        if count > max_blocks:
            raise CutsimError(program, line_of(text, m.start()), 1, f"the program is longer than the limit of "
                              f"{max_blocks:,} blocks set by [simulation] max_blocks: this line is block {count:,} "
                              "of the file (refused before it runs; raise the setting for a longer program)")
