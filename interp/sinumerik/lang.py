"""Sinumerik 840D language: limits, messages and the typed syntax tree, and the reader that
turns a program's text into it (spec/sinumerik.md, docs/dialects/sinumerik.md).

Reading a block goes in phases, as in LinuxCNC's rs274ngc: ``strip_comment`` and ``check_text``
(the characters and the length), ``read_label`` (``NAME:`` and the N word), then one
``statement`` after the other into the block's ``Line``. Expressions become ``Expr`` nodes
(``Num``, ``Str``, ``Neg``, ``Var``, ``RIndex``, ``FuncCall``, ``BinOp``) evaluated when the block
runs; statements become ``Stmt`` nodes (``Word``, ``Assign``, ``Def``, ``Goto``, ``Repeat``,
``Call``, ``SubCall``, ``Ret``, ``Proc``, ``Command``, ``Case``, ``Branch``). ``split_units`` groups
the lines into the main program and its subprograms, and ``lower`` turns the structured control
flow (IF/ELSE/ENDIF, WHILE, FOR, LOOP, REPEAT/UNTIL) into conditional jumps to line indices
(``Branch``), so the executor only ever follows jumps. Both the interpreter (interp/sinumerik/interpreter.py) and the cycles
(interp/sinumerik/milling.py) import from here; this module imports neither.
"""
from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass, field

from ..errors import CutsimError
from ..lexer import split_lines

EXTRA_AXES = set("ABCUVW")  # axis letters beyond X/Y/Z: words for them need the setup's [machine] axes
ADDRESSES = set("GMXYZIJKFSTDLP") | EXTRA_AXES  # single-letter addresses with a number
ISO_ADDRESSES = {"R", "Q"}  # the ISO drilling cycles' R plane and peck depth, with a plain number
EXPR_ADDRESSES = {"X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "CR", "P", "RPL"} | EXTRA_AXES  # RPL: ROT RPL=30
STRUCTURED = {"IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "LOOP", "ENDLOOP", "REPEAT", "UNTIL"}
KEYWORDS = {"DEF", "GOTOF", "GOTOB", "GOTO", "GOTOC", "PROC", "RET", "CASE", "EXTERN", "REPEATB", "CALL", "EXTCALL",
            "PCALL", "OF", "DEFAULT",
            "TO", "AND", "OR", "XOR", "NOT", "DIV", "MOD", "B_AND", "B_OR", "B_XOR", "B_NOT"} | STRUCTURED
TYPES = {"REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME"}
JUMPS = ("GOTOF", "GOTOB", "GOTO", "GOTOC")
# the language's own M codes (interp/sinumerik/interpreter.py); every other M code is the machine side's
# (interp/sinumerik/machine.py: spindle orientation, gear stages, the setup's m_functions)
KNOWN_M = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 17, 30}
# DIAMOF (radius programming) is a mill's only mode: nothing to say about it
IGNORED_WORDS = {"DIAMOF"}
# Bare keywords without parameters read as ``Command`` (never a subprogram, never a file name):
# LANG_COMMANDS change nothing on the tool path and get one warning per kind (docs: "Warnings");
# MACHINE_COMMANDS are for interp/sinumerik/interpreter.py's settings (frames, units, compensation...), which
# consumes those it implements from ``Block.commands``; any left over is an error.
LANG_COMMANDS = {"STOPRE", "DISPLOF", "DISPLON", "SBLOF", "SBLON", "GROUP_BEGIN", "GROUP_END", "ACTBLOCNO",
                 "WAITM", "WAITE", "WAITMC", "PRESETON", "STOPFIFO", "STARTFIFO", "SETMS", "CPRECON", "CPRECOF",
                 "UPATH", "SPATH", "FNORM", "FLIN", "FCUB", "BTAN", "BAUTO", "BNAT", "ETAN", "EAUTO", "ENAT",
                 "G_GROUP", "FIFOCTRL", "RMBBL", "RMIBL", "RMEBL", "RMNBL", "TRAILOF", "SPOF"}
MACHINE_COMMANDS = {"TRANS", "ATRANS", "ROT", "AROT", "SCALE", "ASCALE", "MIRROR", "AMIRROR", "SUPA",
                    "COMPOF", "COMPON", "COMPCURV", "COMPCAD", "DRFOF", "TRAFOOF", "TRAORI", "TRANSMIT",
                    "TRACYL", "DIAMON", "DIAM90", "CUT2D", "CUT2DF", "CUT3DC", "CDON", "CDOF", "CDOF2",
                    "ORIWKS", "ORIMKS", "ORIAXES", "ORIVECT", "ORICONCW", "ORICONCCW", "TOFRAME", "TOROT",
                    "PAROT", "PAROTOF", "TOROTOF", "G500", "DYNNORM", "DYNPOS", "DYNROUGH", "DYNSEMIFIN",
                    "DYNFINISH", "FGREF", "OFFN",
                    # acceleration, feed-forward and feed-reference modes (one warning each, machine side)
                    "SOFT", "BRISK", "SOFTA", "BRISKA", "FFWON", "FFWOF", "CFC", "CFTCP", "CFIN",
                    # the straight approach of radius compensation (the simulator's way, accepted). KONT
                    # & co. stay names: contours are called KONT (CYCLE72("KONT") finds KONT.spf)
                    "NORM",
                    # motion types the simulator does not interpolate: never read as G1 (an error)
                    "ASPLINE", "BSPLINE", "CSPLINE", "POLY", "CIP", "CT", "COMPSURF"}
# NAME=value / NAME[n]=value settings without effect on the tool path (spindle positioning and
# limits, smoothing distances): one warning per kind
SETTING_WORDS = {"SPOS", "SPOSA", "LIMS", "ADIS", "ADISPOS", "SOFTA", "BRISKA", "DRIVEA", "ACC", "OVRA", "VELOLIM",
                 "JERKLIM", "FA", "SCC", "FPR", "FPRAON", "FPRAOF", "FGREF", "COUPON", "COUPOF"}
SYNC_WORDS = {"WHEN", "WHENEVER", "EVERY", "FROM", "DO"}  # synchronized actions: the rest of the block
FUNCS = {"SIN": 1, "COS": 1, "TAN": 1, "ASIN": 1, "ACOS": 1, "ATAN2": 2, "SQRT": 1, "ABS": 1,
         "POT": 1, "TRUNC": 1, "ROUND": 1, "MINVAL": 2, "MAXVAL": 2, "LN": 1, "EXP": 1, "ROUNDUP": 1,
         "BOUND": 3, "STRLEN": 1, "NUMBER": 1, "ISNUMBER": 1, "TOUPPER": 1, "TOLOWER": 1,
         "AXNAME": 1, "AXSTRING": 1, "SPI": 1, "AXTOSPI": 1}  # the axis functions: interp/sinumerik/axes.py
STRING_FUNCS = {"STRLEN", "NUMBER", "ISNUMBER", "TOUPPER", "TOLOWER"}  # take a string argument
LABEL_RE = re.compile(r"\s*(?:N[0-9]+\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)")
EXT_RE = re.compile(r"([MSL])([0-9]+)\s*([=(])", re.I)  # M1=3, S1=1000, L140(2)
SYS_RE = re.compile(r"\$[A-Za-z_][A-Za-z0-9_]*")  # a system variable ($P_TOOLNO, $AA_IW, $MA_...)
EXP_RE = re.compile(r"EX[+\-]?[0-9]+", re.I)  # 10EX-5: the manuals' exponent
NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
R_ASSIGN_RE = re.compile(r"[Rr]([0-9]+)\s*=")
R_NAME = re.compile(r"R[0-9]+")  # an R parameter by name
AC_IC_RE = re.compile(r"(ACP|ACN|AC|IC|DC)\s*\(", re.I)  # DC/ACP/ACN: absolute (rotary direction)
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
          "T": (0, TOOL_LIMIT, ""), "D": (0, TOOL_LIMIT, ""), "P": (1, PASS_LIMIT, ""), "L": (0, L_LIMIT, ""),
          # the ISO drilling cycles' R plane and peck depth Q (G81 .. G89)
          "R": (-COORD_LIMIT, COORD_LIMIT, "mm"), "Q": (0.0, COORD_LIMIT, "mm")}


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
class Not:
    """NOT x (B_NOT: ``bits``)"""
    operand: Expr
    col: int
    bits: bool = False


