"""``cutsim batch``: verify many part programs at once, on a local pool or on a Dask cluster.

Each job runs the public command ``python3 -m cutsim simulate PROGRAM --setup S --out TMP
[--tolerance T] [--images] -q`` in its own process with a time limit and an address-space limit
(RLIMIT_AS); a crash, a time-out or an out-of-memory is that job's result. The job writes into a
private temporary directory where it runs; its files come back to the caller, which commits them
into ``DIR/<job>/`` with cutsim's own output transaction -- so the results are the same bytes
whichever scheduler ran the jobs, and a Dask worker needs no write access to DIR.

Scheduling, retries after a lost worker and transport are Dask's (``dask.distributed.Client``);
without a scheduler the jobs run on a local pool of ``--jobs`` slots (threads, each supervising
one job process). The user docs are docs/batch.md.

Outputs: ``DIR/<job>/`` (as ``cutsim simulate`` writes it), ``DIR/summary.json`` (deterministic:
no times, no host names), ``DIR/timings.json``, ``DIR/junit.xml``, ``DIR/index.html`` and
``DIR/.cutsim-batch/<job>.json`` (one record per finished job, for ``--resume``).
"""
from __future__ import annotations

import csv
import hashlib
import html
import io
import json
import math
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import tomllib
import types
import uuid
from dataclasses import asdict, dataclass, field
from xml.sax.saxutils import escape as _xml_escape

import click

from cutsim.interp import DIALECTS
from cutsim.interp.errors import CutsimError
from cutsim.setup import MIN_TOLERANCE, huge_number_at

DEFAULT_TIMEOUT = 1800.0  # s per job
DEFAULT_MEMORY = 4096  # MiB of address space per job
DEFAULT_REFERENCE_TOL = 0.01  # mm^3 of symmetric difference
RECORDS = ".cutsim-batch"
RESERVED = {"summary.json", "timings.json", "junit.xml", "index.html"}
_NAME_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9._+-]*\Z")
_STDERR_KEEP = 4000
# job statuses: the first two are simulated results (kept by --resume), the rest are errors
PASSED, FAILED = "passed", "failed"
ERROR_STATUSES = ("error", "timeout", "memory", "crashed", "interrupted", "lost")
SIMULATED_EXITS = (0, 1)
_JOB_KEYS = {"name", "program", "setup", "tolerance", "timeout", "memory", "images", "expect"}
_EXPECT_KEYS = {"exit", "removed_volume", "removed_volume_tol", "reference", "reference_tol", "report"}
_DEFAULT_KEYS = {"tolerance", "timeout", "memory", "images", "expect"}
ENV_COMMAND = "CUTSIM_BATCH_COMMAND"  # testing hook: replaces ``python3 -m cutsim`` (shlex words)


# --------------------------------------------------------------------------------------------
# jobs and manifests


@dataclass
class Job:
    """One program to verify. Paths are used as given (relative ones from the current directory)."""

    name: str
    program: str
    setup: str
    tolerance: float | None = None
    timeout: float | None = None  # s; None: the batch default
    memory: int | None = None  # MiB of address space; None: the batch default; 0: no limit
    images: bool | None = None
    expect: dict = field(default_factory=dict)  # exit, removed_volume(_tol), reference(_tol), report


def _err(path, line, col, text):
    return CutsimError(str(path), line, col, text)


def load_manifest(path: str) -> list[Job]:
    """The jobs of a manifest: a TOML file, a CSV file or a folder of PROGRAM + PROGRAM.toml pairs.
    Every error is a CutsimError ``MANIFEST:LINE:COL``."""
    if os.path.isdir(path):
        return _folder_jobs(path)
    try:
        with open(path, "rb") as f:
            raw = f.read(64 << 20)
    except OSError as e:
        raise _err(path, 0, 0, f"cannot read the manifest: {e.strerror}") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise _err(path, 0, 0, "the manifest is not UTF-8 text") from None
    if path.lower().endswith(".csv"):
        return _csv_jobs(path, text)
    return _toml_jobs(path, text)


def _folder_jobs(folder: str) -> list[Job]:
    """PROGRAM with PROGRAM.toml (or NAME.ext with NAME.toml) anywhere under ``folder``; the job
    name is the relative path without the extension, '/' replaced by '-' (examples/sinumerik/
    plate.mpf -> ``sinumerik-plate`` when the folder is examples/)."""
    jobs = []
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        names = set(files)
        for f in sorted(files):
            if f.startswith(".") or f.lower().endswith(".toml"):
                continue
            stem = os.path.splitext(f)[0]
            setup = f + ".toml" if f + ".toml" in names else stem + ".toml" if stem + ".toml" in names else None
            if setup is None:
                continue
            rel = os.path.relpath(os.path.join(root, stem), folder)
            name = rel.replace(os.sep, "-")
            jobs.append(Job(name=name, program=os.path.join(root, f), setup=os.path.join(root, setup)))
    if not jobs:
        raise _err(folder, 0, 0, "no PROGRAM + PROGRAM.toml pairs in this folder")
    _check_names(folder, jobs, {})
    return jobs


def _check_names(manifest, jobs, where):
    seen = {}
    for i, j in enumerate(jobs):
        line, col = where.get(i, (0, 0))
        if not _NAME_RE.match(j.name) or j.name in RESERVED:
            raise _err(manifest, line, col, f"job name {j.name!r}: use letters, digits, '.', '_', '+', '-' "
                       f"(not starting with '.' and not {', '.join(sorted(RESERVED))})")
        if j.name in seen:
            raise _err(manifest, line, col, f"job name {j.name!r} is used twice (also job #{seen[j.name] + 1})")
        seen[j.name] = i


def _positions(text):
    try:
        from cutsim.setup import _key_positions

        return _key_positions(text)
    except Exception:  # noqa: BLE001 - a position is a courtesy
        return {}


