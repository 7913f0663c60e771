"""report.json (build_report, report_bytes: strict JSON) and the warning text. The part file's
mesh and bytes are made in mesh.py (mesh_arrays here returns its closed mesh; part_bytes and the
per-format writers are re-exported); writing the files is output.py."""
from __future__ import annotations

import json
import math

from cutsim.interp.errors import location, printable
from .mesh import closed_mesh, part_bytes, stl_bytes, threemf_bytes  # noqa: F401 - the exporters live in mesh.py


def _round(v: float, nd: int = 6) -> float:
    r = round(float(v), nd)
    return 0.0 if r == 0 else r


def build_report(*, program: str, dialect: str, machine, blocks: int, moves: int, stock_volume: float,
                 part_volume: float, cycle_time: float, warnings: list, final_position, tolerance: float,
                 triangles: int, checks: list | None = None, last_cut_position=None) -> dict:
    """The report.json dict (fields documented in docs/setup.md, "report.json")."""
    return {
        "program": program,
        "dialect": dialect,
        "machine": {"kind": machine.kind, "diameter_programming": machine.diameter_programming, "m03": machine.m03},
        "tolerance": tolerance,
        "blocks": blocks,
        "moves": moves,
        "stock_volume": _round(stock_volume),
        "part_volume": _round(part_volume),
        "removed_volume": _round(stock_volume - part_volume),
        "cycle_time_s": _round(cycle_time, 3),
        "final_position": [_round(v) for v in final_position],
        "last_cut_position": None if last_cut_position is None else [_round(v) for v in last_cut_position],
        "triangles": triangles,
        "warnings": [_warning(src, msg) for src, msg in warnings],
        "checks": checks or [],
    }


def _warning(src, message: str) -> dict:
    """One warning record. For a line of a subprogram body ``called_from`` lists the call sites'
    lines, the direct caller first, and ``called_from_programs`` their files when one is not the
    warning's own file (a Sinumerik NAME.spf called from the main program)."""
    w = {"line": src.line, "column": src.col, "program": src.program, "message": message}
    if src.calls:
        sites = list(reversed(src.calls))
        w["called_from"] = [line for _program, line in sites]
        if any(program != src.program for program, _line in sites):
            w["called_from_programs"] = [program for program, _line in sites]
    return w


def called_from(w: dict) -> str:
    """' (called from P:40, from P:12)' for a warning record from a subprogram body, else ''."""
    lines = w.get("called_from") or []
    if not lines:
        return ""
    programs = w.get("called_from_programs") or [w["program"]] * len(lines)
    return " (called from " + ", from ".join(f"{printable(p)}:{line}" for p, line in zip(programs, lines)) + ")"


def warning_text(w: dict) -> str:
    """A warning record as the CLI prints it: ``PROGRAM:LINE:COL: warning: TEXT (called from ...)``."""
    return f"{location(w['program'], w['line'], w['column'])}: warning: {printable(w['message'])}{called_from(w)}"


def mesh_arrays(part):
    """Vertices (float64, mm) and faces of the part as written: the mesh closed by position
    (reports/mesh.py closed_mesh)."""
    m = closed_mesh(part)
    return m.vertices, m.faces


def report_bytes(report: dict) -> bytes:
    """report.json: strict JSON (RFC 8259). A NaN or infinity anywhere in the report is a bug in
    cutsim and raises ValueError naming the field; it is never written."""
    bad = _non_finite(report, "")
    if bad is not None:
        raise ValueError(f"report.json field {bad} is not a finite number")
    return (json.dumps(report, indent=2, ensure_ascii=False, sort_keys=False, allow_nan=False) + "\n").encode("utf-8")


def _non_finite(value, path: str) -> str | None:
    """The path (``checks[0].measured``) of the first NaN or infinity in ``value``, else None."""
    if isinstance(value, float):
        return None if math.isfinite(value) else (path or "(top level)")
    if isinstance(value, dict):
        items = ((f"{path}.{k}" if path else str(k), v) for k, v in value.items())
    elif isinstance(value, (list, tuple)):
        items = ((f"{path}[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for p, v in items:
        bad = _non_finite(v, p)
        if bad is not None:
            return bad
    return None
