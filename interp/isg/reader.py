"""One line of an ISG (TwinCAT CNC) program -> a statement: a block with its words, assignments,
calls and ``#`` commands, or a ``$`` control statement (docs/dialects/isg.md); program.py reads a
whole file into sections (``%name``, ``%L name``) with their control structures matched.

Expressions are compiled here (lang.py) and evaluated when the block runs (interpreter.py).
This module imports neither the interpreter nor the executor.
"""
from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field

from ..errors import CutsimError
from .lang import CONTROL, IDENT, Cursor, arguments, expression, param, primary, var_ref
from ..core.lexer import (CODE_LIMIT, COORD_LIMIT, SPEED_LIMIT, Block, Word, block_lines, block_number,
                          parse_number)

LETTERS = set("NGMXYZIJKFSTDLHABCUVWR")
LIMITS = {**{a: (COORD_LIMIT, "mm") for a in "XYZIJKABCUVWR"}, "F": (COORD_LIMIT, "mm/min"),
          "S": (SPEED_LIMIT, "rpm"), **{a: (CODE_LIMIT, "") for a in "GMTDH"}}
NAME = re.compile(r"(?:\w|[\u0300-\u036f\u1ab0-\u1aff\u1dc0-\u1dff\u20d0-\u20ff\ufe20-\ufe2f])+")
FILE_NAME = re.compile(r"[^\s;(\[\]]+")
SPINDLE_ATTR = re.compile(r"\.([A-Za-z_]\w*)")
HEADER = re.compile(r"%(?:(?P<local>[Ll])[ \t]+(?P<lname>\S+)|[ \t]*(?P<mname>[^\s(;]+))")
COMMAND = re.compile(r"#\s*([A-Za-z_]+)(?:[ \t]+([A-Za-z_]+))?")
MACRO_DEF = re.compile(r'\s*(?:N[0-9]+\s+)?"([^"\\]+)"\s*=\s*"((?:[^"\\]|\\.)*)"\s*(?:;.*)?$')
MACRO_USE = re.compile(r'"([^"\\]+)"')
MAX_MACRO_DEPTH = 16
NAMED_AXIS = re.compile(r"([A-Za-z][0-9]{1,2})\s*=(?!=)")
AXIS_COMMAND = re.compile(r"\[\s*[A-Za-z_]{3,}\w*\s+[A-Za-z_]")
NOT_AXIS_COMMAND = re.compile(r"\[\s*(?:V\.|P\d|SIN|COS|TAN|ABS|SQRT?|INT|ROUND|FRACT)", re.I)
BLOCK_LINES = block_lines(r"[^\s;%(#]")


def nfc(s: str) -> str:
    return unicodedata.normalize("NFC", s)


@dataclass
class IsgBlock(Block):
    call: tuple[str, int] | None = None  # LL name: (subprogram name, column of the name)
    gcall: tuple[str, int, dict] | None = None  # L name: (file name, column, {"@P1": closure})
    offsets: list[Word] = field(default_factory=list)  # S.OFFSET words
    items: list = field(default_factory=list)  # in order: ("w", Word) | ("x", letter, f, raw, col) | ("a", ...)
    args: dict = field(default_factory=dict)  # column of a G word -> its argument list (G805[...])
    gvalues: dict = field(default_factory=dict)  # column of a G/M word -> value closure (M200=40)
    commands: list = field(default_factory=list)  # (NAME, text after it, column)
    goto: tuple | None = None  # ("N", f, col) | ("S", name or f, col)
    cond: object = None  # $IF <cond> $GOTO ... in one line: the condition
    target: str = ""  # the label this line defines ("N10" for N10:, "[NAME]")
    deferred: str = ""  # a line using a macro not defined when it was read: expanded when it runs
    modal: str = ""  # L/LL CYCLE [..]: "CYCLE", or "MODAL_MOVE" / "MODAL_BLOCK" for a modal cycle call
    cparams: dict = field(default_factory=dict)  # LL CYCLE [..]: {"@P1": closure}
    decls: list = field(default_factory=list)  # a #VAR block after the level's first block: run where it stands

    @property
    def empty(self) -> bool:
        return not (self.items or self.call or self.gcall or self.offsets or self.commands or self.goto
                    or self.deferred or self.decls)


