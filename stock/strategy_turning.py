"""The lathe's strategies with the spindle turning: thread cuts under screw motion (``Screw``)
and turning moves revolved (``Revolve``), each with its sweep and its estimate.

A thread cut is the tool's profile under screw motion, clipped where it leaves the stock and cut
into pieces narrower than the lead where the stock allows it (``screw_pieces``); the passes on one
helix are swept as one group (stock/threads.py). A turning move is a 2D region; all of them are
unioned and revolved once when the cuts are subtracted (stock/removal.py), where that solid is
counted exactly.
"""
from __future__ import annotations

import functools
import math

import manifold3d as m3d
import numpy as np

from cutsim.base.specs import ToolSpec
from cutsim.interp.errors import CutsimError
from cutsim.kinematics.paths import PlanarPath, ScrewPath, segment_angle

from . import axial, inserts, threads
from .cuts import Cut, Frame
from .strategy import Strategy
from .sweeps import (EDGE_STEPS, MAX_CHUNK_DEGREES, clipped_profile, edge_pieces, inner_trim, planar_region,
                     screw_sweep, screw_twist, sweep_polygon_2d)
from .tools import lathe_profile


class Screw(Strategy):
    """A spindle-synchronised cut (thread): the profile under screw motion, grouped by helix
    (stock/threads.py, stock/sweeps.py). A tap's core, moved along the axis, is a revolved region."""

    kind = "screw"

    def __init__(self, run):
        super().__init__(run)
        self.pieces: dict[int, list] = {}  # path index -> its pieces (s0, s1, clip height), from the estimate
        self.counted_groups = threads.ScrewGroups(run.tol)  # the groups as the estimate counts them
        self.groups = threads.ScrewGroups(run.tol)  # the groups swept in finish()

    def estimate(self, i: int, path: ScrewPath) -> None:
        run = self.run
        prof = run.profile(path.tool, path)
        check_axis(path, prof)
        f = run.f
        # a groupable path whose profile is wider than its lead is folded onto one turn with its
        # group (threads.fold): each turn adds one lead-shifted copy of its profile to one turn's
        # sweep instead of a sweep overlapping the others (the group is counted in counted())
        fold = threads.motion(path) is not None
        pieces, parts, tris = [], [], 0
        for piece in screw_pieces(path, prof, f.outline, f.r_clip, f.margin):
            pieces.append(piece)
            parts.append((piece[0], piece[1], clipped_profile(prof, piece[2])))
            tris += screw_triangles(path, parts[-1][2], piece[0], piece[1], run.tol, overlap=not fold)
            if tris > run.work.room():  # stop a huge one early: extrapolate its total
                run.work.add(round(tris / max(piece[1], 1e-9)), path.src, "this thread cut")
        self.pieces[i] = pieces
        parts = [pt for pt in parts if not pt[2].is_empty()]
        if parts and f.meets(*threads.bounds(path, parts)):  # as sweep() keeps it
            self.counted_groups.add(i, path, parts)  # counted as swept, grouped by helix (counted())

    def counted(self) -> None:
        """The thread cuts as ``threads.ScrewGroups`` sweeps them: one sweep per stretch of each
        helix's group (the union of its passes' profiles), the ungrouped passes one by one. (The
        passes' own sweeps near a checked rapid are built one at a time and released.)"""
        run = self.run
        for path, prof in self.counted_groups.sweeps():  # a wide group folded onto one turn (threads.fold)
            run.work.add(threads.sweep_triangles(path, prof, run.tol), path.src,
                         "the thread cuts on this helix, swept as one")
        for m in self.counted_groups.single:
            run.work.add(sum(screw_triangles(m.path, prof, s0, s1, run.tol) for s0, s1, prof in m.parts),
                         m.path.src, "this thread cut")

    def sweep(self, i: int, path: ScrewPath) -> None:
        run = self.run
        body_check(run, i, path)
        if path.tool.kind == "tap":  # its core, moved along the axis: a revolved region (stock/axial.py)
            run.region_cut(i, axial.core_region(path.tool, path.z0, path.z1), path)
        parts = []
        for s0, s1, h in self.pieces.pop(i):
            prof = clipped_profile(run.profile(path.tool, path), h)
            if not prof.is_empty():
                parts.append((s0, s1, prof))
        if not parts:
            return
        tol = run.tol

        def near(z0, z1):
            return [x for s0, s1, prof in parts for x in screw_sweep(path, prof, tol, s0, s1, (z0, z1))]

        lo, hi = threads.bounds(path, parts)
        if run.f.meets(lo, hi):  # swept with its helix's group (stock/threads.py); `near` for the checks
            self.groups.add(i, path, parts)
            run.cuts.append(Cut(i, [], None, lo, hi, near, build=list))

    def finish(self, n: int) -> None:
        """The thread groups, at index ``n``: never an "earlier cut" for the checks, which use each
        pass's own ``near``."""
        if self.groups:
            self.run.add_cut(n, self.groups.solids())


