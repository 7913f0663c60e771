"""The 2D geometry of a G70-G72 profile: its segments in the ZX plane, their offset by a distance
towards the cycle's start point, and where a pass line meets them.

Points are ``(z, x)`` in mm (X a radius), the plane's first and second axes, so an arc's
counter-clockwise sense is the usual mathematical one (G3 in G18). A ``Seg`` is a straight line
(``centre`` None) or an arc about ``centre``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

EPS = 1e-9
SAMPLES = 16  # points along an arc checked for monotonic travel
TANGENT = 2e-3  # segments meeting at less than this (sine of the angle) join without a corner


@dataclass(frozen=True)
class Seg:
    p0: tuple
    p1: tuple
    centre: tuple | None = None
    ccw: bool = False

    @property
    def radius(self) -> float:
        return math.dist(self.p0, self.centre)

    def tangent(self, at_end: bool) -> tuple:
        """The unit direction of travel at the start (or the end)."""
        if self.centre is None:
            d = (self.p1[0] - self.p0[0], self.p1[1] - self.p0[1])
            n = math.hypot(*d)
            return (d[0] / n, d[1] / n) if n > 0 else (0.0, 0.0)
        p = self.p1 if at_end else self.p0
        e = ((p[0] - self.centre[0]) / self.radius, (p[1] - self.centre[1]) / self.radius)
        return (-e[1], e[0]) if self.ccw else (e[1], -e[0])

    def angles(self) -> tuple[float, float]:
        """Start angle and the signed sweep (positive counter-clockwise) of an arc."""
        c = self.centre
        a0 = math.atan2(self.p0[1] - c[1], self.p0[0] - c[0])
        a1 = math.atan2(self.p1[1] - c[1], self.p1[0] - c[0])
        sweep = (a1 - a0) % (2 * math.pi) if self.ccw else -((a0 - a1) % (2 * math.pi))
        return a0, sweep

    def points(self) -> list[tuple]:
        """The start, points along an arc and the end."""
        if self.centre is None:
            return [self.p0, self.p1]
        a0, sweep = self.angles()
        r = self.radius
        inner = [(self.centre[0] + r * math.cos(a0 + sweep * k / SAMPLES),
                  self.centre[1] + r * math.sin(a0 + sweep * k / SAMPLES)) for k in range(1, SAMPLES)]
        return [self.p0, *inner, self.p1]


def cross(a, b) -> float:
    return a[0] * b[1] - a[1] * b[0]


def side_of(first: Seg, start) -> float:
    """+1 when ``start`` lies left of the profile's first segment, -1 right (0 on its line)."""
    c = cross(first.tangent(False), (start[0] - first.p0[0], start[1] - first.p0[1]))
    return 0.0 if abs(c) < EPS else math.copysign(1.0, c)


def shifted(s: Seg, d: float, side: float) -> Seg:
    """The segment moved ``d`` to its ``side`` (+1 left of the travel)."""
    if s.centre is None:
        t = s.tangent(False)
        n = (-t[1] * side * d, t[0] * side * d)
        return Seg((s.p0[0] + n[0], s.p0[1] + n[1]), (s.p1[0] + n[0], s.p1[1] + n[1]))
    grow = d * (-side if s.ccw else side)  # left of a counter-clockwise arc is towards its centre
    r = s.radius
    if r + grow <= EPS:
        raise ValueError("the distance D is larger than an inside arc's radius (not simulated)")
    k = (r + grow) / r
    c = s.centre
    return Seg((c[0] + (s.p0[0] - c[0]) * k, c[1] + (s.p0[1] - c[1]) * k),
               (c[0] + (s.p1[0] - c[0]) * k, c[1] + (s.p1[1] - c[1]) * k), c, s.ccw)


def offset(segs: list[Seg], d: float, side: float, small: float, cut: tuple[int, int]) -> list[Seg]:
    """The profile ``d`` to ``side``: each segment moved, an arc of radius d about each corner the
    offset goes round (convex) where the moved segments' ends lie more than ``small`` (LinuxCNC 2.9:
    0.01 program units) apart along the cut, the later one ahead of the earlier (``cut``: the axis
    and the profile's direction along it), the neighbours cut back to where they meet at the others."""
    if d == 0.0:
        return list(segs)
    moved = [shifted(s, d, side) for s in segs]
    out = [moved[0]]
    for i in range(1, len(moved)):
        prev, cur, corner = out[-1], moved[i], segs[i].p0
        if math.dist(prev.p1, cur.p0) < 1e-7:
            out.append(replace(cur, p0=prev.p1))
            continue
        t0, t1 = segs[i - 1].tangent(True), segs[i].tangent(False)
        turn = cross(t0, t1)
        if abs(turn) < TANGENT and t0[0] * t1[0] + t0[1] * t1[1] > 0:  # tangent but for rounding
            p = first_crossing(prev, cur)
            if p is not None:  # two arcs whose circles cross: they meet there (rs274 2.9)
                out[-1] = replace(prev, p1=p)
                cur = replace(cur, p0=p)
            out.append(cur)
            continue
        gap = (prev.p1[cut[0]] - cur.p0[cut[0]]) * -cut[1]
        p = None if turn * side < 0 and gap > small else meet(prev, cur, corner)
        if p is None and turn * side < 0:
            out.append(Seg(prev.p1, cur.p0, corner, turn > 0))
            out.append(cur)
            continue
        if p is None:
            raise ValueError("the offset profile's segments do not meet at a corner (not simulated)")
        out[-1] = replace(prev, p1=p)
        out.append(replace(cur, p0=p))
    return out


