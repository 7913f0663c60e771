"""The thread passes of Sinumerik's thread cutting cycles CYCLE97 (one thread) and CYCLE98 (a chain
of three segments), planned as plain data: no interpreter state, no records, no meshes.

Given a cycle's parameters (by their manual names) the planner returns a ``ThreadPlan``: for every
start of a multi-start thread and every cut (roughing, finishing, idle) the infeed point, the
chained G33 segments (run-in, thread, run-out) with their lead, lead axis and the spindle angle each
starts at, the flank offset of the infeed and the retract point. The interpreter turns the plan's
``moves()`` into G0 and G33 records; everything the manual leaves open is decided here once and
written in docs/dialects/sinumerik-turning.md ("What cutsim assumes").

Coordinates: ``Point.x`` is a diameter (the cycles' DM values are diameters), ``Point.z`` the
longitudinal axis, both absolute in the G18 plane. Depths, allowances, run-in/run-out lengths and
the retraction distance are distances on the workpiece (radius), as the manual measures them.
Errors are ``ThreadParamError``: a ``ValueError`` naming the parameter, which the interpreter turns
into its error at the call (as the other cycles' checks read: ``CYCLE97: <message>``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .cycle import COARSE_PITCH
from .syntax import range_message

# coarse metric threads (ISO 261) M3..M60: CYCLE97's MPIT range reaches M60, the tapping cycles' M48
METRIC_PITCH: dict[int, float] = COARSE_PITCH
DEFAULT_RETRACT = 1.0  # mm: the lift above the thread when _VRT is 0 (manual: 1 mm)
MAX_IANG = 89.0  # degrees: beyond, tan() makes the flank offset meaningless
EPS = 1e-9

CYCLE97_NAMES = "PIT MPIT SPL FPL DM1 DM2 APP ROP TDEP FAL IANG NSP NRC NID VARI NUMT _VRT".split()
CYCLE98_NAMES = ("PO1 DM1 PO2 DM2 PO3 DM3 PO4 DM4 APP ROP TDEP FAL IANG NSP NRC NID PP1 PP2 PP3 VARI NUMT "
                 "_VRT").split()


class ThreadParamError(ValueError):
    """A thread cycle parameter out of its range; ``param`` is the parameter's manual name."""

    def __init__(self, param: str, message: str):
        super().__init__(message)
        self.param = param


# ---------------------------------------------------------------------------------------------
# the plan
@dataclass(frozen=True)
class Point:
    """A position in the G18 plane: ``x`` a diameter, ``z`` the longitudinal axis (absolute)."""

    x: float
    z: float

    @property
    def radius(self) -> float:
        return self.x / 2.0


@dataclass(frozen=True)
class Segment:
    """One G33 block of a pass: ``kind`` "run-in", "thread" or "run-out"; ``lead`` mm per spindle
    revolution along ``lead_axis`` ("Z" or "X", the latter measured on the radius); the spindle
    stands at ``start_angle`` degrees past its zero pulse when the segment begins (the pass's SF for
    the first segment; the angle the spindle has turned on to for the chained ones)."""

    kind: str
    start: Point
    end: Point
    lead: float
    lead_axis: str
    start_angle: float

    @property
    def travel(self) -> float:
        """The travel along the lead axis (mm, X on the radius)."""
        if self.lead_axis == "Z":
            return abs(self.end.z - self.start.z)
        return abs(self.end.x - self.start.x) / 2.0

    @property
    def turns(self) -> float:
        return self.travel / self.lead


@dataclass(frozen=True)
class Pass:
    """One cut of one start: G0 to ``approach`` (lift level), G0 in to ``infeed``, the chained G33
    ``path``, G0 out to ``retract`` (lift level). ``depth`` is the infeed below the thread line
    (mm on the radius for a longitudinal thread, along Z for a face thread), ``flank_offset`` the
    shift of the cut along the first segment's lead axis (signed, mm)."""

    start_index: int
    number: int  # 1-based within its start
    kind: str  # "rough" | "finish" | "idle"
    depth: float
    flank_offset: float
    sf: float  # degrees: the G33 start angle of this pass
    approach: Point
    infeed: Point
    path: tuple[Segment, ...]
    retract: Point


