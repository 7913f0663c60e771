"""ISG (TwinCAT CNC) language pieces: arithmetic expressions in ``[ ]`` and their evaluation,
variable references (``P1``, ``@P1``, ``V.P.NAME[i]``, ``V.L.``, ``V.S.``, ``V.E.``, ``V.G.``),
``#VAR ... #ENDVAR`` declarations and the control statements' keywords (docs/dialects/isg.md,
"Language").

An expression is compiled once, when its line is scanned, into a Python closure ``f(env) -> value``
(a float or a string); ``env`` is the interpreter (interpreter.py), which answers ``read_var`` and
``read_param``. Every error names the program, the line and the column of the offending token.
"""
from __future__ import annotations

import math
import re

from ..errors import CutsimError
from ..core.lexer import NUMBER_LIMIT, foreign_digit

NUM = re.compile(r"(?:[0-9]+\.?[0-9]*|\.[0-9]+)")
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
MAX_DEPTH = 32  # brackets, functions and signs nested in one expression (each costs ~12 Python frames)
CONTROL = {"IF", "ELSEIF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "DO", "ENDDO", "SWITCH",
           "CASE", "DEFAULT", "ENDSWITCH", "BREAK", "CONTINUE", "GOTO"}
SCOPES = {"P": "program-global", "L": "local", "S": "self-retaining", "E": "external", "G": "global"}


def _deg(f):
    return lambda x: f(math.radians(x))


def _adeg(f):
    return lambda x: math.degrees(f(x))


def _round(x: float) -> float:
    return float(math.floor(x + 0.5)) if x >= 0 else -float(math.floor(-x + 0.5))


# name -> (arity, function); angles in degrees as on the controller
FUNCS = {
    "SIN": (1, _deg(math.sin)), "COS": (1, _deg(math.cos)), "TAN": (1, _deg(math.tan)),
    "ASIN": (1, _adeg(math.asin)), "ACOS": (1, _adeg(math.acos)), "ATAN": (1, _adeg(math.atan)),
    "ATAN2": (2, lambda y, x: math.degrees(math.atan2(y, x))),
    "ABS": (1, abs), "SQR": (1, lambda x: x * x), "SQRT": (1, math.sqrt), "EXP": (1, math.exp),
    "LN": (1, math.log), "LOG": (1, math.log10), "DEXP": (1, lambda x: 10.0 ** x),
    "INT": (1, lambda x: float(math.trunc(x))), "FRACT": (1, lambda x: x - math.trunc(x)),
    "ROUND": (1, _round), "FLOOR": (1, lambda x: float(math.floor(x))), "CEIL": (1, lambda x: float(math.ceil(x))),
    "SIGN": (1, lambda x: float((x > 0) - (x < 0))), "MIN": (2, min), "MAX": (2, max),
}
CONSTS = {"TRUE": 1.0, "FALSE": 0.0, "PI": math.pi}
# string conversions (messages and machine data texts): value -> string
STR_FUNCS = {"REAL_TO_STR": lambda x: f"{x:.6f}".rstrip("0").rstrip(".") if isinstance(x, float) else str(x),
             "INT_TO_STR": lambda x: str(int(x)) if not isinstance(x, str) else x}


class Cursor:
    """A position in one line of program text with the error context."""

    __slots__ = ("prog", "line", "text", "i", "depth")

    def __init__(self, prog: str, line: int, text: str, i: int = 0):
        self.prog, self.line, self.text, self.i, self.depth = prog, line, text, i, 0

    def error(self, msg: str, i: int | None = None) -> CutsimError:
        return CutsimError(self.prog, self.line, (self.i if i is None else i) + 1, msg)

    def skip(self) -> None:
        t, n = self.text, len(self.text)
        while self.i < n and t[self.i] in " \t":
            self.i += 1

    def peek(self, k: int = 0) -> str:
        j = self.i + k
        return self.text[j] if j < len(self.text) else ""

    def at_word(self, word: str) -> bool:
        """``word`` (upper case) at the cursor, not followed by an identifier character."""
        t = self.text
        j = self.i + len(word)
        return t[self.i:j].upper() == word and not (j < len(t) and (t[j].isalnum() or t[j] == "_"))


def _num(x, cur: Cursor, col: int, what: str) -> float:
    if isinstance(x, str):
        raise CutsimError(cur.prog, cur.line, col, f"{what}: the string \"{x}\" is not a number")
    return x


