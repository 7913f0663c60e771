"""Sinumerik milling cycles (SLOT1, SLOT2, POCKET1-4, CYCLE71, CYCLE72) and the analytic tool
radius offset of a contour (G41/G42, CYCLE72).

Each cycle expands into plain moves through the ModalMachine methods, every record carrying the
cycle block's Src, so the kinematics and the material removal know nothing about cycles.
Geometry here is plain 2D math on lines and arcs in the working plane; no meshes.

The product decisions where Siemens' documentation is silent are listed in
docs/dialects/sinumerik.md ("What the simulator assumes"); the constants below are those.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .. import canon
from ..canon import Src
from ..errors import CutsimError
from ..modal import PLANE_AXES
from ..compensation import Elem, OffsetError, _cross, _dot, _left, _norm, _sub, length, offset_chain, tangent
from .corners import Corners
from .corners import finish as finish_corners
from .lang import (COORD_LIMIT, Branch, Call, Case, Frame, Goto, Num, Repeat, Ret, SubCall,
                             SubprogramMissing, Word, range_message)

SIDE_STEP = 1.0  # pocket/slot roughing: radial step between concentric paths, x tool radius
INNER_LOOP = 0.9  # the innermost roughing path lies this many tool radii inside the final one
FACE_STEP = 1.5  # CYCLE71 default side step (_MIDA empty), x tool radius
EPS = 1e-9
ANGLES = {"STA1", "INDA", "AFSL", "_STA"}  # degrees, within +-ANGLE_LIMIT
ANGLE_LIMIT = 360.0
NUM_LIMIT = 1000  # SLOT1/SLOT2 NUM


# ---------------------------------------------------------------------------------------------
# 2D elements of a path in the working plane and their offset: interp/compensation.py (shared
# with ISG G41/G42); an arc as elements and a reversed chain are the cycles' own.

def arc_elems(start, end, centre, cw: bool, full: bool) -> list:
    """An arc as elements: a full circle (start and end the same point) as its two halves, through
    the point opposite the start, so every element has a definite sweep for the offset."""
    if not full:
        return [Elem("A", start, end, centre, cw)]
    opp = (2 * centre[0] - start[0], 2 * centre[1] - start[1])
    return [Elem("A", start, opp, centre, cw), Elem("A", opp, end, centre, cw)]


def reverse(elems):
    out = []
    for e in reversed(elems):
        out.append(Elem("L", e.end, e.start) if e.kind == "L" else Elem("A", e.end, e.start, e.centre, not e.cw))
    return out


# ---------------------------------------------------------------------------------------------
# G41/G42 in the program: offset the buffered records
def _p2(v, plane):
    a, b, _ = PLANE_AXES[plane]
    return (v[a], v[b])


def _p3(p, n, plane):
    a, b, c = PLANE_AXES[plane]
    v = [0.0, 0.0, 0.0]
    v[a], v[b], v[c] = p[0], p[1], n
    return (v[0], v[1], v[2])


def _motion_like(r, start, end, feed=None):
    """A straight record like ``r`` (rapid or feed) from ``start`` to ``end``."""
    if isinstance(r, canon.Rapid):
        return canon.Rapid(r.src, start, end, r.diameter)
    return canon.Feed(r.src, start, end, r.diameter, r.feed if feed is None else feed, r.per_rev)


def _contour_of(m, buf, body, plane):
    """The compensated body's records as 2D elements and, for each, the index of its record
    (moves along the tool axis only are left out)."""
    elems, owner = [], []
    for k in body:
        r = buf[k]
        if _norm(_sub(_p2(r.end, plane), _p2(r.start, plane))) < 1e-9 and not (isinstance(r, canon.Arc) and r.full_turn):
            continue
        if isinstance(r, canon.Arc):  # a full circle: its two halves, both owned by the record
            pieces = arc_elems(_p2(r.start, plane), _p2(r.end, plane), _p2(r.center, plane), r.clockwise, r.full_turn)
        else:
            pieces = [Elem("L", _p2(r.start, plane), _p2(r.end, plane))]
        elems.extend(pieces)
        owner.extend([k] * len(pieces))
    return elems, owner


def _pieces(r, pieces, plane, nidx):
    """The offset elements of one record, its tool-axis travel spread over them by length."""
    out = []
    total = sum(length(e) for e in pieces)
    z0, z1 = r.start[nidx], r.end[nidx]
    run = 0.0
    feed = getattr(r, "feed", 0.0)
    for e in pieces:
        za = z0 + (z1 - z0) * (run / total if total > 0 else 0)
        run += length(e)
        zb = z0 + (z1 - z0) * (run / total if total > 0 else 1)
        s3, e3 = _p3(e.start, za, plane), _p3(e.end, zb, plane)
        if e.kind == "L":
            out.append(_motion_like(r, s3, e3, feed))
        else:
            out.append(canon.Arc(r.src, s3, e3, r.diameter, _p3(e.centre, za, plane), plane, e.cw, False, feed,
                                 getattr(r, "per_rev", False)))
    return out


def compensate_records(m, buf, d, plane, has_departure, comp_src):
    """Records between G41/G42 and G40 -> compensated records. The first motion is the approach
    (a straight move to the offset start of the contour), the G40 block's motion the departure."""
    nidx = PLANE_AXES[plane][2]
    motions = [k for k, r in enumerate(buf) if isinstance(r, canon.MOTIONS)]
    if len(motions) < 2 or abs(d) < EPS:
        return list(buf)
    first = motions[0]
    last = motions[-1] if has_departure and len(motions) >= 3 else None
    elems, owner = _contour_of(m, buf, [k for k in motions[1:] if k != last], plane)
    if not elems:
        return list(buf)
    try:
        chain = offset_chain(elems, d)
    except OffsetError as e:
        r = buf[owner[e.index]]
        raise m.error(r.src.line, r.src.col, f"radius compensation: {e}") from None
    by_owner: dict[int, list] = {}
    for e, i in chain:
        by_owner.setdefault(owner[i], []).append(e)
    out = []
    cur = None  # current 3D position
    for k, r in enumerate(buf):
        if not isinstance(r, canon.MOTIONS):
            out.append(r)
            continue
        if k == first:
            new = [_motion_like(r, r.start, _p3(chain[0][0].start, r.end[nidx], plane))]
        elif k == last:
            new = [_motion_like(r, cur, r.end)]
        elif k in by_owner:
            new = _pieces(r, by_owner[k], plane, nidx)
        else:  # a move along the tool axis only: done where the tool stands
            end = list(cur)
            end[nidx] = r.end[nidx]
            new = [_motion_like(r, cur, (end[0], end[1], end[2]), getattr(r, "feed", 0.0))]
        out.extend(new)
        cur = new[-1].end
    return out


