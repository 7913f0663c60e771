"""Cutter radius compensation G40, G41/G42 (D: a tool of the tool table) and G41.1/G42.1 (D: the
diameter, L: a lathe tool's orientation) on LinuxCNC 2.9's rules: interp/core/comp_queue.py offsets
the moves one block behind; here the words, the radius and orientation, the codes LinuxCNC refuses
while it is on, and the records (docs/dialects/rs274ngc.md, "Cutter radius compensation").

State on the machine: ``comp_side`` (0 off, +1 left, -1 right: on even with radius 0, for the
refusals), ``comp`` (the compensator while the radius is not 0), ``comp_exit`` (where the tool stands
after G40: the next move starts there), ``comp_memory`` (LinuxCNC's queue start, kept across
selections as rs274 keeps it).
"""
from __future__ import annotations

import dataclasses
import math

from cutsim.interp import canon
from cutsim.interp.core import Group, Step
from cutsim.interp.core.comp_queue import QueuedComp
from cutsim.interp.core.compensation import nose_shift
from cutsim.interp.core.lexer import Word
from cutsim.interp.core.modal import PLANE_AXES

from .cycles import CYCLE_CODES, turn_ends

CODES = {40: 0, 41: 1, 42: -1, 41.1: 1, 42.1: -1}
# LinuxCNC's lathe tool orientations (L, tool table Q) number the tip positions for +X towards the
# operator; cutsim's cutting edge positions (docs/setup.md) for +X up: the same position mirrored in X
ORIENTATION_EDGE = {1: 4, 2: 3, 3: 2, 4: 1, 5: 5, 6: 8, 7: 7, 8: 6}


def init(m) -> None:
    m.comp_side, m.comp, m.comp_exit, m.comp_memory = 0, None, None, {}


def on_after(m, st: Step) -> bool:
    """Compensation is on when the block's later steps run (G41/G42 in it, or on and no G40)."""
    g = st.groups.get(Group.RADIUS_COMP)
    if g is None:
        return m.comp_side != 0
    return round(g.value, 4) != 40


def refuse(m, st: Step, w: Word, what: str, after: bool = True) -> None:
    """LinuxCNC refuses ``what`` while compensation is on (in this block's later steps when ``after``)."""
    if on_after(m, st) if after else m.comp_side:
        raise m.error(st.block.line, w.col, f"{what} with cutter radius compensation on (G40 first)")


def select(m, st: Step) -> None:
    """G40/G41/G42/G41.1/G42.1 of the block (after the tool change, before the tool length offset)."""
    g = st.g.pop(Group.RADIUS_COMP, None)
    if g is None:
        return
    code, line = round(g.value, 4), st.block.line
    if code == 40:
        finish(m, st)
        m.comp_side = 0
        return
    if m.comp_side:
        raise m.error(line, g.col, "cannot turn cutter radius compensation on when it is on (G40 first)")
    if m.plane not in ("XY", "ZX"):
        raise m.error(line, g.col, f"G{g.raw}: cutter radius compensation works in G17 and G18 only")
    side = CODES[code]
    d, l = st.words.pop("D", None), st.words.pop("L", None)
    if code in (41.1, 42.1):
        if d is None:
            raise m.error(line, g.col, f"G{g.raw} needs the tool diameter D")
        radius = d.value * m.scale / 2.0
        orientation = 0 if l is None else m.whole(line, l, "orientation L")
        if l is not None and m.plane != "ZX":
            raise m.error(line, l.col, f"G{g.raw} with an orientation L needs the plane G18")
        shift = _orientation_shift(orientation, abs(radius))
    else:
        number = m.tool_no if d is None else m.whole(line, d, "tool number D")
        if d is not None:
            m.known_tool(st, number, d)
        radius, shift, lathe_tool = _tool_radius(m, number)
        if lathe_tool and m.plane != "ZX":
            raise m.error(line, g.col, f"G{g.raw} with a lathe tool (tool table Q) needs the plane G18")
    if radius < 0:  # a negative diameter swaps the side (rs274)
        side, radius = -side, -radius
    m.comp_side = side
    if radius > 0:
        start = m.comp_exit or m.start_point()
        m.comp_exit = None
        m.comp = QueuedComp(side, radius, m.plane, start, shift, m.comp_memory, lambda *a, plane=m.plane: _out(m, plane, *a))


def _orientation_shift(orientation: int, radius: float) -> tuple:
    edge = ORIENTATION_EDGE.get(orientation)
    return (0.0, 0.0) if edge is None else nose_shift(edge, radius, "ZX")


def _tool_radius(m, number: int) -> tuple:
    """(radius, shift, lathe tool) of tool ``number``: the tool table's D and Q, else the setup's tool
    (a lathe tool's nose radius and cutting edge position)."""
    entry = m.tools.get(number, {})
    if "D" in entry or "Q" in entry:
        q = int(entry.get("Q", 0))
        radius = entry.get("D", 0.0) / 2.0
        return radius, _orientation_shift(q, abs(radius)) if m.plane == "ZX" else (0.0, 0.0), q != 0
    if m.cfg.machine_kind == "lathe" and number in m.cfg.tool_noses:
        r, edge = m.cfg.tool_noses[number]
        return r, nose_shift(edge, r, "ZX") if m.plane == "ZX" else (0.0, 0.0), False
    return float(m.cfg.tool_radii.get(number, 0.0)), (0.0, 0.0), False


