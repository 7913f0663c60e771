"""The moves of Sinumerik's stock removal cycle CYCLE95 for its simplest machining types, planned as
plain data: longitudinal outside roughing (VARI 1), finishing (5) or both (9) of a contour that
rises monotonically from its start towards -Z (no undercut). No interpreter state, no meshes.

The contour comes in as elements in (radius, z): ("L", p, q) or ("A", p, q, centre, clockwise),
clockwise seen from +Y as G2 in G18. The moves go out as interp/sinumerik/grooving.py's do:
("G0" | "G1", (x, z)) and ("ARC", (x, z), (cx, cz), clockwise), x a diameter. What the Cycles
manual ("Stock removal with relief cut CYCLE95") leaves open is in docs/dialects/sinumerik-turning.md.
"""
from __future__ import annotations

import math

from .grooving import _budget, _enter, _leave, _num, _Path, _unsigned, DEFAULT_CLEARANCE, GrooveParamError, ToolEdge

EPS = 1e-7


def _r_at(e, t: float) -> tuple[float, float]:
    """The point at the parameter t (0..1) of an element: along a line, or the angle along an arc."""
    p, q = e[1], e[2]
    if e[0] == "L":
        return (p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]))
    c = e[3]
    a0, sweep = _sweep(e)
    a = a0 + t * sweep
    rad = math.hypot(p[0] - c[0], p[1] - c[1])
    return (c[0] + rad * math.sin(a), c[1] + rad * math.cos(a))


def _sweep(e) -> tuple[float, float]:
    """An arc's start angle and signed sweep, angles measured in (z, x) from +Z towards +X."""
    p, q, c, cw = e[1], e[2], e[3], e[4]
    a0 = math.atan2(p[0] - c[0], p[1] - c[1])
    a1 = math.atan2(q[0] - c[0], q[1] - c[1])
    sweep = a1 - a0
    if cw and sweep > 0:
        sweep -= 2 * math.pi
    if not cw and sweep < 0:
        sweep += 2 * math.pi
    return a0, sweep


def _monotone(e) -> bool:
    """Radius non-decreasing and z non-increasing over the element (an arc: no extreme inside)."""
    p, q = e[1], e[2]
    if q[0] < p[0] - EPS or q[1] > p[1] + EPS:
        return False
    if e[0] == "L":
        return True
    a0, sweep = _sweep(e)
    for k in range(-8, 9):  # the arc's extremes in r and z lie at multiples of 90 degrees
        a = k * math.pi / 2
        if min(a0, a0 + sweep) + 1e-9 < a < max(a0, a0 + sweep) - 1e-9:
            return False
    return True


def _crossing(elems, level: float):
    """Where the contour first rises above ``level`` (radius): (element index, parameter t, point);
    None when it never does."""
    for i, e in enumerate(elems):
        p, q = e[1], e[2]
        if q[0] <= level + EPS:
            continue
        if p[0] > level + EPS:
            return i, 0.0, p
        lo, hi = 0.0, 1.0  # r rises monotonically over the element: bisection to the level
        for _ in range(60):
            mid = (lo + hi) / 2
            if _r_at(e, mid)[0] > level:
                hi = mid
            else:
                lo = mid
        if e[0] == "L":
            t = (level - p[0]) / (q[0] - p[0])
            return i, t, (level, p[1] + t * (q[1] - p[1]))
        pt = _r_at(e, hi)
        return i, hi, (level, pt[1])
    return None


def _follow(path: _Path, elems, a, b) -> None:
    """Along the contour from crossing ``a`` to crossing ``b`` (or its end when b is None)."""
    i0, t0, _ = a
    i1, t1 = (b[0], b[1]) if b is not None else (len(elems) - 1, 1.0)
    for i in range(i0, i1 + 1):
        e = elems[i]
        ta, tb = (t0 if i == i0 else 0.0), (t1 if i == i1 else 1.0)
        if tb <= ta + 1e-12:
            continue
        end = b[2] if (b is not None and i == i1) else _r_at(e, tb)
        if e[0] == "L":
            path.g1(*end)
        else:
            path.moves.append(("ARC", (2.0 * end[0], end[1]), (2.0 * e[3][0], e[3][1]), e[4]))


def plan_cycle95(v: dict, start, elems: list, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """CYCLE95 VARI 1 / 5 / 9 on the contour from ``start`` (radius, z) through ``elems``."""
    vari = _num(v, "VARI")
    if vari not in (1, 5, 9):
        raise GrooveParamError("VARI", f"VARI {vari:g}: of CYCLE95's machining types only longitudinal outside "
                                       "roughing (1), finishing (5) and complete machining (9) are simulated yet")
    if abs(_num(v, "FAL")) > EPS:
        raise GrooveParamError("FAL", "FAL (a contour-parallel allowance) is not simulated yet: give FALZ and FALX")
    mid = _unsigned(v, "MID")
    falz, falx = _unsigned(v, "FALZ"), _unsigned(v, "FALX")
    _unsigned(v, "DT")
    _unsigned(v, "DAM")
    if vari in (1, 9) and mid <= EPS:
        raise GrooveParamError("MID", "MID, the infeed depth of the roughing cuts, must be greater than 0")
    for k, e in enumerate(elems):
        if not _monotone(e):
            raise GrooveParamError("NPP", f"the contour's element {k + 1} (ending at Z{e[2][1]:g}) falls "
                                          "back towards the axis or runs towards +Z: only a contour rising "
                                          "monotonically towards -Z (no undercut) is simulated yet")
    clear = _unsigned(v, "_VRT") or DEFAULT_CLEARANCE
    r_min, z0 = start
    r_max = elems[-1][2][0]
    p = _Path()
    z_start = z0 + falz + clear
    _enter(p, tool, True, r_max + clear, z_start)
    if vari in (1, 9):
        off = [(e[0], (e[1][0] + falx, e[1][1] + falz), (e[2][0] + falx, e[2][1] + falz))
               + ((((e[3][0] + falx, e[3][1] + falz)), e[4]) if e[0] == "A" else ()) for e in elems]
        depth = r_max - (r_min + falx)
        n = max(1, math.ceil(depth / mid - 1e-9)) if depth > EPS else 0
        _budget(n * (len(elems) + 4) + len(elems) + 8, max_moves, f"{n} cuts of MID {mid:g}", "MID")
        p.moves.append(("F", _num(v, "FF1")))
        prev = None
        for k in range(1, n + 1):
            level = r_max - depth * k / n
            p.g0(level + (depth / n if k > 1 else clear), z_start)
            p.g0(level, z_start)
            hit = _crossing(off, level)
            if hit is None:  # pragma: no cover - the offset contour ends above every level
                continue
            p.g1(level, hit[2][1])
            _follow(p, off, hit, prev)
            top = p.moves[-1][1][0] / 2.0
            p.g0(top + clear, p.moves[-1][1][1])
            p.g0(top + clear, z_start)
            prev = hit
    if vari in (5, 9):
        p.moves.append(("F", _num(v, "FF3")))
        p.g0(r_min, z_start)
        p.g1(r_min, z0)
        _follow(p, elems, (0, 0.0, start), None)
        p.g0(r_max + clear, elems[-1][2][1])
    else:
        p.g0(r_max + clear, p.moves[-1][1][1])
    _leave(p, tool, True, r_max + clear)
    return p.moves
