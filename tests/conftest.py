"""Test configuration: where the examples are, and skipping what needs the shared folder.

Two sets of example programs:

- ``REPO_EXAMPLES`` (``examples/`` in this repository): always there; their tests always run.
- ``EXAMPLES`` (``../shared/examples`` beside the repository, or ``$CUTSIM_SHARED/examples``): the
  controller manuals' own programs. A clone of cutsim alone has no such folder. Then every test
  that uses it is skipped, here in one place (``pytest_collection_modifyitems``): a test is
  taken to use it when it asks for the ``examples`` fixture, when one of its parameters is a path
  in the shared folder, or when its code - or the code of a fixture or module-level function it
  uses, followed through the module - reads a module global that holds such a path (``EXAMPLES``,
  ``LATHE = EXAMPLES / "cnc8x6-lathe"``, ...) or is assigned at module level from one
  (``SETUP = (LATHE / "lead-in.toml").read_text() if LATHE.is_dir() else ""``). Tests may also say it outright with
  ``@needs_shared`` (``from conftest import needs_shared``).

CI has the shared folder, so these tests always run there; set ``CUTSIM_REQUIRE_SHARED=1`` to
make a missing shared folder an error instead of a skip.
"""
from __future__ import annotations

import ast
import inspect
import os
import shutil
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
REPO_EXAMPLES = ROOT / "examples"
SHARED = Path(os.environ.get("CUTSIM_SHARED", ROOT.parent / "shared"))
EXAMPLES = SHARED / "examples"
HAVE_SHARED = EXAMPLES.is_dir()
REQUIRE_SHARED = os.environ.get("CUTSIM_REQUIRE_SHARED", "") not in ("", "0")
SKIP_REASON = f"the shared folder's examples are not at {EXAMPLES} (a clone alone; set CUTSIM_SHARED)"

needs_shared = pytest.mark.skipif(not HAVE_SHARED, reason=SKIP_REASON)
REQUIRE_TOOLS = os.environ.get("CUTSIM_REQUIRE_TOOLS", "") not in ("", "0")


def external_tool(*names: str, package: str) -> str:
    """The path of the first of ``names`` on PATH (a Debian package's program the tests run).

    Without it the test is skipped, or fails when ``CUTSIM_REQUIRE_TOOLS=1`` (CI installs them).
    """
    for name in names:
        path = shutil.which(name)
        if path:
            return path
    reason = f"no {names[0]} on PATH (apt-get install {package})"
    if REQUIRE_TOOLS:
        pytest.fail(f"CUTSIM_REQUIRE_TOOLS is set but {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="session")
def examples() -> Path:
    """The manuals' example programs (``../shared/examples``); skips the test without them."""
    if not HAVE_SHARED:
        if REQUIRE_SHARED:
            pytest.fail(SKIP_REASON)
        pytest.skip(SKIP_REASON)
    return EXAMPLES


@pytest.fixture(scope="session")
def repo_examples() -> Path:
    """The repository's own example programs (``examples/``)."""
    return REPO_EXAMPLES


def in_shared(value) -> bool:
    """Whether ``value`` is (or holds) a path inside the shared folder."""
    if isinstance(value, (Path, str)):
        try:
            return Path(value).resolve().is_relative_to(SHARED.resolve())
        except (OSError, ValueError):
            return False
    if isinstance(value, (list, tuple, set, frozenset)):
        return any(in_shared(v) for v in value)
    return False


def _codes(code: types.CodeType):
    yield code
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            yield from _codes(const)


def _reads_shared(func, module, shared_names: set[str], seen: set) -> bool:
    """Whether ``func`` reads one of ``shared_names`` from ``module``, directly or through the
    module-level functions it calls."""
    func = inspect.unwrap(getattr(func, "__func__", func))
    code = getattr(func, "__code__", None)
    if code is None or code in seen:
        return False
    seen.add(code)
    glob = vars(module)
    for c in _codes(code):
        for name in c.co_names:
            if name in shared_names:
                return True
            target = glob.get(name)
            target = getattr(target, "_get_wrapped_function", lambda: target)()  # pytest fixtures
            if (inspect.isfunction(target) and target.__module__ == module.__name__
                    and _reads_shared(target, module, shared_names, seen)):
                return True
    return False


_SHARED_NAMES: dict[str, set[str]] = {}


def shared_names(module) -> set[str]:
    """Module globals that hold a path in the shared folder, or whose module-level assignment
    reads one of those (followed to a fixed point)."""
    if module.__name__ in _SHARED_NAMES:
        return _SHARED_NAMES[module.__name__]
    names = {name for name, value in vars(module).items() if in_shared(value)}
    try:
        tree = ast.parse(inspect.getsource(module))
    except (OSError, TypeError, SyntaxError):
        tree = ast.Module(body=[], type_ignores=[])
    assigns = []
    for node in tree.body:
        if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)) and node.value is not None:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            assigns.append(({n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)},
                            {n.id for n in ast.walk(node.value) if isinstance(n, ast.Name)}))
    changed = True
    while changed:
        changed = False
        for targets, used in assigns:
            if used & names and not targets <= names:
                names |= targets
                changed = True
    _SHARED_NAMES[module.__name__] = names
    return names


def uses_shared(item) -> bool:
    """Whether a collected test needs the shared folder (see the module docstring)."""
    if "examples" in getattr(item, "fixturenames", ()):
        return True
    callspec = getattr(item, "callspec", None)
    if callspec is not None and any(in_shared(v) for v in callspec.params.values()):
        return True
    module = getattr(item, "module", None)
    if module is None:
        return False
    names = shared_names(module)
    funcs = [item.function]
    defs = getattr(getattr(item, "_fixtureinfo", None), "name2fixturedefs", {})
    for name in getattr(item, "fixturenames", ()):
        for fixdef in defs.get(name, ()):
            if fixdef.func is not None and getattr(fixdef.func, "__module__", None) == module.__name__:
                funcs.append(fixdef.func)
    seen: set = set()
    return any(_reads_shared(f, module, names, seen) for f in funcs)


def pytest_collection_modifyitems(config, items):
    if HAVE_SHARED:
        return
    needing = [item for item in items if uses_shared(item)]
    if needing and REQUIRE_SHARED:
        raise pytest.UsageError(f"CUTSIM_REQUIRE_SHARED is set but {SKIP_REASON}; "
                                f"{len(needing)} tests need it")
    for item in needing:
        item.add_marker(pytest.mark.skip(reason=SKIP_REASON))