@dataclass(frozen=True)
class ThreadPlan:
    """Every pass of one cycle call in the order the controller cuts them (each start in turn, all
    its cuts; manual: "the whole sequence is repeated for each further thread turn"). ``home`` is
    where the cycle goes first with G0 and where it ends."""

    outside: bool
    face: bool
    starts: int
    home: Point
    passes: tuple[Pass, ...]

    def depths(self, start_index: int = 0) -> list[float]:
        return [p.depth for p in self.passes if p.start_index == start_index]

    def moves(self) -> list[tuple[str, object]]:
        """The plan as the interpreter emits it: ("G0", Point) and ("G33", Segment) in order, from
        the position before the cycle to ``home`` after the last pass."""
        out: list[tuple[str, object]] = [("G0", self.home)]
        for p in self.passes:
            out += [("G0", p.approach), ("G0", p.infeed)]
            out += [("G33", s) for s in p.path]
            out.append(("G0", p.retract))
        out.append(("G0", self.home))
        return out


def program_moves(plan: ThreadPlan, diameter: bool, y: float = 0.0) -> list[tuple]:
    """``plan.moves()`` in program values for the interpreter: ("G0", (x, y, z)) for a rapid and
    ("G33", (x, y, z), lead, lead_axis, start_angle) for a thread block, X a diameter under DIAMON
    (``diameter``) and a radius under DIAMOF; ``y`` is where the Y axis stands (it does not move).
    The arguments are those of ModalMachine.rapid and ModalMachine.synced."""
    def at(p: Point):
        return (p.x if diameter else p.radius, y, p.z)

    out: list[tuple] = []
    for kind, item in plan.moves():
        if kind == "G0":
            out.append(("G0", at(item)))
        else:
            out.append(("G33", at(item.end), item.lead, item.lead_axis, item.start_angle))
    return out


# ---------------------------------------------------------------------------------------------
# parameter checks
def _get(v: dict, name: str) -> float:
    val = v.get(name)
    if val is None:
        return 0.0
    if isinstance(val, str) or not math.isfinite(float(val)):
        raise ThreadParamError(name, f"{name} must be a number (got {val!r})")
    return float(val)


def _unsigned(v: dict, name: str) -> float:
    val = _get(v, name)
    if val < 0:
        raise ThreadParamError(name, f"{name} is written without a sign (got {val:g})")
    return val


def _count(v: dict, name: str, lo: int, hi: int) -> int:
    val = _get(v, name)
    if val != int(val) or not lo <= val <= hi:
        raise ThreadParamError(name, range_message(name, val, lo, hi) + " (a whole number)")
    return int(val)


def pitch(v: dict) -> float:
    """The lead of each start (mm/rev): PIT, or MPIT's coarse metric pitch (M3..M60); both given
    must agree (manual: "thread pitch wrong" otherwise)."""
    pit = _unsigned(v, "PIT")
    mpit = _get(v, "MPIT")
    from_size = None
    if mpit != 0:
        if mpit != int(mpit) or int(mpit) not in METRIC_PITCH:
            sizes = ", ".join(str(k) for k in METRIC_PITCH)
            raise ThreadParamError("MPIT", f"MPIT must be a metric thread size ({sizes}), got {mpit:g}")
        from_size = METRIC_PITCH[int(mpit)]
    if pit and from_size is not None and abs(pit - from_size) > 1e-9:
        raise ThreadParamError("MPIT", f"MPIT {mpit:g} (pitch {from_size:g}) and PIT {pit:g} contradict each "
                                       "other: give one of them")
    if not pit and from_size is None:
        raise ThreadParamError("PIT", "no thread pitch: give PIT (mm) or the thread size MPIT (3 for M3 .. 60 for M60)")
    return pit or from_size