# ---------------------------------------------------------------------------------------------
# parameters
@dataclass(frozen=True)
class P:
    name: str
    kind: str = "n"  # "n" number | "s" string
    default: object = 0.0  # None: required


def _spec(names: str, required: str = "", strings: str = ""):
    req = set(required.split())
    st = set(strings.split())
    return [P(n, "s" if n in st else "n", None if n in req else ("" if n in st else 0.0)) for n in names.split()]


SPECS = {
    "SLOT1": _spec("RTP RFP SDIS DP DPR NUM LENG WID CPA CPO RAD STA1 INDA FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF _FALD _STA2",
                   "RTP RFP LENG WID"),
    "SLOT2": _spec("RTP RFP SDIS DP DPR NUM AFSL WID CPA CPO RAD STA1 INDA FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF _FFCP",
                   "RTP RFP AFSL WID RAD"),
    "POCKET1": _spec("RTP RFP SDIS DP DPR LENG WID CRAD CPA CPO STA1 FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF",
                     "RTP RFP LENG WID"),
    "POCKET2": _spec("RTP RFP SDIS DP DPR PRAD CPA CPO FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF", "RTP RFP PRAD"),
    "POCKET3": _spec("_RTP _RFP _SDIS _DP _LENG _WID _CRAD _PA _PO _STA _MID _FAL _FALD _FFP1 _FFD _CDIR _VARI _MIDA "
                     "_AP1 _AP2 _AD _RAD1 _DP1", "_RTP _RFP _DP _LENG _WID"),
    "POCKET4": _spec("_RTP _RFP _SDIS _DP _PRAD _PA _PO _MID _FAL _FALD _FFP1 _FFD _CDIR _VARI _MIDA _AP1 _AD _RAD1 _DP1",
                     "_RTP _RFP _DP _PRAD"),
    "CYCLE71": _spec("_RTP _RFP _SDIS _DP _PA _PO _LENG _WID _STA _MID _MIDA _FDP _FALD _FFP1 _VARI _FDP1",
                     "_RTP _RFP _DP _LENG _WID"),
    "CYCLE72": _spec("_KNAME _RTP _RFP _SDIS _DP _MID _FAL _FALD _FFP1 _FFD _VARI _RL _AS1 _LP1 _FF3 _AS2 _LP2",
                     "_KNAME _RTP _RFP _DP", "_KNAME"),
}
CYCLES = set(SPECS)
DRILLING: set[str] = set()  # the drilling cycles and patterns (drilling.register fills it)


class Cycle:
    """One cycle call: its parameters by name (checked against SPECS) and the motion helpers."""

    def __init__(self, m, name: str, args, src: Src, col: int, label: str | None = None):
        self.m, self.name, self.src, self.line, self.col = m, name, src, src.line, col
        self.label = label or name  # what the messages call it: the cycle, or the ISO code run as it
        spec = SPECS[name]
        if len(args) > len(spec):
            raise m.error(self.line, args[len(spec)][1], f"{name} takes at most {len(spec)} parameters, not {len(args)}")
        self.v: dict[str, object] = {}
        self.given: set[str] = set()
        for k, p in enumerate(spec):
            val, col = args[k] if k < len(args) else (None, self.col)
            if val is None:
                if p.default is None:
                    raise m.error(self.line, col, f"{name}: parameter {k + 1} ({p.name}) is required")
                self.v[p.name] = p.default
                continue
            if p.kind == "n" and isinstance(val, str):
                raise m.error(self.line, col, f"{name}: parameter {k + 1} ({p.name}) must be a number, not the string \"{val}\"")
            if p.kind == "s" and not isinstance(val, str):
                raise m.error(self.line, col, f"{name}: parameter {k + 1} ({p.name}) must be a string in double quotes")
            if p.kind == "n":
                lim, unit = (ANGLE_LIMIT, "degrees") if p.name in ANGLES else (COORD_LIMIT, "")
                if not -lim <= val <= lim:
                    raise m.error(self.line, col, f"{name}: parameter {k + 1} " + range_message(p.name, val, -lim, lim, unit))
            self.v[p.name] = val
            self.given.add(p.name)
        self.rt = m.tool_radius()
        self.saved_feed = m.feed

    def __getitem__(self, k):
        return self.v[k]

    def err(self, msg: str):
        return self.m.error(self.line, self.col, f"{self.label}: {msg}")

    def unsigned(self, *names):
        for n in names:
            if self.v[n] < 0:
                raise self.err(f"{n} is written without a sign (got {self.v[n]:g})")

    # -- motion helpers --------------------------------------------------------------------------
    def rapid(self, p, z):
        if self._here(p, z):
            return
        self.m.rapid(self.src, (p[0], p[1], z))

    def feed_to(self, p, z, f):
        if f and f > 0:
            self.m.feed = f
        if self._here(p, z):
            return
        self.m.linear(self.src, (p[0], p[1], z))

    def _here(self, p, z):
        q = self.m.pos
        return abs(q[0] - p[0]) < 1e-9 and abs(q[1] - p[1]) < 1e-9 and abs(q[2] - z) < 1e-9

    def run_elem(self, e, z, f):
        if f and f > 0:
            self.m.feed = f
        if e.kind == "L":
            if self._here(e.end, z):
                return
            self.m.linear(self.src, (e.end[0], e.end[1], z))
        else:
            self.m.arc(self.src, (e.end[0], e.end[1], z), (e.centre[0], e.centre[1], z), e.cw)

    def pos2(self):
        return (self.m.pos[0], self.m.pos[1])

    def depth(self, dp="DP", dpr="DPR", rfp="RFP"):
        """Final depth: DPR (relative, unsigned) wins when given and non-zero."""
        if dpr and dpr in self.given and self.v[dpr] != 0:
            if self.v[dpr] < 0:
                raise self.err(f"{dpr} is written without a sign")
            return self.v[rfp] - self.v[dpr]
        if dp not in self.given:
            raise self.err(f"the depth is missing: give {dp}" + (f" or {dpr}" if dpr else ""))
        return self.v[dp]

    def levels(self, top, bottom, mid):
        if bottom >= top - EPS:
            return []
        if mid < 0:
            raise self.err("the infeed depth is written without a sign")
        n = 1 if mid <= EPS else max(1, math.ceil((top - bottom) / mid - 1e-9))
        return [top - (top - bottom) * k / n for k in range(1, n + 1)]

    def start(self, rtp, p):
        """To the retraction plane, then over the start point."""
        if self.m.pos[2] < rtp - EPS:
            self.m.rapid(self.src, (self.m.pos[0], self.m.pos[1], rtp))
        self.rapid(p, rtp)

    def finish(self, rtp):
        self.m.rapid(self.src, (self.m.pos[0], self.m.pos[1], rtp))
        self.m.feed = self.saved_feed

    def need_radius(self):
        if self.rt <= 0:
            raise self.err("no tool radius: select a milling tool (T.. M6, D1) that the setup describes")

    def ccw(self, cdir):
        """Loops run counter-clockwise (G3) for climb milling with M3 (inside a pocket)."""
        cdir = int(cdir)
        if cdir not in (0, 1, 2, 3):
            raise self.err(f"CDIR must be 0, 1, 2 or 3 (got {cdir})")
        if cdir in (2, 3):
            return cdir == 3
        climb_ccw = self.m.spindle_dir >= 0
        return climb_ccw if cdir == 0 else not climb_ccw


