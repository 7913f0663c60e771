"""Interpreter: program text -> canonical records (see interp/canon.py).

Dialects register here by name; each is a module with ``interpret(name, text, cfg)``.
"""
from __future__ import annotations

from importlib import import_module

from .canon import Program, transcript
from .errors import CutsimError
from .modal import InterpConfig

DIALECTS = {"cnc8x6": "cnc8x6", "isg": "isg", "sinumerik": "sinumerik"}


def available_dialects() -> list[str]:
    out = []
    for name, mod in DIALECTS.items():
        try:
            import_module(f"{__name__}.{mod}")
        except ModuleNotFoundError:
            continue
        out.append(name)
    return out


def interpret(name: str, text: str, cfg: InterpConfig) -> Program:
    """Interpret a whole program. Raises CutsimError with the file, line and column on bad input."""
    if cfg.dialect not in DIALECTS:
        raise CutsimError(name, 0, 0, f"unknown dialect '{cfg.dialect}'")
    try:
        mod = import_module(f"{__name__}.{DIALECTS[cfg.dialect]}")
    except ModuleNotFoundError:
        raise CutsimError(name, 0, 0, f"the {cfg.dialect} dialect is not implemented yet") from None
    return mod.interpret(name, text, cfg)


__all__ = ["CutsimError", "InterpConfig", "Program", "interpret", "transcript", "available_dialects"]
