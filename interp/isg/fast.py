"""The happy path of the ISG line scanner (reader.py, ``scan``): a line made only of an
optional block number and plain address words ``<letter><number>`` (``N10 G01 X20.5 Z-1 F100``),
with an optional ``;`` comment at its end, is split by one regular expression into exactly the
IsgBlock ``scan`` builds. Every other line gives None and goes the long way, which builds the
block or names the error. tests/interp/core/test_fast_readers.py checks, line by line, that the two agree.

core.fast.PlainReader reads it. Conservative on purpose: only blanks and tabs between words, no blank between a letter and its
number, no ``( )`` comment, no ``/``, ``#``, ``$``, ``"``, ``[``, ``=``, ``@``, ``:``; the letters
L (calls), H (machine functions), V and P (variables) and N after the first word are left to the
long way, as is a repeated address other than G and M and any number the long way would refuse
(out of range, glued to a point or a digit, more digits than the regular expression allows).

``plain_block`` runs such a block (G00/G01, X, Y, Z, F) without core.Interpreter.execute's
pipeline, with the same effect (tests/interp/core/test_fast_readers.py runs every ISG program both ways); which blocks
it may take follows from IsgBlock's fields (core.fast.plain_fields).
Hooks: program.parse(..., fast=read_plain) and the first lines of Isg.block.
"""
from __future__ import annotations

from ..core import Step
from ..core.fast import PlainReader, plain_fields
from .reader import LIMITS, IsgBlock

# letters whose plain word is just Word(letter, value, raw, col) in reader.word; numbers of at most 12
# digits before and after the point; a block number of at most 8 digits not followed by ':' (a label)
_LETTERS = "GMXYZIJKFSTDABCUWR"
READER = PlainReader(_LETTERS, {k: LIMITS[k][0] for k in _LETTERS}, 12, r"[Nn]([0-9]{1,8})(?![0-9:])", r"(?s:;.*)?")


def read_plain(program: str, lineno: int, text: str) -> IsgBlock | None:
    """``reader.scan(program, lineno, text)`` for a plain line; None for any other line (and for a
    line without words: ``scan`` decides what that is)."""
    r = READER.read(text)
    if r is None:
        return None
    number, words = r
    if not words:
        if number is None:
            return None  # blank or comment only: the long way returns None
        return IsgBlock(lineno, 1, "N" + number)
    return IsgBlock(lineno, 1, "" if number is None else "N" + number, words, [], items=[("w", w) for w in words])


# -- running a plain block -------------------------------------------------------------------------
_MOVE_LETTERS = frozenset("XYZ")
# a block whose other fields (call, command, offset, jump, ...) all hold their defaults; ``items`` are
# the words when it has as many as words (an expression or assignment adds one)
_plain = plain_fields(IsgBlock, ("line", "col", "label", "words", "items"))


class PlainPath:
    """The plain-block shortcut of Isg (a part of it: the state is the interpreter's)."""

    def plain_block(self, b: IsgBlock, src, fr) -> bool:
        """Run the common block (only a G00/G01, X, Y, Z and F words, nothing else: no expression, call,
        command, offset, jump; G00/G01 active or programmed; F > 0; tool radius compensation off) the
        short way: what ``core.Interpreter.execute`` does to it is to make the motion and F modal and
        to hand the axis words to ``convert_motion``, which is called here the same way. False (nothing
        done) for any other block, which then goes the long way (and raises its errors there).

        ``src`` and ``fr`` are what Isg.block hands to ``execute``."""
        if self.comp_buf is not None or len(b.items) != len(b.words) or not _plain(b):
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
        mode = self.motion if motion is None else motion
        if mode > 1 or (feed is not None and feed[1] <= 0):  # G02/G03/G33 active; F <= 0: the long way's error
            return False
        self.motion = mode
        if feed is not None:
            self.feed = feed[1]
        self.convert_motion(Step(b, src, words, motion, context=fr))
        return True
