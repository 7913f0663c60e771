"""Sinumerik lathe mode (docs/dialects/sinumerik-turning.md): diameter programming (DIAMON, DIAMOF,
DIAM90, DIAMCYCOF), constant cutting speed (G96, G97, LIMS), threads (G33 with SF, chained blocks,
DITS/DITE; G34/G35 with a varying lead), rigid tapping (G331/G332) and floating tapping (G63).

The interpreter keeps its position in machine millimetres with X a **radius** (the records carry
``diameter`` False): under DIAMON (and DIAM90 for absolute values) an X word is halved before the
frames map it (``x_words``); the frames and work offsets shift X as a radius. The machine side
(interp/sinumerik/machine.py) calls in through ``settings``, ``diameter_command``, ``spindle_mode``
and ``x_words``; the interpreter through ``start``, ``spindle``, ``nose`` and ``nose_plane``; the
moves themselves are in interp/sinumerik/turning.py (``turning.motion``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from .. import canon
from ..core.compensation import nose_shift
from .syntax import range_message

# the diameter group: X values are diameters for absolute / incremental values
DIAMETER_MODES = {"DIAMON": (True, True), "DIAM90": (True, False), "DIAMOF": (False, False),
                  "DIAMCYCOF": (False, False)}
LATHE_WORDS = ("SF", "DITS", "DITE", "LIMS")
THREADS = (33, 34, 35)
TAPS = (331, 332)
SYNCED = THREADS + TAPS
SF_MAX = 360.0  # SF is 0 <= SF < 360 degrees
SPEED_LIMIT = 99_999.0  # rpm (LIMS), as S
RAMP_LIMIT = 99_999.9999  # mm (DITS, DITE)
EPS = 1e-9


@dataclass
class Lathe:
    """The lathe's state beyond the modal G groups (the diameter mode is in machine.Modal)."""
    sf: float = 0.0  # SF=: the start angle of the next thread (setting data, modal)
    dits: float = -1.0  # DITS= / DITE=: run-in and run-out paths (setting data; -1 the machine's own)
    dite: float = -1.0
    ramps_set: set = field(default_factory=set)  # "DITS" / "DITE" once programmed (-1 in force is then no reset value)
    chain: tuple | None = None  # (the point the last thread block ended at, the spindle angle there)
    change: float | None = None  # G34/G35: F, the change of lead per revolution (modal)
    css_on: bool = False  # G96/G961 active
    css: float = 0.0  # the cutting speed under G96 (m/min); 0 until an S is programmed
    lims: float = 0.0  # LIMS= (rpm), 0: none
    tapped: tuple | None = None  # the last G331/G332/G63: (end point, pitch, direction, end angle)
    spos: float | None = None  # SPOS=: the last angle the spindle was positioned to (None: not positioned)
    spos_new: bool = False  # a SPOS since the last G331: the next G331 starts at its angle
    g63: bool = False  # G63 in this block
    pending: tuple | None = None  # (record, its list, run-out mm, its name): the block that gets the run-out (finish)
    chaining: bool = False  # turning.run emits a record that continues the chain


def is_lathe(m) -> bool:
    return m.cfg.machine_kind == "lathe"


def start(m) -> None:
    """A setup with diameter programming starts in DIAMON; the position is kept as a radius."""
    if m.diameter:
        m.machine_modal.diam = "DIAMON"
        m.pos[0] /= 2.0
        m.diameter = False


