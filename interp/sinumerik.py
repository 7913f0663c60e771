"""Siemens Sinumerik 840D dialect, milling subset (seed 003, spec/sinumerik.md).

Blocks are read once into the typed syntax tree of interp/sinumerik_lang.py (statements and
expressions as dataclasses); expressions are evaluated when the block runs. A block runs in
phases (``block``): evaluate its assignments and words in order, then the modal G codes, then
spindle, tool and feed, then the motion (with radius compensation), then cycles and subprogram
calls, then jumps and the program end. Cycles (SLOT1, POCKET1, CYCLE72, ...) expand in
interp/sinumerik_cycles.py into ordinary moves through the ModalMachine methods. Tool radius
compensation (G41/G42) buffers the compensated moves and offsets them analytically at G40.

Imports flow one way: sinumerik -> sinumerik_cycles -> sinumerik_lang.

What the simulator assumes where Siemens' manuals are silent: docs/dialects/sinumerik.md.
"""
from __future__ import annotations

import math
import os
import re
import stat
from dataclasses import dataclass, field

from . import canon
from .canon import Src
from .errors import CutsimError
from .modal import PLANE_AXES, PLANES, InterpConfig, ModalMachine
from .sinumerik_cycles import CYCLES, compensate_records, run_cycle
from .sinumerik_lang import (COORD_LIMIT, EXPR_ADDRESSES, PASS_LIMIT, R_LIMIT, RANGES, Assign, BinOp, Call, Def,
                             Frame, FuncCall, Goto, Line, Neg, Num, Repeat, Ret, RIndex, Stmt, Str, SubCall,
                             SubprogramMissing, Unit, Var, Word, range_message, split_units)

KNOWN_G = {0, 1, 2, 3, 9, 17, 18, 19, 40, 41, 42, 53, 54, 55, 56, 57, 60, 64, 90, 91, 94, 95, 500, 505, 506}
KNOWN_M = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 17, 30}
# calls with no geometric effect (messages, high-speed settings, blank definition for the HMI)
IGNORED_CALLS = {"MSG", "WORKPIECE", "CYCLE832", "G_GROUP", "SETMS"}
MAX_SUB_BYTES = 10_000_000  # a NAME.spf file beside the program
MAX_STACK = 64  # subprograms (16 of them at most) and REPEAT sections open at once
R_NAME = re.compile(r"R[0-9]+")
AXIS_LETTER = {0: "I", 1: "J", 2: "K"}  # the centre address of each axis


@dataclass
class Value:
    """An address's value in one block: X, CR, F, ... (``mode`` AC/IC for X=AC(..))."""
    value: float
    mode: str | None
    col: int


@dataclass
class Block:
    """What reading a block's statements gives: its words, G and M codes, calls and jumps."""
    words: dict[str, Value] = field(default_factory=dict)
    gs: list[tuple[int, int]] = field(default_factory=list)  # (code, column)
    ms: list[tuple[int, int]] = field(default_factory=list)
    calls: list[Stmt] = field(default_factory=list)  # Call | SubCall | Ret
    jumps: list[Stmt] = field(default_factory=list)  # Goto | Repeat


