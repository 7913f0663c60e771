"""One job, where it runs (a local pool thread or a Dask worker): ``cutsim simulate`` in its own
process under the job's limits (docs/batch.md, "How a job runs"), its output files read back as
bytes, and in regression mode the part compared with its reference in a second limited process.
Nothing here raises: whatever goes wrong is part of the outcome.
"""
from __future__ import annotations

import json
import os
import shutil
import socket
import sys
import tempfile

from . import process
from .keys import file_sha

STDERR_KEEP = 4000  # characters of a job's stderr kept in its outcome (its end)


def run_job(payload: dict) -> dict:
    """Run one job described by ``payload`` (plain data, see _payload) where this is called and
    return its raw outcome: exit status, signal, stderr, time and the output files' bytes. Never
    raises: whatever goes wrong is part of the outcome."""
    try:
        return _run_job(payload)
    except BaseException as e:  # noqa: BLE001 - a job's failure is its result
        if isinstance(e, KeyboardInterrupt):
            raise
        return {"exit": None, "signal": None, "stderr": f"batch: {type(e).__name__}: {e}", "timed_out": False,
                "seconds": 0.0, "files": {}, "host": socket.gethostname(), "internal": True}


def _run_job(payload: dict) -> dict:
    if process.STOP.is_set():
        return {"exit": None, "signal": None, "stderr": "", "timed_out": False, "seconds": 0.0, "files": {},
                "host": socket.gethostname(), "interrupted": True}
    cmd = payload.get("command") or [sys.executable, "-m", "cutsim"]
    tmp = tempfile.mkdtemp(prefix="cutsim-batch-job-")
    try:
        out = os.path.join(tmp, "out")
        argv = list(cmd) + ["simulate", payload["program"], "--setup", payload["setup"], "--out", out]
        if payload.get("tolerance") is not None:
            argv += ["--tolerance", repr(payload["tolerance"])]
        if payload.get("images"):
            argv += ["--images"]
        argv += ["-q"]
        rc, err, timed_out, seconds = process.run_limited(argv, payload["timeout"], payload["memory"], payload.get("cwd"))
        files = {}
        marker = os.path.join(out, ".cutsim-output.json")
        if os.path.isfile(marker):
            try:
                with open(marker, "rb") as f:
                    names = json.load(f)
                names = names.get("files", names) if isinstance(names, dict) else names
                for n in names:
                    with open(os.path.join(out, n), "rb") as f:
                        files[n] = f.read()
            except (OSError, ValueError, TypeError) as e:
                err += f"\nbatch: cannot read the job's output: {e}"
                files = {}
        res = {"exit": rc if rc is None or rc >= 0 else None, "signal": -rc if rc is not None and rc < 0 else None,
               "stderr": err[-STDERR_KEEP:], "timed_out": timed_out, "seconds": round(seconds, 3),
               "files": files, "host": socket.gethostname(), "interrupted": process.STOP.is_set()}
        ref = payload.get("reference")
        part = os.path.join(out, "part.stl")
        if ref and "part.stl" in files and not process.STOP.is_set():
            res["compare"] = _compare_in_child(part, ref, payload)
        return res
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _compare_in_child(part: str, ref: str, payload: dict) -> dict:
    """Volumes of part - reference and reference - part, computed in a child process (manifold3d
    booleans) under the job's limits."""
    if file_sha(part) == file_sha(ref):
        return {"part_minus_reference": 0.0, "reference_minus_part": 0.0}
    fd, res_path = tempfile.mkstemp(prefix="cutsim-batch-cmp-", suffix=".json")
    os.close(fd)
    try:
        argv = [sys.executable, "-m", "cutsim.batch", "--compare", part, ref, res_path]
        rc, err, timed_out, _ = process.run_limited(argv, payload["timeout"], payload["memory"])
        if rc == 0:
            with open(res_path) as f:
                return json.load(f)
        return {"error": "timed out" if timed_out else (err.strip().splitlines() or [f"exit status {rc}"])[-1]}
    finally:
        os.unlink(res_path)


def compare_solids(part_path: str, ref_path: str) -> dict:
    """Volumes of part - reference and reference - part (mm^3), with manifold3d booleans."""
    from cutsim.reports.measure import load_solid

    a, b = load_solid(part_path), load_solid(ref_path)
    return {"part_minus_reference": round((a - b).volume(), 6), "reference_minus_part": round((b - a).volume(), 6)}


def compare_main(argv) -> int:
    part, ref, dest = argv
    try:
        res = compare_solids(part, ref)
    except MemoryError:
        print(f"{part}:0:0: error: out of memory", file=sys.stderr)
        return 2
    except Exception as e:  # noqa: BLE001 - one line, no traceback
        print(f"{ref}:0:0: error: cannot compare: {e}", file=sys.stderr)
        return 2
    with open(dest, "w") as f:
        json.dump(res, f)
    return 0