# ---------------------------------------------------------------------------------------------
# pocket-like regions: concentric closed paths
def _rot(p, ang, c):
    ca, sa = math.cos(ang), math.sin(ang)
    return (c[0] + p[0] * ca - p[1] * sa, c[1] + p[0] * sa + p[1] * ca)


def rounded_rect_loop(a, b, cr, centre, ang):
    """CCW path of the rounded rectangle |u|<=a, |v|<=b (corner radius cr) from (0, -b), in global
    coordinates; zero-length pieces dropped (a = 0 or b = 0 is a line travelled both ways)."""
    cr = max(0.0, min(cr, a, b))
    pts = []
    seq = [("L", (a - cr, -b)), ("A", (a, -b + cr), (a - cr, -b + cr)), ("L", (a, b - cr)),
           ("A", (a - cr, b), (a - cr, b - cr)), ("L", (-a + cr, b)), ("A", (-a, b - cr), (-a + cr, b - cr)),
           ("L", (-a, -b + cr)), ("A", (-a + cr, -b), (-a + cr, -b + cr)), ("L", (0.0, -b))]
    cur = (0.0, -b)
    for s in seq:
        nxt = s[1]
        if math.hypot(nxt[0] - cur[0], nxt[1] - cur[1]) < 1e-9:
            continue
        g0, g1 = _rot(cur, ang, centre), _rot(nxt, ang, centre)
        if s[0] == "L" or cr <= 1e-9:
            pts.append(Elem("L", g0, g1))
        else:
            pts.append(Elem("A", g0, g1, _rot(s[2], ang, centre), False))
        cur = nxt
    if not pts:  # a point: the tool only plunges
        g = _rot((0.0, -b), ang, centre)
        pts.append(Elem("L", g, g))
    return pts


def arc_slot_loop(rad, rho, t0, t1, centre):
    """CCW path around the arc slot of centre-line radius ``rad`` from angle t0 to t1 (radians,
    t1 > t0) at offset ``rho`` from the centre line, from the inner arc at the middle angle."""
    tm = (t0 + t1) / 2

    def P(r, t):
        return (centre[0] + r * math.cos(t), centre[1] + r * math.sin(t))
    e0, e1 = P(rad, t0), P(rad, t1)
    out = [Elem("A", P(rad - rho, tm), P(rad - rho, t0), centre, True)]
    if rho > 1e-9:
        out.append(Elem("A", P(rad - rho, t0), P(rad + rho, t0), e0, False))
    out.append(Elem("A", P(rad + rho, t0), P(rad + rho, t1), centre, False))
    if rho > 1e-9:
        out.append(Elem("A", P(rad + rho, t1), P(rad - rho, t1), e1, False))
    out.append(Elem("A", P(rad - rho, t1), P(rad - rho, tm), centre, True))
    return out


def offsets(d, rt, step):
    """Offsets (from the final path inwards) of the concentric roughing paths: the innermost lies
    within INNER_LOOP tool radii of the middle, neighbours at most ``step`` apart."""
    if d <= INNER_LOOP * rt:
        return [0.0]
    inner = INNER_LOOP * rt
    n = 1 + math.ceil((d - inner) / step - 1e-9)
    s = (d - inner) / (n - 1)
    return [(n - 1 - j) * s for j in range(n)]


def n_levels(top, bottom, mid) -> int:
    """How many depth steps Cycle.levels makes (without building them)."""
    if bottom >= top - EPS:
        return 0
    return 1 if mid <= EPS else max(1, math.ceil((top - bottom) / mid - 1e-9))


def n_offsets(d, rt, step) -> int:
    """How many concentric paths offsets() makes (without building them)."""
    return 1 if d <= INNER_LOOP * rt else 1 + math.ceil((d - INNER_LOOP * rt) / step - 1e-9)


def budget(cy: Cycle, moves: int, parts: list[tuple[int, str]]) -> None:
    """Refuse a cycle whose moves (estimated from its parameters, before any is built) exceed
    [simulation] max_blocks; ``parts`` are the factors as (count, text naming the parameter)."""
    limit = cy.m.cfg.max_blocks
    if moves > limit:
        detail = ", ".join(f"{n:,} {t}" for n, t in parts)
        raise cy.err(f"the cycle would make about {moves:,} moves ({detail}), more than [simulation] max_blocks = "
                     f"{limit:,}: a cycle may make at most that many moves")


def region_budget(cy: Cycle, top, bottom, mid, midf, fald, units, fal, n_loops, per_loop, step_text, count=1,
                  helix_pitch=None):
    """The moves cut_region will make for ``count`` regions of ``n_loops`` paths of ``per_loop``
    elements each, checked against max_blocks before anything is built."""
    u = "_" if cy.name in ("POCKET3", "POCKET4") else ""
    rough = units in (0, 1)
    fin = units == 2 or (units == 0 and fal > 0)
    nr = n_levels(top, bottom + fald, mid) if rough else 0
    nf = n_levels(top, bottom, midf if midf > 0 else mid) if fin else 0
    per_level = n_loops * (per_loop + 1) + 3
    moves = nr * per_level + (per_level if rough and fald > 0 else 0) + nf * (per_loop + 3) + 6
    parts = [(max(nr, nf), f"infeeds of at most {u}MID {mid:g} over {top - bottom:g} mm"
              + (f" (finishing: MIDF {midf:g})" if nf > nr else "")),
             (n_loops, f"paths side by side {step_text}")]
    if helix_pitch:
        half_turns = math.ceil((top - bottom) / (helix_pitch / 2)) + 4 * nr
        moves += half_turns
        parts.append((half_turns, f"helix half-turns of _DP1 {helix_pitch:g} mm per turn"))
    if count > 1:
        parts.append((count, "slots (NUM)"))
    budget(cy, moves * count, parts)


