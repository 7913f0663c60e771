"""Material removal: every path's swept solid, subtracted from the stock in one batch.

Each path gets one sweep strategy (``sweep_kind``: screw, revolve, hull, level, helix, tube); the
table STRATEGIES names, per kind, the sweep (``_Sweeper``) and the estimate of its triangles
(``Work``), which runs over all paths before anything is built.

Order does not change the final part (subtraction commutes), so all solids are built first and
removed with one ``batch_boolean``. Order matters only for the warnings: a rapid (G00), or a cut
with the spindle stopped, is reported when it removes material that is still there at that moment,
i.e. from the stock minus the earlier cuts that overlap it.
"""
from __future__ import annotations

import bisect
import functools
import math
from dataclasses import dataclass, field, fields
from typing import Callable

import manifold3d as m3d
import numpy as np

from cutsim.interp.errors import CutsimError
from cutsim.kinematics.paths import (ArcRun, GaugePath, PlanarPath, ScrewPath, SpatialPath, circle_segments,
                                     segment_angle)

from . import axial, gauge, helix, mill, threads, tube
from .build import DEFAULT_MAX_TRIANGLES, stock_outline
from cutsim.base.specs import StockSpec, ToolSpec
from .sweeps import (EDGE_STEPS, MAX_CHUNK_DEGREES, clipped_profile, edge_pieces, inner_trim, planar_region,
                     screw_sweep, screw_twist, spatial_hulls)
from .tools import check_tool, lathe_body, lathe_profile, mill_body, tool_error

# A collision smaller than this is numerical noise between two discretisations of one surface.
MIN_COLLISION_VOLUME = 1e-3  # mm^3

DEBRIS_VOLUME = 1e-6  # mm^3: a shell this small is a numerical artefact, not material

Progress = Callable[[str, int, int], None]


@dataclass
class Removal:
    part: m3d.Manifold
    warnings: list = field(default_factory=list)  # (Src, message)
    solids: int = 0  # swept solids subtracted


@dataclass
class _Cut:
    index: int
    solids: list  # Manifolds (screw, spatial) ...
    region: m3d.CrossSection | None  # ... or a 2D region to revolve
    lo: np.ndarray
    hi: np.ndarray
    near: Callable[[float, float], list] | None = None  # the solids restricted to heights z0..z1
    build: Callable[[], list] | None = None  # solids built when needed, not kept (long mill chains)
    keys: list | None = None  # per solid its mill.Poses (a hull of tool poses) or None, as last built

    def get(self) -> list:
        return self.build() if self.build is not None else self.solids


def _bbox(solids: list[m3d.Manifold]):
    los, his = [], []
    for s in solids:
        b = s.bounding_box()
        los.append(b[:3])
        his.append(b[3:])
    return np.min(los, axis=0), np.max(his, axis=0)


def _overlap(lo1, hi1, lo2, hi2) -> bool:
    return bool(np.all(lo1 <= hi2) and np.all(lo2 <= hi1))


def _box_overlap(lo1, hi1, lo2, hi2) -> float:
    """Volume of the intersection of two boxes."""
    return float(np.prod(np.maximum(np.minimum(hi1, hi2) - np.maximum(lo1, lo2), 0.0)))


@dataclass
class _Frame:
    """Where the stock is: its box, the radius a lathe profile is clipped at (the stock's largest
    radius plus a margin), its outline of revolution (None for a box or a mesh) and the segment
    count of its circles, so revolved cuts line up with the stock's faces."""
    lo: np.ndarray
    hi: np.ndarray
    r_clip: float
    margin: float
    outline: np.ndarray | None
    outline_cs: m3d.CrossSection | None
    nseg: int

    @property
    def top(self) -> float:
        return float(self.hi[2])

    def meets(self, lo, hi) -> bool:
        return _overlap(lo, hi, self.lo, self.hi)

    def clip_keyed(self, solids: list[m3d.Manifold], keys: list) -> tuple[list[m3d.Manifold], list]:
        """``clip`` with a key per solid kept beside it (a clipped hull still lies inside any hull
        its whole lay in, up to what lies beyond the box, where there is no stock)."""
        out, kept = [], []
        for s, k in zip(solids, keys):
            c = self.clip([s])
            if c:
                out.append(c[0])
                kept.append(k)
        return out, kept

    def clip(self, solids: list[m3d.Manifold]) -> list[m3d.Manifold]:
        """``solids`` cut off by the planes of the stock's box (plus the margin) they reach beyond by
        more than the box's own size: the stock lies inside the box, so what it loses, and what a
        check finds, are unchanged. A tool far bigger than the stock (a 10 m ball-end over a 30 mm
        plate: hulls 530 mm wide with thousands of triangles, 3M in all, 21 s in the subtract)
        then keeps only the few faces over the stock."""
        lo, hi = self.lo - self.margin, self.hi + self.margin
        reach = CLIP_REACH * float(np.max(hi - lo))
        out = []
        for s in solids:
            b = s.bounding_box()
            for ax in range(3):
                if b[ax] < lo[ax] - reach:
                    s = s.trim_by_plane(tuple(float(k == ax) for k in range(3)), float(lo[ax]))
                if b[ax + 3] > hi[ax] + reach:
                    s = s.trim_by_plane(tuple(-float(k == ax) for k in range(3)), -float(hi[ax]))
            if not s.is_empty():
                out.append(s)
        return out

    def revolve(self, region: m3d.CrossSection) -> m3d.Manifold:
        return m3d.Manifold.revolve(region, circular_segments=self.nseg)


CLIP_REACH = 1.0  # sweeps reaching beyond the stock's box by more than this many times its size are cut off


def _frame(stock: m3d.Manifold, spec: StockSpec, tol: float) -> _Frame:
    sb = stock.bounding_box()
    slo, shi = np.array(sb[:3]), np.array(sb[3:])
    rmax = float(max(np.hypot(slo[0], slo[1]), np.hypot(shi[0], shi[1]), np.hypot(slo[0], shi[1]),
                     np.hypot(shi[0], slo[1])))
    margin = max(10 * tol, 0.05)
    outline = stock_outline(spec)
    # revolve cuts with the stock's own segment count (its true radius, not the bounding box's
    # corner): the faces of cut and stock then line up instead of crossing at every segment
    nseg = circle_segments(float(outline[:, 0].max()) if outline is not None else rmax, tol)
    outline_cs = m3d.CrossSection([outline], m3d.FillRule.Positive) if outline is not None else None
    return _Frame(slo, shi, rmax + margin, margin, outline, outline_cs, nseg)


