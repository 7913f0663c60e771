"""ISG program bodies run with their control flow ($IF/$WHILE/$FOR/$DO/$SWITCH, $GOTO) and the
count of executed blocks checked before running where it is known (bodies without control flow)."""
from __future__ import annotations

from .lang import truth
from .program import expand_macros
from .reader import Ctrl, IsgBlock, Section, scan
from ..canon import Src
from ..errors import CutsimError
from ..core.lexer import fmt_count

class _EveryName:
    """Contains every name (macros after a skipped external subprogram)."""

    def __contains__(self, name) -> bool:
        return True


_EVERY_NAME = _EveryName()


class Flow:
    """The control flow of Isg (a part of it): bodies, loops and jumps. State: ``last_block`` (the
    last block run, for the missing-M30 warning) and ``ended`` (M30 reached)."""

    last_block: object
    ended: bool

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.ended = False
        self.last_block = None

    def check_count(self, main: Section, local: dict) -> None:
        """Without control flow, jumps or global calls, the blocks a program executes are known before
        it runs: refuse one whose count exceeds ``cfg.max_blocks`` at the main program's heaviest call."""
        if main.flow or any(s.flow for s in local.values()):
            return
        counts = static_counts(main, local)
        if counts is None:
            return
        limit = self.cfg.max_blocks
        total, _ = counts[None]
        if total <= limit:
            return
        heaviest = None
        for b in main.blocks:
            if b.call is not None and (heaviest is None or counts[b.call[0]][0] > counts[heaviest.call[0]][0]):
                heaviest = b
            if _ends_program(b) or (b.call is not None and counts[b.call[0]][1]):
                break
        where = (1, 1) if heaviest is None else (heaviest.line, heaviest.call[1])
        what = "" if heaviest is None else (f"LL {heaviest.call[0]} executes {fmt_count(counts[heaviest.call[0]][0])} "
                                             "blocks (its subprogram calls counted): ")
        raise self.error(*where, f"{what}the program would execute {fmt_count(total)} blocks, more than the limit of "
                         f"{limit:,} set by [simulation] max_blocks")

    def block_limit(self, b) -> CutsimError:
        return self.error(b.line, 1, f"more than {self.cfg.max_blocks:,} blocks executed (the limit is [simulation] "
                          "max_blocks): a loop or jump that does not end?")

    def section(self, sec: Section) -> None:
        """Run a program body with its control flow; returns at M29/M17, sets ``self.ended`` at M30."""
        blocks = sec.blocks
        pc, n = 0, len(blocks)
        fr = self.level
        while pc < n:
            b = blocks[pc]
            self.count_block(b)
            if isinstance(b, Ctrl):
                pc = self.control(sec, b, pc)
                continue
            self.last_block = b
            if b.decls:
                self.declare(b)
                pc += 1
                continue
            if b.deferred:
                b = self.expand(b)
                if b is None:
                    pc += 1
                    continue
            try:
                ret = self.block(b, fr)
            except CutsimError as e:
                if fr.stack and e.line == b.line and e.program == self.name and "(in subprogram" not in e.message:
                    raise CutsimError(e.program, e.line, e.col, f"{e.message} (in subprogram '{fr.stack[-1]}' "
                                      f"called from line {fr.calls[-1][1]})") from None
                raise
            if self.ended or ret:
                return
            if fr.modal is not None and _moves(b):
                self.modal_cycle(b, fr)
                if self.ended:
                    return
            if b.goto is not None and (b.cond is None or truth(b.cond(self))):
                pc = self.jump(sec, b)
                continue
            pc += 1

    def expand(self, b: IsgBlock):
        """A line whose macro was not defined when it was read: expanded and read now."""
        used: list = []
        # after a declared external subprogram was skipped, a macro no file defines is taken to be
        # one it defines (a WAAM cell's start program defines "Encender_arco"): every name passes
        external = _EVERY_NAME if self.external_skipped else self.cfg.external_subprograms
        nb = scan(self.name, b.line, expand_macros(self.name, b.line, b.deferred, self.macros, external, used))
        for name in used:
            src = Src(self.name, b.line, 1, b.label, self.level.calls)
            if name.upper() in self.cfg.external_subprograms:
                why = "is declared external in the setup ([machine] external_subprograms): the machine defines it"
            else:
                why = (f"is defined by no file: taken to be defined by the external {self.external_skipped} "
                       "(declared in [machine] external_subprograms and not simulated)")
            self.warn_once(("macro", name.upper()), src, f"macro \"{name}\" {why}; its effect is not simulated "
                           "(it is taken to move nothing)")
        if isinstance(nb, Ctrl):
            raise self.error(b.line, nb.col, f"${nb.kw} from a macro is not supported by the simulator")
        return nb

    def jump(self, sec: Section, b: IsgBlock) -> int:
        kind, target, col = b.goto
        if kind == "S":
            label = target
        else:
            v = target(self)
            if kind == "V" and isinstance(v, str):
                label = f"[{v.strip().upper()}]"
            elif isinstance(v, str) or v != int(v) or v < 0:
                raise self.error(b.line, col, f"$GOTO N{v}: a block number is a whole number")
            else:
                label = f"N{int(v)}"
        if label in sec.labels:
            return sec.labels[label]
        if label + "?" in sec.labels and label.startswith("N"):
            return sec.labels[label + "?"]
        raise self.error(b.line, col, f"$GOTO {label}: no label {label}{':' if label.startswith('N') else ''} in this "
                         "program level (a jump stays in its main program or subprogram)")

    def control(self, sec: Section, st: Ctrl, pc: int) -> int:
        """Run one control statement; the index of the next statement."""
        kw, m, blocks = st.kw, st.match, sec.blocks
        if kw == "IF":
            if truth(st.expr(self)):
                return pc + 1
            for k in m["branches"]:
                br = blocks[k]
                if br.kw == "ELSE" or truth(br.expr(self)):
                    return k + 1
            return m["end"] + 1
        if kw in ("ELSEIF", "ELSE"):
            return m["end"] + 1  # the branch before it ran: leave the $IF
        if kw in ("ENDIF", "DO", "CASE", "DEFAULT", "ENDSWITCH"):
            return pc + 1
        if kw == "WHILE":
            return pc + 1 if truth(st.expr(self)) else m["end"] + 1
        if kw == "ENDWHILE":
            return m["open"]
        if kw == "ENDDO":
            return m["open"] + 1 if truth(st.expr(self)) else pc + 1
        if kw == "FOR":
            start = self.number(st.exprs[0](self), st, "$FOR start")
            self.set_counter(st, start)
            return pc + 1 if self.for_ok(st, start) else m["end"] + 1
        if kw == "ENDFOR":
            head = blocks[m["open"]]
            v = self.number(self.get_counter(head), head, "$FOR counter") + self.for_step(head)
            self.set_counter(head, v)
            return m["open"] + 1 if self.for_ok(head, v) else pc + 1
        if kw == "SWITCH":
            v = st.expr(self)
            default = None
            for k in m["branches"]:
                br = blocks[k]
                if br.kw == "DEFAULT":
                    default = k
                elif br.expr(self) == v:
                    return k + 1
            return (default + 1) if default is not None else m["end"] + 1
        if kw == "BREAK":
            return m["end"] + 1
        if kw == "CONTINUE":
            return m["end"]  # the loop's end statement tests and steps
        raise AssertionError(kw)  # pragma: no cover

    def number(self, v, st, what: str) -> float:
        if isinstance(v, str):
            raise self.error(st.line, st.col, f"{what}: \"{v}\" is not a number")
        return v

    def for_step(self, st: Ctrl) -> float:
        step = self.number(st.exprs[2](self), st, "$FOR step")
        if step == 0:
            raise self.error(st.line, st.col, "$FOR step 0 never ends the loop")
        return step

    def for_ok(self, st: Ctrl, v: float) -> bool:
        end = self.number(st.exprs[1](self), st, "$FOR end")
        return v <= end if self.for_step(st) > 0 else v >= end

    def set_counter(self, st: Ctrl, v: float) -> None:
        if st.var[0] == "P":
            self.params[st.var[1]] = v
        else:
            self.write_var(st.var[1], st.var[2](self), v, st.line, st.var[3])

    def get_counter(self, st: Ctrl):
        if st.var[0] == "P":
            return self.read_param(st.var[1], st.line, st.var[3])
        return self.read_var(st.var[1], st.var[2](self), st.line, st.var[3])


