"""The plane geometry of CYCLE95's contour in the cycle's own frame, as plain data (no interpreter
state, no meshes): the contour turned so that every machining type looks like longitudinal outside
roughing, the contour moved by the finishing allowances, and the walk along it by position.

The frame (a, b): ``a`` the infeed axis pointing out of the part into the material (the radius
outside, minus the radius inside; Z on the face outside, -Z on the face inside), ``b`` the cutting
axis (Z for the longitudinal types, the radius for the face types); the cuts run towards -b, the
contour runs from its start (largest b) to its end (smallest b). Elements: ("L", p, q) or
("A", p, q, centre, clockwise), points (a, b), clockwise as G2 seems when b is drawn to the right
and a up (G18's Z right, X up for VARI 1). A position on the contour is (element index, t), t the
fraction of the element (of its angle for an arc).
"""
from __future__ import annotations

import math

EPS = 1e-7

# VARI's units digit -> (face machining, inside): 1 longitudinal outside, 2 face outside,
# 3 longitudinal inside, 4 face inside (the Cycles manual's table)
KINDS = {1: (False, False), 2: (True, False), 3: (False, True), 4: (True, True)}


class Frame:
    """The map between (radius, z) and the cycle's (a, b) for a machining kind 1..4."""

    def __init__(self, kind: int):
        self.face, self.inside = KINDS[kind]
        s = -1.0 if self.inside else 1.0
        self.s = s
        # (r, z) -> (a, b): longitudinal a = s r, b = z; face a = s z, b = r
        self.flip = (s < 0) != self.face  # the map reverses the turning sense of arcs

    def to(self, r: float, z: float) -> tuple[float, float]:
        return (self.s * z, r) if self.face else (self.s * r, z)

    def back(self, a: float, b: float) -> tuple[float, float]:
        return (b, self.s * a) if self.face else (self.s * a, b)

    def elem(self, e):
        p, q = self.to(*e[1]), self.to(*e[2])
        if e[0] == "L":
            return ("L", p, q)
        return ("A", p, q, self.to(*e[3]), e[4] != self.flip)


def sweep(e) -> tuple[float, float]:
    """An arc's start angle and signed sweep, the angle measured from +b towards +a."""
    p, q, c, cw = e[1], e[2], e[3], e[4]
    a0 = math.atan2(p[0] - c[0], p[1] - c[1])
    a1 = math.atan2(q[0] - c[0], q[1] - c[1])
    sw = a1 - a0
    if cw and sw > 1e-12:
        sw -= 2 * math.pi
    if not cw and sw < -1e-12:
        sw += 2 * math.pi
    return a0, sw


def radius(e) -> float:
    return math.hypot(e[1][0] - e[3][0], e[1][1] - e[3][1])


def at(e, t: float) -> tuple[float, float]:
    """The point at the fraction t of an element."""
    p, q = e[1], e[2]
    if t <= 0.0:
        return p
    if t >= 1.0:
        return q
    if e[0] == "L":
        return (p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]))
    c = e[3]
    a0, sw = sweep(e)
    ang = a0 + t * sw
    rad = radius(e)
    return (c[0] + rad * math.sin(ang), c[1] + rad * math.cos(ang))


def tangent(e, t: float) -> tuple[float, float]:
    """The unit direction of travel at the fraction t."""
    if e[0] == "L":
        d = (e[2][0] - e[1][0], e[2][1] - e[1][1])
    else:
        a0, sw = sweep(e)
        ang = a0 + t * sw
        k = 1.0 if sw > 0 else -1.0
        d = (k * math.cos(ang), -k * math.sin(ang))
    n = math.hypot(*d) or 1.0
    return (d[0] / n, d[1] / n)


def normal(e, t: float) -> tuple[float, float]:
    """The unit normal out of the part (the part lies below the contour, towards -a)."""
    d = tangent(e, t)
    return (-d[1], d[0])


def sub(e, t0: float, t1: float):
    """The piece of an element between two fractions."""
    p, q = at(e, t0), at(e, t1)
    return ("L", p, q) if e[0] == "L" else ("A", p, q, e[3], e[4])


