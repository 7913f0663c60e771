"""M19 [R-] [Q-] [P-]: spindle orientation, as LinuxCNC 2.9 takes it (checked with rs274).

R the angle (degrees, 0 to 360, default 0), Q the time to wait for it (seconds, more than 0),
P the direction (0 the shorter way, 1 clockwise, 2 counter-clockwise). The spindle stops there
(``#<_spindle_on>`` reads 0; its speed stays for the next M3/M4); nothing moves, and the angle has no
geometric effect (a synchronised move waits for the spindle's index after M3/M4 again). The words
are the block's: a G4 P or an arc's R in the same block reads them too, as rs274 shares them.
"""
from __future__ import annotations

from cutsim.interp.core import Group, Step


def run(m, st: Step) -> None:
    m.orient_words = ()
    for code, w in m.m_group(st, Group.SPINDLE):
        if code != 19:
            continue
        line = st.block.line
        r, q, p = (st.words.get(letter) for letter in "RQP")
        if r is not None and not 0.0 <= r.value <= 360.0:
            raise m.error(line, r.col, "M19: the angle R must be within 0 to 360 degrees")
        if q is not None and q.value <= 0.0:
            raise m.error(line, q.col, "M19: the time Q to wait for the orientation must be more than 0")
        if p is not None and p.value != int(p.value):
            raise m.error(line, p.col, "M19: the direction P must be a whole number (0, 1 or 2)")
        if p is not None and int(p.value) not in (0, 1, 2):
            raise m.error(line, p.col, "M19: the direction P must be 0 (the shorter way), 1 (clockwise) or 2 "
                          "(counter-clockwise)")
        m.orient_words = tuple(x for x in (r, q, p) if x is not None)
        m.spindle(m.src(st, w.col), 0, None)


def used(m, w) -> bool:
    """Whether word ``w`` of the block is one M19 read (so it is not a word nothing uses)."""
    return any(w is x for x in m.orient_words)
