"""Tool radius compensation geometry (G41/G42), independent of any dialect.

A contour in the working plane is a chain of 2D elements (straight lines and arcs, ``Elem``). The
tool centre path is the chain offset by the tool radius ``d`` (> 0 to the left of the travel, < 0
to the right), the neighbours joined

- at an inside corner (the offset elements overlap) by their intersection: both are trimmed;
- at an outside corner (a gap opens between them) by a transition: an arc about the corner point
  (``linear=False``: Sinumerik G450, ISG G26), or (``linear=True``: ISG G25, its default) the
  elements' extensions along their tangents - up to their intersection when the path turns by at
  most 90 degrees, otherwise each by the tool radius, joined by one straight block (the number of
  inserted blocks the TwinCAT CNC manual lists under "Generate compensation blocks": LIN-LIN 0/1,
  LIN-CIR 1/2, CIR-CIR 2/3 for turns up to / over 90 degrees).

``compensate_records`` applies it to canonical records (interp/canon.py) between a selection and a
deselection: the first motion in the plane is the approach, the deselection block's motion the
departure; moves along the tool axis only are done where the tool stands.

On a lathe the offset path is the path of the nose's centre, while the control point the program
moves is the tool's theoretical tip, which lies ``r`` from the centre along each axis the cutting
edge position points (``nose_shift``): the compensated path is the offset path moved by that.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ...base.specs import EDGE_POSITIONS
from .. import canon
from .modal import PLANE_AXES

EPS = 1e-9


@dataclass(frozen=True)
class Elem:
    """A straight line (kind "L") or an arc (kind "A", with its centre and sense) from ``start``
    to ``end``."""
    kind: str
    start: tuple[float, float]
    end: tuple[float, float]
    centre: tuple[float, float] | None = None
    cw: bool = False


class OffsetError(ValueError):
    """The offset contour cannot be built at element ``index`` (a bottleneck, a radius too large)."""

    def __init__(self, index: int, message: str):
        super().__init__(message)
        self.index = index


def _sub(p, q):
    return (p[0] - q[0], p[1] - q[1])


def _add(p, v, k=1.0):
    return (p[0] + k * v[0], p[1] + k * v[1])


def _norm(v):
    return math.hypot(v[0], v[1])


def _unit(v):
    n = _norm(v)
    return (v[0] / n, v[1] / n)


def _left(v):
    return (-v[1], v[0])


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1]


def tangent(e: Elem, at_end: bool):
    """Unit direction of travel at the start (or end) of an element."""
    if e.kind == "L":
        return _unit(_sub(e.end, e.start))
    p = e.end if at_end else e.start
    rv = _unit(_sub(p, e.centre))
    return (rv[1], -rv[0]) if e.cw else (-rv[1], rv[0])


def sweep(e: Elem) -> float:
    """Angle an arc turns through, radians, in (0, 2 pi]."""
    a0 = math.atan2(e.start[1] - e.centre[1], e.start[0] - e.centre[0])
    a1 = math.atan2(e.end[1] - e.centre[1], e.end[0] - e.centre[0])
    d = (a0 - a1) if e.cw else (a1 - a0)
    d %= 2 * math.pi
    return d if d > 1e-12 else 2 * math.pi


def length(e: Elem) -> float:
    if e.kind == "L":
        return _norm(_sub(e.end, e.start))
    return _norm(_sub(e.start, e.centre)) * sweep(e)


def offset_elem(e: Elem, d: float, idx: int) -> Elem:
    if e.kind == "L":
        n = _left(tangent(e, False))
        return Elem("L", _add(e.start, n, d), _add(e.end, n, d))
    c = e.centre
    r = _norm(_sub(e.start, c))
    r2 = r + d if e.cw else r - d  # the left of a CCW arc is its centre
    if r2 <= 1e-6:
        raise OffsetError(idx, f"the tool radius {abs(d):g} does not fit the arc of radius {r:g} (concave side)")

    def sc(p):
        return (c[0] + (p[0] - c[0]) * r2 / r, c[1] + (p[1] - c[1]) * r2 / r)
    return Elem("A", sc(e.start), sc(e.end), c, e.cw)


def intersections(e1: Elem, e2: Elem):
    """Intersections of the carriers (infinite line / full circle) of two elements."""
    if e1.kind == "L" and e2.kind == "L":
        d1, d2 = _sub(e1.end, e1.start), _sub(e2.end, e2.start)
        den = _cross(d1, d2)
        if abs(den) < 1e-14:
            return []
        t = _cross(_sub(e2.start, e1.start), d2) / den
        return [_add(e1.start, d1, t)]
    if e1.kind == "A" and e2.kind == "L":
        return intersections(e2, e1)
    if e1.kind == "L":
        c, r = e2.centre, _norm(_sub(e2.start, e2.centre))
        p, d = e1.start, _unit(_sub(e1.end, e1.start))
        f = _sub(p, c)
        b = _dot(f, d)
        disc = b * b - (_dot(f, f) - r * r)
        if disc < -1e-9:
            return []
        s = math.sqrt(max(disc, 0.0))
        return [_add(p, d, -b + k * s) for k in (-1, 1)]
    c1, r1 = e1.centre, _norm(_sub(e1.start, e1.centre))
    c2, r2 = e2.centre, _norm(_sub(e2.start, e2.centre))
    dd = _norm(_sub(c2, c1))
    if dd < 1e-12 or dd > r1 + r2 + 1e-9 or dd < abs(r1 - r2) - 1e-9:
        return []
    a = (r1 * r1 - r2 * r2 + dd * dd) / (2 * dd)
    h = math.sqrt(max(r1 * r1 - a * a, 0.0))
    u = _unit(_sub(c2, c1))
    m = _add(c1, u, a)
    return [(m[0] + k * h * -u[1], m[1] + k * h * u[0]) for k in (-1, 1)]


def _with_end(e: Elem, p, at_end: bool) -> Elem:
    if e.kind == "L":
        return Elem("L", e.start, p) if at_end else Elem("L", p, e.end)
    return Elem("A", e.start, p, e.centre, e.cw) if at_end else Elem("A", p, e.end, e.centre, e.cw)


def _moved(e: Elem, v) -> Elem:
    """The element translated by ``v``."""
    c = None if e.centre is None else _add(e.centre, v)
    return Elem(e.kind, _add(e.start, v), _add(e.end, v), c, e.cw)


def _check_trim(orig: Elem, new: Elem, idx: int) -> None:
    if orig.kind == "L":
        if _dot(_sub(new.end, new.start), _sub(orig.end, orig.start)) <= 0:
            raise OffsetError(idx, "the contour element is too short for the tool radius (bottleneck)")
    elif sweep(new) > sweep(orig) + 1e-7 and sweep(orig) < 2 * math.pi - 1e-9:
        raise OffsetError(idx, "the contour arc is too short for the tool radius (bottleneck)")


def _ray_meet(p, t, q, u):
    """The point where the ray p + a t (a >= 0) meets the ray q - b u (b >= 0), or None."""
    den = _cross(t, u)
    if abs(den) < 1e-14:
        return None
    diff = _sub(q, p)
    a = _cross(diff, u) / den
    b = -_cross(diff, t) / den
    return _add(p, t, a) if a >= -1e-9 and b >= -1e-9 else None


def offset_chain(elems: list[Elem], d: float, linear: bool = False, free_ends: tuple[bool, bool] = (False, False)):
    """Offset an open chain of elements by ``d`` (> 0 to the left of the travel, < 0 to the right)
    and join the neighbours (module docstring). Returns [(element, source index)] in path order.
    ``free_ends``: the first element's start / the last element's end are replaced by the caller
    (an approach or departure), so trimming past them is not a bottleneck."""
    if abs(d) < EPS:
        return [(e, i) for i, e in enumerate(elems)]
    n = len(elems)
    offs = [offset_elem(e, d, i) for i, e in enumerate(elems)]
    before: list[list] = [[] for _ in range(n)]  # pieces inserted before element i (owned by i)
    after: list[list] = [[] for _ in range(n)]  # pieces inserted after element i
    r = abs(d)
    for i in range(n - 1):
        q1, q2 = offs[i].end, offs[i + 1].start
        if _norm(_sub(q1, q2)) <= 1e-7:
            continue
        t1, t2 = tangent(elems[i], True), tangent(elems[i + 1], False)
        turn = _cross(t1, t2)
        if _norm(_sub(q1, q2)) < 0.01 and _dot(t1, t2) > 0.9999:
            # tangent within the rounding of the written coordinates: bridge the gap
            after[i].append((Elem("L", q1, q2), i + 1))
            continue
        convex = (turn < 0) if d > 0 else (turn > 0)
        if abs(turn) < 1e-12:
            convex = _dot(t1, t2) < 0  # reversal: go round the end
        if convex:
            if not linear:
                after[i].append((Elem("A", q1, q2, elems[i].end, d > 0), i + 1))
                continue
            x = _ray_meet(q1, t1, q2, t2) if _dot(t1, t2) >= -1e-12 else None
            if x is not None:  # turn of at most 90 degrees: extend both up to their intersection
                p1 = p2 = x
            else:  # extend each by the tool radius, one straight block between
                p1, p2 = _add(q1, t1, r), _add(q2, t2, -r)
            if offs[i].kind == "L":
                offs[i] = _with_end(offs[i], p1, True)
            else:
                after[i].append((Elem("L", q1, p1), i))
            if _norm(_sub(p2, p1)) > 1e-9:
                after[i].append((Elem("L", p1, p2), i + 1))
            if offs[i + 1].kind == "L":
                offs[i + 1] = _with_end(offs[i + 1], p2, False)
            else:
                before[i + 1].append((Elem("L", p2, q2), i + 1))
            continue
        pts = intersections(offs[i], offs[i + 1])
        if not pts:
            raise OffsetError(i + 1, "the offset contour has no corner here: the tool radius is too large")
        mid = ((q1[0] + q2[0]) / 2, (q1[1] + q2[1]) / 2)
        x = min(pts, key=lambda p: _norm(_sub(p, mid)))
        a = _with_end(offs[i], x, True)
        b = _with_end(offs[i + 1], x, False)
        if not (i == 0 and free_ends[0]):
            _check_trim(offs[i], a, i)
        if not (i + 1 == n - 1 and free_ends[1]):
            _check_trim(offs[i + 1], b, i + 1)
        offs[i], offs[i + 1] = a, b
    out = []
    for i in range(n):
        out.extend(before[i])
        out.append((offs[i], i))
        out.extend(after[i])
    return out


# ---------------------------------------------------------------------------------------------
# canonical records
def _p2(v, plane):
    a, b, _ = PLANE_AXES[plane]
    return (v[a], v[b])


def _p3(p, n, plane):
    a, b, c = PLANE_AXES[plane]
    v = [0.0, 0.0, 0.0]
    v[a], v[b], v[c] = p[0], p[1], n
    return (v[0], v[1], v[2])


def _motion_like(r, start, end):
    """A straight record like ``r`` (rapid or feed) from ``start`` to ``end``."""
    if isinstance(r, canon.Rapid):
        return canon.Rapid(r.src, start, end, r.diameter)
    return canon.Feed(r.src, start, end, r.diameter, getattr(r, "feed", 0.0), getattr(r, "per_rev", False))


def _in_plane(r, plane) -> bool:
    return _norm(_sub(_p2(r.end, plane), _p2(r.start, plane))) >= 1e-9 or (isinstance(r, canon.Arc) and r.full_turn)


def _elem(r, plane, error) -> Elem:
    if isinstance(r, canon.Arc):
        if r.full_turn:
            raise error(r, "a full circle under tool radius compensation is not supported: split it in two arcs")
        return Elem("A", _p2(r.start, plane), _p2(r.end, plane), _p2(r.center, plane), r.clockwise)
    if isinstance(r, canon.SyncedFeed):
        raise error(r, "thread cutting under tool radius compensation is not supported")
    return Elem("L", _p2(r.start, plane), _p2(r.end, plane))


def _pieces(r, pieces, plane):
    """The offset elements of one record, its tool-axis travel spread over them by length."""
    nidx = PLANE_AXES[plane][2]
    out = []
    total = sum(length(e) for e in pieces)
    z0, z1 = r.start[nidx], r.end[nidx]
    run = 0.0
    for e in pieces:
        za = z0 + (z1 - z0) * (run / total if total > 0 else 0)
        run += length(e)
        zb = z0 + (z1 - z0) * (run / total if total > 0 else 1)
        s3, e3 = _p3(e.start, za, plane), _p3(e.end, zb, plane)
        if e.kind == "L":
            out.append(_motion_like(r, s3, e3))
        else:
            out.append(canon.Arc(r.src, s3, e3, r.diameter, _p3(e.centre, za, plane), plane, e.cw, False,
                                 getattr(r, "feed", 0.0), getattr(r, "per_rev", False)))
    return out


def arc_elems(start, end, centre, cw: bool, full: bool) -> list:
    """An arc as elements: a full circle (start and end the same point) as its two halves, through
    the point opposite the start, so every element has a definite sweep for the offset."""
    if not full:
        return [Elem("A", start, end, centre, cw)]
    opp = (2 * centre[0] - start[0], 2 * centre[1] - start[1])
    return [Elem("A", start, opp, centre, cw), Elem("A", opp, end, centre, cw)]


def _contour(buf, body, plane, error, strict: bool):
    """The body's records as 2D elements and, for each element, the index of its record. Strict:
    one element per record, full circles and thread moves refused; otherwise full circles become
    their two halves, a thread move a line, and moves along the tool axis only are left out."""
    elems, owner = [], []
    for k in body:
        r = buf[k]
        if strict:
            pieces = [_elem(r, plane, error)]
        elif not _in_plane(r, plane):
            continue
        elif isinstance(r, canon.Arc):
            pieces = arc_elems(_p2(r.start, plane), _p2(r.end, plane), _p2(r.center, plane), r.clockwise, r.full_turn)
        else:
            pieces = [Elem("L", _p2(r.start, plane), _p2(r.end, plane))]
        elems.extend(pieces)
        owner.extend([k] * len(pieces))
    return elems, owner


# cutting edge position (1-9) -> signs (dx, dz) of the theoretical tip seen from the nose's centre
EDGE_TIP = {edge: signs for signs, edge in EDGE_POSITIONS.items()}


def nose_shift(edge: int, r: float, plane: str) -> tuple[float, float]:
    """From the nose's centre to the theoretical tip of a lathe tool of nose radius ``r`` and cutting
    edge position ``edge`` (docs/setup.md's figure: +X up, +Z to the right; 9 the centre itself), in
    the plane's coordinates (ZX: (z, x), X a radius)."""
    dx, dz = EDGE_TIP.get(edge, (0, 0))
    v = [0.0, 0.0, 0.0]
    v[0], v[2] = dx * r, dz * r
    a, b, _ = PLANE_AXES[plane]
    return (v[a], v[b])


def compensate_records(buf: list, d: float, plane: str, departure: bool, direct: bool, linear: bool, error,
                       strict: bool = True, shift: tuple[float, float] = (0.0, 0.0)):
    """Records from a G41/G42 selection to the deselection -> the tool centre records.

    The first motion that moves in the plane is the approach and the last one, when ``departure``
    (the deselection block's motion), the departure; both must be straight. ``direct`` (ISG G138,
    Sinumerik's default): the approach goes straight to the offset start of the first contour
    element and the departure leaves from the offset end of the last one. Otherwise (ISG G139,
    indirect): the approach and departure blocks are offset with the contour and joined to it like
    any two elements; only their outer ends stay where they were programmed.
    Not ``strict`` (Sinumerik, always direct): the first motion of any kind is the approach, a
    departure needs two motions before it, any motion may approach or depart (it is done straight),
    full circles and thread moves are offset too (see ``_contour``).
    ``shift`` (in the plane) moves the offset path before the approach and departure are joined to
    it: a lathe tool's tip from its nose centre (``nose_shift``).
    ``error(record, message)`` builds the exception for a record that cannot be compensated."""
    if strict:
        motions = [k for k, r in enumerate(buf) if isinstance(r, canon.MOTIONS) and _in_plane(r, plane)]
    else:
        motions = [k for k, r in enumerate(buf) if isinstance(r, canon.MOTIONS)]
    if len(motions) < (1 if strict else 2) or abs(d) < EPS:
        return list(buf)
    first = motions[0]
    last = motions[-1] if departure and len(motions) >= (2 if strict else 3) else None
    for k in (first, last) if strict else ():
        if k is not None and isinstance(buf[k], (canon.Arc, canon.SyncedFeed)):
            what = "approach" if k == first else "departure"
            raise error(buf[k], f"the {what} block of tool radius compensation must be a straight move (G00/G01)")
    body = motions if not direct else [k for k in motions if k not in (first, last)]
    elems, owner = _contour(buf, body, plane, error, strict)
    if not elems:
        return list(buf)
    try:
        chain = offset_chain(elems, d, linear, (not direct, not direct and last is not None))
    except OffsetError as e:
        r = buf[owner[e.index]]
        raise error(r, f"radius compensation: {e}") from None
    if shift != (0.0, 0.0):
        chain = [(_moved(e, shift), i) for e, i in chain]
    if not direct:  # the approach starts, the departure ends where programmed
        e0, i0 = chain[0]
        chain[0] = (_with_end(e0, _p2(buf[first].start, plane), False), i0)
        if last is not None:
            e1, i1 = chain[-1]
            chain[-1] = (_with_end(e1, _p2(buf[last].end, plane), True), i1)
    by_owner: dict[int, list] = {}
    for e, i in chain:
        by_owner.setdefault(owner[i], []).append(e)
    nidx = PLANE_AXES[plane][2]
    out = []
    cur = None  # current 3D position
    for k, r in enumerate(buf):
        if not isinstance(r, canon.MOTIONS):
            out.append(r)
            continue
        if k < first:
            new = [r]
        elif direct and k == first:
            new = [_motion_like(r, r.start, _p3(chain[0][0].start, r.end[nidx], plane))]
        elif direct and k == last:
            new = [_motion_like(r, cur, r.end)]
        elif k in by_owner:
            new = _pieces(r, by_owner[k], plane)
        else:  # a move along the tool axis only: done where the tool stands
            end = list(cur)
            end[nidx] = r.end[nidx]
            new = [_motion_like(r, cur, (end[0], end[1], end[2]))]
        out.extend(new)
        cur = new[-1].end
    return out

