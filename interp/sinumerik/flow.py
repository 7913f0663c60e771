"""Control flow at run time: jumps to labels, CASE, REPEAT sections, the loop guard and the block
limit.
"""
from __future__ import annotations

import re

from ..errors import CutsimError
from .syntax import Branch, Case, Frame, Goto, Num, PASS_LIMIT, Repeat, Unit
from .tables import MAX_STACK
from .values import to_text


class Flow:
    """Control flow at run time: jumps to labels, CASE, REPEAT sections, the loop guard and the block
    limit.

    A part of ``Sinumerik`` (interpreter.py): its methods work on the state declared in
    ``Sinumerik.__init__``."""

    def check_loop(self, stack: list[Frame], line: int, st: Goto) -> None:
        """A backward jump that comes back with the same control state (every frame's place and
        counters, every R parameter and variable) repeats forever: nothing else steers the
        program. States are remembered by hash; a hash seen before keeps its full state, and only
        the full state seen again is the proof (no false alarm from a hash collision)."""
        key = (tuple((id(f.unit), f.pc, f.count, f.stop, f.restart, f.ret, f.kind) for f in stack),
               tuple(sorted(self.params.items())), tuple(sorted((k, repr(v)) for k, v in self.vars.items())),
               tuple(sorted((k, repr(v)) for k, v in self.sysvars.items())))
        h = hash(key)
        if h not in self.loop_hashes:
            self.loop_hashes.add(h)
            return
        if self.loop_states.get(h) == key:
            what = f"{st.kind} {st.label}" if isinstance(st, Goto) else st.kind
            raise self.error(line, st.col, f"the program does not end: {what} comes back with every R parameter "
                             "and variable unchanged, so it loops forever")
        self.loop_states[h] = key

    def block_limit(self, b) -> CutsimError:
        return self.error(b.line, 1, f"the program does not end: more than {self.cfg.max_blocks:,} blocks executed "
                          "(a jump loop; the limit is [simulation] max_blocks)")

    def nearest(self, unit: Unit, label: str, cur: int, forward: bool) -> int | None:
        """The nearest line holding ``label`` after (forward) or at/before ``cur``."""
        lines = unit.all_labels.get(label, ())
        if forward:
            return next((i for i in lines if i > cur), None)
        return next((i for i in reversed(lines) if i <= cur), None)

    def find_label(self, unit: Unit, label: str, line: int, col: int, kind: str = "GOTO",
                   cur: int = -1) -> int | None:
        """The jump destination the Siemens way: GOTOF searches forwards, GOTOB backwards, GOTO and
        GOTOC forwards then backwards (a label written twice: the nearest in that direction).
        GOTOC gives None when the label is missing; the others are errors."""
        if label not in unit.all_labels:
            if kind == "GOTOC":
                return None
            raise self.error(line, col, f"label {label} does not exist in {'the program' if unit is self.main else unit.name}")
        fwd = self.nearest(unit, label, cur, forward=True)
        back = self.nearest(unit, label, cur, forward=False)
        idx = fwd if kind == "GOTOF" else back if kind == "GOTOB" else (fwd if fwd is not None else back)
        if idx is None and kind == "GOTOC":
            return None
        if idx is None:
            where = "before" if kind == "GOTOF" else "after"
            raise self.error(line, col, f"{kind} jumps {'forward' if kind == 'GOTOF' else 'back'}, but {label} "
                             f"comes only {where} this block")
        return idx

    def jump(self, st, line: int, stack: list[Frame]) -> bool:
        """GOTO/Branch/CASE (True when taken) or REPEAT (always taken)."""
        fr = stack[-1]
        cur = fr.pc - 1
        if isinstance(st, Branch):
            if st.cond is not None and bool(self.num(self.ev(st.cond, line, st.col), line, st.col)) != st.when:
                return False
            fr.pc = st.target
            if st.target <= cur:
                self.check_loop(stack, line, st)
            return True
        if isinstance(st, Case):
            st = self.case_jump(st, line)
            if st is None:
                return False
        if isinstance(st, Goto):
            if st.cond is not None and not self.num(self.ev(st.cond, line, st.col), line, st.col):
                return False
            idx = self.find_label(fr.unit, self.goto_label(st, line), line, st.col, st.kind, cur)
            if idx is None:  # GOTOC: no alarm when the label is missing
                return False
            fr.pc = idx
            if idx <= cur:
                self.check_loop(stack, line, st)
            return True
        return self.repeat(st, line, stack)

    def goto_label(self, st: Goto, line: int) -> str:
        """The destination: the written label, or the computed one (GOTOF "STEP_" << NR)."""
        if st.target is None:
            return st.label
        v = self.ev(st.target, line, st.col)
        if not isinstance(v, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*|N?[0-9]+", v.strip()):
            raise self.error(line, st.col, f"{st.kind}: the computed destination {to_text(v)!r} is no label")
        v = v.strip().upper()
        return f"N{int(v.lstrip('N'))}" if re.fullmatch(r"N?[0-9]+", v) else v

    def case_jump(self, st: Case, line: int) -> Goto | None:
        """The jump of the first CASE value equal to the expression, else DEFAULT (None: go on)."""
        v = self.ev(st.value, line, st.col)
        for const, goto in st.branches:
            c = self.ev(const, line, st.col)
            if isinstance(c, str) != isinstance(v, str):
                raise self.error(line, st.col, "CASE compares a string with a number")
            if c == v:
                return goto
        return st.default

    def repeat(self, st: Repeat, line: int, stack: list[Frame]) -> bool:
        fr = stack[-1]
        cur = fr.pc - 1
        a = self.find_label(fr.unit, st.start, line, st.col, "GOTOB", cur)
        n = self.num(self.ev(st.count, line, st.col), line, st.col)
        if n != int(n) or not 1 <= n <= PASS_LIMIT:
            raise self.error(line, st.col, f"REPEAT P must be a whole number from 1 to {PASS_LIMIT} (got {n:.10g})")
        if st.end is None:
            if a >= cur:
                raise self.error(line, st.col, f"REPEAT {st.start}: the label must come before this block")
            stop = cur
        else:
            b = self.nearest(fr.unit, st.end, a, forward=True)
            if b is None:
                b = self.find_label(fr.unit, st.end, line, st.col, "GOTO", cur)
            if b < a:
                raise self.error(line, st.col, f"REPEAT {st.start} {st.end}: the end label comes before the start")
            stop = b + 1
        if len(stack) > MAX_STACK or a <= cur < stop:
            raise self.error(line, st.col, f"REPEAT sections and subprograms nested deeper than {MAX_STACK} "
                             "(a REPEAT inside the section it repeats?)")
        self.repeat_estimate(stack, fr.unit, a, stop, int(n), line, st)
        stack.append(Frame(fr.unit, pc=a, stop=stop, restart=a, ret=cur + 1, count=int(n), kind="repeat",
                           calls=fr.calls, scope=fr.scope))
        return True

    def section_blocks(self, unit: Unit, a: int, stop: int, depth: int = 0) -> int:
        """Blocks one pass of lines [a, stop) runs, with the nested REPEATs of constant count
        multiplied out (the CNC8x6 G73 count; other jumps and calls count as one block)."""
        key = (id(unit), a, stop)
        if key in self.repeat_sizes:
            return self.repeat_sizes[key]
        total = 0
        for idx in range(a, min(stop, len(unit.lines))):
            ln = unit.lines[idx]
            total += 1 if ln.stmts else 0
            for st in ln.stmts:
                if isinstance(st, Repeat) and isinstance(st.count, Num) and depth < MAX_STACK:
                    s0 = unit.all_labels.get(st.start, [None])[0]
                    if s0 is None or s0 >= idx:
                        continue
                    end = (unit.labels.get(st.end, idx - 1) + 1) if st.end else idx
                    if s0 <= idx < end:
                        continue
                    total += int(st.count.value) * self.section_blocks(unit, s0, end, depth + 1)
        self.repeat_sizes[key] = total
        return total

    def repeat_estimate(self, stack: list[Frame], unit: Unit, a: int, stop: int, n: int, line: int, st) -> None:
        """A REPEAT whose passes (times the passes still to come of the REPEATs around it) would
        run past [simulation] max_blocks is refused at once, not after running millions of blocks."""
        est = n * self.section_blocks(unit, a, stop)
        for f in stack:
            if f.kind == "repeat" or f.count > 1:
                est *= max(f.count, 1)
        if self.executed + est > self.cfg.max_blocks:
            raise self.error(line, st.col, f"the program does not end in time: REPEAT {st.start} would run about "
                             f"{est:,} blocks, more than the {self.cfg.max_blocks:,} of [simulation] max_blocks")
