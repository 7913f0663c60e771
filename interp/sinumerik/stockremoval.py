"""The moves of Sinumerik's stock removal cycle CYCLE95, planned as plain data: roughing, finishing
or both (VARI 1..12, with the hundreds digit 2: 201..212), longitudinal or face, outside or inside,
of a contour that may hold relief cuts (undercuts), with the finishing allowances FALZ / FALX / FAL.
No interpreter state, no meshes.

The contour comes in as elements in (radius, z): ("L", p, q) or ("A", p, q, centre, clockwise),
clockwise seen from +Y as G2 in G18. The planning runs in the cycle's own frame (removalgeom.py:
every machining type turned into longitudinal outside roughing); the moves go out as
interp/sinumerik/grooving.py's do: ("G0" | "G1", (x, z)), ("ARC", (x, z), (cx, cz), clockwise) and
("F", feed), x a diameter. What the Cycles manual ("Stock removal with relief cut CYCLE95") leaves
open is in docs/dialects/sinumerik-turning.md.
"""
from __future__ import annotations

import math

from .grooving import _budget, _enter, _leave, _num, _Path, _unsigned, DEFAULT_CLEARANCE, GrooveParamError, ToolEdge
from .removalgeom import (EPS, Frame, basin_end, bulge, first_below, first_up, follow_up, lowest, pieces, point,
                          tip_path)


def _vari(v: dict) -> tuple[int, bool, bool, bool]:
    """VARI -> (kind 1..4, roughing, finishing, overlapping rounding (hundreds digit 0))."""
    vari = _num(v, "VARI")
    ok = vari == int(vari) and (1 <= vari <= 12 or 201 <= vari <= 212)
    if not ok:
        raise GrooveParamError("VARI", f"VARI {vari:g}: the machining type is 1 to 12 (201 to 212: without "
                                       "rounding over the intersections before)")
    unit = int(vari) % 100
    tech = (unit - 1) // 4  # 0 roughing, 1 finishing, 2 complete
    return (unit - 1) % 4 + 1, tech != 1, tech != 0, int(vari) < 100


def _axes(frame: Frame) -> tuple[str, str]:
    return ("X", "Z") if frame.face else ("Z", "X")


def _reverse(e):
    return ("L", e[2], e[1]) if e[0] == "L" else ("A", e[2], e[1], e[3], not e[4])


def _where(frame: Frame, pt) -> str:
    r, z = frame.back(*pt)
    return f"radius {r:g}, Z{z:g}"


def _canonical(frame: Frame, elems: list) -> list:
    """The contour in the cycle's frame, running towards -b; refused (NPP) when it turns back along
    the cutting axis or rises above its end point (the blank's surface)."""
    con = [frame.elem(e) for e in elems]
    b0, b1 = con[0][1][1], con[-1][2][1]
    cut, _ = _axes(frame)
    if abs(b0 - b1) <= EPS:
        raise GrooveParamError("NPP", f"the contour starts and ends at the same {cut}: CYCLE95 removes stock "
                                      f"along {cut}, the contour must advance along it")
    rev = b0 < b1
    if rev:
        con = [_reverse(e) for e in reversed(con)]
    def name(k, e):  # as programmed: the element's number and its end point
        return f"element {len(con) - k if rev else k + 1} (ending at {_where(frame, e[1] if rev else e[2])})"

    for k, e in enumerate(con):
        lo, hi = bulge(e, 1)
        if hi > e[1][1] + EPS or lo < e[2][1] - EPS:
            raise GrooveParamError("NPP", f"the contour's {name(k, e)} runs back along {cut}: CYCLE95 cuts "
                                          f"paraxially, its contour must advance along {cut} all the way")
    top = con[-1][2][0]
    for k, e in enumerate(con):
        if bulge(e, 0)[1] > top + EPS:
            side = "smallest" if frame.inside else "largest"
            what = "Z" if frame.face else "diameter"
            raise GrooveParamError("NPP", f"the contour's {name(k, e)} goes beyond its end point: the end point "
                                          f"must be its {side} {what} (the blank's surface the roughing starts "
                                          "from)")
    return con


