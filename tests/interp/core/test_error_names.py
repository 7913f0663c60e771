"""File names with a newline or a tab in them: every error and warning is still one
``FILE:LINE:COL`` line, the name's control characters escaped as Python's repr escapes them."""
import subprocess
import sys

import pytest

from conftest import REPO_EXAMPLES
from cutsim.interp.errors import CutsimError, location, printable

# the shipped mill helix's setup without its checks
SETUP = (REPO_EXAMPLES / "cnc8x6-mill" / "helix-groove.toml").read_text().split("[[check]]")[0]
PROG = "bad\nname\t.nc"
SET = "set\tup\n.toml"


def _run(tmp_path, program: str, setup: str = SETUP, out: str = "out"):
    (tmp_path / PROG).write_text(program)
    (tmp_path / SET).write_text(setup)
    return subprocess.run([sys.executable, "-m", "cutsim", "simulate", PROG, "--setup", SET, "--out", out, "-q"],
                          capture_output=True, text=True, cwd=tmp_path)


def test_printable_escapes_control_characters_only():
    assert printable("a\nb\tc\x1bd\u2028e\udcff") == "a\\nb\\tc\\x1bd\\u2028e\\udcff"
    assert printable("plain name é 1\xa0mm.nc") == "plain name é 1\xa0mm.nc"
    assert location("x\ny", 3, 4) == "x\\ny:3:4"
    assert str(CutsimError("p\n.nc", 1, 2, "one\ntwo")) == "p\\n.nc:1:2: error: one\\ntwo"


def test_program_error_is_one_line(tmp_path):
    proc = _run(tmp_path, "N10 G00 X35. Y40. Z2.\nN20 G77\n")
    assert proc.returncode == 2
    assert proc.stderr.splitlines() == ["bad\\nname\\t.nc:2:5: error: unknown G code G77"]
    assert not (tmp_path / "out").exists()


def test_setup_error_is_one_line(tmp_path):
    proc = _run(tmp_path, "N10 G00 X35. Y40. Z2.\n", setup="[machine\n")
    assert proc.returncode == 2
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("set\\tup\\n.toml:1:") and ": error: " in lines[0]


@pytest.mark.parametrize("out", ["afile\n/x", "afile\n"])
def test_output_error_is_one_line(tmp_path, out):
    (tmp_path / "afile\n").write_text("a file, not a directory")
    proc = _run(tmp_path, "N10 G00 X35. Y40. Z2.\n", out=out)
    assert proc.returncode == 2
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(printable(out) + ":0:0: error: "), lines


def test_warnings_are_one_line_each(tmp_path):
    proc = _run(tmp_path, "N10 G00 X35. Y40. Z2.\nN20 G01 Z1.\nN30 X40.\n")
    assert proc.returncode == 0
    lines = proc.stderr.splitlines()
    assert lines and all(line.startswith("bad\\nname\\t.nc:2:1: warning: ") for line in lines), lines
