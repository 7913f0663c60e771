"""ISG subprogram calls: local (LL name), global files (L name, found by core.files), cycles with
@P parameters, modal cycle calls, implicit calls (G80..G89, G800..G819) and external subprograms."""
from __future__ import annotations

import os
import unicodedata

from .fast import read_plain
from .program import parse
from .reader import nfc, IsgBlock, Section
from .tables import MAX_CALL_DEPTH, MAX_SUB_BYTES, SUB_EXTENSIONS
from ..canon import Src
from ..core.files import Unreadable, find_subprogram, read_bounded
from ..core.lexer import Word

_UMLAUTS = str.maketrans({"ä": "ae", "ö": "oe", "ü": "ue", "ß": "ss", "Ä": "Ae", "Ö": "Oe", "Ü": "Ue"})


def _folds(name: str) -> set[str]:
    """Spellings a name may have been meant as: case folded, umlauts as digraphs or stripped."""
    n = nfc(name)
    digraph = n.translate(_UMLAUTS).casefold()
    stripped = "".join(c for c in unicodedata.normalize("NFKD", n) if not unicodedata.combining(c)).casefold()
    return {n.casefold(), digraph, stripped}


class Level:
    """One running program level: its file, local subprograms, V.L. variables, call parameters."""

    __slots__ = ("name", "local", "vl", "params", "stack", "calls", "modal", "cycle")

    def __init__(self, name, local, params, stack, calls, cycle=False):
        self.name, self.local, self.params, self.stack, self.calls = name, local, params, stack, calls
        self.cycle = cycle  # a cycle call (L CYCLE, LL CYCLE, an implicit call with an argument list)
        self.vl: dict = {}
        self.modal: tuple | None = None  # L CYCLE [.. MODAL_MOVE ..] of this level: (file name, column, params)


