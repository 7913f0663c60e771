"""A ball-end mill swept along a polyline in a vertical plane: one mitred tube, built directly.

A CAM raster is thousands of short moves along lines in vertical planes. A ball (radius r)
swept along a straight segment is a cylinder about the segment through the ball centre; two
consecutive cylinders of equal radius meet exactly in the bisector (mitre) plane of their axes, in
the same ellipse (semi-axes r and r / cos(theta/2)). So the lower half of the ball's sweep along the
whole line is ONE tube: the half-disc profile extruded along a parameter axis and ``warp_batch``ed
so station k lands on the mitre plane at vertex k. Between stations every profile vertex runs
along a ruling of its cylinder, so the only error is the profile's chord (the one tolerance) and,
on the outside of a bend, the mitre corner standing out of the ball's round joint by
r (1/cos(theta/2) - 1), kept within half the tolerance (bends sharper than that split the line).

Above the ball's equator the tool is its cylinder, and where the flutes reach above the stock the
tool is upward closed (see stock/mill.py): the sweep is everything above the lower surface, between
the walls y = +-r of the plane. The profile's two top vertices therefore run up the mitre plane to
a common height above the stock; walls and top are planar and exact. The tool's own body at both
ends of the line closes the sweep (the half-balls in front of the first and behind the last
station). One line of n moves is then ~n x (profile vertices) x 2 triangles, an order of magnitude
fewer than one hull per move, and nothing inside the line needs a boolean.
"""
from __future__ import annotations

import math

import manifold3d as m3d
import numpy as np

from cutsim.kinematics.paths import segment_angle

from cutsim.base.specs import ToolSpec
from .tools import MILL_KINDS, positive

TUBE_MIN_SEGMENTS = 3  # shorter stretches are cheaper as hulls
MAX_SLOPE = 0.95  # |sin| of a segment's slope; steeper segments (plunges) are hulled
MITRE_FRACTION = 0.5  # the mitre corner may stand out of the round joint by this many tolerances
PLANAR_EPS = 1e-7  # mm: points this close to the vertical plane lie in it
LEVEL_EPS = 1e-9  # mm: segments rising less than this are level
TOP_MARK = 1.0  # profile v of the two top vertices (the arc has v <= 0)


def is_ball(tool: ToolSpec) -> bool:
    return tool.kind in MILL_KINDS and tool.corner_radius >= tool.diameter / 2.0 - 1e-12


def max_turn(r: float, tol: float) -> float:
    """Largest bend (radians) whose mitre stands out of the round joint by at most MITRE_FRACTION tol."""
    return 2.0 * math.acos(1.0 / (1.0 + MITRE_FRACTION * tol / r))


def stretches(pts: np.ndarray, tool: ToolSpec, tol: float, z_top: float) -> list[tuple[int, int]]:
    """Index ranges (i, j) of the tip polyline that one tube sweeps exactly: either segments in
    one vertical plane, progressing along it, not steeper than MAX_SLOPE, bending up and down
    (a raster line), or level segments at one height turning left and right (a waterline); bends
    within ``max_turn``, the tool long enough to reach ``z_top`` and neighbouring mitre sections
    not crossing."""
    r = tool.diameter / 2.0
    n = len(pts)
    if n < TUBE_MIN_SEGMENTS + 1:
        return []
    d = np.diff(pts, axis=0)
    hl = np.hypot(d[:, 0], d[:, 1])
    ln = np.linalg.norm(d, axis=1)
    reach = pts[:, 2] + tool.length >= z_top
    seg_ok = (hl > 1e-9) & (np.abs(d[:, 2]) <= MAX_SLOPE * ln) & reach[:-1] & reach[1:]
    h = d[:, :2] / np.maximum(hl, 1e-300)[:, None]
    cross = h[:-1, 0] * h[1:, 1] - h[:-1, 1] * h[1:, 0]
    bend_ok = np.einsum("ij,ij->i", d[:-1], d[1:]) >= math.cos(max_turn(r, tol)) * ln[:-1] * ln[1:]
    forward = np.einsum("ij,ij->i", h[:-1], h[1:]) > 0
    both = bend_ok & seg_ok[:-1] & seg_ok[1:] & forward
    vert = both & (np.abs(cross) <= 1e-9)  # joint_ok[k]: at point k + 1, in one vertical plane
    level = both & (np.abs(d[:-1, 2]) <= LEVEL_EPS) & (np.abs(d[1:, 2]) <= LEVEL_EPS)  # at one height
    cands, i = [], 0
    while i < n - 1:
        if not seg_ok[i]:
            i += 1
            continue
        j, v_ok, l_ok = i + 1, True, abs(float(d[i, 2])) <= LEVEL_EPS
        while j < n - 1:
            v_ok, l_ok = v_ok and bool(vert[j - 1]), l_ok and bool(level[j - 1])
            if not (v_ok or l_ok):
                break
            j += 1
        cands.append((i, j))
        i = j
    out = []
    while cands:
        i, j = cands.pop(0)
        if j - i < TUBE_MIN_SEGMENTS:
            continue
        k = _first_crossing(pts[i:j + 1], r)
        if k is not None:  # hull the segment whose mitre sections cross; tube the rest
            cands[:0] = [(i, i + k), (i + k + 1, j)]
        elif is_level(pts[i:j + 1]) and not _footprint_simple(pts[i:j + 1], r):
            mid = (i + j) // 2  # a loop that comes back over itself: tube it in halves
            cands[:0] = [(i, mid), (mid, j)]
        else:
            out.append((i, j))
    return out


