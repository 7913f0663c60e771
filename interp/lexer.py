"""Pieces every dialect's block scanner uses: numbers with their written form, words, blocks."""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from .errors import CutsimError

# A number as controllers write it: sign, digits, optional point, optional digits (``3.``, ``.5``,
# ``-00120.000``).  The Unicode minus sign appears in OCR'd manuals and is accepted.
NUMBER = re.compile(r"[+\-\u2212]?(?:\d+\.?\d*|\.\d+)")


@dataclass(frozen=True)
class Word:
    """One address word. ``value`` is the number, ``param`` the R parameter it reads (``FR10``),
    ``raw`` the text as written (needed for rules like "E needs a decimal point")."""

    letter: str
    value: float | None
    raw: str
    col: int
    param: int | None = None


@dataclass
class Block:
    line: int
    col: int
    text: str
    label: str = ""  # N word as written, e.g. "N330"
    words: list[Word] = field(default_factory=list)
    assigns: list[tuple[int, float, int]] = field(default_factory=list)  # (R number, value, col)
    comment: str = ""

    @property
    def empty(self) -> bool:
        return not self.words and not self.assigns

    def find(self, letter: str) -> list[Word]:
        return [w for w in self.words if w.letter == letter]


def parse_number(program: str, line: int, text: str, i: int, what: str) -> tuple[float, str, int]:
    """Read a number at ``text[i:]``; return (value, raw, next index). A number glued to another
    point or digit run (``1.2.3``) is malformed."""
    m = NUMBER.match(text, i)
    if not m:
        raise CutsimError(program, line, i + 1, f"malformed number after {what}")
    raw = m.group(0)
    j = m.end()
    if j < len(text) and (text[j] == "." or text[j].isdigit()):
        bad = re.match(r"[\w.+\-]*", text[i:]).group(0)
        raise CutsimError(program, line, i + 1, f"malformed number '{bad}' after {what}")
    return float(raw.replace("\u2212", "-")), raw, j


def block_number(program: str, line: int, text: str, i: int, block: Block, must_open: bool) -> int:
    """Read the block number after the ``N`` at ``text[i - 1]`` into ``block.label`` (``"N330"``);
    return the index after its digits. ``must_open``: N must be the first word of the block
    (CNC8x6); otherwise it may stand anywhere, once (ISG)."""
    col = i
    j = i
    while j < len(text) and text[j].isdigit():
        j += 1
    if j == i:
        raise CutsimError(program, line, col, "N must be followed by a block number")
    if must_open and (block.label or block.words or block.assigns):
        raise CutsimError(program, line, col, "the block number N must open the block")
    if block.label:
        raise CutsimError(program, line, col, "two block numbers N in one block")
    block.label = "N" + text[i:j]
    return j


def split_lines(text: str) -> list[str]:
    """Program lines without their line ends (CR LF, LF or CR)."""
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
