"""Imports flow one way (docs/architecture.md "Layers and imports").

Every module of the installed package is read with ``ast`` (nothing is imported) and its imports
become edges of a graph: top-level and function-level, absolute and relative. Each package has a
rank; a module may import only from its own rank or a lower one:

    base (0) < interp (1) < kinematics (2) < stock (3) < reports (4) < cutsim API/CLI/batch (5)

The tests fail on
- an edge to a higher rank (an upward import), wherever it is written;
- an import of a cutsim module inside a function whose target imports the importer back (directly
  or through other modules): a cycle dodged by importing late. Lazy imports that close no cycle
  (the API loading a stage only when it is used) are fine;
- an import of a third-party module inside a function that is not on ``LAZY_THIRD_PARTY`` (heavy
  or optional libraries loaded only when asked); the standard library may be imported anywhere;
- a package of pyproject.toml without a rank, or an installed package that is not where
  pyproject.toml maps it.

Known exceptions go in ``KNOWN``, each with its reason; an entry that no longer occurs fails too, so
the list only shrinks.
"""
from __future__ import annotations

import ast
import importlib.util
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

RANKS = {
    "cutsim.base": 0,
    "cutsim.interp": 1,
    "cutsim.interp.core": 1,  # the dialects' packages share the interpreter's rank
    "cutsim.interp.cnc8x6": 1,
    "cutsim.interp.isg": 1,
    "cutsim.interp.rs274ngc": 1,  # a dialect as a package (docs/architecture.md, "How to add a dialect")
    "cutsim.interp.sinumerik": 1,  # a dialect's package shares the interpreter's rank
    "cutsim.kinematics": 2,
    "cutsim.stock": 3,
    "cutsim.reports": 4,
    "cutsim": 5,  # the public API, setup loader, CLI, batch runner, testing helpers
    "cutsim.setup": 5,  # the setup loader
    "cutsim.batch": 5,  # the batch runner
}

# Third-party modules that may be imported inside a function: optional or heavy libraries a run
# needs only for some outputs or checks (images, report.html, measurements, progress, the cluster).
LAZY_THIRD_PARTY = {"pyvista", "vtkmodules", "matplotlib", "trimesh", "scipy", "PIL", "jinja2", "manifold3d",
                    "numpy", "tqdm", "distributed"}

# (importer, imported) -> why it is still there. Every entry names the issue that removes it.
KNOWN: dict[tuple[str, str], str] = {
}


@dataclass(frozen=True)
class Edge:
    src: str  # importing module
    dst: str  # imported module (the module itself when a name is imported from it)
    line: int
    lazy: bool  # written inside a function

    def __str__(self) -> str:
        return f"{self.src}:{self.line} -> {self.dst}{' (inside a function)' if self.lazy else ''}"


def package_dirs(pyproject: Path = ROOT / "pyproject.toml") -> dict[str, Path]:
    """Package name -> source folder, from pyproject.toml's package-dir mapping."""
    cfg = tomllib.loads(pyproject.read_text())["tool"]["setuptools"]
    return {name: pyproject.parent / d for name, d in cfg["package-dir"].items()}


def modules(packages: dict[str, Path]) -> dict[str, tuple[Path, bool]]:
    """Module name -> (file, is a package) for every .py file of the packages (no recursion into
    folders: subpackages are mapped on their own in pyproject.toml)."""
    out = {}
    for pkg, d in packages.items():
        for f in sorted(d.glob("*.py")):
            name = pkg if f.stem == "__init__" else f"{pkg}.{f.stem}"
            out[name] = (f, f.stem == "__init__")
    return out


def _imports(tree: ast.AST):
    """(node, inside a function) for every import statement in ``tree``."""
    stack = [(tree, False)]
    while stack:
        node, lazy = stack.pop()
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                yield child, lazy
            stack.append((child, lazy or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))))


def edges(mods: dict[str, tuple[Path, bool]]) -> tuple[list[Edge], list[Edge]]:
    """(edges between cutsim modules, function-level imports of other modules). A name imported
    from a package that is one of its modules (``from . import canon``) is an edge to that module."""
    inner, outer = [], []
    for src, (path, is_pkg) in mods.items():
        package = src if is_pkg else src.rpartition(".")[0]
        for node, lazy in _imports(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                base = node.module or ""
                if node.level:
                    parts = package.split(".")
                    up = parts[:len(parts) - (node.level - 1)]
                    base = ".".join(up + ([base] if base else []))
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base for a in node.names]
            for t in dict.fromkeys(targets):
                e = Edge(src, t, node.lineno, lazy)
                if t == "cutsim" or t.startswith("cutsim."):
                    inner.append(e)
                elif lazy and t.split(".")[0] != "__future__":
                    outer.append(e)
    return inner, outer


