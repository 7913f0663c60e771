"""Roughing a G71/G72 profile with pockets (it steps away from the start point S along the stepping
axis and back) as LinuxCNC 2.9's rs274 prints it (docs/dialects/rs274ngc.md, "G70, G71, G72").

The cycle is worked out in a normalised frame: points are complex numbers ``a + b j``, ``a`` along the
cut (decreasing from the profile's start P0 to its end), ``b`` across it (P0 no higher than the end;
the passes step down from S). ``chain[0]`` is the line from S to P0 (offset by D), then the offset
profile and the closing line up to S's level. The tool goes down the profile while it dives; at each
pass level (S's level minus k I) it cuts from the profile to where the level meets the profile again,
escapes r (at most half the pass) up and back, goes r past the pass's start and back to it (a feed
inside a pocket, a rapid on the line from S); where the profile climbs it follows it, and where it
dives again (the next pocket) the passes resume on the same levels. G7x.1 follows the profile out
of the first pocket's bottom without cutting the later ones; G7x.2 goes down the profile at once and
cuts the pockets after the first.
"""
from __future__ import annotations

import math

NEAR = 1e-6  # rs274's tolerances, in program units of the normalised frame
ARC_NEAR = 1e-3


class Seg:
    """A line (``centre`` None) or an arc in the normalised frame."""

    def __init__(self, p0: complex, p1: complex, centre: complex | None = None, ccw: bool = False):
        self.p0, self.p1, self.centre, self.ccw = p0, p1, centre, ccw

    def on_arc(self, p: complex) -> bool:
        c = self.centre
        a = ((self.p0 - c).conjugate() * (p - c)).imag
        b = ((self.p1 - c).conjugate() * (p - c)).imag
        return a >= -NEAR and b <= NEAR if self.ccw else a <= NEAR and b >= -NEAR

    def levels(self, x: float) -> list[float]:
        """Where the level ``b = x`` meets the segment (a line along the level: both its ends)."""
        if self.centre is None:
            lo, hi = sorted((self.p0.imag, self.p1.imag))
            if lo > x + NEAR or hi < x - NEAR:
                return []
            if abs(self.p0.imag - self.p1.imag) < NEAR:
                return [self.p0.real, self.p1.real]
            t = (x - self.p0.imag) / (self.p1.imag - self.p0.imag)
            return [self.p0.real + t * (self.p1.real - self.p0.real)]
        c, r = self.centre, abs(self.p0 - self.centre)
        s = -(x - r - c.imag) * (x + r - c.imag)
        if s < -NEAR:
            return []
        s = math.sqrt(max(s, 0.0))
        return [p.real for p in (complex(c.real + s, x), complex(c.real - s, x)) if self.on_arc(p)]

    def top(self) -> complex:
        """Where a counter-clockwise arc climbing out stops: its end, or its top if it goes past it."""
        if self.p1.real < self.centre.real:
            return complex(self.centre.real, self.centre.imag + abs(self.p0 - self.centre))
        return self.p1


