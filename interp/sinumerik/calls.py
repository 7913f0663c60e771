"""Subprogram calls: finding the subprogram (in the program, beside it, external), binding its
parameters, the call stack, PROC ... SAVE and RET.
"""
from __future__ import annotations

import copy
import functools
import os
import re
import stat

from ..canon import Src
from . import axes, drilling as drill, fast as sinumerik_fast
from .syntax import Call, Frame, Index, Ret, SubprogramMissing, Unit, Var
from .reader import split_units
from .cycle import CYCLES
from .milling import run_cycle
from .tables import (call_name, IGNORED_CALLS, MAX_SUB_BYTES, missing_hint, NOT_FILES, NOT_YET, SAVED_MODAL,
                     UNSUPPORTED_MEANINGS)
from .values import ArrayVar, Block, Slot, to_text, Value


class Calls:
    """Subprogram calls: finding the subprogram (in the program, beside it, external), binding its
    parameters, the call stack, PROC ... SAVE and RET.

    A part of ``Sinumerik`` (interpreter.py): its methods work on the state declared in
    ``Sinumerik.__init__``."""

    def find_sub(self, name: str, line: int, col: int) -> Unit:
        """A subprogram: a PROC or %_N_NAME_SPF of the program's own file, else NAME.spf (.mpf, .nc)
        beside the program, else in the setup's [machine] subprogram_path folders, in that order.
        A file whose blocks are all inside ``PROC NAME`` runs that PROC's body."""
        if name in self.subs:
            return self.subs[name]
        if name in NOT_FILES:
            listed = " ([machine] external_subprograms does not apply to it: the simulator knows the Siemens " \
                     "keywords and cycles and will not take one as cutting nothing)" if name in self.externals else ""
            if name in NOT_YET:
                what, why = NOT_YET[name]
                raise self.error(line, col, f"{name} ({what}) is not simulated yet: {why}{listed}")
            what = f" ({UNSUPPORTED_MEANINGS[name]})" if name in UNSUPPORTED_MEANINGS else ""
            raise self.error(line, col, f"{name}{what} is a Siemens keyword the simulator does not support{listed}")
        path = None
        for d in (*self.sub_dirs(), *self.cfg.subprogram_path):
            try:
                cands = sorted(f for f in os.listdir(d) if os.path.splitext(f)[0].upper() in (name, f"_N_{name}_SPF")
                               and os.path.splitext(f)[1].upper() in (".SPF", ".MPF", ".NC", ""))
            except OSError:
                cands = []
            cands = [f for f in cands if os.path.splitext(f)[1]] or cands
            if cands:
                path = os.path.join(d, cands[0])
                break
        if path is None:
            raise SubprogramMissing(self.unit_program, line, col, f"subprogram {name} is not defined (PROC {name} in "
                                    f"this file, {name}.spf beside it or in [machine] subprogram_path"
                                    f"{missing_hint(name)})")
        text = self.read_sub(path, name, line, col)
        unit, more = split_units(path, text, sinumerik_fast.read_plain)
        if not any(ln.stmts for ln in unit.lines) and more:
            unit = more.get(name) or next(iter(more.values()))  # the file is its PROC
        unit.name = name
        self.subs[name] = unit
        for k, u in more.items():
            self.subs.setdefault(k, u)
        return unit

    def sub_dirs(self) -> list[str]:
        """The program's folder, then the global subprogram folders of a Siemens archive beside it
        (SPF.DIR, _N_SPF_DIR, SPF_DIR; also one level up, for a program inside MPF.DIR or a .WPD)."""
        here = os.path.dirname(os.path.abspath(self.name))
        dirs = [here]
        for base in (here, os.path.dirname(here)):
            try:
                names = sorted(os.listdir(base))
            except OSError:
                continue
            dirs += [os.path.join(base, n) for n in names if n.upper() in ("SPF.DIR", "_N_SPF_DIR", "SPF_DIR")
                     and os.path.join(base, n) not in dirs]
        return dirs

    def read_sub(self, path: str, name: str, line: int, col: int) -> str:
        """The text of a subprogram file; a directory, a special or unreadable file, or one larger
        than MAX_SUB_BYTES is an error at the calling block."""
        what = f"subprogram {name}: {path}"
        try:
            st = os.stat(path)
        except OSError as e:
            raise self.error(line, col, f"{what} cannot be read ({e.strerror})") from None
        if stat.S_ISDIR(st.st_mode):
            raise self.error(line, col, f"{what} is a directory, not a program file")
        if not stat.S_ISREG(st.st_mode):
            raise self.error(line, col, f"{what} is not a regular file")
        if st.st_size > MAX_SUB_BYTES:
            raise self.error(line, col, f"{what} has {st.st_size:,} bytes, more than the {MAX_SUB_BYTES:,} a "
                             "subprogram file may have")
        try:
            with open(path, "rb") as f:
                data = f.read(MAX_SUB_BYTES + 1)
        except OSError as e:
            raise self.error(line, col, f"{what} cannot be read ({e.strerror})") from None
        if len(data) > MAX_SUB_BYTES:
            raise self.error(line, col, f"{what} has more than the {MAX_SUB_BYTES:,} bytes a subprogram file may have")
        return data.decode("utf-8-sig", errors="replace")

    def calls(self, blk: Block, src: Src, line: int, stack: list[Frame]) -> bool:
        """Cycles, subprogram calls (NAME, L<n> P<n>) and RET/M17; True when the block hands over
        to another frame (a call or a return)."""
        for st in drill.modal_call(self, blk, line):  # MCALL CYCLE8x(..) / MCALL SUB / MCALL alone
            if isinstance(st, Ret):
                self.ret(stack)
                return True
            if isinstance(st, Call):
                if st.name in IGNORED_CALLS:
                    continue
                if st.name not in CYCLES:  # a PROC with parameters: NAME(1, , R3)
                    if self.call_proc(st, src, blk.words, stack):
                        return True
                    continue  # a declared external subprogram: skipped
                args = [(None if a.value is None else self.ev(a.value, line, a.col), a.col) for a in st.args]
                run_cycle(self, st.name, args, src, st.col)
                continue
            if st.name in self.vars:  # SubCall
                raise self.error(line, st.col, f"'{st.name}' is a variable: write {st.name}=<value> to assign it")
            unit = self.find_unit(st.name, src, st.col, blk.words)
            if unit is None:
                continue  # a declared external subprogram: skipped
            self.call_sub(unit, src, blk.words, stack, st.col)
            return True
        words = blk.words
        if "L" in words:
            lw = words.pop("L")
            if lw.value != int(lw.value):
                raise self.error(line, lw.col, f"L{lw.value:g}: a subprogram number is a whole number")
            unit = self.find_unit(f"L{int(lw.value)}", src, lw.col, words)
            if unit is None:
                return False
            self.call_sub(unit, src, words, stack, lw.col)
            return True
        if "P" in words:
            raise self.error(line, words["P"].col, "P (repeat count) only goes with a subprogram call")
        return False

    def call_proc(self, st: Call, src: Src, words: dict[str, Value], stack: list[Frame]) -> bool:
        """NAME(args) / L140(2): a subprogram with parameters (an unknown name is an error naming
        it as a cycle, function or subprogram); CALL "NAME": the subprogram a string names; EXTCALL
        "path/NAME.SPF": the program a string names on external storage, found by its name. False
        when the subprogram is a declared external one (skipped, ``find_unit``)."""
        if st.name in ("CALL", "EXTCALL"):
            name = self.ev(st.args[0].value, src.line, st.col)
            if st.name == "EXTCALL" and isinstance(name, str):
                name = call_name(name)
            if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name.strip()):
                raise self.error(src.line, st.col, f"{st.name} needs a subprogram name as a string, "
                                 f"not {to_text(name)!r}")
            st = Call(st.col, name.strip().upper(), ())
        try:
            unit = self.find_unit(st.name, src, st.col, words, st.args)
        except SubprogramMissing:
            raise self.error(src.line, st.col, f"unknown cycle, function or subprogram {st.name} (no PROC {st.name} "
                             f"in this file, no {st.name}.spf beside it or in [machine] subprogram_path"
                             f"{missing_hint(st.name)})") from None
        if unit is None:
            return False
        self.call_sub(unit, src, words, stack, st.col, st.args)
        return True

    def find_unit(self, name: str, src: Src, col: int, words: dict[str, Value], args: tuple = ()) -> Unit | None:
        """The subprogram a call names (``find_sub``), or None when it is not found but declared in
        the setup's [machine] external_subprograms: the call is skipped (its P repeat count and its
        arguments checked, one warning per name) and the tool stays where it was."""
        try:
            return self.find_sub(name, src.line, col)
        except SubprogramMissing:
            if name not in self.externals:
                raise
        if "P" in words:
            p = words.pop("P")
            if p.value != int(p.value) or p.value < 1:
                raise self.error(src.line, p.col, "P (repeat count) must be a whole number of at least 1")
        for a in args:  # an argument that is not a bare name (an axis, a VAR target) is evaluated: its errors count
            if a.value is not None and not (isinstance(a.value, Var) and a.value.name not in self.vars):
                self.ev(a.value, src.line, a.col)
        self.external_note(name, Src(src.program, src.line, col, src.label, src.calls))
        return None

    def external_note(self, name: str, src: Src) -> None:
        """The one warning of a skipped call of a declared external subprogram ``name``."""
        if f"external:{name}" in self.warned:
            return
        self.warned.add(f"external:{name}")
        self.warn(src, f"{name} is declared external in the setup ([machine] external_subprograms): its motion is "
                       "not simulated, the tool is taken to stay where it was")

    def ret(self, stack: list[Frame]) -> None:
        while stack and stack[-1].kind == "repeat":
            stack.pop()
        if len(stack) > 1 and stack[-1].count > 1:  # P<n>: run the subprogram again
            stack[-1].count -= 1
            stack[-1].pc = stack[-1].restart
            return
        if len(stack) <= 1:
            stack[:] = []  # RET / M17 in the main program ends it
            return
        fr = stack.pop()
        if fr.saved is not None:  # PROC ... SAVE
            self.restore_modal(fr.saved)
        self.vars = stack[-1].scope

    def call_sub(self, unit: Unit, src: Src, words: dict[str, Value], stack: list[Frame], col: int,
                 args: tuple = ()) -> None:
        n = 1
        if "P" in words:
            p = words.pop("P")
            if p.value != int(p.value) or p.value < 1:
                raise self.error(src.line, p.col, "P (repeat count) must be a whole number of at least 1")
            n = int(p.value)
        if len(stack) > 16:
            raise self.error(src.line, col, "subprograms nested deeper than 16 levels (recursion?)")
        scope = self.bind(unit, args, src.line, col)
        calls = stack[-1].calls + ((src.program, src.line),)
        saved = self.save_modal() if unit.proc is not None and unit.proc.save else None
        stack.append(Frame(unit, pc=0, stop=len(unit.lines), restart=0, ret=stack[-1].pc, count=n, kind="unit",
                           calls=calls, scope=scope, saved=saved))
        self.vars = scope

    def bind(self, unit: Unit, args: tuple, line: int, col: int) -> dict:
        """The called PROC's parameters: values (converted to their type; an omitted one takes its
        default or 0) and VAR parameters sharing the caller's variable, R parameter or element."""
        params = unit.proc.params if unit.proc is not None else ()
        if len(args) > len(params):
            raise self.error(line, args[len(params)].col if args[len(params)].col else col,
                             f"{unit.name} takes {len(params)} parameter(s), not {len(args)}")
        scope: dict = {}
        for k, p in enumerate(params):
            arg = args[k] if k < len(args) else None
            given = arg is not None and arg.value is not None
            if p.var:
                if not given:
                    raise self.error(line, arg.col if arg else col,
                                     f"{unit.name}: parameter {k + 1} ({p.name}) is VAR: pass a variable")
                if not isinstance(arg.value, (Var, Index)):
                    raise self.error(line, arg.col, f"{unit.name}: parameter {k + 1} ({p.name}) is VAR: pass a "
                                     "variable, an R parameter or an array element, not a value")
                held = self.vars.get(arg.value.name) if isinstance(arg.value, Var) else None
                if p.array != isinstance(held, ArrayVar):
                    raise self.error(line, arg.col, f"{unit.name}: parameter {k + 1} ({p.name}) "
                                     f"{'is an array: pass an array' if p.array else 'is no array: pass one element'}")
                scope[p.name] = held if p.array else self.slot(arg.value, line, write=True)
                continue
            value = self.ev if p.type != "AXIS" else functools.partial(axes.axis_of, self)  # PROC P(AXIS A): P(X)
            v = value(arg.value, line, arg.col) if given else (
                value(p.default, line, col) if p.default is not None else ("" if p.type in ("STRING", "AXIS") else 0.0))
            slot = Slot(p.type, "" if p.type in ("STRING", "AXIS") else 0.0)
            if not slot.set(v):
                raise self.error(line, arg.col if given else col,
                                 f"{unit.name}: parameter {k + 1} ({p.name}) is {p.type}, not the string \"{v}\"")
            scope[p.name] = slot
        return scope

    def save_modal(self) -> dict:
        """PROC ... SAVE: the modal state to put back on return (the G groups and what settings
        keeps modal; SAVED_MODAL lists the attributes, the machine functions' among them)."""
        return {a: copy.deepcopy(getattr(self, a)) for a in SAVED_MODAL}

    def restore_modal(self, saved: dict) -> None:
        for a, v in saved.items():
            setattr(self, a, v)