class _Plan:
    """The moves in the cycle's frame: ("G0" | "G1", (a, b)), ("ARC", (a, b), (ca, cb), cw), ("F", f)."""

    def __init__(self, v: dict, off: list, top: float, b_air: float, clear: float, max_moves):
        self.v, self.off, self.top, self.b_air, self.clear = v, off, top, b_air, clear
        self.mid = _unsigned(v, "MID")
        self.safe = top + clear
        self.moves: list[tuple] = []
        self.count, self.max_moves = 0, max_moves

    def g0(self, a, b):
        self.moves.append(("G0", (a, b)))

    def g1(self, a, b):
        self.moves.append(("G1", (a, b)))

    def feed(self, name: str):
        self.moves.append(("F", _num(self.v, name)))

    def here(self):
        return next(m[1] for m in reversed(self.moves) if m[0] != "F")

    def along(self, s0, s1):
        for e in pieces(self.off, s0, s1):
            if e[0] == "L":
                self.g1(*e[2])
            else:
                self.moves.append(("ARC", e[2], e[3], e[4]))

    def levels(self, depth: float) -> int:
        n = max(1, math.ceil(depth / self.mid - 1e-9)) if depth > EPS else 0
        self.count += n * (len(self.off) + 6) + 4
        _budget(self.count, self.max_moves, f"cuts of MID {self.mid:g}", "MID")
        return n

    def lift(self, b_back: float):
        """G0 off the contour by the clearance in both axes (out, and back along b but not past
        ``b_back``, a relief cut's entry), then back along b to ``b_back``."""
        a, b = self.here()
        self.g0(a + self.clear, min(b + self.clear, max(b, b_back)))
        self.g0(a + self.clear, b_back)

    def up(self):
        """G0 straight out to the safe level over the blank (if not above it already)."""
        a, b = self.here()
        self.g0(max(a, self.safe), b)


def _main(pl: _Plan, overlap: bool) -> list:
    """The roughing from the free end: levels from the blank's surface down to the contour's start
    (moved by the allowances), each cut along -b to the contour, then up along it. Returns the
    relief cuts left (top, start position, end position)."""
    off, s0 = pl.off, (0, 0.0)
    end = (len(off) - 1, 1.0)
    depth = pl.top - point(off, s0)[0]
    n = pl.levels(depth)
    subs, prev_c = [], end
    pl.feed("FF1")
    for k in range(1, n + 1):
        level = pl.top - depth * k / n
        pl.g0(level + (depth / n if k > 1 else pl.clear), pl.b_air)
        pl.g0(level, pl.b_air)
        c = first_up(off, s0, level)
        pl.g1(level, point(off, c)[1])
        up = math.inf if k == 1 else level + depth / n * (2 if overlap else 1)
        f, stopped = follow_up(off, c, up)
        pl.along(c, f)
        if stopped and f < prev_c:
            subs.append((level + depth / n, f, prev_c))
        pl.lift(pl.b_air)
        prev_c = c
    bottom = point(off, s0)[0]
    if lowest(off, s0, prev_c) < bottom - EPS:  # the contour dips below its start: a relief cut
        subs.insert(0, (bottom, s0, prev_c))
    return subs


def _pocket(pl: _Plan, top: float, s0, s1, overlap: bool) -> list:
    """A relief cut: the material above the contour between s0 and s1 below ``top``, roughed in
    levels down to its first basin's bottom; each level reached along the contour at FF2 (down its
    falling side), cut along -b at FF1, then up along the contour. Returns the relief cuts inside."""
    off = pl.off
    stop = min(basin_end(off, s0), s1)
    depth = top - lowest(off, s0, stop)
    n = pl.levels(depth)
    if n == 0:
        return []
    d = depth / n
    a0, b0 = point(off, s0)
    pl.up()
    pl.g0(pl.safe, b0)
    pl.g0(min(top + pl.clear, pl.safe), b0)
    ent, above, subs, prev_c = None, (top, b0), [], s1
    for k in range(1, n + 1):
        level = top - k * d
        e = first_below(off, s0, level, stop)
        if e is None:
            break
        pl.feed("FF2")
        pl.g1(*above)
        if e == s0 and a0 < level - EPS:
            pl.g1(level, b0)
            above = (level, b0)
        else:
            if ent is None:
                pl.g1(a0, b0)
            pl.along(ent or s0, e)
            ent, above = e, point(off, e)
        pl.feed("FF1")
        c = first_up(off, e, level)
        pl.g1(level, point(off, c)[1])
        f, stopped = follow_up(off, c, min(top, level + d * (2 if overlap else 1)))
        pl.along(c, f)
        if stopped and f < prev_c:
            subs.append((level + d, f, prev_c))
        pl.lift(above[1])
        prev_c = c
    pl.up()
    return subs


