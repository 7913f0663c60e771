"""Benchmark: a five-pass M70x1.5 external thread over 57 mm (CNC8x6 G33 passes, after the ISG
example m70x1.5.nc), simulated by ``cutsim simulate`` and by a bare script that does only the
exact manifold3d sweep (extrude + warp_batch) + batch subtract + binary STL write of the same
five passes, no cutsim code. Each case runs in its own subprocess so its peak memory
(resource.getrusage ru_maxrss, which sees manifold3d's C++ allocations) is its own.

    python3 bench/bench_thread.py [--repeat N] [--no-bare] [TOL ...]   # default: 0.01 0.001
    python3 bench/bench_thread.py --wide [TOL ...]                     # default: 0.002

Prints, per tolerance: wall time and CPU time (time.process_time, all threads) of the work (after
imports) and wall time of the whole process, triangle count, peak RSS, and the ratios cutsim / bare
and cutsim / floor. With ``--repeat N`` the cases run N times interleaved (floor, cutsim, floor,
...) and the medians are shown: on a loaded machine the CPU ratio is the steadier one.

- bare: one exact sweep per pass, all subtracted in one batch (what cutsim did before issue 13).
- floor: the least work for the same exact solid (issue 13): the passes lie on one helix, so the
  union of their sweeps is the sweep of the union of their profiles: the profiles unioned in 2D,
  ONE sweep, plus the ring the G00 X72 retracts at Z48 cut with the spindle turning (revolved
  once, as cutsim does), one subtract, STL: the same solid as cutsim's. Target: cutsim <= 2.0x
  the floor at 1 um.
- wide (``--wide``): one G33 pass whose profile is wider than its lead (lead 0.1 at X28 on a
  30 mm bar, a 60 degree tool 1.05 mm deep: 12 leads wide), swept as one turn of the profile's
  lead-shifted copies (stock/threads.py fold); before that it was refused at about 12.5M
  estimated triangles. Shows the time and the part's triangles, or the refusal.
- isg: ``cutsim simulate`` of the ISG manual's example (shared/examples/isg-lathe/m70x1.5.nc:
  four passes and a spring pass through a subprogram), when that file is there.
"""
from __future__ import annotations

import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

PASSES = (69.54, 69.08, 68.62, 68.16, 68.16)  # diameters, as in the ISG example
LEAD, Z_START, Z_END = 1.5, 105.0, 48.0
BAR_D, BAR_Z = 70.0, (0.0, 100.0)
ANGLE, HEIGHT = 60.0, 10.0  # thread tool: included angle, profile height (cutsim's default)

PROGRAM = "N10 G00 G95 T1 M03 S400 X72. Z105.\n" + "".join(
    f"N{20 + 10 * i} G00 X{d:.2f}\nN{21 + 10 * i} G33 Z48. F1.5 I0.\nN{22 + 10 * i} G00 X72.\nN{23 + 10 * i} Z105.\n"
    for i, d in enumerate(PASSES)) + "N90 M05 X150. Z200.\n"

SETUP = f"""[machine]
kind = "lathe"
dialect = "cnc8x6"
start = [150.0, 0.0, 200.0]

[stock]
shape = "cylinder"
diameter = {BAR_D}
z = [{BAR_Z[0]}, {BAR_Z[1]}]

[[tool]]
number = 1
kind = "thread"
angle = {ANGLE}
"""


def warm_imports() -> None:
    """Import what ``cutsim simulate`` loads on first use (the stages, the dialect, the writers), so
    cutsim's time is its work after imports, as the floor's is (it imports its libraries first)."""
    import importlib

    for m in ("cutsim.kinematics", "cutsim.stock", "cutsim.stock.removal", "cutsim.reports", "cutsim.reports.report",
              "cutsim.output", "cutsim.reports.mesh", "cutsim.interp.cnc8x6", "cutsim.interp.isg", "pyclipper"):
        importlib.import_module(m)


def write_stl(part, folder: str, header: bytes) -> None:
    """``folder``/part.stl: the binary STL of ``part`` as the bare scripts write it, with manifold3d
    and numpy only (no cutsim code: the scripts are the floor cutsim is measured against)."""
    import numpy as np

    mesh = part.to_mesh()
    v = np.asarray(mesh.vert_properties, dtype=np.float32)[:, :3]
    f_ = np.asarray(mesh.tri_verts, dtype=np.int64)
    tri = v[f_]
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-30)
    rec = np.zeros(len(f_), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["v"] = nrm, tri
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "part.stl"), "wb") as fh:
        fh.write(header.ljust(80, b" ") + np.uint32(len(f_)).tobytes() + rec.tobytes())


