"""Sinumerik chamfers and roundings at contour corners: CHF=, CHR=, RND=, RNDM= and their feeds
FRC=, FRCM= (Programming Manual Fundamentals, "Chamfer, rounding"; docs/dialects/sinumerik.md,
"Chamfers and roundings").

The word goes in the block whose move leads to the corner; the element (a straight chamfer or a
tangent arc) is inserted between that move and the next move in the plane. The interpreter hands
this module every motion record of the moves it runs (``take``): the record of a block with a
corner word (or under RNDM) is held until the next move shows the corner, then both are cut back
to the new element's ends. Records of other kinds that come while one is held wait behind it
(``queue``). Geometry is in the active plane's two coordinates (G17: X, Y), in the machine's mm.

Geometry of one corner P between element 1 (ending at P) and element 2 (starting at P), with
t1, t2 their unit tangents at P (a line's direction; an arc's tangent there):
- RND=r: the arc of radius r tangent to both. Its centre lies at distance r on the inner side of
  both elements: the intersection of the two elements offset by r toward the side the path turns
  to (a line's parallel, an arc's concentric circle of radius R -+ r), the one nearest P. The
  tangent points are the centre's feet on the elements. For two lines meeting at a deflection
  angle phi they lie r tan(phi/2) from P.
- CHR=c: a straight chamfer from the point of element 1 at distance c from P to the point of
  element 2 at distance c from P (straight-line distance: along a line, c; on an arc, the point
  whose chord to P is c).
- CHF=L: the same chamfer with its own length L: between two lines c = L / |t1 + t2|; with an arc,
  c solved for |A(c) B(c)| = L by bisection.
A tangent transition (t1 = t2) is no corner: nothing is inserted.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..canon import Arc, Feed, Rapid, Src
from ..errors import CutsimError
from ..core.modal import PLANE_AXES
from .syntax import COORD_LIMIT, FEED_LIMIT, range_message

EPS = 1e-9


class CornerError(Exception):
    """A chamfer or rounding that does not fit (the caller reports it at the word)."""


@dataclass(frozen=True)
class El:
    """One contour element in the plane: a line s -> e, or an arc s -> e about c (ccw or not)."""
    s: tuple[float, float]
    e: tuple[float, float]
    c: tuple[float, float] | None = None
    ccw: bool = True

    @property
    def r(self) -> float:
        return math.dist(self.s, self.c) if self.c is not None else 0.0


def _unit(v):
    n = math.hypot(v[0], v[1])
    if n < EPS:
        raise CornerError("an element of the corner has no length")
    return (v[0] / n, v[1] / n)


def tangent(el: El, p) -> tuple[float, float]:
    """The unit direction of travel of ``el`` at its point ``p``."""
    if el.c is None:
        return _unit((el.e[0] - el.s[0], el.e[1] - el.s[1]))
    rx, ry = p[0] - el.c[0], p[1] - el.c[1]
    return _unit((-ry, rx) if el.ccw else (ry, -rx))


def _angle(c, p) -> float:
    return math.atan2(p[1] - c[1], p[0] - c[0])


def _sweep(el: El, a, b) -> float:
    """The angle travelled on arc ``el`` from its point a to its point b (0 .. 2 pi)."""
    d = _angle(el.c, b) - _angle(el.c, a)
    if not el.ccw:
        d = -d
    return d % (2 * math.pi)


def _within(el: El, p, toward_end: bool) -> bool:
    """``p`` lies on ``el`` (a point of its line/circle) between its start and end."""
    if el.c is None:
        d = (el.e[0] - el.s[0], el.e[1] - el.s[1])
        n2 = d[0] ** 2 + d[1] ** 2
        u = ((p[0] - el.s[0]) * d[0] + (p[1] - el.s[1]) * d[1]) / n2
        return -1e-9 <= u <= 1 + 1e-9
    total = _sweep(el, el.s, el.e) or 2 * math.pi
    part = _sweep(el, el.s, p)
    if toward_end and part < 1e-12:  # the element's own start seen from its end: all of it
        part = total
    return part <= total + 1e-9


def turn(e1: El, e2: El) -> float:
    """Sine of the turn at the corner (> 0: to the left); 0 for a tangent transition."""
    t1, t2 = tangent(e1, e1.e), tangent(e2, e2.s)
    cross = t1[0] * t2[1] - t1[1] * t2[0]
    dot = t1[0] * t2[0] + t1[1] * t2[1]
    if abs(cross) < 1e-9:
        if dot < 0:
            raise CornerError("the contour turns back on itself at the corner: there is no corner to chamfer "
                              "or round")
        return 0.0
    return cross


def _offset_hits(e1: El, e2: El, r: float, side: float) -> list:
    """Points at distance r on the ``side`` (+1 left) of both elements' lines/circles."""
    curves = []
    for el in (e1, e2):
        if el.c is None:
            t = tangent(el, el.s)
            n = (-t[1] * side * r, t[0] * side * r)
            curves.append(("line", (el.s[0] + n[0], el.s[1] + n[1]), t))
        else:
            rr = el.r - r * side * (1 if el.ccw else -1)  # the left of a ccw arc is toward its centre
            if rr <= EPS:
                raise CornerError(f"the rounding radius {r:g} does not fit inside the arc of radius {el.r:g}")
            curves.append(("circle", el.c, rr))
    return _intersect(*curves)


