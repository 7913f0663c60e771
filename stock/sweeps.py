"""Exact swept solids of tools along kinematic paths.

- screw_sweep: the tool profile under (generalised) screw motion, built directly: the profile is
  extruded along a parameter axis and warped onto the helix (``warp_batch``). Stations are spaced
  so the chord of the outermost point deviates at most ``tol``; ramp kinks are stations.
- planar_region: the 2D area a lathe profile sweeps along an (r, z) polyline (hulls of convex
  pieces), later unioned with the others and revolved once.
- spatial_hulls: a convex tool body on straight segments, one hull per segment.
"""
from __future__ import annotations

import math

import manifold3d as m3d
import numpy as np

from cutsim.interp.errors import CutsimError
from cutsim.kinematics.paths import PlanarPath, ScrewPath, SpatialPath, segment_angle

from .tools import convex_pieces, counter_clockwise, perimeter, positive, signed_area

MAX_CHUNK_DEGREES = 300.0  # a chunk narrower than one turn never overlaps itself


def profile_region(profile: np.ndarray) -> m3d.CrossSection:
    """The region of a tool profile polygon, whatever its orientation: it is made counter-clockwise
    before the Positive fill rule sees it (a clockwise polygon would be an empty region), and the
    region must have the polygon's area (a self-crossing outline would not)."""
    poly = counter_clockwise(profile)
    cs = m3d.CrossSection([poly], m3d.FillRule.Positive)
    a = signed_area(poly)
    if not abs(cs.area() - a) <= 1e-6 * a + 1e-7 * perimeter(poly):  # Clipper's rounding (tools.polygon_problem)
        raise RuntimeError(f"internal: a tool profile of area {a:.6g} mm^2 gives a region of {cs.area():.6g} mm^2")
    return cs


def clipped_profile(profile: np.ndarray, height: float) -> m3d.CrossSection:
    """The profile cut off at u = ``height``: the part of the tool that can reach the stock."""
    cs = profile_region(profile)
    lo, hi = profile[:, 1].min() - 1.0, profile[:, 1].max() + 1.0
    u0 = min(-1.0, float(profile[:, 0].min()) - 1.0)  # below the whole profile (an inside tool's too)
    box = m3d.CrossSection([np.array([[u0, lo], [height, lo], [height, hi], [u0, hi]])])
    return cs ^ box


def inner_trim(profile: np.ndarray, r: np.ndarray, z: np.ndarray, outline: m3d.CrossSection | None,
               margin: float) -> np.ndarray:
    """An inside tool's profile (reaching from its point towards the axis) cut off where it can
    no longer meet the stock on a path through the tool points at radii ``r``, heights ``z``:
    below the stock's smallest radius over the heights the tool reaches, less ``margin`` (a boring
    bar's insert in a bore: the part of the tool in the free bore only costs triangles, and a
    tall V would reach over many turns of a thread). A sliver at the point always stays; the
    profile is unchanged where the stock reaches the axis, where the tool reaches across the axis
    to the stock beyond it (a revolved sweep holds that side too), or for a stock that is not a
    solid of revolution."""
    if outline is None:
        return profile
    vlo, vhi = float(profile[:, 1].min()), float(profile[:, 1].max())
    zlo, zhi = float(np.min(z)) + vlo - margin, float(np.max(z)) + vhi + margin
    b = outline.bounds()
    band = m3d.CrossSection([np.array([[b[0] - 1.0, zlo], [b[2] + 1.0, zlo], [b[2] + 1.0, zhi], [b[0] - 1.0, zhi]])])
    inside = outline ^ band
    rmin = float(inside.bounds()[0]) if not inside.is_empty() else float(b[2])
    umin, umax = float(profile[:, 0].min()), float(profile[:, 0].max())
    free = rmin - margin  # no stock within this radius
    if free <= 0.0 or float(np.min(r)) + umin < -free:  # the tool reaches across the axis into the stock
        return profile
    low = min(free - float(np.max(r)), umax - 1e-3 * (umax - umin))  # (a sliver of the point stays)
    if low <= umin:
        return profile
    box = m3d.CrossSection([np.array([[low, vlo - 1.0], [umax + 1.0, vlo - 1.0], [umax + 1.0, vhi + 1.0],
                                      [low, vhi + 1.0]])])
    polys = (profile_region(profile) ^ box).to_polygons()
    return counter_clockwise(polys[0]) if len(polys) == 1 else profile


