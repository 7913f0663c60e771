"""G70 (finishing) and G71/G71.1/G71.2, G72/G72.1/G72.2 (roughing) as LinuxCNC 2.9 moves them
(move for move the same as its rs274, docs/dialects/rs274ngc.md).

The profile is subroutine o<Q>, run when the cycle block is: its G0-G3 moves are collected, not
cut (G0 counts as G1; feeds and speeds in it do not act). Its first move goes to the profile's
start P0; the rest is the profile. D moves the profile towards the cycle's start point S (the
block's X Z, else where the tool is): each segment shifted by D, an arc of radius D about each
corner the offset goes round, neighbours cut back where they meet at the others.

Roughing (G71 along Z, passes stepping in X; G72 along X, passes stepping in Z; u the stepping
axis, v the cutting one): if S lies beyond P0 in the cutting direction it first moves (rapid)
level with P0. Pass k runs at u = S + k I towards P0 while short of P0: from the line S-P0 at
feed to the first point of the offset profile or the closing line (the profile's end to S's u),
then rapid back r = min(R, half the pass) in both axes, along v back to r past its start, and
to its start. Then the tool goes to P0 (rapid; a feed when no pass was cut) and follows the
offset profile and the closing line at feed. G7x.2 cuts the finishing contour alone; G7x.1 differs
from G7x only in pockets (a profile stepping away from S in u and back: pocket.py).

G70: P passes, pass k (1..P) at distance D - (D - E) k / P from the profile: rapid to S
(after the first), rapid to the start, the profile at feed; no closing line. Under cutter radius
compensation (G70 only: rs274 2.9 refuses G71/G72 there) every move of the cycle, of length 0 too,
goes through the compensation, and once the profile is read the tool's compensated position is taken
to be at the profile's end, as rs274 takes it (compensation.profile_read).
"""
from __future__ import annotations

import math

from cutsim.interp.core import MOTION, Step

from . import compensation, corners, pocket
from .profile import EPS, Seg, crossings, offset, side_of

LATHE_CYCLES = (70, 71, 71.1, 71.2, 72, 72.1, 72.2)
Z, X = 0, 1  # the profile's (z, x) coordinates
SMALL = 0.01  # program units: a convex corner whose offset d x sin(turn) is no more gets no arc (rs274 2.9)


def cycle(m, st: Step) -> None:
    code, line = m.motion, st.block.line
    col = st.groups[MOTION].col if MOTION in st.groups else 1
    if m.plane != "ZX":
        raise m.error(line, col, f"G{code:g} can only be used in the ZX plane (G18)")
    q = st.words.pop("Q", None)
    if q is None:
        raise m.error(line, col, f"G{code:g} needs the profile subroutine number Q")
    vals = {k: st.words.pop(k, None) for k in "DIREP"}
    allowed = "DEP" if code == 70 else "DIR"
    for k, w in vals.items():
        if w is not None and k not in allowed:
            raise m.error(line, w.col, f"{k} word with nothing that uses it in this block")
    start, _ = m.goal(st, letters=("X", "Z"))
    m.check_left(st)
    src = m.src(st)
    y = start[1]
    # under cutter radius compensation (G70 only) the move to S is made even of length 0: the entry
    m.rapid(src, start) if math.dist(m.pos, start) > 0 or m.comp is not None else None
    segs, end = capture(m, st, q, col)
    compensation.profile_read(m, end)
    s2 = (start[2], start[0])
    mm = m.scale
    try:
        if code == 70:
            passes = 1 if vals["P"] is None else m.whole(line, vals["P"], "G70 passes")
            if passes < 1:
                raise m.error(line, vals["P"].col, "G70 needs P of 1 or more passes")
            d = _num(vals["D"], 0.0) * mm
            e = _num(vals["E"], 0.0) * mm
            finish(m, st, src, y, segs, s2, d, e, passes)
        else:
            inc = _num(vals["I"], 1.0)
            if inc <= 0:
                raise m.error(line, col, "G7x: I (the cutting increment) must be more than 0")
            rough(m, st, src, y, segs, s2, code, _num(vals["D"], 0.0) * mm, inc * mm, _num(vals["R"], 0.5) * mm)
    except ValueError as e:
        raise m.error(line, col, f"G{code:g}: {e}") from None
    if m.motion == 0:  # the profile's last motion mode stays, G0 read as G1 (LinuxCNC 2.9)
        m.motion = 1


