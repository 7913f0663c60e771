"""The defaults and ranges the user docs state are the code's.

The docs are read as a user reads them (the tables of docs/setup.md, every "(default N)" of a
setting anywhere in README.md and docs/), and the code is asked through the loader, as a setup
file reaches it: a setup that leaves a key out must get the documented default, and the ends of
a documented range must be accepted while the next value beyond them is refused (exit 2 at the key).
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from cutsim.interp.errors import CutsimError
from cutsim.setup import load_setup

ROOT = Path(__file__).resolve().parents[2]
DOCS = sorted((ROOT / "docs").rglob("*.md")) + [ROOT / "README.md"]
SETUP_MD = ROOT / "docs" / "setup.md"

LATHE = """[machine]
kind = "lathe"
dialect = "cnc8x6"
{machine}
[stock]
shape = "cylinder"
diameter = 40
z = [-60, 0]

[[tool]]
number = 1
kind = "{kind}"
{tool}
{simulation}
"""


def _setup(tmp_path, machine="", kind="turning", tool="", simulation=""):
    path = tmp_path / "s.toml"
    path.write_text(LATHE.format(machine=machine, kind=kind, tool=tool, simulation=simulation))
    return load_setup(str(path))


def _table(section: str) -> dict[str, list[str]]:
    """The rows of the first table under the heading ``section`` of docs/setup.md: key -> cells."""
    text = SETUP_MD.read_text(encoding="utf-8")
    start = text.index(f"## {section}\n")
    rows = {}
    for line in text[start:].splitlines()[1:]:
        if line.startswith("#"):
            break
        m = re.match(r"\| `(\w+)` \|(.*)\|\s*$", line)
        if m:
            rows[m.group(1)] = [c.strip() for c in m.group(2).split(" | ")]
    assert rows, f"no table under {section} in docs/setup.md"
    return rows


def _value(cell: str):
    """A table cell's literal: `0.002`, `1000000`, `false`, `"positive"`."""
    m = re.fullmatch(r'`("?)([^`"]*)\1`', cell.strip())
    assert m, f"not a literal default: {cell!r}"
    word = m.group(2)
    if m.group(1):
        return word
    return {"true": True, "false": False}.get(word, None) if word in ("true", "false") else float(word)


def _number(text: str) -> float:
    """A number as the docs write it: 1000000, 1,000,000 or 1 000 000."""
    return float(re.sub(r"[ ,\u202f]", "", text))


SIMULATION = ("tolerance", "fail_on_warning", "max_blocks", "max_triangles")


def test_simulation_defaults_are_the_loaders(tmp_path):
    rows = _table("`[simulation]`")
    assert set(SIMULATION) <= set(rows)
    s = _setup(tmp_path)
    for key in SIMULATION:
        assert getattr(s, key) == _value(rows[key][0]), key


def test_machine_defaults_are_the_loaders(tmp_path):
    rows = _table("`[machine]`")
    m = _setup(tmp_path).machine
    for key in ("m03", "rapid", "feed"):
        assert getattr(m, key) == _value(rows[key][1]), key


def test_tool_defaults_are_the_loaders(tmp_path):
    """The "keys (default)" column of the [[tool]] table, e.g. ``angle`` (60, ...)."""
    text = SETUP_MD.read_text(encoding="utf-8")
    for kind in ("thread", "turning"):
        row = re.search(rf'^\| `"{kind}"` \| (.*) \|$', text, re.M).group(1)
        tool = _setup(tmp_path, kind=kind).tools[0]
        stated = dict(re.findall(r"`(\w+)` \(([\d.]+)", row))
        assert stated, kind
        for key, default in stated.items():
            assert getattr(tool, key) == float(default), (kind, key)


# Documented ranges of [simulation]: (key, lowest accepted, highest accepted, step just beyond)
def _ranges():
    rows = _table("`[simulation]`")
    tol = re.search(r"([\d.]+) to ([\d.]+)", rows["tolerance"][1])
    blocks = re.search(r"from ([\d,]+) to ([\d,]+)", rows["max_blocks"][1])
    tri = re.search(r"from ([\d,]+) to ([\d,]+)", rows["max_triangles"][1])
    return [("tolerance", float(tol.group(1)), float(tol.group(2)), None),
            ("max_blocks", int(_number(blocks.group(1))), int(_number(blocks.group(2))), 1),
            ("max_triangles", int(_number(tri.group(1))), int(_number(tri.group(2))), 1)]


@pytest.mark.parametrize("key,lo,hi,step", _ranges(), ids=lambda v: str(v))
def test_simulation_ranges_are_the_loaders(tmp_path, key, lo, hi, step):
    coarse = "" if key == "tolerance" else "tolerance = 1\n"  # a stock within the fewest triangles
    for good in (lo, hi):
        assert getattr(_setup(tmp_path, simulation=f"[simulation]\n{coarse}{key} = {good}"), key) == good
    beyond = [lo * 0.99, hi * 1.01] if step is None else [lo - step, hi + step]
    for bad in beyond:
        with pytest.raises(CutsimError) as err:
            _setup(tmp_path, simulation=f"[simulation]\n{coarse}{key} = {bad}")
        assert key in str(err.value) and err.value.line > 0


# Every "(default N)" a doc gives a [simulation] setting, in any file: "`[simulation] max_blocks`
# (default 1 000 000)", "max_blocks` (1,000,000)", "the default tolerance 0.002".
# (a bare `tolerance` is also a [[check]] key: only "[simulation] tolerance" counts for it)
MENTION = re.compile(r"(?:\[simulation\] )?(max_blocks|max_triangles|(?<=\[simulation\] )tolerance)`?\s*"
                     r"\((?:default\s+)?(\d[\d ,.\u202f]*)\)")
DEFAULT_TOLERANCE = re.compile(r"default (?:chordal )?tolerance (?:of )?([\d.]+)")


def test_every_stated_default_in_the_docs_is_the_codes(tmp_path):
    s = _setup(tmp_path)
    seen = 0
    for doc in DOCS:
        text = doc.read_text(encoding="utf-8")
        for m in MENTION.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            assert _number(m.group(2).rstrip(".")) == getattr(s, m.group(1)), f"{doc.name}:{line}: {m.group(0)}"
            seen += 1
        for m in DEFAULT_TOLERANCE.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            assert float(m.group(1).rstrip(".")) == s.tolerance, f"{doc.name}:{line}: {m.group(0)}"
            seen += 1
    assert seen >= 4  # the dialect docs and milling.md state max_blocks, milling.md the tolerance
