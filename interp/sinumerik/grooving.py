"""The moves of Sinumerik's grooving and undercut cycles CYCLE93 (groove), CYCLE94 (undercut DIN 509
form E / F) and CYCLE96 (thread undercut DIN 76), planned as plain data: no interpreter state, no
records, no meshes.

A planner takes the cycle's parameters by their manual names, the active tool (``ToolEdge``) and
the move budget, and returns the moves in the cycle's terms: ("G0" | "G1", (x, z)),
("ARC", (x, z), (cx, cz), clockwise) with x a diameter (the cycles' SPD / DIATH are diameters),
z absolute, "clockwise" seen from +Y as G2 in G18. It starts and ends at the tool's position before
the call (``ToolEdge.start``). Errors are ``GrooveParamError`` naming the parameter.

Where Siemens' Cycles manual (chapter 4: "Grooving CYCLE93", "Undercut (form E and F) CYCLE94",
"Thread undercut CYCLE96") is silent the choices are written in docs/dialects/sinumerik-turning.md
("cutsim assumes"); the DIN 509 and DIN 76 dimension tables are cited there too.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.compensation import nose_shift
from .removalgeom import mapped, tip_path
from .threading import METRIC_PITCH

EPS = 1e-9
CHIP_BREAK = 1.0  # mm: CYCLE93 backs off this far after every IDEP infeed (manual: chip breaking)
DEFAULT_CLEARANCE = 1.0  # mm: _VRT 0 -> the cycles' positioning level this far off the contour
ANGLE_MAX = 89.999  # CYCLE93 ANG1, ANG2 (manual: 0 <= ANG < 89.999 degrees)

# DIN 509:2006-12, undercuts E and F, the size for a diameter (the standard's recommendation by
# diameter, as HEIDENHAIN's MANUALplus 620 manual, 9.2 "Undercut parameters", reproduces it):
# (diameter up to, r, t1, f, t2); the ramp to the cylinder 15 degrees, form F's face relief 8 degrees
DIN509 = ((1.6, 0.1, 0.1, 0.5, 0.1), (3.0, 0.2, 0.1, 1.0, 0.1), (10.0, 0.2, 0.2, 2.0, 0.1),
          (18.0, 0.6, 0.2, 2.0, 0.1), (80.0, 0.6, 0.3, 2.5, 0.2), (math.inf, 1.0, 0.4, 4.0, 0.3))
DIN509_RAMP, DIN509_FACE = 15.0, 8.0
# DIN 76-1 thread undercuts, forms A (external) and C (internal), normal length, by pitch (as
# HEIDENHAIN's MANUALplus 620 manual, 10.2 "Undercut parameters", reproduces them):
# pitch -> (external: diameter below d, length, radius; internal: diameter above D, length, radius);
# the flank on the thread's side 30 degrees (to the axis, as DIN 509's 15)
DIN76 = {0.5: (0.8, 1.75, 0.2, 0.3, 2.7, 0.2), 0.7: (1.1, 2.45, 0.4, 0.3, 3.8, 0.4),
         0.8: (1.3, 2.8, 0.4, 0.3, 4.2, 0.4), 1.0: (1.6, 3.5, 0.6, 0.5, 5.2, 0.6),
         1.25: (2.0, 4.4, 0.6, 0.5, 6.7, 0.6), 1.5: (2.3, 5.2, 0.8, 0.5, 7.8, 0.8),
         1.75: (2.6, 6.1, 1.0, 0.5, 9.1, 1.0), 2.0: (3.0, 7.0, 1.0, 0.5, 10.3, 1.0),
         2.5: (3.6, 8.7, 1.2, 0.5, 13.0, 1.2), 3.0: (4.4, 10.5, 1.6, 0.5, 15.2, 1.6),
         3.5: (5.0, 12.0, 1.6, 0.5, 17.7, 1.6), 4.0: (5.7, 14.0, 2.0, 0.5, 20.0, 2.0),
         4.5: (6.4, 16.0, 2.0, 0.5, 23.0, 2.0), 5.0: (7.0, 17.5, 2.5, 0.5, 26.0, 2.5),
         5.5: (7.7, 19.0, 3.2, 0.5, 28.0, 3.2)}
DIN76_FLANK = 30.0
# DIN 76-1 short thread undercuts, forms B (external) and D (internal), by pitch: the length from the
# face (g2 max); depth and radius as the normal form's of the pitch. Up to pitch 3.5 two published
# transcriptions of DIN 76-1 tables 1 and 2 agree; 4..5.5 from the one carrying them, whose normal rows
# agree with DIN76 above in every row (docs/dialects/sinumerik-turning.md "CYCLE96").
DIN76_SHORT = {0.5: (1.25, 2.0), 0.7: (1.75, 2.75), 0.8: (2.0, 3.0), 1.0: (2.5, 3.7), 1.25: (3.2, 4.9),
               1.5: (3.8, 5.6), 1.75: (4.3, 6.4), 2.0: (5.0, 7.3), 2.5: (6.3, 9.3), 3.0: (7.5, 10.7),
               3.5: (9.0, 12.7), 4.0: (10.0, 14.0), 4.5: (11.0, 16.0), 5.0: (12.5, 18.5),
               5.5: (14.0, 20.0)}


class GrooveParamError(ValueError):
    """A grooving cycle parameter out of its range; ``param`` is the parameter's manual name."""

    def __init__(self, param: str, message: str):
        super().__init__(message)
        self.param = param


