"""The command line contract (conventions.md): exit 0/1/2, outputs, nothing written on error."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest
import trimesh
from click.testing import CliRunner

from conftest import EXAMPLES
from cutsim.cli import main

LATHE = EXAMPLES / "cnc8x6-lathe"


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_simulate_writes_closed_stl_and_report(tmp_path):
    prog = LATHE / "multipass.nc"
    out = tmp_path / "out"
    # the installed entry point, as a user runs it
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(prog), "--setup",
                           str(prog.with_suffix(".toml")), "--out", str(out), "--tolerance", "0.02", "-q"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    mesh = trimesh.load(out / "part.stl", force="mesh")
    assert mesh.is_watertight and mesh.is_volume
    rep = json.loads((out / "report.json").read_text())
    assert rep["program"] == "multipass.nc" and rep["dialect"] == "cnc8x6"
    assert rep["moves"] == 11  # 8 rapids and 3 G33 passes
    assert rep["removed_volume"] == pytest.approx(rep["stock_volume"] - rep["part_volume"], rel=1e-9)
    assert mesh.volume == pytest.approx(rep["part_volume"], rel=1e-5)
    assert rep["warnings"] == []


def test_tolerance_option_refines_the_mesh(tmp_path):
    prog = LATHE / "multipass.nc"
    tris = {}
    for tol in (0.05, 0.01):
        out = tmp_path / f"t{tol}"
        res = cli("simulate", prog, "--setup", prog.with_suffix(".toml"), "--out", out, "--tolerance", tol, "-q")
        assert res.exit_code == 0, res.output
        tris[tol] = len(trimesh.load(out / "part.stl", force="mesh").faces)
    assert tris[0.01] > 2 * tris[0.05]


@pytest.mark.parametrize("tol", ["0", "-0.01", "2"])
def test_bad_tolerance_option_exits_2(tmp_path, tol):
    prog = LATHE / "multipass.nc"
    out = tmp_path / "out"
    res = cli("simulate", prog, "--setup", prog.with_suffix(".toml"), "--out", out, "--tolerance", tol, "-q")
    assert res.exit_code == 2
    assert "error: --tolerance" in res.output
    assert not out.exists()


def test_program_error_writes_nothing_even_into_an_existing_dir(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text("N10 G00 X28. Z2.\nN20 G33 Z-20. F0\n")
    out = tmp_path / "out"
    out.mkdir()
    res = cli("simulate", bad, "--setup", LATHE / "multipass.toml", "--out", out, "-q")
    assert res.exit_code == 2
    assert res.output.startswith(f"{bad}:2:15: error: ")
    assert list(out.iterdir()) == []


def test_missing_program_exits_2(tmp_path):
    res = cli("simulate", tmp_path / "nope.nc", "--setup", LATHE / "multipass.toml", "--out", tmp_path / "o", "-q")
    assert res.exit_code == 2
    assert "nope.nc:0:0: error: cannot read the program" in res.output


def test_setup_error_names_table_key_and_line(tmp_path):
    setup = tmp_path / "s.toml"
    text = (LATHE / "multipass.toml").read_text().replace('angle = 60.0', 'angle = 60.0\nangel = 55.0')
    setup.write_text(text)
    line = text.splitlines().index("angel = 55.0") + 1
    res = cli("simulate", LATHE / "multipass.nc", "--setup", setup, "--out", tmp_path / "o", "-q")
    assert res.exit_code == 2
    assert res.output.startswith(f"{setup}:{line}:1: error: ")
    assert "[[tool]]" in res.output and "angel" in res.output
    assert not (tmp_path / "o").exists()


def test_warning_escalated_exits_1_and_still_writes(tmp_path):
    # runout-constant's N50 rapids into the bar (a warning); fail_on_warning turns it into exit 1
    src = LATHE / "runout-constant.toml"
    setup = tmp_path / "runout-constant.toml"
    setup.write_text(src.read_text() + "\n[simulation]\nfail_on_warning = true\n")
    prog = tmp_path / "runout-constant.nc"
    shutil.copy(LATHE / "runout-constant.nc", prog)
    out = tmp_path / "out"
    res = cli("simulate", prog, "--setup", setup, "--out", out, "--tolerance", "0.05", "-q")
    assert res.exit_code == 1
    assert f"{prog}:5:1: warning: rapid (G00) cuts the stock" in res.output
    assert (out / "part.stl").exists() and (out / "report.json").exists()


def test_moves_command_and_its_errors(tmp_path):
    res = cli("moves", LATHE / "large-lead.nc", "--setup", LATHE / "large-lead.toml")
    assert res.exit_code == 0
    assert "SYNC (50 0 -60) -> (50 0 200) LEAD 250 START 0 DIAM" in res.output
    bad = tmp_path / "bad.nc"
    bad.write_text("N10 R80=1.0\n")
    res = cli("moves", bad, "--setup", LATHE / "large-lead.toml")
    assert res.exit_code == 2 and res.output.startswith(f"{bad}:1:5: error: R80 is reserved")