# -- which sweep a path gets: the tool-kind predicates in one place ---------------------------
def is_mill_move(path) -> bool:
    """A move of a milling tool (the lathe's moves with the spindle stopped are spatial too)."""
    return isinstance(path, SpatialPath) and not path.tool.is_lathe_tool


def check_resolved(tool: ToolSpec, tol: float) -> None:
    """A milling tool narrower than the chordal tolerance (radius below it) cannot be swept at that
    tolerance: its circle's chords would cross its axis, and the passes a cycle lays side by side
    at such a tool's stepover pile up into tens of thousands of overlapping sweeps (fuzz: a 1 um
    end mill in POCKET2, a 2 um ball-end mill in CYCLE71 at 0.05 mm ran for minutes). An error
    at the tool's table naming the tolerance that would resolve it."""
    r = tool.diameter / 2.0
    if r < tol:
        raise tool_error(tool, f"the tool's radius {r:g} mm is below the chordal tolerance {tol:g} mm, so its cut "
                               f"cannot be resolved: simulate with a tolerance of at most {r:g} mm "
                               f"([simulation] tolerance or --tolerance)")


def fine_screw(path, tol: float):
    """A thread cut whose tool point travels at most ``tol`` along its path per revolution, as the
    lathe move it is within the tolerance: in every half-plane through the axis the screw sweep is
    the profile at the path points one revolution apart, the revolved sweep the profile along the
    whole path, and every point of the latter lies within ``tol`` of the former (the nearest pass is
    at most one revolution's path away), so the revolved region is the part within the run's
    tolerance — and costs one 2D region instead of thousands of teeth finer than the tolerance.
    Other paths are returned as they are."""
    if not isinstance(path, ScrewPath) or path.revolutions <= 0:
        return path
    r, z, _ = path.pose(np.asarray(path.breakpoints(), dtype=float))
    if float(np.hypot(np.diff(r), np.diff(z)).sum()) > tol * path.revolutions:
        return path
    return PlanarPath(path.src, path.tool, np.column_stack([r, z]), False)


def sweep_kind(path) -> str:
    """The one sweep strategy for ``path``, a key of STRATEGIES:

    - ``screw``: a spindle-synchronised cut (thread): the profile under screw motion, grouped by
      helix (stock/threads.py, stock/sweeps.py);
    - ``revolve``: a lathe move with the spindle turning: its 2D region, all unioned and revolved once;
    - ``hull``: a move swept on its own and checked against the stock as it is then: rapids,
      plunges of a tool that cannot cut at its centre, a lathe tool with the spindle stopped
      (one hull per segment);
    - ``level``: a flat end mill at constant Z: one 2D offset per Z level, extruded (stock/mill.py);
    - ``helix``: a mill on an arc or helix, consecutive arcs on one helix joined (stock/helix.py);
    - ``tube``: any other 3D mill feed, joined with the moves it continues: tubes along a ball-end
      mill's planar stretches (stock/tube.py), merged hulls of poses elsewhere;
    - ``gauge``: a move with no tool in the spindle: nothing swept, its gauge point checked
      against the stock as it is then (stock/gauge.py)."""
    if isinstance(path, GaugePath):
        return "gauge"
    if isinstance(path, ScrewPath):
        return "screw"
    if isinstance(path, PlanarPath):
        return "revolve"
    if not is_mill_move(path) or path.rapid or mill.plunges(path):
        return "hull"
    if mill.batchable(path):
        return "level"
    return "helix" if path.arc is not None else "tube"