def _intersect(a, b) -> list:
    if a[0] == "circle" and b[0] == "line":
        a, b = b, a
    if a[0] == "line" and b[0] == "line":
        (p, d), (q, f) = a[1:], b[1:]
        den = d[0] * f[1] - d[1] * f[0]
        if abs(den) < 1e-12:
            return []
        u = ((q[0] - p[0]) * f[1] - (q[1] - p[1]) * f[0]) / den
        return [(p[0] + u * d[0], p[1] + u * d[1])]
    if a[0] == "line":  # line-circle
        (p, d), (c, rr) = a[1:], b[1:]
        w = (p[0] - c[0], p[1] - c[1])
        bb = w[0] * d[0] + w[1] * d[1]
        disc = bb * bb - (w[0] ** 2 + w[1] ** 2 - rr * rr)
        if disc < -1e-12:
            return []
        s = math.sqrt(max(disc, 0.0))
        return [(p[0] + u * d[0], p[1] + u * d[1]) for u in (-bb - s, -bb + s)]
    (c1, r1), (c2, r2) = a[1:], b[1:]  # circle-circle
    dd = math.dist(c1, c2)
    if dd < EPS or dd > r1 + r2 + 1e-12 or dd < abs(r1 - r2) - 1e-12:
        return []
    x = (dd * dd + r1 * r1 - r2 * r2) / (2 * dd)
    h = math.sqrt(max(r1 * r1 - x * x, 0.0))
    ux, uy = (c2[0] - c1[0]) / dd, (c2[1] - c1[1]) / dd
    m = (c1[0] + x * ux, c1[1] + x * uy)
    return [(m[0] - h * uy, m[1] + h * ux), (m[0] + h * uy, m[1] - h * ux)]


def _foot(el: El, q) -> tuple[float, float]:
    """The point of ``el``'s line or circle nearest ``q``."""
    if el.c is None:
        t = tangent(el, el.s)
        u = (q[0] - el.s[0]) * t[0] + (q[1] - el.s[1]) * t[1]
        return (el.s[0] + u * t[0], el.s[1] + u * t[1])
    v = _unit((q[0] - el.c[0], q[1] - el.c[1]))
    return (el.c[0] + el.r * v[0], el.c[1] + el.r * v[1])


def fillet(e1: El, e2: El, r: float):
    """RND=r: (end of element 1, start of element 2, the fillet's centre, ccw) or None (no corner)."""
    sin = turn(e1, e2)
    if sin == 0.0:
        return None
    side = 1.0 if sin > 0 else -1.0
    p = e1.e
    hits = _offset_hits(e1, e2, r, side)
    if not hits:
        raise CornerError(f"no arc of radius {r:g} is tangent to both elements")
    q = min(hits, key=lambda h: math.dist(h, p))
    a, b = _foot(e1, q), _foot(e2, q)
    if not _within(e1, a, True) or not _within(e2, b, False) or not _short_side(e1, e2, a, b):
        raise CornerError(f"the rounding of radius {r:g} is longer than an element of the corner")
    return a, b, q, side > 0