def case_cutsim(tol: float, work: str) -> dict:
    from cutsim.cli import run_simulate

    warm_imports()

    prog, setup = os.path.join(work, "m70.nc"), os.path.join(work, "m70.toml")
    with open(prog, "w") as f:
        f.write(PROGRAM)
    with open(setup, "w") as f:
        f.write(SETUP)
    t = time.perf_counter()
    rc = run_simulate(prog, setup, os.path.join(work, "out"), tol, quiet=True)
    dt = time.perf_counter() - t
    with open(os.path.join(work, "out", "report.json")) as f:
        rep = json.load(f)
    return {"rc": rc, "time": dt, "triangles": _stl_triangles(os.path.join(work, "out", "part.stl")),
            "removed": rep["removed_volume"]}


def case_bare(tol: float, work: str) -> dict:
    import manifold3d as m3d
    import numpy as np

    t = time.perf_counter()
    R = BAR_D / 2
    seg = lambda r: 2 * math.acos(1 - tol / r)  # noqa: E731  largest angle with chord error tol
    n = max(8, 4 * math.ceil(math.ceil(2 * math.pi / seg(R)) / 4))
    bar = m3d.Manifold.revolve(m3d.CrossSection([np.array([[0, BAR_Z[0]], [R, BAR_Z[0]], [R, BAR_Z[1]], [0, BAR_Z[1]]])]),
                               circular_segments=n)
    clip = R + max(10 * tol, 0.05)
    half = math.radians(ANGLE) / 2
    turns = (Z_START - Z_END) / LEAD
    cuts = []
    for d in PASSES:
        r0 = d / 2
        h = min(HEIGHT, clip - r0)
        w = h * math.tan(half)
        prof = m3d.CrossSection([np.array([[0.0, 0.0], [h, -w], [h, w]])])
        steps = math.ceil(turns * 2 * math.pi / seg(r0 + h))
        solid = m3d.Manifold.extrude(prof, 1.0, n_divisions=steps - 1)

        def warp(p, r0=r0):  # M03 feeding -Z: right-hand, phi = -2*pi*turns*t
            t_ = np.clip(p[:, 2], 0.0, 1.0)
            phi = -2 * math.pi * turns * t_
            rr = r0 + p[:, 0]
            z = Z_START + (Z_END - Z_START) * t_ + p[:, 1]
            return np.column_stack([rr * np.cos(phi), rr * np.sin(phi), z])

        cuts.append(solid.warp_batch(warp))
    part = m3d.Manifold.batch_boolean([bar] + cuts, m3d.OpType.Subtract)
    write_stl(part, os.path.join(work, "bare"), b"bare")
    dt = time.perf_counter() - t
    return {"rc": 0, "time": dt, "triangles": part.num_tri(), "removed": bar.volume() - part.volume()}