@dataclass
class Ctrl:
    """A control statement: $IF cond, $ELSE, $FOR P1 = a, b, c, ..."""
    line: int
    col: int
    kw: str
    expr: object = None
    var: tuple | None = None  # $FOR: (kind, key closure, column)
    exprs: tuple = ()  # $FOR: start, end, step
    label: str = ""
    match: dict = field(default_factory=dict)  # filled by match_control


@dataclass
class VarDecl:
    line: int
    col: int
    scope: str
    name: str  # upper case, without indices
    dims: tuple[int, ...]
    init: list  # closures (one per element given)


@dataclass
class Section:
    kind: str  # "main" | "local"
    name: str
    line: int
    col: int
    blocks: list = field(default_factory=list)  # IsgBlock and Ctrl
    decls: list[VarDecl] = field(default_factory=list)
    ended: bool = False
    labels: dict = field(default_factory=dict)  # "N10" / "[NAME]" -> index
    others: list = field(default_factory=list)  # further main programs of the file (not run)
    title: str = ""  # text after a main program's name without parentheses ("% 1x10 dots right")

    @property
    def flow(self) -> bool:
        return any(isinstance(b, Ctrl) or b.goto is not None or b.gcall is not None for b in self.blocks)


# -- one line ----------------------------------------------------------------------------------------
def skip_comment(prog: str, line: int, text: str, i: int) -> int:
    """A ``( ... )`` comment at ``text[i]``: the index after its ``)``; without one the comment runs
    to the end of the line (real programs write ``(comment`` that way)."""
    j = text.find(")", i + 1)
    return len(text) if j < 0 else j + 1


def scan(prog: str, lineno: int, text: str):
    """One line (not a header, not inside #COMMENT or #VAR) -> IsgBlock, Ctrl or None (blank)."""
    cur = Cursor(prog, lineno, text)
    block = IsgBlock(line=lineno, col=1)
    cur.skip()
    if cur.peek() == "/":  # block skip: the simulator runs the block (skip switch off)
        cur.i += 1
    seen: dict[str, int] = {}
    while True:
        cur.skip()
        if cur.i >= len(text):
            break
        c = text[cur.i]
        col = cur.i + 1
        if c == ";":
            break
        if c == "(":
            cur.i = skip_comment(prog, lineno, text, cur.i)
            continue
        if c == "$":
            return control(cur, block)
        if c == "#":
            m = re.compile(r"#\s*(IF|ELSE|ENDIF)\b", re.I).match(text, cur.i)
            if m:  # conditional interpretation: read like $IF / $ELSE / $ENDIF
                cur.text = text[:cur.i] + "$" + text[m.start(1):]
                return control(cur, block)
            command(cur, block)
            break
        if c == "[" and not block.items and not block.target:
            m = re.compile(r"\[\s*([A-Za-z_][A-Za-z0-9_]*)\s*\]").match(text, cur.i)
            if not m:
                raise cur.error("a label is a name in '[ ]' at the start of a block ([NAME])")
            block.target = f"[{m.group(1).upper()}]"
            cur.i = m.end()
            continue
        if c == "@" or (c in "Vv" and cur.peek(1) == ".") or (c in "Pp" and (cur.peek(1).isdigit() or cur.peek(1) == "[")):
            assignment(cur, block)
            continue
        if not (c.isascii() and c.isalpha()):
            raise cur.error(f"unexpected character '{c}'")
        word(cur, block, seen)
    if not block.label and block.empty and not block.target:
        return None
    return block