def cut_region(cy: Cycle, rtp, safe, top, bottom, loops_rough, loops_fin, mid, midf, plunge, ffd, ffp1, ffp2,
               fald=0.0, helix=None):
    """Rough the loops level by level (plunge at the first loop's start), then finish along the
    final loop. ``loops_*`` are lists of CCW/CW element lists, inside first."""
    rough_levels = cy.levels(top, bottom + fald, mid) if loops_rough else []
    fin_levels = cy.levels(top, bottom, midf if midf > 0 else mid) if loops_fin else []
    first = (loops_rough or loops_fin)[0][0].start if (loops_rough or loops_fin) else None
    if first is None:
        return
    cy.start(rtp, first)
    cy.rapid(first, safe)
    z_prev = safe
    for lv in rough_levels:
        _plunge(cy, loops_rough[0], z_prev, lv, plunge, ffd, top, helix)
        for k, loop in enumerate(loops_rough):
            if k:
                cy.feed_to(loop[0].start, lv, ffp1)
            for e in loop:
                cy.run_elem(e, lv, ffp1)
        cy.feed_to(loops_rough[0][0].start, lv, ffp1)
        z_prev = lv
    if fald > 0 and loops_rough:  # floor allowance: clear the floor at the final depth
        _plunge(cy, loops_rough[0], z_prev, bottom, 1, ffd, top, None)
        for k, loop in enumerate(loops_rough):
            if k:
                cy.feed_to(loop[0].start, bottom, ffp1)
            for e in loop:
                cy.run_elem(e, bottom, ffp1)
        cy.feed_to(loops_rough[0][0].start, bottom, ffp1)
        z_prev = bottom
    for lv in fin_levels:
        loop = loops_fin[-1]
        if loops_rough:
            cy.feed_to(loop[0].start, cy.m.pos[2], ffp2)
            cy.feed_to(loop[0].start, lv, ffd)
        else:
            _plunge(cy, loop, z_prev, lv, plunge, ffd, top, None)
        for e in loop:
            cy.run_elem(e, lv, ffp2)
        z_prev = lv
    cy.feed_to(cy.pos2(), safe, ffd)
    cy.finish(rtp)


def _plunge(cy: Cycle, loop, z_prev, z, mode, ffd, top, helix):
    p = loop[0].start
    if mode == 0:  # vertical: G0 only down to where the material begins, the infeed itself at FFD
        cy.rapid(p, max(z_prev, z))
        cy.feed_to(p, z, ffd)
    elif mode == 2 and helix is not None:  # helix about the region centre
        c, r, pitch = helix
        s = (c[0] + r, c[1])
        cy.feed_to(s, z_prev, ffd)
        zc = z_prev
        while zc > z + EPS:
            zn = max(z, zc - pitch / 2)
            cy.m.arc(cy.src, (c[0] - r, c[1], zn), (c[0], c[1], zn), False)
            zc = zn
            if zc <= z + EPS:
                cy.m.arc(cy.src, (c[0] + r, c[1], zc), (c[0], c[1], zc), False)
                break
            zn = max(z, zc - pitch / 2)
            cy.m.arc(cy.src, (c[0] + r, c[1], zn), (c[0], c[1], zn), False)
            zc = zn
        cy.m.arc(cy.src, (c[0] - r, c[1], z), (c[0], c[1], z), False)  # flatten the ramp's floor
        cy.m.arc(cy.src, (c[0] + r, c[1], z), (c[0], c[1], z), False)
        cy.feed_to(p, z, ffd)
    elif mode == 3:  # oscillate along the first straight piece of the innermost path
        e = loop[0]
        if e.kind == "L" and length(e) > 1e-3:
            zm = (z_prev + z) / 2
            cy.feed_to(e.end, max(zm, z), ffd)
            cy.feed_to(e.start, z, ffd)
        else:
            cy.feed_to(p, z, ffd)
    else:  # vertical with G1
        cy.feed_to(p, z, ffd)