class _Sweeper:
    """The sweep phase of one removal: every path's solids (or 2D region, or a recipe to build
    them when subtracted) as cuts in program order, and the moves whose collisions are checked.
    Moves are held back where they join the next ones (a 3D mill chain, arcs on one helix) and
    2.5D levels and thread groups are swept when all their moves are known (``finish``)."""

    def __init__(self, frame: _Frame, tol: float, profile, screw_parts: dict):
        self.f, self.tol, self.profile, self.screw_parts = frame, tol, profile, screw_parts
        self.cap = mill.cap_height(frame.top, tol)
        self.cuts: list[_Cut] = []
        self.checks: list[tuple[_Cut, object]] = []
        self.bodies: dict[int, list] = {}
        self.millb = mill.MillBatch(tol)
        self.chain = mill.Chain()
        self.arcs: list = []  # the pending ArcRun (kinematics.paths): consecutive arcs on one helix, joined
        self.screws = threads.ScrewGroups(tol)  # thread cuts, swept grouped by helix in finish()
        self.gauges: list = []  # (index, GaugePath): moves with no tool, checked by stock/gauge.py

    def body(self, tool: ToolSpec) -> list:
        if tool.number not in self.bodies:
            self.bodies[tool.number] = lathe_body(tool, self.tol)  # mills: stock/mill.py builds its own
        return self.bodies[tool.number]

    def add_cut(self, index: int, solids: list, keys: list | None = None) -> _Cut | None:
        if keys is not None:
            solids, keys = self.f.clip_keyed(solids, keys)
        else:
            solids = self.f.clip(solids)
        if solids:
            lo, hi = _bbox(solids)
            if self.f.meets(lo, hi):
                self.cuts.append(_Cut(index, solids, None, lo, hi, keys=keys))
                return self.cuts[-1]
        return None

    def screw(self, i: int, path: ScrewPath) -> None:
        if path.tool.kind == "tap":  # its core, moved along the axis: a revolved region (stock/axial.py)
            self.region_cut(i, axial.core_region(path.tool, path.z0, path.z1), path)
        parts = []
        for s0, s1, h in self.screw_parts.pop(i):
            prof = clipped_profile(self.profile(path.tool, path), h)
            if not prof.is_empty():
                parts.append((s0, s1, prof))
        if not parts:
            return
        tol = self.tol

        def near(z0, z1):
            return [x for s0, s1, prof in parts for x in screw_sweep(path, prof, tol, s0, s1, (z0, z1))]

        lo, hi = threads.bounds(path, parts)
        if self.f.meets(lo, hi):  # swept with its helix's group (stock/threads.py); `near` for the checks
            self.screws.add(i, path, parts)
            self.cuts.append(_Cut(i, [], None, lo, hi, near, build=list))

    def revolve(self, i: int, path: PlanarPath) -> None:
        h = self.f.r_clip - float(path.points[:, 0].min())
        if h <= 0:
            return
        prof = clipped_profile(self.profile(path.tool, path), h)
        if prof.is_empty():
            return
        region = m3d.CrossSection.batch_boolean([planar_region(path, p) for p in prof.to_polygons()],
                                                m3d.OpType.Add)
        self.region_cut(i, region, path)

    def region_cut(self, i: int, region: m3d.CrossSection, path) -> None:
        """A cut that is ``region`` revolved (unioned with the other regions, revolved once)."""
        if self.f.outline_cs is not None and (region ^ self.f.outline_cs).area() <= 0:
            return
        b = region.bounds()
        r_out = max(abs(b[0]), abs(b[2]))
        cut = _Cut(i, [], region, np.array([-r_out, -r_out, b[1]]), np.array([r_out, r_out, b[3]]))
        if self.f.meets(cut.lo, cut.hi):
            self.cuts.append(cut)
            if getattr(path, "rapid", False):
                self.checks.append((cut, path))

    def hull(self, i: int, path: SpatialPath) -> None:
        self.millb.cut_run()  # a checked move ends the 2.5D levels: no level may span it
        if path.tool.is_lathe_tool:
            cut = self.add_cut(i, spatial_hulls(path, self.body(path.tool)))
            if cut is not None:
                self.checks.append((cut, path))
            return
        keys: list = []
        cut = self.add_cut(i, mill.sweep(path, self.tol, self.cap, keys), keys)
        if cut is not None:  # checked with the tool shrunk by a few tolerances (stock/mill.py)
            self.checks.append((_Cut(i, self.f.clip(mill.check_solids(path, self.tol, self.cap)), None, cut.lo, cut.hi),
                                path))

    def level(self, i: int, path: SpatialPath) -> None:
        self.millb.take(i, path)

    def gauge(self, i: int, path: GaugePath) -> None:
        self.millb.cut_run()  # no 2.5D level spans it: the earlier cuts are those before it
        self.gauges.append((i, path))

    def helix(self, i: int, path: SpatialPath) -> None:
        if not (self.arcs and self.arcs[0].extend(path)):
            self.flush()
            self.arcs.append(ArcRun(i, path))

    def tube(self, i: int, path: SpatialPath) -> None:
        if self.arcs or not self.chain.continues(path):
            self.flush()
        self.chain.add(i, path)  # 3D mill feed: joined with the moves it continues (stock/mill.py)

    def flush(self) -> None:
        """Sweep the moves held back for joining: the chain (lazily, piece by piece when it is
        subtracted; a bounding box suffices until then) and the pending arc."""
        tol, cap, clip = self.tol, self.cap, self.f.clip
        if self.chain.parts:
            index, tool = self.chain.index, self.chain.tool
            reach = np.array([tool.diameter / 2.0, tool.diameter / 2.0, 0.0])
            for pts in self.chain.take(tol):
                lo, hi = pts.min(axis=0) - reach, pts.max(axis=0) + reach + [0.0, 0.0, tool.length]
                if self.f.meets(lo, hi):
                    cut = _Cut(index, [], None, lo, hi)
                    cut.build = functools.partial(self._chain_piece, cut, pts, tool)
                    self.cuts.append(cut)
        if self.arcs:
            run = self.arcs.pop()
            index, p = run.index, run.path()
            solids = helix.arc_sweep(p, tol, self.f.top)
            if solids is not None:
                self.add_cut(index, solids)
            else:
                keys: list = []
                self.add_cut(index, mill.hull_sweep(p.points, p.tool, tol, cap, keys), keys)

    def _chain_piece(self, cut: _Cut, pts: np.ndarray, tool: ToolSpec) -> list:
        """The solids of one piece of a 3D mill chain (built when needed), their poses in ``cut.keys``."""
        keys: list = []
        solids, cut.keys = self.f.clip_keyed(mill.hull_sweep(pts, tool, self.tol, self.cap, keys), keys)
        return solids

    def finish(self, n: int, work: "Work") -> None:
        """The held-back moves, the thread groups (at index n: never an "earlier cut" for the
        checks, which use each pass's own ``near``) and the 2.5D levels (each counted exactly
        from its 2D outline before it is extruded)."""
        self.flush()
        if self.screws:
            self.add_cut(n, self.screws.solids())
        for lv in self.millb.levels():
            work.add(_prism_triangles(lv.region()), lv.src, "this Z level of the end mill")
            self.add_cut(lv.index, [lv.solid()])


def remove(stock: m3d.Manifold, spec: StockSpec, paths: list, tol: float,
           progress: Progress | None = None, max_triangles: int = DEFAULT_MAX_TRIANGLES) -> Removal:
    """The part: ``stock`` minus what every path sweeps. Each path gets one sweep strategy
    (``sweep_kind``, STRATEGIES). Before any sweep is built the triangles the sweeps need are
    estimated (``Work``); more than ``max_triangles`` held at once is a CutsimError at the line of
    the move responsible (``[simulation] max_triangles`` raises it)."""
    frame = _frame(stock, spec, tol)
    profiles: dict[int, np.ndarray] = {}

    def profile(tool: ToolSpec, path=None) -> np.ndarray:
        if tool.kind == "tap" and isinstance(path, ScrewPath):  # under screw motion: its teeth (stock/axial.py)
            return axial_tool(tool, path)
        if tool.number not in profiles:
            profiles[tool.number] = lathe_profile(tool, tol)
        if path is not None and tool.side == "inside":  # a boring tool: only what can reach the bore
            return inner_trim(profiles[tool.number], *_path_rz(path), frame.outline_cs, frame.margin)
        return profiles[tool.number]

    for tool in {id(p.tool): p.tool for p in paths if getattr(p, "tool", None) is not None}.values():
        check_tool(tool)  # tools built in Python, not through the setup loader, meet the same ranges
    for tool in {id(p.tool): p.tool for p in paths if is_mill_move(p)}.values():
        check_resolved(tool, tol)
    paths = [fine_screw(p, tol) for p in drop_repeats(paths)]
    kinds = [sweep_kind(p) for p in paths]
    work = Work(max_triangles, stock.num_tri())
    sweeper = _Sweeper(frame, tol, profile, work.estimate(paths, kinds, tol, profile, frame))
    n = len(paths)
    for i, (path, kind) in enumerate(zip(paths, kinds)):
        if progress:
            progress("sweeping", i, n)
        sweep, _, ends_joins = STRATEGIES[kind]
        if ends_joins:
            sweeper.flush()
        sweep(sweeper, i, path)
    sweeper.finish(n, work)
    if progress:
        progress("sweeping", n, n)
    built = _Built(BUILT_TRIANGLES)
    warnings = _collisions(stock, sweeper, progress, built) + _gauge_warnings(stock, sweeper, tol, built, progress)
    if sweeper.millb or any(is_mill_move(p) for p in paths):
        warnings += mill.flute_warnings(sweeper.millb, paths, frame.top, tol, lambda idx, sol: _fresh_volume(
            stock, _Cut(idx, sol, None, *_bbox(sol)), sweeper.cuts, frame.revolve, built), float(frame.lo[2]))
        stock = mill.refined(stock)
    part, count = _subtract(stock, sweeper.cuts, paths, frame, work, progress, built)
    return Removal(part, warnings, count)


