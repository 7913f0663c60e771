"""Milling speed benchmark: generated CAM-like programs through the whole pipeline.

    python bench/bench_mill.py                 # the full table (several minutes on 2 cores)
    python bench/bench_mill.py --quick         # 5k/10k only (pocket and raster)
    python bench/bench_mill.py --baseline 5000 # also the slow path (one hull per move, no 2.5D fast path)
    python bench/bench_mill.py --issue13       # 11k pocket vs its floor, 10k/100k/1M scaling
    python bench/bench_mill.py --issue13 --repeat 5 --no-scaling  # medians of 5 interleaved runs
    python bench/bench_mill.py --design        # design compare on a 26k-triangle pocket
    python bench/bench_mill.py --flute         # flute checks of a slot repeated far below the flutes

Cases (each run in its own process, so the peak memory is its own):
- pocket N: a zig-zag pocket at one Z, a 6 mm flat end mill, passes 0.5 mm apart, every pass
  written as 2 mm pieces (as CAM posts a polyline): N constant-Z moves, square side ~ sqrt(N) mm.
- raster N: a 3D ball-end raster (6 mm ball) over a wavy surface, 1 mm moves, 1 mm stepover, at
  the default tolerance 0.002 (CUTSIM_BENCH_RASTER_TOL to change). Each raster line is one mitred
  tube (stock/tube.py); before that it cost ~20 ms/move and ~6 GB at 5k moves.
- waterline N: a ball-end Z-level finish, level loops of 0.5 mm G01 moves (one tube per half loop).
- baseline: the pocket with the fast path and the merged hull runs switched off (a hull per move,
  all unioned in the batch).

Issue 13 (``--issue13``): the 11k-move pocket through ``cutsim simulate`` (STL and report written)
against the floor for the same exact solid: the tool-centre polyline offset by the radius with
round joins (pyclipper, arcs at the same fraction of the tolerance as stock/mill.py), one
extrude, one subtract, the STL; the removed volume of both against the analytic area x depth
(the rectangle grown by r less the scallops at the pass ends). Target: <= 3.0x the floor,
|error| <= 0.1 mm^3. Wall and CPU time (time.process_time) are both shown; ``--repeat N`` runs
floor and cutsim N times interleaved and shows the medians (on a loaded machine the CPU ratio is
the steadier one); ``--no-scaling`` stops after the 11k pocket. Then the scaling: pockets of 10k, 100k and 1M moves, time per move and
peak memory (target: flat within 1.3x, <= 2 GB at 1M).

Targets (issue 4): pocket <= 0.2 ms/move at 10k and >= 10x faster than the baseline; raster
<= 2 ms/move; doubling the moves costs <= 2.2x the time; peak memory <= 2 GB at 50k.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

from bench_thread import write_stl  # the floor's STL, written with manifold3d and numpy only

POCKET_TOL = 0.002  # the default chordal tolerance
RASTER_TOL = float(os.environ.get("CUTSIM_BENCH_RASTER_TOL", "0.002"))
SETUP = """[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 20.0]

[stock]
shape = "box"
x = [{x0}, {x1}]
y = [{y0}, {y1}]
z = [-10.0, 0.0]

[[tool]]
number = 1
kind = "{kind}"
diameter = 6.0
length = 20.0

