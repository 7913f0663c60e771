"""Beckhoff TwinCAT CNC (ISG kernel) dialect, lathe subset: seed 004 (G33 with a turning spindle).

A file holds one main program ``%name (title)`` ended by M30 and any number of local subprograms
``%L name`` ended by M29 (or M17), called with ``LL name``. See docs/dialects/isg.md for what the
simulator assumes where the manual is silent.
"""
from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field

from . import canon
from .canon import Src
from .errors import CutsimError
from .lexer import (CODE_LIMIT, COORD_LIMIT, SPEED_LIMIT, Block, Word, block_lines, block_number, check_length,
                    fmt_count, iter_lines, parse_number)
from .core import Code, Interpreter, Step
from .modal import AXES, InterpConfig

LETTERS = set("NGMXYZIJKFSTDL")
# The dialect's codes: {code: Code(modal group, addresses it takes, meaning)} (core.Code).
G_CODES = {
    0: Code("motion", "XYZ", "rapid"),
    1: Code("motion", "XYZF", "linear feed"),
    2: Code("motion", "XYZIJKF", "clockwise arc, centre I/J/K from the start"),
    3: Code("motion", "XYZIJKF", "counter-clockwise arc, centre I/J/K from the start"),
    17: Code("plane", "", "plane XY"),
    18: Code("plane", "", "plane ZX"),
    19: Code("plane", "", "plane YZ"),
    33: Code("motion", "XYZIJK", "thread, lead on I/J/K (mm/rev)"),
    51: Code("diameter", "", "diameter programming on (lathe)"),
    52: Code("diameter", "", "diameter programming off"),
    90: Code("dist", "", "absolute"),
    91: Code("dist", "", "incremental"),
    94: Code("feed", "", "feed per minute"),
    95: Code("feed", "", "feed per revolution"),
}
# M codes: stops, program end, spindle, tool change, coolant, subprogram end (the others have no
# geometric effect).
M_CODES = {
    0: Code("stop", "", "program stop"),
    1: Code("stop", "", "optional stop"),
    2: Code("end", "", "program end"),
    3: Code("spindle", "S", "spindle clockwise"),
    4: Code("spindle", "S", "spindle counter-clockwise"),
    5: Code("spindle", "", "spindle stop (after the motion)"),
    6: Code("tool", "TD", "tool change"),
    7: Code("coolant", "", "coolant"),
    8: Code("coolant", "", "coolant"),
    9: Code("coolant", "", "coolant off"),
    17: Code("end", "", "subprogram end"),
    29: Code("end", "", "subprogram end"),
    30: Code("end", "", "program end"),
}
LEADS = {"I": "X", "J": "Y", "K": "Z"}
MIN_LEAD = 0.0001  # mm/rev: the programming resolution
MAX_CALL_DEPTH = 20  # local subprograms open at once (LL inside LL ...)
# The largest magnitude each address accepts (docs/dialects/isg.md, "Limits"); the words' own
# rules (signs, whole numbers, S.OFFSET below 360) are checked where they act.
LIMITS = {**{a: (COORD_LIMIT, "mm") for a in "XYZIJK"}, "F": (COORD_LIMIT, "mm/min"),
          "S": (SPEED_LIMIT, "rpm"), **{a: (CODE_LIMIT, "") for a in "GMTD"}}
NAME = re.compile(r"(?:\w|[\u0300-\u036f\u1ab0-\u1aff\u1dc0-\u1dff\u20d0-\u20ff\ufe20-\ufe2f])+")
# letters (any script, also written with combining marks), digits, underscore
SPINDLE_ATTR = re.compile(r"\.([A-Za-z_]\w*)")


def _nfc(s: str) -> str:
    return unicodedata.normalize("NFC", s)


_UMLAUTS = str.maketrans({"ä": "ae", "ö": "oe", "ü": "ue", "ß": "ss", "Ä": "Ae", "Ö": "Oe", "Ü": "Ue"})


