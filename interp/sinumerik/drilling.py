"""Sinumerik drilling cycles (CYCLE81-CYCLE89, CYCLE840), the modal call MCALL, the position
patterns HOLES1, HOLES2 and CYCLE801, and the ISO shell G73/G74/G81...G89/G80 (G98/G99).

Every cycle drills at the position the tool stands on in the G17 plane and expands into plain
moves (through the Cycle motion helpers of interp/sinumerik/cycle.py), each carrying the cycle
block's Src. The sequences follow Siemens' cycle manuals ("Drilling cycles and drilling patterns");
where they are silent the simulator decides as listed in docs/dialects/sinumerik.md, "Drilling
cycles". Dwells (DTB, DTS, _DTD), spindle stops and orientations change no geometry and are not in
the moves.

Registered into the milling module's SPECS / RUNNERS by interp/sinumerik/interpreter.py (``register``), the module
above both: imports flow one way, sinumerik -> drilling -> milling, machine.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..canon import Src
from ..core import Group
from .codes import G_CODES, ISO_GROUPS
from . import turncycles, turning
from .cycle import COARSE_PITCH, CYCLES
from .milling import run_cycle
from .syntax import COORD_LIMIT, Call, SubCall, range_message
from .machine import in_wcs

EPS = 1e-9
CHIP_BREAK_RETRACT = 1.0  # mm: CYCLE83 VARI=0 retraction when _VRT is 0 (manual: 1 mm)
# CYCLE83 VARI=1: the anticipation distance above the last depth where the feed resumes (manual:
# 0.6 mm up to 30 mm of drilling depth, depth / 50 beyond that, at most 7 mm), unless _DIS1 > 0
ANTICIPATION_MIN, ANTICIPATION_DEPTH, ANTICIPATION_MAX = 0.6, 30.0, 7.0
# HOLES1/HOLES2 NUM and CYCLE801 NUM1 x NUM2 are bounded by [simulation] max_blocks, as every cycle's
# moves: a pattern of n holes with a modal cycle makes at least MOVES_PER_HOLE moves per hole
MOVES_PER_HOLE = 4  # G0 to the position, G0 to RFP + SDIS, G1 to the depth, G0 to RTP

METRIC_PITCH = {k: p for k, p in COARSE_PITCH.items() if k <= 48}  # ISO 261 coarse: MPIT M3..M48 -> pitch

_COMMON = "RTP RFP SDIS DP DPR"
_NEW = " _GMODE _DMODE _AMODE"  # the later (ShopMill / Operate) parameters: _GMODE checked (tip_reference)
NAMES = {
    "CYCLE81": _COMMON + " DTB" + _NEW,
    "CYCLE82": _COMMON + " DTB" + _NEW,
    "CYCLE83": _COMMON + " FDEP FDPR DAM DTB DTS FRF VARI _AXN _MDEP _VRT _DTD _DIS1" + _NEW,
    "CYCLE84": _COMMON + " DTB SDAC MPIT PIT POSS SST SST1 _AXN _PTAB _TECHNO _VARI _DAM _VRT" + _NEW,
    "CYCLE840": _COMMON + " DTB SDR SDAC ENC MPIT PIT _AXN _PTAB _TECHNO" + _NEW,
    "CYCLE85": _COMMON + " DTB FFR RFF" + _NEW,
    "CYCLE86": _COMMON + " DTB SDIR RPA RPO RPAP POSS" + _NEW,
    "CYCLE87": _COMMON + " SDIR",
    "CYCLE88": _COMMON + " DTB SDIR",
    "CYCLE89": _COMMON + " DTB" + _NEW,
    "HOLES1": "SPCA SPCO STA1 FDIS DBH NUM",
    "HOLES2": "CPA CPO RAD STA1 INDA NUM",
    "CYCLE801": "SPCA SPCO STA DIS1 DIS2 NUM1 NUM2",
}
PATTERNS = {"HOLES1", "HOLES2", "CYCLE801"}  # call the modal drilling cycle at their positions
DRILLS = set(NAMES) - PATTERNS  # the cycles MCALL may make modal
REQUIRED = {"HOLES1": "NUM", "HOLES2": "NUM", "CYCLE801": "NUM1 NUM2"}
ANGLES = {"STA"}  # degrees (STA1, INDA are already angles of the milling cycles)


# ---------------------------------------------------------------------------------------------
# the parts every drilling cycle shares
class Hole:
    """The planes of one drilling cycle call: RTP, RFP, RFP + SDIS and the final depth, checked."""

    def __init__(self, cy):
        cy.unsigned("SDIS")
        self.rtp, self.rfp = cy["RTP"], cy["RFP"]
        self.safe = self.rfp + cy["SDIS"]
        self.dp = cy.depth()
        if self.dp >= self.rfp - EPS:
            which = "DPR" if "DPR" in cy.given and cy["DPR"] != 0 else "DP"
            raise cy.err(f"the final drilling depth {self.dp:g} ({which}) is not below the reference plane RFP "
                         f"{self.rfp:g}")
        if self.rtp < self.rfp - EPS:
            raise cy.err(f"the retraction plane RTP {self.rtp:g} lies below the reference plane RFP {self.rfp:g}")
        self.p = cy.pos2()


def _approach(cy, h: Hole) -> None:
    """G0 to the safety plane RFP + SDIS over the hole (from wherever the tool stands on its axis)."""
    cy.rapid(h.p, h.safe)


def _retract(cy, h: Hole) -> None:
    """G0 to the retraction plane RTP; the feed in force is the caller's again."""
    cy.rapid(h.p, h.rtp)
    cy.m.feed = cy.saved_feed


