"""Canned cycles G73 G74 G81 G82 G83 G84 G85 G86 G87 G88 G89 (with G98/G99 and L) and the arcs' geometry
(multi-turn arcs, R centres, the radius check), as LinuxCNC
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
from cutsim.interp.core.lexer import Word
from cutsim.interp.core.modal import PLANE_AXES

from . import exact, polar
from .tables import CYCLES, UVW_PLANES

CYCLE_CODES = frozenset(CYCLES)
DELTA_INCH = 0.010  # G73 chip-break retract and G83 re-approach clearance (inch)
INCH = 25.4
# LinuxCNC 2.9 (rs274, measured) accepts a centre arc whose radii differ by up to 0.02 * sqrt(2) program
# units in G21, 0.002 * sqrt(2) in G20, or by up to 0.1 % of the larger
ARC_ABS_TOL_MM, ARC_ABS_TOL_INCH, ARC_REL_TOL = 0.02 * math.sqrt(2), 0.002 * math.sqrt(2), 0.001
# and an R arc whose chord is longer than 2 R by up to 0.00005 in (0.00127 mm) in both units, as a half circle
RADIUS_TOL = 0.00005 * 25.4
LETTERS = "XYZ"


@dataclass
class CycleState:
    initial: float | None = None  # the initial level (mm, machine frame) of the current series
    initial_exact: float | None = None  # the same as rs274 holds it (program units, exact.py) or None
    code: float | None = None  # the cycle of the previous block (sticky words belong to it)
    r: float | None = None  # R as programmed (sticky)
    depth: float | None = None  # the hole-axis word as programmed (sticky)
    q: float | None = None
    p: float | None = None
    ijk: tuple | None = None  # G87's I J K as programmed (sticky)
    warned_manual: bool = False  # G88's manual retract warned about


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
        cy.initial, cy.initial_exact = m.base()[c], exact.value(m, c)
    cy.r = sticky(m, st, "R", cy.r, new_series, "R clearance plane")
    cy.depth = sticky(m, st, LETTERS[c], cy.depth, new_series, "hole depth")
    if code in (73, 83):
        cy.q = sticky(m, st, "Q", cy.q, new_series, "peck depth")
        if cy.q <= 0:
            raise m.error(line, 1, "Q (peck depth) must be more than 0")
    col = st.groups[MOTION].col if MOTION in st.groups else 1
    if code in (74, 82, 84, 86, 88, 89):
        pw = st.words.pop("P", None)
        if code == 88 and pw is None and (new_series or cy.p is None):
            raise m.error(line, col, "G88 needs the dwell time P")
        cy.p = pw.value if pw is not None else (0.0 if new_series or cy.p is None else cy.p)
    if code == 87:
        back_bore_words(m, st, new_series, col)
    cy.code = code
    if code in (86, 87, 88) and m.spindle_dir == 0:
        raise m.error(line, col, f"spindle not turning in G{code:g}")
    if code in (74, 84) and m.spindle_dir != (1 if code == 84 else -1):
        turning = {0: "not turning", 1: "turning clockwise", -1: "turning counter-clockwise"}[m.spindle_dir]
        raise m.error(line, col, f"spindle {turning} in G{code:g} (G84 taps with M3, G74 with M4)")
    if code == 74 and "L" in st.words:  # rs274 2.9 takes no L with G74 (its check lists the other cycles)
        raise m.error(line, st.words["L"].col, "G74 takes no repeat count L (LinuxCNC 2.9)")
    lw = st.words.pop("L", None)
    repeats = 1 if lw is None else m.whole(line, lw, "repeat count L")
    # R and Q are lengths in program units, never diameters: only the hole-axis word is an X word
    # that G7 reads as a diameter (LinuxCNC halves X words only)
    r = (cy.r * m.scale + m.shift(c)) if m.absolute else cy.initial + cy.r * m.scale
    unit = m.unit(c)
    z = (cy.depth * unit + m.shift(c)) if m.absolute else r + cy.depth * unit
    if z > r:
        raise m.error(line, 1, "the hole bottom lies above R in the canned cycle")
    rounds = polar.take(m, st) if polar.present(st) else None  # @ ^: each repeat from where the tool is
    words = {i: st.words.pop(LETTERS[i]) for i in (a, b) if LETTERS[i] in st.words}
    src = m.src(st)
    up, clear, clear_exact = levels(m, c, r)
    if up:  # to R from where the tool stands: up, or down when the tool is above an initial level under R
        m.rapid(src, point(m, {c: r}))
    # the first hole is approached where the tool is when that is above R, else at the retract level
    # (as rs274 2.9 moves)
    height = m.base()[c] if m.base()[c] > r else clear
    plane_exact = {i: exact.value(m, i) for i in (a, b)}
    for _ in range(repeats):
        hole = {c: height}
        if rounds is not None:
            x, y = polar.target(m, line, *rounds)
            words = {0: Word("X", x, "", 1), 1: Word("Y", y, "", 1)} if m.absolute else \
                {0: Word("X", x - m.program_value(0), "", 1), 1: Word("Y", y - m.program_value(1), "", 1)}
        for i, w in words.items():
            hole[i] = (w.value * m.unit(i) + m.shift(i)) if m.absolute else m.base()[i] + w.value * m.unit(i)
        m.check_position(line, point(m, hole), {i: w.col for i, w in words.items()})
        for i, w in words.items():  # rs274's own values of the hole's position (exact.py)
            v = plane_exact[i]
            plane_exact[i] = w.value if m.absolute else (None if v is None else v + w.value)
            if rounds is not None:
                plane_exact[i] = None
        m.rapid(src, point(m, hole))
        if height != r:
            m.rapid(src, point(m, {c: r}))
        body(m, st, src, code, c, r, z, clear)
        height = clear
    if code == 88:  # the operator retracts: rs274 goes on from the clear level after the block, no move
        if not cy.warned_manual:
            m.warn(src, "G88: the manual retract is not a move: after the block the tool is at the clear level "
                   "without having moved there (as LinuxCNC's interpreter goes on)")
            cy.warned_manual = True
        m.moved(point(m, {c: clear}))
    for i, v in plane_exact.items():
        exact.note(m, i, v, m.pos[i])
    exact.note(m, c, clear_exact, m.pos[c])


def levels(m, c: int, r: float) -> tuple[bool, float, float | None]:
    """Whether the initial level lies under R (the tool goes to R first), the clear level (mm) and
    the clear level as rs274 holds it (program units, or None). rs274 compares the initial level with
    R in its program units, to the last bit (exact.py): where cutsim knows its values it does the same,
    else it compares in mm (a last-bit difference after a tool change's arithmetic taken as equal, as
    rs274 found them)."""
    cy = m.cycle
    il = cy.initial_exact
    r_exact = cy.r if m.absolute else (None if il is None else il + cy.r)
    if c == 0 and m.lathe_diameter:
        il = r_exact = None
    up = il < r_exact if il is not None and r_exact is not None else cy.initial < r - 1e-9
    if not m.retract_old or up:
        return up, r, r_exact
    return up, cy.initial, il


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
        # the pecks counted in program units, as rs274 counts them (a last peck a hair above the bottom
        # and the bottom itself, where millimetres would round to the bottom at once)
        unit, shift = m.unit(c), m.shift(c)
        q, zu = m.cycle.q * m.scale / unit, (z - shift) / unit
        delta = DELTA_INCH * 25.4
        du = (r - shift) / unit
        while True:
            du = max(du - q, zu)
            depth = z if du <= zu else du * unit + shift
            feed(depth)
            if du <= zu:
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
    elif code == 87:
        back_bore(m, st, src, c, r, z, clear)
    elif code in (86, 88):  # G88: the manual retract is the operator's: the tool stays down (rs274)
        feed(z)
        direction = m.spindle_dir
        m.spindle(src, 0, None)
        if code == 86:
            rapid(clear)
        m.spindle(src, direction, None)
    elif code in (74, 84):  # tap in, the spindle reversed, feed out to the clear level, forward again
        feed(z)
        direction = m.spindle_dir
        m.spindle(src, 0, None)
        m.spindle(src, -direction, None)
        feed(clear)
        m.spindle(src, 0, None)
        m.spindle(src, direction, None)


def back_bore_words(m, st: Step, new_series: bool, col: int) -> None:
    """G87's I J K, each required in the first block of a G87 series (rs274 2.9) and kept after."""
    given = {letter: st.words.pop(letter) for letter in "IJK" if letter in st.words}
    if new_series or m.cycle.ijk is None:
        for letter in "IJK":
            if letter not in given:
                raise m.error(st.block.line, col, f"{letter} word missing with G87")
        m.cycle.ijk = (0.0, 0.0, 0.0)
    m.cycle.ijk = tuple(given[letter].value if letter in given else m.cycle.ijk[i] for i, letter in enumerate("IJK"))