@dataclass(frozen=True)
class ToolEdge:
    """What the cycles need of the active tool: ``width`` (a grooving tool's, else 0), ``edge`` the
    cutting edge position (1-9, 0 unknown), ``start`` the position before the call (x a diameter),
    ``face`` whether it is a face tool (it points to -Z, X and Z swapped: docs/setup.md)."""

    width: float
    edge: int
    start: tuple[float, float]
    face: bool = False
    nose: float = 0.0

    @classmethod
    def of(cls, m) -> "ToolEdge":
        t = getattr(m, "tool_no", None)
        width = m.cfg.tool_widths.get(t, 0.0) if t is not None else 0.0
        nose, edge = m.cfg.tool_noses.get(t, (0.0, 0)) if t is not None else (0.0, 0)
        if getattr(m, "d_no", 1) == 0:  # D0: no tool offsets, no nose
            nose = 0.0
        x = 2.0 * m.pos[0]  # the lathe mode keeps X as a radius
        return cls(width, edge, (x, m.pos[2]), t is not None and t in m.cfg.tool_faces, nose)

    def tip_shift(self) -> tuple[float, float]:
        """From the nose's centre to the theoretical tip (radius, z), as G41/G42 take it."""
        dz, dx = nose_shift(self.edge, self.nose, "ZX")
        return (dx, dz)

    @property
    def outside(self) -> bool | None:
        if self.face:  # pointing to -Z: a face groove's outside (into a face looking to +Z)
            return True
        return True if self.edge in (3, 4, 8) else False if self.edge in (1, 2, 6) else None

    @property
    def k(self) -> float:
        """Where the control point sits across the width from the tool's -Z side (a face tool's: -X
        side), 0 to 1: the corner towards -Z (-X) for hand R (edges 3, 2; a face tool's 3), towards
        +Z (+X) for hand L (4, 1; a face tool's 2), the middle else."""
        if self.face:
            return 0.0 if self.edge == 3 else 1.0 if self.edge == 2 else 0.5
        return 0.0 if self.edge in (2, 3) else 1.0 if self.edge in (1, 4) else 0.5


# ---------------------------------------------------------------------------------------------
# parameter helpers
def _num(v: dict, name: str) -> float:
    val = v.get(name, 0.0)
    if val is None:
        return 0.0
    if isinstance(val, str) or not math.isfinite(float(val)):
        raise GrooveParamError(name, f"{name} must be a number (got {val!r})")
    return float(val)


def _unsigned(v: dict, name: str, positive: bool = False) -> float:
    val = _num(v, name)
    if val < 0:
        raise GrooveParamError(name, f"{name} is written without a sign (got {val:g})")
    if positive and val <= EPS:
        raise GrooveParamError(name, f"{name} must be greater than 0")
    return val


def _budget(n: int, max_moves: int | None, what: str, param: str) -> None:
    if max_moves is not None and n > max_moves:
        raise GrooveParamError(param, f"the cycle would make about {n:,} moves ({what}), more than "
                                      f"[simulation] max_blocks = {max_moves:,}")


class _Path:
    """Moves planned in (q, p) = (radius, z), emitted as (diameter, z); with ``swap`` (a face groove)
    planned in (q, p) = (z, radius), the plunge axis Z."""

    def __init__(self, swap: bool = False):
        self.moves: list[tuple] = []
        self.swap = swap

    def _out(self, q, p):
        return (2.0 * p, q) if self.swap else (2.0 * q, p)

    def here(self) -> tuple[float, float]:
        """The last move's end in the planning frame (q, p)."""
        x, z = self.moves[-1][1]
        return (z, x / 2.0) if self.swap else (x / 2.0, z)

    def g0(self, r, z):
        self.moves.append(("G0", self._out(r, z)))

    def g1(self, r, z):
        self.moves.append(("G1", self._out(r, z)))

    def arc(self, r, z, cr, cz, start):
        """An arc from ``start`` (q, p) to (q, p) about (cq, cp), the shorter way."""
        (sx, sz), (ex, ez), (cx, cz2) = self._out(*start), self._out(r, z), self._out(cr, cz)
        a = (sz - cz2, sx - cx)  # (z, x): G18 seen from +Y, Z right and X up
        b = (ez - cz2, ex - cx)
        cw = a[0] * b[1] - a[1] * b[0] < 0
        self.moves.append(("ARC", (ex, ez), (cx, cz2), cw))