def _feed(cy):
    """The feed in force (with the one 'no feed' warning when none was programmed)."""
    return cy.m.need_feed(cy.src)


def _dir(cy, name: str, allowed: tuple[int, ...]) -> int:
    v = cy[name]
    if v != int(v) or int(v) not in allowed:
        raise cy.err(f"{name} must be {', '.join(str(a) for a in allowed[:-1])} or {allowed[-1]} (got {v:g})")
    return int(v)


# ---------------------------------------------------------------------------------------------
# drilling
def tip_reference(cy) -> None:
    """_GMODE of CYCLE81/82/83 (the later parameter lists) chooses what DP measures: 0 the tool's
    tip; another value (the shank, a centring diameter) needs the tool's point, which the
    interpreter does not know: an error rather than a hole of another depth."""
    if cy["_GMODE"] != 0:
        raise cy.err(f"_GMODE {cy['_GMODE']:g}: a depth measured other than at the tool's tip (shank, centring "
                     "diameter) is not simulated: program DP / DPR as the tip's depth with _GMODE 0")


def cycle81(cy) -> None:
    """Drilling, centring: G0 to RFP + SDIS, G1 to the depth with the feed in force, G0 to RTP."""
    h = Hole(cy)
    tip_reference(cy)
    _approach(cy, h)
    cy.feed_to(h.p, h.dp, _feed(cy))
    _retract(cy, h)


cycle82 = cycle81  # + the dwell DTB at the depth (no geometric effect)


def first_stroke(cy, h: Hole) -> float:
    """The first drilling depth (z) of CYCLE83: FDPR (relative to RFP, no sign) wins when given and
    not 0, else FDEP (absolute)."""
    if "FDPR" in cy.given and cy["FDPR"] != 0:
        if cy["FDPR"] < 0:
            raise cy.err(f"FDPR is written without a sign (got {cy['FDPR']:g})")
        return h.rfp - cy["FDPR"]
    if "FDEP" not in cy.given:
        raise cy.err("the first drilling depth is missing: give FDEP (absolute) or FDPR (relative to RFP)")
    z = cy["FDEP"]
    if z >= h.rfp - EPS:
        raise cy.err(f"the first drilling depth FDEP {z:g} is not below the reference plane RFP {h.rfp:g}")
    return z


def strokes(first: float, total: float, dam: float, mdep: float) -> list[float]:
    """The drilling strokes (mm, from RFP down) of CYCLE83, in order, adding up to ``total``:
    the first stroke (the whole depth in one when the first depth reaches it); then each stroke the
    last one less the degression DAM while that stays above DAM, then DAM, no stroke below _MDEP;
    when a stroke of DAM is due and less than 2 x DAM remains, the rest in two equal strokes; a
    stroke that would pass the depth ends on it. DAM = 0: every stroke as long as the first."""
    if first >= total - EPS:
        return [total]
    out = [first]
    rem = total - first
    s = first
    while rem > EPS:
        if dam > 0:
            s = s - dam if s - dam > dam + EPS else dam
        s = max(s, mdep)
        if dam > 0 and s <= dam + EPS and rem < 2 * dam - EPS and rem > s + EPS:
            out += [rem / 2, rem / 2]
            break
        if s >= rem - EPS:
            out.append(rem)
            break
        out.append(s)
        rem -= s
    return out


def n_strokes(first: float, total: float, dam: float, mdep: float) -> int:
    """An upper bound of len(strokes(...)) computed without building them."""
    if first >= total - EPS:
        return 1
    least = first if dam <= 0 else min(first, dam)
    least = max(least, mdep, 1e-12)
    return 2 + math.ceil((total - first) / least)


