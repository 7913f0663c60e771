"""Throughput of ``cutsim batch`` on 1 and 2 workers and its overhead per job.

The jobs are the repository's examples (``examples/*/NAME.nc|.mpf`` + ``NAME.toml``; ``plate``, a
20 s job, left out) repeated with chordal tolerances from 0.1 to 1 mm until there are at least
``--n`` jobs (default 200). Modes:

- ``bare``: every job as a bare ``python3 -m cutsim simulate ... -q`` process, one after the other
  (the sum of these process times is the work itself);
- ``local:1``, ``local:2``: ``run_batch`` on the local pool with 1 and 2 slots;
- ``dask:1``, ``dask:2``: ``run_batch`` on a ``dask.distributed.LocalCluster`` with 1 and 2
  single-threaded worker processes (started here, localhost only; not counted in the wall time).

Printed per mode: wall time, throughput (jobs/min), and the overhead per job: (wall x workers -
the bare sum) / jobs, i.e. the worker-seconds per job that were not spent in a bare cutsim
process (it includes two jobs slowing each other down on shared cores), and (wall x workers - the
sum of the job process times the batch measured itself) / jobs, the scheduling overhead proper. On a machine shared with other work the numbers include that load; run it with
``nice -n 10`` and note ``uptime``.

    nice -n 10 python3 bench/bench_batch.py [--n 200] [--modes bare,local:1,local:2,dask:2] [--json OUT]
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SLOW = {"plate"}
TOLERANCES = (0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.7, 1.0)


def make_jobs(n: int) -> list[dict]:
    from cutsim.batch import load_manifest

    base = [j for j in load_manifest(str(ROOT / "examples")) if j.name.split("-")[-1] not in SLOW]
    jobs = []
    for k in range(-(-n // len(base))):
        tol = TOLERANCES[k % len(TOLERANCES)]
        for j in base:
            jobs.append({"name": f"{j.name}-t{k}", "program": j.program, "setup": j.setup, "tolerance": tol,
                         "expect": {}})
    return jobs


def bare(jobs, tmp) -> dict:
    total, t0 = 0.0, time.monotonic()
    for j in jobs:
        t = time.monotonic()
        subprocess.run([sys.executable, "-m", "cutsim", "simulate", j["program"], "--setup", j["setup"], "--out",
                        os.path.join(tmp, j["name"]), "--tolerance", repr(j["tolerance"]), "-q"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        total += time.monotonic() - t
    return {"wall": time.monotonic() - t0, "job_seconds": total, "workers": 1}


def batch(jobs, tmp, mode) -> dict:
    from cutsim.batch import run_batch

    kind, n = mode.split(":")
    n = int(n)
    if kind == "local":
        t0 = time.monotonic()
        s = run_batch(jobs, tmp, workers=n, progress=False)
        wall = time.monotonic() - t0
    else:
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=n, threads_per_worker=1, host="127.0.0.1", dashboard_address=None,
                          processes=True) as cluster, Client(cluster) as client:
            t0 = time.monotonic()
            s = run_batch(jobs, tmp, client=client, progress=False)
            wall = time.monotonic() - t0
    return {"wall": wall, "job_seconds": s.timings["job_seconds_total"], "workers": n,
            "summary": json.loads((Path(tmp) / "summary.json").read_text()), "counts": s["counts"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--modes", default="bare,local:1,local:2,dask:2")
    ap.add_argument("--json", default=None, help="write the numbers here")
    args = ap.parse_args()
    jobs = make_jobs(args.n)
    load0 = os.getloadavg()
    print(f"{len(jobs)} jobs; load average {load0[0]:.1f} {load0[1]:.1f} {load0[2]:.1f}; {os.cpu_count()} cores",
          flush=True)
    results = {}
    for mode in args.modes.split(","):
        tmp = tempfile.mkdtemp(prefix="cutsim-bench-batch-")
        try:
            r = bare(jobs, tmp) if mode == "bare" else batch(jobs, tmp, mode)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        r["load"] = os.getloadavg()[0]
        results[mode] = r
        print(f"{mode:8s} wall {r['wall']:7.1f} s  {60 * len(jobs) / r['wall']:6.1f} jobs/min  "
              f"process time {r['job_seconds']:7.1f} s  load {r['load']:.1f}", flush=True)
    ref = results.get("bare", {}).get("job_seconds")
    if ref:
        for mode, r in results.items():
            over = (r["wall"] * r["workers"] - ref) / len(jobs)
            sched = (r["wall"] * r["workers"] - r["job_seconds"]) / len(jobs)
            print(f"{mode:8s} overhead per job {over * 1000:6.0f} ms vs the bare sum, {sched * 1000:6.0f} ms vs the "
                  f"batch's own job process times; speed-up vs bare {ref / r['wall']:.2f}")
            r["overhead_per_job_s"] = over
            r["scheduling_overhead_per_job_s"] = sched
    sums = [(m, r.pop("summary")) for m, r in results.items() if "summary" in r]
    if len(sums) > 1:
        same = all(s == sums[0][1] for _, s in sums[1:])
        print(f"summaries of the batch modes identical: {same}")
        results["summaries_identical"] = same
        for m, s in sums[1:]:  # which jobs differ (e.g. cutsim's source changed between the runs)
            a = {j["name"]: j for j in sums[0][1]["jobs"]}
            diff = sorted(j["name"] for j in s["jobs"] if a.get(j["name"]) != j)
            if diff:
                fields = sorted({k for n in diff for k in a[n] if a[n][k] != next(
                    j for j in s["jobs"] if j["name"] == n)[k]})
                print(f"  {m} vs {sums[0][0]}: {len(diff)} jobs differ ({', '.join(diff[:5])}{' ...' if len(diff) > 5 else ''}) "
                      f"in {', '.join(fields)}")
    if args.json:
        Path(args.json).write_text(json.dumps({"jobs": len(jobs), "load_start": load0, "results": results}, indent=1))


if __name__ == "__main__":
    main()