def check_profile(m, st: Step, has_axes: bool) -> None:
    """A block of a G70-G72 profile: straight moves and arcs only, absolute (LinuxCNC's
    incremental profiles are not simulated)."""
    col = st.groups[MOTION].col if MOTION in st.groups else 1
    finish = [st.words.pop(letter) for letter in "AC" if letter in st.words]
    if len(finish) == 2:
        raise m.error(st.block.line, finish[1].col, "A (fillet) and C (chamfer) on one corner of a G70-G72 profile")
    if not has_axes:
        return
    if finish:  # the corner at the end of this block's move (corners.py): noted before the move
        m.profile.append((finish[0].letter, finish[0].value * m.scale, st.block.line, finish[0].col))
    if m.motion not in (0, 1, 2, 3):
        raise m.error(st.block.line, col, f"G{m.motion:g} in a G70-G72 profile (G0-G3 only)")
    if not m.absolute:
        raise m.error(st.block.line, col, "G91 in a G70-G72 profile is not simulated")


def _num(w, default: float) -> float:
    return default if w is None else w.value


def capture(m, st: Step, q, col: int) -> tuple[list[Seg], tuple]:
    """Run the profile subroutine collecting its moves: the profile and where its moves end. The
    tool, the feed and the motion mode it leaves are restored, except the motion mode (LinuxCNC
    keeps the profile's)."""
    pos, feed, scale = tuple(m.pos), m.feed_units, m.feed_scale
    m.profile = []
    try:
        m.run_profile(q.value, st.block.line, q.col)
        moves, end = m.profile, tuple(m.pos)
    finally:
        m.profile = None
    m.moved(pos)
    m.feed_units, m.feed_scale = feed, scale
    if sum(1 for mv in moves if not isinstance(mv[0], str)) < 2:
        raise m.error(st.block.line, col, f"the profile o{q.value:g} needs a move to its start and at least one more")
    segs, finish, pending, first = [], {}, None, True  # segs[0]: the move to the start
    for move in moves:
        if isinstance(move[0], str):  # A or C for the corner after the next move
            pending = move
            continue
        p0, p1, centre, clockwise = move
        a, b = (p0[2], p0[0]), (p1[2], p1[0])
        if not first and centre is None and math.dist(a, b) < 1e-7:
            pending = None
            continue
        # the move to the start is kept until the corners are made: A or C on it rounds or cuts the
        # corner at the profile's start with the line from the cycle's start point (rs274 2.9)
        first = False
        segs.append(Seg(a, b, None if centre is None else (centre[2], centre[0]), not clockwise))
        if pending is not None:
            finish[len(segs) - 1], pending = pending, None
    if len(segs) < 2:
        raise m.error(st.block.line, col, f"the profile o{q.value:g} has no moves after its start")
    try:
        return corners.apply(segs, {i: (f[0], f[1]) for i, f in finish.items()})[1:], end
    except ValueError as e:
        f = finish[e.args[1] if len(e.args) > 1 else max(finish)]
        raise m.error(f[2], f[3], e.args[0]) from None


