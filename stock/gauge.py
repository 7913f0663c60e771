"""Moves with no tool in the spindle (kinematics.GaugePath): they remove nothing, but where the
gauge point (the spindle nose) runs inside the material still there at that moment the machine
would crash its spindle into the workpiece: one warning per such move, at its source line.

Inside means deeper than the chordal tolerance: a gauge point on the stock's surface, or grazing
along it, is not inside. The segments of the path are cast as rays against the material near
them; each stretch between two crossings of its surface is inside when rays from its middle in
eight directions all leave the material first, none within the tolerance.
"""
from __future__ import annotations

import math

import manifold3d as m3d
import numpy as np

# Eight directions, one into each octant, tilted off the diagonals so that no ray runs along a
# face, an edge or a diagonal of a box-shaped stock.
_DIRECTIONS = tuple(tuple(c / math.sqrt(sum(x * x for x in d)) for c in d) for d in (
    (1.0, 1.13, 1.29), (-1.07, 1.0, 1.21), (1.17, -1.0, 1.09), (-1.0, -1.19, 1.03),
    (1.03, 1.23, -1.0), (-1.29, 1.0, -1.11), (1.0, -1.07, -1.17), (-1.13, -1.03, -1.0)))

REACH = 1.0  # mm around the path's box in which the material is taken for the rays


def inside_length(material: m3d.Manifold, points: np.ndarray, tol: float) -> float:
    """Length (mm) of the polyline ``points`` that lies inside ``material`` by more than ``tol``."""
    b = material.bounding_box()
    far = 2.0 * math.dist(b[:3], b[3:]) + 1.0
    total = 0.0
    for a, z in zip(points[:-1], points[1:]):
        seg = float(np.linalg.norm(z - a))
        if seg <= tol:
            continue
        a3, z3 = tuple(float(v) for v in a), tuple(float(v) for v in z)
        ts = [0.0] + sorted(h.distance for h in material.ray_cast(a3, z3)) + [1.0]
        for t0, t1 in zip(ts[:-1], ts[1:]):
            if (t1 - t0) * seg > tol and _deep(material, a + (z - a) * (0.5 * (t0 + t1)), far, tol):
                total += (t1 - t0) * seg
    return total


def _deep(material: m3d.Manifold, p: np.ndarray, far: float, tol: float) -> bool:
    """True when ``p`` lies inside ``material`` more than ``tol`` deep: a ray from it in each of the
    eight directions first meets the surface from inside, beyond ``tol``."""
    for d in _DIRECTIONS:
        q = tuple(float(p[k] + far * d[k]) for k in range(3))
        hits = material.ray_cast(tuple(float(v) for v in p), q)
        if not hits:
            return False
        first = min(hits, key=lambda h: h.distance)
        if float(np.dot(first.normal, d)) <= 0.0 or first.distance * far <= tol:
            return False
    return True


def probe(points: np.ndarray) -> m3d.Manifold:
    """The box around ``points`` grown by REACH: where the material is looked at."""
    lo, hi = points.min(axis=0) - REACH, points.max(axis=0) + REACH
    return m3d.Manifold.cube(tuple(float(v) for v in hi - lo)).translate(tuple(float(v) for v in lo))


def message(length: float) -> str:
    return (f"no tool in the spindle: its gauge point (the spindle nose) runs {length:.3f} mm inside the stock; "
            "the move removes nothing")
