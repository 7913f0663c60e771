"""Measurements on a simulated solid (a manifold3d.Manifold in the workpiece frame, mm, degrees).

Sections come from manifold3d's exact plane slicing (``Manifold.slice`` after a rigid transform),
depths from ``Manifold.ray_cast``; nothing here samples the surface at random, so every function is
deterministic. Accuracy: a measured point lies on the simulated solid, which follows the true
surface to within the chordal tolerance it was built with (helices and arcs are chords inside the
true curve), so a measured radius can read up to that tolerance small.

Lathe vocabulary: the spindle axis is +Z; the half-plane at angle ``phi`` (degrees about +Z from
+X) holds the axial profile (r, z) at that angle.
"""
from __future__ import annotations

import math

import numpy as np


# --------------------------------------------------------------------------------------------
# sections
# --------------------------------------------------------------------------------------------
def _polygons(cs) -> list[np.ndarray]:
    return [np.asarray(p, dtype=np.float64) for p in cs.to_polygons() if len(p) >= 3]


def _edges(polys: list[np.ndarray]) -> np.ndarray:
    """All polygon edges as (n, 2, 2)."""
    if not polys:
        return np.zeros((0, 2, 2))
    return np.concatenate([np.stack([p, np.roll(p, -1, axis=0)], axis=1) for p in polys])


def half_plane_section(part, phi: float) -> list[np.ndarray]:
    """The section of ``part`` by the half-plane at angle ``phi``: closed polygons of (r, z), r >= 0."""
    from manifold3d import CrossSection

    c, s = math.cos(math.radians(phi)), math.sin(math.radians(phi))
    # rows: x' = r along phi, y' = z, z' = distance from the plane (normal (-s, c, 0))
    m = np.array([[c, s, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [-s, c, 0.0, 0.0]])
    cs = part.transform(m).slice(0.0)
    b = part.bounding_box()
    zlo, zhi = b[2] - 1.0, b[5] + 1.0
    rmax = max(abs(v) for v in b[:2] + b[3:5]) * 1.5 + 1.0
    box = CrossSection.square((rmax, zhi - zlo)).translate((0.0, zlo))
    return _polygons(cs ^ box)


# --------------------------------------------------------------------------------------------
# measuring angles clear of construction seams
# --------------------------------------------------------------------------------------------
# Every solid cutsim builds has its vertices on construction seams: a revolved solid (stock,
# turning) has its outline in the half-planes at k * 360 / segments from C0, a screw sweep has
# the tool profile in the half-plane of every station (one at the angle where the cut starts,
# others a turn apart), and a boolean leaves vertices where two surfaces meet. A section by a
# plane that holds such a seam is degenerate (whole edges lie in the plane), and manifold3d's
# slice can then join the wrong pieces: at C0 of a G33 cut started at the zero pulse the groove
# roots vanish from the section. Sections by a plane that holds no vertex cut every triangle
# transversally, so the measuring angles are moved into the widest vertex-free gap near the
# angle asked for, read from the solids themselves (whatever built them).
SEAM_RADIUS = 1e-6  # mm: vertices nearer the axis lie in every half-plane and have no angle


def vertex_angles(solids) -> np.ndarray:
    """Sorted, distinct angles (degrees in [0, 180)) of the vertices of ``solids`` off the axis,
    modulo 180: a half-plane section slices the whole plane, so a vertex on the far side
    (phi + 180) matters as much as one at phi."""
    from cutsim.stock.arrays import solid_arrays

    out = [np.zeros(0)]
    for s in solids:
        v = off_axis(solid_arrays(s)[0])
        out.append(np.degrees(np.arctan2(v[:, 1], v[:, 0])) % 180.0)
    return np.unique(np.concatenate(out))


def off_axis(v: np.ndarray) -> np.ndarray:
    """The vertices ``v`` (n, 3) that lie off the spindle axis (farther than SEAM_RADIUS of the
    solid's size): only they have an angle."""
    return v[np.hypot(v[:, 0], v[:, 1]) > SEAM_RADIUS * max(1.0, float(np.abs(v).max(initial=0.0)))]


def seam_free_angles(solids, phis, window: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """For each angle in ``phis`` (degrees) the angle within +-``window`` of it whose plane
    through the axis lies farthest (in angle) from every vertex of ``solids``, and that
    clearance (degrees; inf when no vertex is off the axis). Ties go to the angle nearest the
    one asked for, so the choice is deterministic."""
    phis = np.atleast_1d(np.asarray(phis, dtype=np.float64))
    a = vertex_angles(solids)
    if not len(a):
        return phis.copy(), np.full(phis.shape, np.inf)
    ext = np.concatenate([a - 180.0, a, a + 180.0, a[:1] + 360.0])
    out, clear = np.empty_like(phis), np.empty_like(phis)
    for i, phi in enumerate(phis):
        p0 = phi % 180.0
        j0 = max(int(np.searchsorted(ext, p0 - window, "right")) - 1, 0)
        j1 = max(min(int(np.searchsorted(ext, p0 + window, "left")), len(ext) - 1), j0 + 1)
        lo, hi = ext[j0:j1], ext[j0 + 1:j1 + 1]
        p = np.clip(0.5 * (lo + hi), p0 - window, p0 + window)
        c = np.minimum(p - lo, hi - p)
        k = int(np.lexsort((np.abs(p - p0), -c))[0])
        out[i], clear[i] = phi + (p[k] - p0), c[k]
    return out, clear


def plane_section(part, axis: str, at: float) -> list[np.ndarray]:
    """The section by the plane ``axis = at`` (axis "x", "y" or "z"): polygons in the other two
    coordinates in order (x: (y, z); y: (x, z); z: (x, y))."""
    if axis == "z":
        return _polygons(part.slice(at))
    if axis == "x":
        m = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, -at]])
    else:
        m = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, -at]])
    return _polygons(part.transform(m).slice(0.0))


