"""ISG program text -> sections: #VAR declarations, macros ("name" = "text"), headers (%name,
%L name), the parse of a whole file and the matching of its control structures."""
from __future__ import annotations

import re

from .lang import Cursor, IDENT, expression
from .reader import NAME, BLOCK_LINES, Ctrl, HEADER, IsgBlock, MACRO_DEF, MACRO_USE, MAX_MACRO_DEPTH, Section, VarDecl, nfc, scan
from ..errors import CutsimError
from ..core.lexer import check_length, iter_lines

# -- #VAR declarations -------------------------------------------------------------------------------
DECL = re.compile(r"\s*(?:N[0-9]+\s+)?[Vv]\.([A-Za-z])\.([A-Za-z_][A-Za-z0-9_]*)((?:\s*\[\s*[0-9]+\s*\])*)")


def declaration(prog: str, lineno: int, text: str) -> VarDecl | None:
    """One line between #VAR and #ENDVAR: ``V.P.NAME``, ``V.L.ARR[3][2]``, ``= value`` or ``= [a, b]``."""
    s = text.strip()
    if not s or s.startswith(";") or s.startswith("("):
        return None
    m = DECL.match(text)
    if not m:
        col = len(text) - len(text.lstrip()) + 1
        raise CutsimError(prog, lineno, col, "a #VAR block declares variables V.P.NAME, V.L.NAME or V.S.NAME "
                          "(with [n] for arrays and '= value')")
    scope = m.group(1).upper()
    col = m.start(0) + len(m.group(0)) - len(m.group(0).lstrip()) + 1
    if scope not in "PLS":
        raise CutsimError(prog, lineno, col, f"V.{scope}. variables are not declared in the program: only V.P., "
                          "V.L. and V.S. (V.E. and V.G. come from the controller; give them in the setup's [variables])")
    dims = tuple(int(d) for d in re.findall(r"[0-9]+", m.group(3)))
    for d in dims:
        if not 1 <= d <= 10_000:
            raise CutsimError(prog, lineno, col, f"array size {d} must be 1 to 10,000")
    cur = Cursor(prog, lineno, text, m.end())
    cur.skip()
    if cur.peek() == ":":  # a type (: INT, : REAL ...) is accepted and not checked
        tm = IDENT.match(text, cur.i + 1) or IDENT.match(text, cur.i + 2)
        cur.i = tm.end() if tm else cur.i + 1
        cur.skip()
    init: list = []
    if cur.peek() == "=":
        cur.i += 1
        cur.skip()
        if cur.peek() == "[" and dims:
            cur.i += 1
            while True:
                cur.skip()
                if cur.peek() == "]":
                    cur.i += 1
                    break
                if cur.peek() == ",":
                    cur.i += 1
                    continue
                if cur.peek() == "[":
                    cur.i += 1
                    continue
                init.append(expression(cur))
        else:
            init.append(expression(cur))
    cur.skip()
    while cur.peek() == "]" or cur.peek() == ",":
        cur.i += 1
        cur.skip()
    if cur.i < len(text) and cur.peek() not in ";(":
        raise cur.error("unexpected text after the declaration")
    return VarDecl(lineno, col, scope, f"V.{scope}.{m.group(2).upper()}", dims, init)


# -- macros (string substitution) ---------------------------------------------------------------------
class MacroMissing(CutsimError):
    """A macro no file has defined (yet)."""


