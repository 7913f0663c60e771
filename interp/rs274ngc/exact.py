"""rs274's own program coordinates, to the last bit, where a decision turns on it.

LinuxCNC's interpreter keeps the current position in program units and moves it by arithmetic when
the G92 offsets change (G92.3: ``current + offset - stored``; ``4.569 + 25.831 - 25.831`` is
4.568999999999999). A canned cycle's initial level is such a position, and rs274 compares it with R
exactly: an initial level a last bit under R sends the tool to R first (down, when it stands above),
one equal to R does not. cutsim's positions are in the machine frame in mm, so the program value it
computes from them differs from rs274's in the last bits. This module keeps, per axis, the program
value as rs274 holds it where it is known: set by a move to a programmed value (G90 word, or a
known value plus a G91 word), by a canned cycle's clear level, by G92; carried through G92.1, G92.2
and G92.3 by rs274's arithmetic. It is trusted only while the machine position, the axis's offset and
the units are those it was noted with; any other change (G5x, G52, a tool length, G20/G21, a move it
did not note) leaves it unknown, and the callers compare in mm with a tolerance instead.
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Exact:
    # per axis: (program value, machine position, shift, mm per unit) when noted, else None
    values: list = field(default_factory=lambda: [None, None, None])
    g92: list = field(default_factory=lambda: [0.0, 0.0, 0.0])  # rs274's G92 offsets (program units)
    stored: list = field(default_factory=lambda: [0.0, 0.0, 0.0])  # its #5211-#5213 as G92.3 reads them
    units: float = 1.0  # the mm per program unit g92 and stored are in


def start(m) -> None:
    """At the start: G92 offsets from a parameter file are known only when 0."""
    m.exact = Exact()
    for i in range(3):
        m.exact.g92[i] = m.exact.stored[i] = 0.0 if m.g92[i] == 0.0 else None


def note(m, i: int, value: float | None, pos_at: float) -> None:
    """Axis ``i`` stands (or will, after the move being made) at ``pos_at`` (mm, machine frame), which
    rs274 holds as ``value`` program units (None: unknown)."""
    ok = value is not None and m.unit(i) == m.scale
    m.exact.values[i] = (value, pos_at, m.shift(i), m.scale) if ok else None


def value(m, i: int) -> float | None:
    """rs274's program value of axis ``i`` where it is known, else None."""
    e = m.exact.values[i]
    if e is None or e[1] != m.pos[i] or e[2] != m.shift(i) or e[3] != m.scale:
        return None
    return e[0]


def goal(m, i: int, w, end: float) -> None:
    """A move's end on axis ``i`` from its word ``w``: rs274 takes the word (G90) or adds it (G91)."""
    if m.absolute:
        note(m, i, w.value, end)
    else:
        v = value(m, i)
        note(m, i, None if v is None else v + w.value, end)


def before_g92(m) -> list:
    """The program values before a G92-family code; rs274's offsets dropped where cutsim's differ
    from them (G52, or #5211-#5213 written by the program)."""
    e = m.exact
    for i in range(3):
        if e.g92[i] is not None and abs(e.g92[i] * e.units - m.g92[i]) > 1e-7:
            e.g92[i] = None
        if e.stored[i] is not None and abs(e.stored[i] * e.units - m.params.numbered.get(5211 + i, 0.0)) > 1e-7:
            e.stored[i] = None
    return [value(m, i) for i in range(3)]


def forget_g92(m) -> None:
    m.exact.g92 = [None, None, None]
    m.exact.stored = [None, None, None]


def g92(m, code: float, words: dict, before: list) -> None:
    """After G92 (``words``), G92.1, G92.2 or G92.3, from the program values ``before`` it: rs274's
    arithmetic on its current position and offsets (G92: offset = current + offset - word)."""
    e = m.exact
    if e.units != m.scale:  # G20/G21 since: rs274 converted its offsets (0 stays 0), not followed here
        e.g92 = [v if v == 0.0 else None for v in e.g92]
        e.stored = [v if v == 0.0 else None for v in e.stored]
        e.units = m.scale
    for i in range(3):
        cur, off = before[i], e.g92[i]
        if code == 92:
            if i not in words:
                note(m, i, cur, m.pos[i])
                continue
            v = words[i].value
            e.g92[i] = None if cur is None or off is None else cur + off - v
            # rs274 keeps #5213 in the user's units: the same numbers in G20 on its inch machine; in G21
            # a round trip through inches not followed here
            e.stored[i] = e.g92[i] if m.scale != 1.0 else None
            note(m, i, v, m.pos[i])
            continue
        if code in (92.1, 92.2):
            new = None if cur is None or off is None else cur + off
            e.g92[i] = 0.0
            if code == 92.1:
                e.stored[i] = 0.0
        else:  # 92.3
            st = e.stored[i]
            new = None if cur is None or off is None or st is None else cur + off - st
            e.g92[i] = st
        note(m, i, new, m.pos[i])
