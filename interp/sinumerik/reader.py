"""The Sinumerik block reader (after LinuxCNC's rs274ngc phases): ``strip_comment`` and ``check_text``
(the characters and the length), ``read_label`` (``NAME:`` and the N word), then one ``statement``
after the other into the block's ``Line``; ``split_units`` groups the lines into the main program
and its subprograms and lowers their control flow (lowering.py).
"""
from __future__ import annotations

import re

from ..errors import CutsimError
from ..core.lexer import split_lines
from .expressions import ExprScanner
from .lowering import lower
from .syntax import (AC_IC_RE, ADDRESSES, Arg, Assign, Call, Case, Command, Decl, Def, Expr, EXPR_ADDRESSES, EXT_RE,
    foreign_char, Goto, HEADER_RE, IGNORED_WORDS, ISO_ADDRESSES, JUMPS, LABEL_RE, LANG_COMMANDS, Line,
    MACHINE_COMMANDS, MAX_BLOCK_CHARS, Num, Param, Proc, R_ASSIGN_RE, R_LIMIT, Repeat, Ret, SETTING_WORDS, Stmt,
    Structured, SubCall, SYNC_WORDS, TYPES, Unit, Var, Word)


class _Scanner(ExprScanner):
    """The statements of one block (on the expression reader)."""

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
        ext = EXT_RE.match(text, self.i) if up in "MSLT" else None
        if ext:
            return self.extended(col, ext, ln)
        if up == "H" and self.i + 1 < len(text) and text[self.i + 1] in "0123456789+-.=":
            return self.h_word(col, ln)
        # an address with its number; R2.5, Q3 of an ISO drilling cycle (G81 R2 Z-10) too: R<n>=.. is
        # an R parameter (above), R<n> alone has no other meaning (refused outside a cycle)
        numbered = self.i + 1 < len(text) and text[self.i + 1] in "0123456789+-.\u2212"
        if numbered and (up in ADDRESSES or up in ISO_ADDRESSES):
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
        if name == "SPOS" and nxt == "=":  # SPOS=90, SPOS=IC(10): the angle (lathe.position_spindle)
            self.i += 1
            ln.stmts.append(self.address_value(col, name))
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
        """M1=3, S1=1000, T1=5 (an address with its extension) and L140(2) (an L call with parameters)."""
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
    ``/`` or ``/0`` .. ``/9`` (its skip level) at the start is read like any block (the skip
    levels are off in the simulation)."""
    ln = Line(lineno, raw)
    text = strip_comment(raw)
    stripped = text.lstrip()
    if stripped.startswith("%") or stripped.startswith("$PATH") or not stripped.strip(FILE_END_BYTES + " \t"):
        return ln  # program header (%_N_NAME_MPF, ;$PATH=...), a blank line or the file's end bytes
    check_text(prog, lineno, text.rstrip(FILE_END_BYTES + " \t"))
    if stripped.startswith("/"):
        k = text.index("/")
        level = 2 if text[k + 1:k + 2].isdigit() and text[k + 1].isascii() else 1  # /1 N70: skip level 1
        text = text[:k] + " " * level + text[k + level:]
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