def anticipation(cy, total: float) -> float:
    d = cy["_DIS1"]
    if d < 0:
        raise cy.err(f"_DIS1 is written without a sign (got {d:g})")
    if d > 0:
        return d
    return ANTICIPATION_MIN if total <= ANTICIPATION_DEPTH else min(total / 50.0, ANTICIPATION_MAX)


def cycle83(cy) -> None:
    """Deep-hole drilling. VARI 0 (chip breaking): after each stroke back by _VRT (0: 1 mm) with G1
    and on; VARI 1 (chip removal): after each stroke G0 to RFP + SDIS, G0 down again to the
    anticipation distance above the depth reached, G1 on. The first stroke runs at the feed in
    force times FRF, the others at the feed in force. G0 to RTP at the end."""
    h = Hole(cy)
    tool_axis(cy)
    tip_reference(cy)
    cy.unsigned("DAM", "FRF", "_MDEP", "_VRT")
    vari = _dir(cy, "VARI", (0, 1))
    frf = cy["FRF"]
    if frf > 1:
        raise cy.err(f"FRF (the feed factor of the first stroke) must be from 0.001 to 1 (got {frf:g})")
    frf = frf if frf > 0 else 1.0
    first_z = first_stroke(cy, h)
    total = h.rfp - h.dp
    first = min(h.rfp - first_z, total)
    dam, mdep = cy["DAM"], cy["_MDEP"]
    budget(cy, 3 * n_strokes(first, total, dam, mdep) + 3, f"strokes of FDEP/FDPR {first:g} mm, DAM {dam:g}, "
           f"_MDEP {mdep:g} over {total:g} mm")
    f = _feed(cy)
    back = cy["_VRT"] if cy["_VRT"] > 0 else CHIP_BREAK_RETRACT
    ant = anticipation(cy, total) if vari == 1 else 0.0
    _approach(cy, h)
    z = h.rfp
    for k, s in enumerate(strokes(first, total, dam, mdep)):
        nz = h.dp if k and abs(z - s - h.dp) < 1e-7 else z - s
        if k:
            if vari == 0:
                cy.feed_to(h.p, min(z + back, h.safe), f)
            else:
                cy.rapid(h.p, h.safe)
                cy.rapid(h.p, min(z + ant, h.safe))
        cy.feed_to(h.p, max(nz, h.dp), f * frf if k == 0 else f)
        z = max(nz, h.dp)
    _retract(cy, h)


def tool_axis(cy) -> None:
    """_AXN: the tool axis; the simulator drills along Z (0 or 3 in G17)."""
    v = cy["_AXN"]
    if v not in (0, 3):
        raise cy.err(f"_AXN {v:g}: drilling along the first or second axis of the plane is not simulated (the "
                     "tool axis is Z in G17: _AXN 0 or 3)")


def pitch(cy) -> float | None:
    """The thread pitch of a tapping cycle (mm): MPIT (thread size M3..M48) or PIT in the unit of
    _PTAB (0, 1 mm; 2 threads per inch; 3 inch per revolution), the sign the hand (not simulated);
    both given must agree. None when neither is given."""
    mp, pt = cy["MPIT"], cy["PIT"]
    p_m = None
    if mp != 0:
        if abs(mp) != int(abs(mp)) or int(abs(mp)) not in METRIC_PITCH:
            sizes = ", ".join(str(k) for k in METRIC_PITCH)
            raise cy.err(f"MPIT must be a metric thread size ({sizes}), got {mp:g}")
        p_m = METRIC_PITCH[int(abs(mp))]
    tab = _dir(cy, "_PTAB", (0, 1, 2, 3))
    p_t = None
    if pt != 0:
        p_t = 25.4 / abs(pt) if tab == 2 else 25.4 * abs(pt) if tab == 3 else abs(pt)
    if p_t is not None and p_m is not None and abs(p_t - p_m) > 1e-9:
        raise cy.err(f"MPIT {mp:g} (pitch {p_m:g}) and PIT {pt:g} (pitch {p_t:g}) contradict each other: give one of them")
    return p_t if p_t is not None else p_m


def _tap(cy, h: Hole, lead: float | None, steps: list[float] | None = None, back: float = 0.0,
         out: bool = False) -> None:
    """In along the axis at the pitch per revolution (or the feed in force without a pitch), out
    again to RFP + SDIS the same way, G0 to RTP. With ``steps`` (depths, z) the tap stops at each:
    back by ``back`` (chip breaking) or out to RFP + SDIS (``out``: chip removal) and in again."""
    _approach(cy, h)
    m = cy.m
    if lead is not None and m.cfg.machine_kind == "lathe":  # G331/G332 on the spindle axis
        hand = -1 if cy["PIT"] < 0 or cy["MPIT"] < 0 else 1  # the sign of the pitch: the hand
        return turncycles.rigid_tap(cy, h.p, (h.safe, lead, hand), steps or [h.dp], back, out, lambda: _retract(cy, h))
    per_rev, feed = m.per_rev, m.feed
    if lead is not None:
        m.per_rev, m.feed = True, lead
    else:
        m.feed = _feed(cy)
    x, y = h.p
    for k, z in enumerate(steps or [h.dp]):
        if k:
            m.linear(cy.src, (x, y, h.safe if out else min(m.pos[2] + back, h.safe)))
        m.linear(cy.src, (x, y, z))
    m.linear(cy.src, (x, y, h.safe))
    m.per_rev, m.feed = per_rev, feed
    _retract(cy, h)