def _folds(name: str) -> set[str]:
    """Spellings a name may have been meant as: case folded, umlauts as digraphs or stripped."""
    n = _nfc(name)
    digraph = n.translate(_UMLAUTS).casefold()
    stripped = "".join(c for c in unicodedata.normalize("NFKD", n) if not unicodedata.combining(c)).casefold()
    return {n.casefold(), digraph, stripped}


@dataclass
class IsgBlock(Block):
    call: tuple[str, int] | None = None  # (subprogram name, column of the name)
    offsets: list[Word] = field(default_factory=list)  # S.OFFSET words


@dataclass
class Section:
    kind: str  # "main" | "local"
    name: str
    line: int
    col: int
    blocks: list[IsgBlock] = field(default_factory=list)
    ended: bool = False  # a local subprogram has seen its M29/M17


def scan(name: str, lineno: int, text: str) -> IsgBlock | None:
    """One ISG line (not a header) -> block; None for a blank or comment-only line."""
    block = IsgBlock(line=lineno, col=1)
    i, n = 0, len(text)
    seen: dict[str, int] = {}
    while i < n:
        c = text[i]
        if c.isspace():
            i += 1
            continue
        col = i + 1
        if c == ";":
            break  # a comment (its text is not kept)
        if c == "(":
            j = text.find(")", i + 1)
            if j < 0:
                raise CutsimError(name, lineno, col, "comment '(' is not closed by ')'")
            i = j + 1
            continue
        if not (c.isascii() and c.isalpha()):
            raise CutsimError(name, lineno, col, f"unexpected character '{c}'")
        letter = c.upper()
        i += 1
        if letter == "N":
            i = block_number(name, lineno, text, i, block, must_open=False)
            continue
        if letter == "L":
            if not (i < n and text[i] in "lL"):
                raise CutsimError(name, lineno, col, "L (global subprogram call) is not supported: define the "
                                  "subprogram in this file as '%L name' and call it with 'LL name'")
            i += 1
            while i < n and text[i] in " \t":
                i += 1
            m = NAME.match(text, i)
            if not m:
                raise CutsimError(name, lineno, i + 1, "LL must be followed by the name of a local subprogram")
            if block.call is not None:
                raise CutsimError(name, lineno, col, "two subprogram calls in one block")
            block.call = (_nfc(m.group(0)), i + 1)
            i = m.end()
            continue
        if letter == "S" and i < n and text[i] == "." and SPINDLE_ATTR.match(text, i):
            m = SPINDLE_ATTR.match(text, i)
            attr = m.group(1)
            if attr.upper() != "OFFSET":
                raise CutsimError(name, lineno, i + 2, f"unknown spindle attribute S.{attr} (only S.OFFSET is supported)")
            if block.offsets:
                raise CutsimError(name, lineno, col, "two spindle offsets (S.OFFSET) in one block")
            j = m.end()
            while j < n and text[j] in " \t":
                j += 1
            if j < n and text[j] == "=":
                j += 1
                while j < n and text[j] in " \t":
                    j += 1
            value, raw, i = parse_number(name, lineno, text, j, "S.OFFSET=", COORD_LIMIT, "degrees", col=col)
            block.offsets.append(Word("S.OFFSET", value, raw, col))
            continue
        if letter not in LETTERS:
            raise CutsimError(name, lineno, col, f"address '{letter}' is not used by the ISG dialect")
        if letter in seen and letter not in "GM":
            raise CutsimError(name, lineno, col, f"address {letter} appears twice in one block")
        seen[letter] = col
        value, raw, i = parse_number(name, lineno, text, i, letter, *LIMITS[letter], col=col)
        block.words.append(Word(letter, value, raw, col))
    if not block.label and not block.words and block.call is None and not block.offsets:
        return None
    return block


HEADER = re.compile(r"%(?:(?P<local>[Ll])[ \t]+(?P<lname>\S+)|(?P<mname>[^\s(;]+))")