# The side faces between two stations are twisted quads, split by one diagonal that always runs
# the same way. A profile edge e = (e_r, e_z) at radius >= r, stepped by d_theta under a motion
# with dr/dtheta = a, dz/dtheta = p, gives quads whose fourth corner is off the plane of the other
# three by t = |e_r (e_z a - e_r p)| d_theta / (r |e|) (a plain turn, a = p = 0, is a cone: flat
# quads). The diagonal then lies up to t/4 off the ruled surface, t/12 on average, always on the
# same side: on long flanks of a steep lead that biased the volume (+0.07 % for a 4 mm flank, lead
# 8 mm, at 2 um). Edges are cut into pieces so that t/4 <= TWIST_FRACTION x tol (the bias then
# stays below tol/6 per unit area, under the chords' own), and never into more pieces than
# EDGE_STEPS * sqrt(tol * r) long, the length of one chord at tolerance tol. An M70x1.5 groove
# (t = 0.09 um at 1 um) is not cut at all: a third of the triangles it had with the length rule.
EDGE_STEPS = 2.0
TWIST_FRACTION = 0.5


def edge_pieces(poly: np.ndarray, max_len: float, twist: tuple[float, float, float] | None = None) -> np.ndarray:
    """How many pieces each edge ``poly[i] -> poly[i+1]`` is cut into (``subdivide``): by length
    ``max_len``, or with ``twist`` = (a, p, d_theta / (r TWIST_FRACTION tol)) only as far as the
    twist of its side quads needs (never more pieces than by length)."""
    e = np.roll(poly, -1, axis=0) - poly
    ln = np.hypot(e[:, 0], e[:, 1])
    k = np.maximum(1, np.ceil(ln / max_len))
    if twist is not None:
        a, p, scale = twist
        er, ez = np.abs(e[:, 0]), np.abs(e[:, 1])
        t = er * (ez * abs(a) + er * abs(p)) * scale / np.maximum(ln, 1e-300)
        k = np.minimum(k, np.maximum(1, np.ceil(t / 4.0)))
    return k.astype(np.int64)


def screw_twist(path: ScrewPath, profile: m3d.CrossSection, tol: float, s0: float = 0.0,
                s1: float = 1.0) -> tuple[float, float, float] | None:
    """The ``twist`` argument of ``edge_pieces`` for ``profile`` swept along ``path`` over [s0, s1]
    (largest |dr/dtheta|, |dz/dtheta| between the ramp kinks, the station angle, the innermost
    radius); None when the path does not turn (then the length rule alone)."""
    big = 2.0 * math.pi * path.revolutions
    if not big > 0:
        return None
    b = profile.bounds()
    brk = np.array([s0] + [x for x in path.breakpoints() if s0 < x < s1] + [s1])
    r, z, _ = path.pose(brk)
    ds = np.diff(brk) * big
    ok = ds > 0
    if not ok.any():
        return None
    a = float(np.max(np.abs(np.diff(r))[ok] / ds[ok]))
    p = float(np.max(np.abs(np.diff(z))[ok] / ds[ok]))
    rin = float(r.min()) + b[0]
    if not rin > 0:
        return None
    dth = segment_angle(float(r.max()) + b[2], tol)
    return a, p, dth / (rin * TWIST_FRACTION * tol)


def subdivide(cs: m3d.CrossSection, max_len: float, twist: tuple[float, float, float] | None = None) -> m3d.CrossSection:
    """The same region with extra (collinear) vertices so no edge is longer than ``max_len`` (with
    ``twist``: only where the side quads' twist needs it, ``edge_pieces``)."""
    polys = []
    for poly in cs.to_polygons():
        out = []
        nxt = np.roll(poly, -1, axis=0)
        for p, q, k in zip(poly, nxt, edge_pieces(poly, max_len, twist)):
            t = np.arange(k)[:, None] / k
            out.append(p + t * (q - p))
        polys.append(np.vstack(out))
    return m3d.CrossSection(polys, m3d.FillRule.Positive)


