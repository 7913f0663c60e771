"""The setup's LinuxCNC files: the tool table (``.tbl``) and the parameter file (``.var``), in mm.

A tool table line is ``T<n> P<pocket> [X..] [Z..] [D..] ... ; comment`` (LinuxCNC's format; the
columns the simulator does not use, Y A B C U V W I J Q, are read and ignored). A parameter file
line is ``<number> <value>``.
"""
from __future__ import annotations

import re

from cutsim.interp.errors import CutsimError

_WORD = re.compile(r"([A-Za-z])\s*([+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))")
TOOL_COLUMNS = set("TPXYZABCUVWDIJQ")


def read_text(path: str) -> str:
    try:
        with open(path, encoding="utf-8") as f:
            return f.read(4_000_000)
    except (OSError, UnicodeDecodeError) as e:
        raise CutsimError(path, 0, 0, f"cannot read the file: {e}") from None


def tool_table(path: str) -> dict[int, dict[str, float]]:
    """tool number -> {"X": mm, "Z": mm, "D": mm, "Q": orientation} (columns given only)."""
    tools: dict[int, dict[str, float]] = {}
    for lineno, raw in enumerate(read_text(path).splitlines(), 1):
        body = raw.split(";", 1)[0]
        if not body.strip():
            continue
        entry: dict[str, float] = {}
        pos = 0
        for m in _WORD.finditer(body):
            if body[pos:m.start()].strip():
                raise CutsimError(path, lineno, pos + 1, f"unexpected text '{body[pos:m.start()].strip()}'")
            letter = m.group(1).upper()
            if letter not in TOOL_COLUMNS:
                raise CutsimError(path, lineno, m.start() + 1, f"unknown tool table column {letter}")
            entry[letter] = float(m.group(2))
            pos = m.end()
        if body[pos:].strip():
            raise CutsimError(path, lineno, pos + 1, f"unexpected text '{body[pos:].strip()}'")
        if "T" not in entry or entry["T"] != int(entry["T"]) or entry["T"] < 0:
            raise CutsimError(path, lineno, 1, "a tool table line starts with T and the tool number")
        number = int(entry.pop("T"))
        if number in tools:
            raise CutsimError(path, lineno, 1, f"tool {number} is listed twice")
        tools[number] = {k: v for k, v in entry.items() if k in "XZDQ"}
    return tools


def parameter_file(path: str) -> dict[int, float]:
    params: dict[int, float] = {}
    for lineno, raw in enumerate(read_text(path).splitlines(), 1):
        parts = raw.split()
        if not parts:
            continue
        if len(parts) < 2 or not parts[0].isdigit():
            raise CutsimError(path, lineno, 1, "a parameter file line is '<number> <value>'")
        try:
            params[int(parts[0])] = float(parts[1])
        except ValueError:
            raise CutsimError(path, lineno, len(raw) - len(raw.lstrip()) + len(parts[0]) + 2,
                              f"'{parts[1]}' is not a number") from None
    return params
