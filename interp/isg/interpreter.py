"""The ISG interpreter on the core executor: the run of a file, one block through
core.Interpreter.execute and its hooks (words with expressions, the G/M tables, settings, ends).
The concerns are parts of Isg, each with its state: variables, flow, frames, compensation, calls,
motion, # commands and the plain-block path."""
from __future__ import annotations

from .calls import Calls, Level
from .commands import Commands
from .compensation import Compensation
from .fast import PlainPath, read_plain
from .flow import Flow
from .frames import Frames
from .motion import Motion
from .program import parse
from .reader import IsgBlock, LIMITS
from .tables import (G_AXIS_PARAMS, G_CODES, G_HARMLESS, G_LATHE_NOT_MODELLED, G_NOT_MODELLED, IMPLICIT_CALLS, MIRRORS,
                     M_CODES, TRC_METHODS)
from .variables import Variables
from .. import canon
from ..canon import Src
from ..core import Code, Group, Interpreter, Step
from ..core.lexer import COORD_LIMIT, Word, check_range
from ..core.modal import AXES, InterpConfig

_NOT_EXTRA = frozenset("DEFGHIJKLMNOPQRSTXYZ")  # letters Isg.extra_axes leaves alone


class Isg(Motion, Calls, Compensation, Frames, Flow, Variables, Commands, PlainPath, Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig):
        super().__init__(name, cfg)
        self.warned: set = set()  # warn_once keys
        self.macros: dict[str, str] = {}  # "name" = "text" definitions read so far
        self.extra_pos: dict[str, float] = {a: 0.0 for a in cfg.axes}  # rotary and extra linear axes

    def warn_once(self, key, src: Src, message: str) -> None:
        if key not in self.warned:
            self.warned.add(key)
            self.warn(src, message)

    def run(self, text: str) -> canon.Program:
        self.macros: dict[str, str] = {}
        main, local = parse(self.name, text, self.cfg.max_blocks, self.macros, read_plain)
        self.check_count(main, local)
        self.level = Level(self.name, local, {}, (), ())
        self.declare(main)
        if main.title:
            t = main.title if len(main.title) <= 60 else main.title[:57] + "..."
            self.warn(Src(self.name, main.line, main.col), f"the text after the program name '%{main.name}' "
                      f"('{t}') is taken as the program's title (write a title in parentheses)")
        for other in main.others:
            self.warn(Src(self.name, other.line, other.col), f"a further main program '%{other.name}' in this file "
                      f"is not run (the file runs its first main program, '%{main.name}')")
        self.section(main)
        if self.comp_buf is not None:
            self.flush_comp(departure=False)
        if not self.ended and self.last_block is not None:
            b = self.last_block
            self.warn(Src(self.name, b.line, 1, getattr(b, "label", "")), "the main program ends without M30")
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    def block(self, b: IsgBlock, fr: Level) -> bool:
        """Execute one block; True when it returns from a subprogram."""
        src = Src(self.name, b.line, 1, b.label, fr.calls)
        if self.plain_block(b, src, fr):  # the common G00/G01 block the short way (fast.py)
            return False
        return bool(self.execute(b, src, fr).result)

    def read_words(self, b: IsgBlock) -> list[Word]:
        """Assignments and words in their order: an expression sees the assignments before it."""
        if len(b.items) == len(b.words):
            return b.words
        out = []
        for it in b.items:
            if it[0] == "w":
                out.append(it[1])
            elif it[0] == "x":
                _, letter, f, raw, col = it
                v = f(self)
                if isinstance(v, str):
                    raise self.error(b.line, col, f"{letter}{raw} is the string \"{v}\", not a number")
                lim, unit = LIMITS.get(letter, (COORD_LIMIT, "mm"))
                check_range(self.name, b.line, col, f"{letter}{raw} = {v:g}", v, -lim, lim, unit)
                out.append(Word(letter, v, f"{v:g}", col))
            else:
                _, target, f, col = it
                self.assign(target, f, b.line, col)
        return out

    def check_g(self, st: Step, gs: list[Word]) -> None:
        """The dialect's G table; G codes that only get a warning; implicit subroutine calls (G80..G89,
        G800..G819); the rest are errors naming the code."""
        line = st.block.line
        keep = []
        for g in gs:
            code = int(g.value) if g.value == int(g.value) else None
            if code is None:
                raise self.error(line, g.col, f"unknown G code G{g.raw}")
            if code in TRC_METHODS:
                if code == 5:
                    st.g[Group.TRC_SELECTION] = g  # G5 tangential: non-modal, this block only
                else:
                    self.trc_method = (code, g)
                continue
            if code in G_LATHE_NOT_MODELLED and self.cfg.machine_kind == "lathe":
                raise self.error(line, g.col, f"G{g.raw} on a lathe ({G_LATHE_NOT_MODELLED[code]}) is not modelled "
                                 "by the simulator")
            if code in G_HARMLESS:
                self.warn_once(("G", code), st.src, f"G{g.raw} ({G_HARMLESS[code]}) does not change the tool path: "
                               "accepted, not simulated")
                if g.col in st.block.gvalues:
                    st.block.gvalues[g.col](self)  # its value is read (errors in it are errors), not used
                for f in st.block.args.get(g.col, ()):
                    f(self)
                if code in G_AXIS_PARAMS:
                    for a in "XYZABCUVWF" + ("SK" if code == 4 else ""):
                        st.words.pop(a, None)
                continue
            if code == 80 and self.g80_plain(g, st.block):
                self.warn_once(("G", 80), st.src, "G80 (modal cycle off) does not change the tool path: accepted")
                continue
            if code in IMPLICIT_CALLS:
                if st.result is not None:
                    raise self.error(line, g.col, "two implicit subroutine calls in one block")
                st.result = ("implicit", code, g)
                continue
            if code in self.G_CODES:
                if g.col in st.block.args:
                    raise self.error(line, g.col, f"G{g.raw} takes no argument list '[...]'")
                if g.col in st.block.gvalues:
                    raise self.error(line, g.col, f"G{g.raw} takes no value '= ...'")
                keep.append(g)
                continue
            if code in G_NOT_MODELLED:
                raise self.error(line, g.col, f"G{g.raw} ({G_NOT_MODELLED[code]}) is not modelled by the simulator "
                                 "(exit rather than a wrong tool path)")
            raise self.error(line, g.col, f"unknown G code G{g.raw}")
        super().check_g(st, keep)

    def g_code(self, st: Step, code: int, row: Code, g: Word) -> None:
        line = st.block.line
        if row.group is Group.DIAMETER:  # G51/G52 act at once
            if self.cfg.machine_kind != "lathe":
                raise self.error(line, g.col, f"G{g.raw} (diameter programming) needs a lathe")
            self.set_diameter(code == 51)
        elif row.group is Group.ZERO_OFFSET:
            self.zero_offset(st, code, g)
        elif row.group is Group.TRC_TRANSITION:
            self.trc_linear = code == 25
        elif row.group is Group.TRC_SELECTION:
            self.trc_method = (code, g)
        elif row.group is Group.CENTRE:
            self.centre_abs = code == 161
        elif row.group is Group.MIRROR:
            self.mirror[0], self.mirror[1] = MIRRORS[code]
            self.frame_changed(line, g.col)
            if code != 20:
                self.warn_once(("G", code), st.src, f"G{g.raw} mirrors the program ({row.meaning}; on this controller "
                               "it is not the millimetre input of other controls)")
        elif code == 69:
            self.rotation = None
            self.frame_changed(line, g.col)
        elif row.group is Group.UNITS:
            if code == 70:
                raise self.error(line, g.col, "G70 (inch programming) is not modelled: the simulator works in millimetres")
        else:  # G41/G42/G40, G351, G68, G92: act in convert_nonmodal / convert_motion
            st.g[row.group] = g

    def check_m(self, st: Step, ms: list[Word]) -> None:
        keep = []
        for m in ms:
            code = int(m.value) if m.value == int(m.value) else None
            if code in self.M_CODES:
                if m.col in st.block.gvalues:
                    raise self.error(st.block.line, m.col, f"M{m.raw} takes no value '= ...'")
                keep.append(m)
            elif code is not None and code in self.cfg.m_functions:
                continue  # a machine function the setup declares: no geometric effect
            else:
                raise self.error(st.block.line, m.col, f"unknown M code M{m.raw}: not an ISG M function and not declared "
                                 f"as a machine function (declare it in the setup: [machine] m_functions = [{m.raw}])")
        super().check_m(st, keep)
        ends = self.m_group(st, Group.END)
        if len(ends) > 1:
            raise self.error(st.block.line, ends[1][1].col, "two program-end M codes in one block")

    def convert_settings(self, st: Step) -> None:
        b, words = st.block, st.words
        for w in [w for w in b.words if w.letter == "H"]:
            if w.value != int(w.value) or int(w.value) not in self.cfg.h_functions:
                raise self.error(b.line, w.col, f"H{w.raw} is not a machine function the setup declares "
                                 f"([machine] h_functions = [{w.raw}])")
        words.pop("H", None)
        if "D" in words:
            self.d_zero = words["D"].value == 0
        speed = st.speed = words.pop("S", None)
        if speed is not None and speed.value < 0:
            raise self.error(b.line, speed.col, "spindle speed S must not be negative")
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
        for name, text, col in st.block.commands:
            self.command(st, name, text, col)
        if Group.REFERENCE in st.g:
            self.set_position(st)
        if Group.MIRROR_AXES in st.g:
            self.mirror_axes(st, st.g[Group.MIRROR_AXES])
        if Group.ROTATION in st.g:
            self.g68(st, st.g[Group.ROTATION])

    def set_position(self, st: Step) -> None:
        """G92 X.. Y.. Z..: the reference point offset (an additive zero offset) of the axes given, set
        under G90 and added under G91 (manual: "Reference point offset (G92)"); G92 X0 resets it."""
        for i, a in enumerate(AXES):
            w = st.words.pop(a, None)
            if w is not None:
                self.g92[i] = w.value if self.absolute else self.g92[i] + w.value

    def convert_feed(self, st: Step) -> None:
        if "F" in st.words:
            f = st.words.pop("F")
            if self.motion == 33:
                raise self.error(st.block.line, f.col, "F has no meaning while G33 is active: the lead is programmed "
                                 "on I, J or K (mm per revolution) and the feed follows from the spindle speed")
            if f.value <= 0:
                raise self.error(st.block.line, f.col, "feed F must be positive")
            self.feed = f.value

    def extra_axes(self, st: Step) -> None:
        if st.words.keys() <= _NOT_EXTRA:  # no A B C U V W nor a named axis: nothing to do
            return
        for a in sorted(k for k in st.words if k in "ABCUVW" or len(k) > 1):
            w = st.words.pop(a)
            if a not in self.cfg.axes:
                raise self.error(st.block.line, w.col, f"axis {a} is not on this machine (declare it in the setup: "
                                 f"[machine] axes = {{ {a} = \"rotary\" }})")
            new = w.value if self.absolute else self.extra_pos[a] + w.value
            if new != self.extra_pos[a]:
                self.warn_once(("axis", a), st.src, f"axis {a} ({self.cfg.axes[a]}) moves: tracked, but it does not "
                               "move the tool or the workpiece in this 3-axis simulation")
            self.extra_pos[a] = new

    def convert_end(self, st: Step) -> None:
        """M05, the subprogram call, then the program or subprogram end; ``st.result`` is True when
        the block returns from a subprogram (or the program ended)."""
        b, src, fr = st.block, st.src, st.context
        if st.direction == 0:
            self.spindle(src, 0, None if st.speed is None else st.speed.value)
        implicit = st.result
        st.result = None
        if b.call is not None:
            self.call_local(b, fr)
        elif b.gcall is not None:
            self.call_global(b, fr)
        if implicit is not None and not self.ended:
            self.call_implicit(b, fr, implicit[1], implicit[2])
        if self.ended:
            st.result = True
            return
        ends = self.m_group(st, Group.END)
        if ends and self.M_CODES[ends[0][0]].meaning == "program end":
            self.end(src)
            self.ended = True
            st.result = True
        elif ends:
            if not fr.stack:  # a subprogram file run as the program: its end is the program's end
                self.warn(src, f"M{ends[0][1].raw} ends a subprogram: the program (run as a main program) ends here")
                self.end(src)
                self.ended = True
            st.result = True


def interpret(name: str, text: str, cfg: InterpConfig) -> canon.Program:
    return Isg(name, cfg).run(text)
