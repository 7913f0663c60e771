"""The Sinumerik turning cycles in the interpreter: CYCLE97 and CYCLE98 (threads, planned by
``threading``), CYCLE93 (grooving), CYCLE94 (undercut DIN 509) and CYCLE96 (thread undercut DIN 76),
planned by ``grooving``, CYCLE95 (stock removal along a contour, ``stockremoval``), and CYCLE84's
rigid tapping on a lathe (``rigid_tap``). Each runs in G18 on a lathe (milling.run_cycle checks
the plane) and expands into plain records through the ModalMachine methods -- G0 ``rapid``, G1 ``linear``, G2/G3
``arc``, G33 ``synced`` with the start angle of each chained block -- every record carrying the
cycle block's Src.

The planners return plain data in the cycles' own terms (X a diameter, as the cycles' diameter
parameters are, whatever DIAMON/DIAMOF say); here X becomes the radius the lathe mode keeps its
position in (interp/sinumerik/lathe.py). A planner's ``ThreadParamError`` /
``GrooveParamError`` names the parameter; the error is raised at that argument's column as
``CYCLE97: <message>``. What the manual leaves open is in docs/dialects/sinumerik-turning.md.
"""
from __future__ import annotations

from ..canon import Arc, MOTIONS
from . import grooving, stockremoval
from .contour import contour_lines, contour_records
from .cycle import Cycle
from .turning import tap_move
from .threading import CYCLE97_NAMES, CYCLE98_NAMES, plan_cycle97, plan_cycle98, program_moves, ThreadParamError

# parameter lists (the Cycles manual's names, in order; Cycle fills the empty ones with 0 or "")
NAMES = {
    "CYCLE93": "SPD SPL WIDG DIAG STA1 ANG1 ANG2 RCO1 RCO2 RCI1 RCI2 FAL1 FAL2 IDEP DTB VARI _VRT _DN",
    "CYCLE94": "SPD SPL FORM _VARI _VRT",
    "CYCLE95": "NPP MID FALZ FALX FAL FF1 FF2 FF3 VARI DT DAM _VRT",
    "CYCLE96": "DIATH SPL FORM _VARI _VRT",
    "CYCLE97": " ".join(CYCLE97_NAMES),
    "CYCLE98": " ".join(CYCLE98_NAMES),
}
REQUIRED = {"CYCLE93": "SPD SPL WIDG DIAG", "CYCLE94": "SPD SPL FORM", "CYCLE95": "NPP VARI",
            "CYCLE96": "DIATH SPL FORM"}
STRINGS = {"CYCLE94": "FORM", "CYCLE95": "NPP", "CYCLE96": "FORM"}


def _fail(cy: Cycle, e: ValueError):
    """A planner's refusal at the column of the parameter it names."""
    col = cy.cols.get(getattr(e, "param", ""), cy.col)
    return cy.m.error(cy.line, col, f"{cy.label}: {e}")


def _y(cy: Cycle) -> float:
    return cy.m.pos[1]


def _thread(cy: Cycle, plan_fn, names) -> None:
    v = {n: cy[n] for n in names}
    try:
        plan = plan_fn(v, cy.m.cfg.max_blocks)
    except ThreadParamError as e:
        raise _fail(cy, e) from None
    m = cy.m
    for mv in program_moves(plan, False, _y(cy)):  # X a radius (the lathe mode keeps it so)
        if mv[0] == "G0":
            if tuple(m.pos) != mv[1]:
                m.rapid(cy.src, mv[1])
        else:
            m.synced(cy.src, mv[1], mv[2], mv[3], mv[4])


def cycle97(cy: Cycle) -> None:
    """Thread cutting: every pass of every start (threading.plan_cycle97)."""
    _thread(cy, plan_cycle97, CYCLE97_NAMES)


def cycle98(cy: Cycle) -> None:
    """Chained thread of three segments (threading.plan_cycle98)."""
    _thread(cy, plan_cycle98, CYCLE98_NAMES)