# -- words and commands (machine.word takes SF= DITS= DITE= LIMS= into the block's words) ----------
def settings(m, ms, src, blk) -> None:
    """Apply the block's SF, DITS, DITE, LIMS (range-checked; on a mill SF, DITS, DITE are errors)."""
    lt, line, words = ms.lathe, src.line, blk.words
    for addr in LATHE_WORDS:
        if addr not in words:
            continue
        w = words.pop(addr)
        if addr == "LIMS" and not is_lathe(m):
            ms.warn_once(m, src, "LIMS", "LIMS (the spindle speed limit) changes nothing on the tool path (warned once)")
            continue
        if not is_lathe(m):
            raise m.error(line, w.col, f"{addr}= belongs to thread cutting on a lathe: the setup's machine is "
                          "a mill ([machine] kind = \"lathe\" for a lathe)")
        v = w.value
        if addr == "SF":
            if not 0.0 <= v < SF_MAX:
                raise m.error(line, w.col, range_message("SF (the thread's start angle)", v, 0.0, 359.9999, "degrees"))
            motion = next((c for c, _ in blk.gs if c in (0, 1, 2, 3) + SYNCED), m.motion)  # this block's
            if lt.chain is not None and motion in THREADS and m.start_point() is lt.chain[0]:
                m.warn(src, f"SF={v:g} in a chained thread block: the spindle synchronised at the chain's first "
                       "block, the offset acts from the next thread on")
            lt.sf = v
        elif addr in ("DITS", "DITE"):
            if not -1.0 <= v <= RAMP_LIMIT:
                raise m.error(line, w.col, range_message(addr, v, -1.0, RAMP_LIMIT, "mm"))
            # in mm (under G70/G700 the value is in inch); turning.run cuts the ramp with its lead
            setattr(lt, addr.lower(), v * ms.unit() if v > 0 else v)
            lt.ramps_set.add(addr)
        else:  # LIMS
            if not 0.0 < v <= SPEED_LIMIT:
                raise m.error(line, w.col, f"LIMS={v:g}: the spindle speed limit is greater than 0 and at most "
                              f"{SPEED_LIMIT:,.0f} rpm")
            lt.lims = v
            if lt.css_on and lt.css > 0:
                spindle(m, src, None, None)


def position_spindle(m, ms, v: float, mode) -> bool:
    """SPOS=angle (AC/DC/ACP/ACN: absolute, IC: added to the last SPOS angle): on a lathe the angle
    the next G331 begins at; on a mill one warning (no effect on the tool path)."""
    if not is_lathe(m):
        if "SPOS" not in m.warned:  # once, with the SPOS[n]= words the interpreter notes (words.command)
            m.warned.add("SPOS")
            ms.warn_once(m, None, "SPOS", "SPOS (spindle positioning) changes nothing on the tool path (warned once)")
        return True
    lt = ms.lathe
    lt.spos = ((lt.spos or 0.0) + v if mode == "IC" else v) % 360.0
    lt.spos_new = True
    return True


def diameter_command(m, ms, name: str, src, col: int) -> None:
    """DIAMON / DIAMOF / DIAM90 / DIAMCYCOF. On a mill only DIAMOF (its one mode) is accepted."""
    if not is_lathe(m):
        if name == "DIAMOF":
            return
        raise m.error(src.line, col, f"{name} (diameter programming) needs a lathe: the setup's machine is a mill "
                      "([machine] kind = \"lathe\")")
    m.machine_modal.diam = name
    if name == "DIAMCYCOF":
        ms.warn_once(m, src, "DIAMCYCOF", "DIAMCYCOF: X values are radii from here on (the display would keep the "
                     "diameter); the cycles' diameter parameters stay diameters")


def x_factor(ms, absolute: bool) -> float:
    """What an X value is multiplied by to become a radius: 0.5 for a diameter."""
    ab, inc = DIAMETER_MODES[ms.m.machine_modal.diam]
    return 0.5 if (ab if absolute else inc) else 1.0


def x_words(m, ms, words: dict, arc: bool) -> None:
    """An X word under DIAMON/DIAM90 becomes a radius; so does an arc's I=AC(..) (an incremental I, a
    distance from the start, is a radius already: cutsim assumes)."""
    if "X" in words:
        w = words["X"]
        ab = m.absolute if w.mode is None else w.mode != "IC"
        f = x_factor(ms, ab)
        if f != 1.0:
            words["X"] = replace(w, value=w.value * f)
    if arc and "I" in words and words["I"].mode == "AC" and x_factor(ms, True) != 1.0:
        words["I"] = replace(words["I"], value=words["I"].value * 0.5)


# -- the spindle: G96 / G97 / LIMS ------------------------------------------------------------------
def spindle_mode(m, ms, code: int, src) -> None:
    """G96/G961 switch the constant cutting speed on (the next S is in m/min), G97/G971 off: the speed
    in force at the tool's radius stays (freezes)."""
    lt = ms.lathe
    on = code in (96, 961)
    if on == lt.css_on:
        return
    if not on and lt.css > 0:
        lt.css_on = False
        rpm = css_speed(m, lt)
        lt.css = 0.0
        m.speed = rpm
        m.emit(canon.Spindle(src, m.spindle_dir, rpm))
        return
    lt.css_on = on
    if not on:
        lt.css = 0.0


def css_limit(m, lt) -> float:
    """The upper limit (rpm) of the G96 speed: the lower of LIMS and G26 S (0: none)."""
    limits = [v for v in (lt.lims, m.machine.speed_max) if v > 0]
    return min(limits) if limits else 0.0