def _start(p: _Path, tool: ToolEdge) -> tuple[float, float]:
    """The position before the call in the planning frame (q, p)."""
    x, z = tool.start
    return (z, x / 2.0) if p.swap else (x / 2.0, z)


def _leave(p: _Path, tool: ToolEdge, outside: bool, clear_r: float) -> None:
    """From the clearance level back to the position before the call: outside along the plunge
    axis first (X; a face groove's Z), inside along the other."""
    sx, sz = _start(p, tool)
    if outside:
        p.g0(max(sx, clear_r), p_z(p))
        p.g0(max(sx, clear_r), sz)
        p.g0(sx, sz)
    else:
        p.g0(clear_r, sz)
        p.g0(sx, sz)


def p_z(p: _Path) -> float:
    return p.here()[1]


def _enter(p: _Path, tool: ToolEdge, outside: bool, clear_r: float, z: float) -> None:
    """From the position before the call to (clear_r, z): outside along the other axis first, inside
    along the plunge axis first."""
    sx, sz = _start(p, tool)
    if outside:
        p.g0(max(sx, clear_r), sz)
        p.g0(max(sx, clear_r), z)
    else:
        p.g0(clear_r, sz)
        p.g0(clear_r, z)
    p.g0(clear_r, z)


# ---------------------------------------------------------------------------------------------
# CYCLE93
@dataclass
class _Groove:
    """CYCLE93's checked parameters in the planning frame (q the plunge axis, p the other: radius
    and z, a face groove's z and radius): ``pts`` the contour's corners P0..P5 (q, p) from before
    edge 1 to after edge 2, ``s`` the direction the groove runs along p, ``d`` the depth's along q,
    ``q0`` the starting point's q, ``slope`` dq/dp of the contour line (tan STA1)."""

    face: bool
    outside: bool
    s: float
    d: float
    q0: float
    p1: float
    slope: float
    pts: list
    fal1: float
    fal2: float
    idep: float
    clear: float
    widg: float
    diag: float

    def surface(self, p: float) -> float:
        """The depth (along d from q0) of the contour line through the starting point at p."""
        return self.d * (p - self.p1) * self.slope


def _cycle93_vari(v: dict) -> tuple[bool, bool, float]:
    """(face, outside, s) from VARI's units digit: 1 longitudinal outside, 2 face outside, 3
    longitudinal inside, 4 face inside, 5..8 the same with the starting point on the right."""
    vari = _num(v, "VARI")
    if vari != int(vari) or int(vari) % 10 not in range(1, 9) or int(vari) // 10 not in (0, 1):
        raise GrooveParamError("VARI", f"VARI must be 1 to 8 or 11 to 18 (got {vari:g}): the machining type is "
                                       "defined incorrectly")
    units = int(vari) % 10
    return units % 2 == 0, units in (1, 2, 5, 6), 1.0 if units <= 4 else -1.0


