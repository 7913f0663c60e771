"""The output directory is one transaction (README "Using it"): a run that fails, is interrupted or
is killed leaves the previous output byte-identical; a complete run replaces cutsim's files and
removes those of an earlier run it did not write, but never a user's own files."""
from __future__ import annotations

import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from conftest import EXAMPLES
from cutsim.cli import main
from cutsim.output import MARKER, STAGING_PREFIX

LATHE = EXAMPLES / "cnc8x6-lathe"
PROG = LATHE / "multipass.nc"
SETUP = LATHE / "multipass.toml"


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def simulate(out, *extra, prog=PROG, tol="0.05"):
    res = cli("simulate", prog, "--setup", SETUP, "--out", out, "--tolerance", tol, "-q", *extra)
    assert "Traceback" not in res.output
    return res


# Runs the CLI with the material removal held: the child writes READY when it is inside the
# simulation and waits there, so a signal sent after READY lands mid-run however loaded the
# machine is (a timed sleep could land in the final commit, where signals are held back).
HOLD_IN_REMOVAL = """
import pathlib, sys, time
import cutsim.stock as stock
from cutsim.cli import main

ready, real = pathlib.Path(sys.argv[1]), stock.remove

def remove(*a, **k):
    ready.write_text("in the simulation")
    time.sleep(600)  # ended by the test's signal
    return real(*a, **k)

stock.remove = remove
main(sys.argv[2:])
"""


