"""Batch manifests: the jobs of a TOML file, a CSV file or a folder of PROGRAM + PROGRAM.toml pairs
(docs/batch.md, "Manifests"), or of a list given in Python. Every error is a CutsimError
``MANIFEST:LINE:COL`` (``jobs:N:0`` for the N-th job of a list).
"""
from __future__ import annotations

import csv
import math
import os
import re
import tomllib
from dataclasses import dataclass, field

from cutsim.interp.errors import CutsimError
from cutsim.setup import MIN_TOLERANCE, huge_number_at, key_positions

RESERVED = {"summary.json", "timings.json", "junit.xml", "index.html"}  # DIR's own files: no job's name
_NAME_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9._+-]*\Z")
JOB_KEYS = {"name", "program", "setup", "tolerance", "timeout", "memory", "images", "expect"}
_EXPECT_KEYS = {"exit", "removed_volume", "removed_volume_tol", "reference", "reference_tol", "report"}
_DEFAULT_KEYS = {"tolerance", "timeout", "memory", "images", "expect"}


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
    check_names(folder, jobs, {})
    return jobs


def check_names(manifest, jobs, where):
    seen = {}
    for i, j in enumerate(jobs):
        line, col = where.get(i, (0, 0))
        if not _NAME_RE.match(j.name) or j.name in RESERVED:
            raise _err(manifest, line, col, f"job name {j.name!r}: use letters, digits, '.', '_', '+', '-' "
                       f"(not starting with '.' and not {', '.join(sorted(RESERVED))})")
        if j.name in seen:
            raise _err(manifest, line, col, f"job name {j.name!r} is used twice (also job #{seen[j.name] + 1})")
        seen[j.name] = i


def _toml_jobs(path: str, text: str) -> list[Job]:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(e))
        msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(e)) or "not TOML"
        raise _err(path, int(m.group(1)) if m else 0, int(m.group(2)) if m else 0, msg) from None
    except ValueError:  # a number with more digits than Python converts (not a TOMLDecodeError)
        raise _err(path, *huge_number_at(text), "a number with too many digits") from None
    pos = key_positions(text)
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
            if k not in JOB_KEYS:
                raise jfail((k,), f"{k}: unknown key (one of {', '.join(sorted(JOB_KEYS))})")
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
    check_names(path, jobs, where)
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
    check_names(path, jobs, where)
    return jobs


def as_job(x, i: int) -> Job:
    if isinstance(x, Job):
        return x
    if isinstance(x, dict):
        d = dict(x)
        if "program" not in d:
            raise CutsimError("jobs", i + 1, 0, f"job #{i + 1}: program: missing")
        d.setdefault("name", os.path.splitext(os.path.basename(d["program"]))[0])
        d.setdefault("setup", os.path.splitext(d["program"])[0] + ".toml")
        unknown = set(d) - JOB_KEYS
        if unknown:
            raise CutsimError("jobs", i + 1, 0, f"job #{i + 1}: unknown key(s) {', '.join(sorted(unknown))}")
        return Job(**d)
    if isinstance(x, (tuple, list)) and len(x) == 2:
        return Job(name=os.path.splitext(os.path.basename(x[0]))[0], program=x[0], setup=x[1])
    raise CutsimError("jobs", i + 1, 0, f"job #{i + 1}: a Job, a dict or a (program, setup) pair is expected")
