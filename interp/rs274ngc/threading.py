"""G76, LinuxCNC's threading cycle, and the spindle-synchronised moves it shares with G33 (``g33``;
``g33_1`` rigid tapping).

The cycle starts at the drive line (where the tool is) and cuts passes towards the end Z:

- I: the thread crest from the drive line (negative: an outside thread, the tool goes down in X;
  positive: a bore, up in X); J: the first pass's depth below the crest; K: the full thread depth
  (K > J > 0). In G7 I, J and K are diameters (halved, as LinuxCNC 2.9 reads them).
- pass n cuts at depth J * n^(1/R) below the crest (R, the degression, at least 1) while that is
  short of K; then the full depth K once, and again for each spring pass H;
- Q: the compound slide angle: a pass at depth d starts (d - J') * tan(Q) further back in Z, where
  J' is the crest, so the tool feeds in along the flank; the end moves K * tan(Q) the other way so
  the last pass ends at Z;
- E: the length of the end tapers along Z, L: which tapers (1 the entry, 2 the exit, 3 both); a
  taper rises by K over E. The synchronised moves advance P (the pitch) along Z per revolution on
  the thread and on the tapers (LinuxCNC syncs the path: the taper's path lead is P * hypot(E, K)/E);
- each pass: rapid back to the retract line (as far out as the full depth), rapid in (or the entry
  taper), the thread along Z, the exit taper if asked for, rapid out; after the passes, a rapid to
  the block's end point.
"""
from __future__ import annotations

import math

from cutsim.interp.core import MOTION, Step
from cutsim.interp.core.lexer import Word

from .values import _L, _PI


def sync_to(m, src, end, path_lead: float, angle: float) -> float:
    """A spindle-synchronised move to ``end`` advancing ``path_lead`` mm along its path per spindle
    revolution (LinuxCNC syncs the path length), from spindle angle ``angle`` (degrees past the index).
    Recorded along the axis (X or Z) that travels more, with the lead scaled to it; a move to where
    the tool is records nothing. Returns the spindle angle at its end, where a following
    synchronised move goes on without waiting."""
    start = m.pos
    length = math.dist(start, end)
    if length == 0.0:
        return angle
    axis = 0 if abs(end[0] - start[0]) > abs(end[2] - start[2]) else 2
    m.synced(src, end, path_lead * abs(end[axis] - start[axis]) / length, "XYZ"[axis], angle % 360.0)
    return angle + 360.0 * length / path_lead


def word(m, st: Step, letter: str, default: float | None = None, integer: bool = False) -> float | None:
    """The value of the block's word ``letter`` (``default`` without it); H and L must be integers."""
    w = st.words.pop(letter, None)
    if w is None:
        return default
    if integer and w.value != int(w.value):
        raise m.error(st.block.line, w.col, f"G76 {letter} must be a whole number")
    return w.value


def g76(m, st: Step) -> None:
    """One G76 block (module docstring), its moves from the current position."""
    line = st.block.line
    col = st.groups[MOTION].col if MOTION in st.groups else 1
    if m.spindle_dir == 0:
        raise m.error(line, col, "spindle not turning in G76")
    pitch = word(m, st, "P")
    if pitch is None:
        raise m.error(line, col, "G76 needs the pitch P")
    if pitch <= 0:
        raise m.error(line, col, "G76 pitch P must be more than 0 (not simulated otherwise)")
    i, j, k = (word(m, st, letter) for letter in "IJK")
    if i is None or j is None or k is None:
        raise m.error(line, col, "G76 needs I, J and K")
    if i == 0 or j <= 0 or k <= j:
        raise m.error(line, col, "G76 needs I not 0, J more than 0 and K more than J")
    half = 2.0 if m.lathe_diameter else 1.0
    i, j, k = (v * m.scale / half for v in (i, j, k))
    springs = int(word(m, st, "H", 0.0, True))  # below 0: not even the one pass at full depth
    flags = int(word(m, st, "L", 0.0, True))
    if flags < 0:
        raise m.error(line, col, "G76 taper flags L must not be negative")
    degression = word(m, st, "R", 1.0)
    degression = 1.0 if degression < 1.0 else degression
    taper = max(word(m, st, "E", 0.0), 0.0) * m.scale
    q = word(m, st, "Q", 0.0)
    angle = float(_L(0.0 if q == -1 else q) * (_PI / _L(180)))
    end, _ = m.goal(st)
    m.check_left(st)
    start = tuple(m.pos)
    if end[2] > start[2]:
        angle, taper = -angle, -taper
    cut = Cut(m, m.src(st), start, i, k, pitch * m.scale, taper, flags, end[2] + k * math.tan(angle))
    crest, full = abs(i), abs(i) + k
    n, depth = 1, abs(i) + j
    while depth < full:
        cut.pass_at(depth, (depth - crest) * math.tan(angle))
        n += 1
        depth = crest + j * n ** (1.0 / degression)
    for _ in range(springs + 1):
        cut.pass_at(full, k * math.tan(angle))
    m.rapid(cut.src, end)