def rank(module: str) -> int:
    pkg = max((p for p in RANKS if module == p or module.startswith(p + ".")), key=len)
    return RANKS[pkg]


def upward(inner: list[Edge]) -> list[Edge]:
    return [e for e in inner if rank(e.dst) > rank(e.src)]


def _graph(inner: list[Edge], mods) -> dict[str, set[str]]:
    """Who runs whose code on import: the edges, plus the ``__init__`` of every package entered from
    outside (importing cutsim.stock.specs runs cutsim/stock/__init__.py). The root package ``cutsim``
    runs before any of its modules, whoever imports them: an import of it (``import cutsim`` for
    ``cutsim.__version__``) orders nothing, and it is left out of the implicit edges too. Its rank
    still counts: only the API's own modules may import it."""
    g: dict[str, set[str]] = {m: set() for m in mods}
    for e in inner:
        if e.dst not in mods or e.dst == "cutsim":
            continue
        g[e.src].add(e.dst)
        parts = e.dst.split(".")
        for k in range(2, len(parts)):
            parent = ".".join(parts[:k])
            if parent in mods and not (e.src == parent or e.src.startswith(parent + ".")):
                g[e.src].add(parent)
    return g


def _reaches(g: dict[str, set[str]], a: str, b: str) -> list[str] | None:
    """A path of imports from a to b, or None."""
    prev, todo = {a: None}, [a]
    while todo:
        n = todo.pop()
        if n == b:
            path = []
            while n is not None:
                path.append(n)
                n = prev[n]
            return path[::-1]
        for m in sorted(g.get(n, ())):
            if m not in prev:
                prev[m] = n
                todo.append(m)
    return None


def cycle_dodges(inner: list[Edge], mods) -> list[tuple[Edge, list[str]]]:
    """Function-level imports of a cutsim module that imports the importer back."""
    g = _graph(inner, mods)
    out = []
    for e in inner:
        if e.lazy and e.dst in mods and e.dst != "cutsim":
            back = _reaches(g, e.dst, e.src)
            if back is not None:
                out.append((e, back))
    return out


def stray_lazy(outer: list[Edge]) -> list[Edge]:
    return [e for e in outer
            if e.dst.split(".")[0] not in LAZY_THIRD_PARTY and e.dst.split(".")[0] not in sys.stdlib_module_names]


def problems(packages: dict[str, Path], known: dict[tuple[str, str], str]) -> tuple[list[str], set]:
    """Every violation as a line of text (known exceptions left out), and the known exceptions seen."""
    mods = modules(packages)
    inner, outer = edges(mods)
    out, seen = [], set()
    for e in upward(inner):
        if (e.src, e.dst) in known:
            seen.add((e.src, e.dst))
        else:
            out.append(f"upward import (rank {rank(e.src)} -> {rank(e.dst)}): {e}")
    for e, back in cycle_dodges(inner, mods):
        if (e.src, e.dst) in known:
            seen.add((e.src, e.dst))
        else:
            out.append(f"import inside a function dodging a cycle: {e}; back: {' -> '.join(back)}")
    for e in stray_lazy(outer):
        out.append(f"third-party import inside a function not on LAZY_THIRD_PARTY: {e}")
    return out, seen


# --------------------------------------------------------------------------------------------
# the package itself


def test_every_package_has_a_rank_and_is_installed_where_pyproject_says():
    packages = package_dirs()
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert sorted(cfg["packages"]) == sorted(packages)
    assert sorted(packages) == sorted(RANKS)
    for name, d in packages.items():
        spec = importlib.util.find_spec(name)
        assert spec is not None and spec.submodule_search_locations, name
        assert Path(list(spec.submodule_search_locations)[0]).resolve() == d.resolve(), name


def test_imports_flow_one_way():
    found, _ = problems(package_dirs(), KNOWN)
    assert not found, "\n".join(found)


def test_known_exceptions_still_occur():
    """An exception that was fixed leaves the list (so it cannot hide a new edge of the same pair)."""
    _, seen = problems(package_dirs(), KNOWN)
    assert set(KNOWN) <= seen, f"no longer occurring, delete from KNOWN: {sorted(set(KNOWN) - seen)}"


def test_the_graph_sees_the_packages_edges():
    """The walker finds real edges of every kind: relative, absolute, from-a-package and lazy."""
    inner, _ = edges(modules(package_dirs()))
    pairs = {(e.src, e.dst, e.lazy) for e in inner}
    assert ("cutsim.interp.cnc8x6.interpreter", "cutsim.interp.canon", False) in pairs  # from .. import canon
    assert ("cutsim.interp.cnc8x6.interpreter", "cutsim.interp.core", False) in pairs  # from ..core import ...
    assert ("cutsim.kinematics.paths", "cutsim.base.specs", False) in pairs  # absolute
    assert ("cutsim.reports.checks", "cutsim.reports.measure", False) in pairs
    assert ("cutsim.cli", "cutsim.output", True) in pairs  # inside a function
    assert len({e.src for e in inner}) > 30