def _collisions(stock: m3d.Manifold, sweeper: _Sweeper, progress: Progress | None, built: "_Built") -> list:
    """(src, message) for each checked move that removes material still there when it runs."""
    warnings = []
    for k, (cut, path) in enumerate(sweeper.checks):
        if progress:
            progress("checking rapids", k, len(sweeper.checks))
        vol = _fresh_volume(stock, cut, sweeper.cuts, sweeper.f.revolve, built)
        if vol > MIN_COLLISION_VOLUME:
            if path.rapid:
                msg = f"rapid (G00) cuts the stock: {vol:.3f} mm^3 removed"
            elif not path.tool.is_lathe_tool:
                msg = mill.plunge_message(path, vol)
            else:
                msg = f"cutting with the spindle stopped: only the tool's own swept volume is removed ({vol:.3f} mm^3)"
            warnings.append((path.src, msg))
    return warnings


def _gauge_warnings(stock: m3d.Manifold, sweeper: _Sweeper, tol: float, built: "_Built",
                    progress: Progress | None = None) -> list:
    """(src, message) for each move with no tool whose gauge point runs inside the material still
    there when it moves (stock/gauge.py). Only a move inside the stock as it came can be; the moves
    between two cuts (one stretch without a tool) all meet the same material, taken once."""
    inside: dict[int, list] = {}  # cuts before the move -> [(index, path)] inside the stock as it came
    starts = sorted(c.index for c in sweeper.cuts)
    for k, (i, path) in enumerate(sweeper.gauges):
        if progress:
            progress("checking moves without a tool", k, len(sweeper.gauges))
        lo, hi = path.points.min(axis=0), path.points.max(axis=0)
        if sweeper.f.meets(lo, hi) and gauge.inside_length(stock, path.points, tol) > tol:
            inside.setdefault(bisect.bisect_left(starts, i), []).append((i, path))
    warnings = []
    for run in inside.values():
        pts = np.concatenate([p.points for _, p in run])
        box = gauge.probe(pts)
        lo, hi = _bbox([box])
        i = run[0][0]
        material = stock
        if any(c.index < i and _overlap(c.lo, c.hi, lo, hi) for c in sweeper.cuts):
            material = _fresh(stock, _Cut(i, [box], None, lo, hi), sweeper.cuts, sweeper.f.revolve, built)
        for _, path in run:
            length = 0.0 if material is None else gauge.inside_length(material, path.points, tol)
            if length > tol:
                warnings.append((path.src, gauge.message(length)))
    return warnings


def _subtract(stock: m3d.Manifold, cuts: list[_Cut], paths: list, frame: _Frame, work: "Work",
              progress: Progress | None, built: "_Built | None" = None) -> tuple[m3d.Manifold, int]:
    """One batch subtract; a program whose solids exceed CHUNK_TRIANGLES is subtracted in
    consecutive batches of about that size (cut order), each built just before and released
    after, so memory stays bounded however long the program is. Returns the part (debris
    dropped) and the number of solids subtracted."""
    regions = [c.region for c in cuts if c.region is not None]
    part, pending, keys, tris, count = stock, [], [], 0, 0
    if regions:
        union = m3d.CrossSection.batch_boolean(regions, m3d.OpType.Add)
        first = min(c.index for c in cuts if c.region is not None)
        work.add(2 * union.num_vert() * frame.nseg, paths[first].src, "the turning moves (one solid of revolution)")
        pending.append(frame.revolve(union))
        keys.append(None)
    for k, c in enumerate(cuts):
        if progress:
            progress("subtracting", k, len(cuts))
        sols = built.take(c) if built is not None else c.get()  # swept for a check: not again
        pending.extend(sols)
        keys.extend(c.keys if c.keys is not None and len(c.keys) == len(sols) else [None] * len(sols))
        tris += sum(sol.num_tri() for sol in sols)
        if tris > CHUNK_TRIANGLES:
            part = m3d.Manifold.batch_boolean([part] + _outermost(pending, keys, frame.top), m3d.OpType.Subtract)
            part.num_tri()  # evaluate now so the batch's solids can be freed
            count += len(pending)
            pending, keys, tris = [], [], 0
    if pending:
        part = m3d.Manifold.batch_boolean([part] + _outermost(pending, keys, frame.top), m3d.OpType.Subtract)
        count += len(pending)
    part = drop_debris(part)
    if progress:
        progress("subtracting", len(cuts), len(cuts))
    return part, count


CHUNK_TRIANGLES = 1_000_000


def _outermost(solids: list, keys: list, top: float) -> list:
    """``solids`` without the hulls of tool poses that lie inside another one of them below the
    stock's top ``top`` (``mill.nested``): a pass below another on the same XY path. The part is
    the same solid, but the coinciding walls of nested passes made the batch boolean cut them into
    slivers."""
    if sum(k is not None for k in keys) < 2:
        return solids
    inside = mill.nested(keys, top)
    return [s for s, drop in zip(solids, inside) if not drop]