def cycle84(cy) -> None:
    """Rigid tapping: G331 in at the pitch, G332 out, G0 to RTP. _VARI 1 (chip breaking) / 2 (chip
    removal): in steps of _DAM, back by _VRT (0: 1 mm) / out to RFP + SDIS after each."""
    h = Hole(cy)
    _dir(cy, "SDAC", (0, 3, 4, 5))
    tool_axis(cy)
    lead = pitch(cy)
    if lead is None:
        raise cy.err("no thread pitch: give MPIT (thread size) or PIT (pitch in mm)")
    vari = _dir(cy, "_VARI", (0, 1, 2))
    cy.unsigned("_DAM", "_VRT")
    if vari == 0:
        _tap(cy, h, lead)
        return
    dam = cy["_DAM"]
    if dam <= 0:
        raise cy.err(f"_VARI {vari} (tapping in steps) needs the step _DAM")
    total = h.rfp - h.dp
    budget(cy, 2 * math.ceil(total / dam) + 4, f"steps of _DAM {dam:g} over {total:g} mm")
    n = max(1, math.ceil(total / dam - 1e-9))
    steps = [max(h.rfp - dam * k, h.dp) for k in range(1, n + 1)]
    steps[-1] = h.dp
    _tap(cy, h, lead, steps, cy["_VRT"] if cy["_VRT"] > 0 else CHIP_BREAK_RETRACT, vari == 2)


def cycle840(cy) -> None:
    """Tapping with compensating chuck: with encoder (ENC 0) at the pitch, without at the feed in force (G63)."""
    h = Hole(cy)
    _dir(cy, "SDR", (0, 3, 4))
    _dir(cy, "SDAC", (0, 3, 4, 5))
    tool_axis(cy)
    lead = pitch(cy)
    if cy.m.cfg.machine_kind == "lathe":  # synchronised with the spindle (turning.compensated_tap)
        return turning.compensated_tap(cy, h, lead, _approach, _retract)
    if cy["ENC"] in (1, 11) or lead is None:
        lead = None  # without encoder: the feed in force
    _tap(cy, h, lead)


def cycle85(cy) -> None:
    """Boring 1: in with FFR, out to RFP + SDIS with RFF, G0 to RTP."""
    h = Hole(cy)
    for k in ("FFR", "RFF"):
        if cy[k] <= 0:
            raise cy.err(f"{k} (the {'boring' if k == 'FFR' else 'retract'} feed) must be positive (got {cy[k]:g})")
    _approach(cy, h)
    cy.feed_to(h.p, h.dp, cy["FFR"])
    cy.feed_to(h.p, h.safe, cy["RFF"])
    _retract(cy, h)


def cycle86(cy) -> None:
    """Boring 2: in with the feed in force, oriented spindle stop, the edge lifted off the wall
    (RPA, RPO, RPAP), G0 out. The tool is the body of revolution of its edge, so the lift-off (which
    only frees the single edge) is not simulated: it retracts along the bore's axis."""
    h = Hole(cy)
    _dir(cy, "SDIR", (3, 4))
    _approach(cy, h)
    cy.feed_to(h.p, h.dp, _feed(cy))
    cy.rapid(h.p, h.safe)
    _retract(cy, h)


def cycle87(cy) -> None:
    """Boring 3: in with the feed in force, M5 M0 (the operator), G0 to RTP."""
    h = Hole(cy)
    _dir(cy, "SDIR", (3, 4))
    _approach(cy, h)
    cy.feed_to(h.p, h.dp, _feed(cy))
    _retract(cy, h)


cycle88 = cycle87  # Boring 4: + the dwell DTB before the stop


def cycle89(cy) -> None:
    """Boring 5: in and out to RFP + SDIS with the feed in force, G0 to RTP."""
    h = Hole(cy)
    _approach(cy, h)
    f = _feed(cy)
    cy.feed_to(h.p, h.dp, f)
    cy.feed_to(h.p, h.safe, f)
    _retract(cy, h)


