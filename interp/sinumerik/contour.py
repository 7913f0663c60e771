"""CYCLE72 (contour milling): the contour named by _KNAME run in a sandbox into elements, offset
and approached/departed as the cycle's parameters say.
"""
from __future__ import annotations

from dataclasses import dataclass

from .. import canon
from ..canon import Src
from ..core.compensation import _left, _norm, _sub, arc_elems, Elem, offset_chain, OffsetError, tangent
from ..errors import CutsimError
from .corners import Corners, finish as finish_corners
from .cycle import budget, Cycle, n_levels
from .syntax import Branch, Call, Case, Frame, Goto, Num, Repeat, Ret, SubCall, SubprogramMissing, Word


# ---------------------------------------------------------------------------------------------
@dataclass
class ModalState:
    """What running a contour's blocks in a sandbox changes on the machine, copied before and put
    back after (contour_elements)."""
    pos: list
    absolute: bool
    plane: str
    motion: int
    feed: float
    per_rev: bool
    records: list
    comp_buf: list | None
    warned_feed: bool
    executed: int

    @classmethod
    def of(cls, m) -> ModalState:
        return cls(list(m.pos), m.absolute, m.plane, m.motion, m.feed, m.per_rev, m.program.records, m.comp_buf,
                   m._warned_feed, m.executed)

    def restore(self, m) -> None:
        m.pos, m.absolute, m.plane, m.motion, m.feed, m.per_rev = (list(self.pos), self.absolute, self.plane,
                                                                  self.motion, self.feed, self.per_rev)
        m.program.records, m.comp_buf, m._warned_feed, m.executed = (self.records, self.comp_buf, self.warned_feed,
                                                                     self.executed)


def contour_lines(m, name: str, cy: Cycle, param: str = "_KNAME"):
    """The unit and the lines of the contour named by ``param`` (CYCLE72 _KNAME, CYCLE95 NPP): a
    subprogram or "START:END" labels."""
    name = name.strip()
    if not name:
        raise cy.err(f"{param} is empty: name the contour (subprogram or \"START:END\" labels)")
    if ":" in name:
        l1, l2 = [s.strip().upper() for s in name.split(":", 1)]
        for unit in [m.main, *m.subs.values()]:
            if l1 in unit.labels and l2 in unit.labels:
                return unit, unit.lines[unit.labels[l1]:unit.labels[l2] + 1]
        raise cy.err(f"contour {name}: the labels {l1} and {l2} are not both in the program")
    try:
        unit = m.find_sub(name.upper(), cy.line, cy.col)
    except SubprogramMissing:
        raise cy.err(f"contour {name} not found (no subprogram and no \"START:END\" labels of that name)") from None
    return unit, unit.lines


def contour_records(m, unit, lines, cy: Cycle, plane: str = "XY") -> list:
    """Run the contour's blocks in a sandbox: their records, with the machine's state put back. The
    contour lies in ``plane`` (CYCLE72: G17; CYCLE95: G18)."""
    saved = ModalState.of(m)
    saved_program = m.unit_program
    saved_corners = m.corners
    m.corners = Corners()  # the contour's own chamfers and roundings; a move held before the cycle waits
    recs: list = []
    m.program.records = recs
    m.comp_buf = None
    m.feed = m.feed or 1.0
    m.unit_program = unit.program  # errors of the contour's blocks name its own file
    try:
        fr = Frame(unit, pc=0)
        for ln in lines:
            if not ln.stmts:
                continue
            if any(isinstance(st, Ret) for st in ln.stmts):  # RET ends a contour subprogram
                break
            for st in ln.stmts:
                # the sandbox runs the lines in order: a jump, a branch of IF/ELSE, a loop or a call
                # would be run straight through (both branches of an IF), so they are errors
                if isinstance(st, (Call, SubCall, Goto, Repeat, Branch, Case)) or (
                        isinstance(st, Word) and st.address == "G" and isinstance(st.value, Num)
                        and st.value.value in (41, 42, 73, 74, *range(81, 90))):
                    what = st.kind if isinstance(st, (Branch, Goto)) else "CASE" if isinstance(st, Case) else \
                        "REPEAT" if isinstance(st, Repeat) else f"G{st.value.value:g}" if isinstance(st, Word) \
                        else "a call"
                    raise m.error(ln.line, st.col, f"a contour for {cy.name} holds only G blocks: {what} is not allowed "
                                  "there (no jumps, control structures IF/WHILE/FOR/CASE, calls, G41/G42 or drilling cycles)")
            m.block(ln, fr, [fr])
            if m.plane != plane:
                g = {"XY": "G17 (XY)", "ZX": "G18 (ZX)"}[plane]
                raise m.error(ln.line, 1, f"the contour for {cy.name} must lie in {g}")
        finish_corners(m)  # RND on the contour's last move: an error there
    finally:
        saved.restore(m)
        m.unit_program = saved_program
        m.corners = saved_corners
    return recs