def word(cur: Cursor, block: IsgBlock, seen: dict) -> None:
    text, lineno, prog = cur.text, cur.line, cur.prog
    col = cur.i + 1
    letter = text[cur.i].upper()
    cur.i += 1
    if letter == "N" and cur.peek().isdigit():
        cur.i = block_number(prog, lineno, text, cur.i, block, must_open=False)
        if cur.peek() == ":":
            cur.i += 1
            block.target = block.label
        return
    if letter == "L":
        return call(cur, block, col)
    if letter == "S" and cur.peek() == "." and SPINDLE_ATTR.match(text, cur.i):
        return spindle_attr(cur, block, col)
    named = NAMED_AXIS.match(text, col - 1) if (letter not in "GMNTDHS" and "=" in text[cur.i:cur.i + 4]) else None
    if named:  # an axis named with digits: W1 = 100, A1=90
        name = named.group(1).upper()
        if name in seen:
            raise CutsimError(prog, lineno, col, f"axis {name} appears twice in one block")
        seen[name] = col
        cur.i = named.end()
        f = expression(cur)
        block.items.append(("x", name, f, text[col - 1:cur.i].strip(), col))
        return
    if letter not in LETTERS or letter == "N":
        m = IDENT.match(text, col - 1)
        what = m.group(0) if m else letter
        raise CutsimError(prog, lineno, col, f"address '{letter}' is not used by the ISG dialect" if len(what) == 1
                          else f"'{what}' is not an ISG address or command (address '{letter}' is not used by "
                          "the ISG dialect)")
    if letter in seen and letter not in "GMH":
        raise CutsimError(prog, lineno, col, f"address {letter} appears twice in one block")
    seen[letter] = col
    cur.skip()
    c = cur.peek()
    if (letter in "GMH" and c and c not in "@[Pp") or (c and (c.isdigit() or c in ".+-\u2212")):
        value, raw, cur.i = parse_number(prog, lineno, text, cur.i, letter, *LIMITS[letter], col=col)
        w = Word(letter, value, raw, col)
        block.words.append(w)
        block.items.append(("w", w))
        if letter == "G" and value in GROUP_WEIGHTS and weight_value(cur, block, col):
            return
        if letter in "GM":
            code_extras(cur, block, col)
        if letter == "G" and value == 4:
            dwell_time(cur)
        return
    if c == "=":
        cur.i += 1
        cur.skip()
        f = expression(cur)
    elif c == "[" and AXIS_COMMAND.match(text, cur.i) and not NOT_AXIS_COMMAND.match(text, cur.i):
        m = re.match(r"\[\s*([A-Za-z_]\w*)", text[cur.i:])
        if m.group(1).upper() == "DIST_CTRL":  # Z[DIST_CTRL OFF NO_MOVE]: run as a command (commands.py)
            j = _closing(text, cur.i)
            if j < 0:
                raise cur.error("']' expected to close the axis command")
            block.commands.append(("DIST_CTRL", f"{letter} {text[cur.i + 1:j]}", col))
            cur.i = j + 1
            return
        raise CutsimError(prog, lineno, col, f"{letter}[{m.group(1)} ...]: an axis-specific command "
                          "is not modelled by the simulator")
    elif c in ("[", "@") or c.isalpha():
        f = primary(cur)
    else:
        raise cur.error(f"malformed number after {letter}")
    raw = text[col:cur.i].strip()
    block.items.append(("x", letter, f, raw, col))


def _closing(text: str, i: int) -> int:
    """Index of the ']' that closes the '[' at ``text[i]`` (-1 without one)."""
    depth = 0
    for j in range(i, len(text)):
        if text[j] == "[":
            depth += 1
        elif text[j] == "]":
            depth -= 1
            if depth == 0:
                return j
    return -1


def dwell_time(cur: Cursor) -> None:
    """``G04 3.0``, ``G04 P1``, ``G04 V.L.TIME``: a dwell time written without an address is read
    and dropped (it does not move the tool); ``G04 X4.5`` and ``G04 S10`` are words G04 consumes."""
    cur.skip()
    c = cur.peek()
    if c and (c.isdigit() or c in ".[" or (c in "Pp" and cur.peek(1).isdigit()) or
              (c in "Vv" and cur.peek(1) == ".")):
        primary(cur)


# axis group weightings written "G131 = 50" or, in the manual's HSC examples, "G131 50"
GROUP_WEIGHTS = frozenset({129, 131, 133, 134, 231, 233, 334, 339})