def expand_macros(prog: str, lineno: int, text: str, macros: dict, external: frozenset = frozenset(),
                  used: list | None = None) -> str:
    """Replace every ``"NAME"`` outside a #MSG text by the macro's content (recursively). A macro no
    file defined whose upper-cased name is in ``external`` (``[machine] external_subprograms``: the
    machine's start program defines it) is replaced by nothing and its name appended to ``used``."""
    if '"' not in text:
        return text
    cmd = re.search(r"(?:^|[\s:\]])#\s*[A-Za-z]", text)
    if cmd:  # a # command's text (#MSG ["..."]) holds strings, not macros
        head = text[:cmd.start()]
        return expand_macros(prog, lineno, head, macros, external, used) + text[cmd.start():] if '"' in head else text
    for _ in range(MAX_MACRO_DEPTH):
        out, i, changed = [], 0, False
        code = text.split(";", 1)[0] if '"' not in text.split(";", 1)[0][-1:] else text
        for m in MACRO_USE.finditer(code):
            name = m.group(1)
            before = code[:m.start()].rstrip()
            if name not in macros and before[-1:] in set("=!<>+-*/,[(&|"):
                continue  # a string in an expression (V.E.X = "text", V.E.M == "A"), not a macro
            if name not in macros and name.upper() in external and used is not None:
                used.append(name)
            elif name not in macros:
                raise MacroMissing(prog, lineno, m.start() + 1, f"macro \"{name}\" is not defined: define it with "
                                  f"\"{name}\" = \"...\" before it is used (a macro from another file is not "
                                  "known to the simulator; one the machine's own start program defines may be "
                                  f"declared: [machine] external_subprograms = [\"{name}\"])")
            out.append(text[i:m.start()])
            out.append(macros.get(name, ""))
            i = m.end()
            changed = True
        if not changed:
            return text
        out.append(text[i:])
        text = "".join(out)
    raise CutsimError(prog, lineno, 1, f"macros nested more than {MAX_MACRO_DEPTH} deep")


# -- a whole file -------------------------------------------------------------------------------------
def header(name: str, lineno: int, indent: int, text: str) -> Section:
    m = HEADER.match(text)
    if not m:
        raise CutsimError(name, lineno, indent + 1, "'%' must be followed by a program name ('%name' or '%L name')")
    if m.group("local"):
        nm = m.group("lname")
        col = indent + m.start("lname") + 1
        if not NAME.fullmatch(nm):
            bad = next(c for c in nm if not NAME.match(c))
            raise CutsimError(name, lineno, col + nm.index(bad),
                              f"subprogram name '{nm}' may hold only letters, digits and '_'")
        sec = Section("local", nfc(nm), lineno, col)
    else:
        sec = Section("main", nfc(m.group("mname")), lineno, indent + m.start("mname") + 1)
    tail = text[m.end():].lstrip()
    if tail.startswith("("):
        j = tail.find(")")
        tail = "" if j < 0 else tail[j + 1:].lstrip()
    if tail and not tail.startswith(";") and sec.kind == "main":
        # a title written without parentheses (a bioprinter's "% 1x10 dots right 24 well plate"):
        # the first word names the program, the rest of the line is its title (a warning says so)
        sec.title = tail.split(";", 1)[0].rstrip()
    elif tail and not tail.startswith(";"):
        raise CutsimError(name, lineno, indent + len(text) - len(tail) + 1,
                          "unexpected text after the program name (a title goes in parentheses, a comment after ';')")
    return sec


def _directive(stripped: str) -> str:
    m = re.match(r"(?:N[0-9]+\s*)?#\s*([A-Za-z]+)(?:[ \t]+([A-Za-z]+))?", stripped)
    if not m:
        return ""
    return (m.group(1) + (" " + m.group(2) if m.group(2) else "")).upper()


def _declare_line(name: str, lineno: int, line: str, var_line: int, sec: Section, var_block) -> None:
    """One line inside #VAR .. #ENDVAR: its declaration joins the level's (the first of each name,
    known from the level's start) and, for a #VAR after the level's first block, that block's."""
    try:
        decl = declaration(name, lineno, line)
    except CutsimError as e:
        raise CutsimError(e.program, e.line, e.col, f"{e.message} (#VAR at line {var_line} is not closed "
                          "by #ENDVAR before this line?)") from None
    if decl is None:
        return
    if all(d.name != decl.name for d in sec.decls):
        sec.decls.append(decl)
    if var_block is not None:
        var_block.decls.append(decl)


