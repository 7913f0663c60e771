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


class GrooveParamError(ValueError):
    """A grooving cycle parameter out of its range; ``param`` is the parameter's manual name."""

    def __init__(self, param: str, message: str):
        super().__init__(message)
        self.param = param


@dataclass(frozen=True)
class ToolEdge:
    """What the cycles need of the active tool: ``width`` (a grooving tool's, else 0), ``edge`` the
    cutting edge position (1-9, 0 unknown), ``start`` the position before the call (x a diameter)."""

    width: float
    edge: int
    start: tuple[float, float]

    @classmethod
    def of(cls, m) -> "ToolEdge":
        t = getattr(m, "tool_no", None)
        width = m.cfg.tool_widths.get(t, 0.0) if t is not None else 0.0
        edge = m.cfg.tool_noses.get(t, (0.0, 0))[1] if t is not None else 0
        x = 2.0 * m.pos[0]  # the lathe mode keeps X as a radius
        return cls(width, edge, (x, m.pos[2]))

    @property
    def outside(self) -> bool | None:
        return True if self.edge in (3, 4, 8) else False if self.edge in (1, 2, 6) else None

    @property
    def k(self) -> float:
        """Where the control point sits across the width from the tool's -Z side (0 to 1): the
        corner towards -Z for hand R (edges 3, 2), towards +Z for hand L (4, 1), the middle else."""
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
    """Moves in (radius, z), emitted as (diameter, z)."""

    def __init__(self):
        self.moves: list[tuple] = []

    def g0(self, r, z):
        self.moves.append(("G0", (2.0 * r, z)))

    def g1(self, r, z):
        self.moves.append(("G1", (2.0 * r, z)))

    def arc(self, r, z, cr, cz, start):
        """An arc from ``start`` (r, z) to (r, z) about (cr, cz), the shorter way."""
        a = (start[1] - cz, start[0] - cr)  # (z, x): G18 seen from +Y, Z right and X up
        b = (z - cz, r - cr)
        cw = a[0] * b[1] - a[1] * b[0] < 0
        self.moves.append(("ARC", (2.0 * r, z), (2.0 * cr, cz), cw))


def _leave(p: _Path, tool: ToolEdge, outside: bool, clear_r: float) -> None:
    """From the clearance level back to the position before the call: outside X first, inside Z."""
    sx, sz = tool.start[0] / 2.0, tool.start[1]
    if outside:
        p.g0(max(sx, clear_r), p_z(p))
        p.g0(max(sx, clear_r), sz)
        p.g0(sx, sz)
    else:
        p.g0(clear_r, sz)
        p.g0(sx, sz)


def p_z(p: _Path) -> float:
    return p.moves[-1][1][1]


def _enter(p: _Path, tool: ToolEdge, outside: bool, clear_r: float, z: float) -> None:
    """From the position before the call to (clear_r, z): outside Z first, inside X first."""
    sx, sz = tool.start[0] / 2.0, tool.start[1]
    if outside:
        p.g0(max(sx, clear_r), sz)
        p.g0(max(sx, clear_r), z)
    else:
        p.g0(clear_r, sz)
        p.g0(clear_r, z)
    p.g0(clear_r, z)


