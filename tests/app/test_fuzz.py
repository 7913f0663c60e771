"""Grammar-aware fuzzing: a fixed-seed run of a few hundred generated cases.

No input may crash cutsim: no exit 3, no traceback, no hang, no worker killed; every exit 2 names
a line that exists in the named file; every part written is a closed volume read back by trimesh.
The generators and the runner live in tests/support/fuzz_cases.py; bench/fuzz.py runs 100 000 cases.
"""
from __future__ import annotations

import random
from collections import Counter

import pytest

from support import fuzz_cases as F

SEED = 20261123
CASES = 300


def test_cases_are_deterministic():
    for i in (0, 7, 123, 9999):
        a, b = F.make_case(SEED, i), F.make_case(SEED, i)
        assert (a.kind, a.files, a.argv, a.notes) == (b.kind, b.files, b.argv, b.notes)
    kinds = Counter(F.make_case(SEED, i).kind for i in range(400))
    assert set(kinds) == {"example", "grammar", "setup", "cli"}


def test_corpus_has_every_dialect():
    dialects = {s.dialect for s in F.corpus()}
    assert dialects == {"cnc8x6", "isg", "sinumerik", "rs274ngc"}


def test_location_oracle(tmp_path):
    (tmp_path / "p.nc").write_bytes(b"N10 G00 X1\r\nN20 G77\rN30\n")  # three lines (CR LF, CR, LF)
    case = {"argv": ["simulate", "p.nc"], "expect_line": None, "missing": []}
    ok = F.check_location("p.nc:3:1: error: x\n", str(tmp_path), case)
    assert ok[0] == "ok-exit2"
    assert F.check_location("p.nc:4:1: error: x\n", str(tmp_path), case)[0] == "ok-exit2"  # after the last LF
    assert F.check_location("p.nc:5:1: error: x\n", str(tmp_path), case)[0] == "bad-location"
    assert F.check_location("p.nc:0:0: error: x\n", str(tmp_path), case)[0] == "bad-location"
    assert F.check_location("q.nc:1:1: error: x\n", str(tmp_path), case)[0] == "bad-location"
    assert F.check_location("internal error\n", str(tmp_path), case)[0] == "bad-location"
    case["expect_line"] = ("p.nc", 2)
    assert F.check_location("p.nc:2:5: error: unknown G77\n", str(tmp_path), case)[0] == "ok-exit2"
    assert F.check_location("p.nc:1:5: error: unknown G77\n", str(tmp_path), case)[0] == "wrong-line"


def test_part_oracle(tmp_path):
    case = {"argv": ["simulate"], "out": "out", "fmt": "stl"}
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "part.stl").write_bytes(F.stl_box(0, 1, 0, 2, 0, 3))
    assert F.check_part(str(tmp_path), case)[0] == "missing-part"  # no report.json
    (tmp_path / "out" / "report.json").write_text(
        '{"program": "p.nc", "dialect": "cnc8x6", "blocks": 1, "moves": 1, "part_volume": 6.0, "warnings": []}')
    assert F.check_part(str(tmp_path), case) == ("", "")
    (tmp_path / "out" / "part.stl").write_bytes(F.stl_box(0, 1, 0, 2, 0, 3, drop=1))
    assert F.check_part(str(tmp_path), case)[0] == "leaky-part"
    (tmp_path / "out" / "part.stl").write_bytes(F.stl_box(0, 1, 0, 2, 0, 3, flip=True))
    assert F.check_part(str(tmp_path), case)[0] == "leaky-part"  # inside out: not a volume
    (tmp_path / "out" / "part.stl").unlink()
    assert F.check_part(str(tmp_path), case)[0] == "missing-part"


def test_runner_catches_hangs_and_memory(tmp_path):
    """The runner's own guards, on a tiny stand-in for cutsim: an endless loop and a huge allocation."""
    runner = F.Runner(jobs=1, timeout=3.0, mem_mb=2048, tmp=str(tmp_path))
    import cutsim.cli

    real = cutsim.cli.main.main

    def fake(args=None, **kw):
        if args[0] == "hang":
            while True:
                pass
        if args[0] == "alloc":
            b = bytearray(8 * 1024 ** 3)  # over the 2 GB cap
            return len(b)
        return real(args=args, **kw)

    cutsim.cli.main.main = fake  # the forked workers inherit the stand-in
    try:
        cases = [F.Case(0, "cli", "x", {}, ["hang"], out=None), F.Case(1, "cli", "x", {}, ["alloc"], out=None),
                 F.Case(2, "cli", "x", {}, ["--version"], out=None)]
        got = {c.index: r for c, r in runner.run(cases)}
    finally:
        cutsim.cli.main.main = real
        runner.close()
    assert got[0]["cls"] == "hang" and "fake" in got[0]["stderr"]  # faulthandler's stack of the worker
    assert got[1]["cls"] == "traceback" and "MemoryError" in got[1]["stderr"]
    assert got[2]["cls"] == "ok-exit0"


def test_fuzz_fixed_seed():
    runner = F.Runner(jobs=2, timeout=60.0)
    counts: Counter = Counter()
    failures = []
    try:
        for case, res in runner.run(F.make_case(SEED, i) for i in range(CASES)):
            counts[res["cls"]] += 1
            if res["cls"] in F.FAILURES:
                failures.append((case, res))
    finally:
        runner.close()
    failures.sort(key=lambda cr: cr[0].size())
    report = f"{CASES} cases: {dict(sorted(counts.items()))}\n\n" + "\n\n".join(F.describe(c, r) for c, r in failures[:12])
    print(report)
    # the generators reach the geometry and the error paths (else this test could not fail)
    assert counts["ok-exit0"] + counts["exit1"] >= CASES // 6, report
    assert counts["ok-exit2"] >= CASES // 6, report
    assert not failures, report
