"""RS274NGC parameters and expression evaluation (LinuxCNC 2.9 semantics).

Numbered parameters #1..#5602 (``#1``-``#30`` are local to a subroutine call: its arguments), named
parameters ``#<name>`` (local to the call level that set them) and global ones ``#<_name>``; the
predefined read-only ones (``#<_x>``, ``#5420`` ...) come from the machine state through
``Parameters.predefined``. Angles are in degrees; comparisons EQ/NE use LinuxCNC's tolerance.
"""
from __future__ import annotations

import math

import numpy as np

from cutsim.interp.errors import CutsimError

MAX_NUMBERED = 5602
TOLERANCE_EQUAL = 0.0001
# LinuxCNC's arithmetic step by step, so results agree to the last bit (a MOD of a huge power turns a
# last-bit difference into any value): SIN/COS/TAN of (x * pi) / 180 in x87 long double (cos[90] is
# -2.5e-20, not 6.1e-17); ATAN/ASIN/ACOS in double, the angle times 180 in double, divided by pi in
# long double; each result stored as a double.
_L = np.longdouble
_PI = _L("3.14159265358979323846264338327950288")
_180 = _L(180)


def _degrees(radians: float) -> float:
    return float(_L(radians * 180.0) / _PI)


def _trig(f, degrees: float) -> float:
    return float(f((_L(degrees) * _PI) / _180))
# Parameters the machine computes on every read (current position, tool, modes): never stored.
READ_ONLY = set(range(5400, 5411)) | set(range(5420, 5429)) | {5220, 5399}


class Unreadable(Exception):
    """A predefined parameter that cannot be read now (the position under cutter radius compensation)."""


def _predefined(params, name: str) -> bool:
    try:
        return params.predefined(name) is not None
    except Unreadable:
        return True


class Parameters:
    """The parameter store with its call frames. ``predefined(key)`` (set by the machine) answers
    the computed parameters (an int for numbered ones, a name for ``_x``-style ones) or None."""

    def __init__(self, program: str, initial: dict[int, float]):
        self.program = program
        self.numbered: dict[int, float] = dict(initial)
        self.globals: dict[str, float] = {}
        self.frames: list[dict[str, float]] = [{}]  # named locals of each call level
        self.saved: list[dict[int, float]] = []  # #1..#30 of each caller
        self.predefined = lambda key: None

    # -- call frames -------------------------------------------------------------------------------
    def push(self, args: list[float]) -> None:
        self.saved.append({i: self.numbered.get(i, 0.0) for i in range(1, 31)})
        for i in range(1, 31):
            self.numbered[i] = args[i - 1] if i <= len(args) else 0.0
        self.frames.append({})

    def push_shared(self) -> None:
        """A call level whose #1-#30 are the caller's (M98): only the named locals are its own."""
        self.saved.append({})
        self.frames.append({})

    def pop(self) -> None:
        self.numbered.update(self.saved.pop())
        self.frames.pop()

    # -- reading and writing -----------------------------------------------------------------------
    def get_numbered(self, n: int, line: int, col: int) -> float:
        if not 1 <= n <= MAX_NUMBERED:
            raise CutsimError(self.program, line, col, f"parameter number #{n} out of range (1 to {MAX_NUMBERED})")
        if n in READ_ONLY:
            try:
                v = self.predefined(n)
            except Unreadable as e:
                raise CutsimError(self.program, line, col, str(e)) from None
            if v is not None:
                return v
        return self.numbered.get(n, 0.0)

    def set_numbered(self, n: int, value: float, line: int, col: int) -> None:
        if not 1 <= n <= MAX_NUMBERED:
            raise CutsimError(self.program, line, col, f"parameter number #{n} out of range (1 to {MAX_NUMBERED})")
        if n in READ_ONLY:
            raise CutsimError(self.program, line, col, f"parameter #{n} is read-only")
        self.numbered[n] = value

    def get_named(self, name: str, line: int, col: int) -> float:
        try:
            v = self.lookup(name)
        except Unreadable as e:
            raise CutsimError(self.program, line, col, str(e)) from None
        if v is None:
            raise CutsimError(self.program, line, col, f"named parameter #<{name}> not defined")
        return v

    def exists(self, name: str) -> bool:
        try:
            return self.lookup(name) is not None
        except Unreadable:
            return True

    def lookup(self, name: str) -> float | None:
        if name.startswith("_"):
            if name in self.globals:
                return self.globals[name]
            return self.predefined(name)
        return self.frames[-1].get(name)

    def set_named(self, name: str, value: float, line: int, col: int) -> None:
        if name.startswith("_"):
            if name not in self.globals and _predefined(self, name):
                raise CutsimError(self.program, line, col, f"#<{name}> is a predefined read-only parameter")
            self.globals[name] = value
        else:
            self.frames[-1][name] = value


