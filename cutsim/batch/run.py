"""The batch: every job's options, key and payload; the stored results ``--resume`` keeps; the
jobs run on the chosen scheduler, each finished one committed into ``DIR/<job>/`` with cutsim's own
output transaction and recorded in ``DIR/.cutsim-batch/<job>.json``; then summary.json,
timings.json, junit.xml and index.html (docs/batch.md, "Outputs").
"""
from __future__ import annotations

import json
import os
import shlex
import tempfile
import threading
import time

from cutsim.interp.errors import CutsimError

from . import process
from .index import index_html
from .junit import junit_xml
from .keys import file_sha, job_key
from .manifest import Job, as_job, check_names, load_manifest
from .progress import Bar
from .records import FAILED, PASSED, SIMULATED_EXITS, record
from .schedule import run_dask, run_local

DEFAULT_TIMEOUT = 1800.0  # s per job
DEFAULT_MEMORY = 4096  # MiB of address space per job
RECORDS = ".cutsim-batch"  # DIR/.cutsim-batch/<job>.json: each finished job's record and time
ENV_COMMAND = "CUTSIM_BATCH_COMMAND"  # testing hook: replaces ``python3 -m cutsim`` (shlex words)


class BatchSummary(dict):
    """The summary (what summary.json holds) with ``.out`` (the output directory) and ``.timings``."""

    out: str = ""
    timings: dict = {}

    @property
    def exit_status(self) -> int:
        return 0 if all(j["status"] == PASSED for j in self["jobs"]) else 1


def write_atomic(path: str, data: bytes) -> None:
    tmp = f"{path}.tmp-{os.getpid()}-{threading.get_ident()}"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def dumps(obj) -> bytes:
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
    job_list, base = _job_list(jobs, base)
    if out is None:
        out = tempfile.mkdtemp(prefix="cutsim-batch-")
    if command is None and os.environ.get(ENV_COMMAND):
        command = shlex.split(os.environ[ENV_COMMAND])
    if isinstance(command, str):
        command = shlex.split(command)
    records_dir = _records_dir(out)
    defaults = {"tolerance": tolerance, "images": images, "timeout": timeout or DEFAULT_TIMEOUT,
                "memory": memory if memory is not None else DEFAULT_MEMORY, "command": list(command) if command else None}
    items = [_item(j, defaults, reference_dir, reference_tol) for j in sorted(job_list, key=lambda j: j.name)]
    state = _State(out, records_dir, base)
    todo = []
    for item in items:
        stored = _resumable(out, records_dir, item[0].name, item[2]) if resume else None
        if stored is not None:  # the record, and the time and host of the run that made it
            state.records[item[0].name], timing = stored
            state.timings[item[0].name] = dict(timing, resumed=True)
        else:
            todo.append(item)
    bar = Bar(len(items), len(items) - len(todo), True if progress is None else progress)
    t0 = time.monotonic()
    interrupted, sched = False, "resumed"
    try:
        if todo:
            if client is not None or scheduler:
                sched = run_dask(todo, client, scheduler, lambda item, raw: state.done(item, raw, bar), bar)
            else:
                n = workers or os.cpu_count() or 1
                sched = f"local:{n}"
                run_local(todo, n, lambda item, raw: state.done(item, raw, bar), bar)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        bar.close()
        process.STOP.clear()
    summary = state.finish(items, sched, round(time.monotonic() - t0, 3), interrupted)
    if interrupted:
        raise KeyboardInterrupt
    return summary


def _job_list(jobs, base: str | None) -> tuple[list[Job], str]:
    """The jobs (of a manifest path or a list) and the folder their paths are relative to."""
    if isinstance(jobs, (str, os.PathLike)):
        manifest = os.fspath(jobs)
        job_list = load_manifest(manifest)
        base = base if base is not None else (manifest if os.path.isdir(manifest) else os.path.dirname(manifest))
    else:
        job_list = [as_job(x, i) for i, x in enumerate(jobs)]
        check_names("jobs", job_list, {i: (i + 1, 0) for i in range(len(job_list))})
    return job_list, os.path.abspath(base or ".")


