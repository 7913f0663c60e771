"""The milling strategies for feed moves that cut: constant-Z moves of a flat end mill (``Level``),
arcs and helices (``Helix``) and every other 3D feed (``Tube``), each with its sweep and its
estimate.

- level: one 2D offset per Z level, extruded (stock/mill.py), counted exactly from the level's 2D
  outline before it is extruded;
- helix: consecutive arcs on one helix joined and swept exactly (stock/helix.py), or as hulls of
  tool poses where that does not apply;
- tube: consecutive 3D feeds joined into a chain, swept lazily piece by piece when the chain is
  subtracted (tubes along a ball-end mill's planar stretches, stock/tube.py; merged hulls of tool
  poses elsewhere, stock/mill.py), counted as the batch plus their largest piece.
"""
from __future__ import annotations

import functools
import math

import manifold3d as m3d
import numpy as np

from cutsim.base.specs import ToolSpec
from cutsim.kinematics.paths import ArcRun, SpatialPath, segment_angle

from . import budget, helix, mill, tube
from .cuts import Cut
from .strategy import Strategy
from .sweeps import EDGE_STEPS
from .tools import mill_body, tool_error


class Level(Strategy):
    """A flat end mill at constant Z: one 2D offset per Z level, extruded (stock/mill.py). Its moves
    do not end a pending join; the levels are swept when all their moves are known."""

    kind = "level"
    ends_joins = False

    def sweep(self, i: int, path: SpatialPath) -> None:
        self.run.levels.take(i, path)

    def finish(self, n: int) -> None:
        """Each level, counted exactly from its 2D outline before it is extruded."""
        run = self.run
        for lv in run.levels.levels():
            run.work.add(prism_triangles(lv.region()), lv.src, "this Z level of the end mill")
            run.add_cut(lv.index, [lv.solid()])


class _Joining(Strategy):
    """A kind whose moves are held back and joined with the next ones that continue them (the run's
    pending strategy), then swept (counted) together: ``join`` decides, with the run's flush for
    the phase (counting or sweeping) to call when the move starts a new join."""

    ends_joins = False

    def join(self, i: int, path: SpatialPath, flush) -> None:
        raise NotImplementedError

    def estimate(self, i: int, path: SpatialPath) -> None:
        self.join(i, path, self.run.flush_counts)

    def sweep(self, i: int, path: SpatialPath) -> None:
        self.join(i, path, self.run.flush_cuts)


class Helix(_Joining):
    """A mill on an arc or helix, consecutive arcs on one helix joined (stock/helix.py)."""

    kind = "helix"

    def __init__(self, run):
        super().__init__(run)
        self.arc: ArcRun | None = None  # the pending arcs on one helix, joined

    def join(self, i: int, path: SpatialPath, flush) -> None:
        if not (self.arc is not None and self.arc.extend(path)):
            flush()
            self.arc = ArcRun(i, path)
            self.run.hold(self)

    def count_held(self) -> None:
        run, p = self.run, self.arc.path()
        self.arc = None
        verts = body_vertices(p.tool, run.tol)
        run.work.add(arc_triangles(p, run.tol, run.f.top, run.cap, verts), p.src, "this arc or helix")

    def sweep_held(self) -> None:
        run, index, p = self.run, self.arc.index, self.arc.path()
        self.arc = None
        solids = helix.arc_sweep(p, run.tol, run.f.top)
        if solids is not None:
            run.add_cut(index, solids)
        else:
            keys: list = []
            run.add_cut(index, mill.hull_sweep(p.points, p.tool, run.tol, run.cap, keys), keys)