def screw_sweep(path: ScrewPath, profile: m3d.CrossSection, tol: float,
                s0: float = 0.0, s1: float = 1.0, zwindow: tuple[float, float] | None = None) -> list[m3d.Manifold]:
    """Solids whose union is the profile swept along ``path`` for s in [s0, s1] (workpiece frame).

    With ``zwindow`` only the stretches between stations that can reach those heights are built,
    on exactly the stations of the full sweep: the same solid, restricted near the window.
    """
    bounds = profile.bounds()  # (umin, vmin, umax, vmax)
    width = bounds[3] - bounds[1]
    brk = [s0] + [b for b in path.breakpoints() if s0 < b < s1] + [s1]
    rmax = float(np.max(path.pose(np.array(brk))[0]))
    reach = rmax + bounds[2]
    total = 360.0 * path.revolutions
    lead = path.travel / path.revolutions if path.revolutions > 0 else math.inf
    step = math.degrees(segment_angle(reach, tol))
    # The whole cut is one piece unless the profile is wider than the lead (turns would overlap);
    # then pieces narrower than a turn. Ramp ends are piece ends, so the kinks are exact.
    single = width < 0.999 * lead
    limit = math.inf if single else MAX_CHUNK_DEGREES
    edges = [brk[0]]
    for a, b in zip(brk, brk[1:]):
        span = (b - a) * total
        k = max(1, math.ceil(span / limit)) if span > 0 else 1
        edges.extend(np.linspace(a, b, k + 1)[1:].tolist())
    # orientation: the map (u, v, t) -> space keeps handedness when phi falls with t
    flip = path.sense > 0
    prof = profile.mirror((0.0, 1.0)) if flip else profile
    prof = subdivide(prof, EDGE_STEPS * math.sqrt(tol * reach), screw_twist(path, profile, tol, s0, s1))
    out = []
    for a, b in zip(edges, edges[1:]):
        if b - a <= 0:
            continue
        n = max(1, math.ceil((b - a) * total / step))
        if zwindow is not None:
            zs = path.pose(a + (b - a) * np.arange(n + 1) / n)[1]
            reach_v = max(abs(bounds[1]), abs(bounds[3]))
            near = np.nonzero((np.minimum(zs[:-1], zs[1:]) - reach_v <= zwindow[1]) &
                              (np.maximum(zs[:-1], zs[1:]) + reach_v >= zwindow[0]))[0]
            if len(near) == 0:
                continue
            j, k = int(near[0]), int(near[-1]) + 1
            a, b, n = a + (b - a) * j / n, a + (b - a) * k / n, k - j
        solid = m3d.Manifold.extrude(prof, 1.0, n_divisions=n - 1)

        def warp(p, a=a, b=b):
            s = a + (b - a) * np.clip(p[:, 2], 0.0, 1.0)
            r, z, phi = path.pose(s)
            u = p[:, 0]
            v = -p[:, 1] if flip else p[:, 1]
            rr = r + u
            return np.column_stack([rr * np.cos(phi), rr * np.sin(phi), z + v])

        swept = solid.warp_batch(warp)
        if swept.status() == m3d.Error.NoError and swept.volume() < 0:
            raise _folded(path, profile, tol)
        out.append(positive(swept, "a screw motion"))
    return out


def _folded(path: ScrewPath, profile: m3d.CrossSection, tol: float) -> CutsimError:
    """A needle-thin profile (thinner than the twist of the side faces between two stations, as a
    steep lead at a coarse tolerance gives) folds its chorded sweep over itself: an input error
    that a finer tolerance cures, named with a tolerance that works (mean width 2 area/perimeter)."""
    length = sum(perimeter(q) for q in profile.to_polygons())
    width = 2.0 * profile.area() / length if length > 0 else 0.0
    return CutsimError(path.src.program, path.src.line, path.src.col,
                       f"the swept solid of this thread cut folds over itself: the tool is only about {width:.4f} mm "
                       f"wide where it can cut, too thin for the chordal tolerance {tol:g} mm; simulate with a finer "
                       f"tolerance (at most about {math.floor(width / 4 * 1e4) / 1e4:g} mm)")


def sweep_polygon_2d(poly: np.ndarray, pts: np.ndarray) -> list[m3d.CrossSection]:
    """Regions whose union is ``poly`` (either orientation) translated along the polyline ``pts``."""
    pieces = convex_pieces(poly)
    regions = []
    for piece in pieces:
        for p0, p1 in zip(pts[:-1], pts[1:]):
            regions.append(m3d.CrossSection.hull_points(np.vstack([piece + p0, piece + p1])))
        if len(pts) == 1:
            regions.append(m3d.CrossSection([piece + pts[0]]))
    return regions


def planar_region(path: PlanarPath, profile: np.ndarray) -> m3d.CrossSection:
    return m3d.CrossSection.batch_boolean(sweep_polygon_2d(profile, path.points), m3d.OpType.Add)


def spatial_hulls(path: SpatialPath, body: list[np.ndarray]) -> list[m3d.Manifold]:
    c, s = math.cos(math.radians(path.angle)), math.sin(math.radians(path.angle))
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    out = []
    for piece in body:
        v = piece @ rot.T
        for p0, p1 in zip(path.points[:-1], path.points[1:]):
            out.append(m3d.Manifold.hull_points(np.vstack([v + p0, v + p1])))
    return out
