"""The CNC8x6 interpreter on the core executor: the run loops (streamed without G73, else over the
program's blocks with its jumps), R parameters, the helix (G09/G10/G98) and the hooks of
core.Interpreter.execute."""
from __future__ import annotations

from .. import canon
from ..canon import Src
from ..core import Group, Interpreter, Step, sweep_degrees
from ..core.lexer import Block, Word, check_length, check_range, iter_lines
from ..core.modal import AXES, InterpConfig
from ..errors import CutsimError
from .language import BLOCK_LINES, G_CODES, JUMP, LIMITS, M_CODES, NOT_DESCRIBED, RESERVED_PARAMS, parse, scan
from .loops import loops_error, running_loops_error
from .plain import PlainPath
from .threads import Threads


class Cnc8x6(PlainPath, Threads, Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig):
        super().__init__(name, cfg)
        self.params: dict[int, float] = dict(cfg.parameters)
        self.helix_on = False
        self.helix_pitch: float | None = None
        self.helix_axis = "Z"  # the axis G10 set the pitch on
        self.blocks: list[Block] = []  # run_blocks: the program's blocks (stream keeps none)
        self.loops: dict[int, int] = {}  # run_blocks: G73 block index -> repeats still to do

    def check_g(self, st: Step, gs: list[Word]) -> None:
        """The core's check, after naming the codes of other controls the manual does not describe."""
        for g in gs:
            if g.value == int(g.value) and int(g.value) in NOT_DESCRIBED:
                raise self.error(st.block.line, g.col, f"G{g.raw} ({NOT_DESCRIBED[int(g.value)]}) is not modelled by "
                                 "the simulator")
        super().check_g(st, gs)

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
            self.ramp_unfinished()
        return self.finish()

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
            self.ramp_unfinished()
        return self.finish()

    def finish(self) -> canon.Program:
        """The program as run: its block count and where the tool ended."""
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    # -- G73 loop counts ---------------------------------------------------------------------------
    def check_loops(self, blocks: list[Block], labels: dict[int, int]) -> None:
        """Refuse, before running, a program whose G73 loops would execute more than
        ``cfg.max_blocks`` blocks (loops.loops_error)."""
        found = loops_error(blocks, labels, self.cfg.max_blocks)
        if found is not None:
            raise self.error(*found)

    def block_limit(self, b: Block):
        """The runtime guard (loops the static count cannot see: L or Q from a parameter). Points at
        the outermost active G73."""
        found = running_loops_error(self.blocks, list(self.loops), self.cfg.max_blocks)
        if found is None:
            return self.error(b.line, b.col, f"the program executes more than the limit of {self.cfg.max_blocks:,} "
                              "blocks set by [simulation] max_blocks")
        return self.error(*found)

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
                self.check_words(b.line, words, "IJKEQL", self.motion)
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


def interpret(name: str, text: str, cfg: InterpConfig) -> canon.Program:
    return Cnc8x6(name, cfg).run(text)