# ---------------------------------------------------------------------------------------------
# CYCLE93
def _cycle93_shape(v: dict):
    """The checked parameters: (outside, s, R0, Rb, z1, zb1, zb2, z2, fal1, fal2, idep, clear)."""
    spd = _unsigned(v, "SPD", positive=True)
    spl = _num(v, "SPL")
    widg = _unsigned(v, "WIDG", positive=True)
    diag = _unsigned(v, "DIAG", positive=True)
    if abs(_num(v, "STA1")) > EPS:
        raise GrooveParamError("STA1", "STA1: a groove on an inclined contour is not simulated yet; a groove on a "
                                       "cylinder is STA1 0")
    angs = []
    for n in ("ANG1", "ANG2"):
        a = _unsigned(v, n)
        if a >= ANGLE_MAX:
            raise GrooveParamError(n, f"{n} must be from 0 to below {ANGLE_MAX:g} degrees (got {a:g})")
        angs.append(math.tan(math.radians(a)))
    fal1, fal2, idep = _unsigned(v, "FAL1"), _unsigned(v, "FAL2"), _unsigned(v, "IDEP")
    _unsigned(v, "DTB")
    vari = _num(v, "VARI")
    if vari != int(vari) or int(vari) % 10 not in range(1, 9) or int(vari) // 10 not in (0, 1):
        raise GrooveParamError("VARI", f"VARI must be 1 to 8 or 11 to 18 (got {vari:g}): the machining type is "
                                       "defined incorrectly")
    units = int(vari) % 10
    if units % 2 == 0:
        raise GrooveParamError("VARI", f"VARI {vari:g}: face grooves (VARI 2, 4, 6, 8) are not simulated yet; a "
                                       "longitudinal groove is VARI 1, 3, 5 or 7")
    outside = units in (1, 5)
    s = 1.0 if units <= 4 else -1.0  # starting point left: the groove runs to +Z; right: to -Z
    if fal1 >= diag - EPS:
        raise GrooveParamError("FAL1", f"the finishing allowance FAL1 {fal1:g} leaves nothing of the groove depth "
                                       f"DIAG {diag:g}")
    r0 = spd / 2.0
    d = -1.0 if outside else 1.0
    rb = r0 + d * diag
    if rb < -EPS:
        raise GrooveParamError("DIAG", f"the groove depth DIAG {diag:g} reaches beyond the turning axis")
    zb1 = spl + s * diag * angs[0]
    zb2 = zb1 + s * widg
    z2 = zb2 + s * diag * angs[1]
    clear = _unsigned(v, "_VRT") or DEFAULT_CLEARANCE
    return outside, s, d, r0, rb, spl, zb1, zb2, z2, fal1, fal2, idep, clear, angs, widg, diag


def _corner(prev, here, nxt, value: float, chf: bool, name: str):
    """A rounding (value > 0, radius) or chamfer (value < 0; CHF: its length, else CHR: its legs)
    at ``here`` between the lines from ``prev`` and to ``nxt`` (points (r, z)): (A, B, element
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
    u, w = (A[1] - c[1], A[0] - c[0]), (B[1] - c[1], B[0] - c[0])  # (z, x): G18 seen from +Y
    return A, B, ("A", A, B, c, u[0] * w[1] - u[1] * w[0] < 0)


def _groove_contour(v, s, d, r0, rb, z1, zb1, zb2, z2, clear):
    """The groove's finished contour in (r, z) from the surface before edge 1 to the surface after
    edge 2, its four corners rounded or chamfered (RCO1 edge 1, RCI1 base 1, RCI2 base 2, RCO2
    edge 2): the elements of side 1 (to the end of the base) and of side 2 (reversed)."""
    chf = int(_num(v, "VARI")) // 10 == 0
    pts = [(r0, z1 - s * (clear + abs(_num(v, "RCO1")) * 2)), (r0, z1), (rb, zb1), (rb, zb2), (r0, z2),
           (r0, z2 + s * (clear + abs(_num(v, "RCO2")) * 2))]
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


def _depth_at(elems, z: float, r0: float, d: float) -> float:
    """The contour's depth (along d, from r0) at z: the shallowest of the elements there."""
    best = None
    for e in elems:
        p, q = e[1], e[2]
        lo, hi = min(p[1], q[1]), max(p[1], q[1])
        if not lo - EPS <= z <= hi + EPS:
            continue
        if e[0] == "L":
            rs = [p[0], q[0]] if abs(q[1] - p[1]) < EPS else [p[0] + (q[0] - p[0]) * (z - p[1]) / (q[1] - p[1])]
        else:
            c = e[3]
            rad = math.hypot(p[0] - c[0], p[1] - c[1])
            h = math.sqrt(max(rad * rad - (z - c[1]) ** 2, 0.0))
            rs = [rr for rr in (c[0] + h, c[0] - h) if min(p[0], q[0]) - EPS <= rr <= max(p[0], q[0]) + EPS]
        for rr in rs:
            dep = d * (rr - r0)
            best = dep if best is None else min(best, dep)
    return 0.0 if best is None else max(best, 0.0)