class Sinumerik(ModalMachine):
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

    # -- values ----------------------------------------------------------------------------------
    def tool_radius(self) -> float:
        if self.d_no == 0 or self.tool_no is None:
            return 0.0
        return float(self.cfg.tool_radii.get(self.tool_no, 0.0))

    def ev(self, node, line: int, col: int):
        """The value of an expression: a string or a finite float (an overflow is an error at the
        expression's column)."""
        v = self._ev(node, line, col)
        if not isinstance(v, str) and not math.isfinite(v):
            raise self.error(line, col, "the expression overflows: its value is not a finite number")
        return v

    def r_index(self, i: float, line: int, col: int) -> str:
        if i != int(i) or not 0 <= i <= R_LIMIT:
            raise self.error(line, col, f"R[{i:.10g}]: there are the parameters R0 to R{R_LIMIT}")
        return f"R{int(i)}"

    def _ev(self, node, line: int, col: int):
        if isinstance(node, (Num, Str)):
            return node.value
        if isinstance(node, Neg):
            v = self._ev(node.operand, line, col)
            if isinstance(v, str):
                raise self.error(line, col, "a string cannot be negated")
            return -v
        if isinstance(node, Var):
            return self.variable(node, line)
        if isinstance(node, RIndex):
            i = self.num(self._ev(node.index, line, col), line, node.col)
            return self.params.get(self.r_index(i, line, node.col), 0.0)
        if isinstance(node, FuncCall):
            args = [self.num(self._ev(a, line, col), line, node.col) for a in node.args]
            r = self.fn(node.name, args, line, node.col)
            if not math.isfinite(r):
                raise self.error(line, node.col, f"{node.name} overflows: the result is not a finite number")
            return r
        if isinstance(node, BinOp):
            return self.binop(node, line, col)
        raise TypeError(f"not an expression node: {node!r}")  # pragma: no cover

    def variable(self, node: Var, line: int):
        name = node.name
        if R_NAME.fullmatch(name):
            if len(name[1:].lstrip("0")) > len(str(R_LIMIT)):
                raise self.error(line, node.col, f"{name}: there are the parameters R0 to R{R_LIMIT}")
            return self.params.get(self.r_index(float(int(name[1:])), line, node.col), 0.0)
        if name in self.vars:
            return self.vars[name]
        if name in ("TRUE", "FALSE"):
            return 1.0 if name == "TRUE" else 0.0
        raise self.error(line, node.col, f"unknown variable '{name}' (declare it with DEF)")

    def binop(self, node: BinOp, line: int, col: int) -> float:
        op = node.op
        a = self._ev(node.left, line, col)
        b = self._ev(node.right, line, col)
        if op in ("==", "<>") and isinstance(a, str) and isinstance(b, str):
            return float((a == b) == (op == "=="))
        a, b = self.num(a, line, col), self.num(b, line, col)
        if op in ("+", "-", "*", "/"):
            if op == "/" and b == 0:
                raise self.error(line, node.col, "division by zero")
            r = a + b if op == "+" else a - b if op == "-" else a * b if op == "*" else a / b
            if not math.isfinite(r):
                raise self.error(line, node.col, f"{a:.10g} {op} {b:.10g} overflows: the result is not a finite number")
            return r
        return float({"==": a == b, "<>": a != b, "<": a < b, ">": a > b, "<=": a <= b, ">=": a >= b}[op])

    def fn(self, f: str, args: list, line: int, col: int) -> float:
        try:
            if f == "SIN":
                return math.sin(math.radians(args[0]))
            if f == "COS":
                return math.cos(math.radians(args[0]))
            if f == "TAN":
                return math.tan(math.radians(args[0]))
            if f == "ASIN":
                return math.degrees(math.asin(args[0]))
            if f == "ACOS":
                return math.degrees(math.acos(args[0]))
            if f == "ATAN2":
                return math.degrees(math.atan2(args[0], args[1]))
            if f == "SQRT":
                return math.sqrt(args[0])
            if f == "ABS":
                return abs(args[0])
            if f == "POT":
                return args[0] * args[0]
            if f == "TRUNC":
                return float(math.trunc(args[0]))
            if f == "ROUND":
                return float(math.floor(args[0] + 0.5))
            if f == "MINVAL":
                return min(args)
            if f == "MAXVAL":
                return max(args)
        except (ValueError, OverflowError):
            raise self.error(line, col, f"{f} of {args[0]:g} is not defined") from None
        raise self.error(line, col, f"unknown function {f}")  # pragma: no cover

    def num(self, v, line: int, col: int) -> float:
        if isinstance(v, str):
            raise self.error(line, col, f"a number is needed here, not the string \"{v}\"")
        if not math.isfinite(v):
            raise self.error(line, col, "the value is not a finite number")
        return float(v)

    # -- emission (radius compensation buffers motions) -----------------------------------------
    def emit(self, rec) -> None:
        for p in (rec.end, getattr(rec, "center", None)) if isinstance(rec, canon.MOTIONS) else ():
            if p is not None and max(abs(c) for c in p) > COORD_LIMIT:
                i = max(range(3), key=lambda k: abs(p[k]))
                what = "the arc centre" if p is not rec.end else "the end point"
                raise CutsimError(rec.src.program, rec.src.line, rec.src.col,
                                  range_message(f"{what} {'XYZ'[i]}", p[i], -COORD_LIMIT, COORD_LIMIT, "mm"))
        if self.comp_buf is not None:
            self.comp_buf.append(rec)
        else:
            self.program.records.append(rec)

    # -- main loop -------------------------------------------------------------------------------
    def run(self, text: str) -> canon.Program:
        self.main, self.subs = split_units(self.name, text)
        stack = [Frame(self.main, pc=0)]
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
            self.executed += 1
            if self.executed > self.cfg.max_blocks:
                raise self.error(ln.line, 1, f"the program does not end: more than {self.cfg.max_blocks:,} blocks executed "
                                 "(a jump loop; the limit is [simulation] max_blocks)")
            ended = self.block(ln, fr, stack)
        if self.comp_buf is not None:
            self.flush_comp(None, last_line)
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    def check_loop(self, stack: list[Frame], line: int, st: Goto) -> None:
        """A backward jump that comes back with the same control state (every frame's place and
        counters, every R parameter and variable) repeats forever: nothing else steers the
        program. States are remembered by hash; a hash seen before keeps its full state, and only
        the full state seen again is the proof (no false alarm from a hash collision)."""
        key = (tuple((id(f.unit), f.pc, f.count, f.stop, f.restart, f.ret, f.kind) for f in stack),
               tuple(sorted(self.params.items())), tuple(sorted((k, repr(v)) for k, v in self.vars.items())))
        h = hash(key)
        if h not in self.loop_hashes:
            self.loop_hashes.add(h)
            return
        if self.loop_states.get(h) == key:
            raise self.error(line, st.col, f"the program does not end: {st.kind} {st.label} comes back with every R parameter "
                             "and variable unchanged, so it loops forever")
        self.loop_states[h] = key

    def error(self, line: int, col: int, message: str) -> CutsimError:
        return CutsimError(self.unit_program, line, col, message)

    def find_label(self, unit: Unit, label: str, line: int, col: int) -> int:
        if label not in unit.labels:
            raise self.error(line, col, f"label {label} does not exist in {'the program' if unit is self.main else unit.name}")
        return unit.labels[label]

    def find_sub(self, name: str, line: int, col: int) -> Unit:
        if name in self.subs:
            return self.subs[name]
        d = os.path.dirname(os.path.abspath(self.name))
        try:
            cands = [f for f in os.listdir(d) if os.path.splitext(f)[0].upper() == name and
                     os.path.splitext(f)[1].upper() in (".SPF", ".MPF", ".NC")]
        except OSError:
            cands = []
        if not cands:
            raise SubprogramMissing(self.unit_program, line, col, f"subprogram {name} is not defined (PROC {name} in "
                                    f"this file, or {name}.spf beside it)")
        path = os.path.join(d, sorted(cands)[0])
        text = self.read_sub(path, name, line, col)
        unit, more = split_units(path, text)
        unit.name = name
        self.subs[name] = unit
        for k, u in more.items():
            self.subs.setdefault(k, u)
        return unit

    def read_sub(self, path: str, name: str, line: int, col: int) -> str:
        """The text of a subprogram file; a directory, a special or unreadable file, or one larger
        than MAX_SUB_BYTES is an error at the calling block."""
        what = f"subprogram {name}: {path}"
        try:
            st = os.stat(path)
        except OSError as e:
            raise self.error(line, col, f"{what} cannot be read ({e.strerror})") from None
        if stat.S_ISDIR(st.st_mode):
            raise self.error(line, col, f"{what} is a directory, not a program file")
        if not stat.S_ISREG(st.st_mode):
            raise self.error(line, col, f"{what} is not a regular file")
        if st.st_size > MAX_SUB_BYTES:
            raise self.error(line, col, f"{what} has {st.st_size:,} bytes, more than the {MAX_SUB_BYTES:,} a "
                             "subprogram file may have")
        try:
            with open(path, "rb") as f:
                data = f.read(MAX_SUB_BYTES + 1)
        except OSError as e:
            raise self.error(line, col, f"{what} cannot be read ({e.strerror})") from None
        if len(data) > MAX_SUB_BYTES:
            raise self.error(line, col, f"{what} has more than the {MAX_SUB_BYTES:,} bytes a subprogram file may have")
        return data.decode("utf-8-sig", errors="replace")

    # -- one block, in phases ----------------------------------------------------------------------
    def block(self, ln: Line, fr: Frame, stack: list[Frame]) -> bool:
        """Run one block; True when it ends the program (M2/M30 in the main program)."""
        src = Src(fr.unit.program, ln.line, 1, ln.nlabel or ln.label, fr.calls)
        line = ln.line
        blk = self.evaluate(ln)
        motion, new_comp = self.modal_codes(blk.gs, line)
        end = self.settings(src, blk, motion)
        self.comp_on(new_comp, src, line)
        self.move(ln, src, blk.words, motion)
        if new_comp == 40 and self.comp_buf is not None:
            self.flush_comp(src, line)
        if self.calls(blk, src, line, stack):
            return False
        for st in blk.jumps:
            if self.jump(st, line, stack):
                return end
        if end:
            if any(f.kind == "unit" for f in stack[1:]):  # M2/M30 in a subprogram: return
                self.ret(stack)
                return False
            if self.comp_buf is not None:
                self.flush_comp(None, line)
            self.end(src)
        return end

    def evaluate(self, ln: Line) -> Block:
        """Assignments and DEFs take effect in order; words are evaluated and range-checked."""
        line = ln.line
        blk = Block()
        for st in ln.stmts:
            if isinstance(st, Assign):
                self.assign(st, line)
            elif isinstance(st, Def):
                self.define(st, line)
            elif isinstance(st, Word):
                self.word(st, line, blk)
            elif isinstance(st, (Goto, Repeat)):
                blk.jumps.append(st)
            elif isinstance(st, (Call, SubCall, Ret)):
                blk.calls.append(st)
        return blk

    def assign(self, st: Assign, line: int) -> None:
        v = self.ev(st.value, line, st.col)
        if R_NAME.fullmatch(st.name):
            self.params[st.name] = self.num(v, line, st.col)
        elif st.name in self.vars:
            self.vars[st.name] = v
        else:
            raise self.error(line, st.col, f"unknown variable '{st.name}' (declare it with DEF)")

    def define(self, st: Def, line: int) -> None:
        for d in st.decls:
            if R_NAME.fullmatch(d.name) or d.name in EXPR_ADDRESSES or len(d.name) == 1:
                raise self.error(line, d.col, f"'{d.name}' is an address or parameter and cannot be a variable name")
            val = 0.0 if st.type != "STRING" else ""
            if d.init is not None:
                val = self.ev(d.init, line, d.col)
                if st.type == "INT" and not isinstance(val, str):
                    val = float(math.trunc(val))
            self.vars[d.name] = val

    def word(self, st: Word, line: int, blk: Block) -> None:
        val = self.ev(st.value, line, st.col)
        if st.address in ("G", "M"):
            v = self.num(val, line, st.col)
            known = KNOWN_G if st.address == "G" else KNOWN_M
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

    def modal_codes(self, gs: list[tuple[int, int]], line: int) -> tuple[int | None, int | None]:
        """Apply the block's modal G codes; the motion (G0..G3) and the G40/G41/G42 it names."""
        motion = None
        new_comp = None
        for code, col in gs:
            if code in (0, 1, 2, 3):
                if motion is not None:
                    raise self.error(line, col, f"G{code} conflicts with G{motion} in the same block")
                motion = code
            elif code in PLANES and self.comp_buf is not None:
                raise self.error(line, col, "the plane cannot change while radius compensation G41/G42 is on")
            elif self.common_g(code):
                pass
            elif code in (40, 41, 42):
                new_comp = code
        return motion, new_comp

    def settings(self, src: Src, blk: Block, motion: int | None) -> bool:
        """Spindle, tool (T, D, M6), feed and the motion mode; True when an M2/M30 ends the program."""
        line, words = src.line, blk.words
        direction = self.spindle_code(line, blk.ms)
        end = any(code in (2, 30) for code, _ in blk.ms)
        change = any(code == 6 for code, _ in blk.ms)
        blk.calls.extend(Ret(col) for code, col in blk.ms if code == 17)
        if "S" in words:
            self.spindle(src, direction, words.pop("S").value)
        elif direction is not None:
            self.spindle(src, direction, None)
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
        if change:
            self.change_tool(src)
        if "F" in words:
            f = words.pop("F")
            if f.value <= 0:
                raise self.error(line, f.col, "feed F must be positive")
            self.feed = f.value
        if motion is not None:
            self.motion = motion
        return end

    def change_tool(self, src: Src) -> None:
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

    def calls(self, blk: Block, src: Src, line: int, stack: list[Frame]) -> bool:
        """Cycles, subprogram calls (NAME, L<n> P<n>) and RET/M17; True when the block hands over
        to another frame (a call or a return)."""
        for st in blk.calls:
            if isinstance(st, Ret):
                self.ret(stack)
                return True
            if isinstance(st, Call):
                if st.name in IGNORED_CALLS:
                    continue
                if st.name not in CYCLES:
                    raise self.error(line, st.col, f"unknown cycle or function {st.name}")
                args = [(None if a.value is None else self.ev(a.value, line, a.col), a.col) for a in st.args]
                run_cycle(self, st.name, args, src, st.col)
                continue
            if st.name in self.vars:  # SubCall
                raise self.error(line, st.col, f"'{st.name}' is a variable: write {st.name}=<value> to assign it")
            self.call_sub(self.find_sub(st.name, line, st.col), src, blk.words, stack, st.col)
            return True
        words = blk.words
        if "L" in words:
            lw = words.pop("L")
            if lw.value != int(lw.value):
                raise self.error(line, lw.col, f"L{lw.value:g}: a subprogram number is a whole number")
            self.call_sub(self.find_sub(f"L{int(lw.value)}", line, lw.col), src, words, stack, lw.col)
            return True
        if "P" in words:
            raise self.error(line, words["P"].col, "P (repeat count) only goes with a subprogram call")
        return False

    def jump(self, st: Goto | Repeat, line: int, stack: list[Frame]) -> bool:
        """GOTO (True when taken) or REPEAT (always taken)."""
        fr = stack[-1]
        cur = fr.pc - 1
        if isinstance(st, Goto):
            if st.cond is not None and not self.num(self.ev(st.cond, line, st.col), line, st.col):
                return False
            idx = self.find_label(fr.unit, st.label, line, st.col)
            if st.kind == "GOTOF" and idx <= cur:
                raise self.error(line, st.col, f"GOTOF jumps forward, but {st.label} comes before this block")
            if st.kind == "GOTOB" and idx > cur:
                raise self.error(line, st.col, f"GOTOB jumps back, but {st.label} comes after this block")
            fr.pc = idx
            if idx <= cur:
                self.check_loop(stack, line, st)
            return True
        a = self.find_label(fr.unit, st.start, line, st.col)
        n = self.num(self.ev(st.count, line, st.col), line, st.col)
        if n != int(n) or not 1 <= n <= PASS_LIMIT:
            raise self.error(line, st.col, f"REPEAT P must be a whole number from 1 to {PASS_LIMIT} (got {n:.10g})")
        if len(stack) > MAX_STACK:
            raise self.error(line, st.col, f"REPEAT sections and subprograms nested deeper than {MAX_STACK} "
                             "(a REPEAT inside the section it repeats?)")
        if st.end is None:
            if a >= cur:
                raise self.error(line, st.col, f"REPEAT {st.start}: the label must come before this block")
            stop = cur
        else:
            b = self.find_label(fr.unit, st.end, line, st.col)
            if b < a:
                raise self.error(line, st.col, f"REPEAT {st.start} {st.end}: the end label comes before the start")
            stop = b + 1
        stack.append(Frame(fr.unit, pc=a, stop=stop, restart=a, ret=cur + 1, count=int(n), kind="repeat",
                           calls=fr.calls))
        return True


    def ret(self, stack: list[Frame]) -> None:
        while stack and stack[-1].kind == "repeat":
            stack.pop()
        if len(stack) > 1 and stack[-1].count > 1:  # P<n>: run the subprogram again
            stack[-1].count -= 1
            stack[-1].pc = stack[-1].restart
            return
        if len(stack) <= 1:
            stack[:] = []  # RET / M17 in the main program ends it
            return
        stack.pop()

    def call_sub(self, unit: Unit, src: Src, words: dict[str, Value], stack: list[Frame], col: int) -> None:
        n = 1
        if "P" in words:
            p = words.pop("P")
            if p.value != int(p.value) or p.value < 1:
                raise self.error(src.line, p.col, "P (repeat count) must be a whole number of at least 1")
            n = int(p.value)
        if len(stack) > 16:
            raise self.error(src.line, col, "subprograms nested deeper than 16 levels (recursion?)")
        calls = stack[-1].calls + ((src.program, src.line),)
        stack.append(Frame(unit, pc=0, stop=len(unit.lines), restart=0, ret=stack[-1].pc, count=n, kind="unit",
                           calls=calls))

    # -- motion ----------------------------------------------------------------------------------
    def axis_targets(self, words: dict[str, Value]) -> dict[int, float]:
        end = {}
        for i, a in enumerate("XYZ"):
            if a in words:
                w = words.pop(a)
                ab = self.absolute if w.mode is None else w.mode == "AC"
                end[i] = w.value if ab else self.pos[i] + w.value
        return end

    def move(self, ln: Line, src: Src, words: dict[str, Value], motion_word) -> None:
        line = ln.line
        cols = {i: words[a].col for i, a in enumerate("XYZ") if a in words}
        targets = self.axis_targets(words)
        if not targets and motion_word not in (2, 3) and not any(k in words for k in ("I", "J", "K", "CR")):
            return
        end = list(self.pos)
        for i, v in targets.items():
            end[i] = v
            self.in_range(line, cols[i], "XYZ"[i], v, "the end point")
        end = (end[0], end[1], end[2])
        if self.motion in (0, 1):
            for a in ("I", "J", "K", "CR"):
                if a in words:
                    raise self.error(line, words[a].col, f"address {a} has no meaning in a G{self.motion} block")
            (self.rapid if self.motion == 0 else self.linear)(src, end)
            return
        nrm = PLANE_AXES[self.plane][2]
        if AXIS_LETTER[nrm] in words:
            raise self.error(line, words[AXIS_LETTER[nrm]].col,
                             f"{AXIS_LETTER[nrm]} is not in the plane {self.plane} of the circle")
        cw = self.motion == 2
        centre = self.radius_centre(line, words, end, cw) if "CR" in words else self.given_centre(line, words)
        self.arc(src, end, (centre[0], centre[1], centre[2]), cw)

    def radius_centre(self, line: int, words: dict[str, Value], end, cw: bool) -> list[float]:
        """The centre of a CR= circle: on the left of the chord for CCW with the short arc (CR > 0),
        on the right for CW; a negative CR takes the long way."""
        a, b, _ = PLANE_AXES[self.plane]
        cr = words.pop("CR")
        r, ccol = cr.value, cr.col
        if any(AXIS_LETTER[i] in words for i in (a, b)):
            raise self.error(line, ccol, "a circle takes either CR= or its centre I/J/K, not both")
        if r == 0:
            raise self.error(line, ccol, "CR must not be 0")
        p0 = (self.pos[a], self.pos[b])
        p1 = (end[a], end[b])
        dx, dy = p1[0] - p0[0], p1[1] - p0[1]
        d = math.hypot(dx, dy)
        if d < 1e-9:
            raise self.error(line, ccol, "a CR= circle needs an end point different from its start")
        if d > 2 * abs(r) + 1e-6:
            raise self.error(line, ccol, f"CR={r:g} is too small: the end point is {d:.4f} mm from the start")
        h = math.sqrt(max(r * r - d * d / 4, 0.0))
        sgn = (1 if not cw else -1) * (1 if r > 0 else -1)
        mx, my = (p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2
        centre = list(self.pos)
        centre[a], centre[b] = mx - sgn * h * dy / d, my + sgn * h * dx / d
        for i in (a, b):
            self.in_range(line, ccol, "XYZ"[i], centre[i], "the arc centre")
        return centre

    def given_centre(self, line: int, words: dict[str, Value]) -> list[float]:
        """The centre from I/J/K (incremental from the start, or =AC(..) absolute)."""
        a, b, _ = PLANE_AXES[self.plane]
        centre = list(self.pos)
        given = False
        for i in (a, b):
            if AXIS_LETTER[i] in words:
                w = words.pop(AXIS_LETTER[i])
                centre[i] = w.value if w.mode == "AC" else self.pos[i] + w.value
                self.in_range(line, w.col, "XYZ"[i], centre[i], "the arc centre")
                given = True
        if not given:
            raise self.error(line, 1, f"circle needs its centre ({AXIS_LETTER[a]}/{AXIS_LETTER[b]}) or a radius CR=")
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
        recs = compensate_records(self, buf, side * r, self.plane, src_g40 is not None, self.comp_src)
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