@dataclass(frozen=True)
class Infeed:
    """The parameters every pass shares, checked: depth, allowance, cut counts, machining type,
    flank angle, starts, start offset and retraction distance."""

    tdep: float
    fal: float
    nrc: int
    nid: int
    outside: bool
    constant_area: bool
    iang: float
    alternating: bool
    starts: int
    nsp: float
    vrt: float
    app: float
    rop: float

    @classmethod
    def read(cls, v: dict) -> "Infeed":
        tdep = _unsigned(v, "TDEP")
        if tdep <= EPS:
            raise ThreadParamError("TDEP", "TDEP, the thread depth, must be greater than 0")
        fal = _unsigned(v, "FAL")
        if fal >= tdep - EPS:
            raise ThreadParamError("FAL", f"the finishing allowance FAL {fal:g} leaves nothing to rough out of "
                                          f"the thread depth TDEP {tdep:g}: FAL must be smaller")
        vari = _get(v, "VARI")
        if vari not in (1, 2, 3, 4):
            raise ThreadParamError("VARI", f"VARI must be 1, 2, 3 or 4 (got {vari:g}): the machining type is "
                                           "defined incorrectly")
        iang = _get(v, "IANG")
        if abs(iang) > MAX_IANG:
            raise ThreadParamError("IANG", range_message("IANG", iang, -MAX_IANG, MAX_IANG, "degrees"))
        nsp = _unsigned(v, "NSP")
        if nsp >= 360.0:
            raise ThreadParamError("NSP", range_message("NSP", nsp, 0, 359.9999, "degrees"))
        return cls(tdep, fal, _count(v, "NRC", 1, 10000), _count(v, "NID", 0, 10000), vari in (1, 3),
                   vari in (3, 4), abs(iang), iang < 0, max(1, _count(v, "NUMT", 0, 360)), nsp,
                   _unsigned(v, "_VRT") or DEFAULT_RETRACT, _unsigned(v, "APP"), _unsigned(v, "ROP"))

    def cuts(self) -> list[tuple[str, float]]:
        """(kind, depth) of every cut of one start: NRC roughing cuts down to TDEP - FAL, the
        finishing cut at TDEP (when FAL > 0), NID idle passes at TDEP.

        Constant infeed (VARI 1, 2): cut i reaches (TDEP - FAL)·i/NRC. Constant cutting cross-
        section (VARI 3, 4): the V profile's area to depth d grows as d², so equal areas per cut
        put cut i at (TDEP - FAL)·sqrt(i/NRC)."""
        rough = self.tdep - self.fal
        n = self.nrc
        frac = (lambda i: math.sqrt(i / n)) if self.constant_area else (lambda i: i / n)
        out = [("rough", rough * frac(i)) for i in range(1, n + 1)]
        if self.fal > EPS:
            out.append(("finish", self.tdep))
        out += [("idle", self.tdep)] * self.nid
        return out

    def flank_offsets(self, cuts: list[tuple[str, float]], taper: bool) -> list[float]:
        """The shift of each cut along the lead axis, against the cutting direction as positive
        side: the tip moves along the flank of the finished groove, (TDEP - depth)·tan(IANG) from
        the finishing position, so the finishing and idle cuts run on the nominal helix. IANG < 0
        alternates the side from cut to cut (cylindrical threads only: a taper gets one flank)."""
        t = math.tan(math.radians(self.iang))
        alternate = self.alternating and not taper
        return [(self.tdep - d) * t * (-1.0 if alternate and k % 2 else 1.0) + 0.0 for k, (_, d) in enumerate(cuts)]


# ---------------------------------------------------------------------------------------------
# geometry in (radius, z)
@dataclass(frozen=True)
class _Seg:
    p: tuple[float, float]  # (radius, z)
    q: tuple[float, float]
    lead: float
    axis: str  # "Z" | "X"


def _axis(p, q) -> str:
    """The lead axis of a segment: Z unless the taper is steeper than 45 degrees (manual: "the cycle
    decides ... longitudinal thread up to 45 degrees, face thread beyond")."""
    return "Z" if abs(q[1] - p[1]) >= abs(q[0] - p[0]) - EPS else "X"


def _along(s: _Seg) -> tuple[float, float]:
    """The segment's direction scaled to one mm of travel on its lead axis."""
    d = (s.q[0] - s.p[0], s.q[1] - s.p[1])
    k = abs(d[1]) if s.axis == "Z" else abs(d[0])
    return (d[0] / k, d[1] / k)


def _prolong(segs: list[_Seg], app: float, rop: float) -> list[tuple[str, _Seg]]:
    """Run-in APP before the first point and run-out ROP after the last, on the segments' lines,
    measured along their lead axes; (kind, segment) with the thread segments between."""
    out: list[tuple[str, _Seg]] = []
    first, last = segs[0], segs[-1]
    if app > EPS:
        u = _along(first)
        p = (first.p[0] - app * u[0], first.p[1] - app * u[1])
        out.append(("run-in", _Seg(p, first.p, first.lead, first.axis)))
    out += [("thread", s) for s in segs]
    if rop > EPS:
        u = _along(last)
        q = (last.q[0] + rop * u[0], last.q[1] + rop * u[1])
        out.append(("run-out", _Seg(last.q, q, last.lead, last.axis)))
    return out


def _wrap(angle: float) -> float:
    """An angle in [0, 360) degrees (a hair below 360 is 0)."""
    a = angle % 360.0
    return 0.0 if 360.0 - a < 1e-9 else a


def _shift(p, d):
    return (p[0] + d[0], p[1] + d[1])


def _pt(p) -> Point:
    return Point(2.0 * p[0], p[1])


