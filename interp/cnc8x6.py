"""MEFI CNC8x6 dialect (lathes and mills): seeds 000/001 (G33 threads) and 002 (helix, jumps).

See docs/dialects.md for what the simulator assumes where the manuals are silent.
"""
from __future__ import annotations

import math
import re
from bisect import bisect_left
from dataclasses import dataclass

from . import canon
from .canon import Ramp, Src
from .errors import CutsimError
from .lexer import (CODE_LIMIT, COORD_LIMIT, SPEED_LIMIT, Block, Word, block_lines, block_number, check_length,
                    check_range, digits_end, fmt_count, foreign_digit, iter_lines, parse_number, read_whole)
from .core.fast import ANY_NUMBER as _NUM, PlainReader
from .core import Code, Group, Interpreter, Step, sweep_degrees
from .modal import AXES, InterpConfig

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
    17: Code(Group.PLANE, "", "plane XY"),
    18: Code(Group.PLANE, "", "plane ZX"),
    19: Code(Group.PLANE, "", "plane YZ"),
    33: Code(Group.MOTION, "XYZFIJE", "thread: lead F, start angle I, runout J, lead-in E"),
    73: Code(Group.JUMP, "LQ", "jump"),
    90: Code(Group.DISTANCE, "", "absolute"),
    91: Code(Group.DISTANCE, "", "incremental"),
    94: Code(Group.FEED, "", "feed per minute"),
    95: Code(Group.FEED, "", "feed per revolution"),
    98: Code(Group.HELIX_OFF, "", "helix off"),
}
# M words: spindle, program end, stops, coolant and gear ranges (the last ones have no geometric effect).
M_CODES = {
    0: Code(Group.STOP, "", "program stop"),
    1: Code(Group.STOP, "", "optional stop"),
    2: Code(Group.END, "", "program end"),
    3: Code(Group.SPINDLE, "S", "spindle clockwise"),
    4: Code(Group.SPINDLE, "S", "spindle counter-clockwise"),
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
PLAIN_AXES = {"X": 0, "Y": 1, "Z": 2}
# A plain move in the usual order, N G00/G01 X Y Z F, each word at most once (plain_line)
MOVE_LINE = re.compile(rf"[ \t]*(?:[Nn]([0-9]{{1,8}})[ \t]*)?(?:[Gg]0?([01])[ \t]*)?(?:[Xx]({_NUM})[ \t]*)?"
                       rf"(?:[Yy]({_NUM})[ \t]*)?(?:[Zz]({_NUM})[ \t]*)?(?:[Ff]({_NUM})[ \t]*)?")
# The words of a plain move -> axis index, -1 for F, -2 for G
_MOVE_WORDS = {"X": 0, "Y": 1, "Z": 2, "F": -1, "G": -2}
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


class Cnc8x6(Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig):
        super().__init__(name, cfg)
        self.params: dict[int, float] = dict(cfg.parameters)
        self.lead: float | None = None
        self.helix_on = False
        self.helix_pitch: float | None = None
        self.after_ramp: tuple[Src, int] | None = None  # (G33 src, 1 = expect empty, 2 = expect all axes)
        self.blocks: list[Block] = []  # run_blocks: the program's blocks (stream keeps none)
        self.loops: dict[int, int] = {}  # run_blocks: G73 block index -> repeats still to do

    # -- main loop -------------------------------------------------------------------------------
    def run(self, text: str) -> canon.Program:
        """Interpret the program: streamed when it cannot jump, else from the list of its blocks."""
        if JUMP.search(text) is None:
            return self.stream(text)
        return self.run_blocks(text)

    def run_blocks(self, text: str) -> canon.Program:
        """Scan every block, count the G73 loops, then execute (jumps need the blocks at hand)."""
        blocks = parse(self.name, text, self.cfg.max_blocks)
        labels: dict[int, int] = {}
        for idx, b in enumerate(blocks):
            if b.label:
                labels.setdefault(int(b.label[1:]), idx)
        self.check_loops(blocks, labels)
        self.blocks = blocks
        self.loops: dict[int, int] = {}  # G73 block index -> repeats still to do (first armed = outermost)
        loops = self.loops
        pc = 0
        while pc < len(blocks):
            b = blocks[pc]
            self.count_block(b)
            jump, ended = self.block(b, labels, pc)
            if ended:
                break
            if jump is not None:
                target, rep, word = jump
                if pc not in loops:
                    loops[pc] = rep
                if loops[pc] > 0:
                    loops[pc] -= 1
                    pc = target
                    continue
                del loops[pc]
            pc += 1
        else:
            if self.after_ramp is not None and self.after_ramp[1] == 1:
                src = self.after_ramp[0]
                raise self.error(src.line, src.col, "a thread with runout or lead-in must be followed by an empty block")
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    def stream(self, text: str) -> canon.Program:
        """``run`` for a program without G73: each line is scanned and executed in turn and not
        kept, so memory does not grow with the number of blocks. The result and every error are
        those of ``run``: that scans the whole file before it executes, so when a block fails here
        the rest of the file is scanned first and its first syntax error, if any, is the error."""
        name = self.name
        check_length(name, text, self.cfg.max_blocks, BLOCK_LINES)
        lines = iter_lines(text)
        for lineno, line in lines:
            try:
                if self.after_ramp is None and self.plain_line(lineno, line):
                    continue
            except CutsimError:
                for lineno, line in lines:  # a syntax error later in the file comes first
                    scan(name, lineno, line)
                raise
            b = scan(name, lineno, line)
            if b is None:
                continue
            try:
                self.count_block(b)
                ended = self.block(b, None, 0)[1]
            except CutsimError:
                for lineno, line in lines:  # a syntax error later in the file comes first
                    scan(name, lineno, line)
                raise
            if ended:
                for lineno, line in lines:  # the blocks after the program end are checked, not run
                    scan(name, lineno, line)
                break
        else:
            if self.after_ramp is not None and self.after_ramp[1] == 1:
                src = self.after_ramp[0]
                raise self.error(src.line, src.col, "a thread with runout or lead-in must be followed by an empty block")
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    # -- G73 loop counts ---------------------------------------------------------------------------
    def check_loops(self, blocks: list[Block], labels: dict[int, int]) -> None:
        """Refuse, before running, a program whose G73 loops would execute more than
        ``cfg.max_blocks`` blocks; the error points at the outermost G73 running when the count
        passes the limit (see count_executions)."""
        jumps, end = static_jumps(blocks, labels)
        limit = self.cfg.max_blocks
        total = count_executions(jumps, end)
        if total <= limit:
            return
        chain = crossing_loops(jumps, end, limit)
        if not chain:  # passed after the loops: name the one that adds the most blocks
            chain = heaviest_loops(jumps)
        if not chain:  # no loop at all: the runtime guard names the block
            return
        outer = chain[0]
        raise self.error(outer.line, outer.col,
                         f"G73 loops would execute {fmt_count(total)} blocks ({_describe(chain)}), more than the limit of "
                         f"{limit:,} set by [simulation] max_blocks; treated as a program that does not end")

    def block_limit(self, b: Block):
        """The runtime guard (loops the static count cannot see: L or Q from a parameter). Points at
        the outermost active G73."""
        blocks, active = self.blocks, list(self.loops)
        limit = self.cfg.max_blocks
        if not active:
            return self.error(b.line, b.col, f"the program executes more than the limit of {limit:,} blocks "
                              "set by [simulation] max_blocks")
        chain = []
        for idx in active:
            g = blocks[idx]
            gw = next(w for w in g.words if w.letter == "G" and w.value == 73)
            q = g.find("Q")
            chain.append(Jump(idx, idx, q[0].raw if q else "?", g.line, gw.col))
        outer = chain[0]
        return self.error(outer.line, outer.col,
                          f"G73 loops ({_describe(chain)}) execute more than the limit of {limit:,} blocks set by "
                          "[simulation] max_blocks; treated as a program that does not end")

    # -- one block (core.Interpreter.execute runs the steps in order) --------------------------------
    def block(self, b: Block, labels: dict[int, int], pc: int):
        """Execute one block: (jump or None, whether the program ended)."""
        if self.after_ramp is None and not b.assigns and self.plain_block(b):
            return None, False
        if self.ramp_rule(b):
            return None, False
        st = self.execute(b, Src(self.name, b.line, 1, b.label), (labels, pc))
        if st.done:
            return None, False
        return st.jump, st.result

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

    def ramp_rule(self, b: Block) -> bool:
        """After a thread with runout or lead-in: an empty block, then one with every axis. True
        for the empty block (nothing else to do)."""
        if self.after_ramp is None:
            return False
        g33src, stage = self.after_ramp
        if stage == 1:
            if not b.empty:
                raise self.error(b.line, 1, f"line {g33src.line} cuts a thread with runout or lead-in: "
                                 "the next block must be empty")
            self.after_ramp = (g33src, 2)
            return True
        missing = [a for a in self.machine_axes() if not b.find(a)]
        if missing:
            raise self.error(b.line, 1, f"after the empty block that follows the thread at line {g33src.line}, "
                             f"this block must program every axis (missing {', '.join(missing)})")
        self.after_ramp = None
        return False

    def read_words(self, b: Block) -> list[Word]:
        """The block's R assignments in order, then its words with parameter values substituted."""
        for num, value, col in b.assigns:
            if num in RESERVED_PARAMS:
                raise self.error(b.line, col, f"R{num:02d} is reserved and cannot be assigned")
            self.params[num] = value
        values = []
        for w in b.words:
            if w.param is not None:
                if w.letter in "GM":
                    raise self.error(b.line, w.col, f"{w.letter} cannot take its value from a parameter")
                if w.param in RESERVED_PARAMS:
                    raise self.error(b.line, w.col, f"R{w.param:02d} is reserved")
                if w.param not in self.params:
                    raise self.error(b.line, w.col, f"parameter R{w.param:02d} is used before it is set")
                value = self.params[w.param]
                lim, unit = LIMITS[w.letter]
                check_range(self.name, b.line, w.col, f"{w.letter}{w.raw} = {value:g}", value, -lim, lim, unit)
                w = Word(w.letter, value, w.raw, w.col, w.param)
            values.append(w)
        return values

    def standalone(self, st: Step) -> bool:
        g98 = st.g.get(Group.HELIX_OFF)
        if g98 is None:
            return False
        if len(st.block.words) != 1 or st.block.assigns:
            raise self.error(st.block.line, g98.col, "G98 (helix off) must stand alone in its block")
        self.helix_on = False
        return True

    def convert_settings(self, st: Step) -> None:
        """Spindle, tool and the other non-motion words take effect before the motion."""
        b, words = st.block, st.words
        speed = words.pop("S").value if "S" in words else None
        if speed is not None and speed < 0:
            raise self.error(b.line, 1, "spindle speed S must not be negative")
        if st.direction is not None or speed is not None:
            self.spindle(st.src, st.direction, speed)
        self.tool_words(st, lambda t: self.whole(b.line, t, "tool number"))
        words.pop("&", None)  # recorded, no effect (docs/dialects.md)

    def convert_nonmodal(self, st: Step) -> None:
        """G73 (the jump the run loop takes), G10 (helix pitch), G09 (helix on)."""
        b, words = st.block, st.words
        if Group.JUMP in st.g:
            labels, pc = st.context
            st.jump = self.parse_jump(b, words, labels, pc, st.g[Group.JUMP])
        g10 = st.g.get(Group.HELIX_PITCH)
        if g10 is not None:  # trailing-axis pitch for the helix: not a motion
            axes = [a for a in AXES if a in words]
            if len(axes) != 1:
                raise self.error(b.line, g10.col, "G10 takes exactly one axis word: the helix pitch")
            self.helix_pitch = words.pop(axes[0]).value
            self.helix_axis = axes[0]
            if st.motion is not None or any(a in words for a in AXES):
                raise self.error(b.line, g10.col, "G10 sets the helix pitch and cannot move the tool")
        g09 = st.g.get(Group.HELIX_ON)
        if g09 is not None:
            if self.helix_pitch is None:
                raise self.error(b.line, g09.col, "G09 switches the helix on, but no pitch was set with G10")
            self.helix_on = True

    def convert_feed(self, st: Step) -> None:
        if "F" in st.words and self.motion != 33:  # F of G33 is the lead (thread)
            f = st.words.pop("F")
            if f.value <= 0:
                raise self.error(st.block.line, f.col, "feed F must be positive")
            self.feed = f.value

    def convert_motion(self, st: Step) -> None:
        b, src, words, motion = st.block, st.src, st.words, st.motion
        axis_words = {AXES.index(a): words[a] for a in AXES if a in words}
        if self.motion == 33 and (motion == 33 or axis_words):
            self.thread(b, src, words, axis_words)
        elif axis_words or motion in (2, 3):
            values = {i: w.value for i, w in axis_words.items()}
            if self.motion in (0, 1):
                allowed = G_CODES[self.motion].words
                for a in "IJKEQL":
                    if a in words and a not in allowed:
                        raise self.error(b.line, words[a].col, f"address {a} has no meaning in a G0{self.motion} block")
                end = self.target(values)
                self.check_position(b.line, end, {i: w.col for i, w in axis_words.items()})
                (self.rapid if self.motion == 0 else self.linear)(src, end)
            else:
                self.circle(b, src, words, values)
        else:
            for a in "IJKE":
                if a in words:
                    raise self.error(b.line, words[a].col, f"address {a} without a motion")

    def convert_end(self, st: Step) -> None:
        st.result = bool(self.m_group(st, Group.END))
        if st.result:
            self.end(st.src)

    def machine_axes(self) -> tuple[str, ...]:
        return ("X", "Z") if self.cfg.machine_kind == "lathe" else ("X", "Y", "Z")

    # -- G73 jump --------------------------------------------------------------------------------
    def parse_jump(self, b: Block, words: dict[str, Word], labels: dict[int, int], pc: int, g: Word):
        lw, qw = words.pop("L", None), words.pop("Q", None)
        if lw is None:
            raise self.error(b.line, g.col, "G73 needs L<block number> to jump to")
        if qw is None:
            raise self.error(b.line, g.col, "G73 needs Q<repeats>: without it the jump never ends")
        if lw.value != int(lw.value) or int(lw.value) not in labels:
            raise self.error(b.line, lw.col, f"G73 jumps to block N{lw.raw}, which does not exist")
        if qw.value != int(qw.value) or qw.value < 0:
            raise self.error(b.line, qw.col, "Q must be a whole number of repeats, 0 or more")
        target = labels[int(lw.value)]
        if target > pc:
            raise self.error(b.line, lw.col, f"G73 jumps back; N{lw.raw} comes after this block")
        return target, int(qw.value), g

    # -- circles and helices ---------------------------------------------------------------------
    def circle(self, b: Block, src: Src, words: dict[str, Word], values: dict[int, float]) -> None:
        centre = self.centre_words(b.line, words)
        end = list(self.target(values))
        if self.helix_on:
            ax = AXES.index(self.helix_axis)
            if ax in values:
                raise self.error(b.line, words[self.helix_axis].col,
                                 f"with the helix on, {self.helix_axis} follows the pitch set by G10 and cannot be programmed")
            sweep = sweep_degrees(self.pos, end, centre, self.plane, self.motion == 2, self.diameter)
            end[ax] = self.pos[ax] + self.helix_pitch * sweep / 360.0
        self.check_position(b.line, end, {i: words[AXES[i]].col for i in values})
        self.arc(src, (end[0], end[1], end[2]), centre, self.motion == 2)

    # -- G33 -------------------------------------------------------------------------------------
    def thread(self, b: Block, src: Src, words: dict[str, Word], axis_words: dict[int, Word]) -> None:
        if "F" in words:
            f = words.pop("F")
            if f.param is None and f.value > MAX_DIRECT_LEAD:
                raise self.error(b.line, f.col, f"lead F{f.raw} exceeds {MAX_DIRECT_LEAD} mm/rev; "
                                 "program a larger lead through a parameter (FR10)")
            if f.value <= 0:
                raise self.error(b.line, f.col, "the lead F of G33 must be greater than zero")
            if f.value < MIN_LEAD:
                raise self.error(b.line, f.col, f"the lead F{f.raw} of G33 is below the smallest lead, {MIN_LEAD} mm/rev")
            self.lead = f.value
        if self.lead is None:
            raise self.error(b.line, 1, "G33 without a lead: program F (mm/rev)")
        if not axis_words:
            raise self.error(b.line, 1, "G33 needs an end point")
        angle = 0.0
        if "I" in words:
            iw = words.pop("I")
            if not 0.0 <= iw.value <= 360.0:
                raise self.error(b.line, iw.col, f"start angle I{iw.raw} is outside 0..360 degrees")
            angle = iw.value
        end = self.target({i: w.value for i, w in axis_words.items()})
        self.check_position(b.line, end, {i: w.col for i, w in axis_words.items()})
        runout = leadin = None
        if "J" in words:
            jw = words.pop("J")
            if jw.value < 0:
                raise self.error(b.line, jw.col, "runout length J is always positive")
            if jw.value > 0:
                runout = self.ramp(b, jw, "runout", jw.value)
        if "E" in words:
            ew = words.pop("E")
            if ew.param is None and "." not in ew.raw:
                raise self.error(b.line, ew.col, f"lead-in E{ew.raw} must be written with a decimal point "
                                 f"(E{ew.raw}. or E{ew.raw}.0)")
            if ew.value < 0:
                raise self.error(b.line, ew.col, "lead-in length E must be positive")
            if ew.value > 0:
                leadin = self.ramp(b, ew, "lead-in", ew.value)
        for a in "KLQ":
            if a in words and a not in G_CODES[33].words:
                raise self.error(b.line, words[a].col, f"address {a} has no meaning in a G33 block")
        if leadin or runout:
            travel = self.thread_travel(end)
            total = (leadin.length if leadin else 0.0) + (runout.length if runout else 0.0)
            if total > travel + 1e-9:
                raise self.error(b.line, 1, f"lead-in and runout ({total:g} mm) are longer than the thread ({travel:g} mm)")
            self.after_ramp = (src, 1)
        if leadin is not None:
            end = self.leadin_end(b, src, end, axis_words, ew, leadin)
        self.synced(src, end, self.lead, None, angle, leadin, runout)
        self.check_position(b.line, self.pos)

    def leadin_end(self, b: Block, src: Src, end, axis_words: dict[int, Word], ew: Word, leadin: Ramp):
        """The record's end for a thread with a lead-in (canon.SyncedFeed: the tool follows the line
        start -> end with the ramps added, so it stops at end + ramp displacements).

        The lead-in ramps from the start point over the first E mm (seed 000, 5.3: the tool starts
        outside, at the value from which the lead-in reaches the thread). The lead-in axis left
        out of the block keeps that value: a straight thread at start + ramp (the manual's
        example). Programmed, it is where the thread ends, like every G33 end point; the thread
        then tapers from where the lead-in would have put a straight one, which is warned about
        unless the value is that straight thread's.
        """
        i = "XYZ".index(leadin.axis)
        scale = 2.0 if (i == 0 and self.diameter) else 1.0
        shift = leadin.displacement * scale  # program units
        if i not in axis_words:
            return end
        straight = self.pos[i] + shift
        if abs(end[i] - straight) > 1e-6:
            w = axis_words[i]
            on = " on the diameter" if scale == 2.0 else ""
            self.warn(src, f"G33 with lead-in E{ew.raw} and {leadin.axis}{w.raw} programmed: the thread ends at "
                           f"{leadin.axis}{end[i]:g} and the lead-in comes in from the start {leadin.axis}{self.pos[i]:g} "
                           f"by {abs(shift):.4g}{on} ({leadin.length:g}*tan {leadin.angle:g} deg) relative to the thread, "
                           f"so the thread tapers; leave {leadin.axis} out (or program {leadin.axis}{straight:.4f}) "
                           "for the manual's straight thread after the lead-in")
        out = list(end)
        out[i] -= shift
        return (out[0], out[1], out[2])

    def thread_travel(self, end) -> float:
        dx = abs(end[0] - self.pos[0]) / (2.0 if self.diameter else 1.0)
        return max(dx, abs(end[1] - self.pos[1]), abs(end[2] - self.pos[2]))

    def ramp(self, b: Block, w: Word, what: str, length: float) -> Ramp:
        """Angle and axis of a runout or lead-in from machine constant 8 or the parameter it names."""
        const = self.cfg.constants.get(8)
        if const is None:
            raise self.error(b.line, w.col, f"{what} needs its angle: set machine constant 8 ([machine.constants] 8 = ...)")
        if not (math.isfinite(const) and abs(const) < 1e8):
            raise self.error(b.line, w.col, f"machine constant 8 = {const} has more than eight decades")
        code = f"{abs(int(const)):08d}"
        if len(code) > 8:
            raise self.error(b.line, w.col, f"machine constant 8 = {const} has more than eight decades")
        if code[:2] == "00":  # angle mode: one angle and axis for runout and lead-in
            sign = -1 if const < 0 else 1
            axis, angle = int(code[2]), int(code[3:]) / 1000.0
            origin = f"machine constant 8 = {int(const)}"
        else:
            pnum = int(code[:2]) if what == "runout" else int(code[2:4])
            if pnum == 0:
                raise self.error(b.line, w.col, f"machine constant 8 = {int(const)} names no {what} parameter")
            if pnum in RESERVED_PARAMS:
                raise self.error(b.line, w.col, f"machine constant 8 names the reserved parameter R{pnum:02d}")
            if pnum not in self.params:
                raise self.error(b.line, w.col, f"the {what} angle parameter R{pnum:02d} (machine constant 8) is not set")
            try:
                sign, axis, angle = decode_angle_code(self.params[pnum])
            except ValueError:
                raise self.error(b.line, w.col, f"R{pnum:02d} = {self.params[pnum]} is not an angle code") from None
            origin = f"R{pnum:02d} = {self.params[pnum]:g}"
        if axis not in (1, 2, 3):
            raise self.error(b.line, w.col, f"{what} axis {axis} from {origin} is not 1 (X), 2 (Y) or 3 (Z)")
        if not 0.0 <= angle <= 60.0:
            raise self.error(b.line, w.col, f"{what} angle {angle:.3f} degrees from {origin} is outside 0..60")
        # + means the runout moves towards + on its axis; the lead-in comes from that side
        direction = sign if what == "runout" else -sign
        return Ramp(length, angle, AXES[axis - 1], direction)


# -- G73 loops without running them ----------------------------------------------------------------
# A G73 block at index g jumping to index t <= g with Q repeats: reached with no counter, it arms
# one with Q and jumps back while the counter is above zero; at zero it deletes the counter and
# execution falls through. Since every jump goes backwards, passing block g forwards means loop g
# has completed, so whenever block g is reached first in an activation, every loop with a G73
# between its target and g is disarmed. Hence (by induction over the G73 blocks from the last) every
# program ends, and one activation of loop g executes 1 + Q * (cost(t, g) + 1) blocks, where
#     cost(s, e) = (e - s) + sum of W_h over the G73 blocks h in [s, e),   W_h = Q_h * (cost(t_h, h) + 1)
# is the number of blocks executed from s (no counters armed) until block e is reached. For properly
# nested loops this is the sum over blocks of the product of (Q + 1) over the loops enclosing them;
# overlapping loops (a loop re-armed by an outer one) are counted exactly as well.


@dataclass(frozen=True)
class Jump:
    index: int  # the G73 block
    target: int  # the block it jumps to
    repeats: int | str  # Q (the text as written when it is not known statically)
    line: int
    col: int  # of the G73 word


def static_jumps(blocks: list[Block], labels: dict[int, int]) -> tuple[list[Jump], int]:
    """The G73 jumps with literal, valid L and Q in block order, and ``end``: how many blocks from the
    start the static count covers. It stops after the first program end (M02/M30) and before the
    first G73 whose L or Q is missing, invalid (an error when it runs) or read from a parameter."""
    jumps: list[Jump] = []
    for i, b in enumerate(blocks):
        if any(w.letter == "M" and w.value in (2, 30) for w in b.words):
            return jumps, i + 1  # the program ends here; a G73 in this block does not jump
        g73 = [w for w in b.words if w.letter == "G" and w.value == 73]
        if not g73:
            continue
        lw, qw = b.find("L"), b.find("Q")
        if len(g73) != 1 or len(lw) != 1 or len(qw) != 1:
            return jumps, i
        lw, qw = lw[0], qw[0]
        if lw.param is not None or qw.param is not None or lw.value != int(lw.value) or qw.value != int(qw.value) \
                or qw.value < 0 or int(lw.value) not in labels or labels[int(lw.value)] > i:
            return jumps, i
        jumps.append(Jump(i, labels[int(lw.value)], int(qw.value), b.line, g73[0].col))
    return jumps, len(blocks)


class _Counts:
    """cost(s, e) of the comment above, from prefix sums of W over the jumps in block order."""

    def __init__(self, jumps: list[Jump]):
        self.jumps = jumps
        self.index = [j.index for j in jumps]
        self.prefix = [0]  # prefix[k] = W of jumps[:k]
        self.w: list[int] = []
        for j in jumps:
            w = j.repeats * (self.cost(j.target, j.index) + 1)
            self.w.append(w)
            self.prefix.append(self.prefix[-1] + w)

    def cost(self, s: int, e: int) -> int:
        lo, hi = bisect_left(self.index, s), bisect_left(self.index, e)
        hi = min(hi, len(self.w))
        return (e - s) + self.prefix[hi] - self.prefix[min(lo, hi)]


def count_executions(jumps: list[Jump], end: int) -> int:
    """Blocks executed from the start until ``end`` (see static_jumps) is passed."""
    return _Counts(jumps).cost(0, end)


def crossing_block(jumps: list[Jump], end: int, limit: int) -> tuple[int, list[Jump]]:
    """Where execution number ``limit + 1`` happens (the program must run that far): the block's
    index and the loops whose counters are armed then, outermost first."""
    c = _Counts(jumps)
    s, e, budget = 0, end, limit  # from block s (no counters armed), ``budget`` blocks run before it
    armed: list[Jump] = []
    while True:
        pos = s
        for k in range(bisect_left(c.index, s), bisect_left(c.index, e)):
            j = jumps[k]
            if budget < j.index - pos:  # in the blocks before G73 j
                return pos + budget, armed
            budget -= j.index - pos
            if budget < 1 + c.w[k]:  # within the activation of loop j
                if budget == 0:  # its first execution: not armed yet
                    return j.index, armed
                budget = (budget - 1) % (c.cost(j.target, j.index) + 1)  # into the repeat that passes
                s, e = j.target, j.index
                armed.append(j)
                break
            budget -= 1 + c.w[k]
            pos = j.index + 1
        else:
            return pos + budget, armed


def crossing_loops(jumps: list[Jump], end: int, limit: int) -> list[Jump]:
    """The loops responsible when execution passes ``limit`` blocks, outermost (the last G73) first:
    those armed then and those enclosing the block being executed (they repeat it); empty when none."""
    pos, armed = crossing_block(jumps, end, limit)
    enclosing = [j for j in jumps if j.target <= pos <= j.index]
    return sorted(set(armed) | set(enclosing), key=lambda j: -j.index)


def heaviest_loops(jumps: list[Jump]) -> list[Jump]:
    """The loop adding the most executions, then within its span the loop adding the most, and so
    on (outermost first); empty when no loop repeats anything."""
    c = _Counts(jumps)
    chain: list[Jump] = []
    lo, hi = 0, len(jumps)  # candidates: jumps[lo:hi]
    while lo < hi:
        k = max(range(lo, hi), key=lambda i: (c.w[i], i))
        if c.w[k] == 0:
            break
        chain.append(jumps[k])
        lo, hi = bisect_left(c.index, jumps[k].target), k
    return chain


def _describe(chain: list[Jump]) -> str:
    """'Q20 at line 5 inside Q20 at line 6': innermost first, at most six loops named."""
    parts = [f"Q{j.repeats} at line {j.line}" for j in reversed(chain)]
    if len(parts) > 6:
        parts = parts[:3] + ["..."] + parts[-2:]
    return " inside ".join(parts)


def interpret(name: str, text: str, cfg: InterpConfig) -> canon.Program:
    return Cnc8x6(name, cfg).run(text)