class Path:
    """Moves of a cycle in the machine frame (the profile's (z, x) with the block's Y). Under cutter
    radius compensation (G70) every move is made, of length 0 too, as rs274 makes them: each is
    one in its compensation's queue."""

    def __init__(self, m, st: Step, src, y: float):
        self.m, self.st, self.src, self.y = m, st, src, y
        self.least = -1.0 if m.comp is not None else EPS

    def at(self, p) -> tuple:
        return (p[X], self.y, p[Z])

    def rapid(self, p) -> None:
        end = self.at(p)
        if math.dist(self.m.pos, end) > self.least:
            self.m.rapid(self.src, end)

    def feed(self, p) -> None:
        end = self.at(p)
        if math.dist(self.m.pos, end) > self.least:
            self.m.feed = self.m.feed_for(self.st, math.dist(self.m.pos, end))
            self.m.linear(self.src, end)

    def arc(self, p1, centre, ccw: bool) -> None:
        m = self.m
        _, sweep = Seg((m.pos[2], m.pos[0]), tuple(p1), tuple(centre), ccw).angles()
        m.feed = m.feed_for(self.st, abs(sweep) * math.dist(p1, centre))
        end, c = self.at(p1), self.at(centre)
        if not compensation.arc_taken(m, self.st, m.start_point(), end, c, not ccw, 1):
            m.arc(self.src, end, c, not ccw)

    def follow(self, segs: list[Seg]) -> None:
        for s in segs:
            if s.centre is None:
                self.feed(s.p1)
            else:
                self.arc(s.p1, s.centre, s.ccw)


def level_start(path: Path | None, start, p0, v: int, vdir: int) -> list:
    """S beyond the profile's start P0 (not offset) along the cut: the tool first goes level with P0
    (rapid, unless ``path`` is None), and the cycle starts there."""
    s = list(start)
    if (s[v] - p0[v]) * vdir > 0:
        s[v] = p0[v]
        path.rapid(s) if path is not None else None
    return s


def finish(m, st, src, y, segs, start, d, e, passes) -> None:
    path = Path(m, st, src, y)
    # G70 levels S with P0 along Z when the profile runs along Z away from S (rs274 2.9: the first
    # pass's move to S goes there); the offset goes to the side of the levelled start, of S where that
    # lies on the first segment's line
    levelled = level_start(None, start, segs[0].p0, Z, _sign(segs[-1].p1[Z] - segs[0].p0[Z]))
    side = side_of(segs[0], levelled) or side_of(segs[0], start)
    start = levelled
    cut = cut_axis([Seg(tuple(start), segs[0].p0)] + segs)
    for k in range(1, passes + 1):
        prof = offset(segs, d - (d - e) * k / passes, side, SMALL * m.scale, cut)  # rs274's rounding at the 0.01 rule
        path.rapid(start)
        path.rapid(prof[0].p0)
        path.follow(prof)


def cut_axis(segs: list[Seg]) -> tuple[int, int]:
    """G70's axis along the cut and the profile's direction on it, as rs274 2.9 takes them: Z, unless
    a segment (the line from S to P0 among them) runs towards +Z (more than 0.001; an arc also when
    it does not keep to one side of its centre along X), then X."""
    def along_z(s: Seg) -> bool:
        dz = s.p1[Z] - s.p0[Z]
        if s.centre is None:
            return dz <= 1e-3
        entry, leave = s.p0[X] - s.centre[X], s.p1[X] - s.centre[X]
        if s.ccw:
            return entry >= -1e-3 and leave >= -1e-3 and dz <= -1e-3
        return entry <= 1e-3 and leave <= 1e-3 and dz <= -1e-3

    v = Z if all(along_z(s) for s in segs) else X
    return v, _sign(segs[-1].p1[v] - segs[0].p1[v])


def _sign(v: float) -> int:
    return 0 if abs(v) < 1e-7 else (1 if v > 0 else -1)


def monotonic(segs: list[Seg], u: int, v: int, su: int, sv: int) -> bool:
    """The profile runs one way in v; True when it steps away from the start in u (a pocket)."""
    away = False
    for s in segs:
        pts = s.points()
        for a, b in zip(pts, pts[1:]):
            away = away or (b[u] - a[u]) * su > 1e-7
            if (b[v] - a[v]) * sv < -1e-7:
                raise ValueError("the profile is not monotonic along the cut")
    return away


