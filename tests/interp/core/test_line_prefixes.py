"""Every prefix of every line of the repository's ISG, Sinumerik and CNC8x6 programs, run alone as a
program: the interpreter either accepts it or stops with a CutsimError whose place lies on that line
(column 1 to one past its end) — never another exception and never a column beyond the text.

A line cut short is what an editor leaves behind and what half-typed programs look like; it found
readers that took the end of the line ("", which ``in "Pp"`` calls a P) for a sign, a P or an L
and ran past the text (fuzz 20261124/4700: ``N130 G01 X[`` at the end of a file was reported at
column 49 of a 16-character line). Errors inside a subprogram file the line calls name that file
and are not checked here.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from cutsim.interp import CutsimError, InterpConfig, interpret

ROOT = Path(__file__).resolve().parents[3]
GLOBS = {
    "isg": ["tests/**/*.nc", "examples/isg*/*.nc"],
    "sinumerik": ["tests/**/*.mpf", "tests/**/*.spf", "examples/sinumerik/*.mpf"],
    "cnc8x6": ["tests/data/bad/cnc8x6/*.nc", "tests/data/programs/mill/*.nc", "examples/cnc8x6*/*.nc"],
}
LINES_PER_FILE = 80


def _lines(dialect: str) -> list[tuple[Path, str]]:
    out, seen = [], set()
    for pattern in GLOBS[dialect]:
        for path in sorted(ROOT.glob(pattern)):
            if dialect == "isg" and "isg" not in str(path.relative_to(ROOT)):
                continue
            for line in path.read_text(encoding="utf-8", errors="replace").splitlines()[:LINES_PER_FILE]:
                if line not in seen:
                    seen.add(line)
                    out.append((path.parent, line))
    return out


@pytest.mark.parametrize("dialect", sorted(GLOBS))
def test_every_line_prefix_is_accepted_or_an_error_on_its_line(dialect):
    lines = _lines(dialect)
    assert len(lines) > 50, "the programs this test reads are missing"
    checked, wrong = 0, []
    for folder, line in lines:
        for k in range(1, len(line) + 1):
            text = line[:k]
            for kind in ("mill", "lathe"):
                cfg = InterpConfig(dialect=dialect, machine_kind=kind, diameter_programming=kind == "lathe",
                                   start=(40.0, 0.0, 5.0), max_blocks=20_000, tool_radii={1: 3.0, 2: 2.0},
                                   axes={"A": "rotary"}, m_functions=frozenset({20}))
                name = str(folder / "prefix.prg")
                checked += 1
                try:
                    interpret(name, text + "\n", cfg)
                except CutsimError as e:
                    if e.program == name and not (e.line == 1 and 1 <= e.col <= len(text) + 1):
                        wrong.append(f"{text!r} ({kind}): {e}")
                except Exception as e:  # noqa: BLE001 - the point of the test
                    wrong.append(f"{text!r} ({kind}): {type(e).__name__}: {e}")
    assert checked > 1000
    assert wrong == [], "\n".join(wrong[:20])