def budget(cy, moves: int, what: str) -> None:
    limit = cy.m.cfg.max_blocks
    if moves > limit:
        raise cy.err(f"the cycle would make about {moves:,} moves ({what}), more than [simulation] max_blocks = "
                     f"{limit:,}: a cycle may make at most that many moves")


# ---------------------------------------------------------------------------------------------
# the modal call and the position patterns
def _count(cy, name: str, lo: int = 1) -> int:
    v = cy[name]
    limit = cy.m.cfg.max_blocks
    if v != int(v) or not lo <= v <= limit:
        raise cy.err(f"{name} must be a whole number from {lo} to {limit:,} ([simulation] max_blocks) (got {v:g})")
    return int(v)


def hole_budget(cy, n: int) -> None:
    """A pattern of ``n`` holes makes at least MOVES_PER_HOLE moves per hole with a modal cycle (one
    without): more than [simulation] max_blocks is an error before any position is built."""
    per = MOVES_PER_HOLE if cy.m.drill.mcall is not None else 1
    budget(cy, n * per, f"{n:,} holes, at least {per} move(s) each")


def holes1(cy) -> list[tuple[float, float]]:
    """A row: NUM holes on the line through (SPCA, SPCO) at STA1 degrees, the first FDIS from that
    point, DBH apart; machined from the end nearer to the tool."""
    n = _count(cy, "NUM")
    hole_budget(cy, n)
    a = math.radians(cy["STA1"])
    u = (math.cos(a), math.sin(a))
    pts = [(cy["SPCA"] + (cy["FDIS"] + k * cy["DBH"]) * u[0], cy["SPCO"] + (cy["FDIS"] + k * cy["DBH"]) * u[1])
           for k in range(n)]
    here = cy.pos2()
    if math.dist(here, pts[-1]) < math.dist(here, pts[0]) - 1e-9:
        pts.reverse()
    return pts


def holes2(cy) -> list[tuple[float, float]]:
    """A circle: NUM holes on radius RAD about (CPA, CPO), the first at STA1 degrees, INDA apart
    (0: 360 / NUM)."""
    n = _count(cy, "NUM")
    hole_budget(cy, n)
    cy.unsigned("RAD")
    inda = cy["INDA"] if cy["INDA"] != 0 else 360.0 / n
    return [(cy["CPA"] + cy["RAD"] * math.cos(math.radians(cy["STA1"] + k * inda)),
             cy["CPO"] + cy["RAD"] * math.sin(math.radians(cy["STA1"] + k * inda))) for k in range(n)]


def cycle801(cy) -> list[tuple[float, float]]:
    """A grid: NUM1 columns DIS1 apart along the angle STA, NUM2 rows DIS2 apart across it, the
    first hole at (SPCA, SPCO); row by row, every other row backwards (meander)."""
    n1, n2 = _count(cy, "NUM1"), _count(cy, "NUM2")
    hole_budget(cy, n1 * n2)
    a = math.radians(cy["STA"])
    u, v = (math.cos(a), math.sin(a)), (-math.sin(a), math.cos(a))
    pts = []
    for j in range(n2):
        row = range(n1) if j % 2 == 0 else range(n1 - 1, -1, -1)
        for i in row:
            s, t = i * cy["DIS1"], j * cy["DIS2"]
            pts.append((cy["SPCA"] + s * u[0] + t * v[0], cy["SPCO"] + s * u[1] + t * v[1]))
    return pts


POSITIONS = {"HOLES1": holes1, "HOLES2": holes2, "CYCLE801": cycle801}


def run_pattern(cy) -> None:
    """G0 in the plane to each position of the pattern, the modal cycle (MCALL) after each; without
    a modal cycle the positions are only approached (one warning)."""
    pts = POSITIONS[cy.name](cy)
    m = cy.m
    for p in pts:
        for c, v in zip("XY", p):
            if abs(v) > COORD_LIMIT:
                raise cy.err(range_message(f"hole position {c}", v, -COORD_LIMIT, COORD_LIMIT, "mm"))
    call = m.drill.mcall
    if call is None:
        m.warn(cy.src, f"{cy.name} without a modal cycle (MCALL CYCLE8x(...) before it): the {len(pts)} positions "
                       "are only approached")
    elif call[3] != "cycle":
        raise cy.err(f"the modal call is the subprogram {call[0]}: the simulator calls only drilling cycles at the "
                     "positions of a pattern")
    for p in pts:
        cy.rapid(p, m.pos[2])
        if call is not None:
            run_modal(m, cy.src)