def _toml_jobs(path: str, text: str) -> list[Job]:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(e))
        msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(e)) or "not TOML"
        raise _err(path, int(m.group(1)) if m else 0, int(m.group(2)) if m else 0, msg) from None
    except ValueError:  # a number with more digits than Python converts (not a TOMLDecodeError)
        raise _err(path, *huge_number_at(text), "a number with too many digits") from None
    pos = _positions(text)
    base = os.path.dirname(path)

    def at(*keys):
        k = tuple(keys)
        while k:
            if k in pos:
                return pos[k]
            k = k[:-1]
        return (1, 1)

    def fail(keys, msg):
        return _err(path, *at(*keys), msg)

    for top in data:
        if top not in ("defaults", "job"):
            raise fail((top,), f"unknown table or key {top!r} (a manifest has [defaults] and [[job]])")
    defaults = data.get("defaults", {})
    if not isinstance(defaults, dict):
        raise fail(("defaults",), "[defaults] must be a table")
    for k in defaults:
        if k not in _DEFAULT_KEYS:
            raise fail(("defaults", k), f"[defaults] {k}: unknown key (one of {', '.join(sorted(_DEFAULT_KEYS))})")
    raw_jobs = data.get("job", [])
    if not isinstance(raw_jobs, list) or not all(isinstance(t, dict) for t in raw_jobs):
        raise fail(("job",), "jobs are written [[job]] (an array of tables)")
    if not raw_jobs:
        raise _err(path, 1, 1, "the manifest has no [[job]]")
    d = _options(defaults, lambda k, m: fail(("defaults",) + k, f"[defaults] {m}"), base)
    jobs, where = [], {}
    for i, t in enumerate(raw_jobs):
        def jfail(k, m, i=i):
            return fail(("job", i) + k, f"[[job]] #{i + 1} {m}")

        for k in t:
            if k not in _JOB_KEYS:
                raise jfail((k,), f"{k}: unknown key (one of {', '.join(sorted(_JOB_KEYS))})")
        if "program" not in t:
            raise jfail((), "program: missing (the part program's path)")
        if not isinstance(t["program"], str) or not t["program"]:
            raise jfail(("program",), "program: a path is expected")
        prog = os.path.join(base, t["program"])
        if "setup" in t:
            if not isinstance(t["setup"], str) or not t["setup"]:
                raise jfail(("setup",), "setup: a path is expected")
            setup = os.path.join(base, t["setup"])
        else:
            setup = os.path.splitext(prog)[0] + ".toml"
        name = t.get("name", os.path.splitext(os.path.basename(t["program"]))[0])
        if not isinstance(name, str):
            raise jfail(("name",), "name: a string is expected")
        o = _options(t, jfail, base)
        expect = dict(d.get("expect", {}))
        expect.update(o.get("expect", {}))
        job = Job(name=name, program=prog, setup=setup, tolerance=o.get("tolerance", d.get("tolerance")),
                  timeout=o.get("timeout", d.get("timeout")), memory=o.get("memory", d.get("memory")),
                  images=o.get("images", d.get("images")), expect=expect)
        where[i] = at("job", i, "name") if "name" in t else at("job", i)
        jobs.append(job)
    _check_names(path, jobs, where)
    return jobs


def _options(t: dict, fail, base: str) -> dict:
    """tolerance/timeout/memory/images/expect of a [[job]] or [defaults] table, checked."""
    o = {}
    if "tolerance" in t:
        v = t["tolerance"]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (MIN_TOLERANCE <= v <= 1.0):
            raise fail(("tolerance",), f"tolerance: {v!r} is not a number between 0.0001 and 1 mm")
        o["tolerance"] = float(v)
    if "timeout" in t:
        v = t["timeout"]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0 < v < 1e7):
            raise fail(("timeout",), f"timeout: {v!r} is not a positive number of seconds")
        o["timeout"] = float(v)
    if "memory" in t:
        v = t["memory"]
        if isinstance(v, bool) or not isinstance(v, int) or not (0 <= v < 1 << 40):
            raise fail(("memory",), f"memory: {v!r} is not a whole number of MiB (0: no limit)")
        o["memory"] = v
    if "images" in t:
        if not isinstance(t["images"], bool):
            raise fail(("images",), "images: true or false is expected")
        o["images"] = t["images"]
    if "expect" in t:
        e = t["expect"]
        if not isinstance(e, dict):
            raise fail(("expect",), "expect: a table is expected ({exit = 0, removed_volume = ...})")
        o["expect"] = _expect(e, lambda k, m: fail(("expect", k), f"expect.{k}: {m}"), base)
    return o


def _expect(e: dict, fail, base: str) -> dict:
    out = {}
    for k, v in e.items():
        if k not in _EXPECT_KEYS:
            raise fail(k, f"unknown key (one of {', '.join(sorted(_EXPECT_KEYS))})")
        if k == "exit":
            if isinstance(v, bool) or not isinstance(v, int) or v not in (0, 1, 2):
                raise fail(k, f"{v!r}: the expected exit status is 0, 1 or 2")
            out[k] = v
        elif k in ("reference", "report"):
            if not isinstance(v, str) or not v:
                raise fail(k, "a path is expected")
            out[k] = os.path.join(base, v)
        else:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (
                    k.endswith("_tol") and v < 0):
                raise fail(k, f"{v!r} is not a {'non-negative ' if k.endswith('_tol') else ''}number")
            out[k] = float(v)
    if "removed_volume_tol" in out and "removed_volume" not in out:
        raise fail("removed_volume_tol", "removed_volume_tol without removed_volume")
    if "reference_tol" in out and "reference" not in out:
        raise fail("reference_tol", "reference_tol without reference")
    return out


_CSV_COLUMNS = ("name", "program", "setup", "tolerance", "timeout", "memory", "images", "expect_exit",
                "expect_removed_volume", "expect_removed_volume_tol", "expect_reference", "expect_reference_tol",
                "expect_report")


def _csv_cells(line: str) -> list[int]:
    """1-based start columns of the cells of one CSV line (quotes respected)."""
    cols, quoted, i = [1], False, 0
    while i < len(line):
        c = line[i]
        if c == '"':
            quoted = not quoted
        elif c == "," and not quoted:
            cols.append(i + 2)
        i += 1
    return cols


