"""Sinumerik spindle-synchronised moves on a lathe (docs/dialects/sinumerik-turning.md): G33 threads
(longitudinal with K, face with I, taper with the lead on the longer travel), SF, chained blocks,
G34/G35 with a lead changing by F per revolution, G331/G332 rigid tapping and G63 floating tapping
along Z. Entry: ``motion`` from Sinumerik.move, with the block's words already in machine values
(interp/sinumerik/machine.py: frames, units, diameters), X a radius.
"""
from __future__ import annotations

from .. import canon
from .lathe import point, SYNCED, TAPS, THREADS
from .threading import ThreadParamError, varying_lead

EPS = 1e-9


def active(m) -> bool:
    """Whether the block's move is one of this module's."""
    return m.motion in SYNCED or m.machine.lathe.g63


def motion(m, src, words: dict, targets: dict[int, float], cols: dict[int, int]) -> None:
    lt = m.machine.lathe
    if lt.g63:
        return floating_tap(m, src, words, targets, cols)
    if m.motion in TAPS:
        return rigid_tap(m, src, words, targets, cols)
    return thread(m, src, words, targets, cols)


def _end(m, targets: dict[int, float]) -> tuple[float, float, float]:
    end = list(m.pos)
    for i, v in targets.items():
        end[i] = v
    return (end[0], end[1], end[2])


def _axis_scale(m, src, i: int, what: str, col: int = 1) -> float:
    """How the active frame scales axis ``i`` (X 0, Z 2), which must map onto itself."""
    lin = m.machine.linear_part()
    off = [abs(lin[i][k]) + abs(lin[k][i]) for k in range(3) if k != i]
    if any(v > 1e-12 for v in off):
        raise m.error(src.line, col, f"{what} under a rotated frame (ROT/AROT) is not modelled: the lead axis would "
                      "leave the turning axes")
    return abs(lin[i][i])


def emit(m, src, end, lead: float, axis: str, angle: float, change: float = 0.0) -> float:
    """One SyncedFeed record from the current position; returns the spindle angle at its end."""
    start = m.start_point()
    rec = canon.SyncedFeed(src, start, end, False, lead, axis, angle % 360.0, None, None, change)
    m.emit(rec)
    m.moved(end)
    i = "XYZ".index(axis)
    return (angle + 360.0 * revolutions(lead, change, abs(end[i] - start[i]))) % 360.0


def revolutions(lead: float, change: float, travel: float) -> float:
    """The spindle's turns over ``travel`` mm from the lead ``lead`` changing by ``change`` per turn."""
    if not change:
        return travel / lead
    return (max(lead * lead + 2.0 * change * travel, 0.0) ** 0.5 - lead) / change


def _lead(m, src, words: dict, code: int) -> tuple[str, object] | None:
    """The block's lead word (address, word): K or I; J and two of them are errors."""
    leads = sorted(((a, words.pop(a)) for a in ("I", "J", "K") if a in words), key=lambda aw: aw[1].col)
    if "CR" in words:
        raise m.error(src.line, words["CR"].col, f"address CR has no meaning in a G{code} block")
    for a, w in leads:
        if a == "J":
            raise m.error(src.line, w.col, f"a lathe has no Y axis: the lead of G{code} is programmed on K (along Z) "
                          "or I (along X)")
    if len(leads) > 1:
        raise m.error(src.line, leads[1][1].col, f"two leads (I and K) in one G{code} block: program the lead on the "
                      "axis with the longer travel")
    return leads[0] if leads else None