def _stock_rmax(outline: np.ndarray | None, zlo: float, zhi: float, default: float) -> float:
    """Largest radius of a stock of revolution between the heights ``zlo`` and ``zhi``."""
    if outline is None:
        return default
    a, b = outline, np.roll(outline, -1, axis=0)
    best = -np.inf
    for (ra, za), (rb, zb) in zip(a, b):
        lo, hi = min(za, zb), max(za, zb)
        if hi < zlo or lo > zhi:
            continue
        if zb == za:
            best = max(best, ra, rb)
            continue
        for z in (max(lo, zlo), min(hi, zhi)):
            best = max(best, ra + (rb - ra) * (z - za) / (zb - za))
    return float(best) if best > -np.inf else 0.0


def _iter_screw_pieces(path: ScrewPath, profile: np.ndarray, outline, r_clip: float, margin: float):
    """Split a screw path into pieces (s0, s1, clip height) such that each piece's profile is clipped
    where it leaves the stock *locally*: a tool point further out than the stock's largest radius
    over the heights the piece can reach never touches material, so the clip is exact. A taper
    thread in a cone then sweeps a profile narrower than the lead (no overlapping turns) instead
    of one as tall as the whole cone, which made the subtract slow.
    """
    vlo, vhi = float(profile[:, 1].min()), float(profile[:, 1].max())
    brk = path.breakpoints()

    def clip(s0: float, s1: float) -> float:
        s = np.array([s0] + [b for b in brk if s0 < b < s1] + [s1])
        r, z, _ = path.pose(s)
        rloc = _stock_rmax(outline, float(z.min()) + vlo, float(z.max()) + vhi, r_clip - margin)
        return min(r_clip, rloc + margin) - float(r.min())

    lead = path.travel / path.revolutions if path.revolutions > 0 else np.inf

    def fits(s0: float, s1: float) -> bool:
        h = clip(s0, s1)
        if h <= 0:
            return True
        b = clipped_profile(profile, h).bounds()
        return b[3] - b[1] < 0.999 * lead

    if outline is None or fits(0.0, 1.0) or path.revolutions <= 1.0:
        h = clip(0.0, 1.0)
        if h > 0:
            yield 0.0, 1.0, h
        return
    step = 1.0 / path.revolutions  # one turn
    s0 = 0.0
    while s0 < 1.0 - 1e-12:
        s1 = min(1.0, s0 + step)
        if fits(s0, s1):  # grow by whole turns while the piece stays narrower than the lead
            while s1 < 1.0 and fits(s0, min(1.0, s1 + step)):
                s1 = min(1.0, s1 + step)
        h = clip(s0, s1)
        if h > 0:
            yield s0, s1, h
        s0 = s1


@functools.lru_cache(maxsize=None)
def _key_fields(cls) -> tuple[str, ...]:
    """The fields of a path type that decide what it sweeps (all but its source line)."""
    return tuple(f.name for f in fields(cls) if f.name != "src")


def _path_key(path) -> tuple:
    """Everything that decides what ``path`` sweeps (not its source line), hashable."""
    key = [type(path).__name__]
    for name in _key_fields(type(path)):
        v = getattr(path, name)
        key.append((v.shape, v.tobytes()) if isinstance(v, np.ndarray) else v)
    return tuple(key)


def drop_repeats(paths: list) -> list:
    """``paths`` without the ones that repeat an earlier path exactly (a loop running the same
    moves again, a spring pass, a zero-length move written many times). Material only ever goes:
    a repeated sweep meets nothing its first run did not already take, so it removes nothing and
    touches no fresh stock (no warning can come from it). Order and source lines are kept."""
    seen, out = set(), []
    for path in paths:
        try:
            key = _path_key(path)
            if key in seen:
                continue
            seen.add(key)
        except TypeError:  # an unhashable field: keep the path
            pass
        out.append(path)
    return out


def _path_rz(path) -> tuple[np.ndarray, np.ndarray]:
    """Radii and heights of a lathe path's tool point at its corners (a screw path's kinks)."""
    if isinstance(path, PlanarPath):
        return path.points[:, 0], path.points[:, 1]
    r, z, _ = path.pose(np.asarray(path.breakpoints(), dtype=float))
    return r, z


@functools.lru_cache(maxsize=64)
def _tap_teeth(tool: ToolSpec) -> np.ndarray:
    return axial.tap_teeth(tool)


def axial_tool(tool: ToolSpec, path: ScrewPath) -> np.ndarray:
    """A tap's teeth for a thread cut, which it makes on the spindle axis only: straight along Z
    at X0, without lead-in or runout ramps (CutsimError at the move's line otherwise)."""
    if max(abs(path.r0), abs(path.r1)) > 1e-9 or path.ramps or abs(path.z1 - path.z0) <= 0:
        raise CutsimError(path.src.program, path.src.line, path.src.col,
                          f"a tap cuts its thread on the spindle axis: a thread cut with tool {tool.number} "
                          f"must run along Z at X0 without lead-in or runout (it runs from X{2 * path.r0:g} "
                          f"Z{path.z0:g} to X{2 * path.r1:g} Z{path.z1:g})")
    return _tap_teeth(tool)


def _check_axis(path: ScrewPath, profile: np.ndarray) -> None:
    """A spindle-synchronised cut keeps the whole tool on one side of the spindle axis: a tool that
    reaches the axis (a lead-in ramping past it, a profile reaching behind its control point)
    sweeps no solid a lathe could cut; it is an error at the move's line, not a folded solid."""
    r = float(np.min(path.pose(np.array(path.breakpoints()))[0]))
    inner = r + float(np.min(profile[:, 0]))
    if inner <= 0.0:
        raise CutsimError(path.src.program, path.src.line, path.src.col,
                          f"the tool reaches the spindle axis in this thread cut: its innermost point comes to "
                          f"radius {inner:.4f} mm (tool point at radius {r:.4f} mm); a spindle-synchronised "
                          f"cut must keep the whole tool on one side of the axis"
                          + (" (a thread on the spindle axis is cut with a tap: kind = \"tap\")"
                             if path.tool is not None and path.tool.kind in ("drill", "centredrill") else ""))


def drop_debris(part: m3d.Manifold) -> m3d.Manifold:
    """Remove zero-volume shells that coincident faces of nested cuts can leave behind; pieces with
    real volume (a part cut loose from the bar) stay."""
    if part.is_empty() or part.genus() >= 0:
        return part
    pieces = part.decompose()
    keep = [p for p in pieces if abs(p.volume()) > DEBRIS_VOLUME]
    if len(keep) == len(pieces):
        return part
    return m3d.Manifold.compose(keep) if keep else m3d.Manifold()