def contour_elements(m, name: str, cy: Cycle):
    """The contour named by _KNAME (a subprogram or "START:END" labels) as (start, elements, the
    Src of each element) in the XY plane; its blocks run in a sandbox that emits nothing."""
    unit, lines = contour_lines(m, name, cy)
    name = name.strip()
    motions = [r for r in contour_records(m, unit, lines, cy) if isinstance(r, canon.MOTIONS)]
    if not motions:
        raise cy.err(f"contour {name} has no moves")
    start = (motions[0].end[0], motions[0].end[1])
    elems, srcs = [], []
    for r in motions[1:]:
        s, e = (r.start[0], r.start[1]), (r.end[0], r.end[1])
        if isinstance(r, canon.Arc):  # a full circle: its two halves
            pieces = arc_elems(s, e, (r.center[0], r.center[1]), r.clockwise, r.full_turn)
            elems.extend(pieces)
            srcs.extend([r.src] * len(pieces))
        elif _norm(_sub(e, s)) > 1e-9:
            elems.append(Elem("L", s, e))
            srcs.append(r.src)
    if not elems:
        raise cy.err(f"contour {name} has a start point but no elements")
    return start, elems, srcs


def contour_error(cy: Cycle, src: Src, msg: str) -> CutsimError:
    """An error of the contour at its own line (and file), naming the cycle's call."""
    return CutsimError(src.program, src.line, src.col, f"{cy.name} (called at line {cy.line}): {msg}")


def cycle72(cy: Cycle):
    m = cy.m
    cy.unsigned("_SDIS", "_MID", "_FAL", "_FALD", "_LP1", "_LP2")
    rl = int(cy["_RL"]) if "_RL" in cy.given else 41
    if rl not in (40, 41, 42):
        raise cy.err(f"_RL must be 40, 41 or 42 (got {cy['_RL']:g})")
    if rl != 40:
        cy.need_radius()
    v = cy["_VARI"]
    if v < 0 or v != int(v):
        raise cy.err("_VARI must be a whole number without a sign")
    units = int(v) % 10
    if units not in (0, 1, 2):
        raise cy.err(f"_VARI units digit must be 0 (complete), 1 (roughing) or 2 (finishing), got {units}")
    _, elems, srcs = contour_elements(m, cy["_KNAME"], cy)
    side = {40: 0, 41: 1, 42: -1}[rl]
    fal = cy["_FAL"] if rl != 40 else 0.0

    def path(extra):
        try:
            chain = offset_chain(elems, side * (cy.rt + extra))
        except OffsetError as e:
            raise contour_error(cy, srcs[e.index], f"contour element {e.index + 1}: {e}") from None
        return [e for e, _ in chain]
    top, bottom, fald = cy["_RFP"], cy["_DP"], cy["_FALD"]
    npass = ((n_levels(top, bottom + fald, cy["_MID"]) if units in (0, 1) else 0)
             + (n_levels(top, bottom, cy["_MID"]) if units == 2 or (units == 0 and (fal > 0 or fald > 0)) else 0))
    budget(cy, npass * (2 * len(elems) + 12), [(npass, f"passes for infeeds of at most _MID {cy['_MID']:g}"),
                                               (len(elems), "contour elements")])
    passes = []
    if units in (0, 1):
        for lv in cy.levels(top, bottom + fald, cy["_MID"]):
            passes.append((path(fal), lv, cy["_FFP1"]))
    if units == 2 or (units == 0 and (fal > 0 or fald > 0)):
        fin = path(0.0)
        for lv in cy.levels(top, bottom, cy["_MID"]):
            passes.append((fin, lv, cy["_FF3"] or cy["_FFP1"]))
    safe = top + cy["_SDIS"]
    for k, (pth, lv, f) in enumerate(passes):
        app = _approach(pth, side, int(cy["_AS1"]) % 10 if cy["_AS1"] else 1, cy["_LP1"], True, cy)
        dep = _approach(pth, side, int(cy["_AS2"]) % 10 if cy["_AS2"] else 1, cy["_LP2"], False, cy)
        s = app[0].start if app else pth[0].start
        if k == 0:
            cy.start(cy["_RTP"], s)
        else:
            cy.rapid(s, cy.m.pos[2])
        cy.rapid(s, safe)
        cy.feed_to(s, lv, cy["_FFD"])
        for e in app + pth + dep:
            cy.run_elem(e, lv, f)
        cy.rapid(cy.pos2(), safe)
    cy.finish(cy["_RTP"])


def _approach(pth, side, kind, lp, start: bool, cy: Cycle):
    """Approach (start=True) to the path's first point or departure from its last: 1 straight along
    the tangent, 2 quarter circle, 3 semicircle of radius _LP on the tool's side."""
    if lp <= 0:
        return []
    e = pth[0] if start else pth[-1]
    p = e.start if start else e.end
    t = tangent(e, not start)
    if kind not in (1, 2, 3):
        raise cy.err(f"approach/retract mode must be 1 (straight), 2 (quarter circle) or 3 (semicircle), got {kind}")
    if kind == 1 or side == 0:
        q = (p[0] - lp * t[0], p[1] - lp * t[1]) if start else (p[0] + lp * t[0], p[1] + lp * t[1])
        return [Elem("L", q, p)] if start else [Elem("L", p, q)]
    n = _left(t) if side > 0 else (t[1], -t[0])  # towards the tool side, away from the contour
    c = (p[0] + lp * n[0], p[1] + lp * n[1])
    cw = side < 0
    if kind == 2:
        q = (c[0] - lp * t[0], c[1] - lp * t[1]) if start else (c[0] + lp * t[0], c[1] + lp * t[1])
    else:
        q = (c[0] + lp * n[0], c[1] + lp * n[1])
    return [Elem("A", q, p, c, cw)] if start else [Elem("A", p, q, c, cw)]