def parse(name: str, text: str, max_blocks: int | None = None, macros: dict | None = None, fast=None):
    """The file -> (main program, local subprograms by name). ``macros``: the program-global macro
    table (``"NAME" = "text"``), shared by every file of a run; a line using a macro no file has
    defined yet is expanded when it runs (a subprogram called before may define it). ``fast``: a
    plain-line reader (read_plain) tried before ``scan``: the same IsgBlock or None."""
    if max_blocks is not None:
        check_length(name, text, max_blocks, BLOCK_LINES)
    loose = Section("main", "", 1, 1)
    sections: list[Section] = []
    macros = {} if macros is None else macros
    mode, mode_line = "", 0
    var_block: IsgBlock | None = None
    pending, pending_line = None, 0
    for lineno, line in iter_lines(text):
        code = line.split(";", 1)[0].rstrip()
        if mode != "comment" and code.endswith("\\") and not line.lstrip().startswith("%"):
            # a block continued on the next line ('\\' at the end): joined, reported at its first line
            if pending is None:
                pending, pending_line = "", lineno
            pending += code[:-1] + " "
            continue
        if pending is not None:
            if not line.strip() or line.lstrip().startswith(";"):
                continue  # blank and comment lines inside a continued block
            line, lineno = pending + line, pending_line
            pending = None
        stripped = line.lstrip()
        d = _directive(stripped) if "#" in stripped[:12] else ""
        if mode == "comment":
            if d == "COMMENT END":
                mode = ""
            continue
        sec = sections[-1] if sections else loose
        if mode == "var":
            if d == "ENDVAR":
                mode = ""
                if var_block is not None and var_block.decls:
                    sec.blocks.append(var_block)  # declared again where it stands (real programs per layer)
            else:
                _declare_line(name, lineno, line, mode_line, sec, var_block)
            continue
        if d == "COMMENT BEGIN":
            mode, mode_line = "comment", lineno
            continue
        if d == "VAR":
            mode, mode_line = "var", lineno
            var_block = IsgBlock(line=lineno, col=1) if sec.blocks and not sec.ended else None
            continue
        if stripped.startswith("%"):
            sections.append(header(name, lineno, len(line) - len(stripped), stripped))
            continue
        md = MACRO_DEF.match(line)
        if md:
            macros[md.group(1)] = md.group(2).replace('\\"', '"')
            continue
        try:
            b = fast(name, lineno, line) if fast is not None else None
            if b is None:
                b = scan(name, lineno, expand_macros(name, lineno, line, macros))
        except MacroMissing:
            b = IsgBlock(line=lineno, col=1, deferred=line)
        if b is None:
            continue
        if sec.ended:
            raise CutsimError(name, lineno, 1, f"block after the end (M29) of subprogram '{sec.name}' "
                              "belongs to no program: start a program with '%name' or '%L name'")
        sec.blocks.append(b)
        if sec.kind == "local" and isinstance(b, IsgBlock) and _ends_sub(b):
            sec.ended = True
    if mode:
        what = "#COMMENT BEGIN" if mode == "comment" else "#VAR"
        raise CutsimError(name, mode_line, 1, f"{what} is not closed by {'#COMMENT END' if mode == 'comment' else '#ENDVAR'}")
    return assemble(name, loose, sections)


def assemble(name: str, loose: Section, sections: list[Section]):
    mains = [s for s in sections if s.kind == "main"]
    if mains and (loose.blocks or loose.decls):
        first = loose.blocks[0] if loose.blocks else loose.decls[0]
        raise CutsimError(name, first.line, 1, "block before the first program header ('%name' or '%L name')")
    if mains:
        main = mains[0]
    elif loose.blocks or loose.decls:
        main = loose
    else:
        raise CutsimError(name, 1, 1, "no main program: the file needs a '%name' program ended by M30")
    local: dict[str, Section] = {}
    for i, s in enumerate(sections):
        if s.kind != "local":
            continue
        if s.name in local:
            raise CutsimError(name, s.line, s.col, f"local subprogram '{s.name}' is defined twice (first at line "
                              f"{local[s.name].line})")
        if not s.ended:
            nxt = sections[i + 1].line if i + 1 < len(sections) else None
            where = f"before line {nxt}" if nxt else "before the end of the file"
            raise CutsimError(name, s.line, s.col, f"local subprogram '{s.name}' is not ended: M29 (or M17) missing {where}")
        local[s.name] = s
    for sec in [main, *local.values()]:
        match_control(name, sec)
    main.others = mains[1:]
    return main, local