def case_floor(tol: float, work: str) -> dict:
    import manifold3d as m3d
    import numpy as np

    t = time.perf_counter()
    R = BAR_D / 2
    seg = lambda r: 2 * math.acos(1 - tol / r)  # noqa: E731  largest angle with chord error tol
    n = max(8, 4 * math.ceil(math.ceil(2 * math.pi / seg(R)) / 4))
    bar = m3d.Manifold.revolve(m3d.CrossSection([np.array([[0, BAR_Z[0]], [R, BAR_Z[0]], [R, BAR_Z[1]], [0, BAR_Z[1]]])]),
                               circular_segments=n)
    clip = R + max(10 * tol, 0.05)
    half = math.radians(ANGLE) / 2
    turns = (Z_START - Z_END) / LEAD
    profs = []
    for d in PASSES:  # each pass's profile in the (r, z) half-plane, absolute radius
        r0 = d / 2
        h = min(HEIGHT, clip - r0)
        w = h * math.tan(half)
        profs.append(m3d.CrossSection([np.array([[r0, 0.0], [r0 + h, -w], [r0 + h, w]])]))
    prof = m3d.CrossSection.batch_boolean(profs, m3d.OpType.Add)
    rin = prof.bounds()[0]
    steps = math.ceil(turns * 2 * math.pi / seg(prof.bounds()[2]))
    solid = m3d.Manifold.extrude(prof.translate((-rin, 0.0)), 1.0, n_divisions=steps - 1)

    def warp(p):  # M03 feeding -Z: right-hand, phi = -2*pi*turns*t
        t_ = np.clip(p[:, 2], 0.0, 1.0)
        phi = -2 * math.pi * turns * t_
        rr = rin + p[:, 0]
        z = Z_START + (Z_END - Z_START) * t_ + p[:, 1]
        return np.column_stack([rr * np.cos(phi), rr * np.sin(phi), z])

    # the G00 X72 retracts at Z48 with the spindle turning: the profile's hull between r0 and
    # X72, clipped at the clip radius, revolved (as cutsim does; the groove's end ring)
    rings = []
    for d in PASSES:
        r0 = d / 2
        tri = lambda r: np.array([[r, Z_END], [r + HEIGHT, Z_END - HEIGHT * math.tan(half)],  # noqa: E731
                                  [r + HEIGHT, Z_END + HEIGHT * math.tan(half)]])
        rings.append(m3d.CrossSection.hull_points(np.vstack([tri(r0), tri(36.0)])))
    ring = m3d.CrossSection.batch_boolean(rings, m3d.OpType.Add) ^ m3d.CrossSection.square((clip, 1000.0)).translate((0.0, -500.0))
    part = m3d.Manifold.batch_boolean([bar, solid.warp_batch(warp), m3d.Manifold.revolve(ring, circular_segments=n)],
                                      m3d.OpType.Subtract)
    write_stl(part, os.path.join(work, "floor"), b"floor")
    dt = time.perf_counter() - t
    return {"rc": 0, "time": dt, "triangles": part.num_tri(), "removed": bar.volume() - part.volume()}


ISG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "examples", "isg-lathe",
                   "m70x1.5.nc")
ISG = os.environ.get("CUTSIM_BENCH_ISG", ISG if os.path.exists(ISG) else "/work/shared/examples/isg-lathe/m70x1.5.nc")


def case_isg(tol: float, work: str) -> dict:
    from cutsim.cli import run_simulate

    warm_imports()

    t = time.perf_counter()
    rc = run_simulate(ISG, ISG[:-3] + ".toml", os.path.join(work, "out"), tol, quiet=True)
    dt = time.perf_counter() - t
    with open(os.path.join(work, "out", "report.json")) as f:
        rep = json.load(f)
    return {"rc": rc, "time": dt, "triangles": _stl_triangles(os.path.join(work, "out", "part.stl")),
            "removed": rep["removed_volume"]}


WIDE_PROGRAM = "N10 G00 G95 T1 S1000 M03\nN20 G00 X28. Z3.\nN30 G33 Z-19. I0. F0.1\nN40 G00 X32.\n"
WIDE_SETUP = """[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [40.0, 0.0, 20.0]

[stock]
shape = "cylinder"
diameter = 30.0
z = [-30.0, 0.0]

[[tool]]
number = 1
kind = "thread"
angle = 60.0
"""


def case_wide(tol: float, work: str) -> dict:
    import cutsim

    prog, setup = os.path.join(work, "wide.nc"), os.path.join(work, "wide.toml")
    with open(prog, "w") as f:
        f.write(WIDE_PROGRAM)
    with open(setup, "w") as f:
        f.write(WIDE_SETUP)
    t = time.perf_counter()
    try:
        r = cutsim.simulate(prog, setup, tolerance=tol)
    except cutsim.CutsimError as e:
        return {"rc": 2, "time": time.perf_counter() - t, "triangles": 0, "removed": 0.0, "error": e.message}
    return {"rc": 0, "time": time.perf_counter() - t, "triangles": r.part.num_tri(), "removed": r.report["removed_volume"]}


def _stl_triangles(path: str) -> int:
    with open(path, "rb") as f:
        f.seek(80)
        return int.from_bytes(f.read(4), "little")