def meet(a: Seg, b: Seg, near) -> tuple | None:
    """The crossing of two segments' lines or circles nearest ``near``."""
    if a.centre is None and b.centre is None:
        da, db = a.tangent(False), b.tangent(False)
        den = cross(da, db)
        if abs(den) < EPS:
            return None
        w = (b.p0[0] - a.p0[0], b.p0[1] - a.p0[1])
        t = cross(w, db) / den
        return (a.p0[0] + da[0] * t, a.p0[1] + da[1] * t)
    if a.centre is None or b.centre is None:
        line, arc = (a, b) if a.centre is None else (b, a)
        # rs274 2.9 cuts an arc's start back on the circle through its end (measured: a line meeting an
        # arc whose end lies 0.0003 inside the circle through its start)
        radius = math.dist(arc.p1, arc.centre) if arc is b else arc.radius
        pts = line_circle(line.p0, line.tangent(False), arc.centre, radius)
    else:
        pts = circle_circle(a.centre, a.radius, b.centre, b.radius)
    return min(pts, key=lambda p: math.dist(p, near)) if pts else None


def first_crossing(a: Seg, b: Seg) -> tuple | None:
    """Two arcs meeting tangent but for the program's decimals: where the circles through their
    starts cross, the crossing ``a`` reaches first (rs274 2.9, measured on a convex arc into a
    concave one, outside and mirrored as a bore); None for a line or circles that do not cross."""
    if a.centre is None or b.centre is None:
        return None
    pts = circle_circle(a.centre, a.radius, b.centre, b.radius)
    if len(pts) < 2:
        return None
    a0, _ = a.angles()

    def along(p) -> float:
        ang = math.atan2(p[1] - a.centre[1], p[0] - a.centre[0])
        return (ang - a0) % (2 * math.pi) if a.ccw else (a0 - ang) % (2 * math.pi)
    return min(pts, key=along)


def line_circle(p, t, c, r) -> list[tuple]:
    w = (p[0] - c[0], p[1] - c[1])
    bq = w[0] * t[0] + w[1] * t[1]
    disc = bq * bq - (w[0] * w[0] + w[1] * w[1] - r * r)
    if disc < -1e-12:
        return []
    root = math.sqrt(max(disc, 0.0))
    return [(p[0] + t[0] * s, p[1] + t[1] * s) for s in (-bq - root, -bq + root)]


def circle_circle(c0, r0, c1, r1) -> list[tuple]:
    d = math.dist(c0, c1)
    if d < EPS or d > r0 + r1 + 1e-9 or d < abs(r0 - r1) - 1e-9:
        return []
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h = math.sqrt(max(r0 * r0 - a * a, 0.0))
    m = (c0[0] + a * (c1[0] - c0[0]) / d, c0[1] + a * (c1[1] - c0[1]) / d)
    ox, oy = -(c1[1] - c0[1]) * h / d, (c1[0] - c0[0]) * h / d
    return [(m[0] + ox, m[1] + oy), (m[0] - ox, m[1] - oy)]


def crossings(s: Seg, u: int, level: float) -> list[float]:
    """The other coordinate where the line ``p[u] == level`` meets the segment (both ends of a
    segment lying on it)."""
    v = 1 - u
    if s.centre is None:
        du = s.p1[u] - s.p0[u]
        if abs(du) < EPS:
            return [s.p0[v], s.p1[v]] if abs(s.p0[u] - level) < 1e-7 else []
        t = (level - s.p0[u]) / du
        if -1e-9 <= t <= 1 + 1e-9:
            return [s.p0[v] + (s.p1[v] - s.p0[v]) * t]
        return []
    c, r = s.centre, s.radius
    h = level - c[u]
    if abs(h) > r + 1e-9:
        return []
    w = math.sqrt(max(r * r - h * h, 0.0))
    a0, sweep = s.angles()
    found = []
    for dv in (w, -w):
        p = [0.0, 0.0]
        p[u], p[v] = level, c[v] + dv
        ang = math.atan2(p[1] - c[1], p[0] - c[0])
        rel = (ang - a0) % (2 * math.pi) if sweep > 0 else (a0 - ang) % (2 * math.pi)
        if rel <= abs(sweep) + 1e-9 or rel >= 2 * math.pi - 1e-9:
            found.append(p[v])
    return found
