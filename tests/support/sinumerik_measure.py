"""Independent measurements for the Sinumerik cycle tests: trimesh plane sections and 2D rays
(numpy only, no cutsim code)."""
from __future__ import annotations

import numpy as np
import trimesh


def hsection(mesh: trimesh.Trimesh, z: float) -> np.ndarray:
    """Segments (n, 2, 2) in XY where the plane Z = z cuts the mesh surface."""
    segs = trimesh.intersections.mesh_plane(mesh, plane_normal=[0, 0, 1.0], plane_origin=[0, 0, z])
    return np.asarray(segs)[..., :2] if len(segs) else np.zeros((0, 2, 2))


def vsection(mesh: trimesh.Trimesh, point, u) -> np.ndarray:
    """Segments (n, 2, 2) of (s, z) in the vertical plane through ``point`` along the unit XY
    direction ``u`` (s measured from ``point`` along ``u``)."""
    p = np.array([point[0], point[1], 0.0])
    u = np.array([u[0], u[1], 0.0]) / np.hypot(u[0], u[1])
    normal = np.array([-u[1], u[0], 0.0])
    segs = np.asarray(trimesh.intersections.mesh_plane(mesh, plane_normal=normal, plane_origin=p))
    if len(segs) == 0:
        return np.zeros((0, 2, 2))
    s = (segs - p) @ u
    return np.stack([s, segs[..., 2]], axis=-1)


def ray(segs: np.ndarray, origin, direction) -> float:
    """Distance from ``origin`` along ``direction`` (2D) to the first segment crossed (inf: none)."""
    o = np.asarray(origin, float)
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    a, b = segs[:, 0], segs[:, 1]
    e = b - a
    den = d[0] * e[:, 1] - d[1] * e[:, 0]
    ok = np.abs(den) > 1e-15
    w = a - o
    t = np.where(ok, (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / np.where(ok, den, 1), np.inf)
    s = np.where(ok, (w[:, 0] * d[1] - w[:, 1] * d[0]) / np.where(ok, den, 1), -1)
    good = ok & (t > 1e-9) & (s >= -1e-12) & (s <= 1 + 1e-12)
    return float(np.min(t[good])) if np.any(good) else float("inf")


def point_segment_distance(segs: np.ndarray, p) -> float:
    """Distance from the 2D point ``p`` to the nearest segment."""
    p = np.asarray(p, float)
    a, b = segs[:, 0], segs[:, 1]
    e = b - a
    L = np.einsum("ij,ij->i", e, e)
    t = np.clip(np.einsum("ij,ij->i", p - a, e) / np.where(L > 0, L, 1), 0, 1)
    q = a + t[:, None] * e
    return float(np.min(np.linalg.norm(q - p, axis=1)))


def floor_z(mesh: trimesh.Trimesh, point, top: float) -> float:
    """Z of the first surface below (point, top) on the vertical line through ``point``."""
    segs = vsection(mesh, point, (1.0, 0.0))
    return top - ray(segs, (0.0, top), (0.0, -1.0))