def _footprint_simple(pts: np.ndarray, r: float) -> bool:
    """The waterline tube does not overlap itself: the quads its stations bound in the plane
    cover as much area together as one by one (a closed loop, a hairpin narrower than the tool
    would overlap; the tube would not be a valid solid)."""
    _, left, scale = _level_frames(pts)
    off = (r * scale)[:, None] * left
    lft, rgt = pts[:, :2] + off, pts[:, :2] - off
    quads = [np.array([rgt[k], rgt[k + 1], lft[k + 1], lft[k]]) for k in range(len(pts) - 1)]
    area = sum(abs(m3d.CrossSection([q], m3d.FillRule.NonZero).area()) for q in quads)
    union = m3d.CrossSection(quads, m3d.FillRule.NonZero).area()
    return union >= area * (1.0 - 1e-9) - 1e-9


def is_level(pts: np.ndarray) -> bool:
    """All points at one height and not all in one vertical plane: a waterline stretch."""
    if float(np.ptp(pts[:, 2])) > LEVEL_EPS * len(pts):
        return False
    d = pts[-1, :2] - pts[0, :2]
    ln = math.hypot(d[0], d[1])
    if ln < 1e-9:
        return True
    lat = np.array([-d[1], d[0]]) / ln
    return bool(np.max(np.abs((pts[:, :2] - pts[0, :2]) @ lat)) > PLANAR_EPS)


def _level_frames(pts: np.ndarray):
    """Unit XY directions of the segments, the horizontal unit normal (left) of the bisector at
    each station and the mitre scale 1 / cos(theta/2)."""
    a = np.diff(pts[:, :2], axis=0)
    a /= np.linalg.norm(a, axis=1)[:, None]
    b = np.vstack([a[:1], a[:-1] + a[1:], a[-1:]])
    b /= np.linalg.norm(b, axis=1)[:, None]
    scale = 1.0 / np.einsum("ij,ij->i", b, np.vstack([a, a[-1:]]))
    left = np.column_stack([-b[:, 1], b[:, 0]])
    return a, left, scale


def _frames(pts: np.ndarray, e: np.ndarray):
    """In-plane (t, z) unit directions of the segments, the bisectors at the stations and the mitre
    scale 1 / cos(theta/2) at each station."""
    tz = np.column_stack([pts[:, :2] @ e, pts[:, 2]])
    a = np.diff(tz, axis=0)
    a /= np.linalg.norm(a, axis=1)[:, None]
    b = np.vstack([a[:1], a[:-1] + a[1:], a[-1:]])
    b /= np.linalg.norm(b, axis=1)[:, None]
    scale = 1.0 / np.einsum("ij,ij->i", b, np.vstack([a, a[-1:]]))
    return a, b, scale


def _mitre_lows(pts: np.ndarray, e: np.ndarray, r: float) -> tuple[np.ndarray, np.ndarray]:
    """In-plane (t, z) of every station's ball centre and of the lowest point of its mitre ellipse."""
    _, b, scale = _frames(pts, e)
    n = np.column_stack([b[:, 1], -b[:, 0]])  # in-plane normal pointing down (b_t > 0)
    c = np.column_stack([pts[:, :2] @ e, pts[:, 2] + r])
    return c, c + (r * scale)[:, None] * n