class Calls:
    """Subprogram calls of Isg (a part of it). State: ``level`` (the running program level),
    ``files`` (global subprogram files read: path -> (main, local)), ``implicit_files`` (#FILE NAME:
    G code -> file name), ``external_stems`` ([machine] external_subprograms without extension) and
    ``external_skipped`` (the first declared external subprogram skipped)."""

    # what a cycle call restores when it ends: the modal G functions, circle data and feed
    _CYCLE_STATE = ("motion", "absolute", "per_rev", "feed", "plane", "circle_r", "centre_abs")

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.level: Level | None = None
        self.files: dict[str, tuple] = {}
        self.implicit_files: dict[str, str] = {}
        self.external_stems = frozenset(os.path.splitext(n)[0] or n for n in cfg.external_subprograms)
        self.external_skipped: str | None = None

    def enter(self, b: IsgBlock, col: int, target: str, fr: Level) -> None:
        if target in fr.stack:
            raise self.error(b.line, col, f"recursive subprogram call: {' -> '.join(fr.stack + (target,))}")
        if len(fr.stack) >= MAX_CALL_DEPTH:
            s = fr.stack
            chain = " -> ".join(s[:3] + ("...",) + s[-2:] if len(s) > 6 else s)
            kind = "local subprograms" if b.call is not None else "subprograms"
            raise self.error(b.line, col, f"{'LL' if b.call is not None else 'L'} {target}: {kind} nested more than "
                             f"{MAX_CALL_DEPTH} deep "
                             f"({chain} -> {target}); the limit of open subprogram calls is {MAX_CALL_DEPTH}")

    def call_local(self, b: IsgBlock, fr: Level, params: dict | None = None) -> None:
        """LL name (the caller's call parameters stay visible), LL CYCLE [NAME = name @P1 = ..] (its own,
        and the caller's modal state restored at its end); ``params``: a modal cycle called again."""
        target, col = b.call
        if params is None and b.modal:
            params = self.cycle_call(b, fr, "LL", target, col, b.cparams)
        sec = fr.local.get(target)
        if sec is None and self.external(b, target):
            return
        if sec is None:
            msg = f"unknown subprogram '{target}'"
            near = [n for n in fr.local if _folds(n) & _folds(target)]
            if near:
                msg += f"; did you mean '{near[0]}'?"
            elif fr.local:
                msg += f" (local subprograms here: {', '.join(sorted(fr.local))})"
            else:
                msg += " (this file defines no local subprogram '%L name')"
            raise self.error(b.line, col, msg)
        self.enter(b, col, target, fr)
        sub = Level(fr.name, fr.local, fr.params if params is None else params, fr.stack + (target,),
                    fr.calls + ((fr.name, b.line),), cycle=params is not None)
        if params is None:
            self.run_level(sec, sub)
            return
        saved = self.cycle_state()
        self.run_level(sec, sub)
        self.restore_cycle_state(saved)

    def cycle_call(self, b: IsgBlock, fr: Level, kind: str, name: str, col: int, pexprs: dict) -> dict:
        """A cycle call's checks and parameters; a MODAL_MOVE one becomes the level's modal cycle."""
        if fr.modal is not None:
            raise self.error(b.line, col, f"cycle call while the modal cycle {fr.modal[1]} (line {fr.modal[4]}) is "
                             "active: deselect it first with #DISABLE MODAL CYCLE")
        if b.modal == "MODAL_BLOCK":
            raise self.error(b.line, col, "MODAL_BLOCK (the cycle called again after every block) is not modelled by "
                             "the simulator; MODAL_MOVE (again after every block with a motion) is")
        params = {k: f(self) for k, f in pexprs.items()}
        if b.modal == "MODAL_MOVE":
            fr.modal = (kind, name, col, params, b.line)
        return params

    def run_level(self, sec: Section, sub: Level) -> None:
        saved, saved_name = self.level, self.name
        self.level, self.name = sub, sub.name
        try:
            self.declare(sec)
            self.section(sec)
        finally:
            self.level, self.name = saved, saved_name

    def call_global(self, b: IsgBlock, fr: Level) -> None:
        fname, col, pexprs = b.gcall
        if b.modal:
            params = self.cycle_call(b, fr, "L", fname, col, pexprs)
        else:
            params = {k: f(self) for k, f in pexprs.items()}
        self.global_file(b, fr, fname, col, params, cycle=bool(b.modal))

    def modal_cycle(self, b: IsgBlock, fr: Level) -> None:
        """The modal cycle (L CYCLE [NAME = .. MODAL_MOVE ..]) again after block ``b`` of its program
        level, which has a motion (manual: "Cycles as global or local subroutines")."""
        kind, name, col, params, _ = fr.modal
        if kind == "LL":
            self.call_local(IsgBlock(b.line, b.col, b.label, call=(name, col)), fr, dict(params))
        else:
            self.global_file(b, fr, name, col, dict(params), cycle=True)

    def global_file(self, b: IsgBlock, fr: Level, fname: str, col: int, params: dict, cycle: bool) -> None:
        """Run the global subprogram file ``fname`` (a declared external one: nothing); a cycle restores
        the caller's modal state when it ends."""
        path = self.find_file(fname, b.line, col, missing_ok=True)
        if path is None:
            if self.external(b, fname):
                return
            self.find_file(fname, b.line, col)  # the error naming the folders and the setup keys
        if not cycle:
            self.run_file(b, fr, path, fname, col, params)
            return
        saved = self.cycle_state()
        self.run_file(b, fr, path, fname, col, params, cycle=True)
        self.restore_cycle_state(saved)

    def cycle_state(self) -> tuple:
        """The modal G functions, circle data and feed a cycle restores when it ends (manual: P-CHAN-00210
        cycle_changes_modal, default 0)."""
        return tuple(getattr(self, k) for k in self._CYCLE_STATE)

    def restore_cycle_state(self, saved: tuple) -> None:
        if self.ended:
            return
        for k, v in zip(self._CYCLE_STATE, saved):
            setattr(self, k, v)

    def external(self, b: IsgBlock, fname: str) -> bool:
        """A subprogram, cycle file or implicit-call G code the setup declares the machine has
        (``[machine] external_subprograms``) and the simulator does not: True (after one warning per
        name) when ``fname`` is one of them; nothing runs and the tool stays where it is."""
        base = fname.replace("\\", "/").rsplit("/", 1)[-1]
        stem = os.path.splitext(base.upper())[0] or base.upper()
        if stem not in self.external_stems:
            return False
        if self.external_skipped is None:
            self.external_skipped = base
        self.warn_once(("external", stem), Src(self.name, b.line, 1, b.label, self.level.calls),
                       f"{base} is declared external in the setup ([machine] external_subprograms): its motion is not "
                       "simulated, the tool is taken to stay where it was")
        return True

    def run_file(self, b: IsgBlock, fr: Level, path: str, fname: str, col: int, params: dict,
                 cycle: bool = False) -> None:
        if path not in self.files:
            text = self.read_file(path, fname, b.line, col)
            self.files[path] = parse(path, text, self.cfg.max_blocks, self.macros, read_plain)
        main, local = self.files[path]
        label = os.path.basename(path)
        self.enter(b, col, label, fr)
        sub = Level(path, local, params, fr.stack + (label,), fr.calls + ((fr.name, b.line),), cycle)
        self.run_level(main, sub)

    def call_implicit(self, b: IsgBlock, fr: Level, code: int, g: Word) -> None:
        """G80..G89 and G800..G819 call a subprogram the machine maker configures; the simulator runs
        the file G<n>.nc from the program's folder or [machine] subprogram_path, the values of an
        argument list G805[a, b, c] as @P1, @P2, @P3 (assumption, docs/dialects/isg.md)."""
        args = [f(self) for f in b.args.get(g.col, [])]
        name = self.implicit_files.get(f"G{code}", f"G{code}")
        path = self.find_file(name, b.line, g.col, missing_ok=True)
        if path is None:
            if self.external(b, name) or self.external(b, f"G{code}"):
                return
            raise self.error(b.line, g.col, f"G{g.raw} is an implicit subroutine call: the machine maker's "
                             f"subprogram behind it ({name}) is not known to the simulator (put the file in the "
                             "program's folder or in the setup's [machine] subprogram_path, or declare it in the "
                             f"setup: [machine] external_subprograms = [\"{name}\"])")
        params = {f"@P{k + 1}": v for k, v in enumerate(args)}
        saved = self.cycle_state()
        self.run_file(b, fr, path, name, g.col, params, cycle=g.col in b.args)
        if g.col in b.args:  # with transfer parameters the call is a cycle call (manual): its changes end with it
            self.restore_cycle_state(saved)

    def g80_plain(self, g: Word, b: IsgBlock) -> bool:
        """G80 without an argument list, with no file named for it (#FILE NAME, G80.nc on the search
        path) and not declared external: the ISO "modal cycle off", which moves nothing."""
        if "G80" in self.implicit_files or g.col in b.args or "G80" in self.external_stems:
            return False
        return self.find_file("G80", b.line, g.col, missing_ok=True) is None

    def find_file(self, fname: str, line: int, col: int, missing_ok: bool = False) -> str | None:
        """A global subprogram: the program's folder, then [machine] subprogram_path. A path written
        for the controller (C:\\...\\name.nc) is looked up by its file name; names compare without
        case, with or without ``.nc``."""
        base = fname.replace("\\", "/").rsplit("/", 1)[-1]
        dirs = [os.path.dirname(os.path.abspath(self.name)), *self.cfg.subprogram_path]
        path = find_subprogram(base, dirs, SUB_EXTENSIONS)
        if path is not None or missing_ok:
            return path
        alt = "" if base.upper().endswith(".NC") else f" (or {base}.nc)"
        raise self.error(line, col, f"global subprogram '{fname}': no file {base}{alt} in "
                         f"{' or '.join(dirs)} (give its folder in the setup: [machine] subprogram_path, or, when the "
                         f"machine has it and its motion need not be simulated: [machine] external_subprograms = "
                         f"[\"{base}\"]; a local subprogram of this file is defined as '%L name' and called with "
                         "'LL name')")

    def read_file(self, path: str, fname: str, line: int, col: int) -> str:
        what = f"subprogram {fname}: {path}"
        try:
            data = read_bounded(path, MAX_SUB_BYTES)
        except Unreadable as e:
            if e.kind == "directory":
                raise self.error(line, col, f"{what} is a directory, not a program file") from None
            if e.kind == "special":
                raise self.error(line, col, f"{what} is not a regular file") from None
            if e.kind == "large":
                size = f"{e.size:,}" if e.size >= 0 else "more"
                raise self.error(line, col, f"{what} has {size} bytes, more than the {MAX_SUB_BYTES:,} a "
                                 "subprogram file may have") from None
            raise self.error(line, col, f"{what} cannot be read ({e.reason})") from None
        return data.decode("utf-8-sig", errors="replace")