def thread(m, src, words: dict, targets: dict[int, float], cols: dict[int, int]) -> None:
    """G33/G34/G35 X.. Z.. K../I.. (F.. the lead change of G34/G35)."""
    line, code, lt = src.line, m.motion, m.machine.lathe
    given = _lead(m, src, words, code)
    change_word = words.pop("F", None) if code in (34, 35) else None
    if change_word is not None:
        lt.change = change_word.value * m.machine.unit()
    if not targets:
        if given:
            raise m.error(line, given[1].col, f"the lead {given[0]} of G{code} without an end point (X or Z) cuts "
                          "nothing")
        return
    end = _end(m, targets)
    if given is None:
        raise m.error(line, min(cols.values()), f"G{code} needs its lead in the block: K (mm per revolution along Z) "
                      "or I (along X)")
    a, w = given
    axis = "Z" if a == "K" else "X"
    if w.value <= 0:
        raise m.error(line, w.col, f"the lead {a} of G{code} must be greater than 0 (it is written without a sign; "
                      "the spindle's M3/M4 gives the hand)")
    dx, dz = abs(end[0] - m.pos[0]), abs(end[2] - m.pos[2])
    if axis == "Z" and dx > dz + EPS:
        raise m.error(line, w.col, f"G{code} taper steeper than 45 degrees (X travel {dx:g} > Z travel {dz:g} mm): "
                      "its lead is programmed on I, the axis with the longer travel")
    if axis == "X" and dz > dx + EPS:
        raise m.error(line, w.col, f"G{code} taper flatter than 45 degrees (Z travel {dz:g} > X travel {dx:g} mm): "
                      "its lead is programmed on K, the axis with the longer travel")
    travel = dz if axis == "Z" else dx
    if travel <= EPS:
        raise m.error(line, w.col, f"G{code} does not move along {axis}, the axis of its lead {a}")
    lead = w.value * _axis_scale(m, src, 2 if axis == "Z" else 0, f"G{code}", w.col)
    change = 0.0
    if code in (34, 35):
        if lt.change is None:
            raise m.error(line, w.col, f"G{code} needs F, the change of lead per revolution (mm/rev²)")
        try:
            varying_lead(lead, lt.change, travel, code == 34)
        except ThreadParamError as e:
            col = change_word.col if (e.param == "F" and change_word is not None) else w.col
            raise m.error(line, col, str(e)) from None
        change = lt.change if code == 34 else -lt.change
    run(m, src, end, lead, axis, travel, change, w.col)


def ramp(m, src, name: str, lead: float) -> tuple[float, str]:
    """The run-in (DITS) or run-out (DITE) a G33 block at ``lead`` gets, in mm along its lead axis, and
    its name for messages. 0: a jump. -1: the path the axis needs to reach the thread's speed
    v = lead * S / 60 at the machine's acceleration a ([machine] thread_acceleration), v^2 / (2 a);
    without it none (one warning when -1 was programmed). A programmed path longer than that is run
    at the maximum acceleration: the ramp is v^2 / (2 a) (the manual: the paths only increase the
    acceleration)."""
    lt, acc = m.machine.lathe, m.cfg.thread_acceleration
    value = lt.dits if name == "DITS" else lt.dite
    natural = (lead * m.speed / 60.0) ** 2 / (2.0 * acc) if acc > 0 else None
    if value == 0 or (natural is None and value < 0):
        if value < 0 and name in lt.ramps_set:
            where = "from the block start" if name == "DITS" else "to the block end"
            m.machine.warn_once(m, src, f"{name}-1", f"{name}=-1: the machine's acceleration is not in the setup "
                                f"([machine] thread_acceleration); the thread is cut at its lead {where}")
        return 0.0, f"{name}={value:g}"
    if natural is None or 0 < value <= natural:
        return value, f"{name}={value:g}"
    how = f"v^2 / 2a at the lead {lead:g} mm, S{m.speed:g} and [machine] thread_acceleration = {acc:g} mm/s^2"
    if value < 0:
        return natural, f"{name}=-1 (the machine's acceleration: {natural:.6g} mm, {how})"
    return natural, f"{name}={value:g} (run at the machine's acceleration: {natural:.6g} mm, {how})"