def finish(m, st: Step) -> None:
    """G40 or the program's end: the last move ends at its offset end; the next one starts there."""
    if m.comp is None:
        return
    comp, m.comp = m.comp, None
    comp.finish(m.scale == 1.0, _error(m, st.block.line))
    m.comp_exit = comp.pos


def _error(m, line: int):
    return lambda message: m.error(line, 1, message)


def route(m, rec) -> bool:
    """A record on its way to the program: into the compensation while it is on (True: taken)."""
    if m.comp_exit is not None and isinstance(rec, canon.MOTIONS):
        start, m.comp_exit = m.comp_exit, None
        m.program.records.append(_with_start(rec, start))
        return True
    if m.comp is None:
        return False
    error = _error(m, rec.src.line)
    if isinstance(rec, (canon.Rapid, canon.Feed)):
        m.comp.line(rec, isinstance(rec, canon.Rapid), m.scale == 1.0, error)
    elif isinstance(rec, canon.MOTIONS):
        raise error("this move is not simulated under cutter radius compensation (G40 first)")
    else:
        m.comp.keep(rec)
    return True


def arc_taken(m, st: Step, start, end, centre, clockwise: bool, turns: int) -> bool:
    """An arc block under compensation (True: taken): the whole arc (all its turns) is one move. The
    move after G40 may not be an arc (rs274)."""
    if m.comp_exit is not None:
        g = st.groups.get(Group.MOTION)
        raise m.error(st.block.line, g.col if g else 1, "the move after G40 must be straight (G0 or G1), not an arc")
    if m.comp is None:
        return False
    a, b, _ = PLANE_AXES[m.plane]
    full = abs(end[a] - start[a]) < 1e-9 and abs(end[b] - start[b]) < 1e-9
    rec = canon.Arc(m.src(st), start, end, m.diameter, tuple(centre), m.plane, clockwise, full, m.feed, m.per_rev)
    m.comp.arc(rec, centre, -turns if clockwise else turns, m.scale == 1.0, _error(m, rec.src.line))
    m.moved(end)
    return True


def profile_read(m, end) -> None:
    """A G70 under compensation has read its profile, whose moves ended at ``end`` (programmed): rs274
    2.9 takes the tool's compensated position to be there (no move; the program position stays the
    cycle's start S): the cycle's next move is joined from there (measured with rs274, the G70 paragraph
    of docs/dialects/rs274ngc.md)."""
    if m.comp is not None:
        m.comp.jump(end)


def refuse_motion(m, st: Step, code: float) -> None:
    """Canned cycles, G33, G33.1 and G76 with compensation on (rs274 refuses all but some G33s); of the
    lathe cycles' blocks (G70-G72.2) G71 and G72 in rs274's words (it runs G70)."""
    w = st.groups.get(Group.MOTION) or next(st.words[a] for a in "XYZ" if a in st.words)
    lathe_cycle = st.motion == code and int(code) in (70, 71, 72)
    if lathe_cycle and code == 70:
        return
    if lathe_cycle:
        raise m.error(st.block.line, w.col, f"G{code:.1f} cannot be used with cutter compensation enabled")
    what = "canned cycles" if code in CYCLE_CODES else f"G{code:g}"
    raise m.error(st.block.line, w.col, f"{what}: not simulated with cutter radius compensation on (G40 first)")


def tool_change(m, st: Step, w: Word) -> None:
    """M6: refused while compensation is on; after G40 LinuxCNC re-reads where the tool is."""
    refuse(m, st, w, "M6: cannot change tools", after=False)
    if m.comp_exit is not None:
        m.moved(m.comp_exit)
        m.comp_exit = None


def _with_start(rec, start):
    return dataclasses.replace(rec, start=start)


def _out(m, plane: str, cut, start, end, centre) -> None:
    """A finished move of the compensator as records (an arc of n turns as n arcs)."""
    rec = cut.rec
    if cut.kind == "-":
        m.program.records.append(rec)
    elif cut.kind == "R":
        m.program.records.append(canon.Rapid(rec.src, start, end, rec.diameter))
    elif cut.kind == "L":
        m.program.records.append(canon.Feed(rec.src, start, end, rec.diameter, rec.feed, rec.per_rev))
    else:
        a, b, _ = PLANE_AXES[plane]
        cw = cut.turn < 0
        s = start
        # a programmed circle stays whole where its offset ends differ by less than rs274 prints
        whole = (abs(abs(cut.sweep) - 2 * math.pi * abs(cut.turn)) < 1e-9
                 and math.hypot(end[a] - start[a], end[b] - start[b]) < 1e-3)
        for e, c in turn_ends(start, end, centre, cw, abs(cut.turn), plane, whole):
            full = math.isclose(e[a], s[a], abs_tol=1e-9) and math.isclose(e[b], s[b], abs_tol=1e-9)
            m.program.records.append(canon.Arc(rec.src, s, e, rec.diameter, c, plane, cw, full, rec.feed, rec.per_rev))
            s = e
