"""Corner finishes in a G70-G72 profile: ``A`` (a fillet) and ``C`` (a chamfer) on a profile move
round or cut off the corner at its end, as LinuxCNC 2.9 does (checked against its rs274).

Both come from the circle of radius ``A`` (or ``C``) tangent to the two segments meeting at the
corner, on the inside of the turn: its centre is where the two segments moved that distance towards
the inside meet (the lines or circles, as the profile's offset finds its corners), its tangent
points are the centre's feet on the two segments. The segments end and start there; a fillet is the
arc between them about the centre, a chamfer the straight line (so ``C`` is the radius of the
circle whose chord it is: on a right angle it cuts ``C`` off each side).
"""
from __future__ import annotations

import math

from .profile import Seg, cross, meet, shifted

TOO_SMALL = 1e-7  # mm: a tangent point this close to a segment's far end still lies on it


def apply(segs: list, finish: dict) -> list[Seg]:
    """The profile (its first segment kept, even when it shrinks to nothing: the move to the start)
    with its corner finishes: ``finish`` maps the index of a segment to (letter, mm)
    for the corner at its end (before the next segment). A finish that cannot be made raises
    ValueError(text, index)."""
    out = list(segs)
    for i in sorted(finish, reverse=True):  # from the end: the indices before stay valid
        letter, d = finish[i]
        if i + 1 >= len(out):  # on the last move: no corner, nothing done (rs274 2.9 alike)
            continue
        prev, nxt = out[i], out[i + 1]
        turn = cross(prev.tangent(True), nxt.tangent(False))
        if abs(turn) < 1e-9:
            raise ValueError(f"{letter} on a corner without a turn (not simulated)", i)
        side = 1.0 if turn > 0 else -1.0
        centre = meet(shifted(prev, d, side), shifted(nxt, d, side), prev.p1)
        if centre is None:
            raise ValueError(f"the {'fillet' if letter == 'A' else 'chamfer'} {letter} does not fit its corner "
                             "(not simulated)", i)
        t0, t1 = foot(prev, centre), foot(nxt, centre)
        if not within(prev, t0) or not within(nxt, t1):
            raise ValueError(f"the {'fillet' if letter == 'A' else 'chamfer'} {letter} needs more room than its "
                             "corner's sides have (not simulated)", i)
        corner = Seg(t0, t1, centre, turn > 0) if letter == "A" else Seg(t0, t1)
        out[i:i + 2] = [trimmed(prev, p1=t0), corner, trimmed(nxt, p0=t1)]
    return out[:1] + [s for s in out[1:] if s.centre is not None or math.dist(s.p0, s.p1) > TOO_SMALL]


def foot(s: Seg, p) -> tuple:
    """The point of the segment's line or circle nearest ``p``."""
    if s.centre is None:
        t = s.tangent(False)
        k = (p[0] - s.p0[0]) * t[0] + (p[1] - s.p0[1]) * t[1]
        return (s.p0[0] + t[0] * k, s.p0[1] + t[1] * k)
    c, r = s.centre, s.radius
    n = math.dist(p, c)
    return (c[0] + (p[0] - c[0]) * r / n, c[1] + (p[1] - c[1]) * r / n)


def within(s: Seg, p) -> bool:
    """``p`` (on the segment's line or circle) lies between its ends."""
    if s.centre is None:
        t = s.tangent(False)
        k = (p[0] - s.p0[0]) * t[0] + (p[1] - s.p0[1]) * t[1]
        return -TOO_SMALL <= k <= math.dist(s.p0, s.p1) + TOO_SMALL
    a0, sweep = s.angles()
    ang = math.atan2(p[1] - s.centre[1], p[0] - s.centre[0])
    rel = (ang - a0) % (2 * math.pi) if sweep > 0 else (a0 - ang) % (2 * math.pi)
    return rel <= abs(sweep) + 1e-9 or rel >= 2 * math.pi - 1e-9


def trimmed(s: Seg, p0=None, p1=None) -> Seg:
    return Seg(p0 if p0 is not None else s.p0, p1 if p1 is not None else s.p1, s.centre, s.ccw)