class Tube(_Joining):
    """Any other 3D mill feed, joined with the moves it continues (``mill.Chain``) and swept lazily,
    piece by piece, when it is subtracted (a bounding box suffices until then): a long CAM program
    is never all in memory as solids at once. Counted as the batch of CHUNK_TRIANGLES plus the
    largest piece."""

    kind = "tube"

    def __init__(self, run):
        super().__init__(run)
        self.chain = mill.Chain()
        self.lazy_total, self.lazy_piece, self.lazy_src = 0, 0, None

    def join(self, i: int, path: SpatialPath, flush) -> None:
        if self.run.pending is not self or not self.chain.continues(path):
            flush()
        self.chain.add(i, path)
        self.run.hold(self)

    def count_held(self) -> None:
        run, tool, src = self.run, self.chain.tool, self.chain.src
        for pts in self.chain.take(run.tol):
            n = chain_piece_triangles(pts, tool, run.tol, run.cap, run.work.room() / 4)
            self.lazy_total += n
            self.lazy_piece = max(self.lazy_piece, n)
            if self.lazy_piece > run.work.room():  # one piece is held whole while it is subtracted
                run.work.add(self.lazy_piece, src, "these 3D milling moves (one piece of their sweep)")
        self.lazy_src = self.lazy_src or src

    def counted(self) -> None:
        if self.lazy_src is not None:
            self.run.work.add(min(self.lazy_total, budget.CHUNK_TRIANGLES + self.lazy_piece), self.lazy_src,
                              "the 3D milling moves, swept in batches")

    def sweep_held(self) -> None:
        run, index, tool = self.run, self.chain.index, self.chain.tool
        reach = np.array([tool.diameter / 2.0, tool.diameter / 2.0, 0.0])
        for pts in self.chain.take(run.tol):
            lo, hi = pts.min(axis=0) - reach, pts.max(axis=0) + reach + [0.0, 0.0, tool.length]
            if run.f.meets(lo, hi):
                cut = Cut(index, [], None, lo, hi)
                cut.build = functools.partial(self._piece, cut, pts, tool)
                run.cuts.append(cut)

    def _piece(self, cut: Cut, pts: np.ndarray, tool: ToolSpec) -> list:
        """The solids of one piece of a chain (built when needed), their poses in ``cut.keys``."""
        run, keys = self.run, []
        solids, cut.keys = run.f.clip_keyed(mill.hull_sweep(pts, tool, run.tol, run.cap, keys), keys)
        return solids


def check_resolved(tool: ToolSpec, tol: float) -> None:
    """A milling tool narrower than the chordal tolerance (radius below it) cannot be swept at that
    tolerance: its circle's chords would cross its axis, and the passes a cycle lays side by side
    at such a tool's stepover pile up into tens of thousands of overlapping sweeps that run for
    minutes. An error at the tool's table naming the tolerance that would resolve it."""
    r = tool.diameter / 2.0
    if r < tol:
        raise tool_error(tool, f"the tool's radius {r:g} mm is below the chordal tolerance {tol:g} mm, so its cut "
                               f"cannot be resolved: simulate with a tolerance of at most {r:g} mm "
                               f"([simulation] tolerance or --tolerance)")


@functools.lru_cache(maxsize=1024)
def body_vertices(tool: ToolSpec, tol: float, height: float | None = None) -> int:
    """Vertices of the mill's body (cut off at ``height`` above the tip) that the hulls are built of."""
    return len(mill_body(tool, tol, height)[0])


# A convex hull of N points has at most 2 N - 4 triangles (Euler); a hull of two poses of a mill
# body of V vertices holds about V of them on its surface: measured 1.9 V (ball-end, 2 mm radius,
# 0.001..0.00001 mm) to 3.0 V (flat end mill) triangles. HULL_PER_SEGMENT x V per segment bounds the
# hull sweeps of a polyline (a merged run of poses has no more than its pairs).
HULL_PER_SEGMENT = 3