class Evaluator:
    """Evaluates the expression trees of ``syntax`` against a ``Parameters`` store; errors name
    the line and the column of the operator or function that failed."""

    def __init__(self, params: Parameters, program: str):
        self.p = params
        self.program = program

    def error(self, line: int, col: int, message: str) -> CutsimError:
        return CutsimError(self.program, line, col, message)

    def ref_number(self, ref, line: int, col: int) -> int:
        v = self.value(ref[1], line, col)
        if abs(v - round(v)) > TOLERANCE_EQUAL:
            raise self.error(line, col, f"parameter number {v:g} is not a whole number")
        return int(round(v))

    def get(self, ref, line: int, col: int) -> float:
        kind = ref[0]
        if kind == "index":
            return self.p.get_numbered(ref[1], line, col)
        if kind == "name":
            return self.p.get_named(ref[1], line, col)
        return self.p.get_numbered(self.ref_number(ref, line, col), line, col)

    def set(self, ref, value: float, line: int, col: int) -> None:
        kind = ref[0]
        if kind == "index":
            self.p.set_numbered(ref[1], value, line, col)
        elif kind == "name":
            self.p.set_named(ref[1], value, line, col)
        else:
            self.p.set_numbered(self.ref_number(ref, line, col), value, line, col)

    def value(self, node, line: int, col: int) -> float:
        kind = node[0]
        if kind == "num":
            return node[1]
        if kind == "par":
            return self.get(node[1], line, col)
        if kind == "neg":
            return -self.value(node[1], line, col)
        if kind == "bin":
            return self.binary(node[1], self.value(node[2], line, col), self.value(node[3], line, col), line, node[4])
        if kind == "fn":
            return self.function(node[1], self.value(node[2], line, col), line, node[3])
        if kind == "atan":
            y, x = self.value(node[1], line, col), self.value(node[2], line, col)
            return _degrees(math.atan2(y, x))
        if kind == "exists":
            return 1.0 if self.p.exists(node[1]) else 0.0
        raise AssertionError(node)  # pragma: no cover - the parser makes no other node

    def binary(self, op: str, a: float, b: float, line: int, col: int) -> float:
        if op == "+":
            return a + b
        if op == "-":
            return a - b
        if op == "*":
            return a * b
        if op == "/":
            if b == 0.0:
                raise self.error(line, col, "attempt to divide by zero")
            return a / b
        if op == "mod":
            if b == 0.0:
                raise self.error(line, col, "attempt to divide by zero (MOD)")
            r = math.fmod(a, b)
            return r + abs(b) if r < 0.0 else r
        if op == "**":
            if a < 0.0 and b != int(b):
                raise self.error(line, col, "attempt to raise a negative number to a non-integer power")
            if a == 0.0 and b < 0.0:
                raise self.error(line, col, "attempt to divide by zero (0 to a negative power)")
            try:
                return float(a ** b)
            except OverflowError:
                raise self.error(line, col, "number too large in the expression") from None
        if op == "eq":
            return 1.0 if abs(a - b) < TOLERANCE_EQUAL else 0.0
        if op == "ne":
            return 0.0 if abs(a - b) < TOLERANCE_EQUAL else 1.0
        if op == "gt":
            return 1.0 if a > b else 0.0
        if op == "ge":
            return 1.0 if a >= b else 0.0
        if op == "lt":
            return 1.0 if a < b else 0.0
        if op == "le":
            return 1.0 if a <= b else 0.0
        if op == "and":
            return 1.0 if (a != 0.0 and b != 0.0) else 0.0
        if op == "or":
            return 1.0 if (a != 0.0 or b != 0.0) else 0.0
        if op == "xor":
            return 1.0 if ((a != 0.0) != (b != 0.0)) else 0.0
        raise AssertionError(op)  # pragma: no cover

    def function(self, name: str, x: float, line: int, col: int) -> float:
        if name == "abs":
            return abs(x)
        if name in ("acos", "asin"):
            if not -1.0 <= x <= 1.0:
                raise self.error(line, col, f"{name.upper()} argument {x:g} out of range (-1 to 1)")
            return _degrees(math.acos(x) if name == "acos" else math.asin(x))
        if name in ("cos", "sin", "tan"):
            return _trig({"cos": np.cos, "sin": np.sin, "tan": np.tan}[name], x)
        if name == "exp":
            try:
                return math.exp(x)
            except OverflowError:
                raise self.error(line, col, "EXP argument too large") from None
        if name in ("fix", "fup"):  # C's floor/ceil keep the sign of a zero (fup[-0.15] is -0: atan sees it)
            v = float(math.floor(x) if name == "fix" else math.ceil(x))
            return math.copysign(v, x) if v == 0.0 else v
        if name == "round":
            # LinuxCNC rounds through a 32-bit int: out of its range (or NaN) x86 gives INT_MIN
            r = x + (-0.5 if x < 0.0 else 0.5)
            return float(int(r)) if -2147483649.0 < r < 2147483648.0 else -2147483648.0
        if name == "ln":
            if x <= 0.0:
                raise self.error(line, col, f"LN of zero or a negative number ({x:g})")
            return math.log(x)
        if name == "sqrt":
            if x < 0.0:
                raise self.error(line, col, f"SQRT of a negative number ({x:g})")
            return math.sqrt(x)
        raise AssertionError(name)  # pragma: no cover