def plan_cycle93(v: dict, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """Grooving: plunges across the groove, each in IDEP steps (backing off CHIP_BREAK after each),
    to the contour less FAL1 below and FAL2 beside; then the finishing cut down side 1 (edge,
    flank, base) with the tool's starting-side corner and down side 2 with the other corner. The
    tool is a grooving tool of the cycle's side."""
    (outside, s, d, r0, rb, z1, zb1, zb2, z2, fal1, fal2, idep, clear, tans, widg,
     diag) = _cycle93_shape(v)
    w = tool.width
    if w <= EPS:
        raise GrooveParamError("VARI", "the active tool is no grooving tool: CYCLE93 plunges with a grooving "
                                       "tool's width (select one the setup describes, T.. D..)")
    if tool.outside is not None and tool.outside != outside:
        raise GrooveParamError("VARI", f"VARI asks for an {'outside' if outside else 'inside'} groove, the active "
                                       f"grooving tool works {'outside' if tool.outside else 'inside'}")
    if widg - 2.0 * fal2 < w - EPS:
        raise GrooveParamError("WIDG", f"the groove's base WIDG {widg:g} less the allowances FAL2 is narrower "
                                       f"than the grooving tool ({w:g} wide)")
    elems, corners = _groove_contour(v, s, d, r0, rb, z1, zb1, zb2, z2, clear)
    lo_z, hi_z = sorted((z1, z2))
    k = tool.k

    def allowed(z):  # the roughing's depth at z: FAL2 beside, FAL1 below the contour (the window
        h = max(fal2 - 1e-6, 0.0)  # open: a vertical wall at its edge does not count)
        return max(min(_depth_at(elems, zz, r0, d) for zz in (z - h, z, z + h)) - fal1, 0.0)

    span_lo, span_hi = lo_z + fal2, hi_z - fal2
    n = max(1, math.ceil((span_hi - span_lo - w) / w - 1e-9) + 1)
    steps = max(1, math.ceil((diag - fal1) / idep - 1e-9)) if idep > EPS else 1
    _budget(n * (2 * steps + 3) + 24, max_moves, f"{n} plunges of {steps} infeeds (IDEP {idep:g})", "IDEP")
    p = _Path()
    clear_r = r0 - d * clear
    starts = [span_lo + (span_hi - span_lo - w) * j / (n - 1) if n > 1 else span_lo for j in range(n)]
    if s < 0:
        starts.reverse()  # from the starting point's side across
    _enter(p, tool, outside, clear_r, starts[0] + k * w)
    for zl in starts:
        dep = min(allowed(zl + 1e-6), allowed(zl + w - 1e-6))
        c = zl + k * w
        p.g0(clear_r, c)
        if dep <= EPS:
            continue
        p.g0(r0 - d * min(clear, CHIP_BREAK), c)
        m = max(1, math.ceil(dep / idep - 1e-9)) if idep > EPS else 1
        for i in range(1, m + 1):
            reach = r0 + d * dep * i / m
            p.g1(reach, c)
            if i < m:
                p.g0(reach - d * CHIP_BREAK, c)
                p.g0(reach, c)
        p.g0(clear_r, c)
    _finish93(p, elems, corners, s, w, k, clear_r)
    _leave(p, tool, outside, clear_r)
    return p.moves


def _finish93(p: _Path, elems, corners, s: float, w: float, k: float, clear_r: float) -> None:
    """Side 1 with the tool's starting-side corner from edge 1 along the base until its other corner
    reaches the base's end (the start of RCI2); side 2 with the other corner from edge 2 back down to
    that end."""
    near = k * w if s > 0 else -(1.0 - k) * w
    far = -(1.0 - k) * w if s > 0 else k * w
    base_end = corners[2][0]  # the base's end on side 2 (A of RCI2)
    stop = base_end[1] - s * w  # the near corner's z when the far corner reaches it
    side1 = _upto(elems, base_end)
    first = corners[0][0]  # the edge 1 point where the cut enters (A of RCO1)
    p.g0(clear_r, first[1] + near)
    p.g1(first[0], first[1] + near)
    _run(p, [e for e in side1 if s * e[1][1] >= s * first[1] - EPS], near, base_end, stop)
    p.g0(clear_r, p.moves[-1][1][1])
    last = corners[3][1]  # the edge 2 point (B of RCO2)
    p.g0(clear_r, last[1] + far)
    p.g1(last[0], last[1] + far)
    back = [_reverse(e) for e in reversed(_from(elems, base_end))]
    back = [e for e in back if s * e[1][1] <= s * last[1] + EPS]
    _run(p, back, far, None, None)
    p.g0(clear_r, p.moves[-1][1][1])


def _upto(elems, point):
    out = []
    for e in elems:
        out.append(e)
        if e[2] == point:
            break
    return out


def _from(elems, point):
    for i, e in enumerate(elems):
        if e[1] == point:
            return elems[i:]
    return []


def _reverse(e):
    return ("L", e[2], e[1]) if e[0] == "L" else ("A", e[2], e[1], e[3], not e[4])


def _run(p: _Path, elems, off: float, base_end, stop) -> None:
    """The elements with the tool's control point ``off`` along z from the contour; on the base
    (the element ending at ``base_end``) only as far as ``stop`` (the near corner's limit)."""
    for e in elems:
        q = e[2]
        if base_end is not None and q == base_end:
            q = (q[0], stop)
            if (q[1] - e[1][1]) * (base_end[1] - e[1][1]) <= EPS:
                continue
        if e[0] == "L":
            p.g1(q[0], q[1] + off)
        else:
            p.moves.append(("ARC", (2.0 * q[0], q[1] + off), (2.0 * e[3][0], e[3][1] + off), e[4]))


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
              r: float, ramp_deg: float, ramp_from_axis: bool, t2: float, clear: float) -> None:
    """From the cylinder (radius R) f away from the face (at z ``face``), down the ramp to the floor
    at depth t1, along it and round the fillet r (tangent to the floor and to the face, or to the face
    moved t2 into the shoulder, whose relief then returns to the face at DIN509_FACE degrees), out."""
    d = -1.0 if outside else 1.0
    rf = R + d * t1
    run = t1 / math.tan(math.radians(ramp_deg)) if ramp_from_axis else t1 * math.tan(math.radians(ramp_deg))
    wall = face - s * t2
    clear_r = R - d * clear
    _enter(p, tool, outside, clear_r, face + s * f)
    p.g1(R, face + s * f)
    p.g1(rf, face + s * (f - run))
    p.g1(rf, wall + s * r)
    top = rf - d * r
    p.arc(top, wall, top, wall + s * r, (rf, wall + s * r))
    cur = top
    if t2 > EPS:
        cur = top - d * t2 / math.tan(math.radians(DIN509_FACE))
        p.g1(cur, face)
    if (cur - clear_r) * d > 0:  # up the face to the clearance level
        cur = clear_r
        p.g1(cur, face)
    _leave(p, tool, outside, cur)


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
    _undercut(p, tool, outside, s, spd / 2.0, _num(v, "SPL"), t1, f, r, DIN509_RAMP, True,
              t2 if form == "F" else 0.0, _unsigned(v, "_VRT") or DEFAULT_CLEARANCE)
    return p.moves