def _relief(pl: _Plan, subs: list, overlap: bool) -> None:
    """The relief cuts one after the other along the contour, each with the ones inside it."""
    for top, s0, s1 in sorted(subs, key=lambda x: x[1]):
        _relief(pl, _pocket(pl, top, s0, s1, overlap), overlap)


def _finish(pl: _Plan, con: list) -> None:
    """G0 before the contour's start, along the contour at FF3, G0 out over the blank."""
    pl.feed("FF3")
    a_s, b_s = con[0][1]
    moved = any(m[0] != "F" for m in pl.moves)
    if moved and abs(pl.here()[1] - pl.b_air) > EPS:  # over a relief cut: out and along first
        pl.up()
        pl.g0(pl.here()[0], pl.b_air)
    pl.g0(a_s, pl.b_air)
    pl.g1(a_s, b_s)
    for e in con:
        if e[0] == "L":
            pl.g1(*e[2])
        else:
            pl.moves.append(("ARC", e[2], e[3], e[4]))
    pl.g0(pl.safe, con[-1][2][1])


def _tip(frame: Frame, con: list, allow: tuple | None, tool: ToolEdge) -> list:
    """The path of the tool's theoretical tip along the contour moved by the allowances (FALX/FALZ
    as (a, b), FAL; None: the finishing's contour itself), its nose kept tangent to it
    (removalgeom.tip_path; the roughing's walk needs its monotone pieces)."""
    if allow is None and tool.nose <= EPS:
        return con
    try:
        return tip_path(con, *(allow or (0.0, 0.0, 0.0)), tool.nose, frame.to(*tool.tip_shift()))
    except ValueError as e:
        raise GrooveParamError("NPP", f"a concave arc ending at {_where(frame, e.args[0])} is narrower than the "
                                      f"tool's nose radius {tool.nose:g} (+ FAL): the nose cannot follow it") from None


def plan_cycle95(v: dict, start, elems: list, tool: ToolEdge, max_moves: int | None = None) -> list[tuple]:
    """CYCLE95 on the contour from ``start`` (radius, z) through ``elems``."""
    kind, rough, finish, overlap = _vari(v)
    frame = Frame(kind)
    mid = _unsigned(v, "MID")
    falz, falx, fal = _unsigned(v, "FALZ"), _unsigned(v, "FALX"), _unsigned(v, "FAL")
    _unsigned(v, "DT")
    _unsigned(v, "DAM")
    if rough and mid <= EPS:
        raise GrooveParamError("MID", "MID, the infeed depth of the roughing cuts, must be greater than 0")
    clear = _unsigned(v, "_VRT") or DEFAULT_CLEARANCE
    con = _canonical(frame, elems)
    fa, fb = (falz, falx) if frame.face else (falx, falz)
    off = _tip(frame, con, (fa, fb, fal) if rough else None, tool)
    for k, e in enumerate(off):
        if e[2][1] > e[1][1] + 1e-6:
            raise GrooveParamError("NPP", f"a relief cut near {_where(frame, e[2])} is narrower than the finishing "
                                          "allowances and the tool's nose on its two sides: the roughing cannot enter it")
    top = con[-1][2][0]
    b_air = max(con[0][1][1], off[0][1][1]) + clear
    pl = _Plan(v, off, top, b_air, clear, max_moves)
    if rough:
        _relief(pl, _main(pl, overlap), overlap)
    if finish:
        _finish(pl, _tip(frame, con, None, tool) if rough else off)
    else:
        pl.up()
    return _real(pl.moves, frame, tool, (top + clear, b_air))


def _real(moves: list, frame: Frame, tool: ToolEdge, first) -> list[tuple]:
    """The frame's moves as (diameter, z) moves, with the approach from and the return to the
    position before the call (outside Z first, inside X first, as the other turning cycles)."""
    p = _Path()
    r, z = frame.back(*first)
    _enter(p, tool, not frame.inside, r, z)
    for mv in moves:
        if mv[0] == "F":
            p.moves.append(mv)
        elif mv[0] == "ARC":
            (r, z), (cr, cz) = frame.back(*mv[1]), frame.back(*mv[2])
            p.moves.append(("ARC", (2.0 * r, z), (2.0 * cr, cz), mv[3] != frame.flip))
        else:
            r, z = frame.back(*mv[1])
            (p.g0 if mv[0] == "G0" else p.g1)(r, z)
    last = [m for m in p.moves if m[0] != "F"][-1][1]
    _leave(p, tool, not frame.inside, last[0] / 2.0)
    return p.moves
