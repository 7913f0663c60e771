"""Siemens Sinumerik 840D dialect, milling subset (seed 003, spec/sinumerik.md).

Blocks are read once into the typed syntax tree of interp/sinumerik/lang.py (statements and
expressions as dataclasses); expressions are evaluated when the block runs. A block runs in
phases (``block``): evaluate its assignments and words in order, then the modal G codes, then
spindle, tool and feed, then the motion (with radius compensation), then cycles and subprogram
calls, then jumps and the program end. Cycles (SLOT1, POCKET1, CYCLE72, ...) expand in
interp/sinumerik/milling.py into ordinary moves through the ModalMachine methods. Tool radius
compensation (G41/G42) buffers the compensated moves and offsets them analytically at G40.

Imports flow one way (issue 11): sinumerik -> drilling -> milling, machine
-> lang. This module, the one above them all, registers the drilling cycles into the
cycles' tables and hands ``run_cycle`` and the cycle names to the machine side's hooks.

What the simulator assumes where Siemens' manuals are silent: docs/dialects/sinumerik.md.
"""
from __future__ import annotations

import copy
import functools
import math
import os
import re
import stat
from dataclasses import dataclass, field

from .. import canon
from ..canon import Src
from ..core import MOTION, Code, arc_centre
from . import axes
from . import machine
from ..errors import CutsimError
from ..modal import PLANE_AXES, PLANES, InterpConfig, ModalMachine
from . import corners as corner
from . import drilling as drill
from . import fast as sinumerik_fast
from .milling import ANGLES, CYCLES, DRILLING, RUNNERS, SPECS, _spec, compensate_records, run_cycle
from .lang import KEYWORDS as LANG_KEYWORDS
from .lang import R_NAME, STRING_FUNCS
from .lang import (COORD_LIMIT, EXPR_ADDRESSES, KNOWN_M, MACHINE_COMMANDS, PASS_LIMIT, R_LIMIT, RANGES, Assign,
                             BinOp, Branch, Call, Case, Command, Def, Frame, FuncCall, Goto, Index, Line, Neg, Not,
                             Num, Repeat, Ret, RIndex, Stmt, Str, SubCall, SubprogramMissing, Unit, Var, Word,
                             range_message, split_units)

KNOWN_G = {0, 1, 2, 3, 4, 9, 17, 18, 19, 40, 41, 42, 53, 54, 55, 56, 57, 60, 64, 90, 91, 94, 95, 500, 505, 506,
           *drill.ISO_G}  # the ISO shell's drilling cycles G73 .. G89 / G80, G98/G99, G290/G291
# modal groups of the language's own G codes (core.Code rows; the machine functions keep theirs)
G_CODES = {**{c: Code(MOTION, "XYZIJK", m) for c, m in ((0, "rapid"), (1, "line"), (2, "arc cw"), (3, "arc ccw"))},
           **{c: Code("plane", "", p) for c, p in PLANES.items()},
           90: Code("distance mode", "", "absolute"), 91: Code("distance mode", "", "incremental"),
           94: Code("feed mode", "F", "per minute"), 95: Code("feed mode", "F", "per revolution"),
           40: Code("radius compensation", "", "off"), 41: Code("radius compensation", "", "left"),
           42: Code("radius compensation", "", "right")}
# calls with no geometric effect (high-speed settings, blank definition for the HMI)
IGNORED_CALLS = {"WORKPIECE", "CYCLE832"}
# language calls that do not change the tool path: one warning per kind (SETAL: an alarm, exit 2)
LANG_CALLS = {"MSG", "SETAL", "FGROUP", "G_GROUP", "SETMS", "GROUP_BEGIN", "GROUP_END", "STOPRE", "WAITM",
              "WAITMC", "WAITE", "SETM", "CLEARM", "CANCEL", "DISPLOF", "DISPLON", "PRESETON", "SPOS", "SPOSA",
              "FA", "WRTPR", "MSG_", "SBLOF", "SBLON", "STOPFIFO", "STARTFIFO", "WAITP", "WAITS", "WAITC",
              "RELEASE", "GET", "GETD", "PRIO"}
NOTES = {"STOPRE": "(preprocessing stop) changes nothing on the tool path",
         "WHENEVER": "(a synchronized action) is not simulated: its condition and action are ignored",
         "ID": "(a synchronized action) is not simulated: its condition and action are ignored",
         "MSG": "(a message on the operator screen) changes nothing on the tool path",
         "FGROUP": "(the axes the feed applies to) is not simulated: F is the path feed of X/Y/Z",
         "H": "(an auxiliary function for the machine's PLC) changes nothing on the tool path",
         "SPOS": "(spindle positioning) changes nothing on the tool path",
         "LIMS": "(the spindle speed limit) changes nothing on the tool path"}
# what PROC ... SAVE puts back on return: the modal G groups, not F, S, T, D, and the machine
# functions' modal state (units, settable and programmable frames: machine.Modal)
SAVED_MODAL = ["absolute", "per_rev", "plane", "motion", "comp", "machine_modal"]
# the drilling cycles and the position patterns join the cycles' tables (CYCLES, SPECS, RUNNERS)
drill.register(SPECS, RUNNERS, CYCLES, ANGLES, _spec, DRILLING)
# keywords that are never a subprogram file, even with a file of that name beside the program
NOT_FILES = LANG_KEYWORDS | MACHINE_COMMANDS | set(CYCLES) | {"MCALL", "HOLES1", "HOLES2", "LONGHOLE", "CYCLE800",
           "CYCLE801", "CYCLE802", "CYCLE832", "CYCLE840", "CYCLE84", "CYCLE86", "CYCLE87", "CYCLE88", "CYCLE89",
           "CYCLE90", "CYCLE61", "CYCLE76", "CYCLE77", "CYCLE79", "CYCLE899", "CYCLE95", "CYCLE97", "MSG", "SETAL",
           "WORKPIECE"}
