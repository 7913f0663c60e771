"""Sinumerik 840D language: limits, messages and the typed syntax tree, and the reader that
turns a program's text into it (spec/sinumerik.md, docs/dialects/sinumerik.md).

Reading a block goes in phases, as in LinuxCNC's rs274ngc: ``strip_comment`` and ``check_text``
(the characters and the length), ``read_label`` (``NAME:`` and the N word), then one
``statement`` after the other into the block's ``Line``. Expressions become ``Expr`` nodes
(``Num``, ``Str``, ``Neg``, ``Var``, ``RIndex``, ``FuncCall``, ``BinOp``) evaluated when the block
runs; statements become ``Stmt`` nodes (``Word``, ``Assign``, ``Def``, ``Goto``, ``Repeat``,
``Call``, ``SubCall``, ``Ret``, ``Proc``). ``split_units`` groups the lines into the main program
and its subprograms. Both the interpreter (interp/sinumerik.py) and the cycles
(interp/sinumerik_cycles.py) import from here; this module imports neither.
"""
from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass, field

from .errors import CutsimError
from .lexer import split_lines

ADDRESSES = set("GMXYZIJKFSTDLP")  # single-letter addresses with a number
EXPR_ADDRESSES = {"X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "CR", "P"}
KEYWORDS = {"DEF", "GOTOF", "GOTOB", "GOTO", "IF", "REPEAT", "PROC", "RET", "ENDIF"}
TYPES = {"REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME"}
JUMPS = ("GOTOF", "GOTOB", "GOTO")
IGNORED_WORDS = {"STOPRE", "SUPA", "FFWON", "FFWOF", "SOFT", "BRISK", "CFC", "CFTCP", "G601", "G602",
                 "DIAMOF", "TRAFOOF", "M17"}
FUNCS = {"SIN": 1, "COS": 1, "TAN": 1, "ASIN": 1, "ACOS": 1, "ATAN2": 2, "SQRT": 1, "ABS": 1,
         "POT": 1, "TRUNC": 1, "ROUND": 1, "MINVAL": 2, "MAXVAL": 2}
LABEL_RE = re.compile(r"\s*(?:N[0-9]+\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)")
NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
R_ASSIGN_RE = re.compile(r"[Rr]([0-9]+)\s*=")
AC_IC_RE = re.compile(r"(AC|IC)\s*\(", re.I)
HEADER_RE = re.compile(r"\s*%_N_([A-Za-z0-9_]+?)_(SPF|MPF)")
NUMBER_RE = re.compile(r"(?:[0-9]+\.?[0-9]*|\.[0-9]+)")  # [0-9], not \d: that matches every script's digits
SIGNED_RE = re.compile(r"[+\-\u2212]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")

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


class SubprogramMissing(CutsimError):
    """A called name that is neither a PROC of the program nor a NAME.spf beside it (CYCLE72 takes
    it for "contour not found"; every other error of a subprogram file stays what it is)."""


# ---------------------------------------------------------------------------------------------
# expression nodes
@dataclass(frozen=True)
class Num:
    value: float


@dataclass(frozen=True)
class Str:
    value: str


@dataclass(frozen=True)
class Neg:
    operand: Expr


@dataclass(frozen=True)
class Var:
    name: str
    col: int


@dataclass(frozen=True)
class RIndex:
    """R[expr]"""
    index: Expr
    col: int


@dataclass(frozen=True)
class FuncCall:
    name: str
    args: tuple
    col: int


@dataclass(frozen=True)
class BinOp:
    op: str
    left: Expr
    right: Expr
    col: int  # the operator's column


Expr = Num | Str | Neg | Var | RIndex | FuncCall | BinOp


# ---------------------------------------------------------------------------------------------
# statement nodes (``col``: where the statement starts, 1-based)
@dataclass(frozen=True)
class Word:
    """An address with a value: G1, X-10.5, X=AC(R1+2), CR=5."""
    col: int
    address: str
    value: Expr
    mode: str | None = None  # AC | IC | None (the modal G90/G91)


@dataclass(frozen=True)
class Assign:
    col: int
    name: str  # R<n> or a DEF variable
    value: Expr


@dataclass(frozen=True)
class Decl:
    name: str
    init: Expr | None
    col: int


@dataclass(frozen=True)
class Def:
    col: int
    type: str
    decls: tuple[Decl, ...]


@dataclass(frozen=True)
class Goto:
    col: int
    kind: str  # GOTOF | GOTOB | GOTO
    label: str
    cond: Expr | None = None  # IF <cond> GOTO..


@dataclass(frozen=True)
class Repeat:
    col: int
    start: str
    end: str | None
    count: Expr


@dataclass(frozen=True)
class Arg:
    value: Expr | None  # None: an empty parameter
    col: int


@dataclass(frozen=True)
class Call:
    """NAME(args): a cycle or an ignored call."""
    col: int
    name: str
    args: tuple[Arg, ...]


@dataclass(frozen=True)
class SubCall:
    """NAME alone: a subprogram call."""
    col: int
    name: str


@dataclass(frozen=True)
class Ret:
    col: int


@dataclass(frozen=True)
class Proc:
    col: int
    name: str


Stmt = Word | Assign | Def | Goto | Repeat | Call | SubCall | Ret | Proc


@dataclass
class Line:
    line: int
    text: str
    label: str = ""  # NAME: label
    nlabel: str = ""  # N word
    stmts: list[Stmt] = field(default_factory=list)


@dataclass
class Unit:
    """A program or subprogram: its lines and label index."""

    name: str
    lines: list[Line]
    labels: dict[str, int] = field(default_factory=dict)
    program: str = ""  # the file its lines are in


@dataclass
class Frame:
    """One entry of the run stack: a (sub)program or a REPEAT section being executed."""
    unit: Unit
    pc: int
    stop: int | None = None  # index where a REPEAT section ends (exclusive)
    restart: int = 0
    ret: int = 0
    count: int = 0
    kind: str = "unit"  # unit | repeat
    calls: tuple = ()


# ---------------------------------------------------------------------------------------------
# reading: characters -> expressions and statements
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
        m = NAME_RE.match(self.s, self.i)
        if not m:
            return ""
        self.i = m.end()
        return m.group(0).upper()

    def close(self, ch: str) -> None:
        if self.peek() != ch:
            raise self.err(self.i + 1, f"'{ch}' expected")
        self.i += 1

    def digits(self, col: int, raw: str) -> None:
        """A written number has at most MAX_DIGITS digits (a 309-digit number is no number)."""
        n = sum(ch in "0123456789" for ch in raw)
        if n > MAX_DIGITS:
            shown = raw if len(raw) <= 24 else f"{raw[:12]}...{raw[-6:]}"
            raise self.err(col, f"the number {shown} has {n} digits, more than the {MAX_DIGITS} a number may have")

    def number_word(self) -> float | None:
        """After an address letter: a plain number (G1, X-10.5)."""
        m = SIGNED_RE.match(self.s, self.i)
        if not m:
            return None
        self.digits(self.i + 1, m.group(0))
        j = m.end()
        if j < len(self.s) and (self.s[j] == "." or self.s[j] in "0123456789"):
            raise self.err(self.i + 1, f"malformed number '{self.s[self.i:j + 1]}'")
        self.i = j
        return float(m.group(0).replace("\u2212", "-"))

    # expressions: comparison > additive > multiplicative > unary > primary
    def expr(self) -> Expr:
        self.enter(self.i + 1)
        left = self.additive()
        self.ws()
        for op in ("==", "<>", "<=", ">=", "<", ">"):
            if self.s.startswith(op, self.i):
                opcol = self.i + 1
                self.i += len(op)
                left = BinOp(op, left, self.additive(), opcol)
                break
        self.depth -= 1
        return left

    def additive(self) -> Expr:
        left = self.term()
        while self.peek() in ("+", "-"):
            op = self.s[self.i]
            self.i += 1
            opcol = self.i  # the operator's 1-based column
            left = BinOp(op, left, self.term(), opcol)
        return left

    def term(self) -> Expr:
        left = self.unary()
        while self.peek() in ("*", "/"):
            op = self.s[self.i]
            self.i += 1
            opcol = self.i
            left = BinOp(op, left, self.unary(), opcol)
        return left

    def unary(self) -> Expr:
        c = self.peek()
        if c in ("-", "+", "\u2212") and c:
            self.enter(self.i + 1)
            self.i += 1
            v = self.unary()
            self.depth -= 1
            return Neg(v) if c != "+" else v
        return self.primary()

    def primary(self) -> Expr:
        c = self.peek()
        col = self.i + 1
        if not c:
            raise self.err(col, "expression expected at the end of the line")
        m = NUMBER_RE.match(self.s, self.i)
        if m:
            self.digits(col, m.group(0))
            self.i = m.end()
            if self.i < len(self.s) and (self.s[self.i] == "." or self.s[self.i].isalpha()
                                         and self.s[self.i].upper() not in ADDRESSES | {"R", "C", "A", "N"}):
                raise self.err(col, f"malformed number '{self.s[col - 1:self.i + 1]}'")
            return Num(float(m.group(0)))
        if c == "(":
            self.i += 1
            v = self.expr()
            self.close(")")
            return v
        if c == '"':
            j = self.s.find('"', self.i + 1)
            if j < 0:
                raise self.err(col, "unterminated string")
            v = Str(self.s[self.i + 1:j])
            self.i = j + 1
            return v
        if c.isalpha() or c == "_":
            return self.name_expr(col)
        raise self.err(col, f"unexpected character '{c}' in an expression")

    def name_expr(self, col: int) -> Expr:
        """A function call, R[expr] or a variable."""
        name = self.ident()
        if name in FUNCS:
            if self.peek() != "(":
                raise self.err(self.i + 1, f"{name} needs its argument in parentheses")
            self.i += 1
            args = [self.expr()]
            while self.peek() == ",":
                self.i += 1
                args.append(self.expr())
            self.close(")")
            if len(args) != FUNCS[name]:
                raise self.err(col, f"{name} takes {FUNCS[name]} argument(s)")
            return FuncCall(name, tuple(args), col)
        if self.peek() == "[" and name == "R":  # R[expr]
            self.i += 1
            idx = self.expr()
            self.close("]")
            return RIndex(idx, col)
        return Var(name, col)

    # statements
    def label(self) -> str:
        self.ws()
        return self.ident()

    def statement(self, first: bool, ln: Line) -> bool:
        """Read the next statement into ``ln``; False at the end of the block."""
        c = self.peek()
        if not c:
            return False
        col = self.i + 1
        up, text = c.upper(), self.s
        if up == "N" and first and self.i + 1 < len(text) and text[self.i + 1] in "0123456789":
            self.i += 1
            ln.nlabel = "N" + str(int(self.number_word()))
            return True
        mr = R_ASSIGN_RE.match(text, self.i)
        if mr:  # R<n>=expr
            if len(mr.group(1).lstrip("0")) > len(str(R_LIMIT)) or int(mr.group(1)) > R_LIMIT:
                raise self.err(col, f"R{mr.group(1)}: there are the parameters R0 to R{R_LIMIT}")
            self.i = mr.end()
            ln.stmts.append(Assign(col, "R" + str(int(mr.group(1))), self.expr()))
            return True
        if up in ADDRESSES and self.i + 1 < len(text) and text[self.i + 1] in "0123456789+-.\u2212":
            self.i += 1
            v = self.number_word()
            if v is None:
                raise self.err(col, f"malformed number after {up}")
            ln.stmts.append(Word(col, up, Num(v)))
            return True
        if not (c.isalpha() or c == "_"):
            raise self.err(col, f"unexpected character '{c}'")
        name = self.ident()
        if not name:  # pragma: no cover - check_text and the test above leave only ASCII names here
            raise self.err(col, f"unexpected character '{c}'")
        nxt = self.peek()
        reader = _KEYWORD_READERS.get(name)
        if reader is not None:
            st = reader(self, col, name)
            ln.stmts.append(st)
            if isinstance(st, Proc):  # the rest of the line is its parameter list
                self.i = len(text)
                return False
            return True
        if name in IGNORED_WORDS:
            return True
        ln.stmts.append(self.named(col, name, nxt))
        return True

    def named(self, col: int, name: str, nxt: str) -> Stmt:
        """NAME(args), NAME=value or NAME alone (a subprogram call)."""
        if nxt == "(":
            self.i += 1
            return Call(col, name, tuple(self.arguments()))
        if nxt == "=":
            self.i += 1
            if name in EXPR_ADDRESSES:
                return self.address_value(col, name)
            return Assign(col, name, self.expr())
        if re.fullmatch(r"[A-Z]", name):
            raise self.err(col, f"address {name} needs a value")
        if col > 1 and self.s[col - 2] in "0123456789.":
            raise self.err(col, f"unexpected '{name}' right after a number")
        return SubCall(col, name)

    def arguments(self) -> list[Arg]:
        """A call's argument list after its '(' (empty parameters kept as None)."""
        args: list[Arg] = []
        if self.peek() == ")":
            self.i += 1
            return args
        while True:
            self.ws()
            acol = self.i + 1  # the parameter's first character (its comma when empty)
            args.append(Arg(None if self.peek() in (",", ")") else self.expr(), acol))
            c2 = self.peek()
            if c2 == ",":
                self.i += 1
                continue
            if c2 == ")":
                self.i += 1
                return args
            raise self.err(self.i + 1, "',' or ')' expected in the argument list")

    def address_value(self, col: int, name: str) -> Word:
        """X=expr, X=AC(expr), X=IC(expr)."""
        self.ws()
        mm = AC_IC_RE.match(self.s, self.i)
        if not mm:
            return Word(col, name, self.expr())
        self.i = mm.end()
        v = self.expr()
        self.close(")")
        return Word(col, name, v, mm.group(1).upper())


def _read_def(sc: _Scanner, col: int, name: str) -> Def:
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
        decls.append(Decl(vname, init, vcol))
        if sc.peek() != ",":
            return Def(col, typ, tuple(decls))
        sc.i += 1


def _read_goto(sc: _Scanner, col: int, name: str, cond: Expr | None = None) -> Goto:
    target = sc.label()
    if not target:
        raise sc.err(sc.i + 1, f"{name} needs a label")
    return Goto(col, name, target, cond)


def _read_if(sc: _Scanner, col: int, name: str) -> Goto:
    cond = sc.expr()
    sc.ws()
    gcol = sc.i + 1
    g = sc.ident()
    if g not in JUMPS:
        raise sc.err(gcol, "IF must be followed by a condition and GOTOF/GOTOB <label>")
    return _read_goto(sc, col, g, cond)


def _read_repeat(sc: _Scanner, col: int, name: str) -> Repeat:
    l1 = sc.label()
    if not l1:
        raise sc.err(sc.i + 1, "REPEAT needs a label")
    sc.ws()
    save = sc.i
    l2 = sc.ident()
    count: Expr = Num(1.0)
    if l2 == "P" and sc.peek() == "=":
        l2 = ""
        sc.i = save
    if sc.peek().upper() == "P":
        sc.i += 1
        if sc.peek() != "=":
            raise sc.err(sc.i + 1, "REPEAT takes P=<count>")
        sc.i += 1
        count = sc.expr()
    return Repeat(col, l1, l2 or None, count)


def _read_proc(sc: _Scanner, col: int, name: str) -> Proc:
    pname = sc.label()
    if not pname:
        raise sc.err(sc.i + 1, "PROC needs the subprogram's name")
    return Proc(col, pname)


_KEYWORD_READERS = {"DEF": _read_def, "GOTOF": _read_goto, "GOTOB": _read_goto, "GOTO": _read_goto,
                    "IF": _read_if, "REPEAT": _read_repeat, "PROC": _read_proc,
                    "RET": lambda sc, col, name: Ret(col)}


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


def read_label(sc: _Scanner, ln: Line) -> None:
    """A leading ``NAME:`` label (with the N word before it, if any)."""
    m = LABEL_RE.match(sc.s)
    if m and m.group(1).upper() not in KEYWORDS and len(m.group(1)) >= 2:
        ln.label = m.group(1).upper()
        pre = re.match(r"\s*N([0-9]+)", sc.s)
        if pre:
            ln.nlabel = "N" + pre.group(1)
        sc.i = m.end()


def scan_line(prog: str, lineno: int, raw: str) -> Line:
    """One block: comment off, characters checked, label, then its statements."""
    ln = Line(lineno, raw)
    text = strip_comment(raw)
    if text.lstrip().startswith("%"):  # program header (%_N_NAME_MPF): handled by the splitter
        return ln
    check_text(prog, lineno, text)
    sc = _Scanner(prog, lineno, text)
    read_label(sc, ln)
    first = True
    while sc.statement(first, ln):
        first = False
    return ln


def split_units(prog: str, text: str) -> tuple[Unit, dict[str, Unit]]:
    """The main program and the subprograms (%_N_NAME_SPF headers, PROC NAME) of one file."""
    lines = [scan_line(prog, k, raw) for k, raw in enumerate(split_lines(text), start=1)]
    main = Unit("MAIN", [], program=prog)
    subs: dict[str, Unit] = {}
    cur = main
    for ln in lines:
        hdr = HEADER_RE.match(ln.text)
        if hdr and hdr.group(2) == "SPF":
            cur = subs.setdefault(hdr.group(1).upper(), Unit(hdr.group(1).upper(), [], program=prog))
            continue
        if ln.stmts and isinstance(ln.stmts[0], Proc):
            cur = subs.setdefault(ln.stmts[0].name, Unit(ln.stmts[0].name, [], program=prog))
            continue
        cur.lines.append(ln)
    for u in [main, *subs.values()]:
        for idx, ln in enumerate(u.lines):
            for lab in (ln.label, ln.nlabel):
                if lab:
                    u.labels.setdefault(lab, idx)
    return main, subs