@dataclass(frozen=True)
class Index:
    """NAME[i, j]: an array element, or a system variable with its index ($AA_IW[X], $A_DBB[5])."""
    name: str
    index: tuple
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


Expr = Num | Str | Neg | Not | Var | Index | RIndex | FuncCall | BinOp


# ---------------------------------------------------------------------------------------------
# statement nodes (``col``: where the statement starts, 1-based)
@dataclass(frozen=True)
class Word:
    """An address with a value: G1, X-10.5, X=AC(R1+2), CR=5."""
    col: int
    address: str
    value: Expr
    mode: str | None = None  # AC | IC | None (the modal G90/G91)
    ext: int | None = None  # the address extension: M1=3, S1=1000 (spindle 1)
    axis: Expr | None = None  # AX[expr]=value: the axis named by an AXIS expression (address "AX")


@dataclass(frozen=True)
class Assign:
    col: int
    name: str  # R<n>, a DEF variable, a system variable ($...) or a setup [variables] name
    value: Expr
    index: tuple = ()  # A[i, j] = ...


@dataclass(frozen=True)
class Decl:
    name: str
    init: Expr | tuple | None  # an expression, or the element values of an array (SET(..), (..))
    col: int
    dims: tuple = ()  # array dimensions (expressions)
    length: int = 0  # STRING[n]


@dataclass(frozen=True)
class Def:
    col: int
    type: str
    decls: tuple[Decl, ...]


@dataclass(frozen=True)
class Goto:
    col: int
    kind: str  # GOTOF | GOTOB | GOTO | GOTOC
    label: str
    cond: Expr | None = None  # IF <cond> GOTO..
    target: Expr | None = None  # a computed destination (a STRING expression) instead of ``label``


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
class Param:
    """A formal parameter of a PROC: ``REAL A``, ``INT B=5``, ``VAR REAL C``, ``VAR REAL D[,3]``."""
    name: str
    type: str
    var: bool
    default: Expr | None
    col: int
    array: bool = False


@dataclass(frozen=True)
class Proc:
    col: int
    name: str
    params: tuple = ()
    save: bool = False  # SAVE: the modal state comes back on return


@dataclass(frozen=True)
class Command:
    """A bare keyword (STOPRE, TRANS, DISPLOF, ...) or a synchronized action (WHENEVER ...)."""
    col: int
    name: str


