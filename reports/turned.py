"""Turned features measured on a simulated lathe part: a hole's bore diameter and depth, a groove's
width, depth and floor diameter, a shoulder's position (docs/checks.md, "bore", "groove",
"shoulder").

Every measurement reads the part's exact outline in half-plane sections (``measure.outer_profile``,
outside or inside) at angles clear of construction seams (``measure.thread_angles``) and takes the
median over them; the range over the angles is reported beside it.
"""
from __future__ import annotations

import math

import numpy as np

from . import measure as M

SECTIONS = 8  # half-planes per measurement (sections at 45 degree steps, each clear of seams)


def _profiles(part, zlo: float, zhi: float, inside: bool, step: float = 0.005):
    return [M.outer_profile(part, float(phi), zlo, zhi, step, inside) for phi in M.thread_angles(part, SECTIONS)]


def _crossing(z: np.ndarray, r: np.ndarray, level: float, start: int, direction: int) -> float | None:
    """z where the polyline (z, r) first reaches ``level`` going from index ``start`` in ``direction``
    (+1 towards +Z, -1 towards -Z), linear between samples; None when it never does."""
    below = r < level
    i = start
    while 0 <= i + direction < len(z):
        j = i + direction
        if below[i] and not below[j] or not np.isfinite(r[j]):
            if not np.isfinite(r[j]):
                return None
            t = (level - r[i]) / (r[j] - r[i])
            return float(z[i] + t * (z[j] - z[i]))
        i = j
    return None


def _stats(values: list) -> dict | None:
    a = np.asarray([v for v in values if v is not None and math.isfinite(v)], dtype=float)
    if len(a) != len(values) or not len(a):
        return None  # a section that could not measure: the feature is not there
    return {"median": float(np.median(a)), "min": float(a.min()), "max": float(a.max())}


FULL_EPS = 0.001  # mm: the full diameter ends where the bore is this much narrower than at z


def bore(part, z: float, face: float) -> dict:
    """A hole on the spindle axis opened from the face at ``face`` (z of the face; the hole goes
    towards -Z): its diameter at height ``z`` (2 x the bore's radius there), the depth from the
    face to where it first narrows below that diameter (less FULL_EPS) going down (the depth of
    the full diameter) and the depth to its bottom on the axis (the drill's point)."""
    b = part.bounding_box()
    diam, depth, tip = [], [], []
    for zz, r in _profiles(part, b[2] - 0.5, face + 0.5, True):
        rz = float(np.interp(z, zz, r))
        diam.append(2.0 * rz if rz > M.SEAM_RADIUS else math.nan)
        k = int(np.searchsorted(zz, min(z, face)))
        lo = _crossing(zz, -r, -(rz - FULL_EPS / 2.0), k, -1) if rz > FULL_EPS else None  # narrows going down
        depth.append(None if lo is None else face - lo)
        open_ = np.flatnonzero((r > M.SEAM_RADIUS) & (zz <= face))
        tip.append(face - float(zz[open_[0] - 1]) if len(open_) and open_[0] > 0 else None)  # the point's vertex
    return {"diameter": _stats(diam), "depth": _stats(depth), "tip_depth": _stats(tip)}


def groove(part, at: float, inside: bool, reach: float) -> dict:
    """A turned groove around height ``at`` (outside, or inside a bore): its floor diameter at
    ``at``, the radial depth below the lower of its two rims (the highest surface within ``reach``
    on either side), its width and centre at half that depth."""
    floor, depth, width, centre = [], [], [], []
    s = -1.0 if inside else 1.0  # u = s r: a groove is where u is low
    for zz, r in _profiles(part, at - reach, at + reach, inside):
        u = s * r
        k = int(np.argmin(np.abs(zz - at)))
        fl = float(np.interp(at, zz, u))
        rim = min(float(np.nanmax(u[:k + 1])), float(np.nanmax(u[k:])))
        level = fl + 0.5 * (rim - fl)
        a, b = _crossing(zz, u, level, k, -1), _crossing(zz, u, level, k, 1)
        floor.append(2.0 * abs(fl))
        depth.append(rim - fl if rim - fl > 0 else None)
        width.append(None if a is None or b is None or rim - fl <= 0 else b - a)
        centre.append(None if a is None or b is None or rim - fl <= 0 else 0.5 * (a + b))
    return {"diameter": _stats(floor), "depth": _stats(depth), "width": _stats(width), "center": _stats(centre)}


def shoulder(part, diameter: float, zlo: float, zhi: float, inside: bool, near: float) -> dict:
    """The z where the outline crosses ``diameter`` (a shoulder's face) between ``zlo`` and
    ``zhi``: the crossing nearest ``near`` in each section."""
    zs = []
    s = -1.0 if inside else 1.0
    for zz, r in _profiles(part, zlo, zhi, inside):
        u, level = s * r, s * diameter / 2.0
        ok = np.isfinite(u)
        sgn = np.sign(np.where(ok, u - level, 0.0))
        idx = np.flatnonzero((sgn[:-1] * sgn[1:] < 0) & ok[:-1] & ok[1:])
        cands = [float(zz[i] + (level - u[i]) / (u[i + 1] - u[i]) * (zz[i + 1] - zz[i])) for i in idx]
        zs.append(min(cands, key=lambda c: abs(c - near)) if cands else None)
    return {"z": _stats(zs)}