def _csv_jobs(path: str, text: str) -> list[Job]:
    base = os.path.dirname(path)
    lines = text.splitlines()
    rows = [(n + 1, ln) for n, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")]
    if not rows:
        raise _err(path, 1, 1, "the manifest is empty (a header line, then one line per job)")
    hline, header_text = rows[0]
    header = [h.strip() for h in next(csv.reader([header_text]))]
    hcols = _csv_cells(header_text)
    for i, h in enumerate(header):
        if h not in _CSV_COLUMNS:
            raise _err(path, hline, hcols[i], f"unknown column {h!r} (columns: {', '.join(_CSV_COLUMNS)})")
    if "program" not in header:
        raise _err(path, hline, 1, "the header needs a 'program' column")
    if len(set(header)) != len(header):
        raise _err(path, hline, 1, "a column is named twice")
    jobs, where = [], {}
    for lineno, ln in rows[1:]:
        cells = next(csv.reader([ln]))
        cols = _csv_cells(ln)
        if len(cells) > len(header):
            raise _err(path, lineno, cols[len(header)], f"{len(cells)} cells, the header has {len(header)}")
        row = {h: c.strip() for h, c in zip(header, cells) if c.strip() != ""}
        col = {h: cols[i] for i, h in enumerate(header) if i < len(cols)}

        def fail(k, m, lineno=lineno, col=col):
            k = k[-1] if isinstance(k, tuple) and k else k
            return _err(path, lineno, col.get(k, col.get("expect_" + str(k), 1)), m)

        if "program" not in row:
            raise fail("program", "program: missing")
        t: dict = {}
        for k in ("tolerance", "timeout"):
            if k in row:
                try:
                    t[k] = float(row[k])
                except ValueError:
                    raise fail(k, f"{k}: {row[k]!r} is not a number") from None
        if "memory" in row:
            try:
                t["memory"] = int(row["memory"])
            except ValueError:
                raise fail("memory", f"memory: {row['memory']!r} is not a whole number of MiB") from None
        if "images" in row:
            v = row["images"].lower()
            if v not in ("true", "false", "1", "0", "yes", "no"):
                raise fail("images", f"images: {row['images']!r} is not true or false")
            t["images"] = v in ("true", "1", "yes")
        e: dict = {}
        for k in ("exit", "removed_volume", "removed_volume_tol", "reference_tol"):
            if "expect_" + k in row:
                try:
                    v = float(row["expect_" + k])
                except ValueError:
                    raise fail("expect_" + k, f"expect_{k}: {row['expect_' + k]!r} is not a number") from None
                e[k] = int(v) if k == "exit" and v == int(v) else v
        for k in ("reference", "report"):
            if "expect_" + k in row:
                e[k] = row["expect_" + k]
        if e:
            t["expect"] = e
        o = _options(t, lambda k, m: fail(k, m), base)
        prog = os.path.join(base, row["program"])
        setup = os.path.join(base, row["setup"]) if "setup" in row else os.path.splitext(prog)[0] + ".toml"
        jobs.append(Job(name=row.get("name", os.path.splitext(os.path.basename(row["program"]))[0]), program=prog,
                        setup=setup, tolerance=o.get("tolerance"), timeout=o.get("timeout"),
                        memory=o.get("memory"), images=o.get("images"), expect=o.get("expect", {})))
        where[len(jobs) - 1] = (lineno, col.get("name", 1))
    if not jobs:
        raise _err(path, hline, 1, "the manifest has no jobs (one line per job after the header)")
    _check_names(path, jobs, where)
    return jobs


def _as_job(x, i: int) -> Job:
    if isinstance(x, Job):
        return x
    if isinstance(x, dict):
        d = dict(x)
        if "program" not in d:
            raise CutsimError("jobs", i + 1, 0, f"job #{i + 1}: program: missing")
        d.setdefault("name", os.path.splitext(os.path.basename(d["program"]))[0])
        d.setdefault("setup", os.path.splitext(d["program"])[0] + ".toml")
        unknown = set(d) - _JOB_KEYS
        if unknown:
            raise CutsimError("jobs", i + 1, 0, f"job #{i + 1}: unknown key(s) {', '.join(sorted(unknown))}")
        return Job(**d)
    if isinstance(x, (tuple, list)) and len(x) == 2:
        return Job(name=os.path.splitext(os.path.basename(x[0]))[0], program=x[0], setup=x[1])
    raise CutsimError("jobs", i + 1, 0, f"job #{i + 1}: a Job, a dict or a (program, setup) pair is expected")


# --------------------------------------------------------------------------------------------
# the resume key


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _file_sha(path: str) -> str:
    try:
        with open(path, "rb") as f:
            return _sha(f.read())
    except OSError as e:
        return f"unreadable:{e.errno}"


_CODE_KEY = None


def code_key() -> str:
    """cutsim's version and a hash of its installed source: a result of another cutsim is stale."""
    global _CODE_KEY
    if _CODE_KEY is None:
        import cutsim
        import cutsim.base
        import cutsim.interp
        import cutsim.kinematics
        import cutsim.reports
        import cutsim.stock

        h = hashlib.sha256(cutsim.__version__.encode())
        for mod in (cutsim, cutsim.base, cutsim.interp, cutsim.kinematics, cutsim.reports, cutsim.stock):
            d = os.path.dirname(mod.__file__)
            for f in sorted(os.listdir(d)):
                if f.endswith(".py"):
                    h.update(f.encode() + b"\0" + _file_sha(os.path.join(d, f)).encode())
        _CODE_KEY = h.hexdigest()
    return _CODE_KEY


def _subprogram_extensions() -> frozenset[str]:
    """The file extensions of programs and subprograms, of every registered dialect (interp.DIALECTS)."""
    return frozenset(e.lower() for d in DIALECTS.values() for e in d.extensions)


def _referenced_files(program: str, setup: str) -> list[str]:
    """Files a job reads besides its program and setup: the setup's mesh stock and design files,
    and subprogram files beside the program or in the setup's [machine] subprogram_path that the
    program (or one of them) names."""
    out, search = set(), []
    try:
        with open(setup, "rb") as f:
            data = tomllib.loads(f.read().decode("utf-8-sig"))
        d = os.path.dirname(os.path.abspath(setup))
        st = data.get("stock")
        if isinstance(st, dict) and isinstance(st.get("path"), str):
            out.add(os.path.normpath(os.path.join(d, st["path"])))
        for c in data.get("check", []) if isinstance(data.get("check"), list) else []:
            if isinstance(c, dict) and isinstance(c.get("path"), str):
                out.add(os.path.normpath(os.path.join(d, c["path"])))
        m = data.get("machine")
        paths = m.get("subprogram_path") if isinstance(m, dict) else None
        search = [os.path.normpath(os.path.join(d, p)) for p in paths if isinstance(p, str)] \
            if isinstance(paths, list) else []
    except (OSError, ValueError, tomllib.TOMLDecodeError):
        pass
    try:
        exts, subs = _subprogram_extensions(), {}
        for d in [os.path.dirname(os.path.abspath(program))] + search:  # the program's folder wins
            try:
                names = sorted(os.listdir(d))  # first by name wins, as the interpreters pick
            except OSError:
                continue
            for f in names:
                if os.path.splitext(f)[1].lower() in exts:
                    subs.setdefault(os.path.splitext(f)[0].upper(), os.path.join(d, f))
        todo, seen = [os.path.abspath(program)], set()
        while todo:
            p = todo.pop()
            if p in seen:
                continue
            seen.add(p)
            try:
                with open(p, "rb") as f:
                    words = set(re.findall(rb"[A-Za-z_][A-Za-z0-9_]*", f.read(8 << 20)))
            except OSError:
                continue
            for w in words:
                q = subs.get(w.decode("ascii").upper())
                if q is not None and q not in seen:
                    out.add(q)
                    todo.append(q)
        out.discard(os.path.abspath(program))
    except OSError:
        pass
    return sorted(out)


def job_key(job: Job, opts: dict) -> str:
    """Same key = same result: program, setup, the files they reference, cutsim and the options."""
    parts = {
        "cutsim": code_key(),
        "program": _file_sha(job.program),
        "setup": _file_sha(job.setup),
        "refs": [[os.path.basename(p), _file_sha(p)] for p in _referenced_files(job.program, job.setup)],
        "tolerance": opts["tolerance"],
        "images": opts["images"],
        "expect": {k: (_file_sha(v) if k in ("reference", "report") else v) for k, v in sorted(job.expect.items())},
        "command": opts.get("command"),
    }
    return _sha(json.dumps(parts, sort_keys=True).encode())


# --------------------------------------------------------------------------------------------
# one job (runs on a pool thread or a Dask worker; never raises)


_RUNNING: dict[int, subprocess.Popen] = {}
_RUNNING_LOCK = threading.Lock()
_STOP = threading.Event()


def _limits(memory_mib: int):
    def set_limits():  # in the child, before exec
        import resource

        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if memory_mib:
            lim = memory_mib << 20
            resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
    return set_limits


def _run_process(argv, timeout, memory_mib, cwd=None):
    """Run argv in its own session with the limits; (returncode, stderr, timed_out, seconds)."""
    t0 = time.monotonic()
    env = dict(os.environ)
    env.pop("CUTSIM_DEBUG", None)
    env.setdefault("PYTHONHASHSEED", "0")
    try:
        p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             preexec_fn=_limits(memory_mib), start_new_session=True, cwd=cwd, env=env)
    except OSError as e:
        return None, f"cannot start the job: {e}", False, 0.0
    with _RUNNING_LOCK:
        _RUNNING[p.pid] = p
    timed_out = False
    try:
        try:
            _, err = p.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            _kill(p)
            _, err = p.communicate()
    finally:
        with _RUNNING_LOCK:
            _RUNNING.pop(p.pid, None)
    return p.returncode, err.decode("utf-8", "replace"), timed_out, time.monotonic() - t0