@dataclass(frozen=True)
class Case:
    """CASE expr OF v1 GOTOF L1 v2 GOTOB L2 DEFAULT GOTOF L3"""
    col: int
    value: Expr
    branches: tuple  # (Expr, Goto), ...
    default: Goto | None


@dataclass(frozen=True)
class Structured:
    """IF/ELSE/ENDIF, WHILE, FOR, LOOP, REPEAT/UNTIL as read; ``lower`` turns them into Branch."""
    col: int
    kind: str
    cond: Expr | None = None
    var: str = ""  # FOR: the counter
    start: Expr | None = None
    end: Expr | None = None


@dataclass(frozen=True)
class Branch:
    """A jump to line index ``target`` of the unit, taken when ``cond`` is None or its truth is
    ``when`` (the lowered structured control flow)."""
    col: int
    target: int
    cond: Expr | None
    when: bool
    kind: str  # the keyword it came from (for messages)


Stmt = Word | Assign | Def | Goto | Repeat | Call | SubCall | Ret | Proc | Command | Case | Structured | Branch


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
    labels: dict[str, int] = field(default_factory=dict)  # the first line of each label
    program: str = ""  # the file its lines are in
    proc: Proc | None = None  # its PROC statement (parameters, SAVE)
    all_labels: dict[str, list[int]] = field(default_factory=dict)  # every line of each label, in order


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
    scope: dict = field(default_factory=dict)  # the local variables of the (sub)program level
    saved: object = None  # PROC ... SAVE: the modal state to put back on return