def _line_crossings(edges: np.ndarray, v: float) -> np.ndarray:
    """u of every point where the horizontal line (second coordinate = v) crosses an edge."""
    u0, v0, u1, v1 = edges[:, 0, 0], edges[:, 0, 1], edges[:, 1, 0], edges[:, 1, 1]
    m = ((v0 <= v) & (v1 > v)) | ((v1 <= v) & (v0 > v))
    t = (v - v0[m]) / (v1[m] - v0[m])
    return np.sort(u0[m] + t * (u1[m] - u0[m]))


def outer_radius(polys: list[np.ndarray], z) -> np.ndarray:
    """Largest r of a half-plane section at each height ``z`` (nan where the section has none)."""
    edges = _edges(polys)
    z = np.atleast_1d(np.asarray(z, dtype=np.float64))
    out = np.full(z.shape, np.nan)
    if len(edges) == 0:
        return out
    r0, z0, r1, z1 = edges[:, 0, 0], edges[:, 0, 1], edges[:, 1, 0], edges[:, 1, 1]
    lo, hi = np.minimum(z0, z1), np.maximum(z0, z1)
    for a in range(0, len(z), 512):
        zz = z[a:a + 512, None]
        m = (lo <= zz) & (hi >= zz)
        dz = np.where(np.abs(z1 - z0) > 1e-15, z1 - z0, 1.0)
        t = np.clip((zz - z0) / dz, 0.0, 1.0)
        r = np.where(m, np.maximum(r0 + t * (r1 - r0), np.where(np.abs(z1 - z0) > 1e-15, -np.inf,
                                                                    np.maximum(r0, r1))), -np.inf)
        best = r.max(axis=1)
        out[a:a + 512] = np.where(np.isfinite(best), best, np.nan)
    return out


def outer_profile(part, phi: float, zlo: float, zhi: float, step: float = 0.01, inside: bool = False):
    """(z, r) of the outer profile at angle ``phi`` between ``zlo`` and ``zhi``: sampled every
    ``step`` and at every section vertex (so minima and maxima of the polyline are exact). With
    ``inside`` the inner profile (the bore's wall: the smallest r of material at each z)."""
    polys = half_plane_section(part, phi)
    if inside:  # the inner wall is the outer one of the section mirrored about the axis
        z, r = outer_profile_of([p * (-1.0, 1.0) for p in polys], zlo, zhi, step)
        return z, -r
    return outer_profile_of(polys, zlo, zhi, step)