# Lines that can be blocks, for lexer.check_length: never one that is not (headers, comment lines
# and blank lines are not; a line opening with a "( )" comment is left out too, which can only
# undercount).
BLOCK_LINES = block_lines(r"[^\s;%(]")


def parse(name: str, text: str, max_blocks: int | None = None) -> tuple[Section, dict[str, Section]]:
    """The file -> (main program, local subprograms by name). With ``max_blocks`` a file with more
    blocks than that is refused before any line is scanned (lexer.check_length)."""
    if max_blocks is not None:
        check_length(name, text, max_blocks, BLOCK_LINES)
    loose: list[IsgBlock] = []  # blocks before any header
    sections: list[Section] = []
    for lineno, line in iter_lines(text):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if stripped.startswith("%"):
            sections.append(_header(name, lineno, indent, stripped))
            continue
        b = scan(name, lineno, line)
        if b is None:
            continue
        if not sections:
            loose.append(b)
            continue
        sec = sections[-1]
        if sec.ended:
            raise CutsimError(name, lineno, 1, f"block after the end (M29) of subprogram '{sec.name}' "
                              "belongs to no program: start a program with '%name' or '%L name'")
        sec.blocks.append(b)
        if sec.kind == "local" and any(w.letter == "M" and w.value in (17, 29) for w in b.words):
            sec.ended = True

    mains = [s for s in sections if s.kind == "main"]
    if len(mains) > 1:
        s = mains[1]
        raise CutsimError(name, s.line, s.col, f"a second main program '%{s.name}' (the first is "
                          f"'%{mains[0].name}' at line {mains[0].line}); a file holds one main program")
    if mains and loose:
        raise CutsimError(name, loose[0].line, 1, "block before the first program header ('%name' or '%L name')")
    if mains:
        main = mains[0]
    elif loose:
        main = Section("main", "", 1, 1, loose)
    else:
        raise CutsimError(name, 1, 1, "no main program: the file needs a '%name' program ended by M30")
    local: dict[str, Section] = {}
    for i, s in enumerate(sections):
        if s.kind != "local":
            continue
        if s.name in local:
            first = local[s.name]
            raise CutsimError(name, s.line, s.col, f"local subprogram '{s.name}' is defined twice (first at line {first.line})")
        if not s.ended:
            nxt = sections[i + 1].line if i + 1 < len(sections) else None
            where = f"before line {nxt}" if nxt else "before the end of the file"
            raise CutsimError(name, s.line, s.col, f"local subprogram '{s.name}' is not ended: M29 (or M17) missing {where}")
        local[s.name] = s
    for b in main.blocks:
        for w in b.words:
            if w.letter == "M" and w.value in (17, 29):
                raise CutsimError(name, b.line, w.col, f"M{w.raw} ends a subprogram; the main program ends with M30")
    return main, local


def _header(name: str, lineno: int, indent: int, text: str) -> Section:
    m = HEADER.match(text)
    if not m:
        raise CutsimError(name, lineno, indent + 1, "'%' must be followed by a program name ('%name' or '%L name')")
    if m.group("local"):
        nm = m.group("lname")
        col = indent + m.start("lname") + 1
        if not NAME.fullmatch(nm):
            bad = next(c for c in nm if not NAME.match(c))
            raise CutsimError(name, lineno, col + nm.index(bad),
                              f"subprogram name '{nm}' may hold only letters, digits and '_'")
        sec = Section("local", _nfc(nm), lineno, col)
        rest = m.end()
    else:
        sec = Section("main", _nfc(m.group("mname")), lineno, indent + 2)
        rest = m.end()
    tail = text[rest:].lstrip()
    if tail.startswith("("):
        j = tail.find(")")
        if j < 0:
            raise CutsimError(name, lineno, indent + len(text) - len(tail) + 1, "program title '(' is not closed by ')'")
        tail = tail[j + 1:].lstrip()
    if tail and not tail.startswith(";"):
        raise CutsimError(name, lineno, indent + len(text) - len(tail) + 1,
                          "unexpected text after the program name (a title goes in parentheses, a comment after ';')")
    return sec