def _kill(p: subprocess.Popen, grace: float = 5.0) -> None:
    """SIGTERM to the job's process group (cutsim cleans up and exits 143), SIGKILL after grace."""
    for sig, wait in ((signal.SIGTERM, grace), (signal.SIGKILL, None)):
        try:
            os.killpg(p.pid, sig)
        except (ProcessLookupError, PermissionError):
            return
        try:
            p.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            continue


def _terminate_all() -> None:
    _STOP.set()
    with _RUNNING_LOCK:
        procs = list(_RUNNING.values())
    threads = [threading.Thread(target=_kill, args=(p, 5.0)) for p in procs]
    for t in threads:
        t.start()
    for t in threads:
        t.join()


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
    if _STOP.is_set():
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
        rc, err, timed_out, seconds = _run_process(argv, payload["timeout"], payload["memory"], payload.get("cwd"))
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
               "stderr": err[-_STDERR_KEEP:], "timed_out": timed_out, "seconds": round(seconds, 3),
               "files": files, "host": socket.gethostname(), "interrupted": _STOP.is_set()}
        ref = payload.get("reference")
        part = os.path.join(out, "part.stl")
        if ref and "part.stl" in files and not _STOP.is_set():
            res["compare"] = _compare_in_child(part, ref, payload)
        return res
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _compare_in_child(part: str, ref: str, payload: dict) -> dict:
    """Volumes of part - reference and reference - part, computed in a child process (manifold3d
    booleans) under the job's limits."""
    if _file_sha(part) == _file_sha(ref):
        return {"part_minus_reference": 0.0, "reference_minus_part": 0.0}
    fd, res_path = tempfile.mkstemp(prefix="cutsim-batch-cmp-", suffix=".json")
    os.close(fd)
    try:
        argv = [sys.executable, "-m", "cutsim.batch", "--compare", part, ref, res_path]
        rc, err, timed_out, _ = _run_process(argv, payload["timeout"], payload["memory"])
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


# --------------------------------------------------------------------------------------------
# turning outcomes into records


def _signame(n):
    try:
        return signal.Signals(n).name
    except ValueError:
        return f"signal {n}"


def _first_error(stderr: str) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    for ln in lines:
        if ": error: " in ln:
            return ln.strip()
    return lines[-1].strip() if lines else ""