def _short_side(e1: El, e2: El, a, b) -> bool:
    """The tangent points lie before P on element 1 and after P on element 2 (not beyond the
    corner on an element's extension: an arc's circle meets the offset twice)."""
    if e1.c is None:
        t = tangent(e1, e1.s)
        if (e1.e[0] - a[0]) * t[0] + (e1.e[1] - a[1]) * t[1] < -1e-9:
            return False
    if e2.c is None:
        t = tangent(e2, e2.s)
        if (b[0] - e2.s[0]) * t[0] + (b[1] - e2.s[1]) * t[1] < -1e-9:
            return False
    return True


def _at_distance(el: El, c: float, from_end: bool):
    """The point of ``el`` at straight-line distance c from its end (from_end) or start."""
    p = el.e if from_end else el.s
    if el.c is None:
        t = tangent(el, el.s)
        k = -c if from_end else c
        q = (p[0] + k * t[0], p[1] + k * t[1])
        return q if _within(el, q, from_end) else None
    if c > 2 * el.r:
        return None
    delta = 2 * math.asin(c / (2 * el.r))  # the chord c subtends delta
    if from_end == el.ccw:
        delta = -delta
    a0 = _angle(el.c, p)
    q = (el.c[0] + el.r * math.cos(a0 + delta), el.c[1] + el.r * math.sin(a0 + delta))
    total = _sweep(el, el.s, el.e) or 2 * math.pi
    return q if 2 * math.asin(min(c / (2 * el.r), 1.0)) <= total + 1e-9 else None


def chamfer(e1: El, e2: El, c: float):
    """CHR=c: (end of element 1, start of element 2) c from the corner, or None (no corner)."""
    if turn(e1, e2) == 0.0:
        return None
    a, b = _at_distance(e1, c, True), _at_distance(e2, c, False)
    if a is None or b is None:
        raise CornerError(f"the chamfer's legs of {c:g} are longer than an element of the corner")
    return a, b


def chamfer_legs(e1: El, e2: El, length: float) -> float:
    """CHF=L: the leg c whose chamfer is L long."""
    if turn(e1, e2) == 0.0:
        return 0.0
    t1, t2 = tangent(e1, e1.e), tangent(e2, e2.s)
    s = math.hypot(t1[0] + t2[0], t1[1] + t2[1])
    if e1.c is None and e2.c is None:
        return length / s
    lo, hi = 0.0, length / s * 4 + length

    def size(c):
        a, b = _at_distance(e1, c, True), _at_distance(e2, c, False)
        return None if a is None or b is None else math.dist(a, b)
    for _ in range(200):
        mid = (lo + hi) / 2
        got = size(mid)
        if got is None or got > length:
            hi = mid
        else:
            lo = mid
    got = size(lo)
    if got is None or abs(got - length) > 1e-6:
        raise CornerError(f"the chamfer of length {length:g} is longer than an element of the corner")
    return lo


# -- the interpreter's side ------------------------------------------------------------------------
CORNER_WORDS = ("CHF", "CHR", "RND", "RNDM", "FRC", "FRCM")
ELEMENT_WORDS = ("CHF", "CHR", "RND")  # one of them per block
MAX_BETWEEN = 3  # blocks without a move in the plane between the two elements (the manual: more, no element)
NAMES = {"CHF": "chamfer", "CHR": "chamfer", "RND": "rounding", "RNDM": "rounding"}


@dataclass
class Hold:
    """The record of the move leading to a corner, waiting for the next move."""
    rec: object  # canon.Rapid | Feed | Arc
    kind: str  # CHF CHR RND RNDM
    value: float  # mm in the machine
    feed: float | None  # FRC / FRCM
    line: int
    col: int
    plane: str
    prog: str  # the file of its block (the next move may run in another: a subprogram, a return)
    blocks: int = 0  # blocks run since its own

    def error(self, message: str, col: int | None = None) -> CutsimError:
        """An error at the word (RNDM: the held block), in the held block's own file."""
        return CutsimError(self.prog, self.line, self.col if col is None else col, message)


@dataclass
class Corners:
    """Per interpreter: RNDM and FRCM (modal), the held record and what waits behind it."""
    modal_r: float = 0.0
    modal_feed: float = 0.0
    hold: Hold | None = None
    queue: list | None = None
    capture: list | None = None  # the records of the move being run (``Sinumerik.move``)

    def active(self) -> bool:
        return self.hold is not None or self.modal_r > 0.0


