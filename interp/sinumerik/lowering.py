"""Structured control flow (IF/ELSE/ENDIF, WHILE, FOR, LOOP, REPEAT/UNTIL) lowered to conditional
jumps to line indices (``Branch``), so that the executor only ever follows jumps.
"""
from __future__ import annotations

from ..errors import CutsimError
from .syntax import Assign, BinOp, Branch, Num, Structured, Unit, Var


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