class Cut:
    """The passes of one G76 block (positions in mm, machine frame, X a radius)."""

    def __init__(self, m, src, start, i: float, k: float, pitch: float, taper: float, flags: int, target_z: float):
        self.m, self.src = m, src
        self.x0, self.y0, self.z0 = start
        self.side = 1.0 if i > 0 else -1.0  # a bore cuts outwards
        self.full = abs(i) + k
        self.k, self.pitch, self.taper, self.target_z = k, pitch, taper, target_z
        self.entry, self.exit = bool(taper and flags & 1), bool(taper and flags & 2)
        self.taper_pitch = pitch * math.hypot(taper, k) / abs(taper) if taper else pitch

    def x(self, depth: float) -> float:
        return self.x0 + self.side * depth

    def at(self, x: float, z: float) -> tuple:
        return (x, self.y0, z)

    def pass_at(self, depth: float, zoff: float) -> None:
        m, src = self.m, self.src
        back, z_in, z_out = self.x(depth - self.full), self.z0 - zoff, self.target_z - zoff
        m.rapid(src, self.at(back, z_in))
        spin = 0.0
        if self.entry:
            spin = sync_to(m, src, self.at(self.x(depth - self.k), z_in), self.taper_pitch, spin)
            spin = sync_to(m, src, self.at(self.x(depth), z_in - self.taper), self.taper_pitch, spin)
        else:
            m.rapid(src, self.at(self.x(depth), z_in))
        if self.exit:
            spin = sync_to(m, src, self.at(self.x(depth), z_out + self.taper), self.pitch, spin)
            sync_to(m, src, self.at(self.x(depth - self.k), z_out), self.taper_pitch, spin)
        else:
            sync_to(m, src, self.at(self.x(depth), z_out), self.pitch, spin)
        m.rapid(src, self.at(back, z_out))


def g33(m, st: Step) -> None:
    """G33 X- Z- K-: a spindle-synchronised straight move of lead K (program units)."""
    k = st.words.pop("K", None)
    if k is None or k.value <= 0:
        raise m.error(st.block.line, st.groups.get(MOTION, Word("G", 33, "33", 1)).col, "G33 needs a pitch K > 0")
    if m.spindle_dir == 0:
        raise m.error(st.block.line, k.col, "spindle not turning in G33")
    end, _ = m.goal(st)
    sync_to(m, m.src(st), end, k.value * m.scale, 0.0)


def g33_1(m, st: Step) -> None:
    """G33.1 Z- K-: rigid tapping, in along Z and out again at lead K."""
    k = st.words.pop("K", None)
    line = st.block.line
    if k is None or k.value <= 0:
        raise m.error(line, 1, "G33.1 needs a pitch K > 0")
    if m.spindle_dir == 0:
        raise m.error(line, k.col, "spindle not turning in G33.1")
    start = m.start_point()
    end, _ = m.goal(st)
    if any(abs(end[i] - start[i]) > 1e-9 for i in (0, 1)):
        raise m.error(line, 1, "G33.1 taps along Z only: X and Y must stay where they are")
    src = m.src(st)
    lead = k.value * m.scale
    m.synced(src, end, lead, "Z", 0.0)
    m.synced(src, start, lead, "Z", 0.0)