def run(m, src, end, lead: float, axis: str, travel: float, change: float, col: int) -> None:
    """Emit the thread block: a chained one continues at the spindle angle the chain reached (SF acts
    at the chain's first block only); DITS (G33 starting a chain) is a run-in over which the lead
    rises linearly in the revolutions from 0 to K, DITE a run-out over which it falls to 0 at the
    end of the chain's last block (``lathe.finish``); their lengths from ``ramp``."""
    lt = m.machine.lathe
    chained = lt.chain is not None and m.start_point() is lt.chain[0]
    angle = lt.chain[1] if chained else lt.sf
    if change != 0.0 and (lt.dits > 0 or lt.dite > 0):
        m.machine.warn_once(m, src, "DITS-G34", "DITS/DITE act on G33 blocks: a G34/G35 block starts and ends at "
                            "its programmed leads")
    run_in, in_name = ramp(m, src, "DITS", lead) if change == 0.0 and not chained else (0.0, "")
    run_out, out_name = ramp(m, src, "DITE", lead) if change == 0.0 else (0.0, "")
    if (run_in > 0 or run_out > 0) and m.comp_buf is not None:
        raise m.error(src.line, col, "DITS/DITE under radius compensation (G41/G42) are not modelled")
    lt.pending = None if chained else lt.pending  # the run-out moves on to this block
    lt.chaining = chained
    try:
        if run_in > 0:
            if run_in >= travel - EPS:
                raise m.error(src.line, col, f"{in_name}: the run-in is not shorter than the thread block's "
                              f"{travel:g} mm along {axis}")
            angle = emit(m, src, point(m.pos, end, run_in / travel), 0.0, axis, angle, lead * lead / (2.0 * run_in))
            lt.chaining = True
        angle = emit(m, src, end, lead, axis, angle, change)
    finally:
        lt.chaining = False
    lt.chain = (m.start_point(), angle)
    if run_out > 0:
        lst = m.comp_buf if m.comp_buf is not None else m.program.records
        if lst and isinstance(lst[-1], canon.SyncedFeed) and lst[-1].end is end:
            lt.pending = (lst[-1], lst, run_out, out_name)


def _stays_on_axis(m, src, code: str, targets: dict[int, float], cols: dict[int, int]) -> None:
    for i in (0, 1):
        if i in targets and abs(targets[i] - m.pos[i]) > EPS:
            raise m.error(src.line, cols[i], f"{code} taps along Z: {'XY'[i]} must stay where it is")


def rigid_tap(m, src, words: dict, targets: dict[int, float], cols: dict[int, int]) -> None:
    """G331 Z.. K..: the spindle follows the tap, K > 0 a right-hand thread (turning as under M3),
    K < 0 a left-hand one; G332 Z.. backs it out on the same helix with the spindle reversed and
    leaves the spindle standing (in position control)."""
    line, code, lt = src.line, m.motion, m.machine.lathe
    for a in ("I", "J", "CR"):
        if a in words:
            raise m.error(line, words[a].col, f"the pitch of G{code} is programmed on K (tapping along Z), not on {a}")
    k = words.pop("K", None)
    if k is not None and k.value == 0:
        raise m.error(line, k.col, f"the pitch K of G{code} must not be 0")
    if not targets:
        if k is not None:
            raise m.error(line, k.col, f"the pitch K of G{code} without an end point Z taps nothing")
        return
    _stays_on_axis(m, src, f"G{code}", targets, cols)
    end = _end(m, targets)
    t = lt.tapped
    here = t is not None and m.start_point() is t[0]
    if code == 332:
        if not here:
            raise m.error(line, min(cols.values()), "G332 backs the tap out from where a G331 stopped: program it "
                          "right after the G331, from its end point")
        if k is not None and abs(abs(k.value) * m.machine.unit() - t[1]) > EPS:
            raise m.error(line, k.col, f"G332 with the pitch K{k.value:g}: it must be the G331's")
        tap_move(m, src, end, t[1], -t[2], (-t[3]) % 360.0)
        m.spindle_dir = 0
        m.emit(canon.Spindle(src, 0, m.speed))
        return
    if k is None:
        raise m.error(line, min(cols.values()), "G331 needs its pitch on K, signed (K2 a right-hand thread, K-2 a "
                      "left-hand one)")
    pitch = abs(k.value) * _axis_scale(m, src, 2, "G331", k.col)
    direction = 1 if k.value > 0 else -1
    keep = here and t[1] == pitch and t[2] == direction and not lt.spos_new
    start = t[3] if keep else lt.spos if lt.spos_new else 0.0  # a new tap: where SPOS put the spindle
    lt.spos_new = False
    tap_move(m, src, end, pitch, direction, start)


def tap_move(m, src, end, pitch: float, direction: int, angle: float) -> None:
    if abs(end[2] - m.pos[2]) <= EPS:
        raise m.error(src.line, 1, "a tapping block must move along Z")
    m.spindle_dir = direction
    m.emit(canon.Spindle(src, direction, m.speed))
    end_angle = emit(m, src, end, pitch, "Z", angle)
    m.machine.lathe.tapped = (m.start_point(), pitch, direction, end_angle)