# --------------------------------------------------------------------------------------------
# the checker on fake packages


def _fake(tmp_path: Path, files: dict[str, str]) -> dict[str, Path]:
    packages = {}
    for pkg, d in (("cutsim", "api"), ("cutsim.base", "base"), ("cutsim.interp", "interp"),
                   ("cutsim.kinematics", "kinematics"), ("cutsim.stock", "stock")):
        (tmp_path / d).mkdir()
        (tmp_path / d / "__init__.py").write_text("")
        packages[pkg] = tmp_path / d
    for rel, text in files.items():
        (tmp_path / rel).write_text(text)
    return packages


def test_a_new_upward_edge_fails(tmp_path):
    packages = _fake(tmp_path, {
        "base/specs.py": "X = 1\n",
        "stock/sweep.py": "from cutsim.base.specs import X\nfrom ..interp import lexer\n",
        "interp/lexer.py": "from cutsim.base import specs\n",
        "interp/bad.py": "import math\n\ndef f():\n    from cutsim.stock.sweep import Y\n",
    })
    found, _ = problems(packages, {})
    assert found == ["upward import (rank 1 -> 3): cutsim.interp.bad:4 -> cutsim.stock.sweep (inside a function)"]
    # listed as known, it passes and is reported as seen
    found, seen = problems(packages, {("cutsim.interp.bad", "cutsim.stock.sweep"): "test"})
    assert found == [] and seen == {("cutsim.interp.bad", "cutsim.stock.sweep")}


def test_relative_upward_edge_fails(tmp_path):
    packages = _fake(tmp_path, {"base/geo.py": "from ..stock import sweep\n", "stock/sweep.py": ""})
    found, _ = problems(packages, {})
    assert found == ["upward import (rank 0 -> 3): cutsim.base.geo:1 -> cutsim.stock.sweep"]


def test_a_lazy_import_dodging_a_cycle_fails(tmp_path):
    """a imports b at the top, b imports a inside a function: same rank, but a cycle."""
    packages = _fake(tmp_path, {
        "interp/a.py": "from . import b\n",
        "interp/b.py": "def f():\n    from .a import g\n",
        "interp/c.py": "def f():\n    from . import b\n",  # lazy, but b never imports c: fine
    })
    found, _ = problems(packages, {})
    assert found == ["import inside a function dodging a cycle: cutsim.interp.b:2 -> cutsim.interp.a "
                     "(inside a function); back: cutsim.interp.a -> cutsim.interp.b"]


def test_a_cycle_through_a_package_init_counts(tmp_path):
    """Importing cutsim.stock.spec runs cutsim/stock/__init__.py, which imports cutsim.stock.tool:
    the late import in tool closes a cycle through the package's __init__ (as kinematics importing
    stock.specs did before the base layer)."""
    packages = _fake(tmp_path, {
        "stock/__init__.py": "from .tool import T\n",
        "stock/tool.py": "def f():\n    from cutsim.kinematics.k import P\n",
        "stock/spec.py": "",
        "kinematics/k.py": "from cutsim.stock.spec import S\n",
    })
    found, _ = problems(packages, {})
    assert found == ["upward import (rank 2 -> 3): cutsim.kinematics.k:1 -> cutsim.stock.spec",
                     "import inside a function dodging a cycle: cutsim.stock.tool:2 -> cutsim.kinematics.k "
                     "(inside a function); back: cutsim.kinematics.k -> cutsim.stock -> cutsim.stock.tool"]
    # the same lazy import with the spec in base closes no cycle
    (tmp_path / "base/spec.py").write_text("")
    (tmp_path / "kinematics/k.py").write_text("from cutsim.base.spec import S\n")
    assert problems(packages, {})[0] == []


def test_lazy_third_party_imports(tmp_path):
    packages = _fake(tmp_path, {
        "stock/view.py": "def f():\n    import pyvista\n    import json\n    from scipy.spatial import cKDTree\n",
        "stock/odd.py": "import requests\n\ndef f():\n    import shapely.geometry\n",
    })
    found, _ = problems(packages, {})
    assert found == ["third-party import inside a function not on LAZY_THIRD_PARTY: "
                     "cutsim.stock.odd:4 -> shapely.geometry (inside a function)"]


@pytest.mark.parametrize("module, expected", [("cutsim.base.specs", 0), ("cutsim.interp", 1), ("cutsim.setup", 5),
                                              ("cutsim.reports.measure", 4), ("cutsim", 5)])
def test_rank(module, expected):
    assert rank(module) == expected
