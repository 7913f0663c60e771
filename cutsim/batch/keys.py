"""Resume keys: a job's key is a hash of everything its result depends on -- the program, the
setup, the files they reference, cutsim itself and the options -- so the same key means the same
result (docs/batch.md, "Resume").
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import tomllib

from cutsim.interp import DIALECTS

from .manifest import Job


def sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def file_sha(path: str) -> str:
    try:
        with open(path, "rb") as f:
            return sha(f.read())
    except OSError as e:
        return f"unreadable:{e.errno}"


_CODE_KEY = None


def code_key() -> str:
    """cutsim's version and a hash of its installed source (every .py and template file of every
    package folder, subpackages included): a result of another cutsim is stale."""
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
            top = os.path.dirname(mod.__file__)
            for d, dirs, files in os.walk(top):
                dirs[:] = sorted(x for x in dirs if not x.startswith((".", "__pycache__")))
                for f in sorted(files):
                    if f.endswith((".py", ".j2")):
                        rel = os.path.relpath(os.path.join(d, f), top)
                        h.update(rel.encode() + b"\0" + file_sha(os.path.join(d, f)).encode())
        _CODE_KEY = h.hexdigest()
    return _CODE_KEY


def _subprogram_extensions() -> frozenset[str]:
    """The file extensions of programs and subprograms, of every registered dialect (interp.DIALECTS)."""
    return frozenset(e.lower() for d in DIALECTS.values() for e in d.extensions)


def referenced_files(program: str, setup: str) -> list[str]:
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
        "program": file_sha(job.program),
        "setup": file_sha(job.setup),
        "refs": [[os.path.basename(p), file_sha(p)] for p in referenced_files(job.program, job.setup)],
        "tolerance": opts["tolerance"],
        "images": opts["images"],
        "expect": {k: (file_sha(v) if k in ("reference", "report") else v) for k, v in sorted(job.expect.items())},
        "command": opts.get("command"),
    }
    return sha(json.dumps(parts, sort_keys=True).encode())
