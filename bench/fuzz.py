"""Long grammar-aware fuzz run of cutsim (all three dialects, the setup, the command line).

    python3 bench/fuzz.py --cases 100000 --jobs 2 --seed 1 --out /tmp/fuzz1

Prints the count per class (see tests/support/fuzz_cases.py: CLASSES, FAILURES), writes the reproducers of
every failure group (program, setup, extra files, cmd.sh, stderr.txt) under OUT/failures/, the
minimised reproducer of the largest groups under OUT/minimal/, and OUT/summary.json. The cases
depend only on the seed (and the example files present); hang and memory results also on the
machine's load. Not part of the test suite (it runs for many minutes); tests/app/test_fuzz.py runs a
few hundred cases of the same generators.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from support import fuzz_cases as F  # noqa: E402


def slug(s: str, n: int = 60) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", s).strip("-")[:n] or "x"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=10000)
    ap.add_argument("--start", type=int, default=0, help="first case index (to continue a run)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds per case before it counts as a hang")
    ap.add_argument("--mem-mb", type=int, default=3072, help="address-space cap per worker")
    ap.add_argument("--max-repro", type=int, default=3, help="reproducers written per failure group")
    ap.add_argument("--minimize", type=int, default=15, help="failure groups to minimise (largest first)")
    ap.add_argument("--confirm-hangs", type=float, default=0.0,
                    help="re-run hangs (up to 10) with this longer timeout to tell slow from endless")
    ap.add_argument("--time-limit", type=float, default=0.0,
                    help="stop starting new cases after this many seconds (then write the results)")
    ap.add_argument("--min-budget", type=int, default=100, help="runs per minimisation")
    ap.add_argument("--kinds", default="", help="only these case kinds (comma list: example,grammar,setup,cli)")
    a = ap.parse_args(argv)

    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    seeds = F.corpus()
    runner = F.Runner(jobs=a.jobs, timeout=a.timeout, mem_mb=a.mem_mb)
    kinds = set(a.kinds.split(",")) if a.kinds else None

    def cases():
        for i in range(a.start, a.start + a.cases):
            if a.time_limit and time.monotonic() - t0 > a.time_limit:
                print(f"time limit: stopping before case {i}", flush=True)
                return
            c = F.make_case(a.seed, i, seeds)
            if kinds is None or c.kind in kinds:
                yield c

    counts: Counter = Counter()
    by_kind: dict = defaultdict(Counter)
    by_dialect: dict = defaultdict(Counter)
    groups: dict[str, dict] = {}
    times: dict = defaultdict(list)
    slow: list = []
    t0 = time.monotonic()
    last = t0
    n = 0
    print(f"fuzz: seed {a.seed}, cases {a.start}..{a.start + a.cases - 1}, jobs {a.jobs}, timeout {a.timeout}s, "
          f"{len(seeds)} example pairs", flush=True)
    try:
        for case, res in runner.run(cases()):
            n += 1
            cls = res["cls"]
            counts[cls] += 1
            by_kind[case.kind][cls] += 1
            by_dialect[case.dialect][cls] += 1
            cpu = res.get("cpu", res["time"])
            times[case.kind].append(cpu)
            if cpu > 5:
                slow.append((round(cpu, 2), case.index, cls, case.dialect, "; ".join(case.notes)[:120]))
            if cls in F.FAILURES:
                sig = F.signature(cls, res)
                g = groups.setdefault(sig, {"class": cls, "signature": sig, "count": 0, "cases": [], "first": None})
                g["count"] += 1
                g["cases"].append((case.size(), case.index))
                g["cases"] = sorted(g["cases"])[: max(a.max_repro, 1)]
                if g["first"] is None:
                    g["first"] = {"detail": res["detail"], "stderr": res["stderr"][-3000:], "trace": res.get("trace")}
                    print(f"  new group [{cls}] {sig}  (case {case.index})", flush=True)
            now = time.monotonic()
            if now - last > 60:
                last = now
                fails = sum(v for k, v in counts.items() if k in F.FAILURES)
                print(f"[{now - t0:7.0f}s] {n} cases ({n / (now - t0):.1f}/s), failures {fails}: "
                      + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), flush=True)
    except KeyboardInterrupt:
        print("interrupted: writing what ran so far", flush=True)
    elapsed = time.monotonic() - t0

    # reproducers: the smallest cases of each group, regenerated from their index
    fail_dir = out / "failures"
    shutil.rmtree(fail_dir, ignore_errors=True)
    ordered = sorted(groups.values(), key=lambda g: (F.FAILURES.index(g["class"]), -g["count"]))
    for gi, g in enumerate(ordered):
        gdir = fail_dir / g["class"] / f"{gi:03d}-{slug(g['signature'])}"
        g["dir"] = str(gdir)
        g["reproducers"] = []
        for _, idx in g["cases"]:
            c = F.make_case(a.seed, idx, seeds)
            # re-run once: the reproducer's own stderr (and a check that it still fails the same way)
            res = next(iter(runner.run([c])))[1]
            d = gdir / f"case{idx}"
            F.write_reproducer(c, res, str(d))
            g["reproducers"].append({"case": idx, "dir": str(d), "command": c.command(), "notes": c.notes,
                                     "reproduced": res["cls"] == g["class"]})

    # confirm hangs with a longer timeout
    if a.confirm_hangs > 0:
        long_runner = F.Runner(jobs=1, timeout=a.confirm_hangs, mem_mb=a.mem_mb)
        for g in ordered:
            if g["class"] != "hang":
                continue
            for rep in g["reproducers"][:1]:
                c = F.make_case(a.seed, rep["case"], seeds)
                res = next(iter(long_runner.run([c])))[1]
                rep["confirm"] = {"timeout": a.confirm_hangs, "class": res["cls"], "time": round(res["time"], 1),
                                  "detail": res["detail"][:300]}
        long_runner.close()

    def write_summary():
        summary = {
            "seed": a.seed, "start": a.start, "cases": n, "jobs": a.jobs, "timeout_s": a.timeout,
            "elapsed_s": round(elapsed, 1), "cases_per_s": round(n / elapsed, 2) if elapsed else None,
            "counts": dict(sorted(counts.items())),
            "failures": sum(v for k, v in counts.items() if k in F.FAILURES),
            "by_kind": {k: dict(sorted(v.items())) for k, v in sorted(by_kind.items())},
            "by_dialect": {k: dict(sorted(v.items())) for k, v in sorted(by_dialect.items())},
            "mean_cpu_s": {k: round(sum(v) / len(v), 4) for k, v in sorted(times.items()) if v},
            "slow_cases": sorted(slow, reverse=True)[:30],
            "groups": [{k: v for k, v in g.items() if k != "cases"} | {"case_indices": [i for _, i in g["cases"]]}
                       for g in ordered],
        }
        (out / "summary.json").write_text(json.dumps(summary, indent=1, default=str))
        return summary

    write_summary()  # before the minimisation (which may take minutes)
    print(f"{n} cases in {elapsed:.0f} s: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), flush=True)

    # minimise the largest groups
    min_dir = out / "minimal"
    shutil.rmtree(min_dir, ignore_errors=True)
    for g in sorted(ordered, key=lambda g: -g["count"])[: a.minimize]:
        if g["class"] == "hang":
            continue  # every trial would take the full timeout
        idx = g["cases"][0][1]
        c = F.make_case(a.seed, idx, seeds)
        m = F.minimize(runner, c, g["class"], g["signature"], budget=a.min_budget)
        res = next(iter(runner.run([m])))[1]
        d = min_dir / f"{slug(g['signature'])}"
        F.write_reproducer(m, res, str(d))
        g["minimal"] = {"dir": str(d), "size": m.size(), "from_size": c.size(), "command": m.command(),
                        "class": res["cls"]}
    runner.close()

    summary = write_summary()
    print(f"\n{n} cases in {elapsed:.0f} s ({summary['cases_per_s']}/s), seed {a.seed}")
    for k in F.CLASSES:
        if counts.get(k):
            print(f"  {k:15s} {counts[k]:7d}" + ("   <-- failure" if k in F.FAILURES else ""))
    print(f"failure groups: {len(ordered)}")
    for g in ordered:
        print(f"  [{g['class']}] x{g['count']}: {g['signature'][:150]}\n      {g.get('minimal', {}).get('dir') or g['dir']}")
    print(f"summary: {out / 'summary.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
