"""Tool paths in the workpiece frame: what the kinematics hands to material removal.

- ScrewPath: a spindle-synchronised cut (G33) on a lathe; the tool profile stays in the axial
  half-plane at workpiece angle phi(s) while its point moves along (r(s), z(s)), s in [0, 1].
- PlanarPath: a move on a turning spindle, as a polyline in the (r, z) half-plane; it removes the
  solid of revolution of the tool profile swept along it.
- SpatialPath: a tool moving through space without spindle rotation (a mill, or a lathe with the
  spindle stopped), as a 3D polyline of the control point; ``angle`` turns the tool body about +Z.
  A circular or helical move in the XY plane on a mill also carries its exact description
  (``ArcGeom``), so the sweep can be built directly instead of from the chords.
- GaugePath: a move with no tool in the spindle, as a 3D polyline of the gauge point (the spindle
  nose, where a tool's control point would be): it removes nothing; where it runs inside the
  stock the geometry warns.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from cutsim.base.specs import ToolSpec
from cutsim.interp.canon import Src
from cutsim.interp.core.modal import PLANE_AXES


@dataclass(frozen=True)
class RampGeom:
    start: float  # lead-axis travel where the ramp begins, mm
    length: float  # lead-axis travel it lasts, mm
    offset: float  # total signed displacement along ``axis`` over the ramp, mm (physical)
    axis: str  # "r" or "z"


@dataclass(frozen=True)
class ScrewPath:
    src: Src
    tool: ToolSpec
    r0: float
    z0: float
    r1: float
    z1: float
    travel: float  # length along the lead axis, mm
    revolutions: float
    phi0: float  # workpiece angle of the tool at the start, degrees
    sense: int  # +1: phi grows with the spindle angle progress, -1: it falls
    ramps: tuple[RampGeom, ...] = ()

    def breakpoints(self) -> list[float]:
        """Parameters s where the path has a kink (ramp ends), including 0 and 1."""
        pts = {0.0, 1.0}
        for rp in self.ramps:
            for d in (rp.start, rp.start + rp.length):
                pts.add(min(1.0, max(0.0, d / self.travel)))
        return sorted(pts)

    def pose(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(r, z, phi in radians) of the tool point at parameters ``s``."""
        s = np.asarray(s, dtype=float)
        r = self.r0 + (self.r1 - self.r0) * s
        z = self.z0 + (self.z1 - self.z0) * s
        d = s * self.travel
        for rp in self.ramps:
            frac = np.clip((d - rp.start) / rp.length, 0.0, 1.0)
            if rp.axis == "r":
                r = r + rp.offset * frac
            else:
                z = z + rp.offset * frac
        phi = np.radians(self.phi0 + self.sense * 360.0 * self.revolutions * s)
        return r, z, phi


@dataclass(frozen=True)
class PlanarPath:
    src: Src
    tool: ToolSpec
    points: np.ndarray  # (k, 2): r, z
    rapid: bool


@dataclass(frozen=True)
class ArcGeom:
    """A circle or helix about an axis parallel to +Z: the control point is at
    (cx + radius cos psi, cy + radius sin psi, z) with psi = psi0 + t * sweep and
    z = z0 + t * (z1 - z0), t in [0, 1]."""

    cx: float
    cy: float
    radius: float
    psi0: float  # polar angle of the start about (cx, cy), radians
    sweep: float  # signed swept angle, radians (> 0 counter-clockwise seen from +Z)
    z0: float
    z1: float

    def pose(self, t) -> np.ndarray:
        """Control points (k, 3) at parameters ``t``."""
        t = np.asarray(t, dtype=float)
        psi = self.psi0 + self.sweep * t
        return np.column_stack([self.cx + self.radius * np.cos(psi), self.cy + self.radius * np.sin(psi),
                                self.z0 + (self.z1 - self.z0) * t])

    def joined(self, nxt: ArcGeom, eps: float = 1e-9) -> ArcGeom | None:
        """One helix made of this arc and ``nxt`` when ``nxt`` continues it (same axis, radius,
        sense, height per radian, and it starts where this one ends); else None."""
        scale = max(1.0, self.radius)
        if (abs(nxt.cx - self.cx) > eps * scale or abs(nxt.cy - self.cy) > eps * scale
                or abs(nxt.radius - self.radius) > eps * scale or self.sweep * nxt.sweep <= 0
                or abs(nxt.z0 - self.z1) > eps * scale):
            return None
        turn = (nxt.psi0 - (self.psi0 + self.sweep)) / (2 * math.pi)
        if abs(turn - round(turn)) > eps:
            return None
        k0, k1 = (self.z1 - self.z0) / self.sweep, (nxt.z1 - nxt.z0) / nxt.sweep
        if abs(k1 - k0) > eps * max(1.0, abs(k0)):
            return None
        return ArcGeom(self.cx, self.cy, self.radius, self.psi0, self.sweep + nxt.sweep, self.z0, nxt.z1)