def _cycle93_shape(v: dict) -> _Groove:
    spd = _unsigned(v, "SPD", positive=True)
    spl = _num(v, "SPL")
    widg = _unsigned(v, "WIDG", positive=True)
    diag = _unsigned(v, "DIAG", positive=True)
    face, outside, s = _cycle93_vari(v)
    sta = _num(v, "STA1")
    if not -EPS <= sta <= 180.0 + EPS:
        raise GrooveParamError("STA1", f"STA1 must be from 0 to 180 degrees (got {sta:g})")
    theta = sta if sta <= 90.0 else sta - 180.0  # the line's angle, -90 .. 90
    if abs(abs(theta) - 90.0) < 1e-6:
        other = "a longitudinal groove (VARI 1, 3, 5, 7)" if face else "a face groove (VARI 2, 4, 6, 8)"
        raise GrooveParamError("STA1", f"STA1 {sta:g}: the contour runs along the groove's plunge axis: program "
                                       f"{other}")
    tans = []
    for n in ("ANG1", "ANG2"):
        a = _unsigned(v, n)
        if a >= ANGLE_MAX:
            raise GrooveParamError(n, f"{n} must be from 0 to below {ANGLE_MAX:g} degrees (got {a:g})")
        tans.append(math.tan(math.radians(a)))
    fal1, fal2, idep = _unsigned(v, "FAL1"), _unsigned(v, "FAL2"), _unsigned(v, "IDEP")
    _unsigned(v, "DTB")
    if fal1 >= diag - EPS:
        raise GrooveParamError("FAL1", f"the finishing allowance FAL1 {fal1:g} leaves nothing of the groove depth "
                                       f"DIAG {diag:g}")
    d = -1.0 if outside else 1.0
    q0, p1 = (spl, spd / 2.0) if face else (spd / 2.0, spl)
    c, sn = math.cos(math.radians(theta)), math.sin(math.radians(theta))

    def at(u, w):  # u along the contour line in the groove's direction, w the depth across it
        return (q0 + u * s * sn + w * d * c, p1 + u * s * c - w * d * sn)

    clear = _unsigned(v, "_VRT") or DEFAULT_CLEARANCE
    u2 = diag * tans[0]
    u4 = u2 + widg + diag * tans[1]
    pts = [at(-(clear + abs(_num(v, "RCO1")) * 2), 0.0), at(0.0, 0.0), at(u2, diag), at(u2 + widg, diag),
           at(u4, 0.0), at(u4 + clear + abs(_num(v, "RCO2")) * 2, 0.0)]
    for i, j, n in ((1, 2, "ANG1"), (3, 4, "ANG2")):  # the paraxial plunges cannot reach under a flank
        if s * (pts[j][1] - pts[i][1]) < -1e-9:
            raise GrooveParamError(n, f"flank {n[-1]} leans over the groove at STA1 {sta:g}: the cycle's paraxial "
                                      f"plunges cannot cut under it ({n} must be at least {abs(theta):g} degrees)")
    if any(pt[1 if face else 0] < -EPS for pt in pts[1:5]):
        raise GrooveParamError("WIDG" if face else "DIAG", "the groove reaches beyond the turning axis")
    return _Groove(face, outside, s, d, q0, p1, sn / c, pts, fal1, fal2, idep, clear, widg, diag)


def _corner(prev, here, nxt, value: float, chf: bool, name: str):
    """A rounding (value > 0, radius) or chamfer (value < 0; CHF: its length, else CHR: its legs)
    at ``here`` between the lines from ``prev`` and to ``nxt`` (points (q, p)): (A, B, element
    from A to B or None) with A on the incoming line, B on the outgoing one."""
    if abs(value) <= EPS:
        return here, here, None
    a = (prev[0] - here[0], prev[1] - here[1])
    b = (nxt[0] - here[0], nxt[1] - here[1])
    la, lb = math.hypot(*a), math.hypot(*b)
    a, b = (a[0] / la, a[1] / la), (b[0] / lb, b[1] / lb)
    theta = math.acos(max(-1.0, min(1.0, a[0] * b[0] + a[1] * b[1])))
    if value > 0:
        t = value / math.tan(theta / 2)
    else:
        t = -value / (2 * math.sin(theta / 2)) if chf else -value
    if t > min(la, lb) / 2.0 + EPS:  # each flank and the base are shared by two corners
        raise GrooveParamError(name, f"{name} {value:g} does not fit on the groove's edges")
    A = (here[0] + a[0] * t, here[1] + a[1] * t)
    B = (here[0] + b[0] * t, here[1] + b[1] * t)
    if value < 0:
        return A, B, ("L", A, B)
    bis = (a[0] + b[0], a[1] + b[1])
    lbis = math.hypot(*bis)
    dist = value / math.sin(theta / 2)
    c = (here[0] + bis[0] / lbis * dist, here[1] + bis[1] / lbis * dist)
    return A, B, ("A", A, B, c)


def _groove_contour(v, pts):
    """The groove's finished contour in (q, p) from the surface before edge 1 to the surface after
    edge 2, its four corners rounded or chamfered (RCO1 edge 1, RCI1 base 1, RCI2 base 2, RCO2
    edge 2): the elements ("L", a, b) / ("A", a, b, centre) and the corners (A, B, element)."""
    chf = int(_num(v, "VARI")) // 10 == 0
    corners = [_corner(pts[i - 1], pts[i], pts[i + 1], _num(v, n), chf, n)
               for i, n in zip(range(1, 5), ("RCO1", "RCI1", "RCI2", "RCO2"))]
    elems = []
    for i, (A, B, el) in enumerate(corners):
        start = pts[0] if i == 0 else corners[i - 1][1]
        if math.hypot(A[0] - start[0], A[1] - start[1]) > EPS:
            elems.append(("L", start, A))
        if el is not None:
            elems.append(el)
    elems.append(("L", corners[3][1], pts[5]))
    return elems, corners


def _q_at(e, z: float) -> list[float]:
    """Where the element crosses the line p = z (its q values; both ends of a line along q)."""
    p, q = e[1], e[2]
    if e[0] == "L":
        return [p[0], q[0]] if abs(q[1] - p[1]) < EPS else [p[0] + (q[0] - p[0]) * (z - p[1]) / (q[1] - p[1])]
    c = e[3]
    rad = math.hypot(p[0] - c[0], p[1] - c[1])
    h = math.sqrt(max(rad * rad - (z - c[1]) ** 2, 0.0))
    return [rr for rr in (c[0] + h, c[0] - h) if _on(e, (rr, z), 1e-6)]


