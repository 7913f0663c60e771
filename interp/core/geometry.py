"""Arc geometry every dialect computes the same way: the centre from I/J/K offsets or from a
radius, and the angle an arc sweeps. X values are diameters when ``diameter`` (a lathe in diameter
mode): I and the radius are radii, so they count twice on X."""
from __future__ import annotations

import math

from .modal import PLANE_AXES

# How much longer than the diameter the chord of a radius-programmed circle may be and still be taken
# as the half circle: the programming resolution of coordinates (0.0001 mm), so that end points rounded
# to it do not make an exact half circle an error.
RADIUS_SLACK = 1e-4


class FullCircle(ValueError):
    """A circle given by its radius whose start and end coincide: its centre is not determined."""


class RadiusTooSmall(ValueError):
    """A circle radius shorter than half the chord; ``chord`` is the distance start -> end (mm)."""

    def __init__(self, chord: float):
        super().__init__(chord)
        self.chord = chord


def arc_centre(pos, plane: str, diameter: bool, offsets: dict[int, float]) -> list[float]:
    """The absolute centre of an arc whose centre is given incrementally from the start ``pos``
    (I/J/K: axis index -> value) in ``plane``. I is a radius even in diameter mode, so it counts
    twice on the X (diameter) value."""
    a, c, _ = PLANE_AXES[plane]
    centre = list(pos)
    for i in (a, c):
        if i in offsets:
            centre[i] = pos[i] + offsets[i] * (2.0 if (i == 0 and diameter) else 1.0)
    return centre


def radius_centre(start, end, r: float, plane: str, clockwise: bool, diameter: bool = False,
                  slack: float = RADIUS_SLACK) -> tuple:
    """The centre of the arc ``start`` -> ``end`` in ``plane`` with radius ``r``: the shorter arc for
    r > 0, the longer one for r < 0 (the centre on the left of the chord for a short counter-clockwise
    arc). Raises FullCircle when start and end coincide in the plane and RadiusTooSmall when the chord
    exceeds the diameter by more than ``slack`` (RADIUS_SLACK unless the dialect says)."""
    a, c, _ = PLANE_AXES[plane]
    k = 0.5 if diameter else 1.0  # X as a diameter

    def phys(p, i):
        return p[i] * k if i == 0 else p[i]
    s2 = (phys(start, a), phys(start, c))
    e2 = (phys(end, a), phys(end, c))
    dx, dy = e2[0] - s2[0], e2[1] - s2[1]
    chord = math.hypot(dx, dy)
    if chord < 1e-9:
        raise FullCircle()
    if chord > 2 * abs(r) + slack:
        raise RadiusTooSmall(chord)
    h = math.sqrt(max(r * r - chord * chord / 4, 0.0))
    side = (-1.0 if clockwise else 1.0) * (1.0 if r > 0 else -1.0)
    mx, my = (s2[0] + e2[0]) / 2, (s2[1] + e2[1]) / 2
    cen = list(start)
    ca, cc = mx + side * h * -dy / chord, my + side * h * dx / chord
    cen[a] = ca / k if a == 0 else ca
    cen[c] = cc / k if c == 0 else cc
    return (cen[0], cen[1], cen[2])


def sweep_degrees(start, end, centre, plane: str, clockwise: bool, diameter: bool) -> float:
    """The angle (degrees, in (0, 360]) an arc turns through from ``start`` to ``end`` about
    ``centre`` in ``plane``; start = end is a full circle. X values are diameters when ``diameter``."""
    a, c, _ = PLANE_AXES[plane]

    def phys(p, i):
        return p[i] / 2.0 if (i == 0 and diameter) else p[i]

    a0 = math.atan2(phys(start, c) - phys(centre, c), phys(start, a) - phys(centre, a))
    a1 = math.atan2(phys(end, c) - phys(centre, c), phys(end, a) - phys(centre, a))
    d = math.degrees(a1 - a0)
    if clockwise:
        d = -d
    d %= 360.0
    if d < 1e-9:
        d = 360.0
    return d