# ---------------------------------------------------------------------------------------------
# reading: characters -> expressions and statements
# Binary operators from the lowest priority to the highest (Job Planning, "Priority of the
# operations"): comparisons, <<, OR, XOR, AND, B_OR, B_XOR, B_AND, + -, * / DIV MOD.
COMPARISONS = ("==", "<>", "<=", ">=", "<", ">")
WORD_LEVELS = (("OR",), ("XOR",), ("AND",), ("B_OR",), ("B_XOR",), ("B_AND",))


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

    def peek_word(self) -> str:
        """The name at the cursor (upper case) without consuming it."""
        self.ws()
        m = NAME_RE.match(self.s, self.i)
        return m.group(0).upper() if m else ""

    def take_word(self, word: str) -> bool:
        if self.peek_word() == word:
            self.i += len(word)
            return True
        return False

    def at_end(self) -> bool:
        return not self.peek()

    def close(self, ch: str) -> None:
        if self.peek() != ch:
            raise self.err(self.i + 1, f"'{ch}' expected")
        self.i += 1

    def digits(self, col: int, raw: str) -> None:
        """A written number has at most MAX_DIGITS digits (a 309-digit number is no number)."""
        if len(raw) <= MAX_DIGITS:
            return
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

    # expressions, by priority (COMPARISONS lowest, then <<, WORD_LEVELS, + -, * / DIV MOD, unary)
    def expr(self) -> Expr:
        self.enter(self.i + 1)
        left = self.concat()
        while True:
            self.ws()
            op = next((o for o in COMPARISONS if self.s.startswith(o, self.i)), None)
            if op is None or self.s.startswith("<<", self.i):
                break
            opcol = self.i + 1
            self.i += len(op)
            left = BinOp(op, left, self.concat(), opcol)
        self.depth -= 1
        return left

    def concat(self) -> Expr:
        left = self.words(0)
        while self.peek() == "<" and self.s.startswith("<<", self.i):
            opcol = self.i + 1
            self.i += 2
            left = BinOp("<<", left, self.words(0), opcol)
        return left

    def words(self, level: int) -> Expr:
        """OR, XOR, AND, B_OR, B_XOR, B_AND (level 0 .. 5), then the additive operators."""
        if level == len(WORD_LEVELS):
            return self.additive()
        left = self.words(level + 1)
        while self.peek_word() in WORD_LEVELS[level]:
            op = self.peek_word()
            opcol = self.i + 1
            self.i += len(op)
            left = BinOp(op, left, self.words(level + 1), opcol)
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
        while True:
            c = self.peek()
            if c in ("*", "/"):
                op = c
            elif self.peek_word() in ("DIV", "MOD"):
                op = self.peek_word()
            else:
                return left
            opcol = self.i + 1
            self.i += len(op)
            left = BinOp(op, left, self.unary(), opcol)

    def unary(self) -> Expr:
        c = self.peek()
        col = self.i + 1
        w = self.peek_word()
        if c in ("-", "+", "\u2212") and c or w in ("NOT", "B_NOT"):
            self.enter(col)
            self.i += len(w) if w in ("NOT", "B_NOT") else 1
            v = self.unary()
            self.depth -= 1
            if w in ("NOT", "B_NOT"):
                return Not(v, col, w == "B_NOT")
            return Neg(v) if c != "+" else v
        return self.primary()

    def primary(self) -> Expr:
        c = self.peek()
        col = self.i + 1
        if not c:
            raise self.err(col, "expression expected at the end of the line")
        m = NUMBER_RE.match(self.s, self.i)
        if m:
            return self.number(col, m)
        if c == "(":
            self.i += 1
            v = self.expr()
            self.close(")")
            return v
        if c in "\"'":
            j = self.s.find(c, self.i + 1)
            if j < 0:
                raise self.err(col, "unterminated string")
            v = Str(self.s[self.i + 1:j])
            self.i = j + 1
            return v
        if c == "$":
            m = SYS_RE.match(self.s, self.i)
            if not m:
                raise self.err(col, "a system variable name is expected after '$'")
            self.i = m.end()
            return self.indexed(m.group(0).upper(), col)
        if c.isalpha() or c == "_":
            return self.name_expr(col)
        raise self.err(col, f"unexpected character '{c}' in an expression")

    def number(self, col: int, m) -> Num:
        self.digits(col, m.group(0))
        self.i = m.end()
        value = float(m.group(0))
        e = EXP_RE.match(self.s, self.i)
        if e:
            self.i = e.end()
            exp = int(e.group(0)[2:])
            if abs(exp) > 300:
                raise self.err(col, f"the exponent EX{exp} is out of range")
            value *= 10.0 ** exp
        elif self.i < len(self.s) and (self.s[self.i] == "." or self.s[self.i].isalpha()
                                       and self.s[self.i].upper() not in ADDRESSES | {"R", "C", "A", "N"}
                                       and self.peek_word() not in KEYWORDS):
            raise self.err(col, f"malformed number '{self.s[col - 1:self.i + 1]}'")
        return Num(value)

    def indexed(self, name: str, col: int) -> Expr:
        """NAME or NAME[i, j] (array element, system variable with its index)."""
        if self.peek() != "[":
            return Var(name, col)
        self.i += 1
        idx = [self.expr()]
        while self.peek() == ",":
            self.i += 1
            idx.append(self.expr())
        self.close("]")
        return Index(name, tuple(idx), col)

    def name_expr(self, col: int) -> Expr:
        """A function call, R[expr], an array element or a variable."""
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
        if name in ("AC", "IC") and self.peek() == "(":
            raise self.err(col, f"{name}(..) only goes with an address: X={name}(..)")
        return self.indexed(name, col)

    # statements
    def label(self) -> str:
        """A jump destination: a label, N<number> or a block number alone (GOTOF 40 = N40)."""
        self.ws()
        m = re.match(r"N?([0-9]+)\b", self.s[self.i:], re.I)
        if m:
            self.i += m.end()
            return "N" + str(int(m.group(1)))
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
        if c == "$":
            return self.sys_assign(col, ln)
        mr = R_ASSIGN_RE.match(text, self.i)
        if mr:  # R<n>=expr
            if len(mr.group(1).lstrip("0")) > len(str(R_LIMIT)) or int(mr.group(1)) > R_LIMIT:
                raise self.err(col, f"R{mr.group(1)}: there are the parameters R0 to R{R_LIMIT}")
            self.i = mr.end()
            ln.stmts.append(Assign(col, "R" + str(int(mr.group(1))), self.expr()))
            return True
        ext = EXT_RE.match(text, self.i) if up in "MSL" else None
        if ext:
            return self.extended(col, ext, ln)
        if up == "H" and self.i + 1 < len(text) and text[self.i + 1] in "0123456789+-.=":
            return self.h_word(col, ln)
        if up in ISO_ADDRESSES and self.i + 1 < len(text) and text[self.i + 1] in "0123456789+-.\u2212":
            # R2.5, Q3 of an ISO drilling cycle (G81 R2 Z-10): R<n>=.. is an R parameter (above), R<n>
            # alone has no other meaning; the interpreter refuses them outside a cycle
            self.i += 1
            v = self.number_word()
            if v is None:
                raise self.err(col, f"malformed number after {up}")
            ln.stmts.append(Word(col, up, Num(v)))
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
        return self.keyword(col, name, first, ln)

    def keyword(self, col: int, name: str, first: bool, ln: Line) -> bool:
        """A statement that starts with a name: keywords, commands, NAME(..), NAME=.., a call."""
        nxt = self.peek()
        reader = _KEYWORD_READERS.get(name)
        if reader is not None and nxt != "=":
            st = reader(self, col, name)
            ln.stmts.append(st)
            if isinstance(st, Proc) or isinstance(st, Command) and st.name == "EXTERN":
                self.i = len(self.s)  # the rest of the line belongs to it
                return False
            return True
        if name in SYNC_WORDS or name in ("ID", "IDS") and nxt == "=":
            ln.stmts.append(Command(col, "WHENEVER" if name in SYNC_WORDS else "ID"))
            self.i = len(self.s)  # a synchronized action: the rest of the block is its condition/action
            return False
        if name in IGNORED_WORDS:
            return True
        if name in SETTING_WORDS and nxt in ("=", "[", "("):
            self.skip_setting()
            ln.stmts.append(Command(col, name))
            return True
        if (name in LANG_COMMANDS or name in MACHINE_COMMANDS) and nxt != "=" and nxt != "[":
            if nxt == "(":
                self.i += 1
                ln.stmts.append(Call(col, name, tuple(self.arguments())))
            else:
                ln.stmts.append(Command(col, name))
            return True
        ln.stmts.append(self.named(col, name, nxt))
        return True

    def skip_setting(self) -> None:
        """SPOS=90, SPOS[2]=IC(10), LIMS=3000, FA[B]=100: read past the index and the value."""
        if self.peek() == "[":
            self.indexed("_", self.i + 1)
        if self.peek() == "(":
            self.i += 1
            self.arguments()
            return
        self.close("=")
        self.ws()
        mm = AC_IC_RE.match(self.s, self.i)
        if mm:
            self.i = mm.end()
            self.expr()
            self.close(")")
        else:
            self.expr()

    def h_word(self, col: int, ln: Line) -> bool:
        """H20, H=5, H2=10: an auxiliary function for the PLC (no effect on the tool path)."""
        m = re.match(r"H([0-9]*)\s*=", self.s[self.i:], re.I)
        if m:  # H=5, H2=10
            self.i += m.end()
            self.expr()
        else:
            self.i += 1
            if self.number_word() is None:
                raise self.err(col, "malformed number after H")
        ln.stmts.append(Command(col, "H"))
        return True

    def extended(self, col: int, m, ln: Line) -> bool:
        """M1=3, S1=1000 (an address with its extension) and L140(2) (an L call with parameters)."""
        letter, num, sep = m.group(1).upper(), m.group(2), m.group(3)
        self.i = m.end()
        if letter == "L":
            if sep != "(":
                raise self.err(col, f"L{num}= is no statement: L<n> calls a subprogram")
            ln.stmts.append(Call(col, f"L{int(num)}", tuple(self.arguments())))
            return True
        if sep == "(":
            raise self.err(col, f"unexpected '(' after {letter}{num}")
        ln.stmts.append(Word(col, letter, self.expr(), ext=int(num)))
        return True

    def sys_assign(self, col: int, ln: Line) -> bool:
        """$NAME=expr or $NAME[i]=expr: a write to a system variable."""
        target = self.primary()
        if self.peek() != "=" or self.s.startswith("==", self.i):
            raise self.err(col, "a system variable stands alone only on the left of '=': $NAME=<value>")
        self.i += 1
        name, idx = (target.name, ()) if isinstance(target, Var) else (target.name, target.index)
        ln.stmts.append(Assign(col, name, self.expr(), idx))
        return True

    def named(self, col: int, name: str, nxt: str) -> Stmt:
        """NAME(args), NAME=value, NAME[i]=value, AX[axis]=value or NAME alone (a subprogram call)."""
        if nxt == "(":
            self.i += 1
            return Call(col, name, tuple(self.arguments()))
        if nxt == "[":
            target = self.indexed(name, col)
            if self.peek() != "=":
                raise self.err(self.i + 1, f"'=' expected after {name}[..]")
            self.i += 1
            if name == "AX":
                w = self.address_value(col, "AX")
                return Word(col, "AX", w.value, w.mode, axis=target.index[0] if len(target.index) == 1 else None)
            return Assign(col, name, self.expr(), target.index)
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
        return Word(col, name, v, "IC" if mm.group(1).upper() == "IC" else "AC")

    def rest_empty(self, what: str) -> None:
        if not self.at_end():
            raise self.err(self.i + 1, f"{what} stands alone in its block: nothing may follow it")