def _record(job: Job, opts: dict, key: str, raw: dict, base: str) -> dict:
    """The deterministic record of a job (summary.json) from its raw outcome."""
    def rel(p):  # the path relative to the manifest's folder when it is inside it, else absolute
        r = os.path.relpath(os.path.abspath(p), base) if base else p
        return os.path.abspath(p) if r == ".." or r.startswith(".." + os.sep) else r

    rec = {"name": job.name, "program": rel(job.program), "setup": rel(job.setup), "tolerance": opts["tolerance"],
           "images": opts["images"], "key": key, "status": None, "exit": raw.get("exit"),
           "signal": _signame(raw["signal"]) if raw.get("signal") else None, "message": "", "problems": [],
           "removed_volume": None, "part_volume": None, "warnings": [], "checks_failed": [],
           "part_sha256": None, "report_sha256": None, "regression": None,
           "expect": {k: (rel(v) if k in ("reference", "report") else v) for k, v in sorted(job.expect.items())}}
    files = raw.get("files") or {}
    rc, stderr = raw.get("exit"), raw.get("stderr", "")
    oom = "MemoryError" in stderr or "out of memory" in stderr or "bad_alloc" in stderr
    report = None
    if "report.json" in files:
        try:
            report = json.loads(files["report.json"])
        except ValueError:
            report = None
    if raw.get("interrupted") and not (rc in SIMULATED_EXITS and report is not None):
        rec.update(status="interrupted", message="interrupted")
        return rec
    if raw.get("timed_out"):
        rec.update(status="timeout", message=f"time limit of {opts['timeout']:g} s exceeded")
        return rec
    if raw.get("internal"):
        rec.update(status="error", message=stderr)
        return rec
    if raw.get("signal"):
        rec.update(status="memory" if oom and opts["memory"] else "crashed",
                   message=f"killed by {_signame(raw['signal'])}" + (
                       f" (memory limit {opts['memory']} MiB)" if oom and opts["memory"] else ""))
        return rec
    if rc in SIMULATED_EXITS and report is None:  # e.g. an interpreter that died before cutsim's guard
        rec.update(status="memory" if oom and opts["memory"] else "crashed",
                   message=(f"out of memory (limit {opts['memory']} MiB): " if oom and opts["memory"] else
                            f"exit status {rc} without a report: ") + _first_error(stderr))
        return rec
    if rc not in SIMULATED_EXITS:
        expected = job.expect.get("exit")
        msg = _first_error(stderr) or f"exit status {rc}"
        if rc == 2 and expected == 2:
            rec.update(status=PASSED, message=msg)
            return rec
        status = "memory" if oom and opts["memory"] and rc in (2, 3) else "interrupted" if rc in (130, 143) \
            else "error"
        rec.update(status=status, message=msg + (f" (memory limit {opts['memory']} MiB)" if status == "memory" else ""))
        return rec
    # simulated: exit 0 or 1 with a report
    rec["removed_volume"] = report.get("removed_volume")
    rec["part_volume"] = report.get("part_volume")
    rec["warnings"] = [f"{w.get('line', 0)}: {w.get('message', w)}" if isinstance(w, dict) else str(w)
                       for w in report.get("warnings", [])]
    rec["checks_failed"] = sorted(c.get("name", "?") for c in report.get("checks", []) if not c.get("passed", True))
    part_name = next((n for n in sorted(files) if n.startswith("part.")), None)
    rec["part_sha256"] = _sha(files[part_name]) if part_name else None
    rec["report_sha256"] = _sha(files["report.json"])
    problems = []
    expected_exit = job.expect.get("exit", 0)
    if rc != expected_exit:
        if rc == 1:
            why = ", ".join(rec["checks_failed"]) or "a warning was escalated"
            problems.append(f"exit status 1 (expected {expected_exit}): failed: {why}")
        else:
            problems.append(f"exit status {rc} (expected {expected_exit})")
    if "removed_volume" in job.expect:
        want = job.expect["removed_volume"]
        tol = job.expect.get("removed_volume_tol", abs(want) * 1e-3)
        got = rec["removed_volume"]
        if got is None or abs(got - want) > tol:
            problems.append(f"removed volume {got} mm^3, expected {want:g} +- {tol:g}")
    if "report" in job.expect:
        problems += _compare_reports(report, job.expect["report"])
    if "reference" in job.expect:
        cmp_ = raw.get("compare") or {"error": "no part to compare"}
        tol = job.expect.get("reference_tol", DEFAULT_REFERENCE_TOL)
        if "error" in cmp_:
            reg = {"reference": rel(job.expect["reference"]), "error": cmp_["error"], "changed": True}
            problems.append(f"cannot compare with the reference: {cmp_['error']}")
        else:
            sym = round(cmp_["part_minus_reference"] + cmp_["reference_minus_part"], 6)
            reg = {"reference": rel(job.expect["reference"]), "symmetric_difference": sym,
                   "part_minus_reference": cmp_["part_minus_reference"],
                   "reference_minus_part": cmp_["reference_minus_part"], "tolerance": tol, "changed": sym > tol}
            if sym > tol:
                problems.append(f"the part changed: symmetric difference {sym:g} mm^3 with the reference "
                                f"(tolerance {tol:g})")
        rec["regression"] = reg
    rec["problems"] = problems
    rec["status"] = FAILED if problems else PASSED
    rec["message"] = problems[0] if problems else ""
    return rec


_REPORT_FIELDS = ("blocks", "moves", "removed_volume", "part_volume", "triangles")


def _compare_reports(report: dict, ref_path: str) -> list[str]:
    """A reference report.json: blocks, moves and triangles equal, volumes within 1e-6 relative,
    the same warnings and the same check outcomes."""
    try:
        with open(ref_path, "rb") as f:
            ref = json.load(f)
    except (OSError, ValueError) as e:
        return [f"cannot read the reference report {ref_path}: {e}"]
    out = []
    for k in _REPORT_FIELDS:
        a, b = report.get(k), ref.get(k)
        if isinstance(a, float) or isinstance(b, float):
            if a is None or b is None or abs(a - b) > 1e-6 * max(1.0, abs(b)):
                out.append(f"report {k}: {a}, the reference has {b}")
        elif a != b:
            out.append(f"report {k}: {a}, the reference has {b}")
    if report.get("warnings") != ref.get("warnings"):
        out.append("report warnings differ from the reference")
    oc = lambda r: [(c.get("name"), c.get("passed")) for c in r.get("checks", [])]  # noqa: E731
    if oc(report) != oc(ref):
        out.append("report check outcomes differ from the reference")
    return out


# --------------------------------------------------------------------------------------------
# the batch


class BatchSummary(dict):
    """The summary (what summary.json holds) with ``.out`` (the output directory) and ``.timings``."""

    out: str = ""
    timings: dict = {}

    @property
    def exit_status(self) -> int:
        return 0 if all(j["status"] == PASSED for j in self["jobs"]) else 1


def _write_atomic(path: str, data: bytes) -> None:
    tmp = f"{path}.tmp-{os.getpid()}-{threading.get_ident()}"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def _dumps(obj) -> bytes:
    return (json.dumps(obj, indent=2, sort_keys=True, ensure_ascii=False) + "\n").encode()


