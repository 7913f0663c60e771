"""Limits of size of ISO general purpose metric threads from a designation such as
``M24x1.5-6g`` or ``M24x1.5-5H6H`` (ISO 965-1:1998, principles and basic data; docs/checks.md).

Basic sizes (ISO 68-1, ISO 724; H = sqrt(3)/2 P): pitch diameter d2 = D2 = d - 0.649519 P,
minor diameter D1 = d1 = d - 1.082532 P.

Fundamental deviations (micrometres, P in mm), ISO 965-1 clause 6:
  bolts   es_e = -(50 + 11 P), es_f = -(30 + 11 P), es_g = -(15 + 11 P), es_h = 0
  nuts    EI_G = +(15 + 11 P), EI_H = 0
Tolerances of grade 6 (clause 7; d the geometric mean of the limits of the diameter range holding
the nominal diameter, clause 7's ranges 0.99/1.4/2.8/5.6/11.2/22.4/45/90/180/355/600 mm):
  T_d(6)  = 180 P^(2/3) - 3.15 / sqrt(P)         major diameter of the bolt (grades 4, 6, 8)
  T_d2(6) = 90 P^0.4 d^0.1                       pitch diameter of the bolt (grades 3 to 9)
  T_D2    = 1.32 T_d2(6) x grade factor           pitch diameter of the nut (grades 4 to 8)
  T_D1(6) = 433 P - 190 P^1.22 (P < 1), 230 P^0.7 (P >= 1): minor diameter of the nut (4 to 8)
and for the other grades the ROUNDED grade 6 value times 0.5 (3), 0.63 (4), 0.8 (5), 1 (6),
1.25 (7), 1.6 (8), 2 (9), rounded again: grade k = r40(factor_k x r40(grade 6)) for T_d, T_d2 and
T_D1, and T_D2(k) = r40(1.32 x factor_k x rounded T_d2(6)). The values are rounded as the standard's
tables print them: to the nearest value of the R40 series of preferred numbers (ISO 3; nearest on a
logarithmic scale, i.e. to the exact 10^(k/40)), in whole micrometres below 100. The tables follow
that rule where the unrounded grade 6 value does not: T_D1 at P 1.5 is printed 190, 236, 300, 375,
475 for grades 4 to 8 (0.8 x 300 = 240 -> 236, where 0.8 x 305.5 = 244.4 would give 250), and
T_d2 of every grade as ASME B1.13M / Machinery's Handbook reprint ISO 965-1's table
(tests/reports/test_iso965_derived.py). ``PRINTED`` holds the grade 6 values where ISO 965-1's
tables differ from the formulas; the other grades follow from the printed value.
"""
from __future__ import annotations

import math
import re

# R40 values of one decade as ISO 965 prints them in micrometres (below 100 in whole micrometres)
R40 = (10, 11, 11, 12, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 24, 25, 26, 28, 30, 32, 34, 36, 38, 40,
       42, 45, 48, 50, 53, 56, 60, 63, 67, 71, 75, 80, 85, 90, 95)
R40_BIG = (100, 106, 112, 118, 125, 132, 140, 150, 160, 170, 180, 190, 200, 212, 224, 236, 250, 265, 280, 300,
           315, 335, 355, 375, 400, 425, 450, 475, 500, 530, 560, 600, 630, 670, 710, 750, 800, 850, 900, 950)
RANGES = (0.99, 1.4, 2.8, 5.6, 11.2, 22.4, 45.0, 90.0, 180.0, 355.0, 600.0)
GRADE_FACTOR = {3: 0.5, 4: 0.63, 5: 0.8, 6: 1.0, 7: 1.25, 8: 1.6, 9: 2.0}
GRADES = {"d": (4, 6, 8), "d2": (3, 4, 5, 6, 7, 8, 9), "D2": (4, 5, 6, 7, 8), "D1": (4, 5, 6, 7, 8)}
# (quantity, pitch) -> micrometres where the printed tables of ISO 965-1 differ from the rounding rule
PRINTED = {("es_g", 0.75): 22.0, ("T_D1(6)", 0.5): 140.0, ("T_D1(6)", 1.0): 236.0, ("T_d2(6) 2.8-5.6", 0.5): 75.0,
           ("T_d2(6) 2.8-5.6", 0.75): 90.0, ("T_d(6)", 4.0): 475.0, ("es_g", 0.4): 19.0, ("T_d(6)", 0.2): 56.0}

_DESIGNATION = re.compile(r"^M(\d+(?:\.\d+)?)x(\d+(?:\.\d+)?)-(\d)([efghGH])(?:(\d)([efghGH]))?$")


class DesignationError(ValueError):
    """A thread designation cutsim cannot read; the message says what is expected."""


def r40(x: float) -> float:
    """``x`` (micrometres, positive) rounded to the nearest R40 preferred number as ISO 965 prints it."""
    k = round(40.0 * math.log10(x))  # nearest 10^(k/40) on the logarithmic scale
    decade, i = divmod(k, 40)
    if decade >= 2:
        return float(R40_BIG[i] * 10 ** (decade - 2))
    return float(R40[i] * 10.0 ** (decade - 1))