def _checked(v: float, prog: str, line: int, col: int) -> float:
    if not math.isfinite(v) or abs(v) > NUMBER_LIMIT * 1e4:
        raise CutsimError(prog, line, col, "the expression's value is out of range (overflow)")
    return v


# -- expressions -----------------------------------------------------------------------------------
BINARY = [  # precedence levels, lowest first
    (("||", "OR"), ("XOR",)),
    (("&&", "AND"),),
    (("|",),),
    (("&",),),
    (("==", "!=", "<>"),),
    (("<=", ">=", "<", ">"),),
    (("+", "-"),),
    (("*", "/", "MOD"),),
]
LEVEL_OPS = [tuple(o for group in level for o in group) for level in BINARY]
_FIRST = {o[0] for level in LEVEL_OPS for o in level} | {o[0].lower() for level in LEVEL_OPS for o in level}
VAR_HEAD = re.compile(r"[Vv]\.([A-Za-z]+)\.")


def _op_at(cur: Cursor, ops) -> str | None:
    cur.skip()
    if cur.i >= len(cur.text) or cur.text[cur.i] not in _FIRST:
        return None
    for op in ops:
        if op.isalpha():
            if cur.at_word(op):
                return op
        elif cur.text.startswith(op, cur.i):
            if op in ("*",) and cur.text.startswith("**", cur.i):
                continue
            if op in ("<", ">") and cur.text.startswith(("<=", ">=", "<>"), cur.i):
                continue
            if op in ("&", "|") and cur.text.startswith(("&&", "||"), cur.i):
                continue
            return op
    return None


def _apply(op: str, a, b, prog: str, line: int, col: int):
    if op in ("==", "!=", "<>"):
        eq = a == b
        return float(eq if op == "==" else not eq)
    if op == "+" and isinstance(a, str) and isinstance(b, str):
        return a + b  # string concatenation
    if isinstance(a, str) or isinstance(b, str):
        raise CutsimError(prog, line, col, f"operator {op} needs numbers, not a string")
    if op == "+":
        r = a + b
    elif op == "-":
        r = a - b
    elif op == "*":
        r = a * b
    elif op == "/":
        if b == 0:
            raise CutsimError(prog, line, col, "division by zero")
        r = a / b
    elif op == "MOD":
        if b == 0:
            raise CutsimError(prog, line, col, "MOD by zero")
        r = math.fmod(a, b)
    elif op == "**":
        try:
            r = float(a) ** float(b)
        except (OverflowError, ZeroDivisionError):
            raise CutsimError(prog, line, col, f"{a} ** {b} cannot be computed") from None
        if isinstance(r, complex):
            raise CutsimError(prog, line, col, f"{a} ** {b} has no real value")
    elif op == "<":
        r = float(a < b)
    elif op == "<=":
        r = float(a <= b)
    elif op == ">":
        r = float(a > b)
    elif op == ">=":
        r = float(a >= b)
    elif op in ("&&", "AND"):
        r = float(bool(a) and bool(b))
    elif op in ("||", "OR"):
        r = float(bool(a) or bool(b))
    elif op == "XOR":
        r = float(bool(a) != bool(b))
    elif op in ("&", "|"):
        if a != int(a) or b != int(b):
            raise CutsimError(prog, line, col, f"bit operation {op} needs whole numbers")
        r = float((int(a) & int(b)) if op == "&" else (int(a) | int(b)))
    else:  # pragma: no cover - every operator of BINARY is listed
        raise AssertionError(op)
    return _checked(r, prog, line, col)


def expression(cur: Cursor, level: int = 0):
    """A full expression at the cursor (binary operators, spaces allowed): a closure env -> value."""
    if level == len(BINARY):
        return _power(cur)
    ops = LEVEL_OPS[level]
    left = expression(cur, level + 1)
    while True:
        op = _op_at(cur, ops)
        if op is None:
            return left
        col = cur.i + 1
        cur.i += len(op)
        right = expression(cur, level + 1)
        left = _bin(op, left, right, cur.prog, cur.line, col)


def _bin(op, f, g, prog, line, col):
    return lambda env: _apply(op, f(env), g(env), prog, line, col)


def _power(cur: Cursor):
    base = unary(cur)
    cur.skip()
    if cur.text.startswith("**", cur.i):
        col = cur.i + 1
        cur.i += 2
        cur.depth += 1
        if cur.depth > MAX_DEPTH:
            raise cur.error(f"expression nested more than {MAX_DEPTH} deep")
        exp = _power(cur)  # right-associative
        cur.depth -= 1
        return _bin("**", base, exp, cur.prog, cur.line, col)
    return base