def weight_value(cur: Cursor, block: IsgBlock, col: int) -> bool:
    """``G131 50``, ``G133 [V.P.W]``: the percentage of a group weighting written after a blank
    (the manual's "N10 G131 50"); kept as the G word's value like ``G131=50``. True if read."""
    j = cur.i
    while j < len(cur.text) and cur.text[j] in " \t":
        j += 1
    if j > cur.i and j < len(cur.text) and (cur.text[j].isdigit() or cur.text[j] in ".["):
        cur.i = j
        block.gvalues[col] = primary(cur)
        return True
    return False


def code_extras(cur: Cursor, block: IsgBlock, col: int) -> None:
    """What may follow a G or M number: an argument list ``G805[1, 2, 3]`` (also ``G80 [0]``) or a
    value ``M200=40``."""
    j = cur.i
    while j < len(cur.text) and cur.text[j] in " \t":
        j += 1
    if j < len(cur.text) and cur.text[j] == "[" and cur.text[cur.i - 1:cur.i].isdigit():
        cur.i = j
    if cur.peek() == "[":
        block.args[col] = arguments(cur, "the argument list")
        return
    j = cur.i
    t = cur.text
    while j < len(t) and t[j] in " \t":
        j += 1
    if j < len(t) and t[j] == "=" and not t.startswith("==", j):
        cur.i = j + 1
        cur.skip()
        block.gvalues[col] = expression(cur)


def spindle_attr(cur: Cursor, block: IsgBlock, col: int) -> None:
    text, prog, lineno = cur.text, cur.prog, cur.line
    m = SPINDLE_ATTR.match(text, cur.i)
    attr = m.group(1)
    if attr.upper() != "OFFSET":
        raise CutsimError(prog, lineno, cur.i + 2, f"unknown spindle attribute S.{attr} (only S.OFFSET is supported)")
    if block.offsets:
        raise CutsimError(prog, lineno, col, "two spindle offsets (S.OFFSET) in one block")
    j = m.end()
    while j < len(text) and text[j] in " \t":
        j += 1
    if j < len(text) and text[j] == "=":
        j += 1
        while j < len(text) and text[j] in " \t":
            j += 1
    value, raw, cur.i = parse_number(prog, lineno, text, j, "S.OFFSET=", COORD_LIMIT, "degrees", col=col)
    block.offsets.append(Word("S.OFFSET", value, raw, col))


def call(cur: Cursor, block: IsgBlock, col: int) -> None:
    """``LL name`` (local subprogram), ``L name`` / ``L path\\name.nc`` (global subprogram file),
    ``L CYCLE [NAME = file @P1 = ..]`` (a cycle: a global subprogram with call parameters)."""
    text, prog, lineno = cur.text, cur.prog, cur.line
    if block.call is not None or block.gcall is not None:
        raise CutsimError(prog, lineno, col, "two subprogram calls in one block")
    if cur.peek() in ("l", "L"):
        cur.i += 1
        cur.skip()
        if cur.at_word("CYCLE"):  # LL CYCLE [NAME = local @P1 = ..]: a local subprogram as a cycle
            cur.i += 5
            cur.skip()
            name, ncol, block.cparams, block.modal = cycle_args(cur)
            block.call = (nfc(name), ncol)
            return
        m = NAME.match(text, cur.i)
        if not m:
            raise cur.error("LL must be followed by the name of a local subprogram")
        block.call = (nfc(m.group(0)), cur.i + 1)
        cur.i = m.end()
        return
    cur.skip()
    if cur.at_word("CYCLE"):
        cur.i += 5
        cur.skip()
        *block.gcall, block.modal = cycle_args(cur)
        block.gcall = tuple(block.gcall)
        return
    m = FILE_NAME.match(text, cur.i)
    if not m:
        raise cur.error("L must be followed by the name of a subprogram file (L name.nc; a local subprogram "
                        "is called with LL name)")
    start = cur.i + 1
    cur.i = m.end()
    params: dict = {}
    cur.skip()
    if cur.peek() == "[":
        cur.i += 1
        params = cycle_params(cur)
    block.gcall = (m.group(0), start, params)


