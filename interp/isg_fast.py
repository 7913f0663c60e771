"""The happy path of the ISG line scanner (interp/isg_scan.py, ``scan``): a line made only of an
optional block number and plain address words ``<letter><number>`` (``N10 G01 X20.5 Z-1 F100``),
with an optional ``;`` comment at its end, is split by one regular expression into exactly the
IsgBlock ``scan`` builds. Every other line gives None and goes the long way, which builds the
block or names the error. tests/test_fast_readers.py checks, line by line, that the two agree.

Conservative on purpose: only blanks and tabs between words, no blank between a letter and its
number, no ``( )`` comment, no ``/``, ``#``, ``$``, ``"``, ``[``, ``=``, ``@``, ``:``; the letters
L (calls), H (machine functions), V and P (variables) and N after the first word are left to the
long way, as is a repeated address other than G and M and any number the long way would refuse
(out of range, glued to a point or a digit, more digits than the regular expression allows).

``plain_block`` runs such a block (G00/G01, X, Y, Z, F) without core.Interpreter.execute's
pipeline, with the same effect (tests/test_fast_readers.py runs every ISG program both ways).
Hooks: isg_scan.parse(..., fast=read_plain) and the first lines of Isg.block (issue 13).
"""
from __future__ import annotations

import re

from .core import Step
from .isg_scan import LIMITS, IsgBlock
from .lexer import Word

# letters whose plain word is just Word(letter, value, raw, col) in isg_scan.word
_LETTERS = "GMXYZIJKFSTDABCUWR"
_NUM = r"[+\-]?(?:[0-9]{1,12}(?:\.[0-9]{0,12})?|\.[0-9]{1,12})"
_CLASS = _LETTERS + _LETTERS.lower()
PLAIN_LINE = re.compile(
    rf"[ \t]*(?:[Nn]([0-9]{{1,8}})(?![0-9:])[ \t]*)?((?:[{_CLASS}]{_NUM}(?![0-9.])[ \t]*)*)(?s:;.*)?")
PLAIN_WORD = re.compile(rf"([{_CLASS}])({_NUM})([ \t]*)")
# letter as written -> (address, the largest magnitude it accepts)
_LIMITS = {c: (k, LIMITS[k][0]) for k in _LETTERS for c in (k, k.lower())}


def read_plain(program: str, lineno: int, text: str) -> IsgBlock | None:
    """``isg_scan.scan(program, lineno, text)`` for a plain line; None for any other line (and for a
    line without words: ``scan`` decides what that is)."""
    m = PLAIN_LINE.fullmatch(text)
    if m is None:
        return None
    number, rest = m.groups()
    if not rest:
        if number is None:
            return None  # blank or comment only: the long way returns None
        return IsgBlock(lineno, 1, "N" + number)
    words = []
    items = []
    seen = ""
    new = tuple.__new__
    col = m.start(2) + 1
    for letter, raw, gap in PLAIN_WORD.findall(rest):
        address, limit = _LIMITS[letter]
        if address in seen and address not in "GM":
            return None  # the long way's "appears twice" error
        seen += address
        value = float(raw)
        if not -limit <= value <= limit:
            return None  # the long way's range error
        w = new(Word, (address, value, raw, col, None))
        words.append(w)
        items.append(("w", w))
        col += 1 + len(raw) + len(gap)
    return IsgBlock(lineno, 1, "" if number is None else "N" + number, words, [], items=items)


# -- running a plain block -------------------------------------------------------------------------
_MOVE_LETTERS = frozenset("XYZ")


def plain_block(m, b: IsgBlock, src, fr) -> bool:
    """Run the common block (only a G00/G01, X, Y, Z and F words, nothing else: no expression, call,
    command, offset, jump; G00/G01 active or programmed; F > 0; tool radius compensation off) the
    short way: what ``core.Interpreter.execute`` does to it is to make the motion and F modal and
    to hand the axis words to ``convert_motion``, which is called here the same way. False (nothing
    done) for any other block, which then goes the long way (and raises its errors there).

    ``m`` is the Isg interpreter, ``src`` and ``fr`` what Isg.block hands to ``execute``."""
    if (m.comp_buf is not None or len(b.items) != len(b.words) or b.call is not None or b.gcall is not None
            or b.offsets or b.commands or b.args or b.gvalues or b.goto is not None or b.deferred):
        return False
    motion = feed = None
    words = {}
    for w in b.words:
        letter = w[0]
        if letter in _MOVE_LETTERS:
            words[letter] = w
        elif letter == "F":
            feed = w
        elif letter == "G" and motion is None and (w[1] == 0.0 or w[1] == 1.0):
            motion = int(w[1])
        else:
            return False
    mode = m.motion if motion is None else motion
    if mode > 1 or (feed is not None and feed[1] <= 0):  # G02/G03/G33 active; F <= 0: the long way's error
        return False
    m.motion = mode
    if feed is not None:
        m.feed = feed[1]
    m.convert_motion(Step(b, src, words, motion, context=fr))
    return True
