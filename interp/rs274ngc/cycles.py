"""Canned cycles G73 G81 G82 G83 G85 G86 G89 (with G98/G99 and L) and multi-turn arcs, as LinuxCNC
2.9 moves them (checked move by move against its rs274, docs/dialects/rs274ngc.md).

In plane G17 the hole axis is Z and the holes lie in XY; G18: axis Y, holes in ZX; G19: axis X,
holes in YZ. The initial level is the hole axis position where a series of cycle blocks began
(kept while the motion mode stays a cycle): G98 retracts to the higher of it and R, and under G91
R counts from it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from cutsim.interp.canon import Src
from cutsim.interp.core import MOTION, Step
from cutsim.interp.core.modal import PLANE_AXES

from .tables import CYCLES

CYCLE_CODES = frozenset(CYCLES)
DELTA_INCH = 0.010  # G73 chip-break retract and G83 re-approach clearance (inch)
LETTERS = "XYZ"


@dataclass
class CycleState:
    initial: float | None = None  # the initial level (mm, machine frame) of the current series
    code: float | None = None  # the cycle of the previous block (sticky words belong to it)
    r: float | None = None  # R as programmed (sticky)
    depth: float | None = None  # the hole-axis word as programmed (sticky)
    q: float | None = None
    p: float | None = None


def sticky(m, st: Step, letter: str, stored, new_series: bool, what: str):
    w = st.words.pop(letter, None)
    if w is not None:
        return w.value
    if stored is None or new_series:
        col = st.groups[MOTION].col if MOTION in st.groups else 1
        raise m.error(st.block.line, col, f"{what} ({letter}) unspecified in the canned cycle")
    return stored


def run(m, st: Step) -> None:
    """One cycle block: its holes (L repeats) with the preliminary move to R."""
    code, line = m.motion, st.block.line
    a, b, c = PLANE_AXES[m.plane]
    cy = m.cycle
    new_series = cy.code != code
    if cy.initial is None:
        cy.initial = m.base()[c]
    cy.r = sticky(m, st, "R", cy.r, new_series, "R clearance plane")
    cy.depth = sticky(m, st, LETTERS[c], cy.depth, new_series, "hole depth")
    if code in (73, 83):
        cy.q = sticky(m, st, "Q", cy.q, new_series, "peck depth")
        if cy.q <= 0:
            raise m.error(line, 1, "Q (peck depth) must be more than 0")
    if code in (82, 86, 89):
        pw = st.words.pop("P", None)
        cy.p = pw.value if pw is not None else (0.0 if new_series or cy.p is None else cy.p)
    cy.code = code
    if code == 86 and m.spindle_dir == 0:
        raise m.error(line, st.groups[MOTION].col if MOTION in st.groups else 1, "spindle not turning in G86")
    lw = st.words.pop("L", None)
    repeats = 1 if lw is None else m.whole(line, lw, "repeat count L")
    # R and Q are lengths in program units, never diameters: only the hole-axis word is an X word
    # that G7 reads as a diameter (LinuxCNC halves X words only)
    r = (cy.r * m.scale + m.shift(c)) if m.absolute else cy.initial + cy.r * m.scale
    unit = m.unit(c)
    z = (cy.depth * unit + m.shift(c)) if m.absolute else r + cy.depth * unit
    if z > r:
        raise m.error(line, 1, "the hole bottom lies above R in the canned cycle")
    words = {i: st.words.pop(LETTERS[i]) for i in (a, b) if LETTERS[i] in st.words}
    src = m.src(st)
    if cy.initial < r:
        m.rapid(src, point(m, {c: r}))
    clear = r if not m.retract_old else max(cy.initial, r)
    # the first hole is approached where the tool is when that is above R, else at the retract level
    # (as rs274 2.9 moves)
    height = m.base()[c] if m.base()[c] > r else clear
    for _ in range(repeats):
        hole = {c: height}
        for i, w in words.items():
            hole[i] = (w.value * m.unit(i) + m.shift(i)) if m.absolute else m.base()[i] + w.value * m.unit(i)
        m.check_position(line, point(m, hole), {i: w.col for i, w in words.items()})
        m.rapid(src, point(m, hole))
        if height != r:
            m.rapid(src, point(m, {c: r}))
        body(m, st, src, code, c, r, z, clear)
        height = clear


def point(m, values: dict[int, float]) -> tuple:
    p = m.base()
    for i, v in values.items():
        p[i] = v
    return (p[0], p[1], p[2])


def body(m, st: Step, src: Src, code, c: int, r: float, z: float, clear: float) -> None:
    """The hole itself, from R down to the bottom ``z`` and back to ``clear``."""
    def feed(v):
        m.linear_to(st, point(m, {c: v}))

    def rapid(v):
        m.rapid(src, point(m, {c: v}))

    if code in (73, 83):
        q = m.cycle.q * m.scale
        delta = DELTA_INCH * 25.4
        depth = r
        while True:
            depth = max(depth - q, z)
            feed(depth)
            if depth <= z:
                break
            if code == 83:
                rapid(r)
                rapid(depth + delta)
            else:
                rapid(depth + delta)
        rapid(clear)
    elif code in (81, 82):
        feed(z)
        rapid(clear)
    elif code == 85:
        feed(z)
        feed(r)
        rapid(clear)
    elif code == 89:
        feed(z)
        feed(clear)
    elif code == 86:
        feed(z)
        direction = m.spindle_dir
        m.spindle(src, 0, None)
        rapid(clear)
        m.spindle(src, direction, None)


def arc_turns(m, src: Src, start, end, centre, clockwise: bool, turns: int) -> None:
    """An arc (helix) of ``turns`` (LinuxCNC's P) as arcs of one turn at most (``turn_ends``)."""
    for e, c in turn_ends(start, end, centre, clockwise, turns, m.plane):
        m.arc(src, e, c, clockwise)


def turn_ends(start, end, centre, clockwise: bool, turns: int, plane: str, whole: bool = False) -> list:
    """An arc of ``turns`` turns as (end, centre) of its pieces: whole turns first, then the rest, the
    axis normal to the plane moving in proportion to the angle turned (each centre at its piece's start).
    ``whole``: the rest is a whole turn too (a compensated circle whose ends differ by rounding)."""
    a, b, n = PLANE_AXES[plane]
    a0 = math.atan2(start[b] - centre[b], start[a] - centre[a])
    a1 = math.atan2(end[b] - centre[b], end[a] - centre[a])
    sweep = ((a0 - a1) if clockwise else (a1 - a0)) % (2 * math.pi)
    if sweep < 1e-9 or abs(sweep - 2 * math.pi) < 1e-9 or whole:
        sweep = 2 * math.pi
    total = sweep + 2 * math.pi * (turns - 1)
    centre_t = (centre[0], centre[1], centre[2])
    pieces, at = [], start
    for k in range(turns - 1):
        mid = list(start)
        mid[n] = start[n] + (end[n] - start[n]) * 2 * math.pi * (k + 1) / total
        pieces.append(((mid[0], mid[1], mid[2]), with_normal(centre_t, n, at[n])))
        at = pieces[-1][0]
    pieces.append((end, with_normal(centre_t, n, at[n])))
    return pieces


def with_normal(centre, n: int, v: float) -> tuple:
    c = list(centre)
    c[n] = v
    return (c[0], c[1], c[2])
