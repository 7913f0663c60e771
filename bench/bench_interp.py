"""Interpreter throughput and memory (issue 13): plain G1 programs per dialect.

    nice -n 10 python3 bench/bench_interp.py                       # 100k blocks, every case
    nice -n 10 python3 bench/bench_interp.py --sizes 100000,1000000
    python3 bench/bench_interp.py --cases cnc8x6-lathe --modes interp --profile 30
                                                                   # top 30 functions (cProfile)
    python3 bench/bench_interp.py --against /tmp/old/pkg           # each row also with another
                                                                   # cutsim (PYTHONPATH) and the ratio

Cases: a generated program of N plain linear blocks ``N.. G01 X.. Z.. F..`` (mill forms with Y as
well) for each dialect and machine form: cnc8x6-lathe, cnc8x6-mill, isg-lathe, isg-mill,
sinumerik-mill, sinumerik-lathe. Modes, each case run in its own process so that its peak memory
(ru_maxrss of that process, os.wait4) is its own:

- interp: ``cutsim.interp.interpret()`` alone on the text already in memory: blocks/s, and the
  memory it adds (peak RSS less the RSS before it ran) per move, with the Program alive;
- plan:   interpret + ``kinematics.plan()`` (what the stock side is handed): bytes/move of both;
- moves:  ``cutsim moves PROG --setup SETUP > /dev/null`` end to end (process start, setup,
  reading, interpretation, transcript): blocks/s over the wall time, peak RSS.

Target (issue 13): >= 50 000 blocks/s per dialect for interp; memory flat in the block count
(bytes/move the same at 100k and 1M; peak <= 2 GB at 1M moves end to end). A benchmark, not a
test: it prints a table and asserts nothing.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

CASES = ("cnc8x6-lathe", "cnc8x6-mill", "isg-lathe", "isg-mill", "sinumerik-mill", "sinumerik-lathe")
MODES = ("interp", "plan", "moves")
TARGET = 50_000  # blocks/s

SETUP = """[machine]
kind = "{kind}"
dialect = "{dialect}"
start = [{sx}, 0.0, 60.0]
{extra}
[stock]
{stock}

