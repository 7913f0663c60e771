"""What every Sinumerik cycle shares: its parameters (``SPECS``: the names, the required ones, the
strings), ``Cycle`` (the arguments of one call, their checks and the motion helpers every cycle
moves through) and the analytic tool radius offset of a contour (G41/G42, CYCLE72).

Each cycle expands into plain moves through the ModalMachine methods, every record carrying the
cycle block's Src, so the kinematics and the material removal know nothing about cycles.
Geometry here is plain 2D math on lines and arcs in the working plane; no meshes. The product
decisions where Siemens' documentation is silent are listed in docs/dialects/sinumerik.md ("What
the simulator assumes"); the constants below are those.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..canon import Src
from ..core.compensation import Elem
from .syntax import COORD_LIMIT, range_message


SIDE_STEP = 1.0  # pocket/slot roughing: radial step between concentric paths, x tool radius
INNER_LOOP = 0.9  # the innermost roughing path lies this many tool radii inside the final one
FACE_STEP = 1.5  # CYCLE71 default side step (_MIDA empty), x tool radius
EPS = 1e-9
# coarse metric threads M3..M60 (ISO 261): size -> pitch (mm), for MPIT (CYCLE84, CYCLE97) and DIATH (CYCLE96)
COARSE_PITCH = {3: 0.5, 4: 0.7, 5: 0.8, 6: 1.0, 8: 1.25, 10: 1.5, 12: 1.75, 14: 2.0, 16: 2.0, 18: 2.5, 20: 2.5,
                22: 2.5, 24: 3.0, 27: 3.0, 30: 3.5, 33: 3.5, 36: 4.0, 39: 4.0, 42: 4.5, 45: 4.5, 48: 5.0, 52: 5.0,
                56: 5.5, 60: 5.5}
ANGLES = {"STA1", "INDA", "AFSL", "_STA"}  # degrees, within +-ANGLE_LIMIT
ANGLE_LIMIT = 360.0
NUM_LIMIT = 1000  # SLOT1/SLOT2 NUM


# ---------------------------------------------------------------------------------------------
# 2D elements of a path in the working plane and their offset: interp/core/compensation.py (shared
# with ISG G41/G42, which also offsets G41/G42 in the program); a reversed chain is the cycles' own.

def reverse(elems):
    out = []
    for e in reversed(elems):
        out.append(Elem("L", e.end, e.start) if e.kind == "L" else Elem("A", e.end, e.start, e.centre, not e.cw))
    return out


# ---------------------------------------------------------------------------------------------
# parameters
@dataclass(frozen=True)
class P:
    name: str
    kind: str = "n"  # "n" number | "s" string
    default: object = 0.0  # None: required


def _spec(names: str, required: str = "", strings: str = ""):
    req = set(required.split())
    st = set(strings.split())
    return [P(n, "s" if n in st else "n", None if n in req else ("" if n in st else 0.0)) for n in names.split()]


SPECS = {
    "SLOT1": _spec("RTP RFP SDIS DP DPR NUM LENG WID CPA CPO RAD STA1 INDA FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF _FALD _STA2",
                   "RTP RFP LENG WID"),
    "SLOT2": _spec("RTP RFP SDIS DP DPR NUM AFSL WID CPA CPO RAD STA1 INDA FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF _FFCP",
                   "RTP RFP AFSL WID RAD"),
    "POCKET1": _spec("RTP RFP SDIS DP DPR LENG WID CRAD CPA CPO STA1 FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF",
                     "RTP RFP LENG WID"),
    "POCKET2": _spec("RTP RFP SDIS DP DPR PRAD CPA CPO FFD FFP1 MID CDIR FAL VARI MIDF FFP2 SSF", "RTP RFP PRAD"),
    "POCKET3": _spec("_RTP _RFP _SDIS _DP _LENG _WID _CRAD _PA _PO _STA _MID _FAL _FALD _FFP1 _FFD _CDIR _VARI _MIDA "
                     "_AP1 _AP2 _AD _RAD1 _DP1", "_RTP _RFP _DP _LENG _WID"),
    "POCKET4": _spec("_RTP _RFP _SDIS _DP _PRAD _PA _PO _MID _FAL _FALD _FFP1 _FFD _CDIR _VARI _MIDA _AP1 _AD _RAD1 _DP1",
                     "_RTP _RFP _DP _PRAD"),
    "CYCLE71": _spec("_RTP _RFP _SDIS _DP _PA _PO _LENG _WID _STA _MID _MIDA _FDP _FALD _FFP1 _VARI _FDP1",
                     "_RTP _RFP _DP _LENG _WID"),
    "CYCLE72": _spec("_KNAME _RTP _RFP _SDIS _DP _MID _FAL _FALD _FFP1 _FFD _VARI _RL _AS1 _LP1 _FF3 _AS2 _LP2",
                     "_KNAME _RTP _RFP _DP", "_KNAME"),
}
CYCLES = set(SPECS)
DRILLING: set[str] = set()  # the drilling cycles and patterns (drilling.register fills it)
TURNING: set[str] = set()  # the turning cycles, run in G18 on a lathe (turncycles.register fills it)


class Cycle:
    """One cycle call: its parameters by name (checked against SPECS) and the motion helpers."""

    def __init__(self, m, name: str, args, src: Src, col: int, label: str | None = None):
        self.m, self.name, self.src, self.line, self.col = m, name, src, src.line, col
        self.label = label or name  # what the messages call it: the cycle, or the ISO code run as it
        spec = SPECS[name]
        if len(args) > len(spec):
            raise m.error(self.line, args[len(spec)][1], f"{name} takes at most {len(spec)} parameters, not {len(args)}")
        self.v: dict[str, object] = {}
        self.given: set[str] = set()
        self.cols: dict[str, int] = {}  # parameter -> the column of its argument (the call's when empty)
        for k, p in enumerate(spec):
            val, col = args[k] if k < len(args) else (None, self.col)
            self.cols[p.name] = col
            if val is None:
                if p.default is None:
                    raise m.error(self.line, col, f"{name}: parameter {k + 1} ({p.name}) is required")
                self.v[p.name] = p.default
                continue
            if p.kind == "n" and isinstance(val, str):
                raise m.error(self.line, col, f"{name}: parameter {k + 1} ({p.name}) must be a number, not the string \"{val}\"")
            if p.kind == "s" and not isinstance(val, str):
                raise m.error(self.line, col, f"{name}: parameter {k + 1} ({p.name}) must be a string in double quotes")
            if p.kind == "n":
                lim, unit = (ANGLE_LIMIT, "degrees") if p.name in ANGLES else (COORD_LIMIT, "")
                if not -lim <= val <= lim:
                    raise m.error(self.line, col, f"{name}: parameter {k + 1} " + range_message(p.name, val, -lim, lim, unit))
            self.v[p.name] = val
            self.given.add(p.name)
        self.rt = m.tool_radius()
        self.saved_feed = m.feed

    def __getitem__(self, k):
        return self.v[k]

    def err(self, msg: str):
        return self.m.error(self.line, self.col, f"{self.label}: {msg}")

    def unsigned(self, *names):
        for n in names:
            if self.v[n] < 0:
                raise self.err(f"{n} is written without a sign (got {self.v[n]:g})")

    # -- motion helpers --------------------------------------------------------------------------
    def rapid(self, p, z):
        if self._here(p, z):
            return
        self.m.rapid(self.src, (p[0], p[1], z))

    def feed_to(self, p, z, f):
        if f and f > 0:
            self.m.feed = f
        if self._here(p, z):
            return
        self.m.linear(self.src, (p[0], p[1], z))

    def _here(self, p, z):
        q = self.m.pos
        return abs(q[0] - p[0]) < 1e-9 and abs(q[1] - p[1]) < 1e-9 and abs(q[2] - z) < 1e-9

    def run_elem(self, e, z, f):
        if f and f > 0:
            self.m.feed = f
        if e.kind == "L":
            if self._here(e.end, z):
                return
            self.m.linear(self.src, (e.end[0], e.end[1], z))
        else:
            self.m.arc(self.src, (e.end[0], e.end[1], z), (e.centre[0], e.centre[1], z), e.cw)

    def pos2(self):
        return (self.m.pos[0], self.m.pos[1])

    def depth(self, dp="DP", dpr="DPR", rfp="RFP"):
        """Final depth: DPR (relative, unsigned) wins when given and non-zero."""
        if dpr and dpr in self.given and self.v[dpr] != 0:
            if self.v[dpr] < 0:
                raise self.err(f"{dpr} is written without a sign")
            return self.v[rfp] - self.v[dpr]
        if dp not in self.given:
            raise self.err(f"the depth is missing: give {dp}" + (f" or {dpr}" if dpr else ""))
        return self.v[dp]

    def levels(self, top, bottom, mid):
        if bottom >= top - EPS:
            return []
        if mid < 0:
            raise self.err("the infeed depth is written without a sign")
        n = 1 if mid <= EPS else max(1, math.ceil((top - bottom) / mid - 1e-9))
        return [top - (top - bottom) * k / n for k in range(1, n + 1)]

    def start(self, rtp, p):
        """To the retraction plane, then over the start point."""
        if self.m.pos[2] < rtp - EPS:
            self.m.rapid(self.src, (self.m.pos[0], self.m.pos[1], rtp))
        self.rapid(p, rtp)

    def finish(self, rtp):
        self.m.rapid(self.src, (self.m.pos[0], self.m.pos[1], rtp))
        self.m.feed = self.saved_feed

    def need_radius(self):
        if self.rt <= 0:
            raise self.err("no tool radius: select a milling tool (T.. M6, D1) that the setup describes")

    def ccw(self, cdir):
        """Loops run counter-clockwise (G3) for climb milling with M3 (inside a pocket)."""
        cdir = int(cdir)
        if cdir not in (0, 1, 2, 3):
            raise self.err(f"CDIR must be 0, 1, 2 or 3 (got {cdir})")
        if cdir in (2, 3):
            return cdir == 3
        climb_ccw = self.m.spindle_dir >= 0
        return climb_ccw if cdir == 0 else not climb_ccw


def n_levels(top, bottom, mid) -> int:
    """How many depth steps Cycle.levels makes (without building them)."""
    if bottom >= top - EPS:
        return 0
    return 1 if mid <= EPS else max(1, math.ceil((top - bottom) / mid - 1e-9))


def budget(cy: Cycle, moves: int, parts: list[tuple[int, str]]) -> None:
    """Refuse a cycle whose moves (estimated from its parameters, before any is built) exceed
    [simulation] max_blocks; ``parts`` are the factors as (count, text naming the parameter)."""
    limit = cy.m.cfg.max_blocks
    if moves > limit:
        detail = ", ".join(f"{n:,} {t}" for n, t in parts)
        raise cy.err(f"the cycle would make about {moves:,} moves ({detail}), more than [simulation] max_blocks = "
                     f"{limit:,}: a cycle may make at most that many moves")