def word(m, corner: dict, name: str, value: float, line: int, col: int) -> None:
    """A corner word of the block: its value checked, kept in ``corner`` (name -> (value, col))."""
    if name in ELEMENT_WORDS:
        other = next((k for k in ELEMENT_WORDS if k in corner), None)
        if other is not None:
            raise m.error(line, col, f"{name}= and {other}= in one block: a corner takes one chamfer or rounding")
    if name == "FRC" and value <= 0:
        raise m.error(line, col, f"FRC={value:g}: the feed of the chamfer or rounding must be more than 0")
    if value < 0:
        raise m.error(line, col, f"{name}={value:g} must not be negative")
    hi = FEED_LIMIT if name in ("FRC", "FRCM") else COORD_LIMIT
    if not value <= hi:  # NaN too
        raise m.error(line, col, range_message(name, value, 0, hi, "mm/min or mm/rev" if name in ("FRC", "FRCM") else "mm"))
    corner[name] = (value, col)


def _scale(m, line: int, col: int) -> float:
    """Program units -> machine mm for a length in the plane: inch units and a frame's uniform scale;
    a frame that tilts the plane or scales it unevenly is refused (the element would not be a circle)."""
    ms = m.machine
    lin = ms.linear_part()
    a, b, n = PLANE_AXES[m.plane]
    cols = [tuple(lin[i][j] for i in range(3)) for j in range(3)]
    sa, sb = math.hypot(*cols[a]), math.hypot(*cols[b])
    if abs(cols[a][n]) > 1e-9 or abs(cols[b][n]) > 1e-9 or abs(sa - sb) > 1e-9 * max(sa, 1.0):
        raise m.error(line, col, "a chamfer or rounding under a frame that tilts the plane or scales it unevenly "
                                 "is not modelled")
    return sa


def run_move(m, corner: dict, line: int, do_move) -> None:
    """Run the block's move (``do_move``) with the corner words ``corner`` of the block: its motion
    record is held for the next corner, or completes the held one's."""
    cs = m.corners
    if "RNDM" in corner:
        cs.modal_r = corner["RNDM"][0] * _scale(m, line, corner["RNDM"][1]) if corner["RNDM"][0] > 0 else 0.0
    if "FRCM" in corner:
        cs.modal_feed = corner["FRCM"][0]
    kind = next((k for k in ELEMENT_WORDS if k in corner), None)
    if kind is None and cs.modal_r > 0:
        kind = "RNDM"
    if kind is None and cs.hold is None:
        do_move()
        return
    if m.machine.deferred:  # the block's cycles run in its move (under a frame): their moves come next
        flush(m, "a cycle's move comes next")
        if kind in ELEMENT_WORDS:
            _refuse(m, line, corner[kind][1], kind)
        do_move()
        return
    cs.capture = []
    try:
        do_move()
    finally:
        recs, cs.capture = cs.capture, None
    _take(m, recs, corner, kind, line)


def _shape(m, rec) -> str:
    """"plane" (a line or arc in the plane), "normal" (a move along the plane's normal only),
    "none" (no displacement), "other" (a ramp, a helix, a thread)."""
    if type(rec).__name__ not in ("Rapid", "Feed", "Arc"):
        return "other"
    a, b, n = PLANE_AXES[m.plane]
    if getattr(rec, "plane", m.plane) != m.plane:
        return "other"
    dn = abs(rec.end[n] - rec.start[n]) > 1e-9
    dp = abs(rec.end[a] - rec.start[a]) > 1e-9 or abs(rec.end[b] - rec.start[b]) > 1e-9 or \
        getattr(rec, "full_turn", False)
    return "other" if dn and dp else "normal" if dn else "plane" if dp else "none"


