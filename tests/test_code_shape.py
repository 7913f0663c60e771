"""The code stays readable: no function over 80 lines, no class over 400, no module over 700
(docs/architecture.md). A long function was a dialect or a sweep strategy that wanted to be a table
row or a hook; a long class or module holds several jobs that want to be modules of a package.

``CHECKED`` lists the folders held to all three limits, subpackages included; add a folder there
once it is split. ``FUNCTIONS_ONLY`` lists the files held to the function limit until then.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LIMIT = 80  # lines of a function or method
CLASS_LIMIT = 400  # lines of a class
MODULE_LIMIT = 700  # lines of a module

CHECKED = ["cutsim", "interp/core", "interp/cnc8x6", "interp/isg", "interp/rs274ngc", "interp/sinumerik", "stock",
           "reports"]  # folders (relative to the repository) under all three limits
FUNCTIONS_ONLY = sorted((ROOT / "interp").glob("*.py"))


def _files(folders: list[str]) -> list[Path]:
    return sorted(p for d in folders for p in (ROOT / d).rglob("*.py") if "__pycache__" not in p.parts)


FILES = sorted(set(_files(CHECKED)) | set(FUNCTIONS_ONLY))


def _long(source: str, kinds, limit: int) -> list[tuple[str, int]]:
    return [(n.name, n.end_lineno - n.lineno + 1) for n in ast.walk(ast.parse(source))
            if isinstance(n, kinds) and n.end_lineno - n.lineno + 1 > limit]


def long_functions(source: str, limit: int = LIMIT) -> list[tuple[str, int]]:
    """(name, lines) of every function or method whose def-to-last-line span exceeds ``limit``."""
    return _long(source, (ast.FunctionDef, ast.AsyncFunctionDef), limit)


def long_classes(source: str, limit: int = CLASS_LIMIT) -> list[tuple[str, int]]:
    """(name, lines) of every class whose class-to-last-line span exceeds ``limit``."""
    return _long(source, ast.ClassDef, limit)


def _id(p: Path) -> str:
    return str(p.relative_to(ROOT))


@pytest.mark.parametrize("path", FILES, ids=_id)
def test_no_function_over_80_lines(path):
    assert long_functions(path.read_text(encoding="utf-8")) == []


@pytest.mark.parametrize("path", _files(CHECKED), ids=_id)
def test_no_class_over_400_lines(path):
    assert long_classes(path.read_text(encoding="utf-8")) == []


@pytest.mark.parametrize("path", _files(CHECKED), ids=_id)
def test_no_module_over_700_lines(path):
    assert len(path.read_text(encoding="utf-8").splitlines()) <= MODULE_LIMIT


def test_the_check_sees_a_long_function_and_class():
    body = "\n".join(f"    x{i} = {i}" for i in range(LIMIT))  # def line + 80 body lines = 81
    assert long_functions(f"def f():\n{body}\n") == [("f", LIMIT + 1)]
    assert long_functions(f"def f():\n{body}\n", limit=LIMIT + 1) == []
    body = "\n".join(f"    x{i} = {i}" for i in range(CLASS_LIMIT))
    assert long_classes(f"class C:\n{body}\n") == [("C", CLASS_LIMIT + 1)]
    assert long_classes(f"class C:\n{body}\n", limit=CLASS_LIMIT + 1) == []


def test_the_checked_folders_hold_the_split_packages():
    files = {_id(p) for p in _files(CHECKED)}
    assert {"cutsim/batch/run.py", "cutsim/setup/loader.py", "cutsim/cli.py"} <= files
    assert {"interp/sinumerik/interpreter.py", "interp/sinumerik/reader.py", "interp/sinumerik/machine.py"} <= files
    assert {"interp/core/executor.py", "interp/cnc8x6/interpreter.py", "interp/isg/interpreter.py"} <= files
    assert {"stock/removal.py", "stock/strategy.py", "stock/budget.py", "stock/collisions.py", "stock/mill_checks.py",
            "reports/measure.py"} <= files
