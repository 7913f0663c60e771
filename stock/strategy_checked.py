"""The strategies for moves checked against the stock as it is when they run, each with its sweep
and its estimate:

- hull: a move swept on its own: a rapid, a plunge of a tool that cannot cut at its centre, a
  lathe tool with the spindle stopped (one hull per segment); its collisions are checked;
- gauge: a move with no tool in the spindle: nothing swept, its gauge point checked against the
  stock (stock/gauge.py, stock/collisions.py).

Both end the 2.5D levels: no level may span them, so the checks see exactly the cuts before them.
"""
from __future__ import annotations

import math

from cutsim.base.specs import ToolSpec
from cutsim.kinematics.paths import GaugePath, SpatialPath, segment_angle

from . import mill
from .cuts import Cut
from .mill_checks import check_solids
from .strategy import Strategy
from .strategy_milling import body_vertices
from .sweeps import spatial_hulls
from .tools import lathe_body


class Hull(Strategy):
    """A move swept on its own and checked against the stock as it is then."""

    kind = "hull"

    def __init__(self, run):
        super().__init__(run)
        self.bodies: dict[int, list] = {}  # lathe tool number -> its body (mills: stock/mill.py builds its own)

    def body(self, tool: ToolSpec) -> list:
        if tool.number not in self.bodies:
            self.bodies[tool.number] = lathe_body(tool, self.run.tol)
        return self.bodies[tool.number]

    def estimate(self, i: int, path: SpatialPath) -> None:
        run, tool = self.run, path.tool
        if tool.is_lathe_tool:  # spindle stopped: a hull per segment and convex piece of the plate
            verts = sum(len(p) for p in lathe_body(tool, run.tol))
            run.work.add(2 * 4 * (len(path.points) - 1) * verts, path.src, "this move with the spindle stopped")
            return
        segs = sum(len(p) - 1 for p in mill.below_cap(path.points, run.cap)) if len(path.points) > 1 else 1
        if mill.is_flat(tool) and mill.is_constant_z(path):
            k = max(2, math.ceil(math.pi / segment_angle(tool.diameter / 2.0, run.tol)))
            tris = 4 * 2 * (k + 1) * max(1, len(path.points) - 1)
        else:
            tris = 4 * segs * body_vertices(tool, run.tol)
        run.work.add(2 * tris, path.src, "this move (its sweep and its collision check)")

    def sweep(self, i: int, path: SpatialPath) -> None:
        run = self.run
        run.levels.cut_run()  # a checked move ends the 2.5D levels: no level may span it
        if path.tool.is_lathe_tool:
            cut = run.add_cut(i, spatial_hulls(path, self.body(path.tool)))
            if cut is not None:
                run.checks.append((cut, path))
            return
        keys: list = []
        cut = run.add_cut(i, mill.sweep(path, run.tol, run.cap, keys), keys)
        if cut is not None:  # checked with the tool shrunk by a few tolerances (stock/mill_checks.py)
            shrunk = run.f.clip(check_solids(path, run.tol, run.cap))
            run.checks.append((Cut(i, shrunk, None, cut.lo, cut.hi), path))


class Gauge(Strategy):
    """A move with no tool in the spindle: nothing swept (nothing counted); its gauge point is
    checked against the stock as it is then (``moves``, stock/collisions.py)."""

    kind = "gauge"

    def __init__(self, run):
        super().__init__(run)
        self.moves: list[tuple[int, GaugePath]] = []

    def sweep(self, i: int, path: GaugePath) -> None:
        self.run.levels.cut_run()  # no 2.5D level spans it: the earlier cuts are those before it
        self.moves.append((i, path))