def _records_dir(out: str) -> str:
    """DIR/.cutsim-batch, created and tried before any job runs, so an unusable DIR is an error at once."""
    records_dir = os.path.join(out, RECORDS)
    try:
        os.makedirs(records_dir, exist_ok=True)
        probe = os.path.join(records_dir, f".probe-{os.getpid()}")
        write_atomic(probe, b"")
        os.unlink(probe)
    except OSError as e:
        raise CutsimError(out, 0, 0, f"--out: {e.strerror or e}") from None
    return records_dir


def _item(j: Job, defaults: dict, reference_dir: str | None, reference_tol: float | None) -> tuple:
    """(job, its options, its key, its payload for run_job): the job's own values over the batch's."""
    if reference_dir and "reference" not in j.expect:
        j.expect = dict(j.expect, reference=os.path.join(reference_dir, j.name, "part.stl"))
        if reference_tol is not None:
            j.expect["reference_tol"] = reference_tol
    opts = {"tolerance": j.tolerance if j.tolerance is not None else defaults["tolerance"],
            "images": bool(j.images if j.images is not None else defaults["images"]),
            "timeout": j.timeout if j.timeout is not None else defaults["timeout"],
            "memory": j.memory if j.memory is not None else defaults["memory"],
            "command": defaults["command"]}
    key = job_key(j, opts)
    payload = {"name": j.name, "program": os.path.abspath(j.program), "setup": os.path.abspath(j.setup),
               "tolerance": opts["tolerance"], "images": opts["images"], "timeout": opts["timeout"],
               "memory": opts["memory"], "command": opts["command"],
               "reference": os.path.abspath(j.expect["reference"]) if "reference" in j.expect else None}
    return j, opts, key, payload


class _State:
    """The records and timings of one batch as its jobs finish (from several threads)."""

    def __init__(self, out: str, records_dir: str, base: str):
        self.out, self.records_dir, self.base = out, records_dir, base
        self.records: dict[str, dict] = {}
        self.timings: dict[str, dict] = {}
        self.lock = threading.Lock()

    def done(self, item, raw: dict, bar: Bar) -> None:
        """A finished job: its files committed into DIR/<job>/, its record (with its time) stored."""
        j, opts, key, payload = item
        rec = record(j, opts, key, raw, self.base)
        files = {n: b for n, b in (raw.get("files") or {}).items() if n != ".cutsim-output.json"}
        if files and rec["status"] != "interrupted" and rec["exit"] in SIMULATED_EXITS:
            try:
                from cutsim.output import write_outputs

                write_outputs(os.path.join(self.out, j.name), files)
            except (CutsimError, OSError) as e:
                rec.update(status="error", message=f"cannot write {os.path.join(self.out, j.name)}: {e}")
        with self.lock:
            self.records[j.name] = rec
            self.timings[j.name] = {"seconds": raw.get("seconds", 0.0), "host": raw.get("host"), "resumed": False}
            if rec["status"] != "interrupted":
                timing = {"seconds": self.timings[j.name]["seconds"], "host": self.timings[j.name]["host"]}
                write_atomic(os.path.join(self.records_dir, j.name + ".json"), dumps(dict(rec, timing=timing)))
            bar.update(j.name, rec)

    def finish(self, items, sched: str, wall: float, interrupted: bool) -> BatchSummary:
        """The summary (unfinished jobs as interrupted) and DIR's four files."""
        for j, opts, key, payload in items:
            if j.name not in self.records:
                self.records[j.name] = record(j, opts, key, {"interrupted": True}, self.base)
        summary = BatchSummary(_summary(self.records))
        summary.out = self.out
        summary.timings = {"scheduler": sched, "wall_seconds": wall, "interrupted": interrupted,
                           "job_seconds_total": round(sum(t.get("seconds", 0.0) for t in self.timings.values()), 3),
                           "jobs": dict(sorted(self.timings.items()))}
        write_atomic(os.path.join(self.out, "summary.json"), dumps(dict(summary)))
        write_atomic(os.path.join(self.out, "timings.json"), dumps(summary.timings))
        write_atomic(os.path.join(self.out, "junit.xml"), junit_xml(summary, self.timings))
        write_atomic(os.path.join(self.out, "index.html"), index_html(summary, self.timings, self.out))
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
    if file_sha(os.path.join(d, "report.json")) != rec.get("report_sha256"):
        return None
    if rec.get("part_sha256") and not any(
            file_sha(os.path.join(d, f"part.{x}")) == rec["part_sha256"] for x in ("stl", "3mf", "glb")):
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