def _read_def(sc: _Scanner, col: int, name: str) -> Def:
    sc.ws()
    for scope in ("NCK", "CHAN"):  # the scope of global data (definition files): no meaning here
        if sc.take_word(scope):
            sc.ws()
    typ = sc.ident()
    if typ not in TYPES:
        raise sc.err(sc.i + 1, "DEF needs a type (REAL, INT, BOOL, CHAR, STRING[n], AXIS, FRAME)")
    length = 0
    if typ == "STRING" and sc.peek() == "[":
        sc.i += 1
        m = re.match(r"\s*([0-9]+)\s*\]", sc.s[sc.i:])
        if not m:
            raise sc.err(sc.i + 1, "STRING[n] needs its length as a number")
        sc.i += m.end()
        length = int(m.group(1))
    decls = []
    while True:
        sc.ws()
        vcol = sc.i + 1
        vname = sc.ident()
        if not vname:
            raise sc.err(vcol, "variable name expected after DEF")
        dims: tuple = ()
        if sc.peek() == "[":
            dims = sc.indexed(vname, vcol).index
        init = None
        if sc.peek() == "=":
            sc.i += 1
            init = _read_init(sc) if dims else sc.expr()
        decls.append(Decl(vname, init, vcol, dims, length))
        if sc.peek() != ",":
            return Def(col, typ, tuple(decls))
        sc.i += 1


def _read_init(sc: _Scanner) -> tuple:
    """An array's initial values: SET(a, b, ..), (a, b, ..), REP(v) or one value for all."""
    rep = sc.take_word("REP")
    if not rep:
        sc.take_word("SET")
    if sc.peek() != "(":
        return ("REP", sc.expr())
    sc.i += 1
    vals = [a.value if a.value is not None else Num(0.0) for a in sc.arguments()]
    return ("REP", vals[0]) if rep and vals else tuple(vals)


def _read_goto(sc: _Scanner, col: int, name: str, cond: Expr | None = None) -> Goto:
    if sc.peek() == '"':  # GOTOF "STEP_" << NR: the destination computed as a string
        return Goto(col, name, "", cond, sc.expr())
    target = sc.label()
    if not target:
        raise sc.err(sc.i + 1, f"{name} needs a label or a block number")
    return Goto(col, name, target, cond)


def _read_if(sc: _Scanner, col: int, name: str) -> Stmt:
    cond = sc.expr()
    if sc.at_end():
        return Structured(col, "IF", cond)
    sc.ws()
    gcol = sc.i + 1
    g = sc.ident()
    if g not in JUMPS:
        raise sc.err(gcol, "IF <condition> is followed by GOTOF/GOTOB/GOTO/GOTOC <label>, or stands alone "
                     "(IF ... ELSE ... ENDIF)")
    return _read_goto(sc, col, g, cond)