def run_batch(jobs, out: str | None = None, client=None, *, scheduler: str | None = None, workers: int | None = None,
              tolerance: float | None = None, timeout: float | None = None, memory: int | None = None,
              images: bool = False, resume: bool = False, reference_dir: str | None = None,
              reference_tol: float | None = None, progress: bool | None = None, command=None,
              base: str | None = None) -> BatchSummary:
    """Run ``jobs`` (a manifest path, or a list of Job / dict / (program, setup)) and return the
    summary. ``client``: a ``dask.distributed.Client`` (or ``scheduler``: its address) to run the
    jobs on a cluster; otherwise a local pool of ``workers`` slots (default: the core count).
    ``out``: the output directory (default: a new temporary directory, ``summary.out``).
    ``tolerance``/``timeout``/``memory``/``images``: defaults for jobs that do not set them.
    ``reference_dir``: regression mode, each part compared with ``reference_dir/<job>/part.stl``.
    ``command``: the words that replace ``python3 -m cutsim`` (testing hook; also $CUTSIM_BATCH_COMMAND).
    Raises CutsimError for a bad manifest or job list; a job's failure is in its record."""
    if isinstance(jobs, (str, os.PathLike)):
        manifest = os.fspath(jobs)
        job_list = load_manifest(manifest)
        base = base if base is not None else (manifest if os.path.isdir(manifest) else os.path.dirname(manifest))
    else:
        job_list = [_as_job(x, i) for i, x in enumerate(jobs)]
        _check_names("jobs", job_list, {i: (i + 1, 0) for i in range(len(job_list))})
    base = os.path.abspath(base or ".")
    if out is None:
        out = tempfile.mkdtemp(prefix="cutsim-batch-")
    if command is None and os.environ.get(ENV_COMMAND):
        command = shlex.split(os.environ[ENV_COMMAND])
    if isinstance(command, str):
        command = shlex.split(command)
    records_dir = os.path.join(out, RECORDS)
    try:
        os.makedirs(records_dir, exist_ok=True)
        probe = os.path.join(records_dir, f".probe-{os.getpid()}")
        _write_atomic(probe, b"")
        os.unlink(probe)
    except OSError as e:
        raise CutsimError(out, 0, 0, f"--out: {e.strerror or e}") from None

    # the options of every job, its key and its payload
    items = []
    for j in sorted(job_list, key=lambda j: j.name):
        if reference_dir and "reference" not in j.expect:
            j.expect = dict(j.expect, reference=os.path.join(reference_dir, j.name, "part.stl"))
            if reference_tol is not None:
                j.expect["reference_tol"] = reference_tol
        opts = {"tolerance": j.tolerance if j.tolerance is not None else tolerance,
                "images": bool(j.images if j.images is not None else images),
                "timeout": j.timeout if j.timeout is not None else (timeout or DEFAULT_TIMEOUT),
                "memory": j.memory if j.memory is not None else (memory if memory is not None else DEFAULT_MEMORY),
                "command": list(command) if command else None}
        key = job_key(j, opts)
        payload = {"name": j.name, "program": os.path.abspath(j.program), "setup": os.path.abspath(j.setup),
                   "tolerance": opts["tolerance"], "images": opts["images"], "timeout": opts["timeout"],
                   "memory": opts["memory"], "command": opts["command"],
                   "reference": os.path.abspath(j.expect["reference"]) if "reference" in j.expect else None}
        items.append((j, opts, key, payload))

    records: dict[str, dict] = {}
    timings: dict[str, dict] = {}
    todo = []
    for j, opts, key, payload in items:
        stored = _resumable(out, records_dir, j.name, key) if resume else None
        if stored is not None:  # the record, and the time and host of the run that made it
            records[j.name], timing = stored
            timings[j.name] = dict(timing, resumed=True)
        else:
            todo.append((j, opts, key, payload))

    if progress is None:
        progress = True
    bar = _Bar(len(items), len(items) - len(todo), progress)
    t0 = time.monotonic()
    finished = threading.Lock()

    def done(item, raw):
        j, opts, key, payload = item
        rec = _record(j, opts, key, raw, base)
        files = {n: b for n, b in (raw.get("files") or {}).items() if n != ".cutsim-output.json"}
        if files and rec["status"] != "interrupted" and rec["exit"] in SIMULATED_EXITS:
            try:
                from cutsim.reports.output import write_outputs

                write_outputs(os.path.join(out, j.name), files)
            except (CutsimError, OSError) as e:
                rec.update(status="error", message=f"cannot write {os.path.join(out, j.name)}: {e}")
        with finished:
            records[j.name] = rec
            timings[j.name] = {"seconds": raw.get("seconds", 0.0), "host": raw.get("host"), "resumed": False}
            if rec["status"] != "interrupted":
                timing = {"seconds": timings[j.name]["seconds"], "host": timings[j.name]["host"]}
                _write_atomic(os.path.join(records_dir, j.name + ".json"), _dumps(dict(rec, timing=timing)))
            bar.update(j.name, rec)

    interrupted = False
    sched = "resumed"
    try:
        if todo:
            if client is not None or scheduler:
                sched = _run_dask(todo, client, scheduler, done, bar)
            else:
                n = workers or os.cpu_count() or 1
                sched = f"local:{n}"
                _run_local(todo, n, done, bar)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        bar.close()
        _STOP.clear()
    for j, opts, key, payload in items:
        if j.name not in records:
            records[j.name] = _record(j, opts, key, {"interrupted": True}, base)
    summary = BatchSummary(_summary(records))
    summary.out = out
    summary.timings = {"scheduler": sched, "wall_seconds": round(time.monotonic() - t0, 3),
                       "interrupted": interrupted,
                       "job_seconds_total": round(sum(t.get("seconds", 0.0) for t in timings.values()), 3),
                       "jobs": dict(sorted(timings.items()))}
    _write_atomic(os.path.join(out, "summary.json"), _dumps(dict(summary)))
    _write_atomic(os.path.join(out, "timings.json"), _dumps(summary.timings))
    _write_atomic(os.path.join(out, "junit.xml"), junit_xml(summary, timings))
    _write_atomic(os.path.join(out, "index.html"), index_html(summary, timings, out))
    if interrupted:
        raise KeyboardInterrupt
    return summary


def _resumable(out: str, records_dir: str, name: str, key: str):
    """(record, timing) stored for ``name`` when it has ``key``, is a simulated result and its
    files are still in DIR/<name>/ with the same bytes; ``timing``: the seconds and host of the run
    that made it."""
    try:
        with open(os.path.join(records_dir, name + ".json"), "rb") as f:
            rec = json.load(f)
    except (OSError, ValueError):
        return None
    if not isinstance(rec, dict) or not isinstance(rec.get("timing"), dict):
        return None
    t = rec.pop("timing")
    timing = {"seconds": t.get("seconds") if isinstance(t.get("seconds"), (int, float)) else 0.0,
              "host": t.get("host")}
    if rec.get("key") != key or rec.get("status") not in (PASSED, FAILED) or rec.get("exit") not in SIMULATED_EXITS:
        return None
    d = os.path.join(out, name)
    if _file_sha(os.path.join(d, "report.json")) != rec.get("report_sha256"):
        return None
    if rec.get("part_sha256") and not any(
            _file_sha(os.path.join(d, f"part.{x}")) == rec["part_sha256"] for x in ("stl", "3mf", "glb")):
        return None
    return rec, timing


def _summary(records: dict) -> dict:
    import cutsim

    jobs = [records[k] for k in sorted(records)]
    counts = {}
    for j in jobs:
        counts[j["status"]] = counts.get(j["status"], 0) + 1
    return {"cutsim_version": cutsim.__version__, "jobs": jobs, "counts": dict(sorted(counts.items())),
            "total": len(jobs), "passed": counts.get(PASSED, 0),
            "changed": [j["name"] for j in jobs if (j.get("regression") or {}).get("changed")],
            "ok": all(j["status"] == PASSED for j in jobs)}


