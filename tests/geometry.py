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
    for i, zz in enumerate(z):
        m = (np.minimum(z0, z1) <= zz) & (np.maximum(z0, z1) >= zz) & (np.abs(z1 - z0) > 1e-12)
        if np.any(m):
            t = (zz - z0[m]) / (z1[m] - z0[m])
            out[i] = np.max(r0[m] + t * (r1[m] - r0[m]))
    return out


def groove_roots(segs: np.ndarray, zlo: float, zhi: float, below: float) -> np.ndarray:
    """(z, r) of the deepest section vertex of each groove between ``zlo`` and ``zhi``: connected
    runs of boundary vertices with r < ``below`` (the crest level), one root per run."""
    pts = segs.reshape(-1, 2)
    pts = pts[(pts[:, 1] >= zlo) & (pts[:, 1] <= zhi) & (pts[:, 0] < below) & (pts[:, 0] > 1e-6)]
    if len(pts) == 0:
        return np.zeros((0, 2))
    pts = pts[np.argsort(pts[:, 1])]
    roots = []
    run = [pts[0]]
    for p in pts[1:]:
        if p[1] - run[-1][1] > 0.05 * max(1.0, 1.0):  # a gap along z: a new groove
            roots.append(min(run, key=lambda q: q[0]))
            run = [p]
        else:
            run.append(p)
    roots.append(min(run, key=lambda q: q[0]))
    return np.array(roots)


def wrap(dz: np.ndarray, period: float) -> np.ndarray:
    """Signed distance to the nearest multiple of ``period``."""
    return (np.asarray(dz) + period / 2) % period - period / 2
