"""A block's words and commands: addresses, modal G codes and their groups, settings, tools and
compensation on, language calls and notes.
"""
from __future__ import annotations

from ..canon import Src
from ..core import Group, Step
from . import axes, lathe, machine
from .codes import G_CODES, LANGUAGE_GROUPS, M_CODES, takes
from .syntax import Call, Command, Line, MACHINE_COMMANDS, range_message, RANGES, Word
from .cycle import CYCLES
from .tables import NOTES, UNSUPPORTED_MEANINGS
from .values import Block, to_text, Value


class Words:
    """A block's words and commands: addresses, modal G codes and their groups, settings, tools and
    compensation on, language calls and notes.

    A part of ``Sinumerik`` (interpreter.py): its methods work on the state declared in
    ``Sinumerik.__init__``."""

    def axis_word(self, st: Word, ln: Line, blk: Block) -> None:
        """AX[axis]=value: the word of the axis the AXIS expression names (an axis name, an AXIS
        variable, AXNAME(..), SPI(..): interp/sinumerik/axes.py); an axis the machine does not have
        is an error at the word. A spindle (AX[SPI(1)]=90) is positioned: one warning, as SPOS."""
        if st.axis is None:
            raise self.error(ln.line, st.col, "AX[..] takes one axis name")
        name = axes.axis_of(self, st.axis, ln.line, st.col)
        if axes.spindle_number(name) is not None:
            self.ev(st.value, ln.line, st.col)
            self.note(Src(self.unit_program, ln.line, st.col, ln.nlabel or ln.label), "SPOS",
                      f"AX[{name}]= positions spindle {name[1:]}: changes nothing on the tool path")
            return
        self.word(Word(st.col, name, st.value, st.mode), ln.line, blk)

    def command(self, st: Command, ln: Line, blk: Block) -> None:
        """A bare keyword: language commands without effect on the tool path get one warning per
        kind; machine commands go on to ``settings`` through ``Block.commands``."""
        if st.name in MACHINE_COMMANDS:
            blk.commands.append((st.name, st.col))
            return
        if st.name == "EXTERN":
            return  # a declaration: the call finds the subprogram by itself
        if st.name == "SETMS":  # SETMS alone: the master spindle of the machine data again (spindle 1)
            self.machine.master = 1
            return
        what = NOTES.get(st.name, "changes nothing on the tool path")
        self.note(Src(self.unit_program, ln.line, st.col, ln.nlabel or ln.label), st.name, f"{st.name} {what}")

    def note(self, src: Src, kind: str, message: str) -> None:
        if kind not in self.warned:
            self.warned.add(kind)
            self.warn(src, message + " (warned once)")

    def lang_call(self, st: Call, ln: Line) -> None:
        """MSG(..), SETAL(..), FGROUP(..), ... : their arguments are evaluated (errors count); SETAL
        raises the alarm it names: the program stops there (exit 2)."""
        line = ln.line
        vals = [None if a.value is None else self.ev(a.value, line, a.col) for a in st.args] \
            if st.name in ("MSG", "SETAL", "SETMS") else []  # FGROUP(X, Y) & co. take axis names, not values
        if st.name == "SETMS":
            self.master_spindle(st, vals, line)
            return
        if st.name == "SETAL":
            raise self.error(line, st.col, f"SETAL({', '.join(to_text(v) for v in vals if v is not None)}): the "
                             "program raises an alarm here and the controller stops it")
        src = Src(self.unit_program, line, st.col, ln.nlabel or ln.label)
        text = f" \"{vals[0]}\"" if st.name == "MSG" and vals and isinstance(vals[0], str) else ""
        self.note(src, st.name, f"{st.name}{text} {NOTES.get(st.name, 'changes nothing on the tool path')}")

    def master_spindle(self, st: Call, vals: list, line: int) -> None:
        """SETMS(n): spindle n is the master spindle from now on (S, M3/M4/M5 and Sn=/Mn= of it drive
        the simulated spindle); SETMS() / SETMS alone: spindle 1 again."""
        if len(vals) > 1:
            raise self.error(line, st.args[1].col, "SETMS takes one spindle number")
        n = 1.0 if not vals or vals[0] is None else self.num(vals[0], line, st.args[0].col)
        if n != int(n) or not 1 <= n <= 99:
            raise self.error(line, st.args[0].col, f"SETMS({n:.10g}): a spindle number is a whole number from 1 to 99")
        self.machine.master = int(n)

    def dwell(self, blk: Block, line: int) -> None:
        """G4 F<seconds> / G4 S<spindle revolutions>: a dwell, alone in its block with its F or S;
        the tool stands still (the modal feed and speed stay as they were)."""
        col = next(c for code, c in blk.gs if code == 4)
        times = [blk.words.pop(a) for a in G_CODES[4].words.split() if a in blk.words]  # F, S
        if len(times) != 1:
            raise self.error(line, col, "G4 needs its dwell time: G4 F<seconds> or G4 S<revolutions>")
        moving = [a for a in blk.words if takes(2, a)]  # the words of a move: X Y Z and a circle's I J K CR
        if moving:
            raise self.error(line, blk.words[moving[0]].col, "G4 (dwell) stands in a block without motion")
        blk.gs = [(code, c) for code, c in blk.gs if code != 4]

    def speed_limit(self, blk: Block, ln: Line) -> None:
        """G25 S<rpm> / G26 S<rpm>: the lower / upper spindle speed limit from now on (FUN,
        "Programmable spindle speed limitation"): every S is held within them, and the G96 speed
        below the lower of G26 and LIMS (interp/sinumerik/lathe.py). With axis values instead the
        block is the working area limitation, a supervision: one warning, no motion."""
        line, ms = ln.line, self.machine
        code, col = next((c, k) for c, k in blk.gs if c in (25, 26))
        other = next((k for c, k in blk.gs if c in (25, 26) and c != code), None)
        if other is not None:
            raise self.error(line, other, "G25 and G26 stand in blocks of their own")
        blk.gs = [(c, k) for c, k in blk.gs if c not in (25, 26)]
        src = Src(self.unit_program, line, col, ln.nlabel or ln.label)
        axes_given = [a for a in list(blk.words) if a in ("X", "Y", "Z") or a in self.cfg.axes]
        for a in axes_given:
            blk.words.pop(a)
        if axes_given:
            self.note(src, "WALIM", f"G{code} {' '.join(axes_given)}: the working area limitation (a supervision "
                      "of the axes) is not checked by the simulator; the block does not move")
        s = blk.words.pop("S", None)
        if s is None:
            if not axes_given:
                raise self.error(line, col, f"G{code} needs S<rpm> (the spindle speed limit) or axis values "
                                 "(the working area limitation)")
            return
        if code == 26 and s.value <= 0:
            raise self.error(line, s.col, f"G26 S{s.value:g}: the upper spindle speed limit is greater than 0")
        lo, hi = (s.value, ms.speed_max) if code == 25 else (ms.speed_min, s.value)
        if lo > 0 and hi > 0 and lo > hi:
            raise self.error(line, s.col, f"G{code} S{s.value:g}: the lower spindle speed limit G25 S{lo:g} lies above "
                             f"the upper G26 S{hi:g}")
        ms.speed_min, ms.speed_max = lo, hi
        self.speed_limit_act(src)

    def speed_limit_act(self, src: Src) -> None:
        """A new limit acts on the spindle at once (the cycle time): the G96 speed under its new
        limit, a running speed outside the limits held at the limit."""
        lt = self.machine.lathe
        if lt.css_on and lt.css > 0:
            self.spindle(src, None, None)
        elif self.speed > 0 and lathe.limited_speed(self.machine, self.speed) != self.speed:
            self.spindle(src, None, self.speed)

    def word(self, st: Word, line: int, blk: Block) -> None:
        val = self.ev(st.value, line, st.col)
        if machine.word(self, st, val, line, blk):  # extra axes, T="name", M1=3, machine M functions (machine)
            return
        if st.address in ("G", "M"):
            v = self.num(val, line, st.col)
            known = G_CODES if st.address == "G" else M_CODES
            if v != int(v) or int(v) not in known:
                raise self.error(line, st.col, f"unknown {st.address} code {st.address}{v:g}")
            (blk.gs if st.address == "G" else blk.ms).append((int(v), st.col))
            return
        if st.address in blk.words:
            raise self.error(line, st.col, f"address {st.address} appears twice in one block")
        v = self.num(val, line, st.col)
        lo, hi, unit = RANGES[st.address]
        if not lo <= v <= hi:
            raise self.error(line, st.col, range_message(st.address, v, lo, hi, unit))
        blk.words[st.address] = Value(v, st.mode, st.col)

    def check_groups(self, gs: list[tuple[int, int]], line: int) -> None:
        """Two different G codes of one of the language's modal groups (codes.LANGUAGE_GROUPS: G0 G1,
        G90 G91, G17 G18) in a block are an error at the second; the same code twice is harmless.
        (The machine side checks units and zero offsets, the ISO shell its drilling codes.)"""
        if len(gs) < 2:
            return  # (most blocks)
        seen: dict[Group, int] = {}
        for code, col in gs:
            group = G_CODES[code].group
            if group not in LANGUAGE_GROUPS:
                continue
            if group in seen and seen[group] != code:
                name = group.value
                raise self.error(line, col, f"G{code} conflicts with G{seen[group]} in the same block (both {name})")
            seen[group] = code

    def convert_settings(self, st: Step) -> None:
        """The executor's hook (core.Interpreter.execute): the machine keywords, then spindle and
        tool (T, D, M6; on a lathe T alone changes the tool, as a turret's T does)."""
        src, blk = st.src, st.block
        machine.settings(self, src, blk, CYCLES)  # frames, TRAORI, CYCLE800, F under G700 (machine)
        line, words = src.line, blk.words
        direction = self.spindle_code(line, blk.ms)
        if "S" in words:
            self.spindle(src, direction, words.pop("S").value)
        elif direction is not None:
            self.spindle(src, direction, None)
        turret = "T" in words and self.cfg.machine_kind == "lathe"  # a lathe's T changes the tool at once
        if "T" in words:
            t = words.pop("T")
            if t.value != int(t.value):
                raise self.error(line, t.col, "T must be a whole tool number")
            self.tool_pre = int(t.value)
        if "D" in words:
            d = words.pop("D")
            if d.value != int(d.value):
                raise self.error(line, d.col, "D must be a whole offset number")
            self.d_no = int(d.value)
        if turret or any(code == 6 for code, _ in blk.ms):
            self.change_tool(src)

    def change_tool(self, src: Src) -> None:
        if machine.change_tool(self, src):  # T0 M6 empties the spindle (machine)
            return
        if self.tool_pre is None:
            raise self.error(src.line, 1, "M6 without a tool: program T<number> first")
        if self.cfg.tool_radii and self.tool_pre not in self.cfg.tool_radii:
            known = ", ".join(f"T{n}" for n in sorted(self.cfg.tool_radii))
            raise self.error(src.line, 1, f"tool T{self.tool_pre} is not in the setup (tools: {known})")
        self.tool_no = self.tool_pre
        self.tool(src, self.tool_pre, self.d_no)

    def comp_on(self, new_comp: int | None, src: Src, line: int) -> None:
        """G41/G42 switched on: start buffering before the approach move."""
        if new_comp not in (41, 42):
            return
        if self.comp_buf is not None and self.comp != new_comp:
            self.flush_comp(None, line)
        if self.comp_buf is None:
            if self.tool_radius() <= 0:
                self.warn(src, f"G{new_comp} with tool radius 0 (no tool radius known for D{self.d_no}): "
                          "the path is not offset")
            self.comp = new_comp
            self.comp_buf = []
            self.comp_src = src

    def unsupported(self, blk: Block, line: int) -> None:
        """A machine keyword ``settings`` did not take (it implements the ones it knows) is an
        error at its column: running on as if it were not there would cut elsewhere."""
        for name, col in blk.commands:
            what = f" ({UNSUPPORTED_MEANINGS[name]})" if name in UNSUPPORTED_MEANINGS else ""
            raise self.error(line, col, f"{name}{what} is not supported by the simulator")
