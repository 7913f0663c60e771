"""The happy path of a dialect's line scanner: a line made only of an optional block number and
plain address words ``<letter><number>`` (``N10 G01 X20.5 Z-1 F100``) is split by one regular
expression into the words the full scanner would give; every other line (and any word that needs a
check to fail: a repeated address, a value out of range) goes the long way, which builds the same
block or names the error. tests/interp/core/test_fast_readers.py checks, line by line, that the two agree.

A dialect gives its plain letters and their limits, how long a number may be, how a block number
and a trailing comment are written. ``plain_fields`` derives from the block type itself which
blocks its plain executor may take: a field added to the block type rules blocks that use it out.
"""
from __future__ import annotations

import re
from dataclasses import MISSING, fields

from .lexer import Word

# Any number, read atomically: once read it is never re-split (a shorter number would leave a digit
# next, which no plain line accepts), so a line that fails to match fails in linear time.
ANY_NUMBER = r"(?>[+\-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))"


def plain_patterns(letters: str, digits: int | None, label: str, comment: str = ""):
    """The two regular expressions of a plain line (see PlainReader): the whole line (group 1: the
    block number's digits as ``label`` captures them, group 2: the words) and one word (letter,
    number, the blanks after it). ``letters`` in upper case; lower case is accepted too."""
    cls = letters + letters.lower()
    if digits is None:
        num, guard, group = ANY_NUMBER, "", "(?>"
    else:
        d = digits
        num, guard, group = rf"[+\-]?(?:[0-9]{{1,{d}}}(?:\.[0-9]{{0,{d}}})?|\.[0-9]{{1,{d}}})", "(?![0-9.])", "(?:"
    line = re.compile(rf"[ \t]*(?:{label}[ \t]*)?({group}[{cls}]{num}{guard}[ \t]*)*){comment}")
    return line, re.compile(rf"([{cls}])({num})([ \t]*)")


class PlainReader:
    """``read(text)``: (block number or None, words) for a plain line, None for any other.

    ``letters``: the addresses (upper case) whose plain word is just ``Word(letter, value, raw,
    col)``; ``limits``: address -> the largest magnitude it accepts; ``digits``: at most that many
    digits before and after the point (None: any number, read atomically so that a long number
    fails in linear time); ``label``: the block number's pattern (one group: its digits);
    ``comment``: the pattern of a comment allowed at the end of the line ("" for none)."""

    def __init__(self, letters: str, limits: dict[str, float], digits: int | None, label: str, comment: str = ""):
        self.line, self.word = plain_patterns(letters, digits, label, comment)
        self.limits = {c: (k, limits[k]) for k in letters for c in (k, k.lower())}

    def read(self, text: str):
        m = self.line.fullmatch(text)
        if m is None:
            return None
        number, rest = m.groups()
        words: list[Word] = []
        if rest:
            limits = self.limits
            seen = ""
            new = tuple.__new__
            col = m.start(2) + 1
            for letter, raw, gap in self.word.findall(rest):
                address, limit = limits[letter]
                if address in seen and address not in "GM":
                    return None  # the long way's "appears twice" error
                seen += address
                value = float(raw)
                if not -limit <= value <= limit:
                    return None  # the long way's range error
                words.append(new(Word, (address, value, raw, col, None)))
                col += 1 + len(raw) + len(gap)
        return number, words


def plain_fields(block_type, plain=("line", "col", "label", "words")):
    """A test ``block -> bool``: whether every field of ``block_type`` besides ``plain`` holds its
    default (no assignment, call, command, jump ... in the block). Written out as one expression
    over the fields (``b.call is None and not b.offsets and ...``, as dataclasses writes its
    methods): it runs for every block, and a generic loop over the fields costs twice as much."""
    terms, env = [], {}
    for f in fields(block_type):
        if f.name in plain:
            continue
        default = f.default if f.default is not MISSING else f.default_factory()
        if default is None:
            terms.append(f"b.{f.name} is None")
        elif not default and isinstance(default, (str, list, dict, tuple, set)):
            terms.append(f"not b.{f.name}")
        else:
            env[f"d_{f.name}"] = default
            terms.append(f"b.{f.name} == d_{f.name}")
    exec(f"def test(b):\n    return {' and '.join(terms) or 'True'}\n", env)  # noqa: S102 - built from field names
    return env["test"]