# path words the simulator does not implement: an error naming them, not "unknown variable"
UNSUPPORTED_NAMES = {"ANG": "a contour angle", "AR": "an arc's opening angle",
                     "AP": "a polar angle", "RP": "a polar radius", "TURN": "helix turns", "POS": "a positioning axis",
                     "POSA": "a positioning axis", "OFFN": "a contour offset", "I1": "an intermediate point",
                     "J1": "an intermediate point", "K1": "an intermediate point"}
# a subprogram file's extensions (find_sub) and its archive form _N_NAME_SPF: stripped from the setup's
# [machine] external_subprograms names and from EXTCALL/PCALL paths to give the name a call uses
SUB_EXTENSIONS = (".SPF", ".MPF", ".NC")
ARCHIVE_NAME = re.compile(r"_N_([A-Z0-9_]+)_(?:SPF|MPF)")
MAX_ARRAY = 1_000_000  # elements of one array (DEF REAL A[1000, 1000])
MAX_SUB_BYTES = 10_000_000  # a NAME.spf file beside the program
MAX_STACK = 64  # subprograms (16 of them at most) and REPEAT sections open at once
AXIS_LETTER = {0: "I", 1: "J", 2: "K"}  # the centre address of each axis


def call_name(file: str) -> str:
    """The name a call uses for a subprogram file: "subs/L_VENDOR.SPF" and "_N_L_VENDOR_SPF" are
    L_VENDOR (folder, extension and archive form removed; upper case)."""
    name = re.split(r"[/\\]", file.strip())[-1].strip().upper()
    base, ext = os.path.splitext(name)
    if ext in SUB_EXTENSIONS:
        name = base
    m = ARCHIVE_NAME.fullmatch(name)
    return m.group(1) if m else name


def missing_hint(name: str) -> str:
    """What to do about a call the simulator finds no subprogram for (the end of its error)."""
    return (f"; a subprogram the machine has but the simulator does not is declared in the setup: "
            f"[machine] external_subprograms = [\"{name}\"]")


COMPARE = {"==": lambda a, b: a == b, "<>": lambda a, b: a != b, "<": lambda a, b: a < b, ">": lambda a, b: a > b,
           "<=": lambda a, b: a <= b, ">=": lambda a, b: a >= b}


def to_text(v) -> str:
    """A value as the << operator and MSG show it: strings as they are, numbers shortest."""
    return v if isinstance(v, str) else f"{v:.10g}"


def convert(typ: str, v, length: int = 0):
    """A value as stored in a variable of type ``typ`` (Job Planning, type conversions): INT rounds
    to the nearest whole number (halves away from 0), BOOL is 0 or 1, STRING takes a number's text;
    None when the value cannot be converted (a string for a number)."""
    if typ in ("STRING", "AXIS"):
        s = to_text(v)
        return s[:length] if length else s
    if isinstance(v, str):
        if typ == "CHAR" and len(v) == 1:
            return float(ord(v))
        return None
    if typ == "INT":
        return float(math.floor(abs(v) + 0.5) * (1 if v >= 0 else -1))
    if typ == "BOOL":
        return float(v != 0)
    return float(v)


@dataclass
class Slot:
    """A scalar variable (or a system variable / setup datum once read or written)."""
    type: str
    value: object
    length: int = 0

    def get(self):
        return self.value

    def set(self, v) -> bool:
        c = convert(self.type, v, self.length)
        if c is None:
            return False
        self.value = c
        return True


@dataclass
class RSlot:
    """An R parameter (its dictionary and key), so a VAR parameter can stand for it."""
    params: dict
    key: str

    def get(self):
        return self.params.get(self.key, 0.0)

    def set(self, v) -> bool:
        if isinstance(v, str):
            return False
        self.params[self.key] = float(v)
        return True


@dataclass
class ArrayVar:
    """DEF REAL A[3, 4]: its type, dimensions and the values row by row."""
    type: str
    dims: tuple
    values: list
    length: int = 0

    def element(self, idx: list[float], m, line: int, col: int):
        if len(idx) != len(self.dims):
            raise m.error(line, col, f"the array has {len(self.dims)} dimension(s), not {len(idx)}")
        flat = 0
        for i, n in zip(idx, self.dims):
            if i != int(i) or not 0 <= i < n:
                raise m.error(line, col, f"array index {i:.10g} out of range 0 to {n - 1}")
            flat = flat * n + int(i)
        return ElemSlot(self, flat)