def _read_cond(sc: _Scanner, col: int, name: str) -> Structured:
    cond = sc.expr()
    sc.rest_empty(f"{name} <condition>")
    return Structured(col, name, cond)


def _read_bare(sc: _Scanner, col: int, name: str) -> Structured:
    sc.rest_empty(name)
    return Structured(col, name)


def _read_for(sc: _Scanner, col: int, name: str) -> Structured:
    sc.ws()
    vcol = sc.i + 1
    var = sc.ident()
    m = R_ASSIGN_RE.match(sc.s, vcol - 1)
    if m:
        var = "R" + str(int(m.group(1)))
        sc.i = m.end() - 1
    if not var or sc.peek() != "=":
        raise sc.err(vcol, "FOR <variable> = <start> TO <end>")
    sc.i += 1
    start = sc.expr()
    if not sc.take_word("TO"):
        raise sc.err(sc.i + 1, "FOR <variable> = <start> TO <end>: TO expected")
    end = sc.expr()
    sc.rest_empty("FOR ... TO ...")
    return Structured(col, "FOR", None, var, start, end)


def _read_repeat(sc: _Scanner, col: int, name: str) -> Stmt:
    if sc.at_end():
        return Structured(col, "REPEAT")
    l1 = sc.label()
    if not l1:
        raise sc.err(sc.i + 1, "REPEAT needs a label (REPEAT <label> P=n) or stands alone (REPEAT ... UNTIL)")
    sc.ws()
    save = sc.i
    l2 = sc.label()
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


def _read_repeatb(sc: _Scanner, col: int) -> Repeat:
    """REPEATB LABEL P=n: the one block with LABEL, n times (REPEAT LABEL LABEL P=n)."""
    lab = sc.label()
    if not lab:
        raise sc.err(sc.i + 1, "REPEATB needs the label of the block to repeat")
    count: Expr = Num(1.0)
    if sc.peek().upper() == "P":
        sc.i += 1
        sc.close("=")
        count = sc.expr()
    return Repeat(col, lab, lab, count)


def _read_call(sc: _Scanner, col: int) -> Call:
    """CALL "NAME" / CALL NAME_VAR: a subprogram named by a string expression."""
    return Call(col, "CALL", (Arg(sc.expr(), sc.i + 1),))


def _read_extcall(sc: _Scanner, col: int) -> Call:
    """EXTCALL "PATH/NAME.SPF": a program on external storage, named by a string expression."""
    return Call(col, "EXTCALL", (Arg(sc.expr(), sc.i + 1),))


PCALL_PATH_RE = re.compile(r"/?(?:[A-Za-z0-9_]+/)*")  # PCALL /_N_WKS_DIR/_N_PART_WPD/NAME: the folders
PCALL_ARCHIVE_RE = re.compile(r"_N_([A-Z0-9_]+)_(?:SPF|MPF)")


def _read_pcall(sc: _Scanner, col: int) -> Call | SubCall:
    """PCALL NAME / PCALL /_N_WKS_DIR/_N_PART_WPD/_N_NAME_SPF(args): a subprogram call by path; the
    simulator finds it by its name (the folders of the path are not searched)."""
    sc.ws()
    sc.i = PCALL_PATH_RE.match(sc.s, sc.i).end()
    ncol = sc.i + 1
    name = sc.ident()
    if not name:
        raise sc.err(ncol, "PCALL needs a subprogram name (PCALL NAME or PCALL /_N_WKS_DIR/_N_PART_WPD/NAME)")
    m = PCALL_ARCHIVE_RE.fullmatch(name)
    name = m.group(1) if m else name
    if sc.peek() == "(":
        sc.i += 1
        return Call(ncol, name, tuple(sc.arguments()))
    return SubCall(ncol, name)


def _read_case(sc: _Scanner, col: int, name: str) -> Case:
    value = sc.expr()
    if not sc.take_word("OF"):
        raise sc.err(sc.i + 1, "CASE <expression> OF <value> GOTOF <label> ... DEFAULT GOTOF <label>")
    branches, default = [], None
    while not sc.at_end():
        if sc.take_word("DEFAULT"):
            default = _case_jump(sc, col)
            break
        const = sc.unary()
        branches.append((const, _case_jump(sc, col)))
    sc.rest_empty("CASE ... DEFAULT GOTOF <label>")
    if not branches and default is None:
        raise sc.err(col, "CASE needs at least one <value> GOTOF <label>")
    return Case(col, value, tuple(branches), default)


def _case_jump(sc: _Scanner, col: int) -> Goto:
    sc.ws()
    gcol = sc.i + 1
    g = sc.ident()
    if g not in JUMPS:
        raise sc.err(gcol, "a CASE value is followed by GOTOF/GOTOB/GOTO/GOTOC <label>")
    return _read_goto(sc, gcol, g)


def _read_proc(sc: _Scanner, col: int, name: str) -> Proc:
    pname = sc.ident()
    if not pname:
        raise sc.err(sc.i + 1, "PROC needs the subprogram's name")
    params: list[Param] = []
    if sc.peek() == "(":
        sc.i += 1
        while sc.peek() != ")":
            params.append(_read_param(sc))
            if sc.peek() == ",":
                sc.i += 1
            elif sc.peek() != ")":
                raise sc.err(sc.i + 1, "',' or ')' expected in the parameter list")
        sc.i += 1
    save = False
    while not sc.at_end():  # SAVE, DISPLOF, SBLOF, ACTBLOCNO ...: attributes
        acol = sc.i + 1
        attr = sc.ident()
        if not attr:
            raise sc.err(acol, "unexpected text after the PROC's parameter list")
        save = save or attr == "SAVE"
    return Proc(col, pname, tuple(params), save)