def css_speed(m, lt) -> float:
    """The spindle speed (rpm) the cutting speed gives at the tool's radius, limited by LIMS and G26."""
    r = abs(m.pos[0])
    n = 1000.0 * lt.css / (2.0 * math.pi * r) if r > 1e-9 else math.inf
    limit = css_limit(m, lt)
    if limit > 0:
        n = min(n, limit)
    return n if math.isfinite(n) else 0.0


def limited_speed(ms, n: float) -> float:
    """A programmed spindle speed within G25 S (lower) and G26 S (upper limit); 0 (a stop) stays."""
    if n > 0 and ms.speed_max > 0:
        n = min(n, ms.speed_max)
    if n > 0 and ms.speed_min > 0:
        n = max(n, ms.speed_min)
    return n


def spindle(m, src, direction: int | None, speed: float | None) -> bool:
    """The spindle under G96 on a lathe: S is the cutting speed (m/min); the record carries it with
    the limit and the speed at the tool's radius. False when G96 is not on (the plain spindle)."""
    lt = m.machine.lathe
    if direction is not None:  # M3/M4/M5: the spindle leaves the position SPOS gave it
        lt.spos, lt.spos_new = None, False
    if not (is_lathe(m) and lt.css_on):
        return False
    if direction is not None:
        m.spindle_dir = direction
    if speed is not None:
        lt.css = speed
    if lt.css <= 0:  # G96 without a cutting speed yet: the speed in force holds
        m.emit(canon.Spindle(src, m.spindle_dir, m.speed))
        return True
    m.speed = css_speed(m, lt)
    m.emit(canon.Spindle(src, m.spindle_dir, m.speed, lt.css, css_limit(m, lt)))
    return True


# -- tool nose radius compensation ------------------------------------------------------------------
def nose_plane(m, blk, line: int) -> None:
    """G41/G42 on a lathe compensate the nose in the turning plane G18 only (an error at the word)."""
    if blk.comp in (41, 42) and is_lathe(m) and m.plane != "ZX" and m.comp_buf is None:
        col = next((c for code, c in blk.gs if code in (41, 42)), 1)
        raise m.error(line, col, f"G{blk.comp} on a lathe in the plane {m.plane}: tool nose radius compensation works "
                      "in the turning plane (G18, Z and X)")


def nose(m) -> tuple[float, tuple[float, float]] | None:
    """On a lathe: the active tool's nose radius and the shift from the nose centre to its tip
    (the cutting edge position); None on a mill."""
    if not is_lathe(m):
        return None
    if m.d_no == 0 or m.tool_no is None:
        return 0.0, (0.0, 0.0)
    r, edge = m.cfg.tool_noses.get(m.tool_no, (0.0, 9))
    return r, nose_shift(edge, r, m.plane)


# -- the DITE run-out at the end of a thread chain (turning.run leaves ``pending``) -------------------
def point(a, b, f: float) -> tuple[float, float, float]:
    return (a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f)


def before_emit(m, rec) -> None:
    """Sinumerik.emit's hook: a record that does not continue the chain ends it, so the last thread
    block gets its DITE run-out first (a spindle speed record does not end a chain)."""
    lt = m.machine.lathe
    if lt.pending is not None and not lt.chaining and not isinstance(rec, canon.Spindle):
        finish(m)


def finish(m) -> None:
    """The pending DITE run-out: the chain's last block's record becomes the thread up to DITE
    before its end and the run-out, over which the lead falls linearly to 0."""
    lt = m.machine.lathe
    if lt.pending is None:
        return
    rec, lst, dite, name = lt.pending
    lt.pending = None
    k = next((i for i in range(len(lst) - 1, -1, -1) if lst[i] is rec), None)
    if k is None:  # pragma: no cover - the record stays in its list until the next record is emitted
        raise RuntimeError("the thread block waiting for its DITE run-out left its list")
    i = "XYZ".index(rec.lead_axis)
    travel = abs(rec.end[i] - rec.start[i])
    if dite >= travel - EPS:
        raise m.error(rec.src.line, rec.src.col, f"{name}: the run-out is not shorter than the thread block's "
                      f"{travel:g} mm along {rec.lead_axis}")
    mid = point(rec.start, rec.end, 1.0 - dite / travel)
    head = replace(rec, end=mid)
    angle = rec.start_angle + 360.0 * (travel - dite) / rec.lead
    tail = replace(rec, start=mid, start_angle=angle % 360.0, lead_change=-rec.lead * rec.lead / (2.0 * dite))
    lst[k:k + 1] = [head, tail]
