"""Fine helix benchmark: a CNC8x6 mill helix of 20,001 circles rising 0.001 mm per turn (below the
tolerance 0.005) through ``cutsim simulate``, against its floor.

    python bench/bench_helix.py                      # the reproducer and the floor
    python bench/bench_helix.py --turns 2000         # a shorter helix
    python bench/bench_helix.py --cutsim /path/to/other/venv/bin/cutsim   # another build (before/after)
    python bench/bench_helix.py --deep               # also: a ball about its own axis, 20 mm deep, 12 mm flutes

The reproducer: a 10 mm end mill plunges to Z-20 at X0 Y0, then ``N50 G09 G02 X0 Y0 I100 G73 L50
Q20000`` and a half circle to X200 (the groove: the annulus 95..105 about (100, 0), 20 mm deep).
The floor is the least work the same exact result needs: that annulus as ONE revolved region
(segments at the tolerance, as cutsim's revolution) and ONE boolean with the plate, no program,
no report. cutsim's time is the whole command (interpretation, planning, sweep, subtract, STL and
report written); wall and CPU seconds (the child's user + system) are shown, the removed volumes
of both against the annulus pi (105^2 - 95^2) x 20.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

SETUP = """[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 50.0]

[stock]
shape = "box"
x = [-20.0, 220.0]
y = [-120.0, 120.0]
z = [-30.0, 0.0]

[[tool]]
number = 1
kind = "{kind}"
diameter = 10.0
length = {length}

[simulation]
tolerance = 0.005
"""
PROGRAM = """N5 G00 X{x0} Y0 Z5.
N6 G01 Z{z0} F1000
N10 Z{pitch} G10
N50 G09 G02 X{x0} Y0 I{radius} G73 L50 Q{q}
N60 G98
N80 G00 Z30.
"""
HALF = "N55 X{x1} Y0 I{radius}\n"


def run_cutsim(exe: str, program: str, setup: str) -> dict:
    """Wall and CPU seconds of one ``cutsim simulate`` and its report."""
    with tempfile.TemporaryDirectory() as tmp:
        prog, stp, out = (os.path.join(tmp, n) for n in ("p.nc", "s.toml", "out"))
        with open(prog, "w") as f:
            f.write(program)
        with open(stp, "w") as f:
            f.write(setup)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run([exe, "simulate", prog, "--setup", stp, "--out", out, "-q"],
                              capture_output=True, text=True)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            raise SystemExit(f"cutsim failed ({proc.returncode}): {proc.stderr.strip()}")
        with open(os.path.join(out, "report.json")) as f:
            rep = json.load(f)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall": wall, "cpu": cpu, "removed": rep["removed_volume"], "warnings": len(rep["warnings"])}


def floor(tol: float, R: float = 100.0, r: float = 5.0, depth: float = 20.0) -> dict:
    """The annulus R - r .. R + r, ``depth`` deep, as one revolved region and one boolean."""
    import manifold3d as m3d

    from cutsim.kinematics.paths import circle_segments

    t0, c0 = time.perf_counter(), time.process_time()
    plate = m3d.Manifold.cube((240.0, 240.0, 30.0)).translate((-20.0, -120.0, -30.0))
    n = circle_segments(R + r, tol)
    step = 2 * math.pi / n
    s = math.sqrt(step / math.sin(step))  # area-true segments, as cutsim revolves
    region = m3d.CrossSection([[(s * (R - r), -depth), (s * (R + r), -depth), (s * (R + r), 1.0),
                                (s * (R - r), 1.0)]])
    ring = m3d.Manifold.revolve(region, circular_segments=n).translate((R, 0.0, 0.0))
    part = m3d.Manifold.batch_boolean([plate, ring], m3d.OpType.Subtract)
    removed = plate.volume() - part.volume()
    return {"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0, "removed": removed}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cutsim", default=shutil.which("cutsim") or "cutsim", help="the cutsim command to time")
    ap.add_argument("--turns", type=int, default=20000, help="G73 repeats Q (the helix runs Q + 1 circles)")
    ap.add_argument("--deep", action="store_true", help="also a ball about its own axis below its flutes")
    args = ap.parse_args()
    q = args.turns
    pitch = 0.001
    prog = PROGRAM.format(x0="0", z0="-20.", pitch=pitch, q=q, radius="100")
    prog = prog.replace("N60 G98", HALF.format(x1="200.", radius="100").rstrip() + "\nN60 G98")
    depth = 20.0
    print(f"reproducer: {q + 1} circles of R100 rising {pitch} per turn from Z-20, 10 mm end mill, tol 0.005")
    got = run_cutsim(args.cutsim, prog, SETUP.format(kind="endmill", length=40.0))
    exact = math.pi * (105.0 ** 2 - 95.0 ** 2) * depth
    print(f"  cutsim  {got['wall']:8.2f} s wall {got['cpu']:8.2f} s cpu  removed {got['removed']:.3f} mm^3 "
          f"(annulus x 20: {exact:.3f})")
    fl = floor(0.005)
    print(f"  floor   {fl['wall']:8.2f} s wall {fl['cpu']:8.2f} s cpu  removed {fl['removed']:.3f} mm^3 "
          f"(one revolved region, one boolean)")
    print(f"  ratio   {got['wall'] / max(fl['wall'], 1e-9):8.1f} x wall")
    if args.deep:
        prog = PROGRAM.format(x0="-3.", z0="0.", pitch=-pitch, q=q, radius="3.")
        got = run_cutsim(args.cutsim, prog, SETUP.format(kind="ballmill", length=12.0).replace(
            'x = [-20.0, 220.0]\ny = [-120.0, 120.0]', 'x = [-20.0, 20.0]\ny = [-20.0, 20.0]'))
        print(f"deep: ball R5 on a helix of R3 about its own axis, {q + 1} turns down {pitch}, flutes 12")
        print(f"  cutsim  {got['wall']:8.2f} s wall {got['cpu']:8.2f} s cpu  removed {got['removed']:.3f} mm^3, "
              f"{got['warnings']} warning(s)")


if __name__ == "__main__":
    sys.exit(main())
