"""The [stock] table: a cylinder, a revolved profile, a box or a mesh file (docs/setup.md)."""
from __future__ import annotations

import os

from cutsim.base.specs import StockSpec

from .limits import COORD_MAX, MIN_SIZE
from .reader import Locator, Reader
from .simulation import Simulation


def read_stock(loc: Locator, s: Reader, sim: Simulation) -> tuple[StockSpec, tuple[int, int]]:
    """The [stock] table and where its size is written (the line build_stock's errors name).
    Ranges: coordinates within COORD_MAX, sizes at least MIN_SIZE, and the solid at the
    setup's tolerance within [simulation] max_triangles."""
    from cutsim.kinematics.paths import circle_segments
    from cutsim.stock.build import load_mesh_stock

    tol, max_tri = sim.tolerance, sim.max_triangles
    shape = s.get("shape", str, check=lambda v: v in ("cylinder", "revolve", "box", "mesh"),
                  why="must be cylinder, revolve, box or mesh")
    key = {"cylinder": "diameter", "revolve": "profile", "box": "x", "mesh": "path"}[shape]
    if shape == "cylinder":
        d = s.get("diameter", float, check=lambda v: MIN_SIZE <= v <= 2 * COORD_MAX,
                  why=f"must be from {MIN_SIZE:g} to {2 * COORD_MAX:g} mm")
        z = s.pair("z")
        s.size("z", *z)
        spec = StockSpec(shape, diameter=d, z=z)
    elif shape == "revolve":
        prof = s.points("profile")
        if any(r < 0 for r, _ in prof):
            raise s.fail("profile", "radii must not be negative")
        if _area(prof) == 0:
            raise s.fail("profile", "the outline encloses no area")
        if max(r for r, _ in prof) < MIN_SIZE or max(z for _, z in prof) - min(z for _, z in prof) < MIN_SIZE:
            raise s.fail("profile", f"the stock must be at least {MIN_SIZE:g} mm in radius and in height")
        spec = StockSpec(shape, profile=prof)
    elif shape == "box":
        box = {a: s.pair(a) for a in ("x", "y", "z")}
        for a, (lo, hi) in box.items():
            s.size(a, lo, hi)
        spec = StockSpec(shape, **box)
    else:
        rel = s.get("path", str)
        path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(loc.path)), rel))
        if not os.path.isfile(path):
            raise s.fail("path", f"no such file: {path}")
        spec = StockSpec(shape, path=path)
    s.done()
    where = loc.locate("stock", key, None)
    if shape == "mesh":  # read and checked now, so its errors name the path key's line (cached)
        load_mesh_stock(spec.path, loc.path, where=where, max_triangles=max_tri, max_coord=COORD_MAX,
                        min_size=MIN_SIZE)
    elif shape in ("cylinder", "revolve"):
        outline = 4 if shape == "cylinder" else len(spec.profile)
        tris = 2 * outline * circle_segments(spec.bounds()[1][0], tol)
        if tris > max_tri:
            raise s.fail(key, f"at the tolerance {tol:g} mm the stock would have about {tris:,} triangles, "
                              f"more than [simulation] max_triangles = {max_tri:,}")
    return spec, where


def _area(pts) -> float:
    return 0.5 * abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1])))