def _ends_sub(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (17, 29) for w in b.words)


OPENERS = {"IF": "ENDIF", "WHILE": "ENDWHILE", "FOR": "ENDFOR", "DO": "ENDDO", "SWITCH": "ENDSWITCH"}
CLOSERS = {v: k for k, v in OPENERS.items()}
LOOPS = ("WHILE", "FOR", "DO")


def match_control(name: str, sec: Section) -> None:
    """Pair every control statement with its structure: ``st.match`` holds the indices the run
    loop jumps to (``end``, ``next`` branch, ``cases``, the ``loop`` a $BREAK/$CONTINUE leaves)."""
    stack: list[tuple[Ctrl, int]] = []
    for i, st in enumerate(sec.blocks):
        if isinstance(st, IsgBlock):
            if st.target:
                sec.labels.setdefault(st.target, i)
            elif st.label and st.label not in sec.labels:
                sec.labels.setdefault(st.label + "?", i)  # a plain block number: a jump target too
            continue
        kw = st.kw
        if st.label:
            sec.labels.setdefault(st.label + "?", i)
        if kw in OPENERS:
            st.match = {"branches": []}
            stack.append((st, i))
        elif kw in ("ELSEIF", "ELSE"):
            top = stack[-1][0] if stack else None
            if top is None or top.kw != "IF" or top.match.get("else") is not None:
                raise CutsimError(name, st.line, st.col, f"${kw} does not match the current control block "
                                  f"({'$' + top.kw + ' at line ' + str(top.line) if top else 'no $IF is open'})")
            top.match["branches"].append(i)
            if kw == "ELSE":
                top.match["else"] = i
            st.match = {"if": stack[-1][1]}
        elif kw in ("CASE", "DEFAULT"):
            top = stack[-1][0] if stack else None
            if top is None or top.kw != "SWITCH":
                raise CutsimError(name, st.line, st.col, f"${kw} outside a $SWITCH")
            top.match["branches"].append(i)
        elif kw in CLOSERS:
            opener = CLOSERS[kw]
            if not stack or stack[-1][0].kw != opener:
                what = f"the open ${stack[-1][0].kw} at line {stack[-1][0].line}" if stack else f"no ${opener} is open"
                raise CutsimError(name, st.line, st.col, f"unexpected ${kw}: it does not match the current control "
                                  f"block ({what})")
            top, j = stack.pop()
            top.match["end"] = i
            st.match = {"open": j}
            for k in top.match["branches"]:
                sec.blocks[k].match["end"] = i
        elif kw in ("BREAK", "CONTINUE"):
            target = None
            for top, j in reversed(stack):
                if top.kw in LOOPS or (kw == "BREAK" and top.kw == "SWITCH"):
                    target = j
                    break
            if target is None:
                raise CutsimError(name, st.line, st.col, f"${kw} outside a loop" + (" or $SWITCH" if kw == "BREAK" else ""))
            st.match = {"loop": target}
    if stack:
        top, _ = stack[-1]
        raise CutsimError(name, top.line, top.col, f"${top.kw} is not closed: ${OPENERS[top.kw]} missing")
    # the open statement of each structure learns its end (already), the closers their opener
    for st in sec.blocks:
        if isinstance(st, Ctrl) and st.kw in ("BREAK", "CONTINUE"):
            loop = sec.blocks[st.match["loop"]]
            st.match["end"] = loop.match["end"]