class _Built:
    """The solids of lazily swept cuts (3D mill chain pieces) with their boxes, kept across the
    checks that ask for them again, the least recently used dropped beyond BUILT_TRIANGLES."""

    def __init__(self, limit: int):
        self.limit = limit
        self.held = 0
        self.solids: dict[int, tuple[_Cut, list, int]] = {}  # id(cut) -> (cut, [(solid, lo, hi)], triangles)

    def get(self, cut: _Cut) -> list:
        got = self.solids.pop(id(cut), None)
        if got is None:
            sols = [(s, *_bbox([s])) for s in cut.get()]
            got = (cut, sols, sum(s.num_tri() for s, _, _ in sols))
            self.held += got[2]
        self.solids[id(cut)] = got  # the newest at the end
        while self.held > self.limit and len(self.solids) > 1:
            old = next(iter(self.solids))
            self.held -= self.solids.pop(old)[2]
        return got[1]

    def take(self, cut: _Cut) -> list:
        """The solids of ``cut`` for the subtract, built ones handed over (and no longer kept)."""
        got = self.solids.pop(id(cut), None)
        if got is None:
            return cut.get()
        self.held -= got[2]
        return [s for s, _, _ in got[1]]


BUILT_TRIANGLES = 1_000_000  # triangles of lazily swept cuts kept between checks


def _fresh_volume(stock, cut: _Cut, cuts: list[_Cut], revolve, built: _Built | None = None) -> float:
    """Volume ``cut`` removes from the stock as it is when the cut happens (``built``: the lazily
    swept earlier cuts already built for other checks)."""
    hit = _fresh(stock, cut, cuts, revolve, built)
    return 0.0 if hit is None else float(hit.volume())


def _fresh(stock, cut: _Cut, cuts: list[_Cut], revolve, built: _Built | None = None) -> m3d.Manifold | None:
    """The part of the stock, as it is when ``cut`` happens, that ``cut``'s solids cover; None when
    that is no more than MIN_COLLISION_VOLUME."""
    mine = cut.get() if cut.region is None else [revolve(cut.region)]
    hit = m3d.Manifold.batch_boolean([stock, m3d.Manifold.batch_boolean(mine, m3d.OpType.Add)], m3d.OpType.Intersect)
    if hit.volume() <= MIN_COLLISION_VOLUME:
        return None
    b = hit.bounding_box()
    hlo, hhi = np.array(b[:3]), np.array(b[3:])
    earlier = [c for c in cuts if c.index < cut.index and _overlap(c.lo, c.hi, hlo, hhi)]
    # only the pieces of earlier sweeps that can reach what this cut hits (a long thread is many turns:
    # rebuilt only near the heights this cut reaches); a 3D mill chain's pieces, swept when they are
    # subtracted (``_Cut.build``), are built only when the loop below comes to them
    hvol = float(np.prod(np.maximum(hhi - hlo, 1e-9)))

    def cover(lo, hi) -> float:
        return round(_box_overlap(lo, hi, hlo, hhi) / hvol, 3)

    items = []  # (cover, order, solid or lazy _Cut)
    for c in earlier:
        if c.build is not None and c.near is None:
            items.append((cover(c.lo, c.hi), len(items), c))
            continue
        for s in (c.near(float(hlo[2]), float(hhi[2])) if c.near is not None else c.get()):
            lo, hi = _bbox([s])
            if _overlap(lo, hi, hlo, hhi):
                items.append((cover(lo, hi), len(items), s))
    regions = [c.region for c in earlier if c.region is not None]
    if regions:
        s = revolve(m3d.CrossSection.batch_boolean(regions, m3d.OpType.Add))
        items.append((cover(*_bbox([s])), -1, s))
    # The sweeps whose boxes cover most of the hit's box first (newest first among equals), in
    # batches of 1, 2, 4 ... FRESH_BATCH, stopping once nothing is left: the hit is small and the
    # earlier sweeps overlap each other (a pocket's passes), so their union in one batch costs far
    # more than taking them off the hit a few at a time, and one or two sweeps (the move a retract
    # starts from, the shallower pass that cleared what is above the flutes) usually take it all
    # (a flute check after a deep pocket: 0.8 s per check in one batch, 0.1 s so; 624 checks of a
    # 34 mm deep CYCLE71 built every earlier chain piece each: 93 s, 2 s when built as reached).
    queue = [it[2] for it in sorted(items, key=lambda t: (-t[0], -t[1]))]
    queue.reverse()  # popped from the end
    size = 1
    while queue:
        batch = []
        while queue and len(batch) < size:
            x = queue.pop()
            if isinstance(x, _Cut):  # a lazy chain piece: its hulls that reach the hit, best first
                sols = built.get(x) if built is not None else [(s, *_bbox([s])) for s in x.get()]
                got = [(cover(lo, hi), k, s) for k, (s, lo, hi) in enumerate(sols) if _overlap(lo, hi, hlo, hhi)]
                queue.extend(g[2] for g in sorted(got, key=lambda t: (t[0], t[1])))
            else:
                batch.append(x)
        if not batch:
            break
        hit = m3d.Manifold.batch_boolean([hit] + batch, m3d.OpType.Subtract)
        if hit.volume() <= MIN_COLLISION_VOLUME:
            return None
        size = min(2 * size, FRESH_BATCH)
    return hit


FRESH_BATCH = 16  # most earlier sweeps taken off a check's hit per boolean


# -- work estimates --------------------------------------------------------------------------------
# Measured peak memory per counted triangle: about 600 bytes for a screw sweep built and
# subtracted from a bar (extrude + warp of 4M triangles: 2.3 GB), 650 for a thread whose turns
# overlap 6 deep (lead 0.045 over 22 mm, 3.4M counted: 2.19 GB), 400 for one 11 deep (lead 0.025,
# 10.9M counted: 4.2 GB). Used for the message only.
BYTES_PER_TRIANGLE = 600


