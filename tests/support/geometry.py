"""Independent measurements on a part mesh for the tests: trimesh slicing, no cutsim code.

The half-plane at angle ``phi`` (degrees, about +Z from +X) contains the Z axis; the section of a
lathe part there is its axial profile (r, z) at that angle.
"""
from __future__ import annotations

import math

import numpy as np
import trimesh


def load(result_or_path) -> trimesh.Trimesh:
    if isinstance(result_or_path, trimesh.Trimesh):
        return result_or_path
    if hasattr(result_or_path, "mesh"):
        return result_or_path.mesh()
    return trimesh.load(str(result_or_path), force="mesh")


def section(mesh: trimesh.Trimesh, phi: float) -> np.ndarray:
    """Segments (n, 2, 2) of (r, z) where the half-plane at ``phi`` cuts the mesh surface."""
    c, s = math.cos(math.radians(phi)), math.sin(math.radians(phi))
    segs = trimesh.intersections.mesh_plane(mesh, plane_normal=[-s, c, 0.0], plane_origin=[0, 0, 0])
    if len(segs) == 0:
        return np.zeros((0, 2, 2))
    r = segs[..., 0] * c + segs[..., 1] * s
    keep = np.all(r > -1e-9, axis=1)
    return np.stack([r[keep], segs[keep][..., 2]], axis=-1)


def outer_radius(segs: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Largest r of the section boundary at each height ``z`` (nan where the section has none)."""
    z = np.atleast_1d(np.asarray(z, dtype=float))
    out = np.full(z.shape, np.nan)
    z0, z1 = segs[:, 0, 1], segs[:, 1, 1]
    r0, r1 = segs[:, 0, 0], segs[:, 1, 0]
    ok = np.abs(z1 - z0) > 1e-12
    z0, z1, r0, r1 = z0[ok], z1[ok], r0[ok], r1[ok]
    lo, hi = np.minimum(z0, z1), np.maximum(z0, z1)
    order = np.argsort(lo)
    lo, hi, z0, z1, r0, r1 = lo[order], hi[order], z0[order], z1[order], r0[order], r1[order]
    maxlen = float(np.max(hi - lo)) if len(lo) else 0.0
    for i, zz in enumerate(z):
        a = np.searchsorted(lo, zz - maxlen, side="left")
        b = np.searchsorted(lo, zz, side="right")
        m = hi[a:b] >= zz
        if np.any(m):
            t = (zz - z0[a:b][m]) / (z1[a:b][m] - z0[a:b][m])
            out[i] = np.max(r0[a:b][m] + t * (r1[a:b][m] - r0[a:b][m]))
    return out


def outer_profile(segs: np.ndarray, zlo: float, zhi: float) -> tuple[np.ndarray, np.ndarray]:
    """The outer profile r(z) between ``zlo`` and ``zhi`` as a polyline through every section
    vertex height (the profile is piecewise linear, so its kinks are all among these heights)."""
    zs = np.unique(segs[..., 1].ravel())
    zs = zs[(zs >= zlo) & (zs <= zhi)]
    return zs, outer_radius(segs, zs)


def groove_roots(segs: np.ndarray, zlo: float, zhi: float, below: float, min_gap: float = 0.3) -> np.ndarray:
    """(z, r) of the root (deepest point) of each groove between ``zlo`` and ``zhi``.

    The outer profile r(z) is taken at every vertex height; a root is a point lower than ``below``
    (the crest level) where the profile is lowest within ``min_gap`` on both sides and which is
    not within ``min_gap`` of the ends of the range. ``min_gap`` must be smaller than half the
    distance between neighbouring grooves and larger than the small notches chords leave on
    the flanks; a third of the lead is a good choice.
    """
    z, r = outer_profile(segs, zlo, zhi)
    good = ~np.isnan(r)
    z, r = z[good], r[good]
    if len(z) < 3:
        return np.zeros((0, 2))
    lo = np.searchsorted(z, z - min_gap, side="left")
    hi = np.searchsorted(z, z + min_gap, side="right")
    # the profile is linear between vertex heights: its minimum over a window is at a vertex
    # inside or at one of the window's ends
    edge = np.minimum(np.interp(z - min_gap, z, r), np.interp(z + min_gap, z, r))
    roots: list[int] = []
    for i in np.argsort(r, kind="stable"):
        if r[i] >= below:
            break
        if z[i] - min_gap < zlo or z[i] + min_gap > zhi:
            continue
        if r[i] <= min(r[lo[i]:hi[i]].min(), edge[i]) and all(abs(z[i] - z[k]) > min_gap for k in roots):
            roots.append(i)
    roots.sort(key=lambda k: z[k])
    return np.column_stack([z[roots], r[roots]]) if roots else np.zeros((0, 2))


def wrap(dz: np.ndarray, period: float) -> np.ndarray:
    """Signed distance to the nearest multiple of ``period``."""
    return (np.asarray(dz) + period / 2) % period - period / 2
