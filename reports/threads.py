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
from dataclasses import dataclass

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
STATION_SHARE = 0.5  # a seam with at least this share of the most vertices near a direction is a station
MAX_SECTIONS = 8  # sections per direction at most (one per start whose station is needed)


@dataclass
class Seams:
    """The seams of a part: clusters of its vertices' angles in the half-plane (0..360 degrees, off
    the axis), sorted, the circle cut in its widest gap; per seam its first and last angle, and
    the heights of its vertices between ``zlo`` and ``zhi`` in the deeper half of the thread
    (below the level halfway between the deepest and the highest vertex there, in the depth
    u = r outside, -r inside): a screw sweep's station holds the tool's point at every turn, at
    the groove roots, where the seams of the revolved blank hold only the grooves' mouths on its
    surface; ``a180`` every vertex angle modulo 180, sorted (a section is of the whole plane)."""
    lo: np.ndarray
    hi: np.ndarray
    zs: list
    a180: np.ndarray

    @property
    def count(self) -> np.ndarray:
        return np.array([len(z) for z in self.zs], dtype=np.int64)


def _seams(part, zlo: float, zhi: float, inside: bool) -> Seams:
    from cutsim.stock.arrays import solid_arrays

    v = M.off_axis(solid_arrays(part)[0])
    a = np.degrees(np.arctan2(v[:, 1], v[:, 0])) % 360.0
    u = np.hypot(v[:, 0], v[:, 1]) * (-1.0 if inside else 1.0)
    over = (v[:, 2] >= zlo) & (v[:, 2] <= zhi)
    mid = 0.5 * (u[over].min() + u[over].max()) if over.any() else 0.0
    order = np.argsort(a, kind="stable")
    a, z = a[order], np.where(over & (u < mid), v[:, 2], np.nan)[order]
    if not len(a):
        return Seams(a, a, [], a)
    k = int(np.argmax(np.diff(np.append(a, a[0] + 360.0))))
    a = np.concatenate([a[k + 1:], a[:k + 1] + 360.0])  # the widest gap at the end
    z = np.concatenate([z[k + 1:], z[:k + 1]])
    first = np.flatnonzero(np.concatenate([[True], np.diff(a) > STATION_CLUSTER]))
    last = np.append(first[1:], len(a)) - 1
    zs = [g[np.isfinite(g)] for g in np.split(z, first[1:])]
    return Seams(a[first], a[last], zs, np.sort(a % 180.0))


def _gap(a180: np.ndarray, edge: float, sign: float) -> float:
    """Degrees from ``edge`` to the next vertex angle (modulo 180) beyond it, towards ``sign``."""
    e = edge % 180.0
    if sign > 0:
        j = int(np.searchsorted(a180, e, "right"))
        return float((a180[j] if j < len(a180) else a180[0] + 180.0) - e)
    j = int(np.searchsorted(a180, e, "left")) - 1
    return float(e - (a180[j] if j >= 0 else a180[-1] - 180.0))


def _beside(seams: Seams, k: int) -> tuple[float, float]:
    """The plane STATION_OFFSET past seam ``k`` (at most halfway to the next vertex), on the side
    with the wider gap, and its clearance (degrees)."""
    after, before = _gap(seams.a180, seams.hi[k], 1.0), _gap(seams.a180, seams.lo[k], -1.0)
    if after >= before:
        side = min(STATION_OFFSET, 0.5 * after)
        return float(seams.hi[k] + side), side
    side = min(STATION_OFFSET, 0.5 * before)
    return float(seams.lo[k] - side), side


def on_station(zf: np.ndarray, zs: np.ndarray | None, pitch: float) -> np.ndarray:
    """Which of the features at heights ``zf`` (groove roots, crests) lie in the tool profile of
    the station whose vertices are at heights ``zs``: within half a groove spacing of one of
    them (another start's groove, a spacing away, is then read at its chords). All with ``zs``
    None (a section clear of every seam)."""
    zf = np.asarray(zf, dtype=float)
    if zs is None:
        return np.ones(zf.shape, dtype=bool)
    if not len(zs):
        return np.zeros(zf.shape, dtype=bool)
    zs = np.sort(zs)
    j = np.clip(np.searchsorted(zs, zf), 1, len(zs) - 1) if len(zs) > 1 else np.zeros(zf.shape, dtype=np.int64)
    d = np.minimum(np.abs(zs[j] - zf), np.abs(zs[np.maximum(j - 1, 0)] - zf))
    return d < 0.5 * pitch


