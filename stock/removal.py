"""Material removal: every path's swept solid, subtracted from the stock in one batch.

Order does not change the final part (subtraction commutes), so all solids are built first and
removed with one ``batch_boolean``. Order matters only for the warnings: a rapid (G00), or a cut
with the spindle stopped, is reported when it removes material that is still there at that moment,
i.e. from the stock minus the earlier cuts that overlap it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import manifold3d as m3d
import numpy as np

from cutsim.kinematics.paths import PlanarPath, ScrewPath, SpatialPath, circle_segments

from .build import stock_outline
from .specs import StockSpec, ToolSpec
from .sweeps import clipped_profile, planar_region, screw_sweep, spatial_hulls
from .tools import lathe_body, lathe_profile, mill_body

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


def _bbox(solids: list[m3d.Manifold]):
    los, his = [], []
    for s in solids:
        b = s.bounding_box()
        los.append(b[:3])
        his.append(b[3:])
    return np.min(los, axis=0), np.max(his, axis=0)


def _overlap(lo1, hi1, lo2, hi2) -> bool:
    return bool(np.all(lo1 <= hi2) and np.all(lo2 <= hi1))


def remove(stock: m3d.Manifold, spec: StockSpec, paths: list, tol: float,
           progress: Progress | None = None) -> Removal:
    sb = stock.bounding_box()
    slo, shi = np.array(sb[:3]), np.array(sb[3:])
    rmax = float(max(np.hypot(slo[0], slo[1]), np.hypot(shi[0], shi[1]), np.hypot(slo[0], shi[1]),
                     np.hypot(shi[0], slo[1])))
    margin = max(10 * tol, 0.05)
    r_clip = rmax + margin
    nseg = circle_segments(rmax, tol)
    outline = stock_outline(spec)
    outline_cs = m3d.CrossSection([outline], m3d.FillRule.Positive) if outline is not None else None

    profiles: dict[int, np.ndarray] = {}
    bodies: dict[int, list] = {}

    def profile(tool: ToolSpec) -> np.ndarray:
        if tool.number not in profiles:
            profiles[tool.number] = lathe_profile(tool, tol)
        return profiles[tool.number]

    def body(tool: ToolSpec) -> list:
        if tool.number not in bodies:
            bodies[tool.number] = lathe_body(tool, tol) if tool.is_lathe_tool else mill_body(tool, tol)
        return bodies[tool.number]

    def revolve(region: m3d.CrossSection) -> m3d.Manifold:
        return m3d.Manifold.revolve(region, circular_segments=nseg)

    cuts: list[_Cut] = []
    checks: list[tuple[_Cut, object]] = []
    n = len(paths)
    for i, path in enumerate(paths):
        if progress:
            progress("sweeping", i, n)
        if isinstance(path, ScrewPath):
            rmin, _ = path.radius_range()
            h = r_clip - rmin
            if h <= 0:
                continue
            prof = clipped_profile(profile(path.tool), h)
            if prof.is_empty():
                continue
            solids = screw_sweep(path, prof, tol)
            lo, hi = _bbox(solids)
            if _overlap(lo, hi, slo, shi):
                cuts.append(_Cut(i, solids, None, lo, hi))
        elif isinstance(path, PlanarPath):
            pts = path.points
            h = r_clip - float(pts[:, 0].min())
            if h <= 0:
                continue
            prof = clipped_profile(profile(path.tool), h)
            if prof.is_empty():
                continue
            region = m3d.CrossSection.batch_boolean([planar_region(path, p) for p in prof.to_polygons()],
                                                    m3d.OpType.Add)
            if outline_cs is not None and (region ^ outline_cs).area() <= 0:
                continue
            b = region.bounds()
            r_out = max(abs(b[0]), abs(b[2]))
            cut = _Cut(i, [], region, np.array([-r_out, -r_out, b[1]]), np.array([r_out, r_out, b[3]]))
            if _overlap(cut.lo, cut.hi, slo, shi):
                cuts.append(cut)
                if path.rapid:
                    checks.append((cut, path))
        elif isinstance(path, SpatialPath):
            solids = spatial_hulls(path, body(path.tool))
            lo, hi = _bbox(solids)
            if _overlap(lo, hi, slo, shi):
                cut = _Cut(i, solids, None, lo, hi)
                cuts.append(cut)
                if path.rapid or path.tool.is_lathe_tool:
                    checks.append((cut, path))
    if progress:
        progress("sweeping", n, n)

    warnings = []
    for k, (cut, path) in enumerate(checks):
        if progress:
            progress("checking rapids", k, len(checks))
        vol = _fresh_volume(stock, cut, cuts, revolve)
        if vol > MIN_COLLISION_VOLUME:
            if path.rapid:
                msg = f"rapid (G00) cuts the stock: {vol:.3f} mm^3 removed"
            else:
                msg = f"cutting with the spindle stopped: only the tool's own swept volume is removed ({vol:.3f} mm^3)"
            warnings.append((path.src, msg))

    if progress:
        progress("subtracting", 0, 1)
    solids = [s for c in cuts for s in c.solids]
    regions = [c.region for c in cuts if c.region is not None]
    if regions:
        solids.append(revolve(m3d.CrossSection.batch_boolean(regions, m3d.OpType.Add)))
    part = m3d.Manifold.batch_boolean([stock] + solids, m3d.OpType.Subtract) if solids else stock
    part = drop_debris(part)
    if progress:
        progress("subtracting", 1, 1)
    return Removal(part, warnings, len(solids))


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


def _fresh_volume(stock, cut: _Cut, cuts: list[_Cut], revolve) -> float:
    """Volume ``cut`` removes from the stock as it is when the cut happens."""
    mine = cut.solids if cut.region is None else [revolve(cut.region)]
    hit = m3d.Manifold.batch_boolean([stock, m3d.Manifold.batch_boolean(mine, m3d.OpType.Add)], m3d.OpType.Intersect)
    if hit.volume() <= MIN_COLLISION_VOLUME:
        return 0.0
    earlier = [c for c in cuts if c.index < cut.index and _overlap(c.lo, c.hi, cut.lo, cut.hi)]
    prior = [s for c in earlier for s in c.solids]
    regions = [c.region for c in earlier if c.region is not None]
    if regions:
        prior.append(revolve(m3d.CrossSection.batch_boolean(regions, m3d.OpType.Add)))
    if prior:
        hit = m3d.Manifold.batch_boolean([hit] + prior, m3d.OpType.Subtract)
    return float(hit.volume())