def _take(m, recs: list, corner: dict, kind: str | None, line: int) -> None:
    cs = m.corners
    explicit = kind in ELEMENT_WORDS
    col = corner[kind][1] if explicit else 1
    shapes = [_shape(m, r) for r in recs]
    if not recs:
        if explicit:
            raise m.error(line, col, f"{kind}= goes in the block whose move in the plane leads to the corner")
        return
    if len(recs) != 1 or shapes[0] == "other":
        if cs.hold is not None and shapes[0] != "none":
            _refuse(m, cs.hold.line, cs.hold.col, cs.hold.kind, cs.hold.prog)
        if explicit or (kind == "RNDM" and shapes[0] != "none"):
            _refuse(m, line, col, kind)
        for r in recs:
            m.emit(r)
        return
    rec, shape = recs[0], shapes[0]
    if shape == "none":
        m.emit(rec)
        return
    if shape == "normal":
        if cs.hold is not None:
            flush(m, "the next move leaves the plane")
        if explicit:
            _note(m, kind, line, col, "the move leading to the corner is not in the plane")
        m.emit(rec)
        return
    if cs.hold is not None:
        rec = _resolve(m, cs.hold, rec, line)
    if kind is None:
        m.emit(rec)
        return
    value = corner[kind][0] * _scale(m, line, col) if explicit else cs.modal_r
    feed = corner["FRC"][0] if "FRC" in corner else cs.modal_feed or None
    if value <= 0:
        m.emit(rec)
        return
    cs.hold, cs.queue = Hold(rec, kind, value, feed, line, col, m.plane, m.unit_program), []


def _refuse(m, line: int, col: int, kind: str, prog: str | None = None):
    g = {"XY": "G17", "ZX": "G18", "YZ": "G19"}[m.plane]
    raise CutsimError(prog or m.unit_program, line, col, f"{kind}: a chamfer or rounding next to a move that is not in the plane {g} "
                             "(a ramp, a helix, a thread or a cycle) is not modelled")


def _note(m, kind: str, line: int, col: int, why: str, prog: str | None = None) -> None:
    if kind in ELEMENT_WORDS:
        m.warn(Src(prog or m.unit_program, line, col), f"{kind}= inserts no {NAMES[kind]} here: {why} (as on the controller)")


def flush(m, why: str | None = None) -> None:
    """Emit the held record as it is (no element at its corner) and what waited behind it."""
    cs = m.corners
    h, queue = cs.hold, cs.queue or []
    if h is None:
        return
    cs.hold, cs.queue = None, None
    if why is not None:
        _note(m, h.kind, h.line, h.col, why, h.prog)
    m.emit(h.rec)
    for r in queue:
        m.emit(r)


def comp_change(m, new_comp: int | None) -> None:
    """A block that starts, changes or ends radius compensation (G41/G42/G40) while a move waits for
    its corner: the held move and the next would be offset differently; not modelled (exit 2 at
    the word leading to the corner)."""
    h = m.corners.hold
    if h is None or new_comp is None:
        return
    on = m.comp_buf is not None
    if (new_comp == 40 and on) or (new_comp in (41, 42) and (not on or m.comp != new_comp)):
        raise h.error(f"{h.kind}: a chamfer or rounding at a corner where the radius compensation "
                      f"starts, changes or ends (G{new_comp}) is not modelled")


def comp_end(m) -> None:
    """G40 ends radius compensation after this block's move, which may wait for its corner: RND/CHF/CHR
    there is not modelled (exit 2 at the word); under RNDM the move goes into the compensation as it
    is (no rounding at the corner after the departure move)."""
    h = m.corners.hold
    if h is None:
        return
    if h.kind in ELEMENT_WORDS:
        raise h.error(f"{h.kind}: a chamfer or rounding at a corner where the radius compensation "
                      "starts, changes or ends (G40) is not modelled")
    flush(m)


def finish(m) -> None:
    """The program (or a cycle's contour) ends: a chamfer or rounding still waiting has no second
    element: RND/CHF/CHR is an error at its word, RNDM's last corner is none."""
    h = m.corners.hold
    if h is not None and h.kind in ELEMENT_WORDS:
        raise h.error(f"{h.kind}= on the last move: no move follows to make the corner with")
    flush(m)


def _plane_el(m, rec) -> El:
    """A record as a plane element (physical coordinates: X halved in diameter mode)."""
    a, b, _ = PLANE_AXES[m.plane]
    k = [0.5 if (rec.diameter and i == 0) else 1.0 for i in range(3)]

    def p2(p):
        return (p[a] * k[a], p[b] * k[b])
    if isinstance(rec, Arc):
        return El(p2(rec.start), p2(rec.end), p2(rec.center), not rec.clockwise)
    return El(p2(rec.start), p2(rec.end))


