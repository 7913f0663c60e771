"""What a lathe's spindle adds to the kinematics: the time of a feed per revolution under a constant
cutting speed (Sinumerik G96), and a thread whose lead changes linearly with the revolutions
(Sinumerik G34/G35) as chained constant-lead screws within the chordal tolerance.

Constant cutting speed ``v`` (m/min) at radius r (mm): n(r) = 1000·v / (2·pi·r) rpm, at most the
limit L (LIMS). A feed f (mm/rev) along a path then takes dt = ds / (f·n(r(s))) minutes, and 1/n is
max(1/L, 2·pi·r / (1000·v)): piecewise linear in s along a straight segment (r linear), so the
integral is exact by the trapezoid rule between the breakpoints (r = 0 and |r| = the radius where
the limit starts to act).

Varying lead: lead(n) = K + c·n after n revolutions, so the travel along the lead axis is
T(n) = K·n + c·n²/2. A screw of constant lead between n0 and n1 = n0 + dn (the chord of T over
that span) is off the true travel by at most |c|·dn²/8 (in the middle), so spans of
dn = sqrt(8·tol / |c|) keep every groove within the tolerance ``tol``.
"""
from __future__ import annotations

import math

MAX_PIECES = 100_000  # constant-lead screws one G34/G35 block may become


def inverse_speed(r: float, css: float, limit: float) -> float:
    """Minutes per revolution at radius ``r`` under the cutting speed ``css`` (m/min), limit rpm."""
    a = 1.0 / limit if limit > 0 else 0.0
    return max(a, 2.0 * math.pi * abs(r) / (1000.0 * css))


def css_minutes(radii, lengths, feed: float, css: float, limit: float) -> float:
    """Minutes to feed ``feed`` mm/rev along a polyline whose vertices lie at ``radii`` with segment
    ``lengths`` under the constant cutting speed ``css`` (m/min) limited to ``limit`` rpm (0: none)."""
    total = 0.0
    r_lim = 1000.0 * css / (2.0 * math.pi * limit) if limit > 0 else 0.0
    for k, length in enumerate(lengths):
        r0, r1 = float(radii[k]), float(radii[k + 1])
        if length <= 0.0:
            continue
        cuts = {0.0, 1.0}
        for level in (0.0, r_lim, -r_lim):
            if (r0 - level) * (r1 - level) < 0.0:
                cuts.add((level - r0) / (r1 - r0))
        s = sorted(cuts)
        for t0, t1 in zip(s, s[1:]):
            g0 = inverse_speed(r0 + (r1 - r0) * t0, css, limit)
            g1 = inverse_speed(r0 + (r1 - r0) * t1, css, limit)
            total += 0.5 * (g0 + g1) * (t1 - t0) * length
    return total / feed


def varying_spans(lead: float, change: float, travel: float, tol: float) -> list[tuple[float, float, float]]:
    """A thread of starting lead ``lead`` changing by ``change`` mm/rev² (signed) over ``travel`` mm,
    as constant-lead spans (travel at its start, travel at its end, revolutions) whose groove stays
    within ``tol`` of the true one (the module's rule). ValueError when the lead reaches 0 first or
    when more than MAX_PIECES spans would be needed."""
    sq = lead * lead + 2.0 * change * travel
    if -1e-9 * max(lead * lead, 1.0) < sq <= 0.0:  # a run-out that brakes to a standstill at its end
        sq = 0.0
    elif sq <= 0.0:
        raise ValueError(f"the lead {lead:g} changing by {change:g} per revolution reaches 0 before the end of the "
                         f"{travel:g} mm thread")
    total = (math.sqrt(sq) - lead) / change
    if total <= 0.0:
        raise ValueError(f"the lead {lead:g} changing by {change:g} per revolution does not advance")
    step = math.sqrt(8.0 * tol / abs(change))
    count = max(1, math.ceil(total / step - 1e-9))
    if count > MAX_PIECES:
        raise ValueError(f"the varying lead needs {count} constant-lead pieces within the tolerance {tol:g} mm "
                         f"(at most {MAX_PIECES})")
    out = []
    for k in range(count):
        n0, n1 = total * k / count, total * (k + 1) / count
        t0 = lead * n0 + 0.5 * change * n0 * n0
        t1 = travel if k == count - 1 else lead * n1 + 0.5 * change * n1 * n1
        out.append((t0, t1, n1 - n0))
    return out


def revolutions(lead: float, change: float, travel: float) -> float:
    """Revolutions a thread of starting lead ``lead`` (changing by ``change`` mm/rev²) turns over
    ``travel`` mm (the lead is checked by the interpreter: it stays above 0)."""
    if change == 0.0:
        return travel / lead
    sq = max(lead * lead + 2.0 * change * travel, 0.0)
    return (math.sqrt(sq) - lead) / change