class _Geometry:
    """The thread line (with run-in and run-out) and the directions of depth, flank offset and lift."""

    def __init__(self, segs: list[_Seg], inf: Infeed):
        self.face = segs[0].axis == "X"
        self.line = _prolong(segs, inf.app, inf.rop)
        # tapered: the points do not all lie at one depth-axis value (radius, or Z for a face thread)
        k = 1 if self.face else 0
        values = [p[k] for s in segs for p in (s.p, s.q)]
        self.taper = max(values) - min(values) > EPS
        # depth: towards the axis (outside) or away from it (inside); a face thread into the face (-Z
        # outside, +Z inside). The flank offset runs along the first segment's lead axis, its positive
        # side against the cutting direction; the lift is _VRT against the depth.
        sgn = -1.0 if inf.outside else 1.0
        self.down = (0.0, sgn) if self.face else (sgn, 0.0)
        u = _along(segs[0])
        self.back = (-math.copysign(1.0, u[0]), 0.0) if self.face else (0.0, -math.copysign(1.0, u[1]))
        self.lift = (-self.down[0] * inf.vrt, -self.down[1] * inf.vrt)
        self._check(inf)

    def _check(self, inf: Infeed) -> None:
        """Refuse a thread whose root, run-in, run-out or lift would cross the turning axis."""
        reach = inf.tdep * math.tan(math.radians(inf.iang)) if self.face else 0.0
        for kind, s in self.line:
            name = {"run-in": "APP", "run-out": "ROP"}.get(kind, "TDEP")
            for p in (s.p, s.q):
                if kind != "thread" and p[0] < -EPS:
                    raise ThreadParamError(name, f"the {kind} path {name} reaches beyond the turning axis "
                                                 f"(X {2 * p[0]:g})")
                if p[0] + self.down[0] * inf.tdep - reach < -EPS:
                    raise ThreadParamError("TDEP", f"the thread depth TDEP {inf.tdep:g} reaches beyond the "
                                                   f"turning axis at X {2 * p[0]:g}")
                if p[0] + self.lift[0] < -EPS:
                    raise ThreadParamError("_VRT", f"the retraction _VRT {inf.vrt:g} reaches beyond the "
                                                   "turning axis")

    def path(self, depth: float, offset: float, sf: float) -> tuple[Segment, ...]:
        """The chained G33 segments of a cut at ``depth`` shifted by ``offset``; the spindle angle
        goes on turning from ``sf`` by 360 degrees a lead of travel."""
        d = (self.down[0] * depth + self.back[0] * offset, self.down[1] * depth + self.back[1] * offset)
        out, angle = [], sf
        for kind, s in self.line:
            seg = Segment(kind, _pt(_shift(s.p, d)), _pt(_shift(s.q, d)), s.lead, s.axis, _wrap(angle))
            out.append(seg)
            angle += 360.0 * seg.turns
        return tuple(out)


def _plan(segs: list[_Seg], inf: Infeed) -> ThreadPlan:
    geo = _Geometry(segs, inf)
    cuts = inf.cuts()
    offsets = inf.flank_offsets(cuts, geo.taper)
    first_p, last_q = geo.line[0][1].p, geo.line[-1][1].q
    lift = geo.lift
    home = _pt(_shift(first_p, lift))
    passes = []
    for j in range(inf.starts):
        sf = _wrap(inf.nsp + j * 360.0 / inf.starts)
        for k, ((kind, depth), off) in enumerate(zip(cuts, offsets)):
            path = geo.path(depth, off, sf)
            shift = (geo.back[0] * off + lift[0], geo.back[1] * off + lift[1])
            passes.append(Pass(j, k + 1, kind, depth, off, sf, _pt(_shift(first_p, shift)), path[0].start,
                               path, _pt(_shift(last_q, shift))))
    return ThreadPlan(inf.outside, geo.face, inf.starts, home, tuple(passes))


def _budget(inf: Infeed, segments: int, max_moves: int | None, name: str) -> None:
    if max_moves is None:
        return
    moves = inf.starts * (inf.nrc + (1 if inf.fal > EPS else 0) + inf.nid) * (3 + segments) + 2
    if moves > max_moves:
        raise ThreadParamError("NRC", f"{name} would make about {moves:,} moves ({inf.starts} starts x "
                                      f"{inf.nrc + inf.nid} cuts), more than [simulation] max_blocks = {max_moves:,}")