def _point(m, rec, q) -> tuple[float, float, float]:
    """A plane point back into the record's coordinates (its normal coordinate kept)."""
    a, b, _ = PLANE_AXES[m.plane]
    p = list(rec.end)
    for i, v in ((a, q[0]), (b, q[1])):
        p[i] = v * 2.0 if (rec.diameter and i == 0) else v
    return (p[0], p[1], p[2])


def _resolve(m, h: Hold, rec, line: int):
    """The held record h and the next one ``rec`` (of the block at ``line`` of the file running) meet
    at a corner: emit h cut back, the element and what waited; return ``rec`` cut back (it may be
    held in turn). Errors name the held block's own file and line (h.error), or the next block's."""
    if h.plane != m.plane:
        flush(m, "the plane changes before the next move")
        return rec
    if h.blocks - 1 > MAX_BETWEEN:
        flush(m, f"more than {MAX_BETWEEN} blocks without a move in the plane come before the next move")
        return rec
    e1, e2 = _plane_el(m, h.rec), _plane_el(m, rec)
    label = f"{h.kind}={h.value:g}"
    try:
        if turn(e1, e2) == 0.0:  # a tangent transition: no corner, no element
            got = None
        elif h.kind in ("RND", "RNDM") and (isinstance(rec, Rapid) or isinstance(h.rec, Rapid)):
            raise _rapid_rounding(m, h, line, label)
        elif h.kind in ("RND", "RNDM"):
            got = fillet(e1, e2, h.value)
        else:
            c = h.value if h.kind == "CHR" else chamfer_legs(e1, e2, h.value)
            got = chamfer(e1, e2, c) if c > 0 else None
    except CornerError as e:
        raise h.error(f"{label}: {e}") from None
    if got is None:  # a tangent transition: no corner
        flush(m)
        return rec
    p1, p2 = _point(m, h.rec, got[0]), _point(m, rec, got[1])
    first = replace(h.rec, end=p1, full_turn=False) if isinstance(h.rec, Arc) else replace(h.rec, end=p1)
    then = replace(rec, start=p2, full_turn=False) if isinstance(rec, Arc) else replace(rec, start=p2)
    feed = h.feed if h.feed is not None and not isinstance(rec, Rapid) else getattr(rec, "feed", 0.0)
    per_rev = getattr(rec, "per_rev", False)
    src = h.rec.src
    if len(got) == 2:
        insert = Rapid(src, p1, p2, rec.diameter) if isinstance(rec, Rapid) else \
            Feed(src, p1, p2, rec.diameter, feed, per_rev)
    else:
        insert = Arc(src, p1, p2, rec.diameter, _point(m, rec, got[2]), m.plane, not got[3], False, feed, per_rev)
    queue = m.corners.queue or []
    m.corners.hold, m.corners.queue = None, None
    for r in (first, insert, *queue):
        if r is insert or not _empty(r):
            m.emit(r)
    return then


def _rapid_rounding(m, h: Hold, line: int, label: str) -> CutsimError:
    """A real corner to be rounded next to a G0 move: the controller traverses the rounding at rapid
    (the manual: F, FRC, FRCM are not active then), but the canonical records have no rapid arc, so
    it is exit 2: RND= at its word; under RNDM at the G0 block (the held one, or the next one in the
    file it runs in), with the way out."""
    if h.kind != "RNDM":
        return h.error(f"{label}: a rounding next to a G0 move is not modelled (there is no rapid arc)")
    why = "would be rounded at rapid traverse, which is not modelled (there is no rapid arc); write RNDM=0"
    if isinstance(h.rec, Rapid):
        return h.error(f"{label}: the corner at the end of this G0 move {why} before this block to leave it sharp", 1)
    where = f"line {h.line}" + ("" if h.prog == m.unit_program else f" of {h.prog}")
    return m.error(line, 1, f"{label}: the corner at the start of this G0 move {why} in or before the block "
                            f"leading to it ({where}) to leave it sharp")


def _empty(rec) -> bool:
    return type(rec) in (Rapid, Feed, Arc) and math.dist(rec.start, rec.end) < 1e-9 and \
        not getattr(rec, "full_turn", False)
