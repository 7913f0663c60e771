"""Thread gauging on a simulated solid: major, minor and pitch diameters of outside and inside
threads, the pitch diameter both as the diameter where groove and ridge are equally wide and over
three wires of the best size (docs/checks.md, "thread").

Every measurement is made in the half-plane sections ``measure.measure_thread`` takes (none on a
construction seam); its ``profiles`` are the exact outline of the part in each: (z, r) with every
section vertex, linear in between. To treat outside and inside threads alike the profile is turned
into a depth coordinate u (u = r outside, u = -r inside): grooves are where u is low, ridges
where it is high, and diameters are 2|u|.
"""
from __future__ import annotations

import math

import numpy as np

from . import measure as M

FLANK_ANGLE = 60.0  # degrees: ISO metric threads (ISO 68-1)


def best_wire(pitch: float, flank_angle: float = FLANK_ANGLE) -> float:
    """The best wire size, touching the flanks at the pitch diameter: P / (2 cos(alpha/2))
    (0.57735 P for 60 degree threads)."""
    return pitch / (2.0 * math.cos(math.radians(flank_angle / 2.0)))


def pitch_from_wires(m: float, wire: float, pitch: float, inside: bool, flank_angle: float = FLANK_ANGLE) -> float:
    """The pitch diameter from a measurement over (outside) or between (inside) three wires, the
    symmetric-thread formula without lead-angle correction:
    d2 = M - dw (1 + 1/sin(alpha/2)) + (P/2) cot(alpha/2), and for an inside thread
    D2 = M + dw (1 + 1/sin(alpha/2)) - (P/2) cot(alpha/2)."""
    half = math.radians(flank_angle / 2.0)
    k = wire * (1.0 + 1.0 / math.sin(half)) - 0.5 * pitch / math.tan(half)
    return m + k if inside else m - k


STATION_CLUSTER = 1e-4  # degrees: vertex angles closer than this are one seam (float noise)
STATION_OFFSET = 0.01  # degrees past a station's seam where the diameters are measured
MIN_CLEARANCE = 2e-4  # degrees: a measuring plane at least this far from every vertex