def child(kind: str, tol: float) -> None:
    import manifold3d  # noqa: F401  imports before the clock, as for every case
    import numpy  # noqa: F401

    with tempfile.TemporaryDirectory() as work:
        c = time.process_time()
        out = {"cutsim": case_cutsim, "bare": case_bare, "floor": case_floor, "isg": case_isg,
               "wide": case_wide}[kind](tol, work)
        out["cpu"] = time.process_time() - c
    out["maxrss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(json.dumps(out))


def wide(tols: list[float]) -> None:
    print("one G33 pass 12 leads wide (lead 0.1 over 22 mm at X28, 60 degree tool)")
    for tol in tols:
        p = subprocess.run([sys.executable, __file__, "--child", "wide", str(tol)], capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"wide at {tol} failed:\n{p.stderr}")
        r = json.loads(p.stdout.strip().splitlines()[-1])
        if r["rc"]:
            print(f"{tol:>8g}  refused after {r['time']:.2f} s: {r['error']}")
        else:
            print(f"{tol:>8g}  {r['time']:.2f} s, cpu {r['cpu']:.2f} s, {r['triangles']} triangles, removed "
                  f"{r['removed']:.3f} mm^3, peak {r['maxrss_mb']:.0f} MB")


def main(tols: list[float], repeat: int = 1, bare: bool = True) -> None:
    import statistics

    print(f"five-pass M70x1.5 over 57 mm ({len(PASSES)} G33 passes), {os.cpu_count()} cpus, "
          f"medians of {repeat} run(s)")
    print(f"{'tol mm':>8} {'case':>7} {'work s':>8} {'cpu s':>8} {'proc s':>8} {'triangles':>10} {'peak MB':>8} "
          f"{'removed mm3':>12}")
    for tol in tols:
        runs: dict[str, list[dict]] = {}
        kinds = (("bare",) if bare else ()) + ("floor", "cutsim") + (("isg",) if os.path.exists(ISG) else ())
        for _ in range(repeat):
            for kind in kinds:
                t = time.perf_counter()
                p = subprocess.run([sys.executable, __file__, "--child", kind, str(tol)], capture_output=True, text=True)
                wall = time.perf_counter() - t
                if p.returncode != 0:
                    sys.exit(f"{kind} at {tol} failed:\n{p.stderr}")
                r = json.loads(p.stdout.strip().splitlines()[-1])
                r["wall"] = wall
                runs.setdefault(kind, []).append(r)
        res = {}
        for kind, rs in runs.items():
            r = dict(rs[0])
            for key in ("time", "cpu", "wall", "maxrss_mb"):
                r[key] = statistics.median(x[key] for x in rs)
            res[kind] = r
            print(f"{tol:>8g} {kind:>7} {r['time']:>8.2f} {r['cpu']:>8.2f} {r['wall']:>8.2f} {r['triangles']:>10d} "
                  f"{r['maxrss_mb']:>8.0f} {r['removed']:>12.3f}")
        if "bare" in res:
            ratio = res["cutsim"]["time"] / res["bare"]["time"]
            ratio_w = res["cutsim"]["wall"] / res["bare"]["wall"]
            print(f"{tol:>8g}   ratio cutsim/bare: work {ratio:.2f}x, whole process {ratio_w:.2f}x")
        for k in ("cutsim", "isg"):
            if k in res:
                rf = res[k]["time"] / res["floor"]["time"]
                rc = res[k]["cpu"] / res["floor"]["cpu"]
                print(f"{tol:>8g}   ratio {k}/floor: work {rf:.2f}x, cpu {rc:.2f}x "
                      f"({'within' if max(rf, rc) <= 2 else 'OVER'} the 2x target); removed volume "
                      f"{res[k]['removed'] - res['floor']['removed']:+.4f} mm^3 against the floor")
        print(f"load average: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child(sys.argv[2], float(sys.argv[3]))
    else:
        import argparse

        ap = argparse.ArgumentParser()
        ap.add_argument("tols", nargs="*", type=float)
        ap.add_argument("--repeat", type=int, default=1)
        ap.add_argument("--no-bare", action="store_true", help="skip the one-sweep-per-pass script")
        ap.add_argument("--wide", action="store_true", help="only the single pass wider than its lead")
        a = ap.parse_args()
        if a.wide:
            wide(a.tols or [0.002])
        else:
            main(a.tols or [0.01, 0.001], a.repeat, not a.no_bare)