def rough(m, st, src, y, segs, start, code, d, inc, retract) -> None:
    path = Path(m, st, src, y)
    u, v = (X, Z) if code < 72 else (Z, X)
    vdir = _sign(segs[-1].p1[v] - segs[0].p0[v])
    if vdir == 0:
        raise ValueError("the profile ends where it starts along the cut")
    s = level_start(path, start, segs[0].p0, v, vdir)
    prof = offset(segs, d, side_of(segs[0], s) or side_of(segs[0], start), SMALL * m.scale, (v, vdir))
    p0, pe = prof[0].p0, prof[-1].p1
    su = _sign(p0[u] - s[u])
    if monotonic(segs, u, v, su, vdir):
        pockets(path, [Seg(tuple(s), p0)] + prof, code, u, v, inc, retract)
        return
    close = [0.0, 0.0]
    close[u], close[v] = s[u], pe[v]
    # the closing line back to S's u (none when S is level with P0: rs274 2.9)
    contour = prof + ([Seg(pe, tuple(close))] if su and math.dist(pe, close) > 1e-7 else [])
    cut = False
    if su and code not in (71.2, 72.2):
        k = 0
        while (p0[u] - (s[u] + k * inc * su)) * su > 1e-7:
            level = s[u] + k * inc * su
            vs = s[v] + (p0[v] - s[v]) * (level - s[u]) / (p0[u] - s[u])
            ahead = [w for seg in contour for w in crossings(seg, u, level) if (w - vs) * vdir > 1e-9]
            if not ahead:
                raise ValueError("a roughing pass meets no profile (not simulated)")
            ve = min(ahead, key=lambda w: (w - vs) * vdir)
            one_pass(path, u, v, level, vs, ve, su, vdir, min(retract, abs(ve - vs) / 2))
            cut = True
            k += 1
    (path.rapid if cut or code in (71.2, 72.2) else path.feed)(p0)
    path.follow(contour)


def pockets(path: Path, chain: list[Seg], code, u: int, v: int, inc: float, retract: float) -> None:
    """A profile with pockets (pocket.py): the normalised frame's a = sa v, b = sb u, sa and sb
    making the profile run down a and up b from P0 to its end (rs274's choice where level)."""
    p0, pe = chain[1].p0, chain[-1].p1
    sa = -1 if p0[v] < pe[v] else 1
    base = 1 if v == Z else -1  # G72 turns the plane a quarter: b = -z before any flip
    sb = -base if base * (p0[u] - pe[u]) > 0 else base
    flip = (sa < 0) ^ (sb < 0) ^ (v == X)

    def norm(p) -> complex:
        return complex(sa * p[v], sb * p[u])

    def back(c: complex) -> tuple:
        p = [0.0, 0.0]
        p[v], p[u] = sa * c.real, sb * c.imag
        return tuple(p)

    segs = [pocket.Seg(norm(s.p0), norm(s.p1), None if s.centre is None else norm(s.centre), s.ccw != flip)
            for s in chain]
    for a, b in zip(segs, segs[1:]):  # the offset's ends left apart (tangent but for the program's
        if abs(a.p1 - b.p0) < 1e-3:   # decimals) meet, as rs274's do
            if b.centre is None:
                b.p0 = a.p1
            elif a.centre is None:
                a.p1 = b.p0
    if segs[-1].p1.imag < segs[0].p0.imag:  # the closing line up to S's level
        segs.append(pocket.Seg(segs[-1].p1, complex(segs[-1].p1.real, segs[0].p0.imag)))

    def out(kind, p, centre=None, ccw=False):
        if kind == "arc":
            path.arc(back(p), back(centre), ccw != flip)
        else:
            (path.rapid if kind == "rapid" else path.feed)(back(p))

    cycle = {71: 0, 72: 0, 71.1: 1, 72.1: 1, 71.2: 2, 72.2: 2}[code]
    pocket.rough(segs, out, cycle, inc, retract)


def one_pass(path: Path, u, v, level, vs, ve, su, vdir, r) -> None:
    def pt(a, b):
        p = [0.0, 0.0]
        p[u], p[v] = a, b
        return p

    path.rapid(pt(level, vs))
    path.feed(pt(level, ve))
    path.rapid(pt(level - su * r, ve - vdir * r))
    path.rapid(pt(level - su * r, vs + vdir * r))
    path.rapid(pt(level, vs))
