"""Milling checks: what a mill move must not do besides cutting, found against the material still
there when the move runs.

- a plunge (feed downwards) with a tool that cannot cut at its centre;
- a cut deeper than the flutes: the tool above them (the shank) meets material;
- the solids the collision checks use: the tool shrunk by a few tolerances, so the slivers two
  discretisations of one surface leave between a move and the earlier cuts do not count.

The volumes come from the caller (``fresh``: the stock as it is before a move, stock/collisions.py);
this module builds the solids to measure and decides which moves to check.
"""
from __future__ import annotations

import math
from dataclasses import replace

import manifold3d as m3d
import numpy as np

from cutsim.base.specs import ToolSpec
from cutsim.kinematics.paths import ArcRun, SpatialPath, segment_angle

from .mill import Z_EPS, Level, MillBatch, batchable, prism, sweep

CHECK_SHRINK = 2.0  # tolerances the tool shrinks by for the collision checks


def plunges(path: SpatialPath) -> bool:
    """A feed move downwards with a tool that cannot cut at its centre."""
    if path.rapid or path.tool.is_lathe_tool or path.tool.center_cutting:
        return False
    return float(path.points[-1, 2]) < float(path.points[0, 2]) - Z_EPS


def plunge_message(path: SpatialPath, vol: float) -> str:
    return (f"plunge (feed downwards in Z) with the non-centre-cutting tool T{path.tool.number} "
            f"into the stock: {vol:.3f} mm^3")


def flute_short(zmin: float, tool: ToolSpec, top: float) -> bool:
    """The stock reaches above the flutes somewhere: a candidate for the flute-length check."""
    return zmin + tool.length < top - Z_EPS


def shank_level(level: Level, top: float) -> m3d.Manifold:
    """What the part of the tool above the flutes sweeps on a level (up to the stock top), shrunk
    by ``CHECK_SHRINK`` tolerances so discretisation slivers against the earlier cuts do not count."""
    reg = level.region().offset(-CHECK_SHRINK * level.tol, m3d.JoinType.Round, 2.0, 16)
    return prism(reg, level.z + level.tool.length, top + 1.0)


def check_solids(path: SpatialPath, tol: float, cap: float) -> list[m3d.Manifold]:
    """The move's swept solid for the collision checks: the tool shrunk by ``CHECK_SHRINK``
    tolerances (radius and tip) so the slivers two discretisations of one surface leave between a
    move and the earlier cuts are not reported as collisions; any real collision remains."""
    t = path.tool
    d = max(t.diameter - 2 * CHECK_SHRINK * tol, t.diameter / 2)
    cr = t.corner_radius if t.corner_radius <= 0 else max(0.0, t.corner_radius - (t.diameter - d) / 2)
    small = replace(t, diameter=d, corner_radius=min(cr, d / 2))
    moved = replace(path, tool=small, points=path.points + np.array([0.0, 0.0, CHECK_SHRINK * tol]))
    return sweep(moved, tol, cap)


def shank_hulls(path: SpatialPath, top: float, tol: float) -> list[m3d.Manifold]:
    """The tool above its flutes (a cylinder of the tool diameter up to the stock top) swept along
    a 3D path: one hull per segment."""
    r = path.tool.diameter / 2.0 - CHECK_SHRINK * tol
    n = max(8, math.ceil(2 * math.pi / segment_angle(r, tol)))
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    ring = np.column_stack([r * np.cos(ang), r * np.sin(ang)])
    out = []
    for p0, p1 in zip(path.points[:-1], path.points[1:]):
        pts = []
        for p in (p0, p1):
            z0 = p[2] + path.tool.length
            if z0 >= top:
                continue
            for z in (z0, top + 1.0):
                pts.append(np.column_stack([ring + p[:2], np.full(n, z)]))
        if pts:
            out.append(m3d.Manifold.hull_points(np.vstack(pts)))
    return out


def flute_message(tool: ToolSpec, z: float, top: float, vol: float) -> str:
    return (f"the cut is deeper than the flute length of T{tool.number} ({tool.length:g} mm): material up to "
            f"Z{top:g} above the flutes at tip Z{z:g} ({vol:.3f} mm^3 would meet the shank)")