def _depth_at(elems, z: float, r0: float, d: float) -> float | None:
    """The contour's depth (along d, from r0) at p = z: the shallowest of the elements there."""
    best = None
    for e in elems:
        lo, hi = min(e[1][1], e[2][1]), max(e[1][1], e[2][1])
        if lo - EPS <= z <= hi + EPS:
            for rr in _q_at(e, z):
                dep = d * (rr - r0)
                best = dep if best is None else min(best, dep)
    return best


def _check_tool(g: _Groove, tool: ToolEdge, vari: float) -> float:
    """The grooving tool's width, after checking it fits the groove's kind and side."""
    w = tool.width
    if w <= EPS:
        raise GrooveParamError("VARI", "the active tool is no grooving tool: CYCLE93 plunges with a grooving "
                                       "tool's width (select one the setup describes, T.. D..)")
    if g.face and not g.outside:
        raise GrooveParamError("VARI", f"VARI {vari:g}: a face groove inside (plunged towards +Z, into a face "
                                       "looking to -Z) needs a tool pointing to +Z; a setup's face tool points to -Z")
    if g.face != tool.face:
        what = 'is no face tool (side = "face")' if g.face else "a face tool"
        raise GrooveParamError("VARI", f"VARI {vari:g} is a {'face' if g.face else 'longitudinal'} groove, the active "
                                       f"grooving tool {what}")
    if tool.outside is not None and tool.outside != g.outside:
        raise GrooveParamError("VARI", f"VARI asks for an {'outside' if g.outside else 'inside'} groove, the active "
                                       f"grooving tool works {'outside' if tool.outside else 'inside'}")
    if g.widg - 2.0 * g.fal2 < w - EPS:
        raise GrooveParamError("WIDG", f"the groove's base WIDG {g.widg:g} less the allowances FAL2 is narrower "
                                       f"than the grooving tool ({w:g} wide)")
    return w