def split_quadrants(e) -> list:
    """An arc cut where its tangent is parallel to an axis: each piece is monotone in a and b."""
    if e[0] == "L":
        return [e]
    a0, sw = sweep(e)
    cuts = []
    for k in range(-12, 13):
        ang = k * math.pi / 2
        t = (ang - a0) / sw if abs(sw) > 1e-12 else -1.0
        if 1e-9 < t < 1 - 1e-9:
            cuts.append(t)
    ts = [0.0] + sorted(cuts) + [1.0]
    return [sub(e, ts[i], ts[i + 1]) for i in range(len(ts) - 1)]


def bulge(e, axis: int) -> tuple[float, float]:
    """The least and largest coordinate ``axis`` (0: a, 1: b) over an element."""
    pts = [at(x, 0.0)[axis] for x in split_quadrants(e)] + [e[2][axis]]
    return min(pts), max(pts)


# ---------------------------------------------------------------------------------------------
# the contour moved by the finishing allowances
def _box(e, fa: float, fb: float) -> tuple[float, float]:
    """The allowance box's corner on the side a monotone piece's normal points to."""
    n = normal(e, 0.5)
    return (fa * (1.0 if n[0] >= -1e-9 else -1.0), fb * (1.0 if n[1] >= -1e-9 else -1.0))


def _shift(e, fa: float, fb: float, fal: float):
    """One monotone piece moved out of the part: by the allowance box's corner (fa along a, fb
    along b) and by ``fal`` along its normal."""
    n = normal(e, 0.5)
    v = _box(e, fa, fb)
    if e[0] == "L":
        return ("L", (e[1][0] + v[0] + fal * n[0], e[1][1] + v[1] + fal * n[1]),
                (e[2][0] + v[0] + fal * n[0], e[2][1] + v[1] + fal * n[1]))
    c = (e[3][0] + v[0], e[3][1] + v[1])
    rad = radius(e) + (-fal if e[4] else fal)  # clockwise: the part outside the circle
    pts = []
    for t in (0.0, 1.0):
        pt = at(e, t)
        u = ((pt[0] - e[3][0]) / radius(e), (pt[1] - e[3][1]) / radius(e))
        pts.append((c[0] + rad * u[0], c[1] + rad * u[1]))
    return ("A", pts[0], pts[1], c, e[4])


def _meet(e, f, near):
    """Where the (extended) elements e and f cross nearest ``near``; None when they do not."""
    cands = []
    if e[0] == "L" and f[0] == "L":
        d1 = (e[2][0] - e[1][0], e[2][1] - e[1][1])
        d2 = (f[2][0] - f[1][0], f[2][1] - f[1][1])
        den = d1[0] * d2[1] - d1[1] * d2[0]
        if abs(den) > 1e-12:
            w = (f[1][0] - e[1][0], f[1][1] - e[1][1])
            s = (w[0] * d2[1] - w[1] * d2[0]) / den
            cands.append((e[1][0] + s * d1[0], e[1][1] + s * d1[1]))
    elif e[0] == "A" and f[0] == "A":
        cands = _circles(e[3], radius(e), f[3], radius(f))
    else:
        ln, ar = (e, f) if e[0] == "L" else (f, e)
        cands = _line_circle(ln[1], ln[2], ar[3], radius(ar))
    if not cands:
        return None
    return min(cands, key=lambda c: math.hypot(c[0] - near[0], c[1] - near[1]))


def _line_circle(p, q, c, r):
    d = (q[0] - p[0], q[1] - p[1])
    f = (p[0] - c[0], p[1] - c[1])
    A = d[0] ** 2 + d[1] ** 2
    B = 2 * (f[0] * d[0] + f[1] * d[1])
    C = f[0] ** 2 + f[1] ** 2 - r * r
    disc = B * B - 4 * A * C
    if A < 1e-18 or disc < -1e-12:
        return []
    sq = math.sqrt(max(disc, 0.0))
    return [(p[0] + s * d[0], p[1] + s * d[1]) for s in ((-B - sq) / (2 * A), (-B + sq) / (2 * A))]


def _circles(c1, r1, c2, r2):
    dx, dy = c2[0] - c1[0], c2[1] - c1[1]
    d = math.hypot(dx, dy)
    if d < 1e-12 or d > r1 + r2 + 1e-9 or d < abs(r1 - r2) - 1e-9:
        return []
    x = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    h = math.sqrt(max(r1 * r1 - x * x, 0.0))
    m = (c1[0] + x * dx / d, c1[1] + x * dy / d)
    return [(m[0] - h * dy / d, m[1] + h * dx / d), (m[0] + h * dy / d, m[1] - h * dx / d)]


