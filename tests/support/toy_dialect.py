"""A toy dialect: the smallest complete one, to prove that a dialect is one module (or subpackage)
plus one registry entry (tests/interp/core/test_dialect_registry.py registers it; docs/architecture.md, "How to
add a dialect").

Blocks are words ``<letter><number>`` separated by blanks, ``;`` starts a comment. G0/G1 move, G2/G3
cut arcs with the centre on I/K (incremental), G90/G91 switch the distance mode; M3/M4/M5 drive the
spindle, M30 ends the program; S, F, T and D as on every controller.
"""
from __future__ import annotations

from cutsim.interp.canon import Program, Src
from cutsim.interp.core import Code, Group, Interpreter, Step
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.lexer import COORD_LIMIT, Block, Word, iter_lines, parse_number
from cutsim.interp.core.modal import AXES, InterpConfig

G_CODES = {
    0: Code(Group.MOTION, "XYZ", "rapid"),
    1: Code(Group.MOTION, "XYZF", "linear feed"),
    2: Code(Group.MOTION, "XYZIJKF", "clockwise arc"),
    3: Code(Group.MOTION, "XYZIJKF", "counter-clockwise arc"),
    90: Code(Group.DISTANCE, "", "absolute"),
    91: Code(Group.DISTANCE, "", "incremental"),
}
M_CODES = {
    3: Code(Group.SPINDLE, "S", "spindle clockwise"),
    4: Code(Group.SPINDLE, "S", "spindle counter-clockwise"),
    5: Code(Group.SPINDLE, "", "spindle stop"),
    30: Code(Group.END, "", "program end"),
}


def scan(name: str, lineno: int, text: str) -> Block | None:
    block = Block(line=lineno, col=1)
    i = 0
    while i < len(text):
        c = text[i]
        if c.isspace():
            i += 1
            continue
        if c == ";":
            break
        if not (c.isascii() and c.isalpha()) or c.upper() not in "GMXYZIJKFSTD":
            raise CutsimError(name, lineno, i + 1, f"unexpected character '{c}'")
        value, raw, j = parse_number(name, lineno, text, i + 1, c.upper(), COORD_LIMIT)
        block.words.append(Word(c.upper(), value, raw, i + 1))
        i = j
    return block if block.words else None


class Toy(Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def convert_settings(self, st: Step) -> None:
        speed = st.words.pop("S", None)
        if st.direction is not None or speed is not None:
            self.spindle(st.src, st.direction, None if speed is None else speed.value)
        self.tool_words(st, lambda t: self.whole(st.block.line, t, "tool number"))

    def convert_feed(self, st: Step) -> None:
        if "F" in st.words:
            self.feed = st.words.pop("F").value

    def convert_motion(self, st: Step) -> None:
        b, words = st.block, st.words
        axis_words = {AXES.index(a): words.pop(a) for a in AXES if a in words}
        end = self.target({i: w.value for i, w in axis_words.items()})
        self.check_position(b.line, end, {i: w.col for i, w in axis_words.items()})
        if self.motion in (2, 3) and axis_words:
            self.arc(st.src, end, self.centre_words(b.line, words), self.motion == 2)
        elif axis_words:
            (self.rapid if self.motion == 0 else self.linear)(st.src, end)

    def convert_end(self, st: Step) -> None:
        st.result = bool(self.m_group(st, Group.END))
        if st.result:
            self.end(st.src)

    def run(self, text: str) -> Program:
        for lineno, line in iter_lines(text):
            b = scan(self.name, lineno, line)
            if b is None:
                continue
            self.count_block(b)
            if self.execute(b, Src(self.name, b.line, 1)).result:
                break
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program


def interpret(name: str, text: str, cfg: InterpConfig) -> Program:
    return Toy(name, cfg).run(text)