class Walker:
    """The tool's place in the normalised frame and the moves it makes (``out`` maps them back)."""

    def __init__(self, out, loc: complex):
        self.out, self.loc = out, loc

    def line(self, p: complex, fast: bool = False) -> None:
        self.out(("rapid" if fast else "feed"), p)
        self.loc = p

    def arc(self, s: Seg, p: complex) -> None:
        if abs(self.loc - p) > ARC_NEAR:
            self.out("arc", p, s.centre, s.ccw)
        self.loc = p

    def dive(self, s: Seg, x: float, fast: bool) -> bool:
        """Down the segment to the level ``x`` (or its end); True when it does not dive."""
        if s.centre is None:
            if s.p0.imag <= s.p1.imag + NEAR:  # level (but for rounding) or climbing
                return True
            if x < s.p1.imag:
                self.line(s.p1, fast)
                return False
            found = s.levels(x)
            if not found:
                raise ValueError("a roughing pass lies above the profile (not simulated)")
            self.line(complex(found[0], x), fast)
            return False
        if abs(self.loc - s.p1) < ARC_NEAR:
            return False
        found, c = s.levels(x), s.centre.real
        if s.ccw:
            if self.loc.real > c:
                return True
            self.arc(s, s.p1 if not found or found[-1] > c else complex(found[-1], x))
        else:
            if self.loc.real <= c:
                return True
            self.arc(s, s.p1 if not found or found[0] < c else complex(found[0], x))
        return False

    def climb(self, s: Seg) -> bool:
        """Up the segment; True when it dives again (a pocket begins: on a counter-clockwise arc
        always, after going up to its top)."""
        if s.centre is None:
            if s.p1.imag < s.p0.imag - NEAR:
                return True
            self.line(s.p1)
            return False
        if not s.ccw:
            if self.loc.real > s.centre.real:
                return True
            self.arc(s, s.p1)
            return False
        if self.loc.real < s.centre.real:
            return True
        self.arc(s, s.top())
        return True

    def climb_only(self, s: Seg) -> None:
        """G7x.1 after the first pocket's bottom: up the climbing parts met at the tool's level."""
        found = s.levels(self.loc.imag)
        if not found or (s.centre is None and s.p1.imag < s.p0.imag - NEAR):
            return
        if s.centre is None:
            self.line(complex(found[0], self.loc.imag))
            self.line(s.p1)
            return
        if (not s.ccw and found[-1] > s.centre.real) or (s.ccw and found[0] < s.centre.real):
            return
        self.line(complex(found[-1] if not s.ccw else found[0], self.loc.imag))
        self.arc(s, s.top() if s.ccw else s.p1)


def rough(chain: list[Seg], out, cycle: int, delta: float, r: float) -> None:
    """The roughing moves of the cycle (``cycle`` 0 for G7x, 1 for G7x.1, 2 for G7x.2)."""
    w = Walker(out, chain[0].p0)
    top = chain[0].p0.imag
    w.line(chain[0].p0, fast=True)
    p, tops = 0, [top]  # the levels the passes of a pocket step down from
    if cycle == 2:  # down the profile at once, then the pockets after the first
        while p < len(chain) and not w.dive(chain[p], -1e9, p == 0):
            p += 1
    while p is not None and p < len(chain):
        p = _pocket(w, chain, p, cycle, tops, delta, r)


def _pocket(w: Walker, chain: list[Seg], p: int, cycle: int, tops: list, delta: float, r: float):
    """Cut from segment ``p`` on: returns where the next pocket begins (None when done). G7x.2's
    passes step down from the top of the second pocket, and of each later one that starts higher
    than the pocket before; G7x's from S."""
    x = tops[-1]
    while p < len(chain):
        while x > w.loc.imag:
            x -= delta
        if w.dive(chain[p], x, p == 0):
            for q in range(p, len(chain)):
                if cycle == 1:
                    w.climb_only(chain[q])
                elif w.climb(chain[q]):
                    if cycle == 2 and w.loc.imag > tops[-1] and len(tops) > 1:
                        tops.pop()
                    if cycle == 2 and len(tops) == 1:
                        tops.append(w.loc.imag)
                    return q
            return None
        if w.loc.imag > x or abs(w.loc.imag - x) > NEAR:
            p += 1
            continue
        p, x = _level(w, chain, p, x, delta, r)
    return None


def _level(w: Walker, chain: list[Seg], p: int, x: float, delta: float, r: float):
    """One pass at the tool's level: to where it meets the profile ahead, escape, back."""
    here = w.loc
    for ip in range(p, len(chain)):
        found = chain[ip].levels(here.imag)
        if not found:
            continue
        dz = found[-1] if ip == p else found[0]
        dist = abs(dz - here.real)
        if dist < NEAR:
            if ip == p:
                continue
            return p + 1, x
        dest = complex(dz, here.imag)
        w.line(dest)
        e = min(1.0, dist / 2 / r) * r * (1 + 1j) if r > 0 else 0j
        w.line(dest + e, fast=True)
        w.line(here - e.conjugate(), fast=True)
        w.line(here, fast=p == 0)
        return p, x - delta
    raise ValueError("a roughing pass meets no profile (not simulated)")