def spawn(out, *extra, tol="0.05", **kw):
    return subprocess.Popen([sys.executable, "-m", "cutsim", "simulate", str(PROG), "--setup", str(SETUP),
                             "--out", str(out), "--tolerance", tol, "-q", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def _as_from_a_terminal() -> None:
    # a run started from a terminal gets Ctrl-C; the test suite itself may run in the background, where
    # the shell ignores SIGINT and the child would inherit that (Python then installs no KeyboardInterrupt)
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def spawn_held(out, ready: Path):
    """A run stopped inside the simulation once ``ready`` exists (HOLD_IN_REMOVAL)."""
    return subprocess.Popen([sys.executable, "-c", HOLD_IN_REMOVAL, str(ready), "simulate", str(PROG), "--setup",
                             str(SETUP), "--out", str(out), "--tolerance", "0.05", "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_as_from_a_terminal)


def wait_held(proc, ready: Path, timeout=120.0):
    t0 = time.monotonic()
    while not ready.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() - t0 < timeout, "the run never reached the simulation"
        time.sleep(0.02)


def snapshot(d: Path) -> dict:
    """Every entry under d (hidden ones too) with its bytes: equal snapshots = byte-identical."""
    out = {}
    for p in sorted(d.rglob("*")):
        out[str(p.relative_to(d))] = p.read_bytes() if p.is_file() else "<dir>"
    return out


def staging_dirs(parent: Path) -> list[Path]:
    return [p for p in parent.iterdir() if p.name.startswith(STAGING_PREFIX)]


def marker(d: Path) -> list[str]:
    return json.loads((d / MARKER).read_text())["files"]


@pytest.fixture
def previous(tmp_path):
    """DIR holding the output of a good earlier run (STL part)."""
    out = tmp_path / "out"
    res = simulate(out)
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "part.stl", "report.json"]
    assert marker(out) == ["part.stl", "report.json"]
    return out


def test_reuse_removes_stale_cutsim_files(previous):
    first = snapshot(previous)
    res = simulate(previous, "--format", "3mf")
    assert res.exit_code == 0, res.output
    # part.stl was cutsim's and this run did not write it: gone
    assert sorted(p.name for p in previous.iterdir()) == [MARKER, "part.3mf", "report.json"]
    assert marker(previous) == ["part.3mf", "report.json"]
    assert (previous / "report.json").read_bytes() == first["report.json"]  # same input, same bytes
    assert staging_dirs(previous.parent) == []


def test_reuse_keeps_user_files(previous):
    (previous / "notes.txt").write_text("mine")
    (previous / "mine").mkdir()
    (previous / "mine" / "part.stl").write_bytes(b"user's own")
    # a file with an output's name that cutsim did not write (not in the marker) is the user's
    (previous / "report.html").write_text("<p>my report</p>")
    res = simulate(previous, "--format", "glb")
    assert res.exit_code == 0, res.output
    names = sorted(p.name for p in previous.iterdir())
    assert names == [MARKER, "mine", "notes.txt", "part.glb", "report.html", "report.json"]
    assert (previous / "notes.txt").read_text() == "mine"
    assert (previous / "mine" / "part.stl").read_bytes() == b"user's own"
    assert (previous / "report.html").read_text() == "<p>my report</p>"
    assert marker(previous) == ["part.glb", "report.json"]
    # and back to STL: part.glb goes, the user's files stay
    assert simulate(previous).exit_code == 0
    assert sorted(p.name for p in previous.iterdir()) == [MARKER, "mine", "notes.txt", "part.stl", "report.html",
                                                          "report.json"]
    assert staging_dirs(previous.parent) == []


def test_empty_existing_dir_and_new_nested_dir(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    assert simulate(empty).exit_code == 0
    assert sorted(p.name for p in empty.iterdir()) == [MARKER, "part.stl", "report.json"]
    nested = tmp_path / "a" / "b" / "c"
    assert simulate(nested).exit_code == 0
    assert sorted(p.name for p in nested.iterdir()) == [MARKER, "part.stl", "report.json"]
    assert (nested / "part.stl").read_bytes() == (empty / "part.stl").read_bytes()


def test_program_error_leaves_previous_output_byte_identical(previous, tmp_path):
    (previous / "notes.txt").write_text("mine")
    before = snapshot(previous)
    bad = tmp_path / "bad.nc"
    bad.write_text("N10 G00 X28. Z2.\nN20 G33 Z-20. F0\n")
    res = simulate(previous, prog=bad)
    assert res.exit_code == 2 and res.output.startswith(f"{bad}:2:")
    assert snapshot(previous) == before
    assert staging_dirs(tmp_path) == []


def test_report_json_directory_is_refused_before_anything_changes(previous):
    # a target that is a directory stops the run before any file, part.stl included, is replaced
    (previous / "report.json").unlink()
    (previous / "report.json").mkdir()
    before = snapshot(previous)
    res = simulate(previous, "--format", "3mf")
    assert res.exit_code == 2
    assert res.output.startswith(f"{previous / 'report.json'}:0:0: error: --out: is a directory")
    assert snapshot(previous) == before
    assert staging_dirs(previous.parent) == []


def test_write_error_at_commit_exits_2_and_keeps_previous_output(previous):
    """A file system that refuses the write (here the file size limit: EFBIG, as ENOSPC would)."""
    before = snapshot(previous)

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))  # part.stl is ~1 MB
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)

    proc = spawn(previous, tol="0.05", preexec_fn=limit)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, err
    assert err.startswith(f"{previous / 'part.stl'}:0:0: error: --out: cannot write it: File too large")
    assert "Traceback" not in err
    assert snapshot(previous) == before
    assert staging_dirs(previous.parent) == []


def test_sigkill_mid_run_leaves_previous_output_byte_identical(previous):
    (previous / "notes.txt").write_text("mine")
    before = snapshot(previous)
    ready = previous.parent / "ready"
    proc = spawn_held(previous, ready)
    wait_held(proc, ready)
    assert staging_dirs(previous.parent), "the staging directory is made before the simulation"
    proc.kill()
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    assert snapshot(previous) == before
    assert len(staging_dirs(previous.parent)) == 1  # left by the killed run, never inside DIR
    # the next run clears it and is not confused by it
    assert simulate(previous, "--format", "3mf").exit_code == 0
    assert staging_dirs(previous.parent) == []
    assert sorted(p.name for p in previous.iterdir()) == [MARKER, "notes.txt", "part.3mf", "report.json"]


KILL_AT = """
import os, signal, sys, types
import cutsim.output as o
from cutsim.cli import main

def die(*a, **k):
    os.kill(os.getpid(), signal.SIGKILL)

where = sys.argv[1]
if where == "exchange":   # every file staged and synced; the swap not yet done
    o._exchange = die
else:                     # per-file commit: the interim marker and the first file are in place
    calls = []
    def replace(a, b, _real=os.replace):
        calls.append(b)
        if len(calls) == 3:
            die()
        _real(a, b)
    o.os = types.SimpleNamespace(**{k: getattr(os, k) for k in dir(os) if not k.startswith("__")})
    o.os.replace = replace
main(sys.argv[2:])
"""


def test_sigkill_at_the_commit_of_a_cutsim_only_dir(previous):
    before = snapshot(previous)
    proc = subprocess.run([sys.executable, "-c", KILL_AT, "exchange", "simulate", str(PROG), "--setup",
                           str(SETUP), "--out", str(previous), "--tolerance", "0.05", "-q", "--format", "3mf"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    assert snapshot(previous) == before
    (stale,) = staging_dirs(previous.parent)
    assert sorted(p.name for p in stale.iterdir()) == [MARKER, "part.3mf", "report.json"]  # complete
    assert simulate(previous).exit_code == 0
    assert staging_dirs(previous.parent) == []
    assert snapshot(previous) == before  # same input, same bytes


def test_sigkill_in_a_per_file_commit_never_loses_track(previous):
    """With a user's file in DIR the files are replaced one by one: a kill between two renames
    leaves a mix of complete files, and the marker (old and new names) keeps every cutsim file
    known, so the next run ends in the clean state."""
    (previous / "notes.txt").write_text("mine")
    proc = subprocess.run([sys.executable, "-c", KILL_AT, "per-file", "simulate", str(PROG), "--setup",
                           str(SETUP), "--out", str(previous), "--tolerance", "0.05", "-q", "--format", "3mf"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    assert sorted(p.name for p in previous.iterdir()) == [MARKER, "notes.txt", "part.3mf", "part.stl",
                                                          "report.json"]
    assert marker(previous) == ["part.3mf", "part.stl", "report.json"]
    assert simulate(previous, "--format", "glb").exit_code == 0
    assert sorted(p.name for p in previous.iterdir()) == [MARKER, "notes.txt", "part.glb", "report.json"]
    assert (previous / "notes.txt").read_text() == "mine"
    assert staging_dirs(previous.parent) == []


@pytest.mark.parametrize("sig, code, word", [(signal.SIGINT, 130, "interrupted"),
                                             (signal.SIGTERM, 143, "terminated")])
def test_interrupt_mid_run_exits_cleanly(previous, sig, code, word):
    before = snapshot(previous)
    ready = previous.parent / "ready"
    proc = spawn_held(previous, ready)
    wait_held(proc, ready)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == code, err
    assert f"cutsim: {word}; nothing written" in err and "Traceback" not in err
    assert snapshot(previous) == before
    assert staging_dirs(previous.parent) == []


def _unwritable(path: Path):
    """Make ``path`` unwritable even for root (chattr +i); returns the undo, or skips."""
    if os.geteuid() != 0:
        path.chmod(0o555)
        return lambda: path.chmod(0o755)
    if subprocess.run(["chattr", "+i", str(path)], capture_output=True).returncode != 0:
        pytest.skip("running as root and chattr +i is not available here")
    return lambda: subprocess.run(["chattr", "-i", str(path)], check=True)


@pytest.mark.parametrize("where", ["dir", "parent"])
def test_unwritable_out_exits_2_before_the_simulation(tmp_path, where):
    locked = tmp_path / "locked"
    locked.mkdir()
    undo = _unwritable(locked)
    try:
        out = locked if where == "dir" else locked / "new"
        bad = tmp_path / "bad.nc"  # a program error would come first if --out were checked late
        bad.write_text("N10 G33 Z-20. F0\n")
        res = simulate(out, prog=bad)
    finally:
        undo()
    assert res.exit_code == 2
    assert res.output.startswith(f"{out}:0:0: error: --out: cannot ")
    assert list(locked.iterdir()) == []


def test_writable_dir_in_a_read_only_parent(tmp_path):
    """Staging beside DIR is impossible: cutsim stages inside DIR and replaces file by file."""
    locked = tmp_path / "locked"
    out = locked / "out"
    out.mkdir(parents=True)
    (out / "notes.txt").write_text("mine")
    undo = _unwritable(locked)
    try:
        first = simulate(out, "--format", "3mf")
        second = simulate(out)
        names = sorted(p.name for p in out.iterdir())
    finally:
        undo()
    assert first.exit_code == 0 and second.exit_code == 0, first.output + second.output
    assert names == [MARKER, "notes.txt", "part.stl", "report.json"]
    assert sorted(p.name for p in locked.iterdir()) == ["out"]


def test_bad_out_targets_exit_2_naming_the_path(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    bad = tmp_path / "bad.nc"  # --out is checked before the program is read
    bad.write_text("N10 G33 Z-20. F0\n")
    cases = {
        str(afile): f"{afile}:0:0: error: --out: not a directory (a file)",
        str(afile / "sub"): f"{afile / 'sub'}:0:0: error: --out: {afile} is not a directory",
        "/dev/null": "/dev/null:0:0: error: --out: not a directory (a character device)",
        "": "cutsim:0:0: error: --out: the output directory name is empty",
        str(tmp_path / ("x" * 300)): f"{tmp_path / ('x' * 300)}:0:0: error: --out: ",
        str(tmp_path / ("y" * 300) / "z"): f"{tmp_path / ('y' * 300) / 'z'}:0:0: error: --out: ",
        str(tmp_path / ".cutsim-tmp-abcd1234"): f"{tmp_path / '.cutsim-tmp-abcd1234'}:0:0: error: --out: names "
                                                "starting with .cutsim-tmp- are cutsim's temporary directories",
    }
    for out, message in cases.items():
        res = cli("simulate", bad, "--setup", SETUP, "--out", out, "-q")
        assert res.exit_code == 2, (out, res.output)
        assert res.output.startswith(message), (out, res.output)
        assert "Traceback" not in res.output and "Usage:" not in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "bad.nc"]
    assert afile.read_text() == "x"


def test_write_outputs_api(tmp_path):
    from cutsim.output import write_outputs

    out = tmp_path / "o"
    write_outputs(str(out), {"a.txt": b"1", "b.txt": b"2"})
    (out / "user.txt").write_text("u")
    write_outputs(str(out), {"b.txt": b"3"})
    assert {p.name: p.read_bytes() for p in out.iterdir()} == {
        MARKER: b'{\n "written_by": "cutsim",\n "files": [\n  "b.txt"\n ]\n}\n', "b.txt": b"3", "user.txt": b"u"}
    mask = os.umask(0)
    os.umask(mask)
    assert (out / "b.txt").stat().st_mode & 0o777 == 0o666 & ~mask


def test_without_renameat2_the_commit_is_per_file(tmp_path, monkeypatch):
    import cutsim.output as output

    monkeypatch.setattr(output, "_RENAMEAT2", [None])  # as off Linux or on an old kernel
    out = tmp_path / "o"
    output.write_outputs(str(out), {"a.txt": b"1", "b.txt": b"2"})
    inode = out.stat().st_ino
    output.write_outputs(str(out), {"b.txt": b"3", "c.txt": b"4"})
    assert out.stat().st_ino == inode  # the same directory, files replaced in it
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.name != MARKER} == {"b.txt": b"3", "c.txt": b"4"}
    assert marker(out) == ["b.txt", "c.txt"]
    assert staging_dirs(tmp_path) == []


def test_disk_full_at_commit_exits_2_and_keeps_previous_output(tmp_path):
    """A real ENOSPC: DIR on a 512 KiB tmpfs in a private mount namespace (root only)."""
    mnt = tmp_path / "small"
    mnt.mkdir()
    out = mnt / "out"
    run = f"{sys.executable} -m cutsim simulate {PROG} --setup {SETUP} --out {out} -q --tolerance"
    listing = f"(cd {out} && sha256sum $(ls -A | sort)); ls -A {mnt}"
    script = (f"mount -t tmpfs -o size=512k tmpfs {mnt} || exit 97\n"
              f"{run} 0.05 || exit 98\n"  # a 170 kB part: fits
              f"{listing}; echo ---\n"
              f"{run} 0.002; echo rc=$?\n"  # a 1 MB part: does not fit
              f"echo ---; {listing}")
    try:
        proc = subprocess.run(["unshare", "-m", "sh", "-c", script], capture_output=True, text=True, timeout=300)
    except FileNotFoundError:
        pytest.skip("no unshare")
    if proc.returncode in (1, 97) and "rc=" not in proc.stdout:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.strip()}")
    before, rc, after = proc.stdout.split("---\n")
    assert rc == "rc=2\n", proc.stderr
    assert proc.stderr.startswith(f"{out / 'part.stl'}:0:0: error: --out: cannot write it: No space left on device")
    assert "Traceback" not in proc.stderr
    assert after == before  # byte-identical, and no staging directory left in the mount
    assert before.split()[-1] == "out" and "part.stl" in before
