"""The CNC8x6 plain path: the common block (G00/G01 with X, Y, Z, F) and, when streaming, the plain
line run without building its block, with exactly the effect and the errors of the long way
(core.Interpreter.execute). tests/interp/cnc8x6/test_interp_stream.py runs programs both ways."""
from __future__ import annotations

import re

from ..core.fast import ANY_NUMBER as _NUM
from ..core.lexer import COORD_LIMIT, Block
from ..canon import Src
from .language import READER

PLAIN_AXES = {"X": 0, "Y": 1, "Z": 2}
# A plain move in the usual order, N G00/G01 X Y Z F, each word at most once (plain_line)
MOVE_LINE = re.compile(rf"[ \t]*(?:[Nn]([0-9]{{1,8}})[ \t]*)?(?:[Gg]0?([01])[ \t]*)?(?:[Xx]({_NUM})[ \t]*)?"
                       rf"(?:[Yy]({_NUM})[ \t]*)?(?:[Zz]({_NUM})[ \t]*)?(?:[Ff]({_NUM})[ \t]*)?")
# The words of a plain move -> axis index, -1 for F, -2 for G
_MOVE_WORDS = {"X": 0, "Y": 1, "Z": 2, "F": -1, "G": -2}


class PlainPath:
    """The plain-block shortcuts of Cnc8x6 (a part of it: the state is the interpreter's)."""

    def plain_block(self, b: Block) -> bool:
        """The common block (only G00/G01, X, Y, Z and F words, none from a parameter; G00/G01
        active) executed directly, with exactly the effect and the errors of ``execute``; False
        (nothing done) for any other block, which then goes the long way."""
        motion = feed = None
        axes = []
        for w in b.words:
            letter = w[0]
            if w[4] is not None:
                return False
            if letter in PLAIN_AXES:
                axes.append((PLAIN_AXES[letter], w[1], w[3]))
            elif letter == "F":
                feed = w[1]
            elif letter == "G" and motion is None and (w[1] == 0.0 or w[1] == 1.0):
                motion = int(w[1])
            else:
                return False
        mode = self.motion if motion is None else motion
        if mode > 1 or (feed is not None and feed <= 0):  # G02/G03/G33 active; F <= 0 is an error
            return False
        self.plain_move(b.line, b.label, mode, feed, axes)
        return True

    def plain_line(self, lineno: int, text: str) -> bool:
        """``stream``'s shortcut: a plain line (READER) that plain_block would run without an
        error, run straight from its text without building its Block: counted and executed with
        the effect of scan + count_block + block. False (nothing done) for any other line."""
        pos = self.pos
        end = pos[:]
        absolute = self.absolute
        m = MOVE_LINE.fullmatch(text)
        if m is not None:  # the usual order: one regular expression reads all of it
            number, g, x, y, z, f = m.groups()
            if x is not None:
                v = float(x)
                if not -COORD_LIMIT <= v <= COORD_LIMIT:
                    return False
                end[0] = v if absolute else pos[0] + v
            if y is not None:
                v = float(y)
                if not -COORD_LIMIT <= v <= COORD_LIMIT:
                    return False
                end[1] = v if absolute else pos[1] + v
            if z is not None:
                v = float(z)
                if not -COORD_LIMIT <= v <= COORD_LIMIT:
                    return False
                end[2] = v if absolute else pos[2] + v
            moves = x is not None or y is not None or z is not None
            if f is not None:
                f = float(f)
                if not 0.0 < f <= COORD_LIMIT:  # F <= 0 is an error: the long way says so
                    return False
            elif not moves and g is None:
                return False  # N alone or a blank line
            motion = None if g is None else int(g)
            return self.plain_apply(lineno, number, motion, f, end, moves)
        r = READER.read(text)
        if r is None:
            return False
        number, words = r
        if not words or (number is not None and len(number) > 8):
            return False
        motion = feed = None
        seen = 0
        for w in words:
            index = _MOVE_WORDS.get(w[0])
            if index is None:
                return False
            value = w[1]
            if index >= 0:
                end[index] = value if absolute else pos[index] + value
                seen += 1
            elif index == -1:
                if value <= 0:
                    return False
                feed = value
            elif motion is None and (value == 0.0 or value == 1.0):
                motion = int(value)
            else:
                return False
        return self.plain_apply(lineno, number, motion, feed, end, seen > 0)

    def plain_apply(self, lineno: int, number: str | None, motion: int | None, feed: float | None, end: list,
                    moves: bool) -> bool:
        """plain_line's effect, when it can have it: G00/G01 ``motion`` and F ``feed`` (None: not
        programmed; > 0) become modal and, when the block ``moves`` (has axis words), the tool goes
        to ``end``. False (nothing done) when the long way must run the block (G02/G03/G33 active,
        an end beyond the limits)."""
        mode = self.motion if motion is None else motion
        if mode > 1:
            return False
        for v in end:
            if not -COORD_LIMIT <= v <= COORD_LIMIT:  # the long way names the word
                return False
        self.executed += 1  # count_block
        if self.executed > self.cfg.max_blocks:
            raise self.block_limit(Block(lineno, 1))
        self.motion = mode
        if feed is not None and feed != self.feed:  # an F repeating the modal feed keeps its float (memory)
            self.feed = feed
        if moves:
            src = Src(self.name, lineno, 1, "" if number is None else "N" + number)
            if mode:
                self.linear(src, (end[0], end[1], end[2]))
            else:
                self.rapid(src, (end[0], end[1], end[2]))
        return True

    def plain_move(self, line: int, label: str, mode: int, feed: float | None, axes: list) -> None:
        """What a plain block does: G00/G01 ``mode`` and F ``feed`` (None: not programmed) become
        modal, and with axis words ((axis index, value, column), ...) the tool moves."""
        self.motion = mode
        if feed is not None and feed != self.feed:  # an F repeating the modal feed keeps its float (memory)
            self.feed = feed
        if axes:
            pos = self.pos
            end = pos[:]
            if self.absolute:
                for i, v, _ in axes:
                    end[i] = v
            else:
                for i, v, _ in axes:
                    end[i] = pos[i] + v
            for v in end:
                if not -COORD_LIMIT <= v <= COORD_LIMIT:
                    self.check_position(line, end, {i: c for i, _, c in axes})
            src = Src(self.name, line, 1, label)
            end = (end[0], end[1], end[2])
            if mode:
                self.linear(src, end)
            else:
                self.rapid(src, end)
