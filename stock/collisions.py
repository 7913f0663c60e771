"""Collision diagnostics: what a move removes from the material still there when it runs.

Order does not change the final part (subtraction commutes), so all cuts are built first and
removed in one batch; order matters only for the warnings. A rapid (G00), a plunge with a tool
that cannot cut at its centre, a lathe tool with the spindle stopped, a mill's shank above its
flutes and the gauge point of a move without a tool are reported when they meet material that is
still there at that moment: the stock minus the earlier cuts that overlap them (``fresh``).
"""
from __future__ import annotations

import bisect
from typing import Callable

import manifold3d as m3d
import numpy as np

from . import gauge, inserts, mill_checks
from .budget import Built
from .cuts import Cut, bbox, box_overlap, overlap
from .mill_checks import plunge_message
from .strategy import Run

# A collision smaller than this is numerical noise between two discretisations of one surface.
MIN_COLLISION_VOLUME = 1e-3  # mm^3
FRESH_BATCH = 16  # most earlier sweeps taken off a check's hit per boolean

Progress = Callable[[str, int, int], None]


def collision_warnings(stock: m3d.Manifold, run: Run, built: Built, progress: Progress | None = None) -> list:
    """(src, message) for each checked move that removes material still there when it runs."""
    warnings = []
    for k, (cut, path) in enumerate(run.checks):
        if progress:
            progress("checking rapids", k, len(run.checks))
        vol = fresh_volume(stock, cut, run.cuts, run.f.revolve, built)
        if vol > MIN_COLLISION_VOLUME:
            if path.rapid:
                msg = f"rapid (G00) cuts the stock: {vol:.3f} mm^3 removed"
            elif not path.tool.is_lathe_tool:
                msg = plunge_message(path, vol)
            else:
                msg = f"cutting with the spindle stopped: only the tool's own swept volume is removed ({vol:.3f} mm^3)"
            warnings.append((path.src, msg))
    return warnings


def gauge_warnings(stock: m3d.Manifold, run: Run, moves: list, built: Built,
                   progress: Progress | None = None) -> list:
    """(src, message) for each move with no tool whose gauge point runs inside the material still
    there when it moves (stock/gauge.py). Only a move inside the stock as it came can be; the moves
    between two cuts (one stretch without a tool) all meet the same material, taken once."""
    inside: dict[int, list] = {}  # cuts before the move -> [(index, path)] inside the stock as it came
    starts = sorted(c.index for c in run.cuts)
    for k, (i, path) in enumerate(moves):
        if progress:
            progress("checking moves without a tool", k, len(moves))
        lo, hi = path.points.min(axis=0), path.points.max(axis=0)
        if run.f.meets(lo, hi) and gauge.inside_length(stock, path.points, run.tol) > run.tol:
            inside.setdefault(bisect.bisect_left(starts, i), []).append((i, path))
    warnings = []
    for stretch in inside.values():
        pts = np.concatenate([p.points for _, p in stretch])
        box = gauge.probe(pts)
        lo, hi = bbox([box])
        i = stretch[0][0]
        material = stock
        if any(c.index < i and overlap(c.lo, c.hi, lo, hi) for c in run.cuts):
            material = fresh(stock, Cut(i, [box], None, lo, hi), run.cuts, run.f.revolve, built)
        for _, path in stretch:
            length = 0.0 if material is None else gauge.inside_length(material, path.points, run.tol)
            if length > run.tol:
                warnings.append((path.src, gauge.message(length)))
    return warnings


def fresh_volume(stock, cut: Cut, cuts: list[Cut], revolve, built: Built | None = None) -> float:
    """Volume ``cut`` removes from the stock as it is when the cut happens (``built``: the lazily
    swept earlier cuts already built for other checks)."""
    hit = fresh(stock, cut, cuts, revolve, built)
    return 0.0 if hit is None else float(hit.volume())