def plan_cycle93(v: dict, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """Grooving: plunges along the plunge axis (X; a face groove's Z) across the groove, each in
    IDEP steps (backing off CHIP_BREAK after each) from the contour line down to the contour less
    FAL1 below and FAL2 beside; then the finishing cut down side 1 with the tool's starting-side
    corner and down side 2 with the other corner. The tool is a grooving tool of the cycle's side."""
    g = _cycle93_shape(v)
    w = _check_tool(g, tool, _num(v, "VARI"))
    elems, corners = _groove_contour(v, g.pts)
    lo_z, hi_z = sorted((g.pts[1][1], g.pts[4][1]))
    k, d, q0 = tool.k, g.d, g.q0

    def allowed(z):  # the roughing's depth at z: FAL2 beside, FAL1 below the contour (the window
        h = max(g.fal2 - 1e-6, 0.0)  # open: a wall along the plunge axis at its edge does not count)
        return min(_depth_at(elems, zz, q0, d) or 0.0 for zz in (z - h, z, z + h)) - g.fal1

    span_lo, span_hi = lo_z + g.fal2, hi_z - g.fal2
    n = max(1, math.ceil((span_hi - span_lo - w) / w - 1e-9) + 1)
    top0 = min(g.surface(lo_z), g.surface(hi_z))
    deepest = max(d * (pt[0] - q0) for pt in g.pts[2:4])
    steps = max(1, math.ceil((deepest - top0 - g.fal1) / g.idep - 1e-9)) if g.idep > EPS else 1
    _budget(n * (2 * steps + 3) + 24, max_moves, f"{n} plunges of {steps} infeeds (IDEP {g.idep:g})", "IDEP")
    p = _Path(g.face)
    clear_r = q0 + d * (top0 - g.clear)
    starts = [span_lo + (span_hi - span_lo - w) * j / (n - 1) if n > 1 else span_lo for j in range(n)]
    if g.s < 0:
        starts.reverse()  # from the starting point's side across
    _enter(p, tool, g.outside, clear_r, starts[0] + k * w)
    crit = sorted({e[i][1] for e in elems for i in (1, 2)} | {e[3][1] for e in elems if e[0] == "A"})
    for zl in starts:  # the shallowest point under the tool: at its ends or a corner / arc top between
        dep = min(allowed(z) for z in [zl + 1e-6, zl + w - 1e-6] + [z for z in crit if zl < z < zl + w])
        top = min(g.surface(zl), g.surface(zl + w))  # the contour line's shallowest point under the tool
        c = zl + k * w
        p.g0(clear_r, c)
        if dep <= top + EPS:
            continue
        p.g0(q0 + d * (top - min(g.clear, CHIP_BREAK)), c)
        m = max(1, math.ceil((dep - top) / g.idep - 1e-9)) if g.idep > EPS else 1
        for i in range(1, m + 1):
            reach = q0 + d * (top + (dep - top) * i / m)
            p.g1(reach, c)
            if i < m:
                p.g0(reach - d * CHIP_BREAK, c)
                p.g0(reach, c)
        p.g0(clear_r, c)
    _finish93(p, g, elems, corners, w, k, clear_r)
    _leave(p, tool, g.outside, clear_r)
    return p.moves


def _crossover(elems, g: _Groove, first, last, w: float):
    """Where the finishing hands over from the starting-side corner to the other: the points x1 (the
    starting-side corner) and x2 = x1 + s w along p at the same depth, both on the contour (the base
    of an inclined groove is cut by the corner on its shallow side: a flat edge stays off it)."""
    depth = lambda z: _depth_at(elems, z, g.q0, g.d)  # noqa: E731
    crit = [e[3][1] for e in elems if e[0] == "A"] + [e[i][1] for e in elems for i in (1, 2)]

    def beyond(x):  # the shallowest point under the tool's width past its starting-side corner
        lo, hi = sorted((x, x + g.s * w))
        return min(depth(z) for z in [x + g.s * w] + [z for z in crit if lo < z < hi])

    a, b = first[1], last[1] - g.s * w
    for _ in range(80):  # depth(x) - beyond(x) rises from < 0 at edge 1 to > 0 at edge 2
        mid = (a + b) / 2.0
        if depth(mid) < beyond(mid):
            a = mid
        else:
            b = mid
    x = (a + b) / 2.0
    if abs(depth(x) - depth(x + g.s * w)) > 1e-6:
        raise GrooveParamError("STA1", "on this inclined contour no position of the grooving tool's flat edge "
                                       "touches the groove with both corners between its edges: the paraxial "
                                       "finishing cut cannot follow it (a flatter STA1 or a deeper groove)")
    q = g.q0 + g.d * depth(x)
    return (q, x), (q, x + g.s * w)


def _finish93(p: _Path, g: _Groove, elems, corners, w: float, k: float, clear_r: float) -> None:
    """Side 1 with the tool's starting-side corner from edge 1 until the other corner touches the
    contour too (a flat base: its end, the start of RCI2); side 2 with the other corner from edge 2
    back down to that point. On an inclined contour an edge's rounding or chamfer can rise from the
    line before it falls into the groove: each side then starts at its shallowest point, and the
    stretch from there out to the line is traced by the other corner (the one the tool's width
    does not reach over the rise from)."""
    s = g.s
    near = k * w if s > 0 else -(1.0 - k) * w
    far = -(1.0 - k) * w if s > 0 else k * w
    first, last = corners[0][0], corners[3][1]  # where the cuts enter: A of RCO1, B of RCO2
    if abs(g.slope) <= EPS:
        x2 = corners[2][0]  # the base's end on side 2 (A of RCI2)
        x1 = (x2[0], x2[1] - s * w)
        if s * (x1[1] - corners[1][1][1]) < 0:  # a base shorter than the tool: side 1 stops at its start
            x1 = corners[1][1]
    else:
        x1, x2 = _crossover(elems, g, first, last, w)
    side1 = [e for e in _cut(elems, x1)[0] if s * e[1][1] >= s * first[1] - EPS]
    back = [_reverse(e) for e in reversed(_cut(elems, x2)[1])]
    side2 = [e for e in back if s * e[1][1] <= s * last[1] + EPS]
    for path, off, other in ((side1, near, far), (side2, far, near)):
        outer, inner = _split_top(path, g)
        top = inner[0][1] if inner else path[-1][2]
        _pass(p, top, inner, off, clear_r)
        if outer:  # from the shallowest point back out to the line, with the other corner
            _pass(p, top, [_reverse(e) for e in reversed(outer)], other, clear_r)


def _pass(p: _Path, start, path, off: float, clear_r: float) -> None:
    """G0 over ``start`` (the control point ``off`` along p from it), G1 down to it, along ``path``, G0 up."""
    p.g0(clear_r, start[1] + off)
    p.g1(start[0], start[1] + off)
    _run(p, path, off)
    p.g0(clear_r, p_z(p))


def _split_top(path, g: _Groove):
    """``path`` (from an edge inwards) split at its shallowest point before it turns into the groove:
    (the elements up to it, those from it). Only a rounding or chamfer on an inclined contour puts it
    past the path's start; on a flat one nothing is split off."""
    depth = lambda pt: g.d * (pt[0] - g.q0)  # noqa: E731
    best, at = depth(path[0][1]) if path else 0.0, None
    for i, e in enumerate(path[:3]):  # the line's piece and the edge's rounding or chamfer
        cands = [e[2]]
        if e[0] == "A":  # the arc's point whose tangent runs along p (its extreme towards the air)
            rad = math.dist(e[1], e[3])
            cands.append((e[3][0] - g.d * rad, e[3][1]))
        for c in cands:
            if (e[0] == "L" or _on(e, c)) and depth(c) < best - 1e-9:
                best, at = depth(c), (i, c)
    if at is None:
        return [], path
    head, tail = _cut(path, at[1])
    return head, tail


def _on(e, pt, tol: float = 1e-7) -> bool:
    a, b = e[1], e[2]
    if e[0] == "L":
        ab, ap = (b[0] - a[0], b[1] - a[1]), (pt[0] - a[0], pt[1] - a[1])
        ll = ab[0] ** 2 + ab[1] ** 2
        t = (ab[0] * ap[0] + ab[1] * ap[1]) / ll if ll > 0 else 0.0
        return -1e-9 <= t <= 1 + 1e-9 and abs(ab[0] * ap[1] - ab[1] * ap[0]) <= 1e-7 * math.sqrt(ll)
    c = e[3]
    u, v, x = (a[0] - c[0], a[1] - c[1]), (b[0] - c[0], b[1] - c[1]), (pt[0] - c[0], pt[1] - c[1])
    if abs(math.hypot(*x) - math.hypot(*u)) > tol:
        return False
    cr = lambda m, n: m[0] * n[1] - m[1] * n[0]  # noqa: E731
    turn = cr(u, v)
    return cr(u, x) * turn >= -1e-12 and cr(x, v) * turn >= -1e-12


def _cut(elems, pt):
    """The elements up to ``pt`` and from it, the one it lies on split there."""
    for i, e in enumerate(elems):
        if _on(e, pt):
            head = elems[:i] + ([(e[0], e[1], pt) + e[3:]] if math.dist(e[1], pt) > EPS else [])
            tail = ([(e[0], pt, e[2]) + e[3:]] if math.dist(pt, e[2]) > EPS else []) + elems[i + 1:]
            return head, tail
    raise AssertionError(f"the point {pt} is not on the groove's contour")


def _reverse(e):
    return (e[0], e[2], e[1]) + e[3:]


def _run(p: _Path, elems, off: float) -> None:
    """The elements with the tool's control point ``off`` along p from the contour."""
    for e in elems:
        q = e[2]
        if e[0] == "L":
            p.g1(q[0], q[1] + off)
        else:
            p.arc(q[0], q[1] + off, e[3][0], e[3][1] + off, p.here())


# ---------------------------------------------------------------------------------------------
# CYCLE94 and CYCLE96: one finishing pass along the undercut's contour
def _side(v: dict, name: str, tool: ToolEdge) -> tuple[bool, float]:
    """(outside, s): where the undercut lies from _VARI 1..4 (a cutting edge position) or, with
    _VARI 0, from the active tool's; s = +1 when the cylinder runs from the face towards +Z."""
    vari = _num(v, name)
    if vari != int(vari) or not 0 <= vari <= 4:
        raise GrooveParamError(name, f"{name} must be 0 (the tool's cutting edge position) or a position 1 to 4 "
                                     f"(got {vari:g})")
    edge = int(vari) or tool.edge
    if edge not in (1, 2, 3, 4):
        raise GrooveParamError(name, f"{name} 0 takes the position from the tool's cutting edge, and the active "
                                     "tool has none of 1 to 4 (a turning tool of hand R or L): give the position")
    return edge in (3, 4), 1.0 if edge in (2, 3) else -1.0


def _undercut(p: _Path, tool: ToolEdge, outside: bool, s: float, R: float, face: float, t1: float, f: float,
              r: float, ramp_deg: float, t2: float, clear: float, size: str) -> None:
    """From the cylinder (radius R) f away from the face (at z ``face``), down the ramp to the floor
    at depth t1, along it and round the fillet r (tangent to the floor and to the face, or to the face
    moved t2 into the shoulder, whose relief then returns to the face at DIN509_FACE degrees), out.
    With a nose radius the theoretical tip runs where the nose stays tangent to that contour
    (removalgeom.tip_path); a fillet narrower than the nose is refused at ``size``."""
    d = -1.0 if outside else 1.0
    rf = R + d * t1
    run = t1 / math.tan(math.radians(ramp_deg))
    wall = face - s * t2
    clear_r = R - d * clear
    top = rf - d * r
    con = [("L", (R, face + s * f), (rf, face + s * (f - run))), ("L", (rf, face + s * (f - run)), (rf, wall + s * r)),
           ("A", (rf, wall + s * r), (top, wall), (top, wall + s * r), (s > 0) == outside)]
    if t2 > EPS:
        con.append(("L", (top, wall), (top - d * t2 / math.tan(math.radians(DIN509_FACE)), face)))
    up = clear_r - tool.tip_shift()[0]  # the face so far that the tip reaches the clearance level
    if (con[-1][2][0] - up) * d > 0:  # up the face to the clearance level
        con.append(("L", con[-1][2], (up, face)))
    if tool.nose > EPS:  # in the frame (a, b) = (-d radius, s z): out of the part, running towards -b
        m = lambda pt: (-d * pt[0], s * pt[1])  # noqa: E731  (its own inverse)
        flip = (d > 0) != (s < 0)
        lead = [("L", (R, face + s * (f + tool.nose)), con[0][1])]  # the cylinder before: the tip enters on it
        try:
            path = tip_path(mapped(lead + con, m, flip), 0.0, 0.0, 0.0, tool.nose, m(tool.tip_shift()), blank=False)
        except ValueError:
            raise GrooveParamError(size, f"the undercut's radius {r:g} is smaller than the tool's nose radius "
                                         f"{tool.nose:g}: the nose cannot follow it") from None
        con = mapped(path, m, flip)
    _enter(p, tool, outside, clear_r, con[0][1][1])
    p.g1(*con[0][1])
    for e in con:
        if e[0] == "L":
            p.g1(*e[2])
        else:
            p.arc(*e[2], *e[3], p.here())
    _leave(p, tool, outside, clear_r if (con[-1][2][0] - clear_r) * d > 0 else con[-1][2][0])


def plan_cycle94(v: dict, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """Undercut DIN 509 form E or F at the corner of the cylinder SPD and the face SPL, its size
    from the diameter (DIN509), in one pass."""
    spd = _unsigned(v, "SPD", positive=True)
    form = str(v.get("FORM", "")).strip().upper()
    if form not in ("E", "F"):
        raise GrooveParamError("FORM", f"FORM must be \"E\" or \"F\" (got \"{v.get('FORM', '')}\")")
    outside, s = _side(v, "_VARI", tool)
    _, r, t1, f, t2 = next(row for row in DIN509 if spd <= row[0] + EPS)
    if outside and spd / 2.0 - t1 <= EPS:
        raise GrooveParamError("SPD", f"the undercut's depth {t1:g} reaches the turning axis (SPD {spd:g})")
    p = _Path()
    _undercut(p, tool, outside, s, spd / 2.0, _num(v, "SPL"), t1, f, r, DIN509_RAMP,
              t2 if form == "F" else 0.0, _unsigned(v, "_VRT") or DEFAULT_CLEARANCE, "SPD")
    return p.moves


def plan_cycle96(v: dict, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """Thread undercut DIN 76 form A / B (outside, normal / short) or C / D (inside, normal / short)
    for the metric coarse thread DIATH (M3..M60: its pitch from ISO 261), at the face SPL, in one pass. A short form is the normal one of its pitch, shorter."""
    diath = _unsigned(v, "DIATH", positive=True)
    form = str(v.get("FORM", "")).strip().upper()
    if form not in ("A", "B", "C", "D"):
        raise GrooveParamError("FORM", f"FORM must be \"A\", \"B\", \"C\" or \"D\" (got \"{v.get('FORM', '')}\")")
    if diath != int(diath) or int(diath) not in METRIC_PITCH:
        sizes = ", ".join(str(k) for k in METRIC_PITCH)
        raise GrooveParamError("DIATH", f"DIATH must be a metric coarse thread size ({sizes}), got {diath:g}")
    pitch = METRIC_PITCH[int(diath)]
    row = DIN76[pitch]
    outside, s = _side(v, "_VARI", tool)
    if outside != (form in ("A", "B")):
        raise GrooveParamError("FORM", f"FORM \"{form}\" is an {'outside' if form in ('A', 'B') else 'inside'} "
                                       f"undercut, the position (_VARI or the tool) an "
                                       f"{'outside' if outside else 'inside'} one")
    dd, length, r = row[0:3] if outside else row[3:6]
    if form in ("B", "D"):
        length = DIN76_SHORT[pitch][0 if outside else 1]
    if outside:
        R, t1 = diath / 2.0, dd / 2.0
    else:  # the bore is the thread's minor diameter D1 = D - 1.0825 P; the undercut D + dd
        R = (diath - 1.082532 * pitch) / 2.0
        t1 = (diath + dd) / 2.0 - R
    p = _Path()
    _undercut(p, tool, outside, s, R, _num(v, "SPL"), t1, length, r, DIN76_FLANK, 0.0,
              _unsigned(v, "_VRT") or DEFAULT_CLEARANCE, "DIATH")
    return p.moves
