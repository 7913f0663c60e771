"""The run loop: O-word control flow (sub/call/return, if/elseif/else, while, do/while, repeat,
break/continue) over a program parsed once, files called by name (``o<name> call`` finds
``name.ngc`` beside the program or on ``[machine] subprogram_path``) and numbered subprograms
(``O100`` alone on a line ... ``M99``, called by ``M98 P100 [L repeats]``).

Each program file is a ``Unit``: its parsed lines and, found before it runs, where every O-word
block ends, so a jump never scans. A call pushes a ``Frame`` (the parameters #1-#30 and named
locals of the call level are pushed in ``values.Parameters``).
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field

from cutsim.interp.canon import Src
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.lexer import Block, Word, iter_lines

from . import context
from .syntax import Line, parse_line

MAX_CALL_DEPTH = 100
LOOPS = ("while", "do", "repeat")


@dataclass
class Unit:
    """One program file: its lines (None where nothing is to do) and its O-word structure."""

    name: str
    lines: list
    subs: dict = field(default_factory=dict)  # label -> index of its "sub" line
    ends: dict = field(default_factory=dict)  # index of an opening line -> index of its closing line
    heads: dict = field(default_factory=dict)  # index of a closing line -> index of its opening line
    branches: dict = field(default_factory=dict)  # index of "if" -> [indices of elseif/else lines]
    owner: dict = field(default_factory=dict)  # index of elseif/else/break/continue/return -> opening index
    programs: dict = field(default_factory=dict)  # number -> index of its "O<number>" line (M98)
    percent_end: int | None = None  # index of a closing '%' line


@dataclass
class Frame:
    unit: Unit
    return_pc: int
    call_line: int
    calls: tuple
    repeats: dict = field(default_factory=dict)  # index of a running "repeat" -> turns left
    m98: list | None = None  # an M98 call: [index of its O line, runs left (L)]


def load_unit(name: str, text: str) -> Unit:
    lines, first = [], True
    unit = Unit(name, lines)
    for lineno, raw in iter_lines(text):
        if raw.strip() == "%":
            if not first and unit.percent_end is None:
                unit.percent_end = len(lines)
            lines.append(None)
            first = False
            continue
        line = parse_line(name, lineno, raw)
        if line is not None:
            first = False
        lines.append(line)
    structure(unit)
    return unit


def structure(unit: Unit) -> None:
    """Pair every O-word opening with its closing line (errors at the line that does not fit)."""
    stack: list[tuple[str, str, int]] = []  # (keyword, label, index)

    def fail(line: Line, message: str):
        return CutsimError(unit.name, line.lineno, line.oword[3], message)

    def define(line: Line, table: dict, label: str, idx: int, what: str) -> None:
        """A subroutine (o... sub) or numbered subprogram (O...): at the top level, once."""
        if stack:
            raise fail(line, f"{what} cannot begin inside another block")
        if label in table:
            raise fail(line, f"{what} is defined twice")
        table[label] = idx

    for idx, line in enumerate(unit.lines):
        if line is None or line.oword is None:
            continue
        label, kw, _, _ = line.oword
        if kw == "program":
            define(line, unit.programs, label, idx, f"subprogram O{label}")
        elif kw == "while" and stack and stack[-1][0] == "do" and stack[-1][1] == label:
            unit.ends[stack.pop()[2]] = idx
        elif kw in ("sub", "if", "while", "do", "repeat"):
            if kw == "sub":
                define(line, unit.subs, label, idx, f"subroutine o{label}")
            stack.append((kw, label, idx))
        elif kw in ("endsub", "endif", "endwhile", "endrepeat"):
            opening = {"endsub": "sub", "endif": "if", "endwhile": "while", "endrepeat": "repeat"}[kw]
            if not stack or stack[-1][0] != opening or stack[-1][1] != label:
                raise fail(line, f"o{label} {kw} without its o{label} {opening}")
            unit.ends[stack.pop()[2]] = idx
        elif kw in ("elseif", "else"):
            if not stack or stack[-1][0] != "if" or stack[-1][1] != label:
                raise fail(line, f"o{label} {kw} without its o{label} if")
            unit.branches.setdefault(stack[-1][2], []).append(idx)
            unit.owner[idx] = stack[-1][2]
        elif kw in ("break", "continue"):
            loop = next((s for s in reversed(stack) if s[0] in LOOPS and s[1] == label), None)
            if loop is None:
                raise fail(line, f"o{label} {kw} outside a loop o{label}")
            if loop[0] == "repeat":  # as LinuxCNC 2.9: break and continue end while and do loops only
                raise fail(line, f"o{label} {kw}: break and continue work in while and do loops, not in repeat")
            unit.owner[idx] = loop[2]
        elif kw == "return":
            sub = next((s for s in stack if s[0] == "sub"), None)
            if sub is None:
                raise fail(line, f"o{label} return outside a subroutine")
            unit.owner[idx] = sub[2]
    unit.heads = {v: k for k, v in unit.ends.items()}
    if stack:
        kw, label, idx = stack[-1]
        raise fail(unit.lines[idx], f"o{label} {kw} is never closed")


class Runner:
    """Runs a main unit on a machine (``machine.Ngc``) with its evaluator."""

    def __init__(self, machine, evaluator, main: Unit, search: tuple[str, ...]):
        self.m, self.ev = machine, evaluator
        self.units = {main.name: main}
        self.search = search
        self.frames: list[Frame] = [Frame(main, -1, 0, ())]

    def value(self, line: Line, node) -> float:
        return self.ev.value(node, line.lineno, line.oword[3] if line.oword else 1)

    def run(self) -> None:
        self.m.run_profile = self.run_profile
        self.loop(self.frames[0].unit, 0, 1)

    def run_profile(self, number: float, lineno: int, col: int) -> None:
        """Run subroutine o<number> (a G70-G72 profile, Q) to its end now, as LinuxCNC 2.9 does: the
        subroutine of the current file, else of the main program."""
        label = f"{number:g}"
        unit = next((u for u in (self.frames[-1].unit, self.frames[0].unit) if label in u.subs), None)
        if unit is None:
            raise CutsimError(self.frames[-1].unit.name, lineno, col, f"the profile subroutine o{label} (Q) is not defined")
        if len(self.frames) > MAX_CALL_DEPTH:
            raise CutsimError(unit.name, lineno, col, f"subroutine calls nested more than {MAX_CALL_DEPTH} deep")
        self.frames.append(Frame(unit, -2, lineno, self.frames[-1].calls + ((self.frames[-1].unit.name, lineno),)))
        self.m.params.push([])
        self.loop(unit, unit.subs[label] + 1, len(self.frames))

    def loop(self, unit: Unit, pc: int, depth: int) -> None:
        """Run lines from ``pc`` until the program ends or the call level ``depth`` returns."""
        while len(self.frames) >= depth:
            if pc >= len(unit.lines) or pc == unit.percent_end:
                if len(self.frames) > 1:
                    raise CutsimError(unit.name, len(unit.lines), 1, "file ended inside a subroutine call")
                if pc == unit.percent_end:
                    return
                last = next((x.lineno for x in reversed(unit.lines) if x is not None), 1)
                raise CutsimError(unit.name, last, 1, "file ended with no percent sign or program end (M2 or M30)")
            line = unit.lines[pc]
            if line is None:
                pc += 1
                continue
            self.m.count_block(line_of(line))
            if line.oword is not None:
                unit, pc = self.oword(unit, pc, line)
                continue
            done = self.block(unit, line)
            if done is True:
                return
            if done:  # M98 / M99
                unit, pc = self.subprogram(unit, pc, line, done)
                if pc < 0:
                    return
                continue
            pc += 1

    def block(self, unit: Unit, line: Line):
        """Evaluate and execute one line; True at the program end, an M98/M99 word to run."""
        words, seen = [], {}
        for ref, _, col in line.assigns:  # a name being set exists (0) while the line is read, as in LinuxCNC
            if ref[0] == "name" and not self.m.params.exists(ref[1]):
                self.ev.set(ref, 0.0, line.lineno, col)
        for letter, node, col in line.words:
            v = self.ev.value(node, line.lineno, col)
            if letter not in "GM" and letter in seen:
                raise CutsimError(unit.name, line.lineno, col, f"two {letter} words in one block")
            seen[letter] = col
            words.append(Word(letter, v, f"{v:g}" if node[0] != "num" else _raw(v), col))
        values = [(ref, self.ev.value(node, line.lineno, col), col) for ref, node, col in line.assigns]
        for ref, v, col in values:
            self.ev.set(ref, v, line.lineno, col)
        if not words:
            return False
        call = next((w for w in words if w.letter == "M" and w.value in (98.0, 99.0)), None)
        if call is not None:
            other = next((w for w in words if w is not call and w.letter not in ("PL" if call.value == 98 else "")), None)
            if other is not None:
                raise CutsimError(unit.name, line.lineno, other.col,
                                  f"M{call.raw} stands alone in its block (M98 with P and L only)")
            return call, {w.letter: w for w in words}
        b = Block(line=line.lineno, col=1, words=words)
        frame = self.frames[-1]
        st = self.m.execute(b, Src(unit.name, line.lineno, 1, "", frame.calls))
        return bool(st.result)

    def oword(self, unit: Unit, pc: int, line: Line) -> tuple[Unit, int]:
        label, kw, args, col = line.oword
        frame = self.frames[-1]
        if kw == "sub":
            return unit, unit.ends[pc] + 1
        if kw == "program":  # reached in sequence: its lines run on (as rs274 reads them)
            return unit, pc + 1
        if kw in ("endsub", "return"):
            if len(self.frames) == 1:
                raise CutsimError(unit.name, line.lineno, col, f"o{label} {kw} outside a subroutine call")
            self.m.params.globals["_value_returned"] = 1.0 if args else 0.0
            if args:
                self.m.params.globals["_value"] = self.value(line, args[0])
            context.returned(self.m, Src(unit.name, line.lineno, col, "", frame.calls))  # M73
            self.frames.pop()
            self.m.params.pop()
            return self.frames[-1].unit if frame.return_pc >= 0 else unit, frame.return_pc
        if kw == "call":
            return self.call(unit, pc, line)
        if kw == "if":
            return unit, self.branch(unit, pc, line)
        if kw in ("elseif", "else"):  # the end of a branch taken: LinuxCNC still reads (evaluates) an elseif
            if kw == "elseif":
                self.value(line, self.one(line, args))
            return unit, unit.ends[unit.owner[pc]] + 1
        if kw in ("endif", "do"):
            return unit, pc + 1
        if kw == "while":
            cond = self.value(line, self.one(line, args)) != 0.0
            if pc in unit.ends:  # the head of a while loop
                return unit, pc + 1 if cond else unit.ends[pc] + 1
            do = unit.heads[pc]
            return unit, do + 1 if cond else pc + 1
        if kw == "endwhile":
            return unit, unit.heads[pc]
        if kw == "repeat":
            n = self.value(line, self.one(line, args))
            frame.repeats[pc] = int(n)
            return unit, pc + 1 if int(n) > 0 else unit.ends[pc] + 1
        if kw == "endrepeat":
            head = unit.heads[pc]
            frame.repeats[head] -= 1
            return unit, head + 1 if frame.repeats[head] > 0 else pc + 1
        loop = unit.owner[pc]  # break / continue
        loop_kw = unit.lines[loop].oword[1]
        if kw == "break":
            return unit, unit.ends[loop] + 1
        if loop_kw == "while":
            return unit, loop
        return unit, unit.ends[loop]  # do: its closing while; repeat: its endrepeat

    def subprogram(self, unit: Unit, pc: int, line: Line, found) -> tuple[Unit, int]:
        """M98 P<n> [L<k>]: run subprogram O<n> (of this file, else the main one) k times, its named
        parameters local, #1-#30 shared with the caller; M99: its end (in the main program: the
        program end, as rs274 takes it). Returns where to go on (pc -1: the program ended)."""
        call, words = found
        frame = self.frames[-1]
        if call.value == 99:
            if frame.m98 is None:
                if len(self.frames) > 1:
                    raise CutsimError(unit.name, line.lineno, call.col, "M99 inside an o-word subroutine call")
                self.m.execute(Block(line=line.lineno, col=1, words=[Word("M", 2.0, "2", call.col)]),
                               Src(unit.name, line.lineno, 1, "", frame.calls))
                return unit, -1
            frame.m98[1] -= 1
            self.m.params.pop()
            if frame.m98[1] > 0:
                self.m.params.push_shared()
                return unit, frame.m98[0] + 1
            self.frames.pop()
            return self.frames[-1].unit, frame.return_pc
        if "P" not in words:
            raise CutsimError(unit.name, line.lineno, call.col, "M98 needs the subprogram number P")
        number = self.m.whole(line.lineno, words["P"], "subprogram number")
        runs = self.m.whole(line.lineno, words["L"], "repeat count") if "L" in words else 1
        target = next((u for u in (unit, self.frames[0].unit) if str(number) in u.programs), None)
        if target is None:
            raise CutsimError(unit.name, line.lineno, words["P"].col, f"subprogram O{number} is not in this program")
        if runs == 0:
            return unit, pc + 1
        if len(self.frames) > MAX_CALL_DEPTH:
            raise CutsimError(unit.name, line.lineno, call.col, f"subroutine calls nested more than {MAX_CALL_DEPTH} deep")
        start = target.programs[str(number)]
        self.frames.append(Frame(target, pc + 1, line.lineno, frame.calls + ((unit.name, line.lineno),),
                                 m98=[start, runs]))
        self.m.params.push_shared()
        return target, start + 1

    def one(self, line: Line, args: list):
        if len(args) != 1:
            raise CutsimError(self.frames[-1].unit.name, line.lineno, line.oword[3],
                              f"o{line.oword[0]} {line.oword[1]} needs one [condition]")
        return args[0]

    def branch(self, unit: Unit, pc: int, line: Line) -> int:
        if self.value(line, self.one(line, line.oword[2])) != 0.0:
            return pc + 1
        for idx in unit.branches.get(pc, []):
            other = unit.lines[idx]
            if other.oword[1] == "else":
                return idx + 1
            if self.value(other, self.one(other, other.oword[2])) != 0.0:
                return idx + 1
        return unit.ends[pc] + 1

    def call(self, unit: Unit, pc: int, line: Line) -> tuple[Unit, int]:
        label, _, args, col = line.oword
        values = [self.value(line, a) for a in args]
        if len(values) > 30:
            raise CutsimError(unit.name, line.lineno, col, "a call passes at most 30 arguments")
        target = unit if label in unit.subs else self.file_unit(unit, line)
        if len(self.frames) > MAX_CALL_DEPTH:
            raise CutsimError(unit.name, line.lineno, col, f"subroutine calls nested more than {MAX_CALL_DEPTH} deep")
        calls = self.frames[-1].calls + ((unit.name, line.lineno),)
        self.frames.append(Frame(target, pc + 1, line.lineno, calls))
        self.m.params.push(values)
        return target, target.subs[label] + 1

    def file_unit(self, unit: Unit, line: Line) -> Unit:
        label, col = line.oword[0], line.oword[3]
        if label.isdigit():
            raise CutsimError(unit.name, line.lineno, col, f"subroutine o{label} is not defined in this program")
        dirs = (os.path.dirname(self.frames[0].unit.name) or ".",) + self.search
        for d in dirs:
            path = os.path.join(d, label + ".ngc")
            if path in self.units:
                return self.units[path]
            if os.path.isfile(path):
                try:
                    with open(path, encoding="utf-8", errors="strict") as f:
                        text = f.read(4_000_000)
                except (OSError, UnicodeDecodeError) as e:
                    raise CutsimError(unit.name, line.lineno, col, f"cannot read {path}: {e}") from None
                u = load_unit(path, text)
                if label not in u.subs:
                    raise CutsimError(path, 1, 1, f"{path} does not define o<{label}> sub")
                self.units[path] = u
                return u
        raise CutsimError(unit.name, line.lineno, col, f"subroutine o<{label}> is not defined in this program and "
                          f"no file {label}.ngc was found beside it or on [machine] subprogram_path")


def _raw(v: float) -> str:
    return f"{v:g}"


def line_of(line: Line):
    return Block(line=line.lineno, col=1)