def flute_warnings(batch: MillBatch, paths: list, top: float, tol: float, fresh, bottom: float = -math.inf) -> list:
    """(src, message) for the first move of each tool that cuts deeper than its flutes: the tool
    above the flutes would meet material still there (``fresh(index, solids)`` gives the volume of
    ``solids`` inside the stock as it is before the move ``index``). Checked in program order only
    where the tip is lower than the stock top minus the flute length.

    A candidate whose shank, within the stock's heights (``bottom`` .. ``top``), lies inside the
    shank of an earlier candidate that met no fresh material meets none either (the stock only
    loses material), so it is not checked again: the same XY path (a cycle's passes repeated at
    every depth step) with the shank's lower end at every point no lower than there, or below the
    stock's bottom on both ends of the earlier one's segment (``_shadowed``): a deep pocket cycle is
    then checked down to its first pass below the stock, not at every depth step."""
    cands = []
    for lv in batch.levels():
        if flute_short(lv.z, lv.tool, top):
            key = ("level", lv.tool.diameter, tuple(_xy_key(pl) for pl in lv.polylines()))
            low = np.array([lv.z + lv.tool.length])
            cands.append((lv.index, lv.src, lv.tool, lv.z, lambda lv=lv: [shank_level(lv, top)], key, low))
    for i, p in enumerate(paths):
        if not isinstance(p, SpatialPath) or p.rapid or p.tool.is_lathe_tool or batchable(p):
            continue
        zmin = float(p.points[:, 2].min())
        if flute_short(zmin, p.tool, top):
            low = p.points[:, 2] + p.tool.length
            low = np.where(low >= top, math.inf, low)  # shank_hulls leaves such a pose out
            key = ("path", p.tool.diameter, _xy_key(p.points))
            cands.append((i, p.src, p.tool, zmin, lambda p=p: shank_hulls(p, top, tol), key, low))
    out, warned = [], set()
    clean: dict[tuple, list[np.ndarray]] = {}  # key -> the lower ends of candidates that found nothing

    found: dict[int, float] = {}

    def volume(c) -> float:
        idx, src, tool, z, solids, key, low = c
        if idx not in found:
            sol = [] if any(_shadowed(low, b, bottom) for b in clean.get(key, ())) else solids()
            found[idx] = fresh(idx, sol) if sol else 0.0
        return found[idx]

    for group in _deepening_runs(sorted(cands, key=lambda c: c[0]), paths, bottom):
        tool = group[0][2]
        if tool.number in warned:
            continue
        hit = next((c for c in group[:1] if volume(c) > 1e-3), None)
        rest = group[1:]
        if hit is None and rest and volume(rest[-1]) > 1e-3:  # bisect for the first that meets material
            lo, hi = 0, len(rest) - 1
            while lo < hi:
                mid = (lo + hi) // 2
                lo, hi = (lo, mid) if volume(rest[mid]) > 1e-3 else (mid + 1, hi)
            hit = rest[lo]
        if hit is not None:
            warned.add(tool.number)
            out.append((hit[1], flute_message(tool, hit[3], top, found[hit[0]])))
        else:
            clean.setdefault(group[-1][5], []).append(group[-1][6])
    return out


def _deepening_runs(cands: list, paths: list, bottom: float) -> list[list]:
    """The flute candidates (in program order) in groups: a group after its first member holds the
    consecutive arcs the sweep joins into one helix (``ArcRun``: one cut, before all of
    them) whose shanks each contain the one before (same XY path, lower ends no higher). Those see
    the same earlier cuts, so the fresh material their shanks meet can only grow along the group:
    the first that meets any is found by bisection (a helix of 20,000 turns descending below its
    flutes: 15 checks, not 20,000). Every other candidate is a group of its own."""
    groups: list[list] = []
    for c in cands:
        g = groups[-1] if groups else None
        if g is not None and g[-1][0] + 1 == c[0] and g[-1][5] == c[5] and c[5][0] == "path":
            p, q = paths[g[-1][0]], paths[c[0]]
            if (not plunges(p) and not plunges(q) and ArcRun(0, p).extend(q)
                    and _shadowed(g[-1][6], c[6], bottom)):
                g.append(c)
                continue
        groups.append([c])
    return groups


def _xy_key(pts: np.ndarray) -> bytes:
    """The XY polyline on a 1e-9 mm grid: candidates with the same key sweep the same footprint."""
    return np.round(np.asarray(pts, dtype=float)[:, :2] * 1e9).astype(np.int64).tobytes()


def _shadowed(low: np.ndarray, earlier: np.ndarray, bottom: float) -> bool:
    """Whether the shank with lower ends ``low`` at the poses of an XY path lies, above the stock's
    ``bottom``, inside the shank of the same path with lower ends ``earlier``: per segment (a level:
    its one height) either the lower ends no lower at both poses (the hull of the shorter columns
    lies in the hull of the longer ones), or the earlier ends both at or below the stock's bottom
    (above it the earlier shank is the whole column over the footprint)."""
    if len(low) != len(earlier):
        return False
    if len(low) == 1:
        return bool(low[0] >= earlier[0] or earlier[0] <= bottom)
    higher = (low[:-1] >= earlier[:-1]) & (low[1:] >= earlier[1:])
    full = (earlier[:-1] <= bottom) & (earlier[1:] <= bottom)
    return bool(np.all(higher | full))