def _run_local(todo, n, done, bar):
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

    def work(item):
        bar.started()
        try:
            return run_job(item[3])
        finally:
            bar.stopped()

    ex = ThreadPoolExecutor(max_workers=max(1, n), thread_name_prefix="cutsim-batch")
    futs = {ex.submit(work, it): it for it in todo}
    try:
        pending = set(futs)
        while pending:
            ready, pending = wait(pending, timeout=0.5, return_when=FIRST_COMPLETED)
            for f in ready:
                done(futs[f], f.result())
    except KeyboardInterrupt:
        for f in futs:
            f.cancel()
        _terminate_all()
        ex.shutdown(wait=True, cancel_futures=True)
        for f in futs:  # the jobs that were running end as "interrupted"; finished ones are kept
            if not f.cancelled() and f.done() and futs[f][0].name not in bar.seen:
                try:
                    done(futs[f], f.result())
                except Exception:  # noqa: BLE001
                    pass
        raise
    finally:
        ex.shutdown(wait=True, cancel_futures=True)


def _run_dask(todo, client, scheduler, done, bar):
    from distributed import Client, as_completed

    own = client is None
    if own:
        try:
            client = Client(scheduler, timeout="30s")
        except Exception as e:  # noqa: BLE001 - an unreachable scheduler is an environment error
            raise CutsimError("cutsim", 0, 0, f"--scheduler: cannot connect to {scheduler}: {e}") from None
    try:
        try:
            nthreads = sum(client.nthreads().values()) or 1
        except Exception:  # noqa: BLE001
            nthreads = 1
        bar.slots = nthreads
        futs = {}
        for it in todo:
            f = client.submit(run_job, it[3], key=f"cutsim-job-{it[0].name}-{uuid.uuid4().hex[:8]}", pure=False)
            futs[f] = it
        try:
            for f in as_completed(list(futs)):
                try:
                    raw = f.result()
                except Exception as e:  # noqa: BLE001 - a lost worker (KilledWorker), a cancelled task
                    raw = {"exit": None, "signal": None, "stderr": f"batch: {type(e).__name__}: {e}",
                           "timed_out": False, "seconds": 0.0, "files": {}, "host": None, "internal": True}
                done(futs[f], raw)
                f.release()
        except KeyboardInterrupt:
            client.cancel(list(futs))
            raise
        return f"dask:{client.scheduler.address}"
    finally:
        if own:
            client.close()


class _Bar:
    """Jobs done / failed / running with an ETA on stderr: tqdm on a terminal, plain lines otherwise."""

    def __init__(self, total, resumed, enabled):
        self.total, self.n, self.failed, self.running = total, resumed, 0, 0
        self.enabled = enabled and total > 0
        self.slots = None
        self.seen = set()
        self.lock = threading.Lock()
        self.tty = self.enabled and sys.stderr.isatty()
        self.t0 = time.monotonic()
        self.bar = None
        if self.tty:
            from tqdm import tqdm

            self.bar = tqdm(total=total, initial=resumed, desc="batch", unit="job", file=sys.stderr,
                            dynamic_ncols=True)
            self._post()
        elif self.enabled and resumed:
            click.echo(f"cutsim batch: {resumed} of {total} jobs resumed", err=True)

    def started(self):
        with self.lock:
            self.running += 1
            self._post()

    def stopped(self):
        with self.lock:
            self.running -= 1

    def _post(self):
        if self.bar is not None:
            running = self.running if self.slots is None else min(self.slots, self.total - self.n)
            self.bar.set_postfix_str(f"failed {self.failed}, running {running}", refresh=True)

    def update(self, name, rec):
        with self.lock:
            self.seen.add(name)
            self.n += 1
            if rec["status"] != PASSED:
                self.failed += 1
            if not self.enabled:
                return
            if self.bar is not None:
                self.bar.update(1)
                self._post()
            else:
                el = time.monotonic() - self.t0
                eta = f", ETA {el / max(1, len(self.seen)) * (self.total - self.n):.0f} s" if self.n < self.total else ""
                click.echo(f"cutsim batch: [{self.n}/{self.total}] {name}: {rec['status']}"
                           f"{': ' + rec['message'] if rec['message'] else ''} (failed {self.failed}{eta})", err=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None


# --------------------------------------------------------------------------------------------
# JUnit XML and the HTML index


def _attr(s) -> str:
    return _xml_escape(str(s), {'"': "&quot;"})


def junit_xml(summary, timings) -> bytes:
    jobs = summary["jobs"]
    failures = sum(j["status"] == FAILED for j in jobs)
    errors = sum(j["status"] in ERROR_STATUSES for j in jobs)
    total = sum(t.get("seconds", 0.0) for t in timings.values())
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<testsuites name="cutsim batch" tests="{len(jobs)}" failures="{failures}" errors="{errors}" '
           f'time="{total:.3f}">',
           f'  <testsuite name="cutsim batch" tests="{len(jobs)}" failures="{failures}" errors="{errors}" '
           f'skipped="0" time="{total:.3f}">']
    for j in jobs:
        t = timings.get(j["name"], {}).get("seconds", 0.0)
        head = f'    <testcase classname="cutsim.batch" name="{_attr(j["name"])}" file="{_attr(j["program"])}" time="{t:.3f}"'
        body = []
        if j["status"] == FAILED:
            text = "\n".join(j["problems"] + [f"check failed: {c}" for c in j["checks_failed"]])
            body.append(f'      <failure message="{_attr(j["message"])}" type="expectation">{_xml_escape(text)}</failure>')
        elif j["status"] in ERROR_STATUSES:
            body.append(f'      <error message="{_attr(j["message"] or j["status"])}" type="{_attr(j["status"])}">'
                        f'{_xml_escape(j["message"])}</error>')
        if j["warnings"]:
            body.append(f'      <system-out>{_xml_escape(chr(10).join("warning: " + w for w in j["warnings"]))}</system-out>')
        out.append(head + (">" if body else "/>"))
        if body:
            out += body + ["    </testcase>"]
    out += ["  </testsuite>", "</testsuites>", ""]
    return "\n".join(out).encode()


