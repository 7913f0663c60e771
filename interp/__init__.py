"""Interpreter: program text -> canonical records (see interp/canon.py).

The one registry of dialects: ``DIALECTS`` maps a dialect's name (``[machine] dialect`` in a setup)
to its ``Dialect`` entry: the module that interprets it (``interpret(name, text, cfg)``) and the
setup defaults that belong to it. The setup loader (cutsim/setup/) and the CLI read this table;
a new dialect is one subpackage (interp/<name>/, on the shared core: interp/core/) plus one line
here (docs/architecture.md, "How to add a dialect").
"""
from __future__ import annotations

import gc
import re
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
class VariableNames:
    """The names a setup's [variables] may give: values the dialect's programs read from the
    controller that only the setup can say (system variables, PLC data, global user data).

    ``pattern``: a regular expression the whole name must match, upper-cased and with the spaces
    inside ``[ ]`` removed; empty when the dialect's programs read no such values. ``accepts``: the
    error message for any other name: what the dialect accepts, with ``examples`` (each of them
    matches the pattern), or, without a pattern, where such values go instead."""

    pattern: str = ""
    accepts: str = "this dialect reads no [variables]"
    examples: tuple[str, ...] = ()

    def matches(self, name: str) -> bool:
        return bool(self.pattern) and re.fullmatch(self.pattern, name) is not None


_IDENT = r"[A-Z_][A-Z0-9_]*"
_INDEX = r"\[[A-Z0-9_.+\-]+(?:,[A-Z0-9_.+\-]+)*\]"  # Sinumerik: [5], [X1], [1,X,TR]
_WHOLE = r"\[(?:0|[1-9][0-9]*)\]"  # ISG: one whole number per bracket, printed as the program's key prints it

_SINUMERIK_VARIABLES = VariableNames(
    rf"\$?{_IDENT}(?:{_INDEX})*",
    "a Sinumerik variable is a system variable ($P_TOOLNO, $A_DBB[5], $MA_JOG_VELO[X1], $P_UIFR[1,X,TR]) "
    "or a global user data name (MYDATA, GUD_ARR[2]), written without spaces",
    ("$P_TOOLNO", "$A_DBB[5]", "$MA_JOG_VELO[X1]", "$P_UIFR[1,X,TR]", "MYDATA", "GUD_ARR[2]"))
_ISG_VARIABLES = VariableNames(  # any scope but the program's own P, L and S
    rf"V\.(?![PLS]\.)[A-Z]+\.{_IDENT}(?:{_WHOLE})*(?:\.{_IDENT}(?:{_WHOLE})*)*",
    "an ISG variable the setup gives is the controller's: V.E.NAME (external), V.G.NAME (global) or "
    "another V.<scope>. name, with more .FIELD parts and whole-number indexes (V.E.SPEED, V.G.WZ[2].L, "
    "V.A.ACS.X), written without spaces; V.P., V.L. and V.S. variables are declared in the program "
    "(#VAR ... #ENDVAR)",
    ("V.E.SPEED", "V.G.WZ[2].L", "V.A.ACS.X"))
_CNC8X6_VARIABLES = VariableNames(
    "", "CNC8x6 programs read no variables; their R parameters are set in [parameters] (R4 = ...)")
_RS274NGC_VARIABLES = VariableNames(
    "", "RS274NGC programs read no [variables]: LinuxCNC's numbered parameters come from [machine] "
        "parameter_file (its .var file), and named parameters (#<_name>) are set by the program")


@dataclass(frozen=True)
class Dialect:
    """One registry entry.

    ``module``: the module or package with ``interpret(name, text, cfg) -> Program``; a name
    starting with a dot is relative to this package (``".cnc8x6"``), any other is absolute (a plug-in).
    ``diameter_programming``: on a lathe, whether X values are diameters when the setup does not
    say (``[machine] diameter_programming``); mills always program radii.
    ``extensions``: the file extensions its programs and subprograms usually have.
    ``work_offsets``: the settable work offsets a setup may give ([work_offsets]).
    ``variables``: the names a setup's [variables] may give.
    """

    module: str
    diameter_programming: bool
    extensions: tuple[str, ...]
    title: str
    work_offsets: WorkOffsets = WorkOffsets()
    variables: VariableNames = VariableNames()


DIALECTS: dict[str, Dialect] = {
    # CNC8x6 lathes program diameters; ISG and Sinumerik start in radius mode (G52 / DIAMOF) and
    # switch in the program.
    "cnc8x6": Dialect(".cnc8x6", True, (".nc",), "MEFI CNC8x6", variables=_CNC8X6_VARIABLES),
    "isg": Dialect(".isg", False, (".nc",), "Beckhoff TwinCAT CNC (ISG kernel)", variables=_ISG_VARIABLES),
    "sinumerik": Dialect(".sinumerik", False, (".mpf", ".spf", ".nc"), "Siemens Sinumerik 840D",
                         _SINUMERIK_WORK_OFFSETS, _SINUMERIK_VARIABLES),
    "rs274ngc": Dialect(".rs274ngc", False, (".ngc", ".nc", ".tap"), "RS274NGC (LinuxCNC 2.9)",
                        variables=_RS274NGC_VARIABLES),
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
    # garbage collector would walk them again and again as they grow, a large share of a long run
    enabled = gc.isenabled()
    gc.disable()
    try:
        return dialect_module(cfg.dialect).interpret(name, text, cfg)
    finally:
        if enabled:
            gc.enable()


__all__ = ["CutsimError", "Dialect", "DIALECTS", "VariableNames", "WorkOffsets", "InterpConfig", "Program", "interpret", "transcript",
           "available_dialects", "dialect_module"]