def _read_param(sc: _Scanner) -> Param:
    sc.ws()
    pcol = sc.i + 1
    var = sc.take_word("VAR")
    sc.ws()
    typ = sc.ident()
    if typ not in TYPES:
        raise sc.err(pcol, "a PROC parameter is [VAR] <type> <name> (REAL, INT, BOOL, CHAR, STRING[n], AXIS, FRAME)")
    if typ == "STRING" and sc.peek() == "[":
        j = sc.s.find("]", sc.i)
        sc.i = len(sc.s) if j < 0 else j + 1
    sc.ws()
    ncol = sc.i + 1
    pname = sc.ident()
    if not pname:
        raise sc.err(ncol, "a PROC parameter needs a name")
    array = False
    if sc.peek() == "[":  # VAR REAL A[,3]: an array parameter (dimensions as declared by the caller)
        j = sc.s.find("]", sc.i)
        sc.i = len(sc.s) if j < 0 else j + 1
        array = True
    default = None
    if sc.peek() == "=":
        sc.i += 1
        default = sc.expr()
    return Param(pname, typ, var, default, ncol, array)


def _read_extern(sc: _Scanner, col: int, name: str) -> Command:
    if not sc.ident():
        raise sc.err(sc.i + 1, "EXTERN needs the subprogram's name")
    return Command(col, "EXTERN")


def _read_ret(sc: _Scanner, col: int, name: str) -> Ret:
    if sc.peek() == "(":  # RET("label", ..) / RET(, , n): a return to a block; not simulated
        raise sc.err(col, "RET with parameters (a return to another block) is not supported: use RET")
    return Ret(col)


_KEYWORD_READERS = {"DEF": _read_def, "GOTOF": _read_goto, "GOTOB": _read_goto, "GOTO": _read_goto,
                    "GOTOC": _read_goto, "IF": _read_if, "REPEAT": _read_repeat, "PROC": _read_proc,
                    "REPEATB": lambda sc, col, name: _read_repeatb(sc, col), "CALL": lambda sc, col, name: _read_call(sc, col),
                    "EXTCALL": lambda sc, col, name: _read_extcall(sc, col),
                    "PCALL": lambda sc, col, name: _read_pcall(sc, col),
                    "RET": _read_ret, "CASE": _read_case, "EXTERN": _read_extern, "FOR": _read_for,
                    "WHILE": _read_cond, "UNTIL": _read_cond, "ELSE": _read_bare, "ENDIF": _read_bare,
                    "ENDWHILE": _read_bare, "ENDFOR": _read_bare, "LOOP": _read_bare, "ENDLOOP": _read_bare}


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
    if m and m.group(1).upper() not in ("DEF", "IF", "CASE") and len(m.group(1)) >= 2:
        ln.label = m.group(1).upper()
        pre = re.match(r"\s*N([0-9]+)", sc.s)
        if pre:
            ln.nlabel = "N" + str(int(pre.group(1)))
        sc.i = m.end()


# Bytes that may end a file without being a block: Ctrl-Z (0x1A, the DOS end of file the
# controllers' PC tools append) and NUL padding.
FILE_END_BYTES = "\x1a\x00"


def scan_line(prog: str, lineno: int, raw: str) -> Line:
    """One block: comment off, characters checked, label, then its statements. A skip block
    ``/`` at the start is read like any block (the skip level is off in the simulation)."""
    ln = Line(lineno, raw)
    text = strip_comment(raw)
    stripped = text.lstrip()
    if stripped.startswith("%") or stripped.startswith("$PATH") or not stripped.strip(FILE_END_BYTES + " \t"):
        return ln  # program header (%_N_NAME_MPF, ;$PATH=...), a blank line or the file's end bytes
    check_text(prog, lineno, text.rstrip(FILE_END_BYTES + " \t"))
    if stripped.startswith("/"):
        text = text.replace("/", " ", 1)
    sc = _Scanner(prog, lineno, text.rstrip(FILE_END_BYTES + " \t"))
    read_label(sc, ln)
    first = True
    while sc.statement(first, ln):
        first = False
    return ln


def split_units(prog: str, text: str, fast=None) -> tuple[Unit, dict[str, Unit]]:
    """The main program and the subprograms (%_N_NAME_SPF headers, PROC NAME) of one file; their
    structured control flow lowered to jumps (``lower``). ``fast``: a plain-line reader
    (sinumerik_fast.read_plain) tried before ``scan_line``: the same Line or None."""
    lines = [(fast and fast(prog, k, raw)) or scan_line(prog, k, raw) for k, raw in enumerate(split_lines(text), start=1)]
    main = Unit("MAIN", [], program=prog)
    subs: dict[str, Unit] = {}
    cur = main
    for ln in lines:
        hdr = HEADER_RE.match(ln.text)
        if hdr and hdr.group(2) == "SPF":
            cur = subs.setdefault(hdr.group(1).upper(), Unit(hdr.group(1).upper(), [], program=prog))
            continue
        if ln.stmts and isinstance(ln.stmts[0], Proc):
            proc = ln.stmts[0]
            if cur is not main and cur.name == proc.name and not any(x.stmts for x in cur.lines):
                cur.proc = proc  # %_N_NAME_SPF followed by PROC NAME(...)
            elif cur is main and not any(x.stmts for x in main.lines):
                cur = subs.setdefault(proc.name, Unit(proc.name, [], program=prog, proc=proc))
            else:
                cur = subs.setdefault(proc.name, Unit(proc.name, [], program=prog, proc=proc))
            continue
        cur.lines.append(ln)
    for u in [main, *subs.values()]:
        for idx, ln in enumerate(u.lines):
            for lab in (ln.label, ln.nlabel):
                if lab:
                    u.labels.setdefault(lab, idx)
                    u.all_labels.setdefault(lab, []).append(idx)
        lower(prog, u)
    return main, subs