# the modal call: the interpreter's hooks --------------------------------------------------------
def modal_call(m, blk, line: int) -> list:
    """``MCALL NAME(args)`` / ``MCALL NAME`` / ``MCALL L<n>`` in a block: NAME becomes the modal
    call (a drilling cycle: its arguments evaluated and checked now; a subprogram: it must exist
    now, its arguments are evaluated at each call), ``MCALL`` alone ends it. Returns the block's
    other calls. (Hook in Sinumerik.calls.) ``m.drill.mcall`` is (name, arguments or the call, column,
    "cycle" | "sub") or None."""
    calls = blk.calls
    if not calls or not (isinstance(calls[0], SubCall) and calls[0].name == "MCALL"):
        return calls
    rest = list(calls[1:])
    if rest and isinstance(rest[0], Call) and rest[0].name in CYCLES:
        st = rest.pop(0)
        if st.name not in DRILLS:
            raise m.error(line, st.col, f"MCALL {st.name}: the simulator runs drilling cycles (CYCLE81 ... CYCLE89, "
                                        "CYCLE840) and subprograms as modal calls")
        args = [(None if a.value is None else m.ev(a.value, line, a.col), a.col) for a in st.args]
        dry_run(m, st.name, args, Src(m.unit_program, line, 1), st.col)  # parameter errors at the MCALL
        m.drill.mcall = (st.name, args, st.col, "cycle")
    elif rest and isinstance(rest[0], (Call, SubCall)):
        st = rest.pop(0)
        # a missing subprogram is an error at the MCALL; a declared external one: no modal call (it would do nothing)
        found = m.find_unit(st.name, Src(m.unit_program, line, 1), st.col, {}) is not None
        m.drill.mcall = (st.name, st, st.col, "sub") if found else None
    elif "L" in blk.words:
        lw = blk.words.pop("L")
        if lw.value != int(lw.value):
            raise m.error(line, lw.col, f"L{lw.value:g}: a subprogram number is a whole number")
        name = f"L{int(lw.value)}"
        found = m.find_unit(name, Src(m.unit_program, line, 1), lw.col, {}) is not None
        m.drill.mcall = (name, SubCall(lw.col, name), lw.col, "sub") if found else None
    else:
        m.drill.mcall = None
    return rest


def dry_run(m, name: str, args, src: Src, col: int) -> None:
    """Run the cycle where the tool stands with nothing recorded, so a wrong parameter is an error
    at the MCALL block itself; the machine state is left as it was."""
    saved = (list(m.pos), m.feed, m.per_rev, m.motion, m._warned_feed, len(m.program.warnings))
    m.emit = lambda rec: None  # an instance attribute shadows the method for the dry run
    try:
        run_cycle(m, name, args, src, col)
    finally:
        del m.emit
        m.pos, m.feed, m.per_rev, m.motion, m._warned_feed, n = saved
        del m.program.warnings[n:]


def moves_axes(words) -> bool:
    """The block programs a position (X, Y or Z): with a modal call, it runs after it."""
    return any(a in words for a in "XYZ")


def after_block(m, src: Src, moved: bool, blk, stack: list) -> None:
    """Run the modal call after a block that programmed a position (not the MCALL block itself,
    nor a block of the modal subprogram while it runs). (Hook in Sinumerik.convert_end, after
    the block's motion.)"""
    call = m.drill.mcall
    if not moved or call is None:
        return
    if any(isinstance(c, SubCall) and c.name == "MCALL" for c in blk.calls):
        return
    if call[3] == "cycle":
        name, args, col, _ = call
        run_modal(m, src, name, args, col)
        return
    running = m.drill.mcall_frame
    if running is not None and any(f is running for f in stack):
        return  # the modal subprogram's own moves do not call it again
    name, st, col, _ = call
    if blk.calls or blk.jumps or "L" in blk.words or any(code in (2, 17, 30) for code, _ in blk.ms):
        raise m.error(src.line, 1, f"a block with a call or a jump while the modal subprogram {name} (MCALL) is "
                                   "active: the simulator does not order the two; put them in separate blocks")
    if isinstance(st, Call):
        m.call_proc(st, src, {}, stack)
    else:
        m.call_sub(m.find_sub(name, src.line, col), src, {}, stack, col)
    m.drill.mcall_frame = stack[-1]


def run_modal(m, src: Src, name=None, args=None, col=None) -> None:
    """Run the modal cycle where the tool stands, in the workpiece coordinates of the active frames
    and offsets (interp/machine.in_wcs maps its moves into the machine)."""
    if name is None:
        name, args, col, _ = m.drill.mcall
    in_wcs(m, lambda: run_cycle(m, name, args, src, col), name, src.line, col)