def _with_end(e, pt, start: bool):
    if start:
        return (e[0], pt, e[2]) + tuple(e[3:])
    return (e[0], e[1], pt) + tuple(e[3:])


def _bridge(p, q, prev, here, fa: float, fb: float, fal: float) -> list:
    """Across an outer corner (where ``prev`` ends and ``here`` starts) from p to q: the allowance
    box's side (a line) where the box turns its corner, and the arc of radius FAL about the vertex
    moved by the box (cw False: it turns as the convex arcs do)."""
    if fal <= EPS:
        return [("L", p, q)]
    v = _box(here, fa, fb)
    c = (here[1][0] + v[0], here[1][1] + v[1])
    n = normal(prev, 1.0)
    mid = (c[0] + fal * n[0], c[1] + fal * n[1])
    out = []
    if math.hypot(mid[0] - p[0], mid[1] - p[1]) > 1e-9:
        out.append(("L", p, mid))
    out.append(("A", mid, q, c, False))
    return out


def offset(elems: list, fa: float, fb: float, fal: float) -> list:
    """The contour moved out of the part by the allowances: each monotone piece moved (``_shift``);
    where the pieces overlap (an inner corner) both are cut back to their crossing, where they part
    (an outer corner, or an arc's piece where the allowance box turns its corner) a line bridges
    them. Every returned element is monotone in a and in b."""
    pieces = [x for e in elems for x in split_quadrants(e)]
    if fa <= EPS and fb <= EPS and fal <= EPS:
        return pieces
    out = [_shift(pieces[0], fa, fb, fal)]
    for k in range(1, len(pieces)):
        prev, here = pieces[k - 1], pieces[k]
        moved = _shift(here, fa, fb, fal)
        last = out[-1]
        gap = math.hypot(last[2][0] - moved[1][0], last[2][1] - moved[1][1])
        if gap > 1e-9:
            t1, t2 = tangent(prev, 1.0), tangent(here, 0.0)
            turn = t1[0] * t2[1] - t1[1] * t2[0]
            # an inner corner, or a concave arc's piece where the box turns its corner
            inner = turn > 1e-9 or (abs(turn) <= 1e-9 and any(x[0] == "A" and x[4] for x in (prev, here)))
            meet = _meet(last, moved, here[1]) if inner else None
            if meet is not None and math.hypot(meet[0] - here[1][0], meet[1] - here[1][1]) \
                    < 4 * (fa + fb + fal) + 1e-6:
                out[-1] = _with_end(last, meet, False)
                moved = _with_end(moved, meet, True)
            else:
                out.extend(_bridge(last[2], moved[1], prev, here, fa, fb, fal))
        out.append(moved)
    return [x for e in out for x in split_quadrants(e)
            if math.hypot(e[2][0] - e[1][0], e[2][1] - e[1][1]) > 1e-9]


def mapped(elems: list, f, flip: bool = False) -> list:
    """The elements with every point taken through ``f`` (a rigid map); ``flip``: it mirrors, so
    each arc turns the other way."""
    return [(e[0], f(e[1]), f(e[2])) + ((f(e[3]), e[4] != flip) if e[0] == "A" else ()) for e in elems]


def tip_path(elems: list, fa: float, fb: float, fal: float, nose: float, shift: tuple[float, float],
             blank: bool = True) -> list:
    """Where the tool's theoretical tip runs so that its nose circle (radius ``nose``) stays tangent
    to the contour moved by the allowances, on the air's side (+a): the nose centre's path is that
    contour moved ``nose`` further along its normal (rounded by the nose about its outer corners, as
    G41/G42's), the tip ``shift`` (a, b) from the centre (the cutting edge position). With ``blank``
    (the contour's end rising to the blank's level) a piece along that level is added past the end,
    so that the path reaches the level too. Raises ValueError
    (the point) where a concave arc is narrower than the nose plus FAL."""
    if nose <= EPS:
        return offset(elems, fa, fb, fal)
    for e in elems:
        if e[0] == "A" and e[4] and radius(e) <= fal + nose + EPS:
            raise ValueError(e[2])
    end = elems[-1][2]
    ext = [("L", end, (end[0], end[1] - 2.0 * (nose + fa + fb + fal) - 1.0))] if blank else []
    path = mapped(offset(list(elems) + ext, fa, fb, fal + nose), lambda pt: (pt[0] + shift[0], pt[1] + shift[1]))
    while blank and len(path) > 1 and min(path[-1][1][0], path[-1][2][0]) >= end[0] - EPS:
        path.pop()  # along the blank's level: no material there, the path ends where it reaches it
    return path


