"""A job's record (an entry of summary.json) from its raw outcome: its status (docs/batch.md, "A
job's status"), the numbers of its report and whether each expectation holds. Deterministic: no
times, no host names.
"""
from __future__ import annotations

import json
import os
import signal

from .keys import sha
from .manifest import Job

# job statuses: the first two are simulated results (kept by --resume), the rest are errors
PASSED, FAILED = "passed", "failed"
ERROR_STATUSES = ("error", "timeout", "memory", "crashed", "interrupted", "lost")
SIMULATED_EXITS = (0, 1)
DEFAULT_REFERENCE_TOL = 0.01  # mm^3 of symmetric difference
_REPORT_FIELDS = ("blocks", "moves", "removed_volume", "part_volume", "triangles")


def signame(n):
    try:
        return signal.Signals(n).name
    except ValueError:
        return f"signal {n}"


def first_error(stderr: str) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    for ln in lines:
        if ": error: " in ln:
            return ln.strip()
    return lines[-1].strip() if lines else ""


def record(job: Job, opts: dict, key: str, raw: dict, base: str) -> dict:
    """The deterministic record of a job (summary.json) from its raw outcome."""
    def rel(p):  # the path relative to the manifest's folder when it is inside it, else absolute
        r = os.path.relpath(os.path.abspath(p), base) if base else p
        return os.path.abspath(p) if r == ".." or r.startswith(".." + os.sep) else r

    rec = {"name": job.name, "program": rel(job.program), "setup": rel(job.setup), "tolerance": opts["tolerance"],
           "images": opts["images"], "key": key, "status": None, "exit": raw.get("exit"),
           "signal": signame(raw["signal"]) if raw.get("signal") else None, "message": "", "problems": [],
           "removed_volume": None, "part_volume": None, "warnings": [], "checks_failed": [],
           "part_sha256": None, "report_sha256": None, "regression": None,
           "expect": {k: (rel(v) if k in ("reference", "report") else v) for k, v in sorted(job.expect.items())}}
    files = raw.get("files") or {}
    report = None
    if "report.json" in files:
        try:
            report = json.loads(files["report.json"])
        except ValueError:
            report = None
    if _unsimulated(rec, job, opts, raw, report):
        return rec
    # simulated: exit 0 or 1 with a report
    rec["removed_volume"] = report.get("removed_volume")
    rec["part_volume"] = report.get("part_volume")
    rec["warnings"] = [f"{w.get('line', 0)}: {w.get('message', w)}" if isinstance(w, dict) else str(w)
                       for w in report.get("warnings", [])]
    rec["checks_failed"] = sorted(c.get("name", "?") for c in report.get("checks", []) if not c.get("passed", True))
    part_name = next((n for n in sorted(files) if n.startswith("part.")), None)
    rec["part_sha256"] = sha(files[part_name]) if part_name else None
    rec["report_sha256"] = sha(files["report.json"])
    problems = _expectations(rec, job, raw, report, rel)
    rec["problems"] = problems
    rec["status"] = FAILED if problems else PASSED
    rec["message"] = problems[0] if problems else ""
    return rec


def _unsimulated(rec: dict, job: Job, opts: dict, raw: dict, report: dict | None) -> bool:
    """Fill in the status and message of a job that did not simulate (interrupted, timed out,
    crashed, out of memory, an error exit -- or the expected exit 2); False when it simulated."""
    rc, stderr = raw.get("exit"), raw.get("stderr", "")
    oom = "MemoryError" in stderr or "out of memory" in stderr or "bad_alloc" in stderr
    if raw.get("interrupted") and not (rc in SIMULATED_EXITS and report is not None):
        rec.update(status="interrupted", message="interrupted")
    elif raw.get("timed_out"):
        rec.update(status="timeout", message=f"time limit of {opts['timeout']:g} s exceeded")
    elif raw.get("internal"):
        rec.update(status="error", message=stderr)
    elif raw.get("signal"):
        rec.update(status="memory" if oom and opts["memory"] else "crashed",
                   message=f"killed by {signame(raw['signal'])}" + (
                       f" (memory limit {opts['memory']} MiB)" if oom and opts["memory"] else ""))
    elif rc in SIMULATED_EXITS and report is None:  # e.g. an interpreter that died before cutsim's guard
        rec.update(status="memory" if oom and opts["memory"] else "crashed",
                   message=(f"out of memory (limit {opts['memory']} MiB): " if oom and opts["memory"] else
                            f"exit status {rc} without a report: ") + first_error(stderr))
    elif rc not in SIMULATED_EXITS:
        msg = first_error(stderr) or f"exit status {rc}"
        if rc == 2 and job.expect.get("exit") == 2:
            rec.update(status=PASSED, message=msg)
            return True
        status = "memory" if oom and opts["memory"] and rc in (2, 3) else "interrupted" if rc in (130, 143) \
            else "error"
        rec.update(status=status, message=msg + (f" (memory limit {opts['memory']} MiB)" if status == "memory" else ""))
    else:
        return False
    return True


def _expectations(rec: dict, job: Job, raw: dict, report: dict, rel) -> list[str]:
    """What does not hold of the job's expect table (exit status, removed volume, reference report,
    reference solid); sets ``rec["regression"]`` for a reference solid."""
    problems = []
    rc = raw.get("exit")
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
    return problems


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