class Isg(Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig):
        super().__init__(name, cfg)
        self.lead: tuple[float, str] | None = None  # (mm per revolution, axis letter)
        self.offset = 0.0  # S.OFFSET, degrees
        self.ended = False
        self.last_block: IsgBlock | None = None

    # -- program structure -----------------------------------------------------------------------
    def run(self, text: str) -> canon.Program:
        self.main, self.local = parse(self.name, text, self.cfg.max_blocks)
        self.check_count()
        self.section(self.main, (), ())
        if not self.ended and self.last_block is not None:
            b = self.last_block
            self.warn(Src(self.name, b.line, 1, b.label), "the main program ends without M30")
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    def check_count(self) -> None:
        """Refuse before running a program whose subprogram calls would execute more than
        ``cfg.max_blocks`` blocks: calls are unconditional, so the count is known (static_counts).
        The error is at the main program's call that executes the most blocks."""
        counts = static_counts(self.main, self.local)
        if counts is None:
            return  # an unknown or recursive call: an error when it runs
        limit = self.cfg.max_blocks
        total, _ = counts[None]
        if total <= limit:
            return
        heaviest = None
        for b in self.main.blocks:
            if b.call is not None and (heaviest is None or counts[b.call[0]][0] > counts[heaviest.call[0]][0]):
                heaviest = b
            if _ends_program(b) or (b.call is not None and counts[b.call[0]][1]):
                break
        where = (1, 1) if heaviest is None else (heaviest.line, heaviest.call[1])
        what = "" if heaviest is None else (f"LL {heaviest.call[0]} executes {fmt_count(counts[heaviest.call[0]][0])} blocks "
                                             "(its subprogram calls counted): ")
        raise self.error(*where, f"{what}the program would execute {fmt_count(total)} blocks, more than the limit of "
                         f"{limit:,} set by [simulation] max_blocks")

    def section(self, sec: Section, calls: tuple, stack: tuple) -> None:
        """Execute a program body; returns at M29/M17, sets ``self.ended`` at M30/M02."""
        for b in sec.blocks:
            self.count_block(b)
            self.last_block = b
            try:
                ret = self.block(b, calls, stack)
            except CutsimError as e:
                if stack and e.line == b.line and e.program == self.name:
                    raise CutsimError(e.program, e.line, e.col,
                                      f"{e.message} (in subprogram '{stack[-1]}' called from line {calls[-1][1]})") from None
                raise
            if self.ended or ret:
                return

    def call(self, b: IsgBlock, calls: tuple, stack: tuple) -> None:
        target, col = b.call
        sec = self.local.get(target)
        if sec is None:
            msg = f"unknown subprogram '{target}'"
            wanted = _folds(target)
            near = [n for n in self.local if _folds(n) & wanted]
            if near:
                msg += f"; did you mean '{near[0]}'?"
            elif self.local:
                msg += f" (local subprograms here: {', '.join(sorted(self.local))})"
            else:
                msg += " (this file defines no local subprogram '%L name')"
            raise self.error(b.line, col, msg)
        if target in stack:
            chain = " -> ".join(stack + (target,))
            raise self.error(b.line, col, f"recursive subprogram call: {chain}")
        if len(stack) >= MAX_CALL_DEPTH:
            chain = " -> ".join(stack[:3] + ("...",) + stack[-2:] if len(stack) > 6 else stack)
            raise self.error(b.line, col, f"LL {target}: local subprograms nested more than {MAX_CALL_DEPTH} deep "
                             f"({chain} -> {target}); the limit of open subprogram calls is {MAX_CALL_DEPTH}")
        self.section(sec, calls + ((self.name, b.line),), stack + (target,))

    # -- one block (core.Interpreter.execute runs the steps in order) --------------------------------
    def block(self, b: IsgBlock, calls: tuple, stack: tuple) -> bool:
        """Execute one block; True when it returns from a subprogram."""
        src = Src(self.name, b.line, 1, b.label, calls)
        return bool(self.execute(b, src, (calls, stack)).result)

    def g_code(self, st: Step, code: int, row: Code, g: Word) -> None:
        if row.group == "diameter":  # G51/G52 act at once
            if self.cfg.machine_kind != "lathe":
                raise self.error(st.block.line, g.col, f"G{g.raw} (diameter programming) needs a lathe")
            self.set_diameter(code == 51)

    def check_m(self, st: Step, ms: list[Word]) -> None:
        super().check_m(st, ms)
        ends = self.m_group(st, "end")
        if len(ends) > 1:
            raise self.error(st.block.line, ends[1][1].col, "two program-end M codes in one block")

    def convert_settings(self, st: Step) -> None:
        b, words = st.block, st.words
        speed = st.speed = words.pop("S", None)
        if speed is not None and speed.value < 0:
            raise self.error(b.line, speed.col, "spindle speed S must not be negative")
        # M03/M04 act before the motion of their block, M05 after it.
        if st.direction != 0 and (st.direction is not None or speed is not None):
            self.spindle(st.src, st.direction, None if speed is None else speed.value)
        self.tool_words(st, lambda t: self.tool_number(b, t))

    def tool_number(self, b: IsgBlock, t: Word) -> int:
        if t.value != int(t.value) or t.value < 0:
            raise self.error(b.line, t.col, f"tool number T{t.raw} must be a whole number")
        return int(t.value)

    def convert_nonmodal(self, st: Step) -> None:
        for w in st.block.offsets:
            if not 0.0 <= w.value < 360.0:
                raise self.error(st.block.line, w.col, f"S.OFFSET={w.raw} is outside the spindle's modulo range "
                                 "(0 <= offset < 360 degrees)")
            self.offset = w.value

    def convert_feed(self, st: Step) -> None:
        if "F" in st.words:
            f = st.words.pop("F")
            if self.motion == 33:
                raise self.error(st.block.line, f.col, "F has no meaning while G33 is active: the lead is programmed "
                                 "on I, J or K (mm per revolution) and the feed follows from the spindle speed")
            if f.value <= 0:
                raise self.error(st.block.line, f.col, "feed F must be positive")
            self.feed = f.value

    def convert_motion(self, st: Step) -> None:
        b, src, words, motion = st.block, st.src, st.words, st.motion
        axis_words = {AXES.index(a): words.pop(a) for a in AXES if a in words}
        values = {i: w.value for i, w in axis_words.items()}
        cols = {i: w.col for i, w in axis_words.items()}
        centre = {a: words.pop(a) for a in "IJK" if a in words}
        if self.motion == 33:
            self.thread_block(b, src, motion, centre, values, cols)
        elif self.motion in (2, 3) and (axis_words or motion in (2, 3)):
            self.circle(b, src, centre, values, cols)
        else:
            for a, w in centre.items():
                what = f"a G0{self.motion} block" if axis_words or motion is not None else "a block without a motion"
                raise self.error(b.line, w.col, f"address {a} has no meaning in {what}")
            if axis_words:
                end = self.target(values)
                self.check_position(b.line, end, cols)
                (self.rapid if self.motion == 0 else self.linear)(src, end)

    def convert_end(self, st: Step) -> None:
        """M05, the subprogram call, then the program or subprogram end; ``st.result`` is True when
        the block returns from a subprogram (or the program ended)."""
        b, src = st.block, st.src
        calls, stack = st.context
        if st.direction == 0:
            self.spindle(src, 0, None if st.speed is None else st.speed.value)
        if b.call is not None:
            self.call(b, calls, stack)
            if self.ended:
                st.result = True
                return
        ends = self.m_group(st, "end")
        if ends and self.M_CODES[ends[0][0]].meaning == "program end":
            self.end(src)
            self.ended = True
            st.result = True
        elif ends:
            if not stack:  # parse() rejects M29 in the main program; kept for safety
                raise self.error(b.line, ends[0][1].col, f"M{ends[0][1].raw} outside a subprogram")
            st.result = True

    # -- G33 -------------------------------------------------------------------------------------
    def thread_block(self, b: IsgBlock, src: Src, motion, leads: dict[str, Word], values: dict[int, float],
                     cols: dict[int, int]) -> None:
        if len(leads) > 1:
            a, w = list(leads.items())[1]
            raise self.error(b.line, w.col, f"two leads ({' and '.join(leads)}) in one G33 block: "
                             "program the lead on one of I, J, K")
        for a, w in leads.items():
            if w.raw.lstrip("+").startswith(("-", "\u2212")):
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} is programmed without a sign")
            if w.value == 0:
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} must not be zero when G33 is selected")
            if w.value < MIN_LEAD:
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} is below the programming resolution, "
                                 f"{MIN_LEAD} mm per revolution")
            self.lead = (w.value, LEADS[a])
        if self.lead is None:
            col = b.words[0].col if b.words else 1
            for w in b.words:
                if w.letter == "G" and w.value == 33:
                    col = w.col
            raise self.error(b.line, col, "G33 without a lead: program it without sign on I, J or K "
                             "(mm per revolution along X, Y or Z), e.g. 'G33 Z48 K1.5'")
        if not values:
            return  # G33 (and the lead) selected, no motion in this block
        end = self.target(values)
        self.check_position(b.line, end, cols)
        lead, axis = self.lead
        self.synced(src, end, lead, axis, self.offset)

    # -- circles ---------------------------------------------------------------------------------
    def circle(self, b: IsgBlock, src: Src, words: dict[str, Word], values: dict[int, float],
               cols: dict[int, int]) -> None:
        centre = self.centre_words(b.line, words, ", relative to the start")
        end = self.target(values)
        self.check_position(b.line, end, cols)
        self.arc(src, end, centre, self.motion == 2)