def _first_crossing(pts: np.ndarray, r: float) -> int | None:
    """The first segment of the stretch ``pts`` along which the mitre half-discs of its two
    stations (centre to lowest point; on a waterline: both sides) do not keep their order, or
    None. (Above the centres the sections are vertical and the centres progress.)"""
    if is_level(pts):
        a, left, scale = _level_frames(pts)
        bad = np.zeros(len(a), dtype=bool)
        for side in (-1.0, 1.0):
            q = pts[:, :2] + side * (r * scale)[:, None] * left
            bad |= np.einsum("ij,ij->i", np.diff(q, axis=0), a) <= 0
        return int(np.argmax(bad)) if bad.any() else None
    d = pts[-1, :2] - pts[0, :2]
    e = d / math.hypot(d[0], d[1])
    c, low = _mitre_lows(pts, e, r)
    a, _, _ = _frames(pts, e)
    bad = (np.einsum("ij,ij->i", np.diff(low, axis=0), a) <= 0) | (np.einsum("ij,ij->i", np.diff(c, axis=0), a) <= 0)
    return int(np.argmax(bad)) if bad.any() else None


def profile(r: float, tol: float) -> tuple[m3d.CrossSection, int]:
    """The tube's cross-section: the ball's lower half-disc and two top vertices. The arc's
    vertices stand a little outside the circle so each chord's triangle has the sector's area:
    the swept volume is unbiased (chords within -tol/3 .. +2 tol/3 of the ball)."""
    k = max(2, math.ceil(math.pi / segment_angle(r, tol)))
    delta = math.pi / k
    f = math.sqrt(delta / math.sin(delta))
    beta = np.linspace(-math.pi / 2, math.pi / 2, k + 1)
    arc = np.column_stack([r * np.sin(beta), -r * np.cos(beta)])
    arc[1:-1] *= f
    poly = np.vstack([arc, [[r, TOP_MARK], [-r, TOP_MARK]]])
    return m3d.CrossSection([poly], m3d.FillRule.Positive), k


def tube(pts: np.ndarray, tool: ToolSpec, tol: float, z_top: float) -> m3d.Manifold:
    """The lower ball plus the cylinder up to ``z_top`` swept along the stretch ``pts`` (between
    the first and the last station; the end bodies are the caller's). Below the ball centres each
    station's section is the half-disc in its mitre plane; above them it is vertical: the tool's
    cylinder above the centre line, up to ``z_top``."""
    r = tool.diameter / 2.0
    m = len(pts)
    if is_level(pts):
        # level cylinders meet in the vertical mitre plane: the half-disc stretches sideways
        # by the mitre scale and keeps its depth
        _, left, scale = _level_frames(pts)
        side = np.column_stack([left * scale[:, None], np.zeros(m)])
        down = np.tile([0.0, 0.0, -1.0], (m, 1))
    else:
        # cylinders in one vertical plane meet in the tilted mitre plane: the half-disc keeps its
        # width and stretches along the plane's fall line
        d = pts[-1, :2] - pts[0, :2]
        e = d / math.hypot(d[0], d[1])
        _, b, scale = _frames(pts, e)
        side = np.tile([-e[1], e[0], 0.0], (m, 1))
        down = (b[:, 1:2] * np.append(e, 0.0) - b[:, 0:1] * np.array([0.0, 0.0, 1.0])) * scale[:, None]
    return positive(_warped(pts + np.array([0.0, 0.0, r]), side, down, r, tol, z_top), "a ball-end mill")


def _warped(centre: np.ndarray, side: np.ndarray, down: np.ndarray, r: float, tol: float,
            z_top: float) -> m3d.Manifold:
    """The profile extruded over the stations and warped: at station k an arc vertex (u, v) lands
    on centre + u side + (-v) down, a top vertex straight above centre + u side at ``z_top``."""
    rise = z_top - centre[:, 2]
    m = len(centre) - 1
    prof, _ = profile(r, tol)
    solid = m3d.Manifold.extrude(prof, 1.0, n_divisions=m - 1)
    # (u, v, s) -> world keeps its orientation unless (side, -down, path) is left-handed
    flip = np.linalg.det(np.column_stack([side[0], -down[0], centre[1] - centre[0]])) < 0

    def warp(p):
        k = np.clip(np.rint(p[:, 2] * m).astype(int), 0, m)
        u = -p[:, 0] if flip else p[:, 0]
        top = p[:, 1] > 0.5 * TOP_MARK
        out = centre[k] + u[:, None] * side[k]
        arc = ~top
        out[arc] -= p[arc, 1][:, None] * down[k[arc]]
        out[top, 2] += rise[k[top]]
        return out

    return solid.warp_batch(warp)