_OPENERS = {"IF": ("ELSE", "ENDIF"), "WHILE": ("ENDWHILE",), "FOR": ("ENDFOR",), "LOOP": ("ENDLOOP",),
            "REPEAT": ("UNTIL",)}
_CLOSERS = {"ELSE": "IF", "ENDIF": "IF", "ENDWHILE": "WHILE", "ENDFOR": "FOR", "ENDLOOP": "LOOP", "UNTIL": "REPEAT"}
MAX_STRUCT_DEPTH = 16  # IF/WHILE/FOR/LOOP/REPEAT nested in one (sub)program (Siemens: 16 levels)


def lower(prog: str, unit: Unit) -> None:
    """Replace the unit's structured statements by Branch jumps (line indices of the unit): IF c
    jumps past its ELSE (or ENDIF) when c is false, ELSE jumps past ENDIF; WHILE c jumps past
    ENDWHILE when c is false and ENDWHILE back to the WHILE; FOR sets its counter and jumps past
    ENDFOR when it is beyond the end, ENDFOR counts up and jumps back after the FOR while it is
    not; ENDLOOP jumps back after LOOP; UNTIL c jumps back after REPEAT while c is false. A closer
    without its opener, or an opener left open, is an error at the opener's line."""
    open_: list[tuple[int, Structured, int | None]] = []  # (line index, statement, ELSE index)
    for idx, ln in enumerate(unit.lines):
        st = next((s for s in ln.stmts if isinstance(s, Structured)), None)
        if st is None:
            continue
        if ln.stmts[0] is not st or len(ln.stmts) > 1:
            raise CutsimError(prog, ln.line, st.col, f"{st.kind} stands alone in its block")
        if st.kind in _OPENERS:
            if len(open_) >= MAX_STRUCT_DEPTH:
                raise CutsimError(prog, ln.line, st.col, f"control structures nested deeper than {MAX_STRUCT_DEPTH} levels")
            open_.append((idx, st, None))
            continue
        if not open_:
            raise CutsimError(prog, ln.line, st.col, f"{st.kind} without {_CLOSERS[st.kind]}")
        oidx, ost, else_idx = open_[-1]
        if _CLOSERS[st.kind] != ost.kind:
            oln = unit.lines[oidx]
            raise CutsimError(prog, oln.line, ost.col, f"{ost.kind} (line {oln.line}) is closed by {st.kind} "
                              f"in line {ln.line}: expected {' or '.join(_OPENERS[ost.kind])}")
        if st.kind == "ELSE":
            if else_idx is not None:
                raise CutsimError(prog, ln.line, st.col, f"a second ELSE for the IF of line {unit.lines[oidx].line}")
            open_[-1] = (oidx, ost, idx)
            continue
        open_.pop()
        _lower_pair(unit, oidx, ost, else_idx, idx, st)
    if open_:
        oidx, ost, _ = open_[-1]
        raise CutsimError(prog, unit.lines[oidx].line, ost.col,
                          f"{ost.kind} without {_OPENERS[ost.kind][-1]} in {'the program' if unit.name == 'MAIN' else unit.name}")


def _lower_pair(unit: Unit, o: int, ost: Structured, e: int | None, c: int, cst: Structured) -> None:
    """Rewrite the opener at line index ``o`` (ELSE at ``e``) and its closer at ``c``."""
    lines = unit.lines
    if ost.kind == "IF":
        lines[o].stmts = [Branch(ost.col, (e if e is not None else c) + 1, ost.cond, False, "IF")]
        if e is not None:
            lines[e].stmts = [Branch(lines[e].stmts[0].col, c + 1, None, True, "ELSE")]
        lines[c].stmts = []
    elif ost.kind == "WHILE":
        lines[o].stmts = [Branch(ost.col, c + 1, ost.cond, False, "WHILE")]
        lines[c].stmts = [Branch(cst.col, o, None, True, "ENDWHILE")]
    elif ost.kind == "FOR":
        counter = Var(ost.var, ost.col)
        lines[o].stmts = [Assign(ost.col, ost.var, ost.start),
                          Branch(ost.col, c + 1, BinOp(">", counter, ost.end, ost.col), True, "FOR")]
        lines[c].stmts = [Assign(cst.col, ost.var, BinOp("+", counter, Num(1.0), cst.col)),
                          Branch(cst.col, o + 1, BinOp("<=", counter, ost.end, cst.col), True, "ENDFOR")]
    elif ost.kind == "LOOP":
        lines[o].stmts = []
        lines[c].stmts = [Branch(cst.col, o + 1, None, True, "ENDLOOP")]
    else:  # REPEAT ... UNTIL
        lines[o].stmts = []
        lines[c].stmts = [Branch(cst.col, o + 1, cst.cond, False, "UNTIL")]