def back_bore(m, st: Step, src: Src, c: int, r: float, z: float, clear: float) -> None:
    """G87 from the hole at R, as LinuxCNC 2.9 moves it: to the offset point (the I J K words of the
    plane's two axes, always from the hole), the spindle stopped (LinuxCNC orients it: not simulated),
    down to the bottom there, over to the hole, the spindle started, feed up to the back bore's top (the
    hole axis's word: absolute in G90, from the bottom in G91), back down to the bottom, stopped, out
    through the offset point to the clear level, back over the hole, the spindle started again."""
    a, b, _ = PLANE_AXES[m.plane]
    ijk = m.cycle.ijk
    hole = m.base()
    off = {a: hole[a] + ijk[a] * m.scale, b: hole[b] + ijk[b] * m.scale}
    top = z + ijk[c] * m.scale if not m.absolute else ijk[c] * m.scale + m.shift(c)
    direction = m.spindle_dir

    def at(values, feed=False):
        (m.linear_to(st, point(m, values)) if feed else m.rapid(src, point(m, values)))

    at({**off, c: r})
    m.spindle(src, 0, None)
    at({**off, c: z})
    at({a: hole[a], b: hole[b], c: z})
    m.spindle(src, direction, None)
    at({c: top}, feed=True)
    at({c: z}, feed=True)
    m.spindle(src, 0, None)
    at({**off, c: z})
    at({**off, c: clear})
    at({a: hole[a], b: hole[b], c: clear})
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