def unary(cur: Cursor):
    """A signed primary: ``-x``, ``+x``, ``!x`` / ``NOT x``, or a primary."""
    cur.skip()
    c = cur.peek()
    cur.depth += 1
    if cur.depth > MAX_DEPTH:
        raise cur.error(f"expression nested more than {MAX_DEPTH} deep")
    try:
        if c and c in "+-\u2212":  # "" (the end of the line) is in every string
            col = cur.i + 1
            cur.i += 1
            f = unary(cur)
            if c == "+":
                return f
            return lambda env: -_num(f(env), cur, col, "sign")
        if c == "!" or (c and c in "Nn" and cur.at_word("NOT")):
            col = cur.i + 1
            cur.i += 1 if c == "!" else 3
            f = unary(cur)
            return lambda env: float(not _num(f(env), cur, col, "NOT"))
        return primary(cur)
    finally:
        cur.depth -= 1


def _is_call(cur: Cursor, n: int) -> bool:
    j = cur.i + n
    t = cur.text
    while j < len(t) and t[j] in " \t":
        j += 1
    return j < len(t) and t[j] == "["


def primary(cur: Cursor):
    """A number, ``[expr]``, a string, a parameter or variable, a constant or a function call."""
    cur.skip()
    t, i = cur.text, cur.i
    c = cur.peek()
    if c == "[":  # its depth is counted by unary() around it
        cur.i += 1
        f = expression(cur)
        cur.skip()
        if cur.peek() != "]":
            raise cur.error("']' expected to close the '[' at column %d" % (i + 1))
        cur.i += 1
        return f
    if c == '"':
        j = t.find('"', i + 1)
        if j < 0:
            raise cur.error("string is not closed by '\"'")
        s = t[i + 1:j]
        cur.i = j + 1
        return lambda env: s
    m = NUM.match(t, i)
    if m:
        foreign_digit(cur.prog, cur.line, t, m.end())
        if m.end() < len(t) and (t[m.end()] == "." or t[m.end()].isdigit()):
            raise cur.error(f"malformed number '{t[i:m.end() + 1]}'")
        v = float(m.group(0))
        cur.i = m.end()
        return lambda env: v
    foreign_digit(cur.prog, cur.line, t, i)
    if c == "@" and cur.peek(1) in ("P", "p"):
        return param(cur)
    m = IDENT.match(t, i)
    if not m:
        raise cur.error("a number, a parameter, a variable or '[' expected" if c else
                        "the expression ends too early")
    word = m.group(0).upper()
    if word.startswith("V") and cur.peek(1) == ".":
        return variable(cur)
    if word[0] == "P" and word[1:].isdigit():
        return param(cur)
    if word == "P" and cur.peek(1) == "[":
        return param(cur)
    if word in FUNCS:
        return call(cur, word)
    if word == "EXIST" and _is_call(cur, 5):
        cur.i = m.end()
        cur.skip()
        cur.i += 1
        cur.skip()
        if not (cur.peek() in "Vv" and cur.peek(1) == "."):
            raise cur.error("EXIST[...] asks for a variable: EXIST[V.P.NAME]")
        scope, keyf, vcol = var_ref(cur)
        cur.skip()
        if cur.peek() != "]":
            raise cur.error("']' expected to close EXIST[")
        cur.i += 1
        return lambda env: float(env.exists(scope, keyf(env)))
    if word in STR_FUNCS:
        cur.i = m.end()
        cur.skip()
        if cur.peek() != "[":
            raise cur.error(f"{word} needs its argument in '[ ]'")
        arg = primary(cur)
        fn = STR_FUNCS[word]
        return lambda env: fn(arg(env))
    if word in CONSTS:
        cur.i = m.end()
        v = CONSTS[word]
        return lambda env: v
    if _is_call(cur, len(word)):
        raise cur.error(f"unknown function {word}[...] (the simulator knows {', '.join(sorted(FUNCS))})")
    raise cur.error(f"'{m.group(0)}' is not a number, parameter (P1), variable (V.P.NAME) or function")


def arguments(cur: Cursor, what: str) -> list:
    """The expressions of the list ``[a, b, ...]`` at the cursor (on its '['), the cursor after its
    ']'; ``what`` names the list in the error for a missing ']'."""
    cur.i += 1
    args = [expression(cur)]
    cur.skip()
    while cur.peek() == ",":
        cur.i += 1
        args.append(expression(cur))
        cur.skip()
    if cur.peek() != "]":
        raise cur.error(f"']' expected to close {what}")
    cur.i += 1
    return args