def plan_cycle96(v: dict, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """Thread undercut DIN 76 form A (outside) or C (inside), normal length, for the metric coarse
    thread DIATH (M3..M60: its pitch from ISO 261), at the face SPL, in one pass."""
    diath = _unsigned(v, "DIATH", positive=True)
    form = str(v.get("FORM", "")).strip().upper()
    if form not in ("A", "B", "C", "D"):
        raise GrooveParamError("FORM", f"FORM must be \"A\", \"B\", \"C\" or \"D\" (got \"{v.get('FORM', '')}\")")
    if form in ("B", "D"):
        raise GrooveParamError("FORM", f"FORM \"{form}\": the short undercuts B and D are not simulated yet (the "
                                       "normal ones A outside, C inside are)")
    if diath != int(diath) or int(diath) not in METRIC_PITCH:
        sizes = ", ".join(str(k) for k in METRIC_PITCH)
        raise GrooveParamError("DIATH", f"DIATH must be a metric coarse thread size ({sizes}), got {diath:g}")
    pitch = METRIC_PITCH[int(diath)]
    row = DIN76[pitch]
    outside, s = _side(v, "_VARI", tool)
    if outside != (form == "A"):
        raise GrooveParamError("FORM", f"FORM \"{form}\" is an {'outside' if form == 'A' else 'inside'} undercut, "
                                       f"the position (_VARI or the tool) an {'outside' if outside else 'inside'} one")
    dd, length, r = row[0:3] if outside else row[3:6]
    if outside:
        R, t1 = diath / 2.0, dd / 2.0
    else:  # the bore is the thread's minor diameter D1 = D - 1.0825 P; the undercut D + dd
        R = (diath - 1.082532 * pitch) / 2.0
        t1 = (diath + dd) / 2.0 - R
    p = _Path()
    _undercut(p, tool, outside, s, R, _num(v, "SPL"), t1, length, r, DIN76_FLANK, True, 0.0,
              _unsigned(v, "_VRT") or DEFAULT_CLEARANCE)
    return p.moves