_AXIS_LETTERS = frozenset("XYZABCUVW")
_NO_MOTION_G = frozenset({4.0, 92.0, 98.0, 99.0, 130.0, 132.0, 230.0, 333.0})  # G codes whose axis words are not a motion


def _moves(b: IsgBlock) -> bool:
    """The block holds motion commands (axis words) - what calls a MODAL_MOVE cycle again."""
    letters = {w.letter for w in b.words} | {it[1] for it in b.items if it[0] == "x"}
    if not letters & _AXIS_LETTERS:
        return False
    return not any(w.letter == "G" and w.value in _NO_MOTION_G for w in b.words)


def _ends_program(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (2, 30) for w in b.words)


def _ends_sub(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (17, 29) for w in b.words)


def static_counts(main: Section, local: dict[str, Section]) -> dict | None:
    """Blocks each body executes, its calls included, without running it (only for bodies without
    control flow): name (None for the main program) -> (count, whether it ends the program). None
    when a call names an unknown subprogram or is recursive (errors when they run)."""
    counts: dict = {}
    bodies = {None: main, **local}
    stack = [[None, 0, 0]]
    open_names = {None}
    while stack:
        frame = stack[-1]
        name, k, total = frame
        blocks = bodies[name].blocks
        pushed = False
        ended = False
        while k < len(blocks):
            b = blocks[k]
            callee = b.call[0] if b.call is not None else None
            if callee is not None:
                if callee not in local or callee in open_names:
                    return None
                if callee not in counts:
                    frame[1], frame[2] = k, total
                    stack.append([callee, 0, 0])
                    open_names.add(callee)
                    pushed = True
                    break
            total += 1 + (counts[callee][0] if callee is not None else 0)
            k += 1
            if _ends_program(b) or (callee is not None and counts[callee][1]):
                ended = True
                break
            if name is not None and _ends_sub(b):
                break
        if pushed:
            continue
        counts[name] = (total, ended)
        stack.pop()
        open_names.discard(name)
    return counts
