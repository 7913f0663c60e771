"""Values and variables of the running program: expressions, R parameters, DEF'd variables and
arrays, system variables and setup data, functions.
"""
from __future__ import annotations

import math

from ..core.modal import PLANE_AXES
from . import axes, corners as corner
from .syntax import (Assign, BinOp, Def, EXPR_ADDRESSES, FuncCall, Index, Line, Neg, Not, Num, R_LIMIT, R_NAME, RIndex, Stmt,
    Str, STRING_FUNCS, Var)
from .tables import COMPARE, MAX_ARRAY, UNSUPPORTED_NAMES
from dataclasses import dataclass, field


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
    """One block as it runs through ``core.Interpreter.execute``: its Line and what reading its
    statements gives (words, G and M codes, calls and jumps), then what the hooks decide about it."""
    ln: Line
    words: dict[str, Value] = field(default_factory=dict)
    gs: list[tuple[int, int]] = field(default_factory=list)  # (code, column)
    ms: list[tuple[int, int]] = field(default_factory=list)
    calls: list[Stmt] = field(default_factory=list)  # Call | SubCall | Ret
    jumps: list[Stmt] = field(default_factory=list)  # Goto | Repeat | Case | Branch
    # bare machine keywords (name, column) of syntax.MACHINE_COMMANDS: ``settings`` removes
    # the ones it implements; any left over is an error (``unsupported``)
    commands: list[tuple[str, int]] = field(default_factory=list)
    corner: dict = field(default_factory=dict)  # CHF CHR RND RNDM FRC FRCM -> (value, column) (corners)
    comp: int | None = None  # the G40/G41/G42 it names
    drills: bool = False  # an ISO drilling cycle drills a hole at its position (drilling.iso_codes)
    end: bool = False  # M2/M30
    moved: bool = False  # it programs X, Y or Z (a modal call runs after it: drilling.after_block)

    @property
    def line(self) -> int:
        return self.ln.line


class Values:
    """The values of the running program: expressions, R parameters, DEF'd variables and arrays,
    system variables and setup data, functions.

    A part of ``Sinumerik`` (interpreter.py): its methods work on the state declared in
    ``Sinumerik.__init__``."""

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
