"""Siemens Sinumerik 840D dialect, milling subset (spec/sinumerik.md), on the core executor.

Blocks are read once into the typed syntax tree of interp/sinumerik/syntax.py (statements and
expressions as dataclasses); expressions are evaluated when the block runs. A block runs through
``core.Interpreter.execute`` with the G and M tables of codes.py: ``read_words`` evaluates its
assignments, DEFs and words in order; ``check_g`` the modal G codes (the machine side's units,
zero offsets and path modes, then the motion, plane, distance and feed modes, the compensation
and the ISO drilling codes); ``convert_settings`` spindle and tool; ``convert_feed`` F;
``convert_motion`` the compensation changes and the move (with its chamfer or rounding, or the
hole of an ISO cycle); ``convert_end`` MCALL, cycles and subprogram calls, jumps and the program
end. Plain G0/G1 blocks take the short way of fast.py. Cycles (SLOT1, POCKET1, CYCLE72, ...)
expand in milling.py, contour.py and drilling.py into ordinary moves through the ModalMachine
methods. Tool radius compensation (G41/G42) buffers the compensated moves and offsets them at G40.

The class is split by concern into parts on one declared state (``Sinumerik.__init__``):
values.py (expressions and variables), flow.py (jumps, CASE, REPEAT, the loop guard), calls.py
(subprograms), words.py (a block's words, G code groups, settings); this module runs blocks and
moves. Imports flow one way: interpreter -> parts -> tables -> drilling -> milling, machine ->
codes, syntax; tables.py registers the drilling cycles into the cycles' tables; this module hands
``run_cycle`` and the cycle names to the machine side's hooks.

What the simulator assumes where Siemens' manuals are silent: docs/dialects/sinumerik.md.
"""
from __future__ import annotations


from .. import canon
from ..canon import Src
from ..core import arc_centre, CENTRE_WORDS, Group, Interpreter, Step
from ..core.geometry import FullCircle, radius_centre, RadiusTooSmall
from ..core.compensation import compensate_records
from ..errors import CutsimError
from ..core.modal import InterpConfig, PLANE_AXES
from . import corners as corner, drilling as drill, fast as sinumerik_fast, lathe, machine, turning
from .codes import G_CODES, M_CODES, takes
from .calls import Calls
from .flow import Flow
from .syntax import (Assign, Branch, Call, Case, Command, COORD_LIMIT, Def, Frame, Goto, Line, range_message, Repeat,
    Ret, SubCall, Unit, Word)
from .reader import split_units
from .milling import run_cycle
from .tables import call_name, LANG_CALLS
from .values import Block, Slot, Value, Values
from .words import Words

CR_SLACK = 1e-6  # how much the chord of a CR= circle may exceed its diameter (mm)


