"""Sinumerik 840D language: its limits and messages and the typed syntax tree the reader builds
(spec/sinumerik.md, docs/dialects/sinumerik.md). Expressions are ``Expr`` nodes (``Num``, ``Str``,
``Neg``, ``Var``, ``RIndex``, ``FuncCall``, ``BinOp``) evaluated when the block runs; statements are
``Stmt`` nodes (``Word``, ``Assign``, ``Def``, ``Goto``, ``Repeat``, ``Call``, ``SubCall``, ``Ret``,
``Proc``, ``Command``, ``Case``, ``Branch``); a program is ``Unit``s of ``Line``s.
"""
from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass, field

from ..core.lexer import permitted_range
from ..errors import CutsimError


EXTRA_AXES = set("ABCUVW")  # axis letters beyond X/Y/Z: words for them need the setup's [machine] axes
ADDRESSES = set("GMXYZIJKFSTDLP") | EXTRA_AXES  # single-letter addresses with a number
ISO_ADDRESSES = {"R", "Q"}  # the ISO drilling cycles' R plane and peck depth, with a plain number
EXPR_ADDRESSES = {"X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "CR", "P", "RPL",
                  "SF", "DITS", "DITE", "LIMS"} | EXTRA_AXES  # RPL: ROT RPL=30; the lathe's (interp/sinumerik/lathe.py)
STRUCTURED = {"IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "LOOP", "ENDLOOP", "REPEAT", "UNTIL"}
KEYWORDS = {"DEF", "GOTOF", "GOTOB", "GOTO", "GOTOC", "PROC", "RET", "CASE", "EXTERN", "REPEATB", "CALL", "EXTCALL",
            "PCALL", "OF", "DEFAULT",
            "TO", "AND", "OR", "XOR", "NOT", "DIV", "MOD", "B_AND", "B_OR", "B_XOR", "B_NOT"} | STRUCTURED
TYPES = {"REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME"}
JUMPS = ("GOTOF", "GOTOB", "GOTO", "GOTOC")
IGNORED_WORDS: set[str] = set()
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
                    "TRACYL", "DIAMON", "DIAM90", "DIAMOF", "DIAMCYCOF", "CUT2D", "CUT2DF", "CUT3DC", "CDON", "CDOF", "CDOF2",
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
SETTING_WORDS = {"SPOS", "SPOSA", "ADIS", "ADISPOS", "SOFTA", "BRISKA", "DRIVEA", "ACC", "OVRA", "VELOLIM",
                 "JERKLIM", "FA", "SCC", "FPR", "FPRAON", "FPRAOF", "FGREF", "COUPON", "COUPOF"}
SYNC_WORDS = {"WHEN", "WHENEVER", "EVERY", "FROM", "DO"}  # synchronized actions: the rest of the block
FUNCS = {"SIN": 1, "COS": 1, "TAN": 1, "ASIN": 1, "ACOS": 1, "ATAN2": 2, "SQRT": 1, "ABS": 1,
         "POT": 1, "TRUNC": 1, "ROUND": 1, "MINVAL": 2, "MAXVAL": 2, "LN": 1, "EXP": 1, "ROUNDUP": 1,
         "BOUND": 3, "STRLEN": 1, "NUMBER": 1, "ISNUMBER": 1, "TOUPPER": 1, "TOLOWER": 1,
         "AXNAME": 1, "AXSTRING": 1, "SPI": 1, "AXTOSPI": 1}  # the axis functions: interp/sinumerik/axes.py
STRING_FUNCS = {"STRLEN", "NUMBER", "ISNUMBER", "TOUPPER", "TOLOWER"}  # take a string argument
LABEL_RE = re.compile(r"\s*(?:N[0-9]+\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)")
EXT_RE = re.compile(r"([MSLT])([0-9]+)\s*([=(])", re.I)  # M1=3, S1=1000, T1=5, L140(2)
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


def range_message(what: str, value: float, lo: float, hi: float, unit: str = "") -> str:
    """The one message for a value beyond its range (the manuals' "value exceeds the permitted range")."""
    shown = f"{value:.10g}" if math.isfinite(value) else str(value)
    return f"{what} = {shown}: value {permitted_range(lo, hi, unit)}"


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