RUNNERS = {"CYCLE81": cycle81, "CYCLE82": cycle82, "CYCLE83": cycle83, "CYCLE84": cycle84, "CYCLE840": cycle840,
           "CYCLE85": cycle85, "CYCLE86": cycle86, "CYCLE87": cycle87, "CYCLE88": cycle88, "CYCLE89": cycle89,
           "HOLES1": run_pattern, "HOLES2": run_pattern, "CYCLE801": run_pattern}


# ---------------------------------------------------------------------------------------------
# the ISO shell: G81 X.. Y.. Z.. R.. F.. modal until G80 (or G0..G3), as the 840D's ISO dialect mode
# (G291) and the Fanuc-style programs written for it. Each code runs the Siemens cycle of the same
# sequence, with RFP = R, SDIS 0, DP = Z and RTP the return level: G98 the initial level (where the
# tool stood on its axis when the cycle mode began), G99 the R plane.
ISO_CYCLES = {73: "CYCLE83", 74: "CYCLE840", 81: "CYCLE81", 82: "CYCLE82", 83: "CYCLE83", 84: "CYCLE840",
              85: "CYCLE89", 86: "CYCLE86", 88: "CYCLE88", 89: "CYCLE89"}
ISO_G = frozenset(c for c, row in G_CODES.items() if row.group in ISO_GROUPS)  # with G80, G98/G99, G290/G291


@dataclass
class IsoCycle:
    code: int  # 73, 74, 81 ... 89
    col: int  # the column of its G word (errors of a hole in its own block point there)
    initial: float  # the initial level: the tool's Z in the workpiece coordinates when the mode began
    r: float | None = None  # the R plane (absolute)
    z: float | None = None  # the hole's depth (absolute)
    q: float | None = None  # G73/G83: the peck depth
    p: float = 0.0  # G82/G88/G89: the dwell at the bottom (ms; no geometric effect)
    where: tuple = ()  # (program, line) of the G word
    here: int = 1  # the column errors of the block being run point at


@dataclass
class DrillState:
    """The drilling side's modal state of one run, owned by the interpreter (``Sinumerik.drill``)."""
    mcall: tuple | None = None  # MCALL's modal call: (name, arguments or the call, column, "cycle" or "sub")
    mcall_frame: object = None  # the program level that ran the modal call last (after_block)
    iso: IsoCycle | None = None  # the active ISO drilling cycle (G73, G74, G81 ... G89) until G80
    iso_return: int = 98  # G98 (initial level) or G99 (R plane)
    iso_warned: bool = False  # G291 warned about once


def iso_codes(m, blk, src: Src) -> bool:
    """The block's ISO cycle codes and words (hook at the end of Sinumerik.check_g):
    G73/G74/G81..G89 start or change the modal cycle, G80 and G0..G3 end it, G98/G99 choose the
    return level; R, Q, P (dwell) and Z (the depth) of a block in cycle mode are the cycle's data.
    True when the block drills (the cycle is on and the block names X, Y, Z or R): the block's
    X/Y then position the tool with G0 and ``iso_drill`` drills there after the move."""
    line = src.line
    codes = [(c, col) for c, col in blk.gs if c in ISO_G] if blk.gs else []
    cycle: list = []
    if codes:
        blk.gs[:] = [(c, col) for c, col in blk.gs if c not in ISO_G]
        groups = [[(c, col) for c, col in codes if G_CODES[c].group is g] for g in ISO_GROUPS]
        cycle = groups[0]  # G73, G74, G80 .. G89; then G98/G99 and G290/G291 (codes.ISO_GROUPS)
        for group in groups:
            if len({c for c, _ in group}) > 1:
                raise m.error(line, group[1][1], f"G{group[1][0]} conflicts with G{group[0][0]} in the same block")
    motion = [(c, col) for c, col in blk.gs if G_CODES[c].group is Group.MOTION] \
        if cycle or m.drill.iso is not None else []  # (it matters only with a cycle code or mode)
    if cycle and cycle[0][0] != 80 and motion:
        raise m.error(line, motion[0][1], f"G{motion[0][0]} and the drilling cycle G{cycle[0][0]} in one block")
    for c, col in codes:
        if c in (98, 99):
            m.drill.iso_return = c
        elif c == 291 and not m.drill.iso_warned:
            m.drill.iso_warned = True
            m.warn(src, "G291 (ISO dialect mode): the simulator reads the Siemens language and the ISO drilling "
                        "cycles G73..G89; other ISO forms are errors (warned once)")
    iso = m.drill.iso
    if motion and iso is not None:
        m.drill.iso = iso = None  # a G0..G3 ends the cycle mode, as G80
    if cycle:
        c, col = cycle[0]
        if c == 87:
            raise m.error(line, col, "G87 (back boring) is not simulated: the tool would have to pass the bore "
                                     "off-centre; write CYCLE86/CYCLE87 boring from above")
        if c == 80:
            m.drill.iso = iso = None
        else:
            if m.drill.mcall is not None:
                raise m.error(line, col, f"G{c} while the modal call MCALL {m.drill.mcall[0]} is active: end it with MCALL first")
            initial = iso.initial if iso is not None else wcs_z(m)
            old = iso
            m.drill.iso = iso = IsoCycle(c, col, initial, where=(src.program, line))
            if old is not None:  # the hole data stay until G80 (a new cycle code keeps R, Z, Q, P)
                iso.r, iso.z, iso.q, iso.p = old.r, old.z, old.q, old.p
    words = blk.words
    if iso is None:
        for a in ("R", "Q"):  # addresses only the ISO cycles read
            if a in words:
                w = words[a]
                raise m.error(line, w.col, f"{a}{w.value:g}: the address {a} belongs to the ISO drilling cycles (G81 .. "
                              f"G89){'; an R parameter is assigned with R<n>=<value>' if a == 'R' else ''}")
        return False
    drills = any(a in words for a in ("X", "Y", "Z", "R"))
    if not drills:
        return False  # F, S, M, a call (L100 alone is a subprogram call): the cycle waits
    # errors of this block's hole: at the cycle's G word in its own block, else at the first position word
    iso.here = iso.col if iso.where == (src.program, line) else min(words[a].col for a in "XYZR" if a in words)
    if m.drill.mcall is not None:
        raise m.error(line, iso.here, f"the ISO cycle G{iso.code} and the modal call MCALL {m.drill.mcall[0]} are both "
                      "active: end one of them (G80 or MCALL alone) first")
    for a in ("K", "L"):
        if a in words:
            raise m.error(line, words[a].col, f"{a}: a repeat count of the drilling cycle G{iso.code} is not simulated: "
                          "program each hole position")
    if not m.absolute or any(words[a].mode == "IC" for a in ("Z", "R") if a in words):
        raise m.error(line, iso.here, f"G{iso.code} with G91 (incremental R and Z) is not simulated: program the "
                      "cycle under G90")
    if "R" in words:
        iso.r = words.pop("R").value
    if "Z" in words:
        iso.z = words.pop("Z").value
    if "Q" in words:
        iso.q = words.pop("Q").value
    if "P" in words and iso.code in (82, 88, 89):
        iso.p = words.pop("P").value
    return drills


