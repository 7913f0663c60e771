"""Interpreter: program text -> canonical records (see interp/canon.py).

The one registry of dialects: ``DIALECTS`` maps a dialect's name (``[machine] dialect`` in a setup)
to its ``Dialect`` entry: the module that interprets it (``interpret(name, text, cfg)``) and the
setup defaults that belong to it. The setup loader (cutsim/setup/) and the CLI read this table;
a new dialect is one subpackage (interp/<name>/, on the shared core: interp/core/) plus one line
here (docs/architecture.md, "How to add a dialect").
"""
from __future__ import annotations

import gc
from dataclasses import dataclass
from importlib import import_module

from .canon import Program, transcript
from .errors import CutsimError
from .core.modal import InterpConfig


@dataclass(frozen=True)
class WorkOffsets:
    """The settable work offsets of a dialect's controller, as a setup's [work_offsets] names them.

    ``names``: the G codes a setup may give; ``known``: how messages list them;
    ``not_settable``: (G code, why a setup cannot give it) for codes that mean something else on
    this controller."""

    names: tuple[str, ...] = tuple(f"G{n}" for n in range(54, 60))
    known: str = "G54 to G59"
    not_settable: tuple[tuple[str, str], ...] = ()


_SINUMERIK_WORK_OFFSETS = WorkOffsets(
    tuple(f"G{n}" for n in (*range(54, 58), *range(505, 600))), "G54 to G57 and G505 to G599",
    tuple((g, f"on Sinumerik {g} is a programmable axial offset written in the program") for g in ("G58", "G59")))


@dataclass(frozen=True)
class Dialect:
    """One registry entry.

    ``module``: the module or package with ``interpret(name, text, cfg) -> Program``; a name
    starting with a dot is relative to this package (``".cnc8x6"``), any other is absolute (a plug-in).
    ``diameter_programming``: on a lathe, whether X values are diameters when the setup does not
    say (``[machine] diameter_programming``); mills always program radii.
    ``extensions``: the file extensions its programs and subprograms usually have.
    ``work_offsets``: the settable work offsets a setup may give ([work_offsets]).
    """

    module: str
    diameter_programming: bool
    extensions: tuple[str, ...]
    title: str
    work_offsets: WorkOffsets = WorkOffsets()


DIALECTS: dict[str, Dialect] = {
    # CNC8x6 lathes program diameters; ISG and Sinumerik start in radius mode (G52 / DIAMOF) and
    # switch in the program.
    "cnc8x6": Dialect(".cnc8x6", True, (".nc",), "MEFI CNC8x6"),
    "isg": Dialect(".isg", False, (".nc",), "Beckhoff TwinCAT CNC (ISG kernel)"),
    "sinumerik": Dialect(".sinumerik", False, (".mpf", ".spf", ".nc"), "Siemens Sinumerik 840D",
                         _SINUMERIK_WORK_OFFSETS),
    "rs274ngc": Dialect(".rs274ngc", False, (".ngc", ".nc", ".tap"), "RS274NGC (LinuxCNC 2.9)"),
}


def available_dialects() -> list[str]:
    """The registered dialects' names. Every entry's module must import: a missing module is a
    packaging bug and raises (ModuleNotFoundError), it is not silently left out."""
    return list(DIALECTS)


def dialect_module(name: str):
    """The module interpreting dialect ``name`` (a key of DIALECTS)."""
    return import_module(DIALECTS[name].module, __name__)


def interpret(name: str, text: str, cfg: InterpConfig) -> Program:
    """Interpret a whole program. Raises CutsimError with the file, line and column on bad input."""
    if cfg.dialect not in DIALECTS:
        raise CutsimError(name, 0, 0, f"unknown dialect '{cfg.dialect}'")
    # The program's blocks and records are many, long-lived and free of reference cycles: the cyclic
    # garbage collector walking them again and again as they grow costs up to half the run (issue 13)
    enabled = gc.isenabled()
    gc.disable()
    try:
        return dialect_module(cfg.dialect).interpret(name, text, cfg)
    finally:
        if enabled:
            gc.enable()


__all__ = ["CutsimError", "Dialect", "DIALECTS", "WorkOffsets", "InterpConfig", "Program", "interpret", "transcript",
           "available_dialects", "dialect_module"]
