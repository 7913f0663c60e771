"""The command line contract (conventions.md): exit 0/1/2, outputs, nothing written on error."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest
import trimesh
from click.testing import CliRunner

from conftest import EXAMPLES, REPO_EXAMPLES
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


# ---- errors of the command line itself: cutsim:0:0 / FILE:0:0, exit 2, never a traceback or usage text


def _no_noise(res):
    assert "Traceback" not in res.output and "Usage:" not in res.output, res.output
    assert res.output.count("\n") == 1, res.output  # one line


@pytest.mark.parametrize("args, message", [
    (["--tolerance", "abc"], "cutsim:0:0: error: --tolerance: 'abc' is not a valid float"),
    (["--tolerance", "nan"], "cutsim:0:0: error: --tolerance: nan is not between 0.0001 and 1 mm"),
    (["--format", "obj"], "cutsim:0:0: error: --format: 'obj' is not one of 'stl', '3mf', 'glb'"),
    (["--tolerance"], "cutsim:0:0: error: Option '--tolerance' requires an argument"),
    (["--bogus"], "cutsim:0:0: error: No such option '--bogus'"),
])
def test_bad_options_exit_2_in_file_line_col_form(tmp_path, args, message):
    out = tmp_path / "out"
    res = cli("simulate", LATHE / "multipass.nc", "--setup", LATHE / "multipass.toml", "--out", out, "-q", *args)
    assert res.exit_code == 2
    assert res.output.startswith(message), res.output
    _no_noise(res)
    assert list(tmp_path.iterdir()) == []


def test_missing_options_and_arguments_exit_2(tmp_path):
    res = cli("simulate", LATHE / "multipass.nc", "--out", tmp_path / "o")
    assert res.exit_code == 2 and res.output == "cutsim:0:0: error: --setup: missing (a required option)\n"
    res = cli("simulate", "--setup", LATHE / "multipass.toml", "--out", tmp_path / "o")
    assert res.exit_code == 2 and res.output == "cutsim:0:0: error: PROGRAM: missing (a required argument)\n"
    res = cli("simulate", "", "--setup", LATHE / "multipass.toml", "--out", tmp_path / "o")
    assert res.exit_code == 2 and res.output == "cutsim:0:0: error: PROGRAM: the file name is empty\n"
    res = cli("simulat")
    assert res.exit_code == 2 and res.output.startswith("cutsim:0:0: error: No such command 'simulat'")
    assert list(tmp_path.iterdir()) == []


def test_help_and_version_still_work():
    res = cli("--help")
    assert res.exit_code == 0 and "simulate" in res.output and "moves" in res.output
    res = cli("simulate", "--help")
    assert res.exit_code == 0 and res.output.startswith("Usage: cutsim simulate [OPTIONS] PROGRAM")
    assert "--tolerance" in res.output
    res = cli("--version")
    assert res.exit_code == 0 and "version" in res.output


def test_program_that_is_not_a_readable_file_exits_2(tmp_path):
    import os

    fifo = tmp_path / "pipe.nc"
    os.mkfifo(fifo)  # opening it must not wait for a writer
    big = tmp_path / "big.nc"
    with open(big, "wb") as f:
        f.truncate(64 * 1024 * 1024 + 1)  # sparse: one byte over the limit
    cases = {
        tmp_path: "cannot read the program: it is a directory",
        "/dev/zero": "cannot read the program: not a regular file",
        fifo: "cannot read the program: not a regular file",
        big: "cannot read the program: the file is larger than 64 MiB",
    }
    for prog, text in cases.items():
        for cmd in (["simulate", prog, "--out", tmp_path / "o"], ["moves", prog]):
            res = cli(*cmd, "--setup", LATHE / "multipass.toml")
            assert res.exit_code == 2, (cmd, res.output)
            assert res.output.startswith(f"{prog}:0:0: error: {text}"), res.output
            _no_noise(res)
    assert not (tmp_path / "o").exists()


def test_read_program_limit_is_inclusive(tmp_path):
    import cutsim

    exact = tmp_path / "exact.nc"
    exact.write_bytes(b"N10 G00 X1.\n".ljust(cutsim.MAX_PROGRAM_BYTES, b" "))
    assert len(cutsim.read_program(str(exact))) == cutsim.MAX_PROGRAM_BYTES


def test_moves_never_prints_a_traceback(tmp_path, monkeypatch):
    res = cli("moves", LATHE / "multipass.nc", "--setup", tmp_path)  # a setup that is a directory
    assert res.exit_code == 2 and res.output.startswith(f"{tmp_path}:0:0: error: cannot read the setup")
    _no_noise(res)
    # an unexpected exception (a bug) is exit 3 with the report-it message, for every command
    import cutsim.interp

    def boom(*a, **k):
        raise RuntimeError("boom")

    monkeypatch.setattr(cutsim.interp, "interpret", boom)
    res = cli("moves", LATHE / "multipass.nc", "--setup", LATHE / "multipass.toml")
    assert res.exit_code == 3
    assert res.output.startswith(f"{LATHE / 'multipass.nc'}:0:0: error: internal error in cutsim "
                                 "(RuntimeError: boom); please report it")
    _no_noise(res)
    monkeypatch.setattr(cutsim, "interpret", boom)
    res = cli("simulate", LATHE / "multipass.nc", "--setup", LATHE / "multipass.toml", "--out", tmp_path / "o", "-q")
    assert res.exit_code == 3 and "internal error in cutsim (RuntimeError: boom)" in res.output
    _no_noise(res)
    assert not (tmp_path / "o").exists()


def test_moves_into_a_closed_pipe_is_quiet(tmp_path):
    # `cutsim moves ... | head -1`: the reader goes away; no traceback, no "Exception ignored"
    proc = subprocess.Popen([sys.executable, "-m", "cutsim", "moves", str(LATHE / "multipass.nc"), "--setup",
                             str(LATHE / "multipass.toml")], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) in (0, 1, 141)
    assert "Traceback" not in err and "Exception" not in err, err


# ---- streams and help: results on stdout, diagnostics on stderr; every --help true to the code


def test_summary_on_stdout_warnings_on_stderr(tmp_path):
    """`cutsim simulate ... > log` keeps the summary; the warning (runout-constant's N50 rapids into
    the bar) stays on the terminal. With -q stdout is empty and the warning still shows."""
    prog = LATHE / "runout-constant.nc"
    for quiet in (False, True):
        out = tmp_path / f"out{quiet}"
        proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(prog), "--setup",
                               str(prog.with_suffix(".toml")), "--out", str(out), "--tolerance", "0.05"]
                              + (["-q"] if quiet else []), capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        rep = json.loads((out / "report.json").read_text())
        warning = f"{prog}:5:1: warning: rapid (G00) cuts the stock"
        assert warning in proc.stderr and "warning:" not in proc.stdout
        if quiet:
            assert proc.stdout == ""
        else:
            assert proc.stdout == (f"runout-constant.nc: {rep['blocks']} blocks, {rep['moves']} moves, removed "
                                   f"{rep['removed_volume']:.3f} mm^3, {len(rep['warnings'])} warning(s) -> {out}\n")
            assert "blocks" not in proc.stderr


def _help(*cmd):
    res = CliRunner().invoke(main, [*cmd, "--help"], terminal_width=200)
    assert res.exit_code == 0, res.output
    return " ".join(res.output.split())


def test_every_option_of_every_command_has_help():
    import click

    for name, cmd in main.commands.items():
        for p in cmd.params:
            if isinstance(p, click.Option) and "--help" not in p.opts:
                assert p.help and p.help.strip(), (name, p.opts)
    assert "--setup PATH Setup TOML" in _help("moves")


def test_out_help_says_what_the_code_does(tmp_path):
    """--out: other files in DIR are kept, cutsim's own files of an earlier run are removed (not
    "replaced as a whole")."""
    text = _help("simulate")
    assert "replaced as a whole" not in text and "other files in DIR are kept" in text
    assert "cutsim's files of an earlier run are replaced or removed" in text
    prog = REPO_EXAMPLES / "cnc8x6-lathe" / "m16x2.nc"
    out = tmp_path / "out"
    args = ["simulate", prog, "--setup", prog.with_suffix(".toml"), "--out", out, "--tolerance", "0.05", "-q"]
    assert cli(*args, "--format", "3mf").exit_code in (0, 1)  # 1: its checks want a finer tolerance
    (out / "notes.txt").write_text("mine")
    assert cli(*args).exit_code in (0, 1)
    assert sorted(p.name for p in out.iterdir()) == [".cutsim-output.json", "notes.txt", "part.stl", "report.json"]