def _vari(cy: Cycle, key="VARI"):
    v = cy[key]
    if v < 0 or v != int(v):
        raise cy.err(f"{key} must be a whole number without a sign (got {v:g})")
    v = int(v)
    units, tens = v % 10, (v // 10) % 10
    if units not in (0, 1, 2):
        raise cy.err(f"{key} units digit must be 0 (complete), 1 (roughing) or 2 (finishing), got {units}")
    return units, tens


def _plunge_mode(cy, tens, allowed):
    if tens not in allowed:
        raise cy.err(f"VARI tens digit {tens} is not one of {', '.join(map(str, sorted(allowed)))}")
    return tens


def _loops_for(units, fal, build_rough, build_fin):
    rough = build_rough() if units in (0, 1) else []
    fin = build_fin() if (units == 2 or (units == 0 and fal > 0)) else []
    return rough, fin


def _orient(loops, ccw):
    return [lp if ccw else reverse(lp) for lp in loops]


# ---------------------------------------------------------------------------------------------
def _seg_dist(p1, p2, q1, q2):
    def pd(p, a, b):
        ab = _sub(b, a)
        L = _dot(ab, ab)
        t = 0.0 if L < 1e-18 else max(0.0, min(1.0, _dot(_sub(p, a), ab) / L))
        return _norm(_sub(p, (a[0] + t * ab[0], a[1] + t * ab[1])))
    d1, d2 = _sub(p2, p1), _sub(q2, q1)
    den = _cross(d1, d2)
    if abs(den) > 1e-14:
        t = _cross(_sub(q1, p1), d2) / den
        u = _cross(_sub(q1, p1), d1) / den
        if 0 <= t <= 1 and 0 <= u <= 1:
            return 0.0
    return min(pd(p1, q1, q2), pd(p2, q1, q2), pd(q1, p1, p2), pd(q2, p1, p2))


def _slot_count(cy: Cycle) -> int:
    """NUM: how many slots (default 1), a whole number."""
    num = cy["NUM"] if "NUM" in cy.given else 1
    if num < 1 or num != int(num) or num > NUM_LIMIT:
        raise cy.err(f"NUM must be a whole number of slots from 1 to {NUM_LIMIT} (got {num:.10g})")
    return int(num)


def _tool_fits_slot(cy: Cycle, wid: float, fal: float) -> None:
    """The tool, with the finishing allowance on both sides, fits the slot width."""
    if 2 * cy.rt > wid + 1e-9:
        raise cy.err(f"the tool (diameter {2 * cy.rt:g}) is wider than the slot (WID {wid:g})")
    if 2 * (cy.rt + fal) > wid + 1e-9:
        raise cy.err(f"the finishing allowance FAL {fal:g} leaves no room for the tool in the slot")


def slot1(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "NUM", "LENG", "WID", "RAD", "MID", "FAL", "MIDF")
    rt = cy.rt
    num = _slot_count(cy)
    leng, wid, fal = cy["LENG"], cy["WID"], cy["FAL"]
    _tool_fits_slot(cy, wid, fal)
    if leng < wid - 1e-9:
        raise cy.err(f"the slot length LENG {leng:g} is shorter than its width WID {wid:g}")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1, 3})
    inda = cy["INDA"] if cy["INDA"] != 0 else 360.0 / num
    c = (cy["CPA"], cy["CPO"])
    axes = []
    for k in range(num):
        ang = math.radians(cy["STA1"] + k * inda)
        u = (math.cos(ang), math.sin(ang))
        r0, r1 = cy["RAD"] + wid / 2, cy["RAD"] + leng - wid / 2
        axes.append((ang, (c[0] + r0 * u[0], c[1] + r0 * u[1]), (c[0] + r1 * u[0], c[1] + r1 * u[1])))
    for i in range(num):
        for j in range(i + 1, num):
            if _seg_dist(axes[i][1], axes[i][2], axes[j][1], axes[j][2]) < wid - 1e-6:
                raise cy.err(f"slots {i + 1} and {j + 1} overlap (width {wid:g}, angle step {inda:g} degrees)")
    ccw = cy.ccw(cy["CDIR"])
    bottom = cy.depth()
    safe = cy["RFP"] + cy["SDIS"]
    region_budget(cy, cy["RFP"], bottom, cy["MID"], cy["MIDF"], 0.0, units, fal,
                  n_offsets(max(wid / 2 - rt - fal, 0.0), rt, SIDE_STEP * rt), 9,
                  f"{SIDE_STEP * rt:g} mm apart (the tool radius {rt:g} mm)", count=num)
    for ang, p0, p1 in axes:
        mid = ((p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2)
        a, b = leng / 2 - rt, wid / 2 - rt

        def build(extra, a=a, b=b, mid=mid, ang=ang):
            return [rounded_rect_loop(a - extra - o, b - extra - o, b - extra - o, mid, ang)
                    for o in offsets(b - extra, rt, SIDE_STEP * rt)]
        rough, fin = _loops_for(units, fal, lambda: build(fal), lambda: [rounded_rect_loop(a, b, b, mid, ang)])
        cut_region(cy, cy["RTP"], safe, cy["RFP"], bottom, _orient(rough, ccw), _orient(fin, ccw), cy["MID"],
                   cy["MIDF"], mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"])


def slot2(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "NUM", "AFSL", "WID", "RAD", "MID", "FAL", "MIDF")
    rt = cy.rt
    num = _slot_count(cy)
    afsl, wid, rad, fal = cy["AFSL"], cy["WID"], cy["RAD"], cy["FAL"]
    _tool_fits_slot(cy, wid, fal)
    if rad - wid / 2 <= 1e-9:
        raise cy.err(f"the slot (width {wid:g}) does not fit on the radius RAD {rad:g}")
    if afsl <= 0 or afsl >= 360:
        raise cy.err(f"AFSL must be between 0 and 360 degrees (got {afsl:g})")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1, 3})
    inda = cy["INDA"] if cy["INDA"] != 0 else 360.0 / num
    # neighbours: the ends' circles of radius WID/2 must not overlap
    cap = 2 * math.degrees(math.asin(min(1.0, wid / (2 * rad))))
    if num > 1:
        gaps = [(((cy["STA1"] + (k + 1) * inda) - (cy["STA1"] + k * inda + afsl)) % 360.0) for k in range(num)]
        starts = sorted(((cy["STA1"] + k * inda) % 360.0) for k in range(num))
        spacing = min((starts[(k + 1) % num] - starts[k]) % 360.0 for k in range(num))
        if spacing < afsl + cap - 1e-6 or min(gaps) < cap - 1e-6:
            raise cy.err(f"the slots overlap: {num} slots of {afsl:g} degrees and width {wid:g} do not fit "
                         f"with the angle step {inda:g} degrees")
    elif afsl + cap > 360 + 1e-6:
        raise cy.err("the slot closes on itself")
    ccw = cy.ccw(cy["CDIR"])
    c = (cy["CPA"], cy["CPO"])
    bottom = cy.depth()
    safe = cy["RFP"] + cy["SDIS"]
    region_budget(cy, cy["RFP"], bottom, cy["MID"], cy["MIDF"], 0.0, units, fal,
                  n_offsets(max(wid / 2 - rt - fal, 0.0), rt, SIDE_STEP * rt), 5,
                  f"{SIDE_STEP * rt:g} mm apart (the tool radius {rt:g} mm)", count=num)
    for k in range(num):
        t0 = math.radians(cy["STA1"] + k * inda)
        t1 = t0 + math.radians(afsl)
        b = wid / 2 - rt

        def build(extra, t0=t0, t1=t1, b=b):
            return [arc_slot_loop(rad, b - extra - o, t0, t1, c) for o in offsets(b - extra, rt, SIDE_STEP * rt)]
        rough, fin = _loops_for(units, fal, lambda: build(fal), lambda: [arc_slot_loop(rad, b, t0, t1, c)])
        cut_region(cy, cy["RTP"], safe, cy["RFP"], bottom, _orient(rough, ccw), _orient(fin, ccw), cy["MID"],
                   cy["MIDF"], mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"])


def _rect_pocket(cy: Cycle, leng, wid, crad, centre, sta, mid, midf, fal, fald, units, mode, ffd, ffp1, ffp2,
                 cdir, rtp, rfp, sdis, bottom, step, helix_r=None, helix_pitch=None, circle=False):
    rt = cy.rt
    what = "pocket"
    if circle:
        if crad < rt - 1e-9:
            raise cy.err(f"the pocket radius {crad:g} is smaller than the tool radius {rt:g}")
    else:
        if min(leng, wid) < 2 * rt - 1e-9:
            raise cy.err(f"the tool (diameter {2 * rt:g}) is wider than the {what} ({leng:g} x {wid:g})")
        if crad < rt - 1e-9:
            raise cy.err(f"the corner radius CRAD {crad:g} is smaller than the tool radius {rt:g}")
        if crad > min(leng, wid) / 2 + 1e-9:
            raise cy.err(f"the corner radius CRAD {crad:g} is larger than half the pocket width")
    a, b, cr = leng / 2 - rt, wid / 2 - rt, crad - rt
    if min(a, b) - fal < -1e-9:
        raise cy.err(f"the finishing allowance {fal:g} leaves no room for the tool in the pocket")
    ang = math.radians(sta)
    ccw = cy.ccw(cdir)
    pitch = None
    if mode == 2:
        pitch = helix_pitch if helix_pitch and helix_pitch > 0 else max(rt / 2, 1e-3)
    mida_given = cy.name in ("POCKET3", "POCKET4") and cy["_MIDA"] > 0
    step_text = f"_MIDA {step:g} mm apart" if mida_given else f"{step:g} mm apart (the tool radius {rt:g} mm)"
    region_budget(cy, rfp, bottom, mid, midf, fald, units, fal, n_offsets(max(min(a, b) - fal, 0.0), rt, step),
                  9, step_text, helix_pitch=pitch)

    def build(extra):
        d = max(min(a, b) - extra, 0.0)
        return [rounded_rect_loop(max(a - extra - o, 0), max(b - extra - o, 0), cr - extra - o, centre, ang)
                for o in offsets(d, rt, step)]
    rough, fin = _loops_for(units, fal, lambda: build(fal), lambda: [rounded_rect_loop(a, b, cr, centre, ang)])
    helix = None
    if mode == 2:
        r = helix_r if helix_r and helix_r > 0 else rt / 2
        if r + rt > min(leng, wid) / 2 + 1e-9:
            raise cy.err(f"the helix radius {r:g} does not fit in the pocket with this tool")
        helix = (centre, r, pitch)
    cut_region(cy, rtp, rfp + sdis, rfp, bottom, _orient(rough, ccw), _orient(fin, ccw), mid, midf, mode, ffd, ffp1,
               ffp2, fald, helix)


def pocket1(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "LENG", "WID", "CRAD", "MID", "FAL", "MIDF")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1})
    _rect_pocket(cy, cy["LENG"], cy["WID"], cy["CRAD"], (cy["CPA"], cy["CPO"]), cy["STA1"], cy["MID"], cy["MIDF"],
                 cy["FAL"], 0.0, units, mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"], cy["CDIR"],
                 cy["RTP"], cy["RFP"], cy["SDIS"], cy.depth(), SIDE_STEP * cy.rt)