def call(cur: Cursor, name: str):
    col = cur.i + 1
    cur.i += len(name)
    cur.skip()
    if cur.peek() != "[":
        raise cur.error(f"{name} needs its argument in '[ ]'")
    args = arguments(cur, f"{name}[")
    arity, fn = FUNCS[name]
    if len(args) != arity:
        raise CutsimError(cur.prog, cur.line, col, f"{name} takes {arity} argument{'s' if arity > 1 else ''}, "
                          f"not {len(args)}")
    prog, line = cur.prog, cur.line

    def run(env):
        vals = [_num(a(env), cur, col, name) for a in args]
        try:
            r = fn(*vals)
        except (ValueError, OverflowError):
            raise CutsimError(prog, line, col, f"{name}[{', '.join(f'{v:g}' for v in vals)}] has no value") from None
        return _checked(float(r), prog, line, col)
    return run


def param(cur: Cursor):
    """``P12``, ``P[expr]`` or a call parameter ``@P3``: a closure reading it."""
    col = cur.i + 1
    at = cur.peek() == "@"
    if at:
        cur.i += 1
    cur.i += 1  # the P
    t = cur.text
    if cur.peek() == "[":
        idx = primary(cur)
        prog, line = cur.prog, cur.line

        def run(env):
            n = _num(idx(env), cur, col, "P[...]")
            if n != int(n) or n < 0:
                raise CutsimError(prog, line, col, f"parameter number P[{n:g}] must be a whole number")
            return env.read_param(("@P" if at else "P") + str(int(n)), line, col)
        return run
    j = cur.i
    while j < len(t) and t[j].isdigit() and t[j] < "\x80":
        j += 1
    if j == cur.i:
        raise cur.error("P must be followed by the parameter's number")
    key = ("@P" if at else "P") + str(int(t[cur.i:j]))
    cur.i = j
    prog, line = cur.prog, cur.line
    return lambda env: env.read_param(key, line, col)


def var_ref(cur: Cursor):
    """``V.<scope>.NAME[i][j].FIELD``: (scope letter(s), a closure env -> key, column). The key is the
    upper-cased name with its evaluated indices: ``V.P.ARR[2]``."""
    col = cur.i + 1
    t = cur.text
    m = VAR_HEAD.match(t, cur.i)
    if not m:
        raise cur.error("a variable is written V.<scope>.NAME (V.P., V.L., V.S., V.E., V.G.)")
    scope = m.group(1).upper()
    cur.i = m.end()
    parts: list = []  # strings and index closures
    while True:
        mm = IDENT.match(t, cur.i)
        if not mm and scope == "G" and not parts and t[cur.i:cur.i + 2].upper() == "@P":
            parts.append("@P")  # V.G.@P[i].VALID: was the cycle's @Pi programmed?
            cur.i += 2
        elif not mm:
            raise cur.error(f"variable name expected after V.{scope}.")
        else:
            parts.append(mm.group(0).upper())
            cur.i = mm.end()
        while cur.peek() == "[":
            cur.i += 1
            f = expression(cur)
            cur.skip()
            if cur.peek() != "]":
                raise cur.error("']' expected to close the variable's index")
            cur.i += 1
            parts.append(f)
        if cur.peek() == "." and IDENT.match(t, cur.i + 1):
            cur.i += 1
            parts.append(".")
            continue
        break
    prefix = f"V.{scope}."
    prog, line = cur.prog, cur.line
    if not any(callable(p) for p in parts):
        key = prefix + "".join(parts)
        return scope, (lambda env: key), col

    def keyf(env):
        out = [prefix]
        for p in parts:
            if isinstance(p, str):
                out.append(p)
            else:
                v = p(env)
                if isinstance(v, str) or v != int(v) or v < 0:
                    raise CutsimError(prog, line, col, f"array index {v} must be a whole number, 0 or more")
                out.append(f"[{int(v)}]")
        return "".join(out)
    return scope, keyf, col


def variable(cur: Cursor):
    scope, keyf, col = var_ref(cur)
    line = cur.line
    return lambda env: env.read_var(scope, keyf(env), line, col)


def truth(v) -> bool:
    """A condition: a number is true when it is not 0 (a string when it is not empty)."""
    return bool(v)