class Sinumerik(Values, Flow, Calls, Words, Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig):
        super().__init__(name, cfg)
        self.params: dict[str, float] = {f"R{k}": float(v) for k, v in cfg.parameters.items()}
        self.vars: dict[str, object] = {}
        self.motion = 0
        self.tool_pre: int | None = None
        radii = cfg.tool_radii or {}
        self.tool_no: int | None = next(iter(radii), None)
        self.d_no = 1
        self.comp = 40  # G40/G41/G42
        self.comp_buf: list | None = None
        self.comp_src: Src | None = None
        self.executed = 0
        self.loop_hashes: set[int] = set()  # control states at backward jumps (check_loop)
        self.loop_states: dict[int, tuple] = {}
        self.unit_program = name  # the file of the line being executed (subprograms from NAME.spf)
        self.main: Unit | None = None
        self.subs: dict[str, Unit] = {}
        self.cfg_vars = {str(k).upper().replace(" ", ""): v for k, v in cfg.variables.items()}
        self.cfg_names = {k.partition("[")[0] for k in self.cfg_vars}  # names given in [variables]
        self.sysvars: dict[str, Slot] = {}  # system variables and setup data read or written so far
        self.warned: set[str] = set()  # command kinds warned about (one warning each)
        # the setup's [machine] external_subprograms, by the name a call uses (call_name)
        self.externals = frozenset(call_name(n) for n in cfg.external_subprograms)
        self.corners = corner.Corners()  # chamfers and roundings: RNDM, FRCM, the held move (corners)
        self.repeat_sizes: dict[tuple, int] = {}  # blocks of a REPEAT section (repeat_estimate)
        self.machine_modal = machine.Modal()  # the machine side's modal part (saved by PROC ... SAVE)
        self.machine = machine.Machine(cfg, self)  # the machine side: units, frames, extra axes, spindles
        self.drill = drill.DrillState()  # MCALL and the ISO drilling cycles
        lathe.start(self)  # a lathe set up for diameters starts in DIAMON (the position kept as a radius)

    # -- values ----------------------------------------------------------------------------------
    def tool_radius(self) -> float:
        nose = lathe.nose(self)
        if nose is not None:  # a lathe tool's nose radius
            return nose[0]
        if self.d_no == 0 or self.tool_no is None:
            return 0.0
        return float(self.cfg.tool_radii.get(self.tool_no, 0.0))


    # -- emission (radius compensation buffers motions) -----------------------------------------
    def emit(self, rec) -> None:
        if self.machine.lathe.pending is not None:  # a thread chain's last block waits for its DITE run-out
            lathe.before_emit(self, rec)
        for p in (rec.end, getattr(rec, "center", None)) if isinstance(rec, canon.MOTIONS) else ():
            if p is not None and max(abs(c) for c in p) > COORD_LIMIT:
                i = max(range(3), key=lambda k: abs(p[k]))
                what = "the arc centre" if p is not rec.end else "the end point"
                raise CutsimError(rec.src.program, rec.src.line, rec.src.col,
                                  range_message(f"{what} {'XYZ'[i]}", p[i], -COORD_LIMIT, COORD_LIMIT, "mm"))
        cs = self.corners
        if cs.capture is not None:  # the block's move, for its corner (corners.run_move)
            cs.capture.append(rec)
            return
        if cs.hold is not None:  # a move waits for its corner: other records wait behind it
            if not isinstance(rec, canon.MOTIONS):
                cs.queue.append(rec)
                return
            corner.flush(self, "a cycle's or another kind of move comes next")
        if self.comp_buf is not None:
            self.comp_buf.append(rec)
        else:
            self.program.records.append(rec)

    def corner_flush(self) -> None:
        """A cycle's moves follow a move held for its corner: the held move goes out as it is
        (machine.run_mapped calls this before it collects the cycle's records)."""
        corner.flush(self, "a cycle's move comes next")

    # -- main loop -------------------------------------------------------------------------------
    def run(self, text: str) -> canon.Program:
        self.main, self.subs = split_units(self.name, text, sinumerik_fast.read_plain)
        if not any(ln.stmts for ln in self.main.lines) and self.subs:
            self.main = next(iter(self.subs.values()))  # the program is its first PROC (PROC MAIN ... M30)
            self.vars = self.bind(self.main, (), 1, 1)  # its parameters take their defaults (or 0)
        stack = [Frame(self.main, pc=0, scope=self.vars)]
        ended = False
        last_line = 1
        while stack and not ended:
            fr = stack[-1]
            if fr.stop is not None and fr.pc >= fr.stop:
                fr.count -= 1
                if fr.count > 0:
                    fr.pc = fr.restart
                    continue
                stack.pop()
                if stack:
                    stack[-1].pc = fr.ret
                continue
            if fr.pc >= len(fr.unit.lines):
                stack.pop()
                if fr.kind == "repeat" and stack:
                    stack[-1].pc = fr.ret
                continue
            ln = fr.unit.lines[fr.pc]
            last_line = ln.line
            self.unit_program = fr.unit.program  # errors name the file of the line running
            fr.pc += 1
            if not ln.stmts:
                continue
            self.count_block(ln)
            ended = self.block(ln, fr, stack)
        corner.finish(self)  # a chamfer or rounding on the last move (no M30) is an error there
        lathe.finish(self)  # the DITE run-out of a thread chain at the program's end
        if self.comp_buf is not None:
            self.flush_comp(None, last_line)
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program


    def error(self, line: int, col: int, message: str) -> CutsimError:
        return CutsimError(self.unit_program, line, col, message)


    # -- one block: core.Interpreter.execute and its hooks ----------------------------------------
    def block(self, ln: Line, fr: Frame, stack: list[Frame]) -> bool:
        """Run one block; True when it ends the program (M2/M30 in the main program)."""
        src = Src(fr.unit.program, ln.line, 1, ln.nlabel or ln.label, fr.calls)
        if sinumerik_fast.plain_block(self, ln, src):  # constant G0/G1 X Y Z F, nothing else active
            return False
        if self.corners.hold is not None:
            self.corners.hold.blocks += 1
        return self.execute(Block(ln), src, stack).result

    def read_words(self, blk: Block) -> Block:
        """Assignments and DEFs take effect in order; words are evaluated and range-checked;
        commands are warned about or handed on (Block.commands); G4 takes its F/S as the dwell.
        The evaluated block is its own split (``split_words``)."""
        ln = blk.ln
        plain = sinumerik_fast.plain_evaluate(self, ln, Value)  # constant G0/G1 X Y Z F (fast.py)
        if plain is not None:
            blk.words, blk.gs = plain
            return blk
        line = ln.line
        for st in ln.stmts:
            if isinstance(st, Assign) and st.name in corner.CORNER_WORDS and not st.index and st.name not in self.vars:
                corner.word(self, blk.corner, st.name, self.num(self.ev(st.value, line, st.col), line, st.col), line,
                            st.col)
            elif isinstance(st, Assign):
                self.assign(st, line)
            elif isinstance(st, Def):
                self.define(st, line)
            elif isinstance(st, Word) and st.address in self.vars and st.mode is None:
                self.assign(Assign(st.col, st.address, st.value), line)  # PROC P(REAL B): B=B+1
            elif isinstance(st, Word) and st.address == "AX":
                self.axis_word(st, ln, blk)
            elif isinstance(st, Word):
                self.word(st, line, blk)
            elif isinstance(st, (Goto, Repeat, Case, Branch)):
                blk.jumps.append(st)
            elif isinstance(st, Command):
                self.command(st, ln, blk)
            elif isinstance(st, Call) and st.name in LANG_CALLS:
                self.lang_call(st, ln)
            elif isinstance(st, (Call, SubCall, Ret)):
                blk.calls.append(st)
        if any(code == 4 for code, _ in blk.gs):
            self.dwell(blk, line)
        if any(code in (25, 26) for code, _ in blk.gs):
            self.speed_limit(blk, ln)
        return blk

    @staticmethod
    def split_words(blk: Block) -> tuple[list, list, dict]:
        """The block's G and M codes as (code, column) pairs and its other words by address."""
        return blk.gs, blk.ms, blk.words

    def check_g(self, st: Step, gs: list[tuple[int, int]]) -> None:
        """The G codes (known to codes.G_CODES since ``word``): one per language group; the machine
        side's codes (units, zero offsets, G53, path modes) act; then the motion, the plane, distance
        and feed modes and the compensation G40/G41/G42 the block names; last the ISO drilling codes."""
        blk, line = st.block, st.block.line
        self.check_groups(gs, line)
        for code, col in machine.g_codes(self, gs, line):
            group = G_CODES[code].group
            if group is Group.MOTION:
                st.motion = code
            elif group is Group.PLANE and self.comp_buf is not None:
                raise self.error(line, col, "the plane cannot change while radius compensation G41/G42 is on")
            elif group is Group.RADIUS_COMP:
                blk.comp = code
            else:
                self.common_g(code)  # G90/G91, G94/G95, G17/G18/G19
        blk.drills = drill.iso_codes(self, blk, st.src)  # G81 .. G89 / G80: True when this block drills a hole

    def check_m(self, st: Step, ms: list[tuple[int, int]]) -> None:
        """The M codes (known to codes.M_CODES since ``word``): M2/M30 end the program after the
        block, M17 returns like RET. The spindle direction is taken in ``convert_settings``, after
        the machine keywords (their errors come first)."""
        if ms:
            blk = st.block
            blk.end = any(code in (2, 30) for code, _ in ms)
            blk.calls.extend(Ret(col) for code, col in ms if code == 17)

    def spindle(self, src: Src, direction, speed) -> None:
        if not lathe.spindle(self, src, direction, speed):  # G96 on a lathe: S is a cutting speed
            super().spindle(src, direction, None if speed is None else lathe.limited_speed(self.machine, speed))

    def convert_feed(self, st: Step) -> None:
        if "F" in st.words and self.motion not in (34, 35):  # G34/G35: F is the change of lead
            f = st.words.pop("F")
            if f.value <= 0:
                raise self.error(st.src.line, f.col, "feed F must be positive")
            self.feed = f.value

    def convert_motion(self, st: Step) -> None:
        """Machine keywords left over are errors; radius compensation starts (a corner waiting for
        its element where it changes is refused); the move, or the hole of an ISO drilling cycle,
        or the move with its chamfer or rounding; G40 ends the compensation after the move."""
        blk, src, line = st.block, st.src, st.src.line
        self.unsupported(blk, line)
        corner.comp_change(self, blk.comp)  # a corner where G40/G41/G42 changes: not modelled
        lathe.nose_plane(self, blk, line)  # a lathe compensates its tool's nose in G18 only
        self.comp_on(blk.comp, src, line)
        blk.moved = drill.moves_axes(blk.words)  # MCALL: the modal cycle runs after a block with X/Y/Z
        if blk.drills:  # the hole position: G0 in the plane at the level the tool stands on, then the hole
            modal_motion, self.motion = self.motion, 0
            self.move(src, blk.words, 0)
            self.motion = modal_motion
            drill.iso_drill(self, src)
        elif blk.corner or self.corners.active():
            corner.run_move(self, blk.corner, line, lambda: self.move(src, blk.words, st.motion))
        else:
            self.move(src, blk.words, st.motion)
        if blk.comp == 40 and self.comp_buf is not None:
            corner.comp_end(self)  # the departure move, if it waits for its corner, goes into the compensation
            self.flush_comp(src, line)

    def convert_end(self, st: Step) -> None:
        """The modal call after a block that moved, subprogram calls, jumps, the program end;
        ``Step.result`` is True when the program ends (``st.context``: the run loop's stack)."""
        blk, src, line, stack = st.block, st.src, st.src.line, st.context
        st.result = False
        drill.after_block(self, src, blk.moved, blk, stack)
        if self.calls(blk, src, line, stack):
            return
        for j in blk.jumps:
            if self.jump(j, line, stack):
                st.result = blk.end
                return
        if blk.end:
            if any(f.kind == "unit" for f in stack[1:]):  # M2/M30 in a subprogram: return
                self.ret(stack)
                return
            corner.finish(self)
            if self.comp_buf is not None:
                self.flush_comp(None, line)
            self.end(src)
            st.result = True

    # -- motion ----------------------------------------------------------------------------------
    def axis_targets(self, words: dict[str, Value]) -> dict[int, float]:
        end = {}
        for i, a in enumerate("XYZ"):
            if a in words:
                w = words.pop(a)
                ab = self.absolute if w.mode is None else w.mode == "AC"
                end[i] = w.value if ab else self.pos[i] + w.value
        return end

    def move(self, src: Src, words: dict[str, Value], motion_word) -> None:
        line = src.line
        machine.move(self, src, words, run_cycle)  # WCS -> machine: units, frames, extra axes (machine)
        cols = {i: words[a].col for i, a in enumerate("XYZ") if a in words}
        targets = self.axis_targets(words)
        if turning.active(self):  # G33/G34/G35, G331/G332, G63 (interp/sinumerik/turning.py)
            for i, v in targets.items():
                self.in_range(line, cols[i], "XYZ"[i], v, "the end point")
            turning.motion(self, src, words, targets, cols)
            return
        if not targets and motion_word not in (2, 3) and not any(k in words for k in ("I", "J", "K", "CR")):
            return
        end = list(self.pos)
        for i, v in targets.items():
            end[i] = v
            self.in_range(line, cols[i], "XYZ"[i], v, "the end point")
        end = (end[0], end[1], end[2])
        if self.motion in (0, 1):
            for a in ("I", "J", "K", "CR"):
                if a in words and not takes(self.motion, a):  # the circle's words (codes.G_CODES)
                    raise self.error(line, words[a].col, f"address {a} has no meaning in a G{self.motion} block")
            (self.rapid if self.motion == 0 else self.linear)(src, end)
            return
        nrm = PLANE_AXES[self.plane][2]
        if CENTRE_WORDS[nrm] in words:
            raise self.error(line, words[CENTRE_WORDS[nrm]].col,
                             f"{CENTRE_WORDS[nrm]} is not in the plane {self.plane} of the circle")
        cw = (self.motion == 2) != self.machine.arc_flip  # a mirror turns G2 into G3
        centre = self.radius_centre(line, words, end, cw) if "CR" in words else self.given_centre(line, words)
        self.arc(src, end, (centre[0], centre[1], centre[2]), cw)

    def radius_centre(self, line: int, words: dict[str, Value], end, cw: bool) -> tuple:
        """The centre of a CR= circle: on the left of the chord for CCW with the short arc (CR > 0),
        on the right for CW; a negative CR takes the long way."""
        a, b, _ = PLANE_AXES[self.plane]
        cr = words.pop("CR")
        r, ccol = cr.value, cr.col
        if any(CENTRE_WORDS[i] in words for i in (a, b)):
            raise self.error(line, ccol, "a circle takes either CR= or its centre I/J/K, not both")
        if r == 0:
            raise self.error(line, ccol, "CR must not be 0")
        try:  # the chord may exceed 2 CR by CR_SLACK only (not the core default RADIUS_SLACK)
            centre = radius_centre(self.pos, end, r, self.plane, cw, slack=CR_SLACK)
        except FullCircle:
            raise self.error(line, ccol, "a CR= circle needs an end point different from its start") from None
        except RadiusTooSmall as e:
            raise self.error(line, ccol, f"CR={r:g} is too small: the end point is {e.chord:.4f} mm from the start") from None
        for i in (a, b):
            self.in_range(line, ccol, "XYZ"[i], centre[i], "the arc centre")
        return centre

    def given_centre(self, line: int, words: dict[str, Value]) -> list[float]:
        """The centre from I/J/K: incremental from the start (core.arc_centre, as every dialect), or
        =AC(..) absolute."""
        a, b, _ = PLANE_AXES[self.plane]
        given = {i: words.pop(CENTRE_WORDS[i]) for i in (a, b) if CENTRE_WORDS[i] in words}
        if not given:
            raise self.error(line, 1, f"circle needs its centre ({CENTRE_WORDS[a]}/{CENTRE_WORDS[b]}) or a radius CR=")
        centre = arc_centre(self.pos, self.plane, False, {i: w.value for i, w in given.items() if w.mode != "AC"})
        for i, w in given.items():
            if w.mode == "AC":
                centre[i] = w.value
            self.in_range(line, w.col, "XYZ"[i], centre[i], "the arc centre")
        return centre

    def in_range(self, line: int, col: int, axis: str, v: float, what: str) -> None:
        """A position the tool reaches (incremental words add up) stays within COORD_LIMIT."""
        if abs(v) > COORD_LIMIT:
            raise self.error(line, col, range_message(f"{what} {axis}", v, -COORD_LIMIT, COORD_LIMIT, "mm"))

    # -- tool radius compensation ----------------------------------------------------------------
    def flush_comp(self, src_g40: Src | None, line: int) -> None:
        buf, self.comp_buf = self.comp_buf, None
        side = 1 if self.comp == 41 else -1
        r = self.tool_radius()
        nose = lathe.nose(self)  # a lathe tool: its tip is where the program's contour runs
        recs = compensate_records(buf, side * r, self.plane, src_g40 is not None, True, False,
                                  lambda rec, msg: self.error(rec.src.line, rec.src.col, msg), strict=False,
                                  shift=(0.0, 0.0) if nose is None else nose[1])
        self.program.records.extend(recs)
        self.comp = 40
        # the position is where the last emitted motion ends
        for rec in reversed(recs):
            if isinstance(rec, canon.MOTIONS):
                self.pos = list(rec.end)
                break


def interpret(name: str, text: str, cfg: InterpConfig) -> canon.Program:
    return Sinumerik(name, cfg).run(text)


__all__ = ["interpret", "Sinumerik"]