class Work:
    """The triangles of the solids a run holds at once (the stock, every sweep kept for the batch
    subtract, the largest piece of lazily swept mill moves), estimated before anything is swept,
    path by path with the same strategy the sweep will use (``estimate``). More than ``limit`` is
    a CutsimError at the line of the move that goes over it."""

    def __init__(self, limit: int, stock_triangles: int):
        self.limit = int(limit)
        self.held = int(stock_triangles)

    def add(self, tris: int, src, what: str) -> None:
        self.held += int(tris)
        if self.held > self.limit:
            raise CutsimError(src.program, src.line, src.col, self.message(int(tris), what))

    def message(self, tris: int, what: str) -> str:
        gb = self.held * BYTES_PER_TRIANGLE / 1e9
        return (f"too much geometry: the sweeps would need about {self.held:,} triangles at once "
                f"({what}: about {tris:,}), more than [simulation] max_triangles = {self.limit:,}; this would take "
                f"about {gb:.1f} GB of memory: raise max_triangles in the setup or use a coarser tolerance")

    def estimate(self, paths: list, kinds: list[str], tol: float, profile, frame: _Frame) -> dict[int, list]:
        """Count every path's sweep in program order (STRATEGIES), refusing as soon as the total
        goes over the limit; returns the screw paths' pieces (computed once, used by the sweep).
        3D mill feeds are swept and subtracted piece by piece, so they count as the batch of
        CHUNK_TRIANGLES plus their largest piece."""
        self.tol, self.profile, self.frame = tol, profile, frame
        self.cap = mill.cap_height(frame.top, tol)
        self.screw_pieces: dict[int, list] = {}
        self.screws = threads.ScrewGroups(tol)
        self.arc: list = []  # the pending ArcRun (kinematics.paths) (consecutive arcs on one helix joined)
        self.chain: list = []  # [tool, src, points...]: consecutive 3D feeds joined as mill.Chain does
        self.lazy_total, self.lazy_piece, self.lazy_src = 0, 0, None
        for i, (path, kind) in enumerate(zip(paths, kinds)):
            _, count, ends_joins = STRATEGIES[kind]
            if ends_joins:
                self.flush()
            count(self, i, path)
        self.flush()
        self.screws_done()
        if self.lazy_src is not None:
            self.add(min(self.lazy_total, CHUNK_TRIANGLES + self.lazy_piece), self.lazy_src,
                     "the 3D milling moves, swept in batches")
        return self.screw_pieces

    def screw(self, i: int, path: ScrewPath) -> None:
        prof = self.profile(path.tool, path)
        _check_axis(path, prof)
        f = self.frame
        # a groupable path whose profile is wider than its lead is folded onto one turn with its
        # group (threads.fold): each turn adds one lead-shifted copy of its profile to one turn's
        # sweep instead of a sweep overlapping the others (the group is counted in screws_done)
        fold = threads.motion(path) is not None
        pieces, parts, tris = [], [], 0
        for piece in _iter_screw_pieces(path, prof, f.outline, f.r_clip, f.margin):
            pieces.append(piece)
            parts.append((piece[0], piece[1], clipped_profile(prof, piece[2])))
            tris += _screw_triangles(path, parts[-1][2], piece[0], piece[1], self.tol, overlap=not fold)
            if self.held + tris > self.limit:  # stop a huge one early: extrapolate its total
                self.add(round(tris / max(piece[1], 1e-9)), path.src, "this thread cut")
        self.screw_pieces[i] = pieces
        parts = [pt for pt in parts if not pt[2].is_empty()]
        if parts and self.frame.meets(*threads.bounds(path, parts)):  # as _Sweeper.screw keeps it
            self.screws.add(i, path, parts)  # counted as swept, grouped by helix (screws_done)

    def screws_done(self) -> None:
        """The thread cuts as ``threads.ScrewGroups`` sweeps them: one sweep per stretch of each
        helix's group (the union of its passes' profiles), the ungrouped passes one by one. (The
        passes' own sweeps near a checked rapid are built one at a time and released.)"""
        for path, prof in self.screws.sweeps():  # a wide group folded onto one turn (threads.fold)
            self.add(threads.sweep_triangles(path, prof, self.tol), path.src,
                     "the thread cuts on this helix, swept as one")
        for m in self.screws.single:
            self.add(sum(_screw_triangles(m.path, prof, s0, s1, self.tol) for s0, s1, prof in m.parts),
                     m.path.src, "this thread cut")

    def revolve(self, i: int, path: PlanarPath) -> None:
        pass  # counted exactly from the union of the regions before it is revolved (_subtract)

    def level(self, i: int, path: SpatialPath) -> None:
        pass  # counted exactly from the level's 2D outline before it is extruded (_Sweeper.finish)

    def gauge(self, i: int, path: GaugePath) -> None:
        pass  # nothing swept

    def hull(self, i: int, path: SpatialPath) -> None:
        tool = path.tool
        if tool.is_lathe_tool:  # spindle stopped: a hull per segment and convex piece of the plate
            verts = sum(len(p) for p in lathe_body(tool, self.tol))
            self.add(2 * 4 * (len(path.points) - 1) * verts, path.src, "this move with the spindle stopped")
            return
        segs = sum(len(p) - 1 for p in mill.below_cap(path.points, self.cap)) if len(path.points) > 1 else 1
        if mill.is_flat(tool) and mill.is_constant_z(path):
            k = max(2, math.ceil(math.pi / segment_angle(tool.diameter / 2.0, self.tol)))
            tris = 4 * 2 * (k + 1) * max(1, len(path.points) - 1)
        else:
            tris = 4 * segs * _body_vertices(tool, self.tol)
        self.add(2 * tris, path.src, "this move (its sweep and its collision check)")

    def helix(self, i: int, path: SpatialPath) -> None:
        if not (self.arc and self.arc[0].extend(path)):
            self.flush()
            self.arc.append(ArcRun(i, path))

    def tube(self, i: int, path: SpatialPath) -> None:
        chain = self.chain
        if not self.arc and chain and chain[0] == path.tool and np.all(np.abs(chain[-1][-1] - path.points[0]) <= 1e-9):
            chain.append(path.points[1:])
        else:
            self.flush()
            chain.extend([path.tool, path.src, path.points])

    def flush(self) -> None:
        """Count the moves held back for joining, as ``_Sweeper.flush`` sweeps them."""
        if self.chain:
            tool, src, parts = self.chain[0], self.chain[1], self.chain[2:]
            self.chain = []
            pts = np.concatenate(parts)
            size = _piece_size(tool, self.tol)
            for k in range(0, max(1, len(pts) - 1), size - 1):
                n = _chain_piece_triangles(pts[k:k + size], tool, self.tol, self.cap, (self.limit - self.held) / 4)
                self.lazy_total += n
                self.lazy_piece = max(self.lazy_piece, n)
                if self.lazy_piece > self.limit - self.held:  # one piece is held whole while it is subtracted
                    self.add(self.lazy_piece, src, "these 3D milling moves (one piece of their sweep)")
            self.lazy_src = self.lazy_src or src
        if self.arc:
            p = self.arc.pop().path()
            verts = _body_vertices(p.tool, self.tol)
            self.add(_arc_triangles(p, self.tol, self.frame.top, self.cap, verts), p.src, "this arc or helix")