def pocket2(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "PRAD", "MID", "FAL", "MIDF")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1})
    r = cy["PRAD"]
    _rect_pocket(cy, 2 * r, 2 * r, r, (cy["CPA"], cy["CPO"]), 0.0, cy["MID"], cy["MIDF"], cy["FAL"], 0.0, units,
                 mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"], cy["CDIR"], cy["RTP"], cy["RFP"], cy["SDIS"],
                 cy.depth(), SIDE_STEP * cy.rt, circle=True)


def _mida(cy: Cycle):
    mida = cy["_MIDA"]
    if mida < 0:
        raise cy.err("_MIDA is written without a sign")
    if mida > 2 * cy.rt + 1e-9:
        raise cy.err(f"_MIDA {mida:g} is larger than the tool diameter {2 * cy.rt:g}: material would be left")
    return mida if mida > 0 else SIDE_STEP * cy.rt


def pocket3(cy: Cycle):
    cy.need_radius()
    cy.unsigned("_SDIS", "_LENG", "_WID", "_CRAD", "_MID", "_FAL", "_FALD")
    units, tens = _vari(cy, "_VARI")
    mode = _plunge_mode(cy, tens, {0, 1, 2, 3})
    _rect_pocket(cy, cy["_LENG"], cy["_WID"], cy["_CRAD"], (cy["_PA"], cy["_PO"]), cy["_STA"], cy["_MID"], 0.0,
                 cy["_FAL"], cy["_FALD"] if units != 2 else 0.0, units, mode, cy["_FFD"], cy["_FFP1"], cy["_FFP1"],
                 cy["_CDIR"], cy["_RTP"], cy["_RFP"], cy["_SDIS"], cy.depth("_DP", None, "_RFP"), _mida(cy),
                 cy["_RAD1"], cy["_DP1"])


def pocket4(cy: Cycle):
    cy.need_radius()
    cy.unsigned("_SDIS", "_PRAD", "_MID", "_FAL", "_FALD")
    units, tens = _vari(cy, "_VARI")
    mode = _plunge_mode(cy, tens, {0, 1, 2})
    r = cy["_PRAD"]
    _rect_pocket(cy, 2 * r, 2 * r, r, (cy["_PA"], cy["_PO"]), 0.0, cy["_MID"], 0.0, cy["_FAL"],
                 cy["_FALD"] if units != 2 else 0.0, units, mode, cy["_FFD"], cy["_FFP1"], cy["_FFP1"], cy["_CDIR"],
                 cy["_RTP"], cy["_RFP"], cy["_SDIS"], cy.depth("_DP", None, "_RFP"), _mida(cy), cy["_RAD1"], cy["_DP1"],
                 circle=True)