def rigid_tap(cy: Cycle, p, tap: tuple[float, float, int], steps: list[float], back: float, out: bool,
              retract) -> None:
    """CYCLE84 on a lathe (``tap``: the safety level, the pitch, the hand +1 right): G331 in to each
    depth of ``steps`` (z) with the spindle following the tap (right-hand: turning as under M3), G332
    back out on the same helix (back by ``back`` between steps, or out to the safety level with
    ``out``), the spindle direction restored, then ``retract`` (the drilling cycle's G0 to RTP)."""
    m, src = cy.m, cy.src
    safe, lead, hand = tap
    before = m.spindle_dir
    angle = cy["POSS"] % 360.0  # CYCLE84 stops the spindle at POSS (SPOS) before tapping
    for k, z in enumerate(steps):
        if k:
            up = safe if out else min(m.pos[2] + back, safe)
            tap_move(m, src, (p[0], p[1], up), lead, -hand, (-angle) % 360.0)
            angle = m.machine.lathe.tapped[3]
            angle = (-angle) % 360.0
        tap_move(m, src, (p[0], p[1], z), lead, hand, angle)
        angle = m.machine.lathe.tapped[3]
    tap_move(m, src, (p[0], p[1], safe), lead, -hand, (-angle) % 360.0)
    m.spindle_dir = before
    m.spindle(src, before, None)
    retract()


def _groove(cy: Cycle, plan_fn) -> None:
    """A grooving planner's moves: ("G0" | "G1", (x, z)), ("ARC", (x, z), (cx, cz), clockwise), x a
    diameter, and ("F", feed); the feed in force cuts them unless the cycle gives its own."""
    m = cy.m
    tool = grooving.ToolEdge.of(m)
    try:
        moves = plan_fn(cy.v, tool, m.cfg.max_blocks)
    except grooving.GrooveParamError as e:
        raise _fail(cy, e) from None
    k = 0.5  # the planner's diameters -> the radius the lathe mode keeps X as
    y = _y(cy)
    for mv in moves:
        if mv[0] == "F":  # the cycle's feed from here on (0: the feed in force)
            m.feed = mv[1] if mv[1] > 0 else cy.saved_feed
            continue
        x, z = mv[1]
        p = (x * k, y, z)
        if mv[0] == "G0":
            if tuple(m.pos) != p:
                m.rapid(cy.src, p)
        elif mv[0] == "G1":
            if tuple(m.pos) != p:
                m.linear(cy.src, p)
        else:
            c = mv[2]
            m.arc(cy.src, p, (c[0] * k, y, c[1]), mv[3])
    m.feed = cy.saved_feed


def cycle93(cy: Cycle) -> None:
    _groove(cy, grooving.plan_cycle93)


def cycle94(cy: Cycle) -> None:
    _groove(cy, grooving.plan_cycle94)


def cycle96(cy: Cycle) -> None:
    _groove(cy, grooving.plan_cycle96)


def _contour95(cy: Cycle):
    """CYCLE95's contour NPP (a subprogram or "START:END" labels) in G18: its start (radius, z) and
    its elements ("L", p, q) / ("A", p, q, centre, clockwise); the blocks run in a sandbox."""
    unit, lines = contour_lines(cy.m, str(cy["NPP"]), cy, "NPP")
    recs = [r for r in contour_records(cy.m, unit, lines, cy, "ZX") if isinstance(r, MOTIONS)]
    if len(recs) < 2:
        raise cy.m.error(cy.line, cy.cols["NPP"], f"CYCLE95: the contour {cy['NPP']} needs a start point and "
                         "at least one element")
    start = (recs[0].end[0], recs[0].end[2])
    elems = []
    for r in recs[1:]:
        p, q = (r.start[0], r.start[2]), (r.end[0], r.end[2])
        if isinstance(r, Arc):
            elems.append(("A", p, q, (r.center[0], r.center[2]), r.clockwise))
        elif abs(q[0] - p[0]) + abs(q[1] - p[1]) > 1e-9:
            elems.append(("L", p, q))
    return start, elems


def cycle95(cy: Cycle) -> None:
    start, elems = _contour95(cy)
    _groove(cy, lambda v, tool, limit: stockremoval.plan_cycle95(v, start, elems, tool, limit))


RUNNERS = {"CYCLE93": cycle93, "CYCLE94": cycle94, "CYCLE95": cycle95, "CYCLE96": cycle96, "CYCLE97": cycle97,
           "CYCLE98": cycle98}


def register(specs: dict, runners: dict, cycles: set, spec, turning: set) -> None:
    """Add the turning cycles to the cycles' tables (``spec`` is cycle._spec)."""
    for name, names in NAMES.items():
        specs[name] = spec(names, REQUIRED.get(name, ""), STRINGS.get(name, ""))
    runners.update(RUNNERS)
    cycles.update(NAMES)
    turning.update(NAMES)