def floating_tap(m, src, words: dict, targets: dict[int, float], cols: dict[int, int]) -> None:
    """G63 Z.. F..: tapping with a compensating chuck, a straight move along Z at the feed; the tap's
    lead is the feed per revolution (F under G95, F/S under G94). The chuck lets the tap follow its
    thread, so a G63 that reverses the spindle from where the last one stopped backs out on its
    helix; a first G63 meets the workpiece at the spindle's zero mark (cutsim assumes)."""
    line, lt = src.line, m.machine.lathe
    lt.g63 = False
    for a in ("I", "J", "K", "CR"):
        if a in words:
            raise m.error(line, words[a].col, f"address {a} has no meaning in a G63 block (the lead is the feed)")
    if not targets:
        return
    _stays_on_axis(m, src, "G63", targets, cols)
    end = _end(m, targets)
    if m.spindle_dir == 0:
        raise m.error(line, min(cols.values()), "G63 taps with the spindle turning: program M3 or M4 first")
    if m.feed is None or m.feed <= 0:
        raise m.error(line, min(cols.values()), "G63 needs its feed F (the tap's lead per revolution under G95)")
    if m.per_rev:
        lead = m.feed
    else:
        if m.speed <= 0:
            raise m.error(line, min(cols.values()), "G63 under G94 needs the spindle speed S (the lead is F / S)")
        lead = m.feed / m.speed
    t = lt.tapped
    keep = t is not None and m.start_point() is t[0] and abs(t[1] - lead) <= EPS and t[2] == -m.spindle_dir
    end_angle = emit(m, src, end, lead, "Z", (-t[3]) % 360.0 if keep else 0.0)
    lt.tapped = (m.start_point(), lead, m.spindle_dir, end_angle)


def compensated_tap(cy, h, lead: float | None, approach, retract) -> None:
    """CYCLE840 on a lathe, tapping with compensating chuck along Z on the spindle axis: the tap in to
    the depth and out to RFP + SDIS synchronised with the spindle (the chuck lets it follow its
    thread): at the pitch MPIT / PIT (with encoder the cycle's G33; without encoder, ENC 1, the
    G63 feed it derives from the pitch), or at the feed in force per revolution when no pitch is
    given (G63: F under G95, F / S under G94). The hand is the spindle direction in force (M3: a
    right-hand thread); out with the spindle reversed (SDR 0) or turning as SDR says (3 / 4: M3 /
    M4, which must be the other way), on the same helix; then the direction SDAC (0: the one
    before the call; 5: stopped), and ``retract`` (G0 to RTP). ``h`` is the drilling cycle's Hole."""
    m, src = cy.m, cy.src
    hand = m.spindle_dir
    if hand == 0:
        raise cy.err("the spindle stands: tapping with a compensating chuck needs it turning (program M3 or M4 "
                     "and S before the call)")
    if lead is None:
        feed = m.feed if m.feed is not None else 0.0
        if feed <= 0:
            raise cy.err("no thread pitch (MPIT, PIT) and no feed F: the tap's lead is the feed per revolution")
        if not m.per_rev and m.speed <= 0:
            raise cy.err("no thread pitch (MPIT, PIT) under G94: the tap's lead is F / S, and S is 0")
        lead = feed if m.per_rev else feed / m.speed
    sdr = int(cy["SDR"])
    back = -hand if sdr == 0 else (1 if sdr == 3 else -1)
    if back == hand:
        raise m.error(cy.line, cy.cols.get("SDR", cy.col), f"{cy.label}: SDR {sdr} turns the spindle the way it "
                      f"tapped in (M{3 if hand > 0 else 4}): the tap would not back out (SDR 0 reverses it)")
    approach(cy, h)
    x, y = h.p
    tap_move(m, src, (x, y, h.dp), lead, hand, 0.0)
    tap_move(m, src, (x, y, h.safe), lead, back, (-m.machine.lathe.tapped[3]) % 360.0)
    sdac = int(cy["SDAC"])
    after = hand if sdac == 0 else {3: 1, 4: -1, 5: 0}[sdac]
    m.spindle_dir = after
    m.spindle(src, after, None)
    retract(cy, h)
