"""Siemens Sinumerik 840D dialect, milling subset (seed 003, spec/sinumerik.md).

Blocks are scanned into statements (words, assignments, jumps, calls) once; expressions are
evaluated when the block runs. Cycles (SLOT1, POCKET1, CYCLE72, ...) expand in
interp/sinumerik_cycles.py into ordinary moves through the ModalMachine methods. Tool radius
compensation (G41/G42) buffers the compensated moves and offsets them analytically at G40.

What the simulator assumes where Siemens' manuals are silent: docs/dialects/sinumerik.md.
"""
from __future__ import annotations

import math
import os
import re
import stat
import unicodedata
from dataclasses import dataclass, field, replace

from . import canon
from .canon import Src
from .errors import CutsimError
from .lexer import split_lines
from .modal import PLANE_AXES, PLANES, InterpConfig, ModalMachine

KNOWN_G = {0, 1, 2, 3, 9, 17, 18, 19, 40, 41, 42, 53, 54, 55, 56, 57, 60, 64, 90, 91, 94, 95, 500, 505, 506}
KNOWN_M = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 17, 30}
ADDRESSES = set("GMXYZIJKFSTDLP")  # single-letter addresses with a number
EXPR_ADDRESSES = {"X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "CR", "P"}
KEYWORDS = {"DEF", "GOTOF", "GOTOB", "GOTO", "IF", "REPEAT", "PROC", "RET", "ENDIF"}
TYPES = {"REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME"}
# calls with no geometric effect (messages, high-speed settings, blank definition for the HMI)
IGNORED_CALLS = {"MSG", "WORKPIECE", "CYCLE832", "G_GROUP", "SETMS"}
IGNORED_WORDS = {"STOPRE", "SUPA", "FFWON", "FFWOF", "SOFT", "BRISK", "CFC", "CFTCP", "G601", "G602",
                 "DIAMOF", "TRAFOOF", "M17"}
FUNCS = {"SIN": 1, "COS": 1, "TAN": 1, "ASIN": 1, "ACOS": 1, "ATAN2": 2, "SQRT": 1, "ABS": 1,
         "POT": 1, "TRUNC": 1, "ROUND": 1, "MINVAL": 2, "MAXVAL": 2}
LABEL_RE = re.compile(r"\s*(?:N[0-9]+\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)")
CONTOUR_BEGIN = "contour definition begin"

# -- limits (docs/dialects/sinumerik.md, "Limits"; the same ranges as the other dialects) ----------
COORD_LIMIT = 99_999.9999  # |X Y Z I J K CR|, every position reached, cycle lengths and positions (mm)
FEED_LIMIT = 99_999.9999  # F (mm/min, mm/rev) and cycle feeds
SPEED_LIMIT = 99_999.0  # S (rpm)
TOOL_LIMIT = 32_000  # T and D numbers
PASS_LIMIT = 9_999  # P: repetitions of a subprogram call or of REPEAT
L_LIMIT = 9_999_999  # L<n> subprogram numbers
R_LIMIT = 9_999  # R0..R9999
MAX_DIGITS = 20  # digits of one written number
MAX_BLOCK_CHARS = 512  # characters of a block's statements (its comment not counted)
MAX_NESTING = 32  # parentheses, function calls and signs nested in one expression
MAX_SUB_BYTES = 10_000_000  # a NAME.spf file beside the program
MAX_STACK = 64  # subprograms (16 of them at most) and REPEAT sections open at once
RANGES = {**{a: (-COORD_LIMIT, COORD_LIMIT, "mm") for a in ("X", "Y", "Z", "I", "J", "K", "CR")},
          "F": (0.0, FEED_LIMIT, "mm/min or mm/rev"), "S": (0.0, SPEED_LIMIT, "rpm"),
          "T": (0, TOOL_LIMIT, ""), "D": (0, TOOL_LIMIT, ""), "P": (1, PASS_LIMIT, ""), "L": (0, L_LIMIT, "")}


def _fmt(v: float) -> str:
    """99999.9999 -> '99 999.9999' (groups of three as in the docs)."""
    whole, _, frac = f"{abs(v):.4f}".rstrip("0").rstrip(".").partition(".")
    groups = []
    while len(whole) > 3:
        groups.insert(0, whole[-3:])
        whole = whole[:-3]
    groups.insert(0, whole)
    return ("-" if v < 0 else "") + " ".join(groups) + ("." + frac if frac else "")


def range_message(what: str, value: float, lo: float, hi: float, unit: str = "") -> str:
    """The one message for a value beyond its range (the manuals' "value exceeds the permitted range")."""
    shown = f"{value:.10g}" if math.isfinite(value) else str(value)
    return f"{what} = {shown}: value exceeds the permitted range {_fmt(lo)} to {_fmt(hi)}{' ' + unit if unit else ''}"


def foreign_char(ch: str) -> str:
    """The message for a non-ASCII character outside comments and strings."""
    if ch == "\ufffd":
        return "a byte that is not UTF-8 text (shown as U+FFFD) outside a comment or a string"
    name = unicodedata.name(ch, f"U+{ord(ch):04X}")
    if ch.isdigit() or unicodedata.numeric(ch, None) is not None:
        return f"'{ch}' ({name}) is not a digit the controller reads: write numbers with the ASCII digits 0-9"
    return (f"'{ch}' ({name}) is not allowed outside a comment or a string: addresses, names and numbers "
            "are ASCII")
CONTOUR_END = "contour definition end"


# ---------------------------------------------------------------------------------------------
# statements
@dataclass
class Stmt:
    kind: str  # word | assign | def | goto | repeat | call | sub | ret | end
    col: int
    a: object = None
    b: object = None
    c: object = None
    d: object = None


@dataclass
class Line:
    line: int
    text: str
    label: str = ""  # NAME: label
    nlabel: str = ""  # N word
    stmts: list[Stmt] = field(default_factory=list)


class _Scanner:
    """Character scanner for one line (comment removed)."""

    def __init__(self, prog: str, line: int, text: str):
        self.prog, self.line, self.s, self.i = prog, line, text, 0
        self.depth = 0  # expressions, parentheses and signs open (MAX_NESTING)

    def enter(self, col: int) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise self.err(col, f"expression nested deeper than {MAX_NESTING} levels (parentheses, functions, signs)")

    def err(self, col: int, msg: str) -> CutsimError:
        return CutsimError(self.prog, self.line, col, msg)

    def ws(self) -> None:
        while self.i < len(self.s) and self.s[self.i] in " \t\f\v":
            self.i += 1

    def peek(self) -> str:
        self.ws()
        return self.s[self.i] if self.i < len(self.s) else ""

    def ident(self) -> str:
        m = re.compile(r"[A-Za-z_][A-Za-z0-9_]*").match(self.s, self.i)
        if not m:
            return ""
        self.i = m.end()
        return m.group(0).upper()

    # expressions: comparison > additive > multiplicative > unary > primary
    def expr(self):
        self.enter(self.i + 1)
        left = self.additive()
        self.ws()
        for op in ("==", "<>", "<=", ">=", "<", ">"):
            if self.s.startswith(op, self.i):
                opcol = self.i + 1
                self.i += len(op)
                left = ("bin", op, left, self.additive(), opcol)
                break
        self.depth -= 1
        return left

    def additive(self):
        left = self.term()
        while True:
            c = self.peek()
            if c in ("+", "-") and c:
                self.i += 1
                opcol = self.i  # 1-based column of the operator
                left = ("bin", c, left, self.term(), opcol)
            else:
                return left

    def term(self):
        left = self.unary()
        while True:
            c = self.peek()
            if c in ("*", "/") and c:
                self.i += 1
                opcol = self.i
                left = ("bin", c, left, self.unary(), opcol)
            else:
                return left

    def unary(self):
        c = self.peek()
        if c in ("-", "+", "\u2212") and c:
            self.enter(self.i + 1)
            self.i += 1
            v = self.unary()
            self.depth -= 1
            return ("neg", v) if c != "+" else v
        return self.primary()

    def primary(self):
        c = self.peek()
        col = self.i + 1
        if not c:
            raise self.err(col, "expression expected at the end of the line")
        m = NUMBER_RE.match(self.s, self.i)
        if m:
            digits(self, col, m.group(0))
            self.i = m.end()
            if self.i < len(self.s) and (self.s[self.i] == "." or self.s[self.i].isalpha() and self.s[self.i].upper() not in ADDRESSES | {"R", "C", "A", "N"}):
                raise self.err(col, f"malformed number '{self.s[col - 1:self.i + 1]}'")
            return ("num", float(m.group(0)))
        if c == "(":
            self.i += 1
            v = self.expr()
            if self.peek() != ")":
                raise self.err(self.i + 1, "')' expected")
            self.i += 1
            return v
        if c == '"':
            j = self.s.find('"', self.i + 1)
            if j < 0:
                raise self.err(col, "unterminated string")
            v = ("str", self.s[self.i + 1:j])
            self.i = j + 1
            return v
        if c.isalpha() or c == "_":
            name = self.ident()
            if name in FUNCS:
                if self.peek() != "(":
                    raise self.err(self.i + 1, f"{name} needs its argument in parentheses")
                self.i += 1
                args = [self.expr()]
                while self.peek() == ",":
                    self.i += 1
                    args.append(self.expr())
                if self.peek() != ")":
                    raise self.err(self.i + 1, "')' expected")
                self.i += 1
                if len(args) != FUNCS[name]:
                    raise self.err(col, f"{name} takes {FUNCS[name]} argument(s)")
                return ("fn", name, args, col)
            if self.peek() == "[" and name == "R":  # R[expr]
                self.i += 1
                idx = self.expr()
                if self.peek() != "]":
                    raise self.err(self.i + 1, "']' expected")
                self.i += 1
                return ("ridx", idx, col)
            return ("var", name, col)
        raise self.err(col, f"unexpected character '{c}' in an expression")


NUMBER_RE = re.compile(r"(?:[0-9]+\.?[0-9]*|\.[0-9]+)")  # [0-9], not \d: that matches every script's digits
SIGNED_RE = re.compile(r"[+\-\u2212]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")


def digits(sc: _Scanner, col: int, raw: str) -> None:
    """A written number has at most MAX_DIGITS digits (a 309-digit number is no number)."""
    n = sum(ch in "0123456789" for ch in raw)
    if n > MAX_DIGITS:
        shown = raw if len(raw) <= 24 else f"{raw[:12]}...{raw[-6:]}"
        raise sc.err(col, f"the number {shown} has {n} digits, more than the {MAX_DIGITS} a number may have")


def _number_word(sc: _Scanner):
    """After an address letter: a plain number (G1, X-10.5)."""
    m = SIGNED_RE.match(sc.s, sc.i)
    if not m:
        return None
    digits(sc, sc.i + 1, m.group(0))
    j = m.end()
    if j < len(sc.s) and (sc.s[j] == "." or sc.s[j] in "0123456789"):
        raise sc.err(sc.i + 1, f"malformed number '{sc.s[sc.i:j + 1]}'")
    sc.i = j
    return float(m.group(0).replace("\u2212", "-"))


def strip_comment(text: str) -> str:
    inq = False
    for k, ch in enumerate(text):
        if ch == '"':
            inq = not inq
        elif ch == ";" and not inq:
            return text[:k]
    return text


def check_text(prog: str, lineno: int, text: str) -> None:
    """A block (comment removed) is ASCII outside double-quoted strings (the Unicode minus sign of
    OCR'd listings aside) and at most MAX_BLOCK_CHARS long."""
    if len(text.rstrip()) > MAX_BLOCK_CHARS:
        raise CutsimError(prog, lineno, MAX_BLOCK_CHARS + 1, f"the block is longer than {MAX_BLOCK_CHARS} characters "
                          "(its comment not counted)")
    if text.isascii():
        return
    inq = False
    for k, ch in enumerate(text):
        if ch == '"':
            inq = not inq
        elif ch >= "\x80" and not inq and ch != "\u2212":
            raise CutsimError(prog, lineno, k + 1, foreign_char(ch))


def scan_line(prog: str, lineno: int, raw: str) -> Line:
    ln = Line(lineno, raw)
    text = strip_comment(raw)
    if text.lstrip().startswith("%"):  # program header (%_N_NAME_MPF): handled by the splitter
        return ln
    check_text(prog, lineno, text)
    sc = _Scanner(prog, lineno, text)
    m = LABEL_RE.match(text)
    if m and m.group(1).upper() not in KEYWORDS and len(m.group(1)) >= 2:
        ln.label = m.group(1).upper()
        pre = re.match(r"\s*N([0-9]+)", text)
        if pre:
            ln.nlabel = "N" + pre.group(1)
        sc.i = m.end()
    first = True
    while True:
        c = sc.peek()
        if not c:
            break
        col = sc.i + 1
        up = c.upper()
        if up == "N" and first and sc.i + 1 < len(text) and text[sc.i + 1] in "0123456789":
            sc.i += 1
            v = _number_word(sc)
            ln.nlabel = "N" + str(int(v))
            first = False
            continue
        first = False
        # R<n>=expr assignment
        mr = re.compile(r"[Rr]([0-9]+)\s*=").match(text, sc.i)
        if mr:
            if len(mr.group(1).lstrip("0")) > len(str(R_LIMIT)) or int(mr.group(1)) > R_LIMIT:
                raise sc.err(col, f"R{mr.group(1)}: there are the parameters R0 to R{R_LIMIT}")
            sc.i = mr.end()
            ln.stmts.append(Stmt("assign", col, "R" + str(int(mr.group(1))), sc.expr()))
            continue
        if up in ADDRESSES and sc.i + 1 < len(text) and text[sc.i + 1] in "0123456789+-.\u2212":
            sc.i += 1
            v = _number_word(sc)
            if v is None:
                raise sc.err(col, f"malformed number after {up}")
            ln.stmts.append(Stmt("word", col, up, ("num", v), None))
            continue
        if not (c.isalpha() or c == "_"):
            raise sc.err(col, f"unexpected character '{c}'")
        name = sc.ident()
        if not name:  # pragma: no cover - check_text and the test above leave only ASCII names here
            raise sc.err(col, f"unexpected character '{c}'")
        nxt = sc.peek()
        if name == "DEF":
            sc.ws()
            typ = sc.ident()
            if typ not in TYPES:
                raise sc.err(sc.i + 1, "DEF needs a type (REAL, INT, ...)")
            decls = []
            while True:
                sc.ws()
                vcol = sc.i + 1
                vname = sc.ident()
                if not vname:
                    raise sc.err(vcol, "variable name expected after DEF")
                init = None
                if sc.peek() == "=":
                    sc.i += 1
                    init = sc.expr()
                decls.append((vname, init, vcol))
                if sc.peek() == ",":
                    sc.i += 1
                    continue
                break
            ln.stmts.append(Stmt("def", col, typ, decls))
            continue
        if name in ("GOTOF", "GOTOB", "GOTO"):
            sc.ws()
            target = sc.ident()
            if not target:
                raise sc.err(sc.i + 1, f"{name} needs a label")
            ln.stmts.append(Stmt("goto", col, name, target, None))
            continue
        if name == "IF":
            cond = sc.expr()
            sc.ws()
            gcol = sc.i + 1
            g = sc.ident()
            if g not in ("GOTOF", "GOTOB", "GOTO"):
                raise sc.err(gcol, "IF must be followed by a condition and GOTOF/GOTOB <label>")
            sc.ws()
            target = sc.ident()
            if not target:
                raise sc.err(sc.i + 1, f"{g} needs a label")
            ln.stmts.append(Stmt("goto", col, g, target, cond))
            continue
        if name == "REPEAT":
            sc.ws()
            l1 = sc.ident()
            if not l1:
                raise sc.err(sc.i + 1, "REPEAT needs a label")
            sc.ws()
            save = sc.i
            l2 = sc.ident()
            count = ("num", 1.0)
            if l2 == "P" and sc.peek() == "=":
                l2 = ""
                sc.i = save
            if sc.peek().upper() == "P":
                sc.i += 1
                if sc.peek() != "=":
                    raise sc.err(sc.i + 1, "REPEAT takes P=<count>")
                sc.i += 1
                count = sc.expr()
            ln.stmts.append(Stmt("repeat", col, l1, l2 or None, count))
            continue
        if name == "PROC":
            sc.ws()
            pname = sc.ident()
            if not pname:
                raise sc.err(sc.i + 1, "PROC needs the subprogram's name")
            ln.stmts.append(Stmt("proc", col, pname))
            sc.i = len(text)
            break
        if name == "RET":
            ln.stmts.append(Stmt("ret", col))
            continue
        if name in IGNORED_WORDS:
            continue
        if nxt == "(":
            sc.i += 1
            args = []
            if sc.peek() == ")":
                sc.i += 1
            else:
                while True:
                    sc.ws()
                    acol = sc.i + 1  # the parameter's first character (its comma when empty)
                    if sc.peek() in (",", ")"):
                        args.append((None, acol))
                    else:
                        args.append((sc.expr(), acol))
                    c2 = sc.peek()
                    if c2 == ",":
                        sc.i += 1
                        continue
                    if c2 == ")":
                        sc.i += 1
                        break
                    raise sc.err(sc.i + 1, "',' or ')' expected in the argument list")
            ln.stmts.append(Stmt("call", col, name, args))
            continue
        if nxt == "=":
            sc.i += 1
            if name in EXPR_ADDRESSES:
                mode = None
                sc.ws()
                mm = re.compile(r"(AC|IC)\s*\(", re.I).match(text, sc.i)
                if mm:
                    mode = mm.group(1).upper()
                    sc.i = mm.end()
                    v = sc.expr()
                    if sc.peek() != ")":
                        raise sc.err(sc.i + 1, "')' expected")
                    sc.i += 1
                else:
                    v = sc.expr()
                ln.stmts.append(Stmt("word", col, name, v, mode))
            else:
                ln.stmts.append(Stmt("assign", col, name, sc.expr()))
            continue
        if re.fullmatch(r"[A-Z]", name):
            raise sc.err(col, f"address {name} needs a value")
        if col > 1 and text[col - 2] in "0123456789.":
            raise sc.err(col, f"unexpected '{name}' right after a number")
        ln.stmts.append(Stmt("sub", col, name))
    return ln


# ---------------------------------------------------------------------------------------------
@dataclass
class Unit:
    """A program or subprogram: its lines and label index."""

    name: str
    lines: list[Line]
    labels: dict[str, int] = field(default_factory=dict)
    program: str = ""  # the file its lines are in


def split_units(prog: str, text: str) -> tuple[Unit, dict[str, Unit]]:
    lines = [scan_line(prog, k, raw) for k, raw in enumerate(split_lines(text), start=1)]
    main = Unit("MAIN", [], program=prog)
    subs: dict[str, Unit] = {}
    cur = main
    for ln in lines:
        hdr = re.match(r"\s*%_N_([A-Za-z0-9_]+?)_(SPF|MPF)", ln.text)
        if hdr and hdr.group(2) == "SPF":
            cur = subs.setdefault(hdr.group(1).upper(), Unit(hdr.group(1).upper(), [], program=prog))
            continue
        if ln.stmts and ln.stmts[0].kind == "proc":
            cur = subs.setdefault(ln.stmts[0].a, Unit(ln.stmts[0].a, [], program=prog))
            continue
        cur.lines.append(ln)
    for u in [main, *subs.values()]:
        for idx, ln in enumerate(u.lines):
            for lab in (ln.label, ln.nlabel):
                if lab:
                    u.labels.setdefault(lab, idx)
    return main, subs


@dataclass
class Frame:
    unit: Unit
    pc: int
    stop: int | None = None  # index where a REPEAT section ends (exclusive)
    restart: int = 0
    ret: int = 0
    count: int = 0
    kind: str = "unit"  # unit | repeat | contour
    calls: tuple = ()


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
        k = node[0]
        if k == "num":
            return node[1]
        if k == "str":
            return node[1]
        if k == "neg":
            v = self._ev(node[1], line, col)
            if isinstance(v, str):
                raise self.error(line, col, "a string cannot be negated")
            return -v
        if k == "var":
            name = node[1]
            if re.fullmatch(r"R[0-9]+", name):
                if len(name[1:].lstrip("0")) > len(str(R_LIMIT)):
                    raise self.error(line, node[2], f"{name}: there are the parameters R0 to R{R_LIMIT}")
                return self.params.get(self.r_index(float(int(name[1:])), line, node[2]), 0.0)
            if name in self.vars:
                return self.vars[name]
            if name in ("TRUE", "FALSE"):
                return 1.0 if name == "TRUE" else 0.0
            raise self.error(line, node[2], f"unknown variable '{name}' (declare it with DEF)")
        if k == "ridx":
            i = self.num(self._ev(node[1], line, col), line, node[2])
            return self.params.get(self.r_index(i, line, node[2]), 0.0)
        if k == "fn":
            args = [self.num(self._ev(a, line, col), line, node[3]) for a in node[2]]
            f = node[1]
            r = self.fn(f, args, line, node[3])
            if not math.isfinite(r):
                raise self.error(line, node[3], f"{f} overflows: the result is not a finite number")
            return r
        if k == "bin":
            op = node[1]
            a = self._ev(node[2], line, col)
            b = self._ev(node[3], line, col)
            if op in ("==", "<>") and isinstance(a, str) and isinstance(b, str):
                return float((a == b) == (op == "=="))
            a, b = self.num(a, line, col), self.num(b, line, col)
            if op in ("+", "-", "*", "/"):
                if op == "/" and b == 0:
                    raise self.error(line, node[4], "division by zero")
                r = a + b if op == "+" else a - b if op == "-" else a * b if op == "*" else a / b
                if not math.isfinite(r):
                    raise self.error(line, node[4], f"{a:.10g} {op} {b:.10g} overflows: the result is not a finite number")
                return r
            return float({"==": a == b, "<>": a != b, "<": a < b, ">": a > b, "<=": a <= b, ">=": a >= b}[op])
        raise self.error(line, col, "bad expression")  # pragma: no cover

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
        stack = [Frame(self.main, 0)]
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
                if fr.kind == "unit" and stack:
                    continue
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

    def check_loop(self, stack: list[Frame], line: int, st) -> None:
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
            raise self.error(line, st.col, f"the program does not end: {st.a} {st.b} comes back with every R parameter "
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
            raise self.error(line, col, f"subprogram {name} is not defined (PROC {name} in this file, or {name}.spf beside it)")
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

    # -- one block -------------------------------------------------------------------------------
    def block(self, ln: Line, fr: Frame, stack: list[Frame]) -> bool:
        src = Src(fr.unit.program, ln.line, 1, ln.nlabel or ln.label, fr.calls)
        line = ln.line
        words: dict[str, tuple] = {}
        gs: list[tuple[int, int]] = []
        ms: list[tuple[int, int]] = []
        calls: list[Stmt] = []
        jumps: list[Stmt] = []
        for st in ln.stmts:
            if st.kind == "assign":
                v = self.ev(st.b, line, st.col)
                if st.a.startswith("R") and re.fullmatch(r"R[0-9]+", st.a):
                    self.params[st.a] = self.num(v, line, st.col)
                elif st.a in self.vars:
                    self.vars[st.a] = v
                else:
                    raise self.error(line, st.col, f"unknown variable '{st.a}' (declare it with DEF)")
            elif st.kind == "def":
                for vname, init, vcol in st.b:
                    if re.fullmatch(r"R[0-9]+", vname) or vname in EXPR_ADDRESSES or len(vname) == 1:
                        raise self.error(line, vcol, f"'{vname}' is an address or parameter and cannot be a variable name")
                    val = 0.0 if st.a != "STRING" else ""
                    if init is not None:
                        val = self.ev(init, line, vcol)
                        if st.a == "INT" and not isinstance(val, str):
                            val = float(math.trunc(val))
                    self.vars[vname] = val
            elif st.kind == "word":
                val = self.ev(st.b, line, st.col)
                if st.a == "G":
                    v = self.num(val, line, st.col)
                    if v != int(v) or int(v) not in KNOWN_G:
                        raise self.error(line, st.col, f"unknown G code G{v:g}")
                    gs.append((int(v), st.col))
                elif st.a == "M":
                    v = self.num(val, line, st.col)
                    if v != int(v) or int(v) not in KNOWN_M:
                        raise self.error(line, st.col, f"unknown M code M{v:g}")
                    ms.append((int(v), st.col))
                else:
                    if st.a in words:
                        raise self.error(line, st.col, f"address {st.a} appears twice in one block")
                    v = self.num(val, line, st.col)
                    lo, hi, unit = RANGES[st.a]
                    if not lo <= v <= hi:
                        raise self.error(line, st.col, range_message(st.a, v, lo, hi, unit))
                    words[st.a] = (v, st.c, st.col)
            elif st.kind in ("goto", "repeat"):
                jumps.append(st)
            elif st.kind in ("call", "sub", "ret"):
                calls.append(st)

        # modal G codes
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
                new_comp = (code, col)
        # spindle, tool, feed
        direction = self.spindle_code(line, ms)
        end = False
        change = False
        for code, col in ms:
            if code in (2, 30):
                end = True
            elif code == 6:
                change = True
            elif code == 17:
                calls.append(Stmt("ret", col))
        if "S" in words:
            s = words.pop("S")
            if s[0] < 0:
                raise self.error(line, s[2], "spindle speed S must not be negative")
            self.spindle(src, direction, s[0])
        elif direction is not None:
            self.spindle(src, direction, None)
        if "T" in words:
            t = words.pop("T")
            if t[0] != int(t[0]) or t[0] < 0:
                raise self.error(line, t[2], "T must be a whole tool number")
            self.tool_pre = int(t[0])
        if "D" in words:
            d = words.pop("D")
            if d[0] != int(d[0]) or d[0] < 0:
                raise self.error(line, d[2], "D must be a whole offset number")
            self.d_no = int(d[0])
        if change:
            if self.tool_pre is None:
                raise self.error(line, 1, "M6 without a tool: program T<number> first")
            if self.cfg.tool_radii and self.tool_pre not in self.cfg.tool_radii:
                known = ", ".join(f"T{n}" for n in sorted(self.cfg.tool_radii))
                raise self.error(line, 1, f"tool T{self.tool_pre} is not in the setup (tools: {known})")
            self.tool_no = self.tool_pre
            self.tool(src, self.tool_pre, self.d_no)
        if "F" in words:
            f = words.pop("F")
            if f[0] <= 0:
                raise self.error(line, f[2], "feed F must be positive")
            self.feed = f[0]
        if motion is not None:
            self.motion = motion

        # compensation switched on: start buffering before the approach move
        if new_comp is not None and new_comp[0] in (41, 42):
            if self.comp_buf is not None and self.comp != new_comp[0]:
                self.flush_comp(None, line)
            if self.comp_buf is None:
                if self.tool_radius() <= 0:
                    self.warn(src, f"G{new_comp[0]} with tool radius 0 (no tool radius known for D{self.d_no}): the path is not offset")
                self.comp = new_comp[0]
                self.comp_buf = []
                self.comp_src = src

        self.move(ln, src, words, motion)

        if new_comp is not None and new_comp[0] == 40 and self.comp_buf is not None:
            self.flush_comp(src, line)
        # cycles and subprogram calls
        for st in calls:
            if st.kind == "ret":
                self.ret(stack)
                return False
            if st.kind == "call":
                if st.a in IGNORED_CALLS:
                    continue
                from . import sinumerik_cycles
                if st.a in sinumerik_cycles.CYCLES:
                    args = []
                    for node, acol in st.b:
                        args.append((None if node is None else self.ev(node, line, acol), acol))
                    sinumerik_cycles.run_cycle(self, st.a, args, src, ln)
                    continue
                raise self.error(line, st.col, f"unknown cycle or function {st.a}")
            if st.kind == "sub":
                if st.a in self.vars:
                    raise self.error(line, st.col, f"'{st.a}' is a variable: write {st.a}=<value> to assign it")
                self.call_sub(self.find_sub(st.a, line, st.col), src, words, stack, st.col)
                return False
        if "L" in words:
            lw = words.pop("L")
            if lw[0] != int(lw[0]):
                raise self.error(line, lw[2], f"L{lw[0]:g}: a subprogram number is a whole number")
            self.call_sub(self.find_sub(f"L{int(lw[0])}", line, lw[2]), src, words, stack, lw[2])
            return False
        if "P" in words:
            raise self.error(line, words["P"][2], "P (repeat count) only goes with a subprogram call")
        for st in jumps:
            if st.kind == "goto":
                if st.c is not None and not self.num(self.ev(st.c, line, st.col), line, st.col):
                    continue
                fr2 = stack[-1]
                idx = self.find_label(fr2.unit, st.b, line, st.col)
                cur = fr2.pc - 1
                if st.a == "GOTOF" and idx <= cur:
                    raise self.error(line, st.col, f"GOTOF jumps forward, but {st.b} comes before this block")
                if st.a == "GOTOB" and idx > cur:
                    raise self.error(line, st.col, f"GOTOB jumps back, but {st.b} comes after this block")
                fr2.pc = idx
                if idx <= cur:
                    self.check_loop(stack, line, st)
                return end
            if st.kind == "repeat":
                fr2 = stack[-1]
                cur = fr2.pc - 1
                a = self.find_label(fr2.unit, st.a, line, st.col)
                n = self.num(self.ev(st.c, line, st.col), line, st.col)
                if n != int(n) or not 1 <= n <= PASS_LIMIT:
                    raise self.error(line, st.col, f"REPEAT P must be a whole number from 1 to {PASS_LIMIT} (got {n:.10g})")
                if len(stack) > MAX_STACK:
                    raise self.error(line, st.col, f"REPEAT sections and subprograms nested deeper than {MAX_STACK} "
                                     "(a REPEAT inside the section it repeats?)")
                if st.b is None:
                    if a >= cur:
                        raise self.error(line, st.col, f"REPEAT {st.a}: the label must come before this block")
                    stop = cur
                else:
                    b = self.find_label(fr2.unit, st.b, line, st.col)
                    if b < a:
                        raise self.error(line, st.col, f"REPEAT {st.a} {st.b}: the end label comes before the start")
                    stop = b + 1
                stack.append(Frame(fr2.unit, a, stop, a, cur + 1, int(n), "repeat", fr2.calls))
                return end
        if end:
            if any(f.kind == "unit" for f in stack[1:]):  # M2/M30 in a subprogram: return
                self.ret(stack)
                return False
            if self.comp_buf is not None:
                self.flush_comp(None, line)
            self.end(src)
        return end

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

    def call_sub(self, unit: Unit, src: Src, words: dict, stack: list[Frame], col: int) -> None:
        n = 1
        if "P" in words:
            p = words.pop("P")
            if p[0] != int(p[0]) or p[0] < 1:
                raise self.error(src.line, p[2], "P (repeat count) must be a whole number of at least 1")
            n = int(p[0])
        if len(stack) > 16:
            raise self.error(src.line, col, "subprograms nested deeper than 16 levels (recursion?)")
        calls = stack[-1].calls + ((src.program, src.line),)
        stack.append(Frame(unit, 0, len(unit.lines), 0, stack[-1].pc, n, "unit", calls))

    # -- motion ----------------------------------------------------------------------------------
    def axis_targets(self, words: dict) -> dict[int, float]:
        end = {}
        for i, a in enumerate("XYZ"):
            if a in words:
                v, mode, _ = words.pop(a)
                ab = self.absolute if mode is None else mode == "AC"
                end[i] = v if ab else self.pos[i] + v
        return end

    def move(self, ln: Line, src: Src, words: dict, motion_word) -> None:
        line = ln.line
        cols = {i: words[a][2] for i, a in enumerate("XYZ") if a in words}
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
                    raise self.error(line, words[a][2], f"address {a} has no meaning in a G{self.motion} block")
            (self.rapid if self.motion == 0 else self.linear)(src, end)
            return
        a, b, nrm = PLANE_AXES[self.plane]
        cw = self.motion == 2
        letters = {0: "I", 1: "J", 2: "K"}
        if letters[nrm] in words:
            raise self.error(line, words[letters[nrm]][2], f"{letters[nrm]} is not in the plane {self.plane} of the circle")
        if "CR" in words:
            r, _, ccol = words.pop("CR")
            if any(letters[i] in words for i in (a, b)):
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
            # centre on the left of the chord for CCW with the short arc (CR>0), right for CW
            sgn = (1 if not cw else -1) * (1 if r > 0 else -1)
            mx, my = (p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2
            cx, cy = mx - sgn * h * dy / d, my + sgn * h * dx / d
            centre = list(self.pos)
            centre[a], centre[b] = cx, cy
            for i in (a, b):
                self.in_range(line, ccol, "XYZ"[i], centre[i], "the arc centre")
        else:
            centre = list(self.pos)
            given = False
            for i in (a, b):
                if letters[i] in words:
                    v, mode, icol = words.pop(letters[i])
                    centre[i] = v if mode == "AC" else self.pos[i] + v
                    self.in_range(line, icol, "XYZ"[i], centre[i], "the arc centre")
                    given = True
            if not given:
                raise self.error(line, 1, f"circle needs its centre ({letters[a]}/{letters[b]}) or a radius CR=")
        self.arc(src, end, (centre[0], centre[1], centre[2]), cw)

    def in_range(self, line: int, col: int, axis: str, v: float, what: str) -> None:
        """A position the tool reaches (incremental words add up) stays within COORD_LIMIT."""
        if abs(v) > COORD_LIMIT:
            raise self.error(line, col, range_message(f"{what} {axis}", v, -COORD_LIMIT, COORD_LIMIT, "mm"))

    # -- tool radius compensation ----------------------------------------------------------------
    def flush_comp(self, src_g40: Src | None, line: int) -> None:
        from .sinumerik_cycles import compensate_records
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


__all__ = ["interpret", "Sinumerik", "replace"]