def cycle_params(cur: Cursor) -> dict:
    """``@P1 = expr, @P2 = expr ...]`` after the '[' (commas optional): {"@P1": closure}."""
    params: dict = {}
    while True:
        cur.skip()
        c = cur.peek()
        if c == "]":
            cur.i += 1
            return params
        if c == ",":
            cur.i += 1
            continue
        if c == "@" and cur.peek(1) in ("P", "p"):
            m = re.compile(r"@[Pp]([0-9]+)\s*=").match(cur.text, cur.i)
            if not m:
                raise cur.error("a call parameter is written @P<n> = value")
            cur.i = m.end()
            params["@P" + str(int(m.group(1)))] = expression(cur)
            continue
        if not c:
            raise cur.error("']' expected to close the call's parameters")
        raise cur.error(f"unexpected '{c}' in the call's parameters (@P<n> = value)")


def cycle_args(cur: Cursor) -> tuple:
    """``L CYCLE [NAME = file.nc, @P1 = ...]``: (file name, its column, parameters)."""
    if cur.peek() != "[":
        raise cur.error("L CYCLE needs its parameters in '[ ]': L CYCLE [NAME = file.nc ...]")
    m = re.compile(r"\[\s*NAME\s*=\s*(\"[^\"]*\"|[^\s,\]]+)", re.I).match(cur.text, cur.i)
    if not m:
        raise cur.error("L CYCLE [...] must name the cycle first: L CYCLE [NAME = file.nc ...]")
    cur.i = m.end()
    mm = re.compile(r"[\s,]*(MODAL_MOVE|MODAL_BLOCK|MODAL)\b", re.I).match(cur.text, cur.i)
    modal = "CYCLE"
    if mm:
        modal = "MODAL_MOVE" if mm.group(1).upper() == "MODAL" else mm.group(1).upper()
        cur.i = mm.end()
    return (m.group(1).strip('"'), m.start(1) + 1, cycle_params(cur), modal)


def assignment(cur: Cursor, block: IsgBlock) -> None:
    """``P1 = expr``, ``@P1 = expr``, ``V.P.NAME[i] = expr`` (also V.L., V.S., V.E., V.G.)."""
    col = cur.i + 1
    c = cur.peek()
    if c in "Vv":
        scope, keyf, _ = var_ref(cur)
        target = ("V", scope, keyf)
    else:
        at = c == "@"
        if at:
            cur.i += 1
            if cur.peek() not in ("P", "p"):
                raise cur.error("'@' must be followed by P and a number (@P1)")
        cur.i += 1
        if cur.peek() == "[":
            idx = primary(cur)
            target = ("P", "@P" if at else "P", idx)
        else:
            m = re.compile(r"[0-9]+").match(cur.text, cur.i)
            if not m:
                raise cur.error("P must be followed by the parameter's number")
            key = ("@P" if at else "P") + str(int(m.group(0)))
            cur.i = m.end()
            target = ("P", key, None)
    cur.skip()
    if cur.peek() != "=" or cur.text.startswith("==", cur.i):
        name = cur.text[col - 1:cur.i].strip()
        raise cur.error(f"'=' expected: {name} is assigned with {name} = value (a parameter or variable is "
                        "used in a word as X[...])")
    cur.i += 1
    f = expression(cur)
    block.items.append(("a", target, f, col))


def command(cur: Cursor, block: IsgBlock) -> None:
    m = COMMAND.match(cur.text, cur.i)
    if not m:
        raise cur.error("'#' must be followed by a command name (#MSG, #FLUSH WAIT, #CS ON ...)")
    name = m.group(1).upper()
    rest = cur.text[m.end(1):]
    block.commands.append((name, _strip_comment(rest), cur.i + 1))
    cur.i = len(cur.text)


def _strip_comment(s: str) -> str:
    """The command's text up to a ';' comment that is not inside a string."""
    out, q = [], False
    for ch in s:
        if ch == '"':
            q = not q
        if ch == ";" and not q:
            break
        out.append(ch)
    return "".join(out).strip()