def check_radii(m, line: int, start, end, centre, a: int, b: int) -> None:
    r0 = math.hypot(start[a] - centre[a], start[b] - centre[b])
    r1 = math.hypot(end[a] - centre[a], end[b] - centre[b])
    err = abs(r1 - r0)
    tol = ARC_ABS_TOL_MM if m.scale == 1.0 else ARC_ABS_TOL_INCH * INCH
    if err > tol and err > ARC_REL_TOL * max(r0, r1):
        raise m.error(line, 1, f"radius to end of arc differs from radius to start ({r0:.4f} mm, {r1:.4f} mm)")

def radius_centre(m, st: Step, start, end, r: float, clockwise: bool, col: int) -> list:
    a, b, _ = PLANE_AXES[m.plane]
    dx, dy = end[a] - start[a], end[b] - start[b]
    chord = math.hypot(dx, dy)
    if chord < 1e-9:
        raise m.error(st.block.line, col, "an R arc needs an end point other than its start (use I/J/K for a circle)")
    half = chord / 2.0
    if abs(r) < half:
        if half - abs(r) > RADIUS_TOL:
            raise m.error(st.block.line, col, f"arc radius {abs(r) / m.scale:g} too small to reach the end point")
        h = 0.0
    else:
        h = math.sqrt(r * r - half * half)
    # centre to the right of start->end for a clockwise arc under 180 degrees (R > 0)
    side = -1.0 if clockwise else 1.0
    if r < 0:
        side = -side
    mx, my = start[a] + dx / 2.0, start[b] + dy / 2.0
    centre = list(start)
    centre[a] = mx - side * h * dy / chord
    centre[b] = my + side * h * dx / chord
    return centre

def arc_length(m, start, end, centre, clockwise: bool, turns: int) -> float:
    a, b, n = PLANE_AXES[m.plane]
    r = math.hypot(start[a] - centre[a], start[b] - centre[b])
    a0 = math.atan2(start[b] - centre[b], start[a] - centre[a])
    a1 = math.atan2(end[b] - centre[b], end[a] - centre[a])
    sweep = (a0 - a1) if clockwise else (a1 - a0)
    sweep %= 2 * math.pi
    if sweep < 1e-12:
        sweep = 2 * math.pi
    sweep += 2 * math.pi * (turns - 1)
    return math.hypot(r * sweep, end[n] - start[n])


def refuse_uvw(m, st: Step, code: float) -> None:
    """An arc or a canned cycle in G17.1-G19.1: they need the axes U V W (rs274 refuses them too)."""
    w = st.groups.get(MOTION) or next(st.words[a] for a in "XYZIJK" if a in st.words)
    plane = UVW_PLANES[m.plane]
    raise m.error(st.block.line, w.col, f"{'arcs' if code in (2, 3) else 'canned cycles'} in plane {plane} "
                  "need the axes U V W (not simulated)")
