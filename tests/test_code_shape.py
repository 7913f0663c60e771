"""Issue 11: the interpreter and the removal stage stay readable — no function in interp/ or
stock/removal.py longer than 80 lines (a long function there was a dialect or a sweep strategy
that wanted to be a table row or a hook)."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LIMIT = 80
FILES = sorted((ROOT / "interp").glob("*.py")) + [ROOT / "stock" / "removal.py"]


def long_functions(source: str, limit: int = LIMIT) -> list[tuple[str, int]]:
    """(name, lines) of every function or method whose def-to-last-line span exceeds ``limit``."""
    return [(n.name, n.end_lineno - n.lineno + 1) for n in ast.walk(ast.parse(source))
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.end_lineno - n.lineno + 1 > limit]


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_function_over_80_lines(path):
    assert long_functions(path.read_text(encoding="utf-8")) == []


def test_the_check_sees_a_long_function():
    body = "\n".join(f"    x{i} = {i}" for i in range(LIMIT))  # def line + 80 body lines = 81
    assert long_functions(f"def f():\n{body}\n") == [("f", LIMIT + 1)]
    assert long_functions(f"def f():\n{body}\n", limit=LIMIT + 1) == []