@dataclass
class ElemSlot:
    array: ArrayVar
    k: int

    def get(self):
        return self.array.values[self.k]

    def set(self, v) -> bool:
        c = convert(self.array.type, v, self.array.length)
        if c is None:
            return False
        self.array.values[self.k] = c
        return True


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
    jumps: list[Stmt] = field(default_factory=list)  # Goto | Repeat | Case | Branch
    # bare machine keywords (name, column) of lang.MACHINE_COMMANDS: ``settings`` removes
    # the ones it implements; any left over is an error (``unsupported``)
    commands: list[tuple[str, int]] = field(default_factory=list)
    corner: dict = field(default_factory=dict)  # CHF CHR RND RNDM FRC FRCM -> (value, column) (corners)


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

    # -- values ----------------------------------------------------------------------------------
    def tool_radius(self) -> float:
        if self.d_no == 0 or self.tool_no is None:
            return 0.0
        return float(self.cfg.tool_radii.get(self.tool_no, 0.0))

    def ev(self, node, line: int, col: int):
        """The value of an expression: a string or a finite float (an overflow is an error at the
        expression's column)."""
        if node.__class__ is Num and -math.inf < node.value < math.inf:  # a constant (most words)
            return node.value
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
        if isinstance(node, Not):
            v = self.num(self._ev(node.operand, line, node.col), line, node.col)
            return float(~self.whole_value(v, line, node.col)) if node.bits else float(not v)
        if isinstance(node, (Var, Index)):
            return self.slot(node, line, write=False).get()
        if isinstance(node, RIndex):
            i = self.num(self._ev(node.index, line, col), line, node.col)
            return self.params.get(self.r_index(i, line, node.col), 0.0)
        if isinstance(node, FuncCall) and node.name in axes.AXIS_FUNCS:
            return axes.function(self, node, line, col)
        if isinstance(node, FuncCall) and node.name in STRING_FUNCS:
            return self.string_fn(node, self._ev(node.args[0], line, col), line)
        if isinstance(node, FuncCall):
            args = [self.num(self._ev(a, line, col), line, node.col) for a in node.args]
            r = self.fn(node.name, args, line, node.col)
            if not math.isfinite(r):
                raise self.error(line, node.col, f"{node.name} overflows: the result is not a finite number")
            return r
        if isinstance(node, BinOp):
            return self.binop(node, line, col)
        raise TypeError(f"not an expression node: {node!r}")  # pragma: no cover

    def slot(self, node, line: int, write: bool):
        """Where a name reads and writes: an R parameter, a local variable or array element (VAR
        parameters share their caller's slot), a system variable or a setup [variables] name."""
        name, col = node.name, node.col
        index = node.index if isinstance(node, Index) else ()
        if name == "R" and len(index) == 1:  # R[expr]=...
            return RSlot(self.params, self.r_index(self.num(self.ev(index[0], line, col), line, col), line, col))
        if R_NAME.fullmatch(name) and not index:
            if len(name[1:].lstrip("0")) > len(str(R_LIMIT)):
                raise self.error(line, col, f"{name}: there are the parameters R0 to R{R_LIMIT}")
            return RSlot(self.params, self.r_index(float(int(name[1:])), line, col))
        if name.startswith("$"):
            return self.system_slot(name, index, line, col, write)
        held = self.vars.get(name)
        if isinstance(held, ArrayVar):
            if not index:
                raise self.error(line, col, f"'{name}' is an array: write {name}[index]")
            return held.element([self.num(self.ev(i, line, col), line, col) for i in index], self, line, col)
        if held is not None:
            if index:
                raise self.error(line, col, f"'{name}' is not an array")
            return held
        if name in ("TRUE", "FALSE") and not write:
            return Slot("BOOL", 1.0 if name == "TRUE" else 0.0)
        if name in self.cfg_names:  # global user data from the setup (also arrays: "_ZSFR[0]")
            return self.system_slot(name, index, line, col, write)
        if name in UNSUPPORTED_NAMES:
            raise self.error(line, col, f"{name}= ({UNSUPPORTED_NAMES[name]}) is not supported by the simulator")
        if name in corner.CORNER_WORDS:
            raise self.error(line, col, f"{name} is a corner's chamfer, rounding or feed, written {name}=<value> in "
                                        "a block with a move, not a variable")
        raise self.error(line, col, f"unknown variable '{name}' (declare it with DEF, or give a global one a "
                         f"value in the setup: [variables] \"{name}\" = ...)")

    def system_slot(self, name: str, index: tuple, line: int, col: int, write: bool):
        """A system variable ($P_..., $AA_IW[X], $A_DBB[5]) or global datum, keyed as written (upper
        case, the index evaluated): what the program wrote, else the setup's [variables] value."""
        parts = []
        for i in index:
            if isinstance(i, Var) and i.name not in self.vars and not R_NAME.fullmatch(i.name) \
                    and not i.name.startswith("$") and i.name not in self.cfg_vars:
                parts.append(i.name)  # an axis or channel name: $AA_IW[X]
                continue
            v = self.ev(i, line, col)
            parts.append(v if isinstance(v, str) else f"{v:.10g}")
        key = name + (f"[{','.join(parts)}]" if parts else "")
        known = self.known_system(key) if key not in self.sysvars and key not in self.cfg_vars else None
        if known is not None and not write:
            return Slot("STRING" if isinstance(known, str) else "REAL", known)
        if key not in self.sysvars:
            if key not in self.cfg_vars and not write:
                raise self.error(line, col, f"{key} is not known to the simulator (give it a value in the setup: "
                                 f"[variables] \"{key}\" = ...)")
            v = self.cfg_vars.get(key, 0.0)
            self.sysvars[key] = Slot("STRING" if isinstance(v, str) else "REAL",
                                     v if isinstance(v, str) else float(v))
        return self.sysvars[key]

    def known_system(self, key: str):
        """The system variables the simulation itself knows (the setup's [variables] win): the run
        is the real one ($P_SEARCH, $P_SIM, $P_DRYRUN, $P_ISTEST 0), the axis names of the plane
        ($P_AXN1..3), the active tool, edge and feed ($P_TOOLNO, $P_TOOL, $P_F). None otherwise."""
        if key in ("$P_SEARCH", "$P_SIM", "$P_DRYRUN", "$P_ISTEST"):
            return 0.0
        if key in ("$P_AXN1", "$P_AXN2", "$P_AXN3"):
            return "XYZ"[PLANE_AXES[self.plane][int(key[-1]) - 1]]
        if key == "$P_TOOLNO":
            return float(self.tool_no or 0)
        if key == "$P_TOOL":
            return float(self.d_no)
        if key == "$P_F" and self.feed is not None:
            return float(self.feed)
        return None

    def whole_value(self, v: float, line: int, col: int) -> int:
        if v != int(v):
            raise self.error(line, col, f"a whole number is needed here, not {v:.10g}")
        return int(v)

    def binop(self, node: BinOp, line: int, col: int):
        op = node.op
        a = self._ev(node.left, line, col)
        b = self._ev(node.right, line, col)
        if op == "<<":
            return to_text(a) + to_text(b)
        if op in COMPARE and isinstance(a, str) and isinstance(b, str):
            return float(COMPARE[op](a, b))
        a, b = self.num(a, line, col), self.num(b, line, col)
        if op in ("+", "-", "*", "/"):
            if op == "/" and b == 0:
                raise self.error(line, node.col, "division by zero")
            r = a + b if op == "+" else a - b if op == "-" else a * b if op == "*" else a / b
            if not math.isfinite(r):
                raise self.error(line, node.col, f"{a:.10g} {op} {b:.10g} overflows: the result is not a finite number")
            return r
        if op in COMPARE:
            return float(COMPARE[op](a, b))
        if op in ("AND", "OR", "XOR"):
            return float(bool(a) and bool(b) if op == "AND" else bool(a) or bool(b) if op == "OR" else bool(a) != bool(b))
        x, y = self.whole_value(a, line, node.col), self.whole_value(b, line, node.col)
        if op in ("DIV", "MOD") and y == 0:
            raise self.error(line, node.col, "division by zero")
        if op == "DIV":
            return float(int(x / y))
        if op == "MOD":
            return float(x - y * int(x / y))
        return float({"B_AND": x & y, "B_OR": x | y, "B_XOR": x ^ y}[op])

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
            if f in ("LN", "EXP"):
                return math.log(args[0]) if f == "LN" else math.exp(args[0])
            if f == "ROUNDUP":
                return float(math.ceil(args[0])) if args[0] >= 0 else float(math.floor(args[0]))
            if f == "BOUND":
                return min(max(args[2], args[0]), args[1])
        except (ValueError, OverflowError):
            raise self.error(line, col, f"{f} of {args[0]:g} is not defined") from None
        raise self.error(line, col, f"unknown function {f}")  # pragma: no cover

    def string_fn(self, node: FuncCall, v, line: int):
        """STRLEN, NUMBER, ISNUMBER, TOUPPER, TOLOWER of a string."""
        if not isinstance(v, str):
            raise self.error(line, node.col, f"{node.name} takes a string, not the number {v:.10g}")
        if node.name == "STRLEN":
            return float(len(v))
        if node.name in ("TOUPPER", "TOLOWER"):
            return v.upper() if node.name == "TOUPPER" else v.lower()
        try:
            number = float(v.strip())
            ok = math.isfinite(number)
        except ValueError:
            number, ok = 0.0, False
        if node.name == "ISNUMBER":
            return float(ok)
        if not ok:
            raise self.error(line, node.col, f"NUMBER(\"{v}\"): the string is no number")
        return number

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
               tuple(sorted(self.params.items())), tuple(sorted((k, repr(v)) for k, v in self.vars.items())),
               tuple(sorted((k, repr(v)) for k, v in self.sysvars.items())))
        h = hash(key)
        if h not in self.loop_hashes:
            self.loop_hashes.add(h)
            return
        if self.loop_states.get(h) == key:
            what = f"{st.kind} {st.label}" if isinstance(st, Goto) else st.kind
            raise self.error(line, st.col, f"the program does not end: {what} comes back with every R parameter "
                             "and variable unchanged, so it loops forever")
        self.loop_states[h] = key

    def error(self, line: int, col: int, message: str) -> CutsimError:
        return CutsimError(self.unit_program, line, col, message)

    def block_limit(self, b) -> CutsimError:
        return self.error(b.line, 1, f"the program does not end: more than {self.cfg.max_blocks:,} blocks executed "
                          "(a jump loop; the limit is [simulation] max_blocks)")

    def nearest(self, unit: Unit, label: str, cur: int, forward: bool) -> int | None:
        """The nearest line holding ``label`` after (forward) or at/before ``cur``."""
        lines = unit.all_labels.get(label, ())
        if forward:
            return next((i for i in lines if i > cur), None)
        return next((i for i in reversed(lines) if i <= cur), None)

    def find_label(self, unit: Unit, label: str, line: int, col: int, kind: str = "GOTO",
                   cur: int = -1) -> int | None:
        """The jump destination the Siemens way: GOTOF searches forwards, GOTOB backwards, GOTO and
        GOTOC forwards then backwards (a label written twice: the nearest in that direction).
        GOTOC gives None when the label is missing; the others are errors."""
        if label not in unit.all_labels:
            if kind == "GOTOC":
                return None
            raise self.error(line, col, f"label {label} does not exist in {'the program' if unit is self.main else unit.name}")
        fwd = self.nearest(unit, label, cur, forward=True)
        back = self.nearest(unit, label, cur, forward=False)
        idx = fwd if kind == "GOTOF" else back if kind == "GOTOB" else (fwd if fwd is not None else back)
        if idx is None and kind == "GOTOC":
            return None
        if idx is None:
            where = "before" if kind == "GOTOF" else "after"
            raise self.error(line, col, f"{kind} jumps {'forward' if kind == 'GOTOF' else 'back'}, but {label} "
                             f"comes only {where} this block")
        return idx

    def find_sub(self, name: str, line: int, col: int) -> Unit:
        """A subprogram: a PROC or %_N_NAME_SPF of the program's own file, else NAME.spf (.mpf, .nc)
        beside the program, else in the setup's [machine] subprogram_path folders, in that order.
        A file whose blocks are all inside ``PROC NAME`` runs that PROC's body."""
        if name in self.subs:
            return self.subs[name]
        if name in NOT_FILES:
            listed = " ([machine] external_subprograms does not apply to it: the simulator knows the Siemens " \
                     "keywords and cycles and will not take one as cutting nothing)" if name in self.externals else ""
            raise self.error(line, col, f"{name} is a Siemens keyword the simulator does not support{listed}")
        path = None
        for d in (*self.sub_dirs(), *self.cfg.subprogram_path):
            try:
                cands = sorted(f for f in os.listdir(d) if os.path.splitext(f)[0].upper() in (name, f"_N_{name}_SPF")
                               and os.path.splitext(f)[1].upper() in (".SPF", ".MPF", ".NC", ""))
            except OSError:
                cands = []
            cands = [f for f in cands if os.path.splitext(f)[1]] or cands
            if cands:
                path = os.path.join(d, cands[0])
                break
        if path is None:
            raise SubprogramMissing(self.unit_program, line, col, f"subprogram {name} is not defined (PROC {name} in "
                                    f"this file, {name}.spf beside it or in [machine] subprogram_path"
                                    f"{missing_hint(name)})")
        text = self.read_sub(path, name, line, col)
        unit, more = split_units(path, text, sinumerik_fast.read_plain)
        if not any(ln.stmts for ln in unit.lines) and more:
            unit = more.get(name) or next(iter(more.values()))  # the file is its PROC
        unit.name = name
        self.subs[name] = unit
        for k, u in more.items():
            self.subs.setdefault(k, u)
        return unit

    def sub_dirs(self) -> list[str]:
        """The program's folder, then the global subprogram folders of a Siemens archive beside it
        (SPF.DIR, _N_SPF_DIR, SPF_DIR; also one level up, for a program inside MPF.DIR or a .WPD)."""
        here = os.path.dirname(os.path.abspath(self.name))
        dirs = [here]
        for base in (here, os.path.dirname(here)):
            try:
                names = sorted(os.listdir(base))
            except OSError:
                continue
            dirs += [os.path.join(base, n) for n in names if n.upper() in ("SPF.DIR", "_N_SPF_DIR", "SPF_DIR")
                     and os.path.join(base, n) not in dirs]
        return dirs

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
        if sinumerik_fast.plain_block(self, ln, src):  # constant G0/G1 X Y Z F, nothing else active
            return False
        line = ln.line
        if self.corners.hold is not None:
            self.corners.hold.blocks += 1
        blk = self.evaluate(ln)
        motion, new_comp = self.modal_codes(blk.gs, line)
        iso = drill.iso_codes(self, blk, src)  # G81 .. G89 / G80: True when this block drills a hole
        end = self.settings(src, blk, motion)
        self.unsupported(blk, line)
        corner.comp_change(self, new_comp)  # a corner where G40/G41/G42 changes: not modelled
        self.comp_on(new_comp, src, line)
        moved = drill.moves_axes(blk.words)  # MCALL: the modal cycle runs after a block with X/Y/Z
        if iso:  # the hole position: G0 in the plane at the level the tool stands on, then the hole
            modal_motion, self.motion = self.motion, 0
            self.move(ln, src, blk.words, 0)
            self.motion = modal_motion
            drill.iso_drill(self, src)
        elif blk.corner or self.corners.active():
            corner.run_move(self, blk.corner, line, lambda: self.move(ln, src, blk.words, motion))
        else:
            self.move(ln, src, blk.words, motion)
        if new_comp == 40 and self.comp_buf is not None:
            corner.comp_end(self)  # the departure move, if it waits for its corner, goes into the compensation
            self.flush_comp(src, line)
        drill.after_block(self, src, moved, blk, stack)
        if self.calls(blk, src, line, stack):
            return False
        for st in blk.jumps:
            if self.jump(st, line, stack):
                return end
        if end:
            if any(f.kind == "unit" for f in stack[1:]):  # M2/M30 in a subprogram: return
                self.ret(stack)
                return False
            corner.finish(self)
            if self.comp_buf is not None:
                self.flush_comp(None, line)
            self.end(src)
        return end

    def evaluate(self, ln: Line) -> Block:
        """Assignments and DEFs take effect in order; words are evaluated and range-checked;
        commands are warned about or handed on (Block.commands); G4 takes its F/S as the dwell."""
        blk = sinumerik_fast.plain_evaluate(self, ln, Block, Value)  # constant G0/G1 X Y Z F (sinumerik_fast.py)
        if blk is not None:
            return blk
        line = ln.line
        blk = Block()
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
        return blk

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
        times = [blk.words.pop(a) for a in ("F", "S") if a in blk.words]
        if len(times) != 1:
            raise self.error(line, col, "G4 needs its dwell time: G4 F<seconds> or G4 S<revolutions>")
        moving = [a for a in blk.words if a in "XYZ" or a in ("I", "J", "K", "CR")]
        if moving:
            raise self.error(line, blk.words[moving[0]].col, "G4 (dwell) stands in a block without motion")
        blk.gs = [(code, c) for code, c in blk.gs if code != 4]

    def assign(self, st: Assign, line: int) -> None:
        if getattr(self.vars.get(st.name), "type", None) == "AXIS":  # AXN=Y, AXN=AXNAME("Y"): an axis of this machine
            v = axes.axis_of(self, st.value, line, st.col)
        else:
            v = self.ev(st.value, line, st.col)
        target = Index(st.name, st.index, st.col) if st.index else Var(st.name, st.col)
        slot = self.slot(target, line, write=True)
        if not slot.set(v):
            raise self.error(line, st.col, f"{st.name} takes a number, not the string \"{v}\"")

    def define(self, st: Def, line: int) -> None:
        for d in st.decls:
            if R_NAME.fullmatch(d.name) or d.name in EXPR_ADDRESSES or len(d.name) == 1:
                raise self.error(line, d.col, f"'{d.name}' is an address or parameter and cannot be a variable name")
            blank = "" if st.type in ("STRING", "AXIS") else 0.0
            if d.dims:
                self.vars[d.name] = self.new_array(st, d, line, blank)
                continue
            slot = Slot(st.type, blank, d.length)
            if d.init is not None:
                init = d.init
                if st.type == "AXIS":  # DEF AXIS AXN=X: an axis of this machine
                    val = axes.axis_of(self, init, line, d.col)
                else:
                    val = self.ev(init, line, d.col)
                if not slot.set(val):
                    raise self.error(line, d.col, f"{d.name} ({st.type}) takes a number, not the string \"{val}\"")
            self.vars[d.name] = slot

    def new_array(self, st: Def, d, line: int, blank) -> ArrayVar:
        dims = []
        for e in d.dims:
            n = self.num(self.ev(e, line, d.col), line, d.col)
            if n != int(n) or not 1 <= n <= MAX_ARRAY:
                raise self.error(line, d.col, f"array dimension {n:.10g}: whole numbers 1 to {MAX_ARRAY:,}")
            dims.append(int(n))
        size = math.prod(dims)
        if size > MAX_ARRAY:
            raise self.error(line, d.col, f"array {d.name} has {size:,} elements, more than {MAX_ARRAY:,}")
        arr = ArrayVar(st.type, tuple(dims), [blank] * size, d.length)
        if d.init is None:
            return arr
        if d.init and d.init[0] == "REP":
            vals = [self.ev(d.init[1], line, d.col)] * size
        else:
            vals = [self.ev(e, line, d.col) for e in d.init]
            if len(vals) > size:
                raise self.error(line, d.col, f"{len(vals)} initial values for the {size} elements of {d.name}")
        for k, v in enumerate(vals):
            if not ElemSlot(arr, k).set(v):
                raise self.error(line, d.col, f"{d.name} ({st.type}) takes numbers, not the string \"{v}\"")
        return arr

    def word(self, st: Word, line: int, blk: Block) -> None:
        val = self.ev(st.value, line, st.col)
        if machine.word(self, st, val, line, blk):  # units, frames, extra axes, T="name", M1=3 (machine)
            return
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

    def check_groups(self, gs: list[tuple[int, int]], line: int) -> None:
        """Two different G codes of one modal group in a block (G90 G91, G17 G18) are an error at the
        second (the shared table rows of interp/core.py; the same code twice is harmless)."""
        seen: dict[str, int] = {}
        for code, col in gs:
            row = G_CODES.get(code)
            if row is None:
                continue
            if row.group in seen and seen[row.group] != code:
                raise self.error(line, col, f"G{code} conflicts with G{seen[row.group]} in the same block "
                                 f"(both {row.group})")
            seen[row.group] = code

    def modal_codes(self, gs: list[tuple[int, int]], line: int) -> tuple[int | None, int | None]:
        """Apply the block's modal G codes; the motion (G0..G3) and the G40/G41/G42 it names."""
        self.check_groups(gs, line)
        gs = machine.g_codes(self, gs, line)  # G70/G71/G700/G710, G54.., G53, G64.. (machine)
        motion = None
        new_comp = None
        for code, col in gs:
            if code in (0, 1, 2, 3):
                if motion is not None and motion != code:
                    raise self.error(line, col, f"G{code} conflicts with G{motion} in the same block")
                motion = code
            elif code in PLANES and self.comp_buf is not None:
                raise self.error(line, col, "the plane cannot change while radius compensation G41/G42 is on")
            elif code in (40, 41, 42):
                new_comp = code
            else:
                self.common_g(code)  # G90/G91, G94/G95, G17/G18/G19
        return motion, new_comp

    def settings(self, src: Src, blk: Block, motion: int | None) -> bool:
        """Spindle, tool (T, D, M6), feed and the motion mode; True when an M2/M30 ends the program."""
        machine.settings(self, src, blk, CYCLES)  # frames, TRAORI, CYCLE800, F under G700 (machine)
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

    def calls(self, blk: Block, src: Src, line: int, stack: list[Frame]) -> bool:
        """Cycles, subprogram calls (NAME, L<n> P<n>) and RET/M17; True when the block hands over
        to another frame (a call or a return)."""
        for st in drill.modal_call(self, blk, line):  # MCALL CYCLE8x(..) / MCALL SUB / MCALL alone
            if isinstance(st, Ret):
                self.ret(stack)
                return True
            if isinstance(st, Call):
                if st.name in IGNORED_CALLS:
                    continue
                if st.name not in CYCLES:  # a PROC with parameters: NAME(1, , R3)
                    if self.call_proc(st, src, blk.words, stack):
                        return True
                    continue  # a declared external subprogram: skipped
                args = [(None if a.value is None else self.ev(a.value, line, a.col), a.col) for a in st.args]
                run_cycle(self, st.name, args, src, st.col)
                continue
            if st.name in self.vars:  # SubCall
                raise self.error(line, st.col, f"'{st.name}' is a variable: write {st.name}=<value> to assign it")
            unit = self.find_unit(st.name, src, st.col, blk.words)
            if unit is None:
                continue  # a declared external subprogram: skipped
            self.call_sub(unit, src, blk.words, stack, st.col)
            return True
        words = blk.words
        if "L" in words:
            lw = words.pop("L")
            if lw.value != int(lw.value):
                raise self.error(line, lw.col, f"L{lw.value:g}: a subprogram number is a whole number")
            unit = self.find_unit(f"L{int(lw.value)}", src, lw.col, words)
            if unit is None:
                return False
            self.call_sub(unit, src, words, stack, lw.col)
            return True
        if "P" in words:
            raise self.error(line, words["P"].col, "P (repeat count) only goes with a subprogram call")
        return False

    def jump(self, st, line: int, stack: list[Frame]) -> bool:
        """GOTO/Branch/CASE (True when taken) or REPEAT (always taken)."""
        fr = stack[-1]
        cur = fr.pc - 1
        if isinstance(st, Branch):
            if st.cond is not None and bool(self.num(self.ev(st.cond, line, st.col), line, st.col)) != st.when:
                return False
            fr.pc = st.target
            if st.target <= cur:
                self.check_loop(stack, line, st)
            return True
        if isinstance(st, Case):
            st = self.case_jump(st, line)
            if st is None:
                return False
        if isinstance(st, Goto):
            if st.cond is not None and not self.num(self.ev(st.cond, line, st.col), line, st.col):
                return False
            idx = self.find_label(fr.unit, self.goto_label(st, line), line, st.col, st.kind, cur)
            if idx is None:  # GOTOC: no alarm when the label is missing
                return False
            fr.pc = idx
            if idx <= cur:
                self.check_loop(stack, line, st)
            return True
        return self.repeat(st, line, stack)

    def goto_label(self, st: Goto, line: int) -> str:
        """The destination: the written label, or the computed one (GOTOF "STEP_" << NR)."""
        if st.target is None:
            return st.label
        v = self.ev(st.target, line, st.col)
        if not isinstance(v, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*|N?[0-9]+", v.strip()):
            raise self.error(line, st.col, f"{st.kind}: the computed destination {to_text(v)!r} is no label")
        v = v.strip().upper()
        return f"N{int(v.lstrip('N'))}" if re.fullmatch(r"N?[0-9]+", v) else v

    def case_jump(self, st: Case, line: int) -> Goto | None:
        """The jump of the first CASE value equal to the expression, else DEFAULT (None: go on)."""
        v = self.ev(st.value, line, st.col)
        for const, goto in st.branches:
            c = self.ev(const, line, st.col)
            if isinstance(c, str) != isinstance(v, str):
                raise self.error(line, st.col, "CASE compares a string with a number")
            if c == v:
                return goto
        return st.default

    def repeat(self, st: Repeat, line: int, stack: list[Frame]) -> bool:
        fr = stack[-1]
        cur = fr.pc - 1
        a = self.find_label(fr.unit, st.start, line, st.col, "GOTOB", cur)
        n = self.num(self.ev(st.count, line, st.col), line, st.col)
        if n != int(n) or not 1 <= n <= PASS_LIMIT:
            raise self.error(line, st.col, f"REPEAT P must be a whole number from 1 to {PASS_LIMIT} (got {n:.10g})")
        if st.end is None:
            if a >= cur:
                raise self.error(line, st.col, f"REPEAT {st.start}: the label must come before this block")
            stop = cur
        else:
            b = self.nearest(fr.unit, st.end, a, forward=True)
            if b is None:
                b = self.find_label(fr.unit, st.end, line, st.col, "GOTO", cur)
            if b < a:
                raise self.error(line, st.col, f"REPEAT {st.start} {st.end}: the end label comes before the start")
            stop = b + 1
        if len(stack) > MAX_STACK or a <= cur < stop:
            raise self.error(line, st.col, f"REPEAT sections and subprograms nested deeper than {MAX_STACK} "
                             "(a REPEAT inside the section it repeats?)")
        self.repeat_estimate(stack, fr.unit, a, stop, int(n), line, st)
        stack.append(Frame(fr.unit, pc=a, stop=stop, restart=a, ret=cur + 1, count=int(n), kind="repeat",
                           calls=fr.calls, scope=fr.scope))
        return True

    def section_blocks(self, unit: Unit, a: int, stop: int, depth: int = 0) -> int:
        """Blocks one pass of lines [a, stop) runs, with the nested REPEATs of constant count
        multiplied out (the CNC8x6 G73 count; other jumps and calls count as one block)."""
        key = (id(unit), a, stop)
        if key in self.repeat_sizes:
            return self.repeat_sizes[key]
        total = 0
        for idx in range(a, min(stop, len(unit.lines))):
            ln = unit.lines[idx]
            total += 1 if ln.stmts else 0
            for st in ln.stmts:
                if isinstance(st, Repeat) and isinstance(st.count, Num) and depth < MAX_STACK:
                    s0 = unit.all_labels.get(st.start, [None])[0]
                    if s0 is None or s0 >= idx:
                        continue
                    end = (unit.labels.get(st.end, idx - 1) + 1) if st.end else idx
                    if s0 <= idx < end:
                        continue
                    total += int(st.count.value) * self.section_blocks(unit, s0, end, depth + 1)
        self.repeat_sizes[key] = total
        return total

    def repeat_estimate(self, stack: list[Frame], unit: Unit, a: int, stop: int, n: int, line: int, st) -> None:
        """A REPEAT whose passes (times the passes still to come of the REPEATs around it) would
        run past [simulation] max_blocks is refused at once, not after running millions of blocks."""
        est = n * self.section_blocks(unit, a, stop)
        for f in stack:
            if f.kind == "repeat" or f.count > 1:
                est *= max(f.count, 1)
        if self.executed + est > self.cfg.max_blocks:
            raise self.error(line, st.col, f"the program does not end in time: REPEAT {st.start} would run about "
                             f"{est:,} blocks, more than the {self.cfg.max_blocks:,} of [simulation] max_blocks")

    def call_proc(self, st: Call, src: Src, words: dict[str, Value], stack: list[Frame]) -> bool:
        """NAME(args) / L140(2): a subprogram with parameters (an unknown name is an error naming
        it as a cycle, function or subprogram); CALL "NAME": the subprogram a string names; EXTCALL
        "path/NAME.SPF": the program a string names on external storage, found by its name. False
        when the subprogram is a declared external one (skipped, ``find_unit``)."""
        if st.name in ("CALL", "EXTCALL"):
            name = self.ev(st.args[0].value, src.line, st.col)
            if st.name == "EXTCALL" and isinstance(name, str):
                name = call_name(name)
            if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name.strip()):
                raise self.error(src.line, st.col, f"{st.name} needs a subprogram name as a string, "
                                 f"not {to_text(name)!r}")
            st = Call(st.col, name.strip().upper(), ())
        try:
            unit = self.find_unit(st.name, src, st.col, words, st.args)
        except SubprogramMissing:
            raise self.error(src.line, st.col, f"unknown cycle, function or subprogram {st.name} (no PROC {st.name} "
                             f"in this file, no {st.name}.spf beside it or in [machine] subprogram_path"
                             f"{missing_hint(st.name)})") from None
        if unit is None:
            return False
        self.call_sub(unit, src, words, stack, st.col, st.args)
        return True

    def find_unit(self, name: str, src: Src, col: int, words: dict[str, Value], args: tuple = ()) -> Unit | None:
        """The subprogram a call names (``find_sub``), or None when it is not found but declared in
        the setup's [machine] external_subprograms: the call is skipped (its P repeat count and its
        arguments checked, one warning per name) and the tool stays where it was."""
        try:
            return self.find_sub(name, src.line, col)
        except SubprogramMissing:
            if name not in self.externals:
                raise
        if "P" in words:
            p = words.pop("P")
            if p.value != int(p.value) or p.value < 1:
                raise self.error(src.line, p.col, "P (repeat count) must be a whole number of at least 1")
        for a in args:  # an argument that is not a bare name (an axis, a VAR target) is evaluated: its errors count
            if a.value is not None and not (isinstance(a.value, Var) and a.value.name not in self.vars):
                self.ev(a.value, src.line, a.col)
        self.external_note(name, Src(src.program, src.line, col, src.label, src.calls))
        return None

    def external_note(self, name: str, src: Src) -> None:
        """The one warning of a skipped call of a declared external subprogram ``name``."""
        if f"external:{name}" in self.warned:
            return
        self.warned.add(f"external:{name}")
        self.warn(src, f"{name} is declared external in the setup ([machine] external_subprograms): its motion is "
                       "not simulated, the tool is taken to stay where it was")

    def unsupported(self, blk: Block, line: int) -> None:
        """A machine keyword ``settings`` did not take (it implements the ones it knows) is an
        error at its column: running on as if it were not there would cut elsewhere."""
        for name, col in blk.commands:
            raise self.error(line, col, f"{name} is not supported by the simulator")

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
        fr = stack.pop()
        if fr.saved is not None:  # PROC ... SAVE
            self.restore_modal(fr.saved)
        self.vars = stack[-1].scope

    def call_sub(self, unit: Unit, src: Src, words: dict[str, Value], stack: list[Frame], col: int,
                 args: tuple = ()) -> None:
        n = 1
        if "P" in words:
            p = words.pop("P")
            if p.value != int(p.value) or p.value < 1:
                raise self.error(src.line, p.col, "P (repeat count) must be a whole number of at least 1")
            n = int(p.value)
        if len(stack) > 16:
            raise self.error(src.line, col, "subprograms nested deeper than 16 levels (recursion?)")
        scope = self.bind(unit, args, src.line, col)
        calls = stack[-1].calls + ((src.program, src.line),)
        saved = self.save_modal() if unit.proc is not None and unit.proc.save else None
        stack.append(Frame(unit, pc=0, stop=len(unit.lines), restart=0, ret=stack[-1].pc, count=n, kind="unit",
                           calls=calls, scope=scope, saved=saved))
        self.vars = scope

    def bind(self, unit: Unit, args: tuple, line: int, col: int) -> dict:
        """The called PROC's parameters: values (converted to their type; an omitted one takes its
        default or 0) and VAR parameters sharing the caller's variable, R parameter or element."""
        params = unit.proc.params if unit.proc is not None else ()
        if len(args) > len(params):
            raise self.error(line, args[len(params)].col if args[len(params)].col else col,
                             f"{unit.name} takes {len(params)} parameter(s), not {len(args)}")
        scope: dict = {}
        for k, p in enumerate(params):
            arg = args[k] if k < len(args) else None
            given = arg is not None and arg.value is not None
            if p.var:
                if not given:
                    raise self.error(line, arg.col if arg else col,
                                     f"{unit.name}: parameter {k + 1} ({p.name}) is VAR: pass a variable")
                if not isinstance(arg.value, (Var, Index)):
                    raise self.error(line, arg.col, f"{unit.name}: parameter {k + 1} ({p.name}) is VAR: pass a "
                                     "variable, an R parameter or an array element, not a value")
                held = self.vars.get(arg.value.name) if isinstance(arg.value, Var) else None
                if p.array != isinstance(held, ArrayVar):
                    raise self.error(line, arg.col, f"{unit.name}: parameter {k + 1} ({p.name}) "
                                     f"{'is an array: pass an array' if p.array else 'is no array: pass one element'}")
                scope[p.name] = held if p.array else self.slot(arg.value, line, write=True)
                continue
            value = self.ev if p.type != "AXIS" else functools.partial(axes.axis_of, self)  # PROC P(AXIS A): P(X)
            v = value(arg.value, line, arg.col) if given else (
                value(p.default, line, col) if p.default is not None else ("" if p.type in ("STRING", "AXIS") else 0.0))
            slot = Slot(p.type, "" if p.type in ("STRING", "AXIS") else 0.0)
            if not slot.set(v):
                raise self.error(line, arg.col if given else col,
                                 f"{unit.name}: parameter {k + 1} ({p.name}) is {p.type}, not the string \"{v}\"")
            scope[p.name] = slot
        return scope

    def save_modal(self) -> dict:
        """PROC ... SAVE: the modal state to put back on return (the G groups and what settings
        keeps modal; SAVED_MODAL lists the attributes, the machine functions' among them)."""
        return {a: copy.deepcopy(getattr(self, a)) for a in SAVED_MODAL}

    def restore_modal(self, saved: dict) -> None:
        for a, v in saved.items():
            setattr(self, a, v)

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
        machine.move(self, src, words, run_cycle)  # WCS -> machine: units, frames, extra axes (machine)
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
        cw = (self.motion == 2) != self.machine.arc_flip  # a mirror turns G2 into G3
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
        """The centre from I/J/K: incremental from the start (core.arc_centre, as every dialect), or
        =AC(..) absolute."""
        a, b, _ = PLANE_AXES[self.plane]
        given = {i: words.pop(AXIS_LETTER[i]) for i in (a, b) if AXIS_LETTER[i] in words}
        if not given:
            raise self.error(line, 1, f"circle needs its centre ({AXIS_LETTER[a]}/{AXIS_LETTER[b]}) or a radius CR=")
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