class Revolve(Strategy):
    """A lathe move with the spindle turning: its 2D region, all unioned and revolved once (counted
    exactly from the union before it is revolved, stock/removal.py)."""

    kind = "revolve"

    def sweep(self, i: int, path: PlanarPath) -> None:
        run = self.run
        body_check(run, i, path)
        h = run.f.r_clip - float(path.points[:, 0].min())
        if h <= 0:
            return
        prof = clipped_profile(run.profile(path.tool, path), h)
        if prof.is_empty():
            return
        region = m3d.CrossSection.batch_boolean([planar_region(path, p) for p in prof.to_polygons()],
                                                m3d.OpType.Add)
        run.region_cut(i, region, path)


def body_check(run, i: int, path) -> None:
    """A tool's body on a move with the spindle turning: an inside tool's boring bar
    (inserts.bar_section, from the top of the tool's profile out of the bore), an outside or face
    tool's holder (inserts.holder_section, from where the insert ends out beyond the stock), the
    region it covers along the move kept in ``run.bodies`` to be checked against the material still
    there (stock/collisions.py), never cut. Its place in program order is just after the move's own
    cut: the insert leads the body into the material, so what the move cuts is gone where it comes.
    A body whose region misses the stock as it came is not kept."""
    tool = path.tool
    r, z = _path_rz(path)
    if tool.bar_diameter:
        start = float(run.profile(tool)[:, 1].max())
        length = float(run.f.hi[2]) + run.f.margin - (float(z.min()) + start)
        section = inserts.bar_section(tool, start, length) if length > 0 else None
    elif tool.shank and tool.side != "inside" and tool.kind in ("thread", "turning", "grooving"):
        reach = (float(run.f.hi[2]) - float(z.min()) if tool.side == "face" else run.f.r_clip - float(r.min()))
        section = inserts.holder_section(tool, reach + run.f.margin)
    else:
        return
    if section is None:
        return
    region = m3d.CrossSection.batch_boolean(sweep_polygon_2d(section, np.column_stack([r, z])), m3d.OpType.Add)
    # the part beyond the axis turns past it too, at the radius |x| (a revolve keeps only x >= 0)
    region = m3d.CrossSection.batch_boolean([region, region.mirror((1.0, 0.0))], m3d.OpType.Add)
    if run.f.outline_cs is not None and (region ^ run.f.outline_cs).area() <= 0:
        return
    b = region.bounds()
    r_out = max(abs(b[0]), abs(b[2]))
    cut = Cut(i + 0.5, [], region, np.array([-r_out, -r_out, b[1]]), np.array([r_out, r_out, b[3]]))
    if run.f.meets(cut.lo, cut.hi):
        run.bodies.append((cut, path))


class Profiles:
    """The lathe tools' profiles of one removal, each built once: a tap's teeth for a thread cut
    (stock/axial.py), a boring tool's profile trimmed to what can reach the bore along its path."""

    def __init__(self, frame: Frame, tol: float):
        self.frame, self.tol = frame, tol
        self.built: dict[int, np.ndarray] = {}

    def __call__(self, tool: ToolSpec, path=None) -> np.ndarray:
        if tool.kind == "tap" and isinstance(path, ScrewPath):  # under screw motion: its teeth (stock/axial.py)
            return axial_tool(tool, path)
        if tool.number not in self.built:
            self.built[tool.number] = lathe_profile(tool, self.tol)
        if path is not None and tool.side == "inside":  # a boring tool: only what can reach the bore
            return inner_trim(self.built[tool.number], *_path_rz(path), self.frame.outline_cs, self.frame.margin)
        return self.built[tool.number]


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


def screw_pieces(path: ScrewPath, profile: np.ndarray, outline, r_clip: float, margin: float):
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


def check_axis(path: ScrewPath, profile: np.ndarray) -> None:
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



def screw_triangles(path: ScrewPath, prof: m3d.CrossSection, s0: float, s1: float, tol: float,
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
        # the subtract intersects each turn with all of them: the work grows with that count.
        tris = round(tris * width / lead)
    return tris