# ---------------------------------------------------------------------------------------------
# the cycles
def plan_cycle97(v: dict, max_moves: int | None = None) -> ThreadPlan:
    """CYCLE97(PIT, MPIT, SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP, NRC, NID, VARI, NUMT,
    _VRT): one cylindrical, tapered or face thread from (DM1, SPL) to (DM2, FPL). ``v`` maps the
    manual's names to numbers; a missing name or None is an empty parameter (0)."""
    lead = pitch(v)
    inf = Infeed.read(v)
    p = (_get(v, "DM1") / 2.0, _get(v, "SPL"))
    q = (_get(v, "DM2") / 2.0, _get(v, "FPL"))
    for name, val in (("DM1", p[0]), ("DM2", q[0])):
        if val <= EPS:
            raise ThreadParamError(name, f"{name}, the thread diameter, must be greater than 0 (got {2 * val:g})")
    if abs(q[0] - p[0]) <= EPS and abs(q[1] - p[1]) <= EPS:
        raise ThreadParamError("FPL", "the thread has no length: FPL and DM2 give the starting point SPL, DM1 again")
    seg = _Seg(p, q, lead, _axis(p, q))
    _budget(inf, 3, max_moves, "CYCLE97")
    return _plan([seg], inf)


def plan_cycle98(v: dict, max_moves: int | None = None) -> ThreadPlan:
    """CYCLE98(PO1, DM1, PO2, DM2, PO3, DM3, PO4, DM4, APP, ROP, TDEP, FAL, IANG, NSP, NRC, NID, PP1,
    PP2, PP3, VARI, NUMT, _VRT): a chain of three thread segments P1-P2 (lead PP1), P2-P3 (PP2),
    P3-P4 (PP3), each longitudinal or face by its own taper, cut as chained G33 blocks without a
    stop. The depth runs along the first segment's depth direction for the whole chain."""
    inf = Infeed.read(v)
    pts = []
    for i in range(1, 5):
        r = _get(v, f"DM{i}") / 2.0
        if r <= EPS:
            raise ThreadParamError(f"DM{i}", f"DM{i}, the thread diameter, must be greater than 0 (got {2 * r:g})")
        pts.append((r, _get(v, f"PO{i}")))
    segs = []
    for i in range(3):
        name = f"PP{i + 1}"
        lead = _unsigned(v, name)
        if lead <= EPS:
            raise ThreadParamError(name, f"{name}, the lead of segment {i + 1}, must be greater than 0")
        p, q = pts[i], pts[i + 1]
        if abs(q[0] - p[0]) <= EPS and abs(q[1] - p[1]) <= EPS:
            raise ThreadParamError(f"PO{i + 2}", f"segment {i + 1} has no length: PO{i + 2}, DM{i + 2} repeat "
                                                 f"PO{i + 1}, DM{i + 1}")
        segs.append(_Seg(p, q, lead, _axis(p, q)))
    for i in (1, 2):  # a chain goes on: no segment turns back against the one before
        a, b = _along(segs[i - 1]), _along(segs[i])
        if a[0] * b[0] + a[1] * b[1] < -EPS:
            raise ThreadParamError(f"PO{i + 2}", f"segment {i + 1} (to PO{i + 2}, DM{i + 2}) runs back against "
                                                 f"segment {i}: a thread chain goes on in one direction")
    _budget(inf, 5, max_moves, "CYCLE98")
    return _plan(segs, inf)


# ---------------------------------------------------------------------------------------------
# G34 / G35
def varying_lead(start_lead: float, change: float, travel: float, increasing: bool) -> tuple[float, float]:
    """G34 (``increasing``) / G35: the lead grows or shrinks by ``change`` (F, mm/rev²) every
    revolution from ``start_lead`` (K or I). Over ``travel`` mm the end lead Ke satisfies
    Ke² = Ka² ± 2·F·travel (the lead is linear in the revolutions n: K(n) = Ka ± F·n, so the travel
    is Ka·n ± F·n²/2); returns (Ke, the revolutions turned, |Ke - Ka| / F, or travel / Ka when F is
    0). A G35 whose lead would reach zero before the end is refused, naming F."""
    if start_lead <= 0:
        raise ThreadParamError("K", f"the starting lead must be greater than 0 (got {start_lead:g})")
    if change < 0:
        raise ThreadParamError("F", f"F, the change of lead per revolution, is written without a sign (got {change:g})")
    if change == 0:
        return start_lead, travel / start_lead
    sq = start_lead * start_lead + (2.0 if increasing else -2.0) * change * travel
    if sq <= EPS:
        reach = start_lead * start_lead / (2.0 * change)
        raise ThreadParamError("F", f"G35 with F {change:g} brings the lead {start_lead:g} to zero after {reach:.4g} mm, "
                                    f"before the end of the {travel:g} mm thread")
    end = math.sqrt(sq)
    return end, abs(end - start_lead) / change