# The one table: each sweep kind's strategy (stock/removal.py _Sweeper), its estimate (Work) and
# whether the moves held back for joining (a 3D mill chain, arcs on one helix) are swept first.
STRATEGIES = {
    "screw": (_Sweeper.screw, Work.screw, True),
    "revolve": (_Sweeper.revolve, Work.revolve, True),
    "hull": (_Sweeper.hull, Work.hull, True),
    "level": (_Sweeper.level, Work.level, False),
    "helix": (_Sweeper.helix, Work.helix, False),
    "tube": (_Sweeper.tube, Work.tube, False),
    "gauge": (_Sweeper.gauge, Work.gauge, True),
}


@functools.lru_cache(maxsize=1024)
def _body_vertices(tool: ToolSpec, tol: float, height: float | None = None) -> int:
    """Vertices of the mill's body (cut off at ``height`` above the tip) that the hulls are built of."""
    return len(mill_body(tool, tol, height)[0])


def _piece_size(tool: ToolSpec, tol: float) -> int:
    """Poses per piece of a chain as ``mill.Chain.take`` cuts it (a ball-end mill: CHAIN_POINTS;
    other mills: about PIECE_VERTICES body vertices per piece, at least 50 poses)."""
    if tube.is_ball(tool):
        return mill.CHAIN_POINTS
    return int(min(mill.CHAIN_POINTS, max(50, mill.PIECE_VERTICES // _body_vertices(tool, tol))))


# A convex hull of N points has at most 2 N - 4 triangles (Euler); a hull of two poses of a mill
# body of V vertices holds about V of them on its surface: measured 1.9 V (ball-end, 2 mm radius,
# 0.001..0.00001 mm) to 3.0 V (flat end mill) triangles. HULL_PER_SEGMENT x V per segment bounds the
# hull sweeps of a polyline (a merged run of poses has no more than its pairs).
HULL_PER_SEGMENT = 3


def _chain_piece_triangles(pts: np.ndarray, tool: ToolSpec, tol: float, cap: float, budget: float = 0.0) -> int:
    """Triangles of ``mill.hull_sweep(pts, tool, tol, cap)`` without building it: the tubes of a
    ball-end mill's planar stretches (``tube.stretches``, two triangles per profile vertex and
    station) with a body hull at each end, and HULL_PER_SEGMENT x the body's vertices for every
    other segment (bodies cut off where the sweep cuts them: above the stock, over the corner).
    Where that bound exceeds ``budget`` the segments' merged runs (``mill.runs``) are counted
    instead: one hull of about HULL_PER_SEGMENT x V per run plus a ring's worth (4 triangles per
    ring vertex) for every pose inside it."""
    rc = min(tool.corner_radius, tool.diameter / 2.0)
    tris = 0
    for sub in mill.below_cap(pts, cap):
        top = max(cap, float(sub[:, 2].max()) + rc)
        v = _body_vertices(tool, tol, round(min(top - float(sub[:, 2].min()), tool.length), 6))
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
        if HULL_PER_SEGMENT * v * segs > budget:  # merged runs: count their hulls (as hull_sweep makes them)
            ring = max(8, math.ceil(2 * math.pi / segment_angle(tool.diameter / 2.0, tol)))
            hulls = [(i, j) for i, j in mill.runs(sub, tol, closed) if not any(a <= i and j <= b for a, b in st)]
            tris += sum(HULL_PER_SEGMENT * v + 4 * ring * max(0, j - i - 1) for i, j in hulls)
        else:
            tris += HULL_PER_SEGMENT * v * segs
    return tris


def _prism_triangles(region: m3d.CrossSection) -> int:
    """An extruded region: two triangles per side edge and about one per vertex in each cap."""
    return 4 * region.num_vert()


def _screw_triangles(path: ScrewPath, prof: m3d.CrossSection, s0: float, s1: float, tol: float,
                     overlap: bool = True) -> int:
    """Triangles of ``sweeps.screw_sweep(path, prof, tol, s0, s1)`` without building it: the same
    stations and chunks, the profile's vertices after ``subdivide`` (its length and twist rules);
    with ``overlap`` the work of subtracting a profile wider than the lead, whose turns overlap
    (not for a path folded with its group, threads.fold: its turns lie side by side in one turn)."""
    if prof.is_empty():
        return 0
    bounds = prof.bounds()
    width = bounds[3] - bounds[1]
    brk = [s0] + [b for b in path.breakpoints() if s0 < b < s1] + [s1]
    reach = float(np.max(path.pose(np.array(brk))[0])) + bounds[2]
    total = 360.0 * path.revolutions
    lead = path.travel / path.revolutions if path.revolutions > 0 else math.inf
    step = math.degrees(segment_angle(reach, tol))
    limit = math.inf if width < 0.999 * lead else MAX_CHUNK_DEGREES
    max_len = EDGE_STEPS * math.sqrt(tol * reach)
    twist = screw_twist(path, prof, tol, s0, s1)
    nv = sum(int(edge_pieces(poly, max_len, twist).sum()) for poly in prof.to_polygons())
    tris = 0
    for a, b in zip(brk, brk[1:]):
        span = (b - a) * total
        k = max(1, math.ceil(span / limit)) if span > 0 else 1
        n = max(1, math.ceil(span / k / step)) if span > 0 else 1
        tris += k * (2 * nv * n + 2 * nv)
    if overlap and width >= 0.999 * lead:
        # A profile wider than the lead: every point of the groove lies in width / lead turns, and
        # the subtract intersects each turn with all of them. Measured (G33 lead 0.025 over 22 mm,
        # 11 turns deep: 1.0M triangles built, 4.2 GB and 940 s): the work grows with that count.
        tris = round(tris * width / lead)
    return tris


def _arc_triangles(path: SpatialPath, tol: float, top: float, cap: float, body: int) -> int:
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