def wcs_z(m) -> float:
    """The tool's Z in the workpiece coordinates (the initial level of an ISO cycle)."""
    ms = m.machine
    return ms.to_wcs(m.pos)[2] / ms.unit()


def iso_drill(m, src: Src) -> None:
    """Drill one hole of the active ISO cycle where the tool stands (after the block's positioning),
    as the Siemens cycle of the same sequence (``ISO_CYCLES``), in the workpiece coordinates."""
    c = m.drill.iso
    code = f"G{c.code}"
    if c.z is None:
        raise m.error(src.line, c.here, f"{code} needs the depth of the hole: Z")
    if c.r is None:
        raise m.error(src.line, c.here, f"{code} needs the R plane: R (the level the feed starts from)")
    if c.code in (73, 83) and not c.q:
        raise m.error(src.line, c.here, f"{code} needs the peck depth Q (positive)")
    name = ISO_CYCLES[c.code]
    rtp = c.initial if m.drill.iso_return == 98 else c.r
    vals = {"RTP": rtp, "RFP": c.r, "SDIS": 0.0, "DP": c.z}
    if c.code in (73, 83):
        vals.update(FDPR=c.q, DAM=0.0, FRF=1.0, VARI=1.0 if c.code == 83 else 0.0)
    elif c.code in (74, 84):
        vals.update(ENC=1.0)  # at the F in force (F = pitch x speed), in and out, as Fanuc's G84
    elif c.code in (86, 88):
        vals.update(SDIR=3.0 if m.spindle_dir >= 0 else 4.0)
    if c.code in (82, 88, 89):
        vals.update(DTB=c.p / 1000.0)
    args = [(vals.get(n), c.here) for n in NAMES[name].split()]
    label = f"{code} (as {name}: RFP = R, DP = Z, RTP = the return level)"
    in_wcs(m, lambda: run_cycle(m, name, args, src, c.here, label=label), code, src.line, c.here)


def register(specs: dict, runners: dict, cycles: set, angles: set, spec, drilling: set) -> None:
    """Add the drilling cycles to milling' tables (``spec`` is its _spec; ``drilling`` the
    set of the cycles that drill along the tool axis)."""
    for name, names in NAMES.items():
        specs[name] = spec(names, REQUIRED.get(name, ""))
    runners.update(RUNNERS)
    cycles.update(NAMES)
    drilling.update(NAMES)
    angles.update(ANGLES)