def _seams(part, zlo: float, zhi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The seams of ``part``: clusters of its vertices' angles (modulo 180, off the axis) as
    (first angle, last angle, count of the vertices between ``zlo`` and ``zhi``), sorted, the
    circle cut in its widest gap. (Every vertex places a seam; only those over the thread count
    towards telling a thread's station from a revolved solid's seam.)"""
    from cutsim.stock.arrays import solid_arrays

    v = M.off_axis(solid_arrays(part)[0])
    a = np.degrees(np.arctan2(v[:, 1], v[:, 0])) % 180.0
    order = np.argsort(a)
    a, w = a[order], ((v[:, 2] >= zlo) & (v[:, 2] <= zhi))[order].astype(np.int64)
    if not len(a):
        return a, a, w
    gaps = np.diff(np.append(a, a[0] + 180.0))
    k = int(np.argmax(gaps))
    a = np.concatenate([a[k + 1:], a[:k + 1] + 180.0])  # the widest gap at the end
    w = np.concatenate([w[k + 1:], w[:k + 1]])
    start = np.concatenate([[True], np.diff(a) > STATION_CLUSTER])
    first = np.flatnonzero(start)
    last = np.append(first[1:], len(a)) - 1
    return a[first], a[last], np.add.reduceat(w, first)


def gauge_angles(part, angles: int = 36, zlo: float = -math.inf, zhi: float = math.inf) -> np.ndarray:
    """Measuring angles for the diameters: for each of ``angles`` equally spaced angles from C0,
    the seam holding the most vertices between ``zlo`` and ``zhi`` within half a spacing of it
    (over a thread, a screw sweep's station: there the tool profile lies on the true helicoid,
    between stations its flanks are chords up to the tolerance inside it) and the plane STATION_OFFSET beside it, on the side with the
    wider gap (at most halfway to the next seam), so it holds no vertex. Where no seam qualifies,
    the angle clearest of seams (``measure.seam_free_angles``). Sorted, distinct, degrees."""
    lo, hi, cnt = _seams(part, zlo, zhi)
    step = 360.0 / angles
    nominal = np.arange(angles) * step
    if not len(lo):
        return nominal
    after = np.append(lo[1:], lo[0] + 180.0) - hi
    before = lo - np.insert(hi[:-1], 0, hi[-1] - 180.0)
    out = []
    for phi in nominal:
        d = (lo - phi + 90.0) % 180.0 - 90.0
        near = np.flatnonzero(np.abs(d) <= step / 2.0)
        for k in near[np.lexsort((np.abs(d[near]), -cnt[near]))]:
            if max(after[k], before[k]) >= 2.0 * MIN_CLEARANCE:
                side = min(STATION_OFFSET, 0.5 * max(after[k], before[k]))
                out.append(phi + d[k] + (hi[k] - lo[k] + side if after[k] >= before[k] else -side))
                break
        else:
            out.append(float(M.seam_free_angles([part], [phi], step / 2.0)[0][0]))
    return np.unique(np.round(np.asarray(out) % 360.0, 9))


def _depth(profile, inside: bool) -> tuple[np.ndarray, np.ndarray]:
    _phi, z, r = profile
    ok = np.isfinite(r)
    return z[ok], (-r[ok] if inside else r[ok])


def _groove_fraction(z: np.ndarray, u: np.ndarray, level: float) -> float:
    """Share of the length of the polyline (z, u) over which u lies below ``level``."""
    z0, z1, u0, u1 = z[:-1], z[1:], u[:-1], u[1:]
    lo, hi = np.minimum(u0, u1), np.maximum(u0, u1)
    span = np.where(hi > lo, hi - lo, 1.0)
    frac = np.where(hi <= level, 1.0, np.where(lo >= level, 0.0, np.clip((level - lo) / span, 0.0, 1.0)))
    return float(np.sum(frac * (z1 - z0)) / (z[-1] - z[0]))


def equal_width_level(z: np.ndarray, u: np.ndarray, roots: np.ndarray) -> float | None:
    """The level u at which the grooves and the ridges of the profile are equally wide along z,
    over the whole number of groove spacings between its first and last root (each groove and
    ridge counted once); None with fewer than two roots."""
    if len(roots) < 2:
        return None
    za, zb = float(roots[0, 0]), float(roots[-1, 0])
    keep = (z > za) & (z < zb)
    zz = np.concatenate([[za], z[keep], [zb]])
    uu = np.interp(zz, z, u)
    lo, hi = float(uu.min()), float(uu.max())
    for _ in range(60):  # the groove's share grows with the level: bisection to below 1e-15 mm
        mid = 0.5 * (lo + hi)
        if _groove_fraction(zz, uu, mid) < 0.5:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _wire_height(z: np.ndarray, u: np.ndarray, zc: float, rw: float) -> float:
    """Lowest u of the centre of a circle of radius ``rw`` at ``zc`` lying on the profile: the
    largest u(z) + sqrt(rw^2 - (z - zc)^2) over the profile's segments, each exactly (the point
    of a straight segment where the circle touches it)."""
    i0 = max(int(np.searchsorted(z, zc - rw)) - 1, 0)
    i1 = min(int(np.searchsorted(z, zc + rw)) + 1, len(z) - 1)
    z0, z1, u0, u1 = z[i0:i1], z[i0 + 1:i1 + 1], u[i0:i1], u[i0 + 1:i1 + 1]
    b = (u1 - u0) / (z1 - z0)
    a0, a1 = np.maximum(z0, zc - rw), np.minimum(z1, zc + rw)
    ok = a1 >= a0
    t = np.clip(zc + b * rw / np.sqrt(1.0 + b * b), a0, a1)
    h = u0 + b * (t - z0) + np.sqrt(np.maximum(rw * rw - (t - zc) ** 2, 0.0))
    return float(np.max(h[ok])) if np.any(ok) else math.nan


def wire_centre(z: np.ndarray, u: np.ndarray, z_root: float, rw: float, pitch: float) -> float:
    """The u of the centre of a wire of radius ``rw`` pressed into the groove whose root is at
    ``z_root``: the lowest it can sit, between the flanks (searched within a quarter pitch of
    the root on a grid, then by golden section)."""
    grid = np.linspace(z_root - pitch / 4.0, z_root + pitch / 4.0, 41)
    hs = [_wire_height(z, u, float(g), rw) for g in grid]
    k = int(np.nanargmin(hs))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = _wire_height(z, u, c, rw), _wire_height(z, u, d, rw)
    for _ in range(50):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = _wire_height(z, u, c, rw)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = _wire_height(z, u, d, rw)
    return min(fc, fd, float(np.nanmin(hs)))


def gauge(measured: dict, pitch: float, inside: bool, wire: float | None = None) -> dict:
    """Major, minor and pitch diameters (median over the sections, with their min..max) of the
    thread ``measured`` by ``measure.measure_thread`` (its ``profiles``): ``pitch`` is the
    spacing of neighbouring grooves (lead / starts), ``wire`` the wire diameter (best size by
    default). Values are None when a section holds no complete groove and ridge."""
    wire = best_wire(pitch) if wire is None else wire
    crests, roots, levels, centres = [], [], [], []
    for prof in measured.get("profiles", []):
        z, u = _depth(prof, inside)
        if len(z) < 3:
            continue
        rts = M.groove_roots(z, u)
        crs = M.groove_roots(z, -u)
        crests.extend(-crs[:, 1])
        roots.extend(rts[:, 1])
        lvl = equal_width_level(z, u, rts)
        if lvl is not None:
            levels.append(lvl)
        for zr in rts[:, 0]:
            if z[0] + pitch <= zr <= z[-1] - pitch:  # the wire's whole groove in the range
                centres.append(wire_centre(z, u, float(zr), wire / 2.0, pitch))
    crest_d, root_d, pitch_d = _diam(crests), _diam(roots), _diam(levels)
    centre = float(np.median(centres)) if centres else None
    if centre is None:
        over = None
    else:
        over = 2.0 * abs(centre) + (-wire if inside else wire)
    out = {"major_diameter": root_d if inside else crest_d, "minor_diameter": crest_d if inside else root_d,
           "pitch_diameter": pitch_d, "wire": wire, "over_wires": over,
           "pitch_diameter_wires": None if over is None else pitch_from_wires(over, wire, pitch, inside),
           "sections": len(levels), "wires": len(centres)}
    return out


def gauge_part(part, zlo: float, zhi: float, pitch: float, inside: bool, angles: int = 36,
               wire: float | None = None, step: float = 0.01) -> dict:
    """``gauge`` of the thread on ``part`` between ``zlo`` and ``zhi``, in the sections at
    ``gauge_angles``."""
    profs = [(float(phi),) + M.outer_profile(part, float(phi), zlo, zhi, step, inside)
             for phi in gauge_angles(part, angles, zlo, zhi)]
    return gauge({"profiles": profs}, pitch, inside, wire)


def _diam(us: list) -> dict | None:
    """Median and range of 2|u|, or None."""
    a = 2.0 * np.abs(np.asarray(us, dtype=float))
    a = a[np.isfinite(a)]
    if not len(a):
        return None
    return {"median": float(np.median(a)), "min": float(a.min()), "max": float(a.max())}