def cycle71(cy: Cycle):
    cy.need_radius()
    cy.unsigned("_SDIS", "_MID", "_MIDA", "_FDP", "_FALD", "_FDP1")
    rt = cy.rt
    v = cy["_VARI"]
    if v < 0 or v != int(v):
        raise cy.err("_VARI must be a whole number without a sign")
    units, tens = int(v) % 10, (int(v) // 10) % 10
    if units not in (0, 1, 2):
        raise cy.err(f"_VARI units digit must be 1 (roughing) or 2 (finishing), got {units}")
    if tens not in (1, 2, 3, 4):
        raise cy.err(f"_VARI tens digit must be 1..4 (direction and one-way / zig-zag), got {tens}")
    leng, wid = cy["_LENG"], cy["_WID"]
    if leng == 0 or wid == 0:
        raise cy.err("_LENG and _WID must not be 0")
    along_first = tens in (1, 3)
    zigzag = tens in (3, 4)
    mida = cy["_MIDA"]
    if mida > 2 * rt + 1e-9:
        raise cy.err(f"_MIDA {mida:g} is larger than the tool diameter {2 * rt:g}: material would be left")
    step = mida if mida > 0 else FACE_STEP * rt
    ang = math.radians(cy["_STA"])
    corner = (cy["_PA"], cy["_PO"])
    u0, u1 = sorted((0.0, leng))
    v0, v1 = sorted((0.0, wid))
    if not along_first:  # cut along the second axis: swap the roles
        u0, u1, v0, v1 = v0, v1, u0, u1
    n = max(1, math.ceil((v1 - v0) / step - 1e-9))
    top, bottom, fald = cy["_RFP"], cy["_DP"], cy["_FALD"]
    nl = n_levels(top, bottom, cy["_MID"]) + 1
    budget(cy, nl * (3 * (n + 1) + 4), [(nl, f"infeeds of at most _MID {cy['_MID']:g} over {top - bottom:g} mm"),
                                        (n + 1, f"lines {step:g} mm apart" + (" (_MIDA)" if mida > 0 else
                                                                            f" (the tool radius {rt:g} mm)"))])
    vs = [v0 + (v1 - v0) * k / n for k in range(n + 1)]
    ext0 = rt + (cy["_FDP"] if cy["_FDP"] > 0 else cy["_SDIS"])
    ext1 = rt + cy["_FDP1"]

    def G(u, v):
        p = (u, v) if along_first else (v, u)
        return _rot(p, ang, corner)
    levels = []
    if units in (0, 1):
        levels += cy.levels(top, bottom + (fald if units == 1 or fald > 0 else 0.0), cy["_MID"])
    if units == 2 or (units == 0 and fald > 0):
        levels.append(bottom)
    f = cy["_FFP1"]
    safe = top + cy["_SDIS"]
    cy.start(cy["_RTP"], G(u0 - ext0, vs[0]))
    for j, lv in enumerate(levels):
        # one-way returns in G0 run _SDIS above the material this level cuts (its top is the level
        # before, or RFP), not above the level itself: that would cut the lines still to come
        back = (levels[j - 1] if j and levels[j - 1] > lv else top) + cy["_SDIS"]
        cy.rapid(G(u0 - ext0, vs[0]), max(safe, lv + cy["_SDIS"]) if cy.m.pos[2] > lv else cy.m.pos[2])
        cy.feed_to(G(u0 - ext0, vs[0]), lv, f)
        fwd = True
        for k, v in enumerate(vs):
            if fwd:
                a, b = G(u0 - ext0, v), G(u1 + ext1, v)
            else:
                a, b = G(u1 + ext1, v), G(u0 - ext0, v)
            if k:
                if zigzag:
                    cy.feed_to(a, lv, f)
                else:
                    cy.rapid(cy.pos2(), back)
                    cy.rapid(a, back)
                    cy.feed_to(a, lv, f)
            cy.feed_to(b, lv, f)
            if zigzag:
                fwd = not fwd
        cy.rapid(cy.pos2(), safe)
        cy.rapid(G(u0 - ext0, vs[0]), safe)
    cy.finish(cy["_RTP"])


# ---------------------------------------------------------------------------------------------
@dataclass
class ModalState:
    """What running a contour's blocks in a sandbox changes on the machine, copied before and put
    back after (contour_elements)."""
    pos: list
    absolute: bool
    plane: str
    motion: int
    feed: float
    per_rev: bool
    records: list
    comp_buf: list | None
    warned_feed: bool
    executed: int

    @classmethod
    def of(cls, m) -> ModalState:
        return cls(list(m.pos), m.absolute, m.plane, m.motion, m.feed, m.per_rev, m.program.records, m.comp_buf,
                   m._warned_feed, m.executed)

    def restore(self, m) -> None:
        m.pos, m.absolute, m.plane, m.motion, m.feed, m.per_rev = (list(self.pos), self.absolute, self.plane,
                                                                  self.motion, self.feed, self.per_rev)
        m.program.records, m.comp_buf, m._warned_feed, m.executed = (self.records, self.comp_buf, self.warned_feed,
                                                                     self.executed)


def contour_lines(m, name: str, cy: Cycle):
    """The unit and the lines of the contour named by _KNAME: a subprogram or "START:END" labels."""
    name = name.strip()
    if not name:
        raise cy.err("_KNAME is empty: name the contour (subprogram or \"START:END\" labels)")
    if ":" in name:
        l1, l2 = [s.strip().upper() for s in name.split(":", 1)]
        for unit in [m.main, *m.subs.values()]:
            if l1 in unit.labels and l2 in unit.labels:
                return unit, unit.lines[unit.labels[l1]:unit.labels[l2] + 1]
        raise cy.err(f"contour {name}: the labels {l1} and {l2} are not both in the program")
    try:
        unit = m.find_sub(name.upper(), cy.line, cy.col)
    except SubprogramMissing:
        raise cy.err(f"contour {name} not found (no subprogram and no \"START:END\" labels of that name)") from None
    return unit, unit.lines


def contour_records(m, unit, lines, cy: Cycle) -> list:
    """Run the contour's blocks in a sandbox: their records, with the machine's state put back."""
    saved = ModalState.of(m)
    saved_program = m.unit_program
    saved_corners = m.corners
    m.corners = Corners()  # the contour's own chamfers and roundings; a move held before the cycle waits
    recs: list = []
    m.program.records = recs
    m.comp_buf = None
    m.feed = m.feed or 1.0
    m.unit_program = unit.program  # errors of the contour's blocks name its own file
    try:
        fr = Frame(unit, pc=0)
        for ln in lines:
            if not ln.stmts:
                continue
            if any(isinstance(st, Ret) for st in ln.stmts):  # RET ends a contour subprogram
                break
            for st in ln.stmts:
                # the sandbox runs the lines in order: a jump, a branch of IF/ELSE, a loop or a call
                # would be run straight through (both branches of an IF), so they are errors
                if isinstance(st, (Call, SubCall, Goto, Repeat, Branch, Case)) or (
                        isinstance(st, Word) and st.address == "G" and isinstance(st.value, Num)
                        and st.value.value in (41, 42, 73, 74, *range(81, 90))):
                    what = st.kind if isinstance(st, (Branch, Goto)) else "CASE" if isinstance(st, Case) else \
                        "REPEAT" if isinstance(st, Repeat) else f"G{st.value.value:g}" if isinstance(st, Word) \
                        else "a call"
                    raise m.error(ln.line, st.col, f"a contour for {cy.name} holds only G blocks: {what} is not allowed "
                                  "there (no jumps, control structures IF/WHILE/FOR/CASE, calls, G41/G42 or drilling cycles)")
            m.block(ln, fr, [fr])
            if m.plane != "XY":
                raise m.error(ln.line, 1, f"the contour for {cy.name} must lie in G17 (XY)")
        finish_corners(m)  # RND on the contour's last move: an error there
    finally:
        saved.restore(m)
        m.unit_program = saved_program
        m.corners = saved_corners
    return recs


def contour_elements(m, name: str, cy: Cycle):
    """The contour named by _KNAME (a subprogram or "START:END" labels) as (start, elements, the
    Src of each element) in the XY plane; its blocks run in a sandbox that emits nothing."""
    unit, lines = contour_lines(m, name, cy)
    name = name.strip()
    motions = [r for r in contour_records(m, unit, lines, cy) if isinstance(r, canon.MOTIONS)]
    if not motions:
        raise cy.err(f"contour {name} has no moves")
    start = (motions[0].end[0], motions[0].end[1])
    elems, srcs = [], []
    for r in motions[1:]:
        s, e = (r.start[0], r.start[1]), (r.end[0], r.end[1])
        if isinstance(r, canon.Arc):  # a full circle: its two halves
            pieces = arc_elems(s, e, (r.center[0], r.center[1]), r.clockwise, r.full_turn)
            elems.extend(pieces)
            srcs.extend([r.src] * len(pieces))
        elif _norm(_sub(e, s)) > 1e-9:
            elems.append(Elem("L", s, e))
            srcs.append(r.src)
    if not elems:
        raise cy.err(f"contour {name} has a start point but no elements")
    return start, elems, srcs


def contour_error(cy: Cycle, src: Src, msg: str) -> CutsimError:
    """An error of the contour at its own line (and file), naming the cycle's call."""
    return CutsimError(src.program, src.line, src.col, f"{cy.name} (called at line {cy.line}): {msg}")


def cycle72(cy: Cycle):
    m = cy.m
    cy.unsigned("_SDIS", "_MID", "_FAL", "_FALD", "_LP1", "_LP2")
    rl = int(cy["_RL"]) if "_RL" in cy.given else 41
    if rl not in (40, 41, 42):
        raise cy.err(f"_RL must be 40, 41 or 42 (got {cy['_RL']:g})")
    if rl != 40:
        cy.need_radius()
    v = cy["_VARI"]
    if v < 0 or v != int(v):
        raise cy.err("_VARI must be a whole number without a sign")
    units = int(v) % 10
    if units not in (0, 1, 2):
        raise cy.err(f"_VARI units digit must be 0 (complete), 1 (roughing) or 2 (finishing), got {units}")
    _, elems, srcs = contour_elements(m, cy["_KNAME"], cy)
    side = {40: 0, 41: 1, 42: -1}[rl]
    fal = cy["_FAL"] if rl != 40 else 0.0

    def path(extra):
        try:
            chain = offset_chain(elems, side * (cy.rt + extra))
        except OffsetError as e:
            raise contour_error(cy, srcs[e.index], f"contour element {e.index + 1}: {e}") from None
        return [e for e, _ in chain]
    top, bottom, fald = cy["_RFP"], cy["_DP"], cy["_FALD"]
    npass = ((n_levels(top, bottom + fald, cy["_MID"]) if units in (0, 1) else 0)
             + (n_levels(top, bottom, cy["_MID"]) if units == 2 or (units == 0 and (fal > 0 or fald > 0)) else 0))
    budget(cy, npass * (2 * len(elems) + 12), [(npass, f"passes for infeeds of at most _MID {cy['_MID']:g}"),
                                               (len(elems), "contour elements")])
    passes = []
    if units in (0, 1):
        for lv in cy.levels(top, bottom + fald, cy["_MID"]):
            passes.append((path(fal), lv, cy["_FFP1"]))
    if units == 2 or (units == 0 and (fal > 0 or fald > 0)):
        fin = path(0.0)
        for lv in cy.levels(top, bottom, cy["_MID"]):
            passes.append((fin, lv, cy["_FF3"] or cy["_FFP1"]))
    safe = top + cy["_SDIS"]
    for k, (pth, lv, f) in enumerate(passes):
        app = _approach(pth, side, int(cy["_AS1"]) % 10 if cy["_AS1"] else 1, cy["_LP1"], True, cy)
        dep = _approach(pth, side, int(cy["_AS2"]) % 10 if cy["_AS2"] else 1, cy["_LP2"], False, cy)
        s = app[0].start if app else pth[0].start
        if k == 0:
            cy.start(cy["_RTP"], s)
        else:
            cy.rapid(s, cy.m.pos[2])
        cy.rapid(s, safe)
        cy.feed_to(s, lv, cy["_FFD"])
        for e in app + pth + dep:
            cy.run_elem(e, lv, f)
        cy.rapid(cy.pos2(), safe)
    cy.finish(cy["_RTP"])


def _approach(pth, side, kind, lp, start: bool, cy: Cycle):
    """Approach (start=True) to the path's first point or departure from its last: 1 straight along
    the tangent, 2 quarter circle, 3 semicircle of radius _LP on the tool's side."""
    if lp <= 0:
        return []
    e = pth[0] if start else pth[-1]
    p = e.start if start else e.end
    t = tangent(e, not start)
    if kind not in (1, 2, 3):
        raise cy.err(f"approach/retract mode must be 1 (straight), 2 (quarter circle) or 3 (semicircle), got {kind}")
    if kind == 1 or side == 0:
        q = (p[0] - lp * t[0], p[1] - lp * t[1]) if start else (p[0] + lp * t[0], p[1] + lp * t[1])
        return [Elem("L", q, p)] if start else [Elem("L", p, q)]
    n = _left(t) if side > 0 else (t[1], -t[0])  # towards the tool side, away from the contour
    c = (p[0] + lp * n[0], p[1] + lp * n[1])
    cw = side < 0
    if kind == 2:
        q = (c[0] - lp * t[0], c[1] - lp * t[1]) if start else (c[0] + lp * t[0], c[1] + lp * t[1])
    else:
        q = (c[0] + lp * n[0], c[1] + lp * n[1])
    return [Elem("A", q, p, c, cw)] if start else [Elem("A", p, q, c, cw)]


RUNNERS = {"SLOT1": slot1, "SLOT2": slot2, "POCKET1": pocket1, "POCKET2": pocket2, "POCKET3": pocket3,
           "POCKET4": pocket4, "CYCLE71": cycle71, "CYCLE72": cycle72}


def run_cycle(m, name: str, args, src: Src, col: int, label: str | None = None) -> None:
    """Run the cycle ``name`` called at ``src`` (column ``col``) with evaluated ``args``
    [(value or None, column)] on the machine ``m`` (a Sinumerik interpreter); ``label`` names it in
    the messages (the ISO shell's "G83 (CYCLE83)")."""
    label = label or name
    if m.comp_buf is not None:
        raise m.error(src.line, 1, f"{label} cannot run with radius compensation G41/G42 on: program G40 first")
    if m.plane != "XY" and name in DRILLING:
        g, axis = ("G18", "Y") if m.plane == "ZX" else ("G19", "X")
        raise m.error(src.line, 1, f"{label} in {g} drills along {axis}: the simulated tool stands along Z (a "
                      "vertical 3-axis machine), so drilling along another axis is not simulated; program the "
                      "holes in G17")
    if m.plane != "XY":
        raise m.error(src.line, 1, f"{label} is simulated in the G17 plane only")
    cy = Cycle(m, name, args, src, col, label)
    motion = m.motion
    RUNNERS[name](cy)
    m.motion = motion