def control(cur: Cursor, block: IsgBlock):
    """A ``$`` control statement. Only a block number may stand before it; ``$IF cond $GOTO ..`` is
    one line (a conditional jump); ``$GOTO`` may also close a block of words."""
    col = cur.i + 1
    m = IDENT.match(cur.text, cur.i + 1)
    kw = m.group(0).upper() if m else ""
    if kw not in CONTROL:
        raise cur.error(f"unknown control statement ${kw} (the simulator knows "
                        f"{', '.join('$' + k for k in sorted(CONTROL))})")
    cur.i = m.end()
    if kw == "GOTO":
        goto(cur, block, col)
        return block
    if block.items or block.call or block.gcall or block.offsets:
        raise CutsimError(cur.prog, cur.line, col, f"${kw} must open its block (only a block number may stand before it)")
    st = Ctrl(cur.line, col, kw, label=block.label)
    if kw in ("IF", "ELSEIF", "WHILE", "SWITCH", "CASE", "ENDDO"):
        cur.skip()
        if cur.i >= len(cur.text) or cur.peek() == ";":
            raise cur.error(f"${kw} needs {'a value' if kw in ('SWITCH', 'CASE') else 'a condition'}")
        st.expr = expression(cur)
    elif kw == "FOR":
        for_head(cur, st)
    cur.skip()
    if kw == "IF" and cur.peek() == "$":
        m2 = IDENT.match(cur.text, cur.i + 1)
        if m2 and m2.group(0).upper() == "GOTO":
            gcol = cur.i + 1
            cur.i = m2.end()
            goto(cur, block, gcol)
            block.cond = st.expr
            return block
    while cur.i < len(cur.text) and cur.peek() == "(":
        cur.i = skip_comment(cur.prog, cur.line, cur.text, cur.i)
        cur.skip()
    if cur.i < len(cur.text) and cur.peek() != ";":
        raise cur.error(f"${kw} must stand alone in its block: move '{cur.text[cur.i:].strip()[:20]}' to the next line")
    return st


def for_head(cur: Cursor, st: Ctrl) -> None:
    """``$FOR P1 = start, end, step`` (also V. variables as the counter)."""
    cur.skip()
    col = cur.i + 1
    c = cur.peek()
    if c in "Vv" and cur.peek(1) == ".":
        scope, keyf, _ = var_ref(cur)
        st.var = ("V", scope, keyf, col)
    elif c in ("P", "p", "@"):
        f = param(cur)  # only to move past it; the key is read from the text
        key = cur.text[col - 1:cur.i].upper().replace(" ", "")
        if "[" in key:
            raise CutsimError(cur.prog, cur.line, col, "$FOR counts with a plain parameter (P1) or a variable")
        st.var = ("P", key, f, col)
    else:
        raise cur.error("$FOR needs a counter: $FOR P1 = start, end, step")
    cur.skip()
    if cur.peek() != "=":
        raise cur.error("'=' expected: $FOR P1 = start, end, step")
    cur.i += 1
    parts = [expression(cur)]
    for _ in range(2):
        cur.skip()
        if cur.peek() != ",":
            raise cur.error("$FOR needs start, end and step separated by ',': $FOR P1 = 0, 10, 1")
        cur.i += 1
        parts.append(expression(cur))
    st.exprs = tuple(parts)


def goto(cur: Cursor, block: IsgBlock, col: int) -> None:
    cur.skip()
    c = cur.peek()
    if c == "[":
        m = re.compile(r"\[\s*([A-Za-z_][A-Za-z0-9_]*)\s*\]").match(cur.text, cur.i)
        if not m:
            raise cur.error("$GOTO [NAME] names a label in '[ ]'")
        block.goto = ("S", f"[{m.group(1).upper()}]", col)
        cur.i = m.end()
    elif c in ("N", "n"):
        cur.i += 1
        cur.skip()
        f = primary(cur)
        block.goto = ("N", f, col)
    elif c in "Vv" and cur.peek(1) == ".":
        f = primary(cur)
        block.goto = ("V", f, col)
    else:
        raise cur.error("$GOTO needs its target: $GOTO N100 or $GOTO [NAME]")
    cur.skip()
    while cur.peek() == "(":
        cur.i = skip_comment(cur.prog, cur.line, cur.text, cur.i)
        cur.skip()
    if cur.i < len(cur.text) and cur.peek() != ";":
        raise cur.error("the jump $GOTO is the last thing in its block")