[simulation]
tolerance = {tol}
"""


def pocket(n: int) -> tuple[str, str]:
    """Zig-zag at Z-2 with ~n constant-Z moves."""
    side = math.sqrt(n * 2 * 0.5)  # passes side/0.5, each side/2 pieces -> n ~ side^2
    piece = 2.0
    per_pass = max(1, round(side / piece))
    passes = max(1, n // (per_pass + 1))
    lines = ["N1 G00 X0 Y0 Z5", "N2 G01 Z-2 F1000"]
    moves = 0
    for p in range(passes):
        y = p * 0.5
        xs = [i * piece for i in range(per_pass + 1)]
        if p % 2:
            xs = xs[::-1]
        if p:
            lines.append(f"Y{y:.3f}")
            moves += 1
        for x in xs[1:]:
            lines.append(f"X{x:.3f}")
            moves += 1
    lines.append("G00 Z20")
    w, h = per_pass * piece, (passes - 1) * 0.5
    setup = SETUP.format(x0=-10.0, x1=w + 10, y0=-10.0, y1=h + 10, kind="endmill", tol=POCKET_TOL)
    return "\n".join(lines) + "\n", setup


def raster(n: int) -> tuple[str, str]:
    """Ball-end raster: lines along X of 1 mm 3D moves over z = -2 + sin(x/7) cos(y/9)."""
    per_line = 100
    nlines = max(1, n // per_line)
    lines = ["N1 G00 X0 Y0 Z5", "N2 G01 Z-2 F1000"]
    for j in range(nlines):
        y = float(j)
        xs = range(per_line + 1) if j % 2 == 0 else range(per_line, -1, -1)
        first = True
        for x in xs:
            z = -2.0 + math.sin(x / 7.0) * math.cos(y / 9.0)
            if first and j:
                lines.append(f"Y{y:.3f} Z{z:.4f}")
            elif not first:
                lines.append(f"X{x:.3f} Z{z:.4f}")
            first = False
    lines.append("G00 Z20")
    setup = SETUP.format(x0=-5.0, x1=per_line + 5.0, y0=-5.0, y1=nlines + 5.0, kind="ballmill", tol=RASTER_TOL)
    return "\n".join(lines) + "\n", setup


def waterline(n: int) -> tuple[str, str]:
    """Ball-end Z-level finish: level loops of radius 20-30 mm as 0.5 mm G01 moves, 0.1 mm apart
    in Z, ~n moves."""
    lines = ["N1 G00 X55 Y0 Z5", "N2 G01 Z-0.1 F1000"]
    moves, level = 0, 0
    while moves < n:
        rad = 25.0 + 5.0 * math.sin(level / 3.0)
        z = -0.1 - 0.1 * level
        k = max(8, round(2 * math.pi * rad / 0.5))
        lines.append(f"X{30 + rad:.4f} Y0 Z{z:.3f}")
        for i in range(1, k + 1):
            a = 2 * math.pi * i / k
            lines.append(f"X{30 + rad * math.cos(a):.4f} Y{rad * math.sin(a):.4f}")
        moves += k + 1
        level += 1
    lines.append("G00 Z20")
    setup = SETUP.format(x0=-5.0, x1=65.0, y0=-40.0, y1=40.0, kind="ballmill", tol=RASTER_TOL)
    return "\n".join(lines) + "\n", setup


def pocket_exact(n: int) -> float:
    """Analytic removed volume of ``pocket(n)``: a disc of radius 3 swept along the zig-zag over
    [0, w] x [0, h] (passes 0.5 apart), 2 mm deep: (w h + 2 r (w + h) + pi r^2 - scallops) x 2."""
    side = math.sqrt(n * 2 * 0.5)
    per_pass = max(1, round(side / 2.0))
    passes = max(1, n // (per_pass + 1))
    w, h, r, hh = per_pass * 2.0, (passes - 1) * 0.5, 3.0, 0.25
    prim = lambda t: (t * math.sqrt(r * r - t * t) + r * r * math.asin(t / r)) / 2  # noqa: E731
    scallop = 2 * (r * hh - prim(hh))
    return (w * h + 2 * r * (w + h) + math.pi * r * r - (passes - 1) * scallop) * 2.0


def warm_imports() -> None:
    """Import what ``cutsim simulate`` loads on first use (the stages, the dialect, the writers), so
    cutsim's time is its work after imports, as the floor's is (it imports its libraries first)."""
    import importlib

    for m in ("cutsim.kinematics", "cutsim.stock", "cutsim.stock.removal", "cutsim.reports", "cutsim.reports.report",
              "cutsim.output", "cutsim.reports.mesh", "cutsim.interp.cnc8x6", "cutsim.interp.isg", "pyclipper"):
        importlib.import_module(m)


def run_cli(n: int) -> dict:
    """``cutsim simulate`` of pocket(n): parse, plan, sweep, subtract, part.stl and report.json."""
    from cutsim.cli import run_simulate

    warm_imports()
    text, setup_text = pocket(n)
    with tempfile.TemporaryDirectory() as d:
        sp, pp = os.path.join(d, "setup.toml"), os.path.join(d, "p.nc")
        with open(sp, "w") as f:
            f.write(setup_text)
        with open(pp, "w") as f:
            f.write(text)
        t0, c0 = time.perf_counter(), time.process_time()
        rc = run_simulate(pp, sp, os.path.join(d, "out"), POCKET_TOL, quiet=True)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
        with open(os.path.join(d, "out", "report.json")) as f:
            rep = json.load(f)
    return {"case": "cli", "rc": rc, "moves": n, "total_s": dt, "cpu_s": cpu, "removed": rep["removed_volume"],
            "error": rep["removed_volume"] - pocket_exact(n),
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def run_floor(n: int) -> dict:
    """The least work for the same solid: polyline offset, extrude, subtract, binary STL."""
    import manifold3d as m3d
    import numpy as np
    import pyclipper

    from cutsim.stock.mill import ARC_FRACTION, GRID

    text, _ = pocket(n)
    t0, c0 = time.perf_counter(), time.process_time()
    pts, x, y = [], 0.0, 0.0
    for line in text.splitlines()[2:-1]:  # the moves at Z-2 (after the plunge at X0 Y0)
        for word in line.split():
            if word[0] == "X":
                x = float(word[1:])
            elif word[0] == "Y":
                y = float(word[1:])
        pts.append((x, y))
    pl = np.array([(0.0, 0.0)] + pts)
    side = math.sqrt(n * 2 * 0.5)
    w = max(1, round(side / 2.0)) * 2.0
    hmax = float(pl[:, 1].max())
    stock = m3d.Manifold.cube((w + 20, hmax + 20, 10.0)).translate((-10.0, -10.0, -10.0))
    off = pyclipper.PyclipperOffset()
    off.ArcTolerance = ARC_FRACTION * POCKET_TOL * GRID
    off.AddPath(np.round(pl * GRID).astype(np.int64), pyclipper.JT_ROUND, pyclipper.ET_OPENROUND)
    reg = m3d.CrossSection([np.asarray(p, dtype=float) / GRID for p in off.Execute(3.0 * GRID)], m3d.FillRule.Positive)
    b = stock.bounding_box()
    stock = stock.refine_to_length(max(b[3] - b[0], b[4] - b[1]) / 64)
    part = stock - m3d.Manifold.extrude(reg, 20.0).translate((0.0, 0.0, -2.0))
    with tempfile.TemporaryDirectory() as d:
        write_stl(part, d, b"floor")
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    removed = stock.volume() - part.volume()
    return {"case": "floor", "moves": n, "total_s": dt, "cpu_s": cpu, "removed": removed, "error": removed - pocket_exact(n),
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def issue13(repeat: int = 1, scaling: bool = True) -> None:
    import statistics

    runs = {"floor": [], "cli": []}
    for _ in range(repeat):  # interleaved, so both see the same load
        for k in runs:
            runs[k].append(sub(k, 11000))
    med = {}
    for k, rs in runs.items():
        med[k] = dict(rs[0], total_s=statistics.median(r["total_s"] for r in rs),
                      cpu_s=statistics.median(r["cpu_s"] for r in rs))
    fl, cl = med["floor"], med["cli"]
    print(f"11k-move pocket ({cl['moves']} moves), medians of {repeat} run(s), load average "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    for r in (fl, cl):
        print(f"  {r['case']:6} {r['total_s']:7.3f} s  cpu {r['cpu_s']:7.3f} s  removed {r['removed']:.4f} mm^3  "
              f"error vs analytic {r['error']:+.4f} mm^3  peak {r['peak_mb']:.0f} MB")
    ratio, ratio_c = cl["total_s"] / fl["total_s"], cl["cpu_s"] / fl["cpu_s"]
    print(f"  cutsim / floor: wall {ratio:.2f}x, cpu {ratio_c:.2f}x "
          f"({'within' if max(ratio, ratio_c) <= 3.0 else 'OVER'} the 3.0x target)")
    if not scaling:
        return
    rows = [sub("pocket", n) for n in (10_000, 100_000, 1_000_000)]
    print(f"scaling ({' '.join(f'{x:.2f}' for x in os.getloadavg())} load average after)")
    print(f"{'moves':>8} {'interp s':>9} {'plan s':>7} {'remove s':>9} {'total s':>8} {'us/move':>8} {'peak MB':>8}")
    for r in rows:
        print(f"{r['moves']:8d} {r['interp_s']:9.2f} {r['plan_s']:7.2f} {r['remove_s']:9.2f} {r['total_s']:8.2f} "
              f"{1000 * r['ms_per_move']:8.1f} {r['peak_mb']:8.0f}")
    print(f"time per move 1M / 10k: {rows[-1]['ms_per_move'] / rows[0]['ms_per_move']:.2f}x")


def design_compare() -> None:
    """compare_design on a ~26k-triangle pocket (300 moves, tolerance 0.002) against the same
    pocket 0.05 mm shallower: once with a gouge (part deeper than the design), once with excess."""
    import cutsim
    from cutsim.reports.measure import compare_design

    parts = []
    for depth in ("-2", "-1.95"):
        text, setup = pocket(300)
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "s.toml"), "w") as f:
                f.write(setup)
            with open(os.path.join(d, "p.nc"), "w") as f:
                f.write(text.replace("Z-2 F1000", f"Z{depth} F1000"))
            parts.append(cutsim.simulate(os.path.join(d, "p.nc"), os.path.join(d, "s.toml"), tolerance=POCKET_TOL))
    a, b = parts
    print(f"design compare, part {a.part.num_tri()} / design {b.part.num_tri()} triangles, load average "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    for name, part, design in (("gouge", a, b), ("excess", b, a)):
        t = time.perf_counter()
        c = compare_design(part.part, design.part, part.stock)
        print(f"  {name:6} {time.perf_counter() - t:6.2f} s  gouge {c['gouge_volume']:.4f} excess {c['excess_volume']:.4f} "
              f"worst {c['worst_deviation']:+.5f} (expected -+0.05 and about 24.2 mm^3)")


def run_case(kind: str, n: int, baseline: bool) -> dict:
    import cutsim
    from cutsim.interp import InterpConfig, interpret
    from cutsim.kinematics import plan
    from cutsim.stock import build_stock, remove

    if baseline:
        from cutsim.stock import mill

        mill.batchable = lambda path: False  # every move: one hull, all unioned in the batch
        mill.is_constant_z = lambda path: False
        mill.MAX_RUN = 2  # no merged runs of poses either: a hull per segment
    text, setup_text = {"pocket": pocket, "raster": raster, "waterline": waterline}[kind](n)
    with tempfile.TemporaryDirectory() as d:
        sp = os.path.join(d, "setup.toml")
        with open(sp, "w") as f:
            f.write(setup_text)
        setup = cutsim.load_setup(sp)
        t0 = time.perf_counter()
        stock = build_stock(setup.stock, setup.tolerance)
        cfg = InterpConfig(dialect="cnc8x6", machine_kind="mill", start=setup.machine.start)
        prog = interpret("bench.nc", text, cfg)
        t1 = time.perf_counter()
        pl = plan(prog, setup.machine, setup.tools, setup.tolerance)
        t2 = time.perf_counter()
        rem = remove(stock, setup.stock, pl.paths, setup.tolerance)
        vol = rem.part.volume()  # forces the lazy boolean
        t3 = time.perf_counter()
    moves = len(prog.moves)
    return {"case": ("baseline" if baseline else kind), "moves": moves, "interp_s": t1 - t0, "plan_s": t2 - t1,
            "remove_s": t3 - t2, "total_s": t3 - t0, "ms_per_move": 1000 * (t3 - t0) / moves,
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "removed": stock.volume() - vol,
            "warnings": len(rem.warnings)}


def sub(kind: str, n: int, baseline: bool = False) -> dict:
    args = [sys.executable, __file__, "--case", kind, str(n)] + (["--as-baseline"] if baseline else [])
    out = subprocess.run(args, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


FLUTE_SETUP = """\
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 10.0]
[stock]
shape = "box"
x = [0.0, 40.0]
y = [0.0, 40.0]
z = [-7.0, 0.0]
[[tool]]
number = 1
kind = "{kind}"
diameter = 6.0
length = {length}
"""


def flute_checks(levels: int = 60) -> None:
    """The flute-length check on a deep cycle (fuzz: SLOT2 64 mm deep in a 7 mm plate with 19 mm
    flutes, 57 s; CYCLE71 34 mm deep with 8 mm flutes, 61 s, over the runner's 30 s): a circular
    slot (chords of G02, a ball-end's 3D moves) or a square (a flat end mill's 2.5D levels) cut at
    depth steps of 0.7 mm down to ``levels`` steps, every step below the flute length a check
    candidate. Passes whose shank lies in an earlier clean pass's are not checked again
    (stock/mill.py ``_shadowed``). Target: a few seconds CPU (the fuzz runner's hang limit is 30 s).
    Measured (23 Nov, shared 2 cores): ball-end 18.6 s before the shadow rule, 4.9 s after; end mill
    1.5 s, 0.6 s; same removed volumes, no warning."""
    import cutsim

    for kind, length, path in (("ballmill", 10.0, "G02 X20. Y10. I0. J10."), ("endmill", 8.0, "G01 X30. Y30.")):
        lines = ["N10 G00 G17 G90 T1 S1000 M03", "G00 X20. Y10. Z2."]
        for k in range(1, levels + 1):
            lines.append(f"G01 Z{-0.7 * k:.3f} F100")
            lines.append(path if kind == "ballmill" else "G01 X30. Y10.\nG01 X30. Y30.\nG01 X10. Y30.\nG01 X10. Y10.\nG01 X20.")
        lines.append("G00 Z20.")
        with tempfile.TemporaryDirectory() as d:
            prog, setup = os.path.join(d, "p.nc"), os.path.join(d, "s.toml")
            with open(prog, "w") as f:
                f.write("\n".join(lines) + "\n")
            with open(setup, "w") as f:
                f.write(FLUTE_SETUP.format(kind=kind, length=length))
            t0 = time.process_time()
            res = cutsim.simulate(prog, setup, tolerance=0.05)
            cpu = time.process_time() - t0
        flutes = sum("flute length" in w["message"] for w in res.warnings)
        print(f"flute checks, {kind} {levels} levels: {cpu:.2f} s CPU, removed {res.report['removed_volume']:.1f} mm^3, "
              f"{flutes} flute warning(s)")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", nargs=2)
    ap.add_argument("--as-baseline", action="store_true")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--issue13", action="store_true")
    ap.add_argument("--design", action="store_true")
    ap.add_argument("--flute", action="store_true")
    ap.add_argument("--repeat", type=int, default=1, help="--issue13: interleaved runs, medians shown")
    ap.add_argument("--no-scaling", action="store_true", help="--issue13: the 11k pocket only")
    ap.add_argument("--baseline", type=int, nargs="*", default=[5000])
    a = ap.parse_args()
    if a.case:
        k, n = a.case[0], int(a.case[1])
        out = run_cli(n) if k == "cli" else run_floor(n) if k == "floor" else run_case(k, n, a.as_baseline)
        print(json.dumps(out))
        return
    if a.issue13:
        issue13(a.repeat, not a.no_scaling)
        return
    if a.design:
        design_compare()
        return
    if a.flute:
        flute_checks()
        return
    sizes = [5000, 10000] if a.quick else [5000, 10000, 20000, 50000]
    rows = [sub("pocket", n) for n in sizes]
    rows += [sub("raster", n) for n in ([5000, 10000] if a.quick else [5000, 10000, 20000, 50000])]
    rows += [sub("waterline", n) for n in (5000, 10000)]
    rows += [sub("pocket", n, baseline=True) for n in a.baseline]
    print(f"{'case':9} {'moves':>6} {'interp s':>9} {'plan s':>7} {'remove s':>9} {'total s':>8} {'ms/move':>8} "
          f"{'x prev':>7} {'peak MB':>8}")
    prev = {}
    for r in rows:
        k = r["case"]
        ratio = f"{r['total_s'] / prev[k]['total_s']:.2f}" if k in prev else "-"
        print(f"{k:9} {r['moves']:6d} {r['interp_s']:9.2f} {r['plan_s']:7.2f} {r['remove_s']:9.2f} {r['total_s']:8.2f} "
              f"{r['ms_per_move']:8.3f} {ratio:>7} {r['peak_mb']:8.0f}")
        prev[k] = r
    for r in rows:
        if r["case"] == "baseline":
            fast = next((x for x in rows if x["case"] == "pocket" and x["moves"] == r["moves"]), None)
            if fast:
                print(f"fast path vs hull-per-move at {r['moves']} moves: {r['total_s'] / fast['total_s']:.1f}x faster "
                      f"(removal alone {r['remove_s'] / fast['remove_s']:.1f}x); removed volume "
                      f"{fast['removed']:.1f} vs {r['removed']:.1f} mm^3")


if __name__ == "__main__":
    main()