def _ends_program(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (2, 30) for w in b.words)


def _ends_sub(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (17, 29) for w in b.words)


def static_counts(main: Section, local: dict[str, Section]) -> dict | None:
    """Blocks each body executes, its calls included, without running it: name (None for the
    main program) -> (count, whether it ends the program with M30/M02). Calls are unconditional,
    so one count per subprogram holds for every call. Worked out by an explicit depth-first walk
    (no recursion: a chain of calls may be as long as the file). None when a call names an
    unknown subprogram or is recursive (errors when they run)."""
    counts: dict = {}
    bodies = {None: main, **local}
    stack = [[None, 0, 0]]  # frames: [name, next block index, blocks so far]
    open_names = {None}
    while stack:
        frame = stack[-1]
        name, k, total = frame
        blocks = bodies[name].blocks
        pushed = ended = False
        while k < len(blocks):
            b = blocks[k]
            callee = b.call[0] if b.call is not None else None
            if callee is not None:
                if callee not in local or callee in open_names:
                    return None
                if callee not in counts:  # count it first, then come back to this block
                    frame[1], frame[2] = k, total
                    stack.append([callee, 0, 0])
                    open_names.add(callee)
                    pushed = True
                    break
            total += 1 + (counts[callee][0] if callee is not None else 0)
            k += 1
            if _ends_program(b) or (callee is not None and counts[callee][1]):
                ended = True
                break
            if name is not None and _ends_sub(b):
                break
        if pushed:
            continue
        counts[name] = (total, ended)
        stack.pop()
        open_names.discard(name)
    return counts


def interpret(name: str, text: str, cfg: InterpConfig) -> canon.Program:
    return Isg(name, cfg).run(text)