def _range_mean(d: float) -> float:
    for lo, hi in zip(RANGES, RANGES[1:]):
        if lo < d <= hi:
            return math.sqrt(lo * hi)
    raise DesignationError(f"nominal diameter {d:g} mm is outside ISO 965-1's range (over 0.99 up to 600 mm)")


def _printed(name: str, p: float, value: float) -> float:
    return PRINTED.get((name, p), value)


def fundamental_deviation(letter: str, p: float) -> float:
    """es (bolts, e f g h) or EI (nuts, G H) in micrometres."""
    base = {"e": 50.0, "f": 30.0, "g": 15.0, "G": 15.0}.get(letter)
    if base is None:
        return 0.0
    v = _printed(f"es_{letter.lower()}", p, r40(base + 11.0 * p))
    return v if letter.isupper() else -v


def td2_grade6(d: float, p: float) -> float:
    """T_d2 of grade 6 (micrometres), rounded."""
    lo = max(x for x in RANGES if x < d) if d > RANGES[0] else RANGES[0]
    hi = RANGES[RANGES.index(lo) + 1] if lo in RANGES[:-1] else RANGES[-1]
    return _printed(f"T_d2(6) {lo:g}-{hi:g}", p, r40(90.0 * p ** 0.4 * _range_mean(d) ** 0.1))


def tolerance(quantity: str, grade: int, d: float, p: float) -> float:
    """T_d, T_d2, T_D2 or T_D1 (``quantity`` "d", "d2", "D2", "D1") of ``grade``, micrometres."""
    if grade not in GRADES[quantity]:
        raise DesignationError(f"tolerance grade {grade} does not exist for {quantity} "
                               f"(ISO 965-1: {', '.join(map(str, GRADES[quantity]))})")
    f = GRADE_FACTOR[grade]
    if quantity == "d2":
        return td2_grade6(d, p) if grade == 6 else r40(f * td2_grade6(d, p))
    if quantity == "D2":
        return r40(1.32 * f * td2_grade6(d, p))
    if quantity == "d":
        t6 = _printed("T_d(6)", p, r40(180.0 * p ** (2.0 / 3.0) - 3.15 / math.sqrt(p)))
    else:
        t6 = _printed("T_D1(6)", p, r40(230.0 * p ** 0.7 if p >= 1.0 else 433.0 * p - 190.0 * p ** 1.22))
    return t6 if grade == 6 else r40(f * t6)


def parse(designation: str) -> tuple[float, float, int, int, str]:
    """(nominal diameter, pitch, pitch-diameter grade, crest grade, position letter)."""
    m = _DESIGNATION.match(designation.strip())
    if not m:
        raise DesignationError(f"{designation!r} is not an ISO metric thread designation like M24x1.5-6g, "
                               "M24x1.5-6H, M24x1.5-4h6h or M24x1.5-5H6H (pitch always written)")
    d, p = float(m.group(1)), float(m.group(2))
    g2, pos = int(m.group(3)), m.group(4)
    gc, pos2 = (int(m.group(5)), m.group(6)) if m.group(5) else (g2, pos)
    if pos2 != pos:
        raise DesignationError(f"{designation!r}: both tolerance classes need the same position letter")
    if d <= 0 or p <= 0 or p > d / 2:
        raise DesignationError(f"{designation!r}: the pitch must be positive and at most half the diameter")
    return d, p, g2, gc, pos


def limits(designation: str) -> dict:
    """Limits of size (mm) of the thread ``designation``: ``inside`` (a nut: G, H) and, per
    "major_diameter", "pitch_diameter", "minor_diameter" [lowest, highest] with None where ISO 965-1 sets no limit
    (a nut's major diameter has no upper limit; a bolt's minor diameter only the upper limit of the
    basic flat-root form, d1 + es)."""
    d, p, g2, gc, pos = parse(designation)
    inside = pos.isupper()
    dev = fundamental_deviation(pos, p) / 1000.0
    d2, d1 = d - 0.649519053 * p, d - 1.082531755 * p
    if inside:
        t2, t1 = tolerance("D2", g2, d, p) / 1000.0, tolerance("D1", gc, d, p) / 1000.0
        lim = {"major_diameter": [d + dev, None], "pitch_diameter": [d2 + dev, d2 + dev + t2],
               "minor_diameter": [d1 + dev, d1 + dev + t1]}
    else:
        t2, td = tolerance("d2", g2, d, p) / 1000.0, tolerance("d", gc, d, p) / 1000.0
        lim = {"major_diameter": [d + dev - td, d + dev], "pitch_diameter": [d2 + dev - t2, d2 + dev],
               "minor_diameter": [None, d1 + dev]}
    rounded = {k: [None if v is None else round(v, 6) for v in lv] for k, lv in lim.items()}
    return {"designation": designation, "diameter": d, "pitch": p, "inside": inside, **rounded}