def index_html(summary, timings, out_dir) -> bytes:
    rows = []
    colours = {PASSED: "#1a7f37", FAILED: "#b35900"}
    thumbs = any(j.get("images") for j in summary["jobs"])  # the thumbnail column only when a job has images
    resumed = any(t.get("resumed") for t in timings.values())
    for j in summary["jobs"]:
        n = j["name"]
        t = timings.get(n, {})
        thumb = ""
        if j.get("images") and os.path.isfile(os.path.join(out_dir, n, "iso.png")):
            thumb = f'<a href="{html.escape(n)}/report.html"><img src="{html.escape(n)}/iso.png" width="96" alt=""></a>'
        link = html.escape(n)
        if os.path.isfile(os.path.join(out_dir, n, "report.json")) and j["exit"] in SIMULATED_EXITS:
            target = "report.html" if j.get("images") else "report.json"
            link = f'<a href="{html.escape(n)}/{target}">{html.escape(n)}</a>'
        rv = "" if j["removed_volume"] is None else f'{j["removed_volume"]:.3f}'
        secs = f'{t.get("seconds", 0.0):.1f}' + (" (stored run)" if t.get("resumed") else "")
        rows.append(
            ('<tr>' + (f'<td>{thumb}</td>' if thumbs else "")) + f'<td>{link}</td><td style="color:{colours.get(j["status"], "#cf222e")}">'
            f'{html.escape(j["status"])}</td><td>{"" if j["exit"] is None else j["exit"]}</td>'
            f'<td class="n">{rv}</td><td class="n">{len(j["warnings"])}</td><td class="n">{secs}</td>'
            f'<td>{html.escape(j["message"])}</td></tr>')
    counts = ", ".join(f"{v} {k}" for k, v in summary["counts"].items())
    note = ("\nResumed jobs were not run again: their time, marked (stored run), is that of the run that made "
            "their result.") if resumed else ""
    doc = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>cutsim batch</title>
<style>body{{font-family:sans-serif;margin:1em}}table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:3px 6px;vertical-align:middle}}td.n{{text-align:right}}</style></head>
<body><h1>cutsim batch</h1><p>{summary["total"]} jobs: {html.escape(counts)}.
Scheduler {html.escape(str(summary.timings.get("scheduler")))}, {summary.timings.get("wall_seconds", 0):.1f} s.{note}
<a href="summary.json">summary.json</a>, <a href="junit.xml">junit.xml</a></p>
<table><tr>{"<th></th>" if thumbs else ""}<th>job</th><th>status</th><th>exit</th><th>removed mm&sup3;</th><th>warnings</th>
<th>time s</th><th>message</th></tr>
{chr(10).join(rows)}
</table></body></html>
"""
    return doc.encode()


# --------------------------------------------------------------------------------------------
# the command


@click.command("batch")
@click.argument("manifest", type=click.Path())
@click.option("--out", "out_dir", required=True, type=click.Path(),
              help="Output directory: DIR/<job>/, summary.json, timings.json, junit.xml, index.html.")
@click.option("--jobs", "-j", "n_jobs", type=click.IntRange(1, 4096), default=None,
              help="Jobs at a time on the local pool (default: the number of cores; ignored with --scheduler).")
@click.option("--scheduler", default=None, help="Run on a Dask cluster: the scheduler's address, tcp://HOST:8786.")
@click.option("--images", is_flag=True, help="Also write PNG views and report.html per job (thumbnails in index.html).")
@click.option("--resume", is_flag=True, help="Skip jobs with a finished result of the same inputs, cutsim and options.")
@click.option("--tolerance", type=float, default=None, help="Chordal tolerance in mm, 0.0001 to 1, for jobs that set none (else the setup's).")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=None,
              help=f"Time limit per job in s for jobs that set none (default {DEFAULT_TIMEOUT:g}).")
@click.option("--memory", type=click.IntRange(min=0), default=None,
              help=f"Address-space limit per job in MiB for jobs that set none (default {DEFAULT_MEMORY}; 0: none).")
@click.option("--reference-dir", type=click.Path(), default=None,
              help="Regression mode: compare each part with REFDIR/<job>/part.stl (an earlier batch's DIR).")
@click.option("--reference-tol", type=click.FloatRange(min=0), default=None,
              help=f"Regression mode: allowed symmetric difference in mm^3 (default {DEFAULT_REFERENCE_TOL:g}).")
@click.option("--quiet", "-q", is_flag=True, help="No progress and no closing summary.")
@click.pass_context
def batch_command(ctx, manifest, out_dir, n_jobs, scheduler, images, resume, tolerance, timeout, memory,
                  reference_dir, reference_tol, quiet):
    """Verify every job of MANIFEST (a TOML or CSV list, or a folder of PROGRAM + PROGRAM.toml).

    The closing summary goes to stdout; progress and errors go to stderr (docs/batch.md)."""
    try:
        if tolerance is not None and not (MIN_TOLERANCE <= tolerance <= 1.0):
            raise CutsimError("cutsim", 0, 0, f"--tolerance: {tolerance:g} is not between 0.0001 and 1 mm")
        summary = run_batch(manifest, out_dir, scheduler=scheduler, workers=n_jobs, tolerance=tolerance,
                            timeout=timeout, memory=memory, images=images, resume=resume,
                            reference_dir=reference_dir, reference_tol=reference_tol, progress=not quiet)
    except CutsimError as e:
        click.echo(str(e), err=True)
        ctx.exit(2)
    except OSError as e:  # writing DIR's files: disk full, permissions
        click.echo(f"{e.filename or out_dir}:0:0: error: {e.strerror or e}", err=True)
        ctx.exit(2)
    except KeyboardInterrupt as e:  # Ctrl-C; SIGTERM too under the cutsim group (cli._Terminated)
        term = type(e).__name__ == "_Terminated"
        click.echo(f"cutsim batch: {'terminated' if term else 'interrupted'}; finished jobs are kept in {out_dir} "
                   "(--resume continues)", err=True)
        ctx.exit(143 if term else 130)
    if not quiet:
        c = summary["counts"]
        click.echo(f"cutsim batch: {summary['total']} jobs, " + ", ".join(f"{v} {k}" for k, v in c.items())
                   + f" in {summary.timings['wall_seconds']:.1f} s -> {out_dir}/index.html")
        for j in summary["jobs"]:
            if j["status"] != PASSED:
                click.echo(f"  {j['name']}: {j['status']}: {j['message']}")
    ctx.exit(summary.exit_status)


def _compare_main(argv) -> int:
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


class _CallableModule(types.ModuleType):
    """``cutsim.batch`` is this module once it is imported (Python sets the package attribute), so
    the module itself is callable: ``cutsim.batch(jobs, out=None, client=None, **options)``."""

    def __call__(self, jobs, out=None, client=None, **options) -> BatchSummary:
        return run_batch(jobs, out, client, **options)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":  # python3 -m cutsim.batch --compare PART REFERENCE RESULT.json
    if len(sys.argv) == 5 and sys.argv[1] == "--compare":
        sys.exit(_compare_main(sys.argv[2:]))
    batch_command()