def gauge_sections(part, angles: int, zlo: float, zhi: float, pitch: float, inside: bool,
                   step: float = 0.01) -> list[tuple]:
    """The sections the diameters are measured in, (angle, z, r, station heights or None): for each
    of ``angles`` equally spaced directions from C0, the plane beside the seam with the most
    deep vertices (``Seams``) within half a spacing of it (a screw sweep's station:
    there the tool profile lies on the true helicoid, between stations its flanks are chords up
    to the tolerance inside it), then beside the next such seams as long as grooves of the first
    section lie in none of the taken stations (the other starts of a multi-start thread, each
    swept with its own stations), at most MAX_SECTIONS. Where no seam qualifies, the plane
    clearest of seams (``measure.seam_free_angles``), all its grooves counted."""
    seams = _seams(part, zlo, zhi, inside)
    cnt = seams.count
    spacing = 360.0 / angles
    out, taken = [], set()
    for phi in np.arange(angles) * spacing:
        d = (seams.lo - phi + 180.0) % 360.0 - 180.0
        near = np.flatnonzero((np.abs(d) <= spacing / 2.0) & (cnt > 0))
        if len(near):
            near = near[cnt[near] >= STATION_SHARE * cnt[near].max()]
            near = near[np.lexsort((np.abs(d[near]), -cnt[near]))]
        got, uncovered = 0, None
        for k in near:
            if k in taken or (uncovered is not None and not on_station(uncovered, seams.zs[k], pitch).any()):
                continue
            x, clear = _beside(seams, int(k))
            if clear < MIN_CLEARANCE:
                continue
            taken.add(k)
            z, r = M.outer_profile(part, x, zlo, zhi, step, inside)
            out.append((x % 360.0, z, r, seams.zs[k]))
            got += 1
            if uncovered is None:
                uncovered = M.groove_roots(*_depth((x, z, r), inside))[:, 0]
            uncovered = uncovered[~on_station(uncovered, seams.zs[k], pitch)]
            if not len(uncovered) or got >= MAX_SECTIONS:
                break
        if not got:
            x = float(M.seam_free_angles([part], [phi], spacing / 2.0)[0][0])
            out.append((x % 360.0,) + tuple(M.outer_profile(part, x, zlo, zhi, step, inside)) + (None,))
    return out


def _depth(profile, inside: bool) -> tuple[np.ndarray, np.ndarray]:
    z, r = profile[1], profile[2]
    ok = np.isfinite(r)
    return z[ok], (-r[ok] if inside else r[ok])


def groove_level(z: np.ndarray, u: np.ndarray, z_root: float, pitch: float) -> float | None:
    """The level u at which the groove whose root is at ``z_root`` is half the groove spacing
    ``pitch`` wide (where it and the ridges beside it are equally wide: the pitch line of ISO
    5408), or the lower of its two crests when it is narrower than that even there; None when the
    profile does not reach half a spacing beyond the root on either side. Each flank (root to
    the crest within a spacing) is made monotone outwards (its running maximum) and crossed by
    interpolation; the width grows with the level: bisection to below 1e-15 mm."""
    if z_root - 0.5 * pitch < z[0] or z_root + 0.5 * pitch > z[-1]:
        return None
    i = int(np.searchsorted(z, z_root))
    lo_i = int(np.searchsorted(z, z_root - pitch))
    hi_i = int(np.searchsorted(z, z_root + pitch, "right"))
    zl, ul = z[lo_i:i + 1][::-1], np.maximum.accumulate(u[lo_i:i + 1][::-1])  # root to the left crest
    zr, ur = z[i:hi_i], np.maximum.accumulate(u[i:hi_i])  # root to the right crest
    lo, hi = float(max(ul[0], ur[0])), float(min(ul[-1], ur[-1]))

    def width(level: float) -> float:
        return float(np.interp(level, ur, zr) - np.interp(level, ul, zl))

    if not hi > lo or width(hi) <= 0.5 * pitch:
        return hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if width(mid) < 0.5 * pitch:
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
    """Major, minor and pitch diameters (median over the grooves and ridges, with their min..max)
    of the thread ``measured`` in its ``profiles`` ((angle, z, r) or, from ``gauge_sections``,
    (angle, z, r, station heights)): only the grooves and crests of each section on its station
    count (``on_station``). ``pitch`` is the spacing of neighbouring grooves (lead / starts),
    ``wire`` the wire diameter (best size by default). Values are None when no section holds a
    complete groove and ridge."""
    wire = best_wire(pitch) if wire is None else wire
    crests, roots, levels, centres = [], [], [], []
    sections = 0
    for prof in measured.get("profiles", []):
        z, u = _depth(prof, inside)
        if len(z) < 3:
            continue
        zs = prof[3] if len(prof) > 3 else None
        rts = M.groove_roots(z, u)
        rts = rts[on_station(rts[:, 0], zs, pitch)]
        crs = M.groove_roots(z, -u)
        crs = crs[on_station(crs[:, 0], zs, pitch)]
        crests.extend(-crs[:, 1])
        roots.extend(rts[:, 1])
        sections += bool(len(rts))
        for zr in rts[:, 0]:
            lvl = groove_level(z, u, float(zr), pitch)
            if lvl is not None:
                levels.append(lvl)
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
           "sections": sections, "grooves": len(levels), "wires": len(centres)}
    return out


def gauge_part(part, zlo: float, zhi: float, pitch: float, inside: bool, angles: int = 36,
               wire: float | None = None, step: float = 0.01) -> dict:
    """``gauge`` of the thread on ``part`` between ``zlo`` and ``zhi``, in ``gauge_sections``."""
    return gauge({"profiles": gauge_sections(part, angles, zlo, zhi, pitch, inside, step)}, pitch, inside, wire)


def _diam(us: list) -> dict | None:
    """Median and range of 2|u|, or None."""
    a = 2.0 * np.abs(np.asarray(us, dtype=float))
    a = a[np.isfinite(a)]
    if not len(a):
        return None
    return {"median": float(np.median(a)), "min": float(a.min()), "max": float(a.max())}