def outer_profile_of(polys: list[np.ndarray], zlo: float, zhi: float, step: float):
    """``outer_profile`` of the (r, z) section polygons ``polys``."""
    verts = np.concatenate(polys) if polys else np.zeros((0, 2))
    n = max(2, int(math.ceil((zhi - zlo) / step)) + 1)
    z = np.concatenate([np.linspace(zlo, zhi, n), verts[(verts[:, 1] > zlo) & (verts[:, 1] < zhi), 1]])
    z = np.unique(z)
    return z, outer_radius(polys, z)


FLAT_ROOT = 1e-7  # relative: points this close to a groove's lowest are on its (flat) root


def groove_roots(z: np.ndarray, r: np.ndarray, min_depth: float = 0.02) -> np.ndarray:
    """(z, r) of the deepest point of each groove of an outer profile (the middle of a flat
    root): a groove is a run of the profile below the level halfway between its highest and
    lowest point; runs that touch either end of the profile (grooves cut off by the range) are
    left out."""
    ok = np.isfinite(r)
    z, r = z[ok], r[ok]
    if len(r) < 3 or r.max() - r.min() < min_depth:
        return np.zeros((0, 2))
    level = 0.5 * (r.max() + r.min())
    below = r < level
    roots = []
    i, n = 0, len(r)
    while i < n:
        if not below[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and below[j + 1]:
            j += 1
        if i > 0 and j < n - 1:
            run = r[i:j + 1]
            low = run <= run.min() + FLAT_ROOT * max(1.0, abs(float(run.min())))
            ks = i + np.flatnonzero(low)  # a flat root (a full-profile insert's tip): its middle
            roots.append((0.5 * (z[ks[0]] + z[ks[-1]]), r[ks[0]]))
        i = j + 1
    return np.array(roots).reshape(-1, 2)


# --------------------------------------------------------------------------------------------
# lathe: diameters, threads, ramps
# --------------------------------------------------------------------------------------------
def radii_at(part, z: float, angles: int = 72) -> np.ndarray:
    """Outer radius at height ``z`` along ``angles`` equally spaced directions from +X (nan where
    the ray from the axis meets no material)."""
    edges = _edges(plane_section(part, "z", z))
    phis = np.radians(np.arange(angles) * 360.0 / angles)
    out = np.full(angles, np.nan)
    if len(edges) == 0:
        return out
    p, q = edges[:, 0], edges[:, 1]
    for i, a in enumerate(phis):
        d = np.array([math.cos(a), math.sin(a)])
        e = q - p
        den = e[:, 0] * d[1] - e[:, 1] * d[0]
        ok = np.abs(den) > 1e-15
        # ray t*d = p + s*e  ->  solve for t (distance along the ray) and s in [0, 1]
        t = np.where(ok, (e[:, 0] * p[:, 1] - e[:, 1] * p[:, 0]) / np.where(ok, den, 1.0), -1.0)
        s = np.where(ok, (d[0] * p[:, 1] - d[1] * p[:, 0]) / np.where(ok, den, 1.0), -1.0)
        hit = ok & (t >= 0) & (s >= -1e-12) & (s <= 1 + 1e-12)
        if np.any(hit):
            out[i] = t[hit].max()
    return out


def diameters_at(part, z: float, angles: int = 72) -> np.ndarray:
    """Diameter (outer radius at phi + outer radius at phi + 180) for ``angles`` // 2 directions."""
    n = angles + angles % 2
    r = radii_at(part, z, n)
    return r[: n // 2] + r[n // 2:]


def min_radius_at(part, z: float) -> float:
    """Smallest distance from the axis to the outer boundary of the section at height ``z``: the
    root radius of a groove that crosses this height (nan without material)."""
    polys = plane_section(part, "z", z)
    if not polys:
        return float("nan")
    outer = max(polys, key=lambda p: abs(_signed_area(p)))
    e = np.stack([outer, np.roll(outer, -1, axis=0)], axis=1)
    p, d = e[:, 0], e[:, 1] - e[:, 0]
    ll = np.einsum("ij,ij->i", d, d)
    t = np.clip(np.where(ll > 0, -np.einsum("ij,ij->i", p, d) / np.where(ll > 0, ll, 1.0), 0.0), 0.0, 1.0)
    return float(np.min(np.linalg.norm(p + t[:, None] * d, axis=1)))


def root_radius_profile(part, zlo: float, zhi: float, step: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """(z, root radius) sampled every ``step`` between ``zlo`` and ``zhi`` (see min_radius_at)."""
    n = max(2, int(math.ceil((zhi - zlo) / step)) + 1)
    z = np.linspace(zlo, zhi, n)
    return z, np.array([min_radius_at(part, float(v)) for v in z])


def _signed_area(p: np.ndarray) -> float:
    return 0.5 * float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))


def _circ_mean(deg: np.ndarray) -> float:
    a = np.radians(deg)
    return float(np.degrees(math.atan2(np.sin(a).mean(), np.cos(a).mean())) % 360.0)


def _circ_diff(a, b):
    return (np.asarray(a) - np.asarray(b) + 180.0) % 360.0 - 180.0


def thread_angles(part, angles: int = 36) -> np.ndarray:
    """The ``angles`` measuring angles of a thread on ``part``: equally spaced from C0, each moved
    (by at most a tenth of the spacing, and 1 degree) to the plane clearest of construction seams
    (``seam_free_angles``). Measurements use the angle actually sectioned, so the move changes no
    result: a groove's z at angle phi is z0 + lead * phi / 360 whatever phi is."""
    nominal = np.arange(angles) * 360.0 / angles
    return seam_free_angles([part], nominal, min(1.0, 36.0 / angles))[0]


def measure_thread(part, zlo: float, zhi: float, angles: int = 36, step: float = 0.01, inside: bool = False) -> dict:
    """Lead, hand, number of starts, root diameter and the grooves' roots of a thread between
    ``zlo`` and ``zhi``; with ``inside`` of an inside thread (the grooves run outwards from the
    bore's wall: their roots are the largest radii of the inner profile). ``profiles`` lists the
    (angle, z, r) profile of every section, for the measurements of cutsim.reports.threads.

    The grooves' roots are found in half-plane sections at ``angles`` angles (``thread_angles``:
    about equally spaced, none on a construction seam). The pitch is the median distance between
    neighbouring roots at one angle. Lead and hand come from every root at once (``lead_fit``):
    each root linked to the nearest at the next angle, the slope of z against the angle fitted to
    the links near the median one (z rising with the angle about +Z: right-hand). Roots that a
    chamfer, a lead-in or a runout cut shallow or lopsided, where they are a minority, change
    nothing. starts = lead / pitch rounded. ``lead_links`` counts the links the lead was fitted
    to, ``track_degrees`` the degrees of the turn they cover. The root diameter is twice the
    median root radius.
    """
    phis = thread_angles(part, angles)
    per_angle, profiles = [], []
    sign = -1.0 if inside else 1.0
    for phi in phis:
        z, r = outer_profile(part, float(phi), zlo, zhi, step, inside)
        per_angle.append(groove_roots(z, sign * r) * (1.0, sign))
        profiles.append((float(phi), z, r))
    roots = [(float(phi), float(zr), float(rr)) for phi, rs in zip(phis, per_angle) for zr, rr in rs]
    out = {"roots": roots, "angles": [float(p) for p in phis], "lead": None, "hand": None, "starts": None,
           "pitch": None, "root_diameter": None, "root_diameter_min": None, "root_diameter_max": None,
           "profiles": profiles}
    if not roots:
        return out
    rr = np.array([r for _, _, r in roots])
    out["root_diameter"] = 2.0 * float(np.median(rr))
    out["root_diameter_min"] = 2.0 * float(rr.min())
    out["root_diameter_max"] = 2.0 * float(rr.max())
    gaps = np.concatenate([np.diff(np.sort(rs[:, 0])) for rs in per_angle if len(rs) > 1] or [np.zeros(0)])
    pitch = float(np.median(gaps)) if len(gaps) else None
    out["pitch"] = pitch
    fit = lead_fit(per_angle, phis, pitch)
    if fit is not None:
        slope, out["lead_links"], out["track_degrees"] = fit
        out["lead"] = abs(slope) * 360.0
        out["hand"] = "right" if slope > 0 else "left"
        out["starts"] = max(1, int(round(out["lead"] / pitch))) if pitch else 1
    return out


LEAD_LINK = 0.01  # a link between roots farther than this fraction of the pitch off the median slope is left out


def lead_fit(per_angle: list[np.ndarray], phis: np.ndarray, pitch: float | None) -> tuple[float, int, float] | None:
    """Slope of the grooves (mm of z per degree; its sign is the hand), the number of links it was
    fitted to and the degrees of the turn they cover, from the roots ``per_angle`` (z, r) at the
    increasing angles ``phis`` (degrees, less than a turn) of grooves ``pitch`` apart.

    Every root is linked to the root nearest it at the next angle (from the last angle to the
    first a turn on): between neighbouring angles a groove moves lead x spacing / 360, under half
    a pitch as long as starts < angles / 2, so a link stays in its groove. A link's slope is its
    dz / dphi. Links that cross from a complete groove to one a chamfer, lead-in or runout cut
    shallow or lopsided, or from one groove to the next where a groove leaves the range, are
    off the median slope by a sizeable part of a pitch; those farther than LEAD_LINK x pitch (x
    the lead without a pitch) from it are left out and the slope is the least-squares one of the
    rest. Links within a displaced groove, and within a start cut late, keep the slope: the
    lead is that of every groove. None with fewer than 3 links."""
    n = len(phis)
    links = []  # (step, dphi, dz)
    for j in range(n if n > 1 else 0):
        a, b = per_angle[j][:, 0], per_angle[(j + 1) % n][:, 0]
        a, b = a[np.isfinite(a)], b[np.isfinite(b)]  # a root a section could not place
        if len(a) and len(b):
            dphi = float((phis[(j + 1) % n] - phis[j]) % 360.0)
            dz = b[np.argmin(np.abs(b[None, :] - a[:, None]), axis=1)] - a
            links += [(j, dphi, float(d)) for d in dz]
    if len(links) < 3:
        return None
    k = np.array(links)
    med = float(np.median(k[:, 2] / k[:, 1]))
    tol = LEAD_LINK * (pitch or abs(med) * 360.0)
    k = k[np.abs(k[:, 2] - med * k[:, 1]) <= tol]
    if not len(k):
        return None
    slope = float(np.sum(k[:, 1] * k[:, 2]) / np.sum(k[:, 1] ** 2))
    steps = np.unique(k[:, 0].astype(int))
    return slope, int(len(k)), float(sum((phis[(j + 1) % n] - phis[j]) % 360.0 for j in steps))


def thread_phases(roots, lead: float, hand: str, phase_z: float) -> np.ndarray:
    """The start phase of each root (phi, z, r): the ``a`` in ``z = phase_z + s*lead*(phi + a)/360
    (mod lead)``, s = +1 right-hand, -1 left-hand; degrees in [0, 360)."""
    s = 1.0 if hand == "right" else -1.0
    a = np.array([(s * (z - phase_z) * 360.0 / lead - phi) for phi, z, _ in roots], dtype=float)
    return a[np.isfinite(a)] % 360.0  # a root the section could not place (NaN) has no phase


def assign_phases(measured: np.ndarray, expected: list[float]) -> list[dict]:
    """Group measured phases by the nearest expected one: per expected phase the circular mean of
    its group, its signed error and the group's size and spread."""
    exp = np.asarray(expected, dtype=float) % 360.0
    d = np.abs(_circ_diff(measured[:, None], exp[None, :]))
    near = np.argmin(d, axis=1)
    out = []
    for k, e in enumerate(exp):
        grp = measured[near == k]
        if len(grp) == 0:
            out.append({"expected": float(e), "measured": None, "error": None, "roots": 0, "spread": None})
            continue
        err = float(_circ_diff(_circ_mean(grp), e))
        m = float(e) + err  # reported next to the expected value (359.9 for 0 reads -0.1)
        out.append({"expected": float(e), "measured": m, "error": err, "roots": int(len(grp)),
                    "spread": float(np.max(np.abs(_circ_diff(grp, m))))})
    return out


# --------------------------------------------------------------------------------------------
# mill: depth at a point, gaps (slots, pockets)
# --------------------------------------------------------------------------------------------
def depth_at(part, x: float, y: float) -> float | None:
    """Z of the first surface met going down the vertical line at (x, y) from above the part
    (None when the line misses it)."""
    b = part.bounding_box()
    top, bot = b[5] + 1.0, b[2] - 1.0
    hits = part.ray_cast((x, y, top), (x, y, bot))
    if not hits:
        return None
    return float(hits[0].position[2])


def gap_at(part, point, direction: str) -> tuple[float, float] | None:
    """The empty interval along ``direction`` ("x" or "y") through ``point`` (x, y, z) that is
    bounded by material on both sides: (low, high) coordinates; None when ``point`` is inside
    material or the gap is open on a side."""
    x, y, z = point
    if direction == "x":
        polys, u, v = plane_section(part, "y", y), x, z  # (x, z)
    else:
        polys, u, v = plane_section(part, "x", x), y, z  # (y, z)
    cr = _line_crossings(_edges(polys), v)
    left, right = cr[cr < u], cr[cr > u]
    if len(left) % 2 == 1 or not len(left) or not len(right):
        return None
    return float(left[-1]), float(right[0])


# --------------------------------------------------------------------------------------------
# design comparison
# --------------------------------------------------------------------------------------------
def _point_triangle_distance(pts: np.ndarray, tri: np.ndarray, max_only: bool = False
                             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distance from every point to the nearest triangle, that nearest point and the triangle's
    index. Exact: brute force when points x triangles is small, else pruned with a kd-tree of the
    triangle centroids (scipy). With ``max_only`` only the largest distance is exact: points
    that cannot beat it keep an upper bound that is no larger than it."""
    n, m = len(pts), len(tri)
    best = np.full(n, np.inf)
    near = np.zeros_like(pts)
    idx = np.zeros(n, dtype=np.int64)
    if n == 0 or m == 0:
        return best, near, idx
    if n * m > 500_000:
        from scipy.spatial import cKDTree

        # exact pruning: the distance to the triangles of the nearest centroids is an upper
        # bound; a triangle within it has its centroid within the bound plus its own radius.
        # Large triangles (radius above the 90th percentile) are always tested.
        cen = tri.mean(axis=1)
        rad = np.linalg.norm(tri - cen[:, None, :], axis=2).max(axis=1)
        rsmall = float(np.percentile(rad, 90))
        big = np.flatnonzero(rad > rsmall)
        tree = cKDTree(cen)
        ub, near_c = tree.query(pts, k=1)
        best[:], idx[:] = ub, near_c
        near[:] = cen[near_c]
        kk = min(8, m)  # exact distances to the triangles of the kk nearest centroids: a tight bound
        _, cnear = tree.query(pts, k=kk)
        cnear = cnear.reshape(n, kk)
        for i in range(0, n, 8192):
            c = cnear[i:i + 8192]
            t = tri[c]
            p = pts[i:i + 8192, None, :]
            q = _closest_on_triangles(p, t[..., 0, :], t[..., 1, :], t[..., 2, :],
                                      t[..., 1, :] - t[..., 0, :], t[..., 2, :] - t[..., 0, :])
            d = np.linalg.norm(q - p, axis=2)
            j = np.argmin(d, axis=1)
            rows = np.arange(len(j))
            better = d[rows, j] < best[i:i + 8192]
            sl = np.arange(i, i + len(j))[better]
            best[sl], near[sl], idx[sl] = d[rows, j][better], q[rows, j][better], c[rows, j][better]
        ub = best.copy()
        small = rad <= rsmall
        top = 0.0
        order = np.argsort(-ub, kind="stable") if max_only else range(n)
        for i in order:
            if max_only and ub[i] <= top:
                break
            cand = np.asarray(tree.query_ball_point(pts[i], ub[i] + rsmall + 1e-9), dtype=np.int64)
            cand = np.concatenate([cand[small[cand]], big]) if len(cand) else big
            if len(cand):
                t = tri[cand]
                p = pts[i][None, :]
                q = _closest_on_triangles(p, t[:, 0], t[:, 1], t[:, 2], t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
                d = np.linalg.norm(q - p, axis=1)
                j = int(np.argmin(d))
                if d[j] < best[i]:
                    best[i], near[i], idx[i] = d[j], q[j], cand[j]
            top = max(top, best[i])
        return best, near, idx
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    ab, ac = b - a, c - a
    chunk = max(1, 2_000_000 // m)
    for i in range(0, n, chunk):
        p = pts[i:i + chunk, None, :]
        q = _closest_on_triangles(p, a, b, c, ab, ac)
        d = np.linalg.norm(q - p, axis=2)
        k = np.argmin(d, axis=1)
        rows = np.arange(len(k))
        best[i:i + chunk], near[i:i + chunk], idx[i:i + chunk] = d[rows, k], q[rows, k], k
    return best, near, idx


def _closest_on_triangles(p, a, b, c, ab, ac):
    """Closest points on triangles (a, b, c) to points p (Ericson, Real-Time Collision Detection)."""
    ap = p - a
    d1, d2 = np.einsum("...k,...k", ab, ap), np.einsum("...k,...k", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("...k,...k", ab, bp), np.einsum("...k,...k", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("...k,...k", ab, cp), np.einsum("...k,...k", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    den = va + vb + vc
    den = np.where(np.abs(den) > 1e-300, den, 1e-300)
    v = vb / den
    w = vc / den
    res = a + ab * v[..., None] + ac * w[..., None]  # interior
    # edges
    with np.errstate(divide="ignore", invalid="ignore"):
        t_ab = np.clip(d1 / (d1 - d3), 0, 1)
        t_ac = np.clip(d2 / (d2 - d6), 0, 1)
        t_bc = np.clip((d4 - d3) / ((d4 - d3) + (d5 - d6)), 0, 1)
    e_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    e_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    e_bc = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
    res = np.where(e_bc[..., None], b + (c - b) * np.nan_to_num(t_bc)[..., None], res)
    res = np.where(e_ac[..., None], a + ac * np.nan_to_num(t_ac)[..., None], res)
    res = np.where(e_ab[..., None], a + ab * np.nan_to_num(t_ab)[..., None], res)
    # vertices
    res = np.where(((d6 >= 0) & (d5 <= d6))[..., None], c + 0 * p, res)
    res = np.where(((d3 >= 0) & (d4 <= d3))[..., None], b + 0 * p, res)
    res = np.where(((d1 <= 0) & (d2 <= 0))[..., None], a + 0 * p, res)
    return res


def load_solid(path: str):
    """A closed mesh file (STL, 3MF, OBJ, ...) as a manifold3d.Manifold; raises ValueError when it
    does not describe a closed solid."""
    import trimesh

    from cutsim.stock.arrays import solid_of

    mesh = trimesh.load(path, force="mesh")
    mesh.merge_vertices()
    man = solid_of(mesh.vertices, mesh.faces)
    if man.status().name != "NoError" or man.is_empty():
        raise ValueError(f"{path} is not a closed solid ({man.status().name})")
    return man


def _mesh(man) -> tuple[np.ndarray, np.ndarray]:
    from cutsim.stock.arrays import solid_arrays

    return solid_arrays(man)


def _probe_points(man) -> np.ndarray:
    """Vertices, edge midpoints and centroids of a solid's triangles (large flat faces have no
    inner vertices; their centroids are where the distance to the other surface is largest)."""
    v, f = _mesh(man)
    t = v[f]
    return np.concatenate([v, t.mean(axis=1), 0.5 * (t[:, 0] + t[:, 1]), 0.5 * (t[:, 1] + t[:, 2]),
                           0.5 * (t[:, 2] + t[:, 0])])


def _farthest(pts: np.ndarray, v: np.ndarray, f: np.ndarray) -> tuple[float, int]:
    """The largest distance from the points to the triangle mesh (v, f) and the index of that
    point. Exact closest-point queries in VTK's static cell locator (a BVH of bins, C++, one call
    for all points); VTK is imported here only, so the core imports without it. Without VTK: the
    numpy/scipy search of ``_point_triangle_distance``."""
    try:
        from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
        from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
        from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance
    except ImportError:  # pragma: no cover - VTK comes with pyvista; kept for a core-only install
        d, _n, _i = _point_triangle_distance(pts, v[f], max_only=True)
        k = int(np.argmax(d))
        return float(d[k]), k
    poly = vtkPolyData()
    vp = vtkPoints()
    vp.SetData(numpy_to_vtk(np.ascontiguousarray(v, dtype=np.float64), deep=True))
    poly.SetPoints(vp)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(f) + 1, 3, dtype=np.int64), deep=True),
                  numpy_to_vtkIdTypeArray(np.ascontiguousarray(f, dtype=np.int64).ravel(), deep=True))
    poly.SetPolys(cells)
    dist = vtkImplicitPolyDataDistance()
    dist.SetInput(poly)
    out = vtkDoubleArray()
    dist.FunctionValue(numpy_to_vtk(np.ascontiguousarray(pts, dtype=np.float64), deep=True), out)
    d = np.abs(vtk_to_numpy(out))  # signed by VTK's normals; only the size is used
    k = int(np.argmax(d))
    return float(d[k]), k


def compare_design(part, design, stock=None, max_points: int = 20000) -> dict:
    """Gouge and excess of ``part`` against ``design`` (both manifolds, same frame).

    gouge volume: design material that is missing from the part (inside the design and the stock,
    removed); excess volume: part material outside the design. The worst deviation is the largest
    distance from a vertex of the gouge or excess solids to the surface on the other side (for a
    gouge: design points inside the design to the part surface; for excess: part points to the
    design surface), with its location and sign (negative = gouge).

    One boolean in the usual case: ``part.split(design)`` gives part & design and the excess at
    once; the part lies in the stock, so the gouge volume is vol(design & stock) - vol(part &
    design). The gouge solid itself (for its probe points) is built only when that is positive."""
    target = design ^ stock if stock is not None else design
    inside, excess = part.split(design)
    gouge_vol = float(target.volume()) - float(inside.volume())
    out = {"gouge_volume": max(0.0, gouge_vol), "excess_volume": max(0.0, float(excess.volume())),
           "worst_deviation": 0.0, "worst_location": None}
    cands = []
    if not excess.is_empty():
        dv, df = _mesh(design)
        ev = _probe_points(excess)
        ev = ev[:: max(1, len(ev) // max_points)]
        d, k = _farthest(ev, dv, df)
        cands.append((d, ev[k]))
    if gouge_vol > GOUGE_EPS:
        gouge = target - part
        if not gouge.is_empty():
            pv_, pf = _mesh(part)
            gv = _probe_points(gouge)
            gv = gv[:: max(1, len(gv) // max_points)]
            d, k = _farthest(gv, pv_, pf)
            cands.append((-d, gv[k]))
    if cands:
        d, loc = max(cands, key=lambda c: abs(c[0]))
        out["worst_deviation"] = d
        out["worst_location"] = [float(v) for v in loc]
    return out


GOUGE_EPS = 1e-9  # mm^3: a smaller gouge volume is rounding (the gouge solid is not built)