@dataclass(frozen=True)
class SpatialPath:
    src: Src
    tool: ToolSpec
    points: np.ndarray  # (k, 3)
    rapid: bool
    angle: float = 0.0  # degrees about +Z applied to the tool body
    arc: ArcGeom | None = None  # the exact circle/helix ``points`` are chords of (XY plane only)


@dataclass(frozen=True)
class GaugePath:
    src: Src
    points: np.ndarray  # (k, 3): the gauge point, physical coordinates
    rapid: bool


class ArcRun:
    """Consecutive arcs of one tool on one helix (a helix programmed as a circle per turn), joined
    into one path as they come: swept as one, its turns are merged directly instead of overlapping
    as separate solids. The chords are gathered piece by piece and stacked once (``path``), so
    joining n circles costs n, not n squared. The joined path has the first one's source line."""

    def __init__(self, index: int, path: SpatialPath):
        self.index, self.first, self.arc = index, path, path.arc
        self.pieces = [path.points]

    def extend(self, path: SpatialPath) -> bool:
        """Join ``path`` when it continues the run (same tool, rapid or not, an arc on the same
        helix starting where the run ends); False, and nothing changed, when it does not."""
        q, end = self.first, self.pieces[-1][-1]
        if (path.arc is None or self.arc is None or q.tool != path.tool or q.rapid != path.rapid
                or float(np.max(np.abs(end - path.points[0]))) > 1e-9):
            return False
        arc = self.arc.joined(path.arc)
        if arc is None:
            return False
        self.arc = arc
        self.pieces.append(path.points[1:])
        return True

    def path(self) -> SpatialPath:
        if len(self.pieces) > 1:
            self.first = replace(self.first, points=np.vstack(self.pieces), arc=self.arc)
            self.pieces = [self.first.points]
        return self.first


# Start and end radius of an arc agree when they differ by at most this fraction of the radius
# (then the arc is a circle or helix, not a spiral).
ARC_RADIUS_RTOL = 1e-9


def arc_geom(start, end, center, plane: str, clockwise: bool, full: bool) -> ArcGeom | None:
    """The exact description of an arc in the XY plane whose start and end radius agree (physical
    coordinates), the same angles as ``arc_points``; None for other planes and spirals."""
    if plane != "XY":
        return None
    p0, p1, c = (np.asarray(v, dtype=float) for v in (start, end, center))
    r = math.hypot(p0[0] - c[0], p0[1] - c[1])
    r1 = math.hypot(p1[0] - c[0], p1[1] - c[1])
    if r <= 0 or abs(r1 - r) > ARC_RADIUS_RTOL * max(1.0, r):
        return None
    t0, sweep = _arc_angles(p0, p1, c, 0, 1, clockwise, full)
    return ArcGeom(float(c[0]), float(c[1]), r, t0, -sweep if clockwise else sweep, float(p0[2]), float(p1[2]))


def _arc_angles(p0, p1, c, a: int, b: int, clockwise: bool, full: bool) -> tuple[float, float]:
    """Start angle and unsigned swept angle of an arc in the plane of axes ``a``, ``b``."""
    t0 = math.atan2(p0[b] - c[b], p0[a] - c[a])
    t1 = math.atan2(p1[b] - c[b], p1[a] - c[a])
    sweep = (t0 - t1) if clockwise else (t1 - t0)
    sweep %= 2 * math.pi
    if full or sweep < 1e-12:
        sweep = 2 * math.pi if full else sweep
    return t0, sweep


def arc_points(start, end, center, plane: str, clockwise: bool, full: bool, tol: float) -> np.ndarray:
    """Points along an arc/helix (physical coordinates), chord error at most ``tol``; includes both ends."""
    a, b, n = PLANE_AXES[plane]
    p0, p1, c = (np.asarray(v, dtype=float) for v in (start, end, center))
    r = math.hypot(p0[a] - c[a], p0[b] - c[b])
    t0, sweep = _arc_angles(p0, p1, c, a, b, clockwise, full)
    step = segment_angle(r, tol)
    k = max(1, math.ceil(sweep / step))
    t = np.linspace(0.0, 1.0, k + 1)
    ang = t0 + (-1 if clockwise else 1) * sweep * t
    r1 = math.hypot(p1[a] - c[a], p1[b] - c[b])
    rr = r + (r1 - r) * t
    pts = np.empty((k + 1, 3))
    pts[:, a] = c[a] + rr * np.cos(ang)
    pts[:, b] = c[b] + rr * np.sin(ang)
    pts[:, n] = p0[n] + (p1[n] - p0[n]) * t
    pts[-1] = p1
    return pts


def segment_angle(radius: float, tol: float) -> float:
    """Largest angle (radians) whose chord on a circle of ``radius`` deviates at most ``tol``."""
    if radius <= tol:
        return math.pi / 2
    return min(math.pi / 2, 2.0 * math.acos(1.0 - tol / radius))


def circle_segments(radius: float, tol: float) -> int:
    """Segments of a full circle of ``radius`` at chordal tolerance ``tol`` (a multiple of 4)."""
    n = math.ceil(2 * math.pi / segment_angle(radius, tol))
    return max(8, 4 * math.ceil(n / 4))
