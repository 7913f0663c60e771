"""The happy path of the Sinumerik block reader (interp/sinumerik_lang.py, ``scan_line``): a line
made only of an optional block number ``N<digits>`` and plain address words ``<letter><number>``
(``N10 G1 X20.5 Z-1 F100``), with an optional ``;`` comment, is split by one regular expression
into exactly the Line (with its ``Word(col, address, Num(value))`` statements) ``scan_line``
builds. Every other line gives None and goes the long way, which builds the Line or names the
error. tests/test_fast_readers.py checks, line by line, that the two agree.

Conservative on purpose: only blanks and tabs between words, no blank between a letter and its
number, nothing but the ASCII letters of plain addresses (G M X Y Z I J K F S T D L P A B C U V W
R Q), signs, digits and points before the comment; no ``=``, ``(``, ``$``, ``"``, ``:``, ``/``,
``%``, no exponent; at most 12 digits on either side of the point (the long way's digit limit is
20); the block (its comment not counted) no longer than the long way's limit.
"""
from __future__ import annotations

import re

from .sinumerik_lang import MAX_BLOCK_CHARS, Line, Num, Word

_LETTERS = "GMXYZIJKFSTDLPABCUVWRQ"
_CLASS = _LETTERS + _LETTERS.lower()
_NUM = r"[+\-]?(?:[0-9]{1,12}(?:\.[0-9]{0,12})?|\.[0-9]{1,12})"
PLAIN_LINE = re.compile(
    rf"[ \t]*(?:[Nn]([0-9]{{1,12}})(?![0-9.])[ \t]*)?((?:[{_CLASS}]{_NUM}(?![0-9.])[ \t]*)*)(?s:;.*)?")
PLAIN_WORD = re.compile(rf"([{_CLASS}])({_NUM})([ \t]*)")
_UPPER = {c: c.upper() for c in _CLASS}


def read_plain(program: str, lineno: int, text: str) -> Line | None:
    """``sinumerik_lang.scan_line(program, lineno, text)`` for a plain line (blank and comment-only
    lines included); None for any other line."""
    m = PLAIN_LINE.fullmatch(text)
    if m is None or m.end(2) > MAX_BLOCK_CHARS:
        return None
    number, rest = m.groups()
    ln = Line(lineno, text, "", "" if number is None else "N" + str(int(number)))
    if rest:
        stmts = ln.stmts
        col = m.start(2) + 1
        upper = _UPPER
        for letter, raw, gap in PLAIN_WORD.findall(rest):
            stmts.append(Word(col, upper[letter], Num(float(raw))))
            col += 1 + len(raw) + len(gap)
    return ln