[[tool]]
number = 1
{tool}
"""
LATHE_TOOL = 'kind = "turning"\nangle = 55.0'
MILL_TOOL = 'kind = "endmill"\ndiameter = 6.0\nlength = 30.0'
LATHE_STOCK = 'shape = "cylinder"\ndiameter = 60.0\nz = [-60.0, 0.0]'
MILL_STOCK = 'shape = "box"\nx = [0.0, 100.0]\ny = [0.0, 100.0]\nz = [-10.0, 0.0]'


def program(case: str, n: int) -> str:
    """``n`` linear feed blocks (plus a short head and the end) in the dialect's plain form: a
    zig-zag so that no two neighbouring blocks are alike."""
    dialect, kind = case.split("-")
    mill = kind == "mill"
    lines = []
    if dialect == "isg":
        lines.append("%bench")
    g1 = "G1" if dialect == "sinumerik" else "G01"
    first = True
    for i in range(n):
        x = 20.0 + (i % 200) * 0.05 if not mill else (i % 500) * 0.1
        z = -((i // 200) % 50) * 0.5 - 1.0 if not mill else -1.0 - (i % 3) * 0.5
        y = f" Y{(i // 500) % 100 * 0.5:.3f}" if mill else ""
        head = f"{g1} " if first or i % 2 == 0 else ""  # the motion is modal: half the blocks omit it
        lines.append(f"N{10 + i} {head}X{x:.3f}{y} Z{z:.3f} F{100 + i % 7 * 10}")
        first = False
    lines.append(f"N{10 + n} M30")
    return "\n".join(lines) + "\n"


def setup_text(case: str) -> str:
    dialect, kind = case.split("-")
    lathe = kind == "lathe"
    extra = "diameter_programming = true\n" if lathe and dialect == "cnc8x6" else ""
    return SETUP.format(kind=kind, dialect=dialect, sx=80.0 if lathe else 0.0, extra=extra,
                        stock=LATHE_STOCK if lathe else MILL_STOCK, tool=LATHE_TOOL if lathe else MILL_TOOL)


def rss_now() -> int:
    """The resident set size of this process now (bytes)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def peak_rss() -> int:
    """The peak resident set size of this process so far (bytes; VmHWM)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    return 0


def child(mode: str, case: str, prog: str, setup: str, profile: int) -> dict:
    """One measurement inside its own process (interp or plan)."""
    import cutsim
    from cutsim.interp import interpret

    s = cutsim.load_setup(setup)
    text = cutsim.read_program(prog)
    cfg = cutsim.interp_config(s, s.machine.start)
    if profile:  # a separate run: the profiler slows it down
        import cProfile
        import pstats

        pr = cProfile.Profile()
        pr.enable()
        interpret(prog, text, cfg)
        pr.disable()
        pstats.Stats(pr, stream=sys.stderr).sort_stats("tottime").print_stats(profile)
    base = rss_now()
    t0 = time.perf_counter()
    p = interpret(prog, text, cfg)
    t_interp = time.perf_counter() - t0
    out = {"blocks": p.blocks, "moves": len(p.moves), "records": len(p.records), "interp_s": t_interp}
    if mode == "plan":
        from cutsim.kinematics import plan

        t0 = time.perf_counter()
        pl = plan(p, s.machine, s.tools, s.tolerance)
        out["plan_s"] = time.perf_counter() - t0
        out["paths"] = len(pl.paths)
    out["added_bytes"] = peak_rss() - base
    out["peak_rss"] = peak_rss()
    return out


def run_case(mode: str, case: str, n: int, work: str, profile: int = 0, pythonpath: str | None = None) -> dict:
    prog = os.path.join(work, f"{case}-{n}.{'mpf' if case.startswith('sinumerik') else 'nc'}")
    setup = os.path.join(work, f"{case}.toml")
    if not os.path.exists(prog):
        with open(prog, "w") as f:
            f.write(program(case, n))
    with open(setup, "w") as f:
        f.write(setup_text(case))
    env = dict(os.environ, PYTHONPATH=pythonpath) if pythonpath else None
    if mode == "moves":
        t0 = time.perf_counter()
        p = subprocess.Popen([sys.executable, "-m", "cutsim", "moves", prog, "--setup", setup],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, cwd=work)
        err = p.stderr.read()
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            return {"error": err.decode(errors="replace").strip()[:200]}
        return {"wall_s": wall, "peak_rss": ru.ru_maxrss * 1024, "blocks": n + 1}
    cmd = [sys.executable, __file__, "--child", mode, case, prog, setup, str(profile)]
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if profile:
        sys.stderr.write(r.stderr)
    if r.returncode != 0:
        return {"error": (r.stderr.strip().splitlines() or ["?"])[-1][:200]}
    return json.loads(r.stdout.strip().splitlines()[-1])


def mib(b: float) -> str:
    return f"{b / 2**20:8.1f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", default="100000", help="comma-separated block counts (default 100000)")
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--modes", default=",".join(MODES))
    ap.add_argument("--profile", type=int, default=0, help="print the top N functions of interpret() (cProfile)")
    ap.add_argument("--against", help="a directory holding another cutsim package (e.g. an older commit's, "
                    "laid out as cutsim/, cutsim/interp/, ...): every row is run with it too, as 'was'")
    ap.add_argument("--child", nargs=5, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        mode, case, prog, setup, profile = a.child
        print(json.dumps(child(mode, case, prog, setup, int(profile))))
        return
    sizes = [int(s) for s in a.sizes.split(",")]
    print(f"{'case':16} {'mode':6} {'blocks':>8} {'s':>7} {'blocks/s':>9} {'target':>6} "
          f"{'peak MiB':>8} {'added MiB':>9} {'B/move':>7}")
    with tempfile.TemporaryDirectory(prefix="cutsim-bench-interp-") as work:
        for n in sizes:
            for case in a.cases.split(","):
                for mode in a.modes.split(","):
                    runs = [("", None)] + ([("was", a.against)] if a.against else [])
                    rates = []
                    for tag, path in runs:
                        r = run_case(mode, case, n, work, a.profile if not tag else 0, path)
                        label = f"{mode} {tag}".strip()
                        if "error" in r:
                            print(f"{case:16} {label:6} {n:>8} error: {r['error']}")
                            continue
                        secs = r["wall_s"] if mode == "moves" else r["interp_s"] + r.get("plan_s", 0.0)
                        rate = r["blocks"] / secs
                        rates.append(rate)
                        added = r.get("added_bytes")
                        per = f"{added / max(1, r['moves']):7.0f}" if added is not None else f"{'':7}"
                        ok = ("ok" if rate >= TARGET else "below") if mode == "interp" and not tag else ""
                        print(f"{case:16} {label:6} {r['blocks']:>8} {secs:7.2f} {rate:9.0f} {ok:>6} "
                              f"{mib(r['peak_rss'])} {mib(added) if added is not None else '':>9} {per}", flush=True)
                    if len(rates) == 2:
                        print(f"{'':16} {'speed-up':>15} {rates[0] / rates[1]:17.2f}x", flush=True)
            # each program is written once per size and removed with the directory
            for f in os.listdir(work):
                if f.endswith((".nc", ".mpf")):
                    os.remove(os.path.join(work, f))


if __name__ == "__main__":
    main()