def fresh(stock, cut: Cut, cuts: list[Cut], revolve, built: Built | None = None) -> m3d.Manifold | None:
    """The part of the stock, as it is when ``cut`` happens, that ``cut``'s solids cover; None when
    that is no more than MIN_COLLISION_VOLUME."""
    mine = cut.get() if cut.region is None else [revolve(cut.region)]
    hit = m3d.Manifold.batch_boolean([stock, m3d.Manifold.batch_boolean(mine, m3d.OpType.Add)], m3d.OpType.Intersect)
    if hit.volume() <= MIN_COLLISION_VOLUME:
        return None
    b = hit.bounding_box()
    hlo, hhi = np.array(b[:3]), np.array(b[3:])
    earlier = [c for c in cuts if c.index < cut.index and overlap(c.lo, c.hi, hlo, hhi)]
    # only the pieces of earlier sweeps that can reach what this cut hits (a long thread is many turns:
    # rebuilt only near the heights this cut reaches); a 3D mill chain's pieces, swept when they are
    # subtracted (``Cut.build``), are built only when the loop below comes to them
    hvol = float(np.prod(np.maximum(hhi - hlo, 1e-9)))

    def cover(lo, hi) -> float:
        return round(box_overlap(lo, hi, hlo, hhi) / hvol, 3)

    items = []  # (cover, order, solid or lazy Cut)
    for c in earlier:
        if c.build is not None and c.near is None:
            items.append((cover(c.lo, c.hi), len(items), c))
            continue
        for s in (c.near(float(hlo[2]), float(hhi[2])) if c.near is not None else c.get()):
            lo, hi = bbox([s])
            if overlap(lo, hi, hlo, hhi):
                items.append((cover(lo, hi), len(items), s))
    regions = [c.region for c in earlier if c.region is not None]
    if regions:
        s = revolve(m3d.CrossSection.batch_boolean(regions, m3d.OpType.Add))
        items.append((cover(*bbox([s])), -1, s))
    # The sweeps whose boxes cover most of the hit's box first (newest first among equals), in
    # batches of 1, 2, 4 ... FRESH_BATCH, stopping once nothing is left: the hit is small and the
    # earlier sweeps overlap each other (a pocket's passes), so their union in one batch costs far
    # more than taking them off the hit a few at a time, and one or two sweeps (the move a retract
    # starts from, the shallower pass that cleared what is above the flutes) usually take it all.
    # A lazy chain piece is built only when the queue comes to it: most checks never need it.
    queue = [it[2] for it in sorted(items, key=lambda t: (-t[0], -t[1]))]
    queue.reverse()  # popped from the end
    size = 1
    while queue:
        batch = []
        while queue and len(batch) < size:
            x = queue.pop()
            if isinstance(x, Cut):  # a lazy chain piece: its hulls that reach the hit, best first
                sols = built.get(x) if built is not None else [(s, *bbox([s])) for s in x.get()]
                got = [(cover(lo, hi), k, s) for k, (s, lo, hi) in enumerate(sols) if overlap(lo, hi, hlo, hhi)]
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


def flute_warnings(stock: m3d.Manifold, run: Run, paths: list, built: Built) -> list:
    """(src, message) for the first move of each mill that cuts deeper than its flutes
    (stock/mill_checks.py), measured against the material still there when it runs."""
    def fresh_at(index: int, solids: list) -> float:
        return fresh_volume(stock, Cut(index, solids, None, *bbox(solids)), run.cuts, run.f.revolve, built)

    return mill_checks.flute_warnings(run.levels, paths, run.f.top, run.tol, fresh_at, float(run.f.lo[2]))


def body_warnings(stock: m3d.Manifold, run: Run, built: Built, progress: Progress | None = None) -> list:
    """(src, message) for the first move of each lathe tool whose body (an inside tool's boring
    bar, an outside or face tool's holder) meets material still there when it moves (the move's
    own cut done: the insert leads the body). One warning per tool, as for the flute length: the
    moves after it mostly repeat it."""
    warnings, warned = [], set()
    for k, (cut, path) in enumerate(run.bodies):
        if progress:
            progress("checking tool bodies", k, len(run.bodies))
        tool = path.tool
        if tool.number in warned:
            continue
        vol = fresh_volume(stock, cut, run.cuts, run.f.revolve, built)
        if vol > MIN_COLLISION_VOLUME:
            warned.add(tool.number)
            warnings.append((path.src, inserts.body_message(tool, vol)))
    return warnings