# ---------------------------------------------------------------------------------------------
# walking along the contour by position (element index, t)
def rising(e) -> bool:
    return e[2][0] > e[1][0] + EPS


def falling(e) -> bool:
    return e[2][0] < e[1][0] - EPS


def point(elems, s) -> tuple[float, float]:
    i, t = s
    return at(elems[i], t) if i < len(elems) else elems[-1][2]


def _solve(e, level: float, t0: float) -> float:
    """The fraction (from t0 on) where a monotone element reaches the level ``level``."""
    if e[0] == "L":
        p, q = e[1], e[2]
        t = (level - p[0]) / (q[0] - p[0])
        return min(1.0, max(t0, t))
    lo, hi = t0, 1.0
    up = at(e, 1.0)[0] > at(e, t0)[0]
    for _ in range(80):
        mid = (lo + hi) / 2
        if (at(e, mid)[0] >= level) == up:
            hi = mid
        else:
            lo = mid
    return (lo + hi) / 2


def first_up(elems, s, level: float):
    """The first position from ``s`` on where the contour rises above ``level`` (its point at the
    level); the contour's end when it never does."""
    for i in range(s[0], len(elems)):
        e = elems[i]
        t0 = s[1] if i == s[0] else 0.0
        pa = at(e, t0)[0]
        if rising(e) and pa <= level + EPS and e[2][0] > level + EPS:
            t = _solve(e, level, t0)
            return (i, t)
        if pa > level + EPS:  # already above (a start or a piece above the level)
            return (i, t0)
    return (len(elems) - 1, 1.0)


def first_below(elems, s, level: float, stop=None):
    """The first position from ``s`` on (before ``stop``) where the contour lies below ``level``:
    ``s`` itself when it does there, else where a falling piece passes the level; None if none."""
    end = stop if stop is not None else (len(elems) - 1, 1.0)
    for i in range(s[0], end[0] + 1):
        e = elems[i]
        t0 = s[1] if i == s[0] else 0.0
        if at(e, t0)[0] < level - EPS:
            return (i, t0)
        if falling(e) and e[2][0] < level + EPS:
            t = _solve(e, level, t0)
            if (i, t) > end:
                return None
            return (i, t)
    return None


def follow_up(elems, s, level: float):
    """From ``s`` along the contour while it does not fall, up to where it reaches ``level``:
    (the stop position, whether it stopped at a top before the level)."""
    for i in range(s[0], len(elems)):
        e = elems[i]
        t0 = s[1] if i == s[0] else 0.0
        if falling(e):
            return (i, t0), True
        if e[2][0] >= level - EPS and at(e, t0)[0] < level + EPS and rising(e):
            return (i, _solve(e, level, t0)), False
    return (len(elems) - 1, 1.0), False


def lowest(elems, s0, s1) -> float:
    """The lowest a between two positions (the pieces are monotone: their ends and the bounds)."""
    vals = [point(elems, s0)[0], point(elems, s1)[0]]
    for i in range(s0[0] + 1, min(s1[0], len(elems) - 1) + 1):
        vals.append(elems[i][1][0])
    return min(vals)


def basin_end(elems, s0):
    """Where the first basin from ``s0`` ends: the first top after the contour has risen."""
    risen = False
    for i in range(s0[0], len(elems)):
        e = elems[i]
        if falling(e) and risen:
            return (i, s0[1] if i == s0[0] else 0.0)
        if rising(e):
            risen = True
    return (len(elems) - 1, 1.0)


def pieces(elems, s0, s1) -> list:
    """The contour between two positions, as elements."""
    out = []
    for i in range(s0[0], min(s1[0], len(elems) - 1) + 1):
        t0 = s0[1] if i == s0[0] else 0.0
        t1 = s1[1] if i == s1[0] else 1.0
        if t1 > t0 + 1e-12:
            out.append(sub(elems[i], t0, t1))
    return out