def chain_piece_triangles(pts: np.ndarray, tool: ToolSpec, tol: float, cap: float, room: float = 0.0) -> int:
    """Triangles of ``mill.hull_sweep(pts, tool, tol, cap)`` without building it: the tubes of a
    ball-end mill's planar stretches (``tube.stretches``, two triangles per profile vertex and
    station) with a body hull at each end, and HULL_PER_SEGMENT x the body's vertices for every
    other segment (bodies cut off where the sweep cuts them: above the stock, over the corner).
    Where that bound exceeds ``room`` (the triangles the budget has left) the segments' merged
    runs (``mill.runs``) are counted instead: one hull of about HULL_PER_SEGMENT x V per run plus
    a ring's worth (4 triangles per ring vertex) for every pose inside it."""
    rc = min(tool.corner_radius, tool.diameter / 2.0)
    tris = 0
    for sub in mill.below_cap(pts, cap):
        top = max(cap, float(sub[:, 2].max()) + rc)
        v = body_vertices(tool, tol, round(min(top - float(sub[:, 2].min()), tool.length), 6))
        segs = len(sub) - 1
        if segs < 1:
            tris += 2 * v
            continue
        closed = bool(np.all(sub[:, 2] + tool.length >= top))
        st = []
        if closed and tube.is_ball(tool) and segs > tube.TUBE_MIN_SEGMENTS:
            z_top = max(cap, float(sub[:, 2].max()) + tool.diameter / 2.0 + 1e-3)
            st = tube.stretches(sub, tool, tol, z_top)
            in_tubes = sum(j - i for i, j in st)
            k = max(2, math.ceil(math.pi / segment_angle(tool.diameter / 2.0, tol)))  # tube.profile's arc
            tris += 2 * (k + 3) * (in_tubes + len(st)) + 2 * v * len({e for s in st for e in s})
            segs -= in_tubes
        if segs == 0:
            continue
        if HULL_PER_SEGMENT * v * segs > room:  # merged runs: count their hulls (as hull_sweep makes them)
            ring = max(8, math.ceil(2 * math.pi / segment_angle(tool.diameter / 2.0, tol)))
            hulls = [(i, j) for i, j in mill.runs(sub, tol, closed) if not any(a <= i and j <= b for a, b in st)]
            tris += sum(HULL_PER_SEGMENT * v + 4 * ring * max(0, j - i - 1) for i, j in hulls)
        else:
            tris += HULL_PER_SEGMENT * v * segs
    return tris


def prism_triangles(region: m3d.CrossSection) -> int:
    """An extruded region: two triangles per side edge and about one per vertex in each cap."""
    return 4 * region.num_vert()



def arc_triangles(path: SpatialPath, tol: float, top: float, cap: float, body: int) -> int:
    """Triangles of ``helix.arc_sweep`` (or of the hull sweep it falls back to) without building it."""
    fine = helix.revolved_triangles(path, tol, top)  # a helix finer than the tolerance: revolved
    if fine is not None:
        return fine
    segs = max(1, sum(len(p) - 1 for p in mill.below_cap(path.points, cap)))
    hulls = 4 * segs * body
    if not helix.applicable(path, tol):
        return hulls
    t = path.tool
    r = t.diameter / 2.0
    h = helix.Helix.of(path.arc)
    a_max = math.asin(r / h.R)
    M = max(8, math.ceil(2 * math.pi / segment_angle(h.R + r, tol)))
    step = 2 * math.pi / M
    J = helix.stations(h.U, a_max, M)
    if J < 1:
        return hulls
    u_a = a_max
    prof = helix.build_profile(h.R, r, min(max(t.corner_radius, 0.0), r), h.k, t.length, tol)
    topc = mill.cap_height(top, tol)

    def z_at(j):
        return float(h.z(u_a + j * step))

    max_len = EDGE_STEPS * math.sqrt(tol * (h.R + r))
    tris = 0
    for pc in helix.plan(J, M, h.k, prof, z_at, topc):
        shifts = [2 * math.pi * h.k * n for n in (pc.n_lo, pc.n_hi)]
        bottom, up = min(shifts), max(shifts)
        zmin = min(z_at(pc.j0), z_at(pc.j1))
        if zmin + bottom + float(prof.lower.min()) > topc:
            continue
        nv = len(helix.profile_polygon(prof, bottom, up, zmin + up + prof.length >= topc, max_len))
        tris += 2 * nv * max(1, pc.j1 - pc.j0) + 2 * nv
    ends = 2 * max(1, math.ceil(2 * a_max / segment_angle(h.R + r, tol)))
    return tris + 4 * ends * body
