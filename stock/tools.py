"""Tool shapes. Lathe tools are profiles in the (u, v) plane of the tool: u radial outwards from the
tool point (+X), v axial (+Z); the control point is the origin, the lowest point of the nose."""
from __future__ import annotations

import math

import manifold3d as m3d
import numpy as np

from cutsim.kinematics.paths import segment_angle

from .specs import ToolSpec


def lathe_profile(tool: ToolSpec, tol: float) -> np.ndarray:
    """Counter-clockwise polygon (k, 2) of a lathe tool's cutting profile."""
    if tool.kind == "profile":
        pts = np.array(tool.points, dtype=float)
        area = 0.5 * np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1])
        return pts if area > 0 else pts[::-1]
    half = math.radians(tool.angle) / 2.0
    h = tool.height
    w = h * math.tan(half)
    rho = tool.tip_radius
    if rho <= 0:
        return np.array([[0.0, 0.0], [h, -w], [h, w]])
    # nose circle centred on the u axis at (rho, 0), tangent to both flanks; its lowest point is the origin
    span = math.pi / 2 - half  # half the arc angle
    k = max(1, math.ceil(span / segment_angle(rho, tol)))
    t = np.linspace(-span, span, 2 * k + 1)  # symmetric, with a vertex at the origin
    arc = np.column_stack([rho + rho * np.cos(math.pi + t), rho * np.sin(math.pi + t)])
    arc = arc[::-1]  # from the upper flank (v > 0) down through the origin to the lower flank
    return np.vstack([[[h, w]], arc, [[h, -w]]])[::-1]


def convex_pieces(poly: np.ndarray) -> list[np.ndarray]:
    """The polygon itself if convex, else the triangles of a triangulation (each convex)."""
    d = np.diff(np.vstack([poly, poly[:2]]), axis=0)
    cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    if np.all(cross >= -1e-12):
        return [poly]
    tris = m3d.triangulate([poly])
    return [poly[list(t)] for t in np.asarray(tris)]


def lathe_body(tool: ToolSpec, tol: float) -> list[np.ndarray]:
    """3D convex pieces (vertex arrays) of a lathe tool: its profile in the XZ plane, ``thickness``
    thick along Y (used when the spindle stands still)."""
    out = []
    t = tool.thickness / 2.0
    for piece in convex_pieces(lathe_profile(tool, tol)):
        out.append(np.vstack([np.column_stack([piece[:, 0], np.full(len(piece), y), piece[:, 1]]) for y in (-t, t)]))
    return out


def mill_body(tool: ToolSpec, tol: float, height: float | None = None) -> list[np.ndarray]:
    """Convex vertex cloud of a milling cutter's fluted part, tip centre at the origin, axis +Z
    (flat, bull-nose: corner radius, ball: corner radius = radius). With ``height`` below the flute
    length the body is cut off at that height (a plane section of the true tool): the part of the
    tool above the stock top never meets material and only costs triangles."""
    r = tool.diameter / 2.0
    rc = min(tool.corner_radius, r)
    top = tool.length if height is None else min(tool.length, max(0.0, height))
    n = max(8, math.ceil(2 * math.pi / segment_angle(r, tol)))
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    # Vertices a little outside the circle so the polygon has the circle's perimeter, hence its
    # mean width: the walls a sweep cuts deviate both ways within the tolerance, unbiased in volume.
    ring = np.column_stack([np.cos(ang), np.sin(ang)]) * (math.pi / (n * math.sin(math.pi / n)))

    def layer(rad: float, z: float) -> np.ndarray:
        return np.column_stack([ring * rad, np.full(n, z)]) if rad > 1e-12 else np.array([[0.0, 0.0, z]])

    layers = []
    if rc > 0:
        k = max(1, math.ceil((math.pi / 2) / segment_angle(rc, tol)))
        # the corner arc's inner vertices stand out so each chord's triangle has the sector's
        # area (as the ring's vertices do around the axis): hull sweeps are unbiased in volume
        delta = (math.pi / 2) / k
        f = math.sqrt(delta / math.sin(delta))
        for i, a in enumerate(np.linspace(0, math.pi / 2, k + 1)):
            s = f if 0 < i < k else 1.0
            z = rc - rc * s * math.cos(a)
            if z >= top:
                break
            layers.append(layer((r - rc) + rc * s * math.sin(a), z))
    else:
        layers.append(layer(r, 0.0))
    if top < rc:  # the cut falls on the corner: its section circle
        layers.append(layer((r - rc) + math.sqrt(max(0.0, rc * rc - (rc - top) ** 2)), top))
    elif top > 0.0 or rc > 0:
        layers.append(layer(r, top))
    return [np.vstack(layers)]
