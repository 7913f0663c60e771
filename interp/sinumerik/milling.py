"""Sinumerik milling cycles SLOT1, SLOT2, POCKET1-4 and CYCLE71 (pocket-like regions as concentric
closed paths, depth levels, plunging), the table of every cycle's runner and ``run_cycle``.
"""
from __future__ import annotations

import math

from ..canon import Src
from ..core.compensation import _cross, _dot, _norm, _sub, Elem, length
from .contour import cycle72
from .lathe import x_factor
from .cycle import budget, Cycle, DRILLING, EPS, FACE_STEP, INNER_LOOP, n_levels, NUM_LIMIT, reverse, SIDE_STEP, TURNING


# ---------------------------------------------------------------------------------------------
# pocket-like regions: concentric closed paths
def _rot(p, ang, c):
    ca, sa = math.cos(ang), math.sin(ang)
    return (c[0] + p[0] * ca - p[1] * sa, c[1] + p[0] * sa + p[1] * ca)


def rounded_rect_loop(a, b, cr, centre, ang):
    """CCW path of the rounded rectangle |u|<=a, |v|<=b (corner radius cr) from (0, -b), in global
    coordinates; zero-length pieces dropped (a = 0 or b = 0 is a line travelled both ways)."""
    cr = max(0.0, min(cr, a, b))
    pts = []
    seq = [("L", (a - cr, -b)), ("A", (a, -b + cr), (a - cr, -b + cr)), ("L", (a, b - cr)),
           ("A", (a - cr, b), (a - cr, b - cr)), ("L", (-a + cr, b)), ("A", (-a, b - cr), (-a + cr, b - cr)),
           ("L", (-a, -b + cr)), ("A", (-a + cr, -b), (-a + cr, -b + cr)), ("L", (0.0, -b))]
    cur = (0.0, -b)
    for s in seq:
        nxt = s[1]
        if math.hypot(nxt[0] - cur[0], nxt[1] - cur[1]) < 1e-9:
            continue
        g0, g1 = _rot(cur, ang, centre), _rot(nxt, ang, centre)
        if s[0] == "L" or cr <= 1e-9:
            pts.append(Elem("L", g0, g1))
        else:
            pts.append(Elem("A", g0, g1, _rot(s[2], ang, centre), False))
        cur = nxt
    if not pts:  # a point: the tool only plunges
        g = _rot((0.0, -b), ang, centre)
        pts.append(Elem("L", g, g))
    return pts


def arc_slot_loop(rad, rho, t0, t1, centre):
    """CCW path around the arc slot of centre-line radius ``rad`` from angle t0 to t1 (radians,
    t1 > t0) at offset ``rho`` from the centre line, from the inner arc at the middle angle."""
    tm = (t0 + t1) / 2

    def P(r, t):
        return (centre[0] + r * math.cos(t), centre[1] + r * math.sin(t))
    e0, e1 = P(rad, t0), P(rad, t1)
    out = [Elem("A", P(rad - rho, tm), P(rad - rho, t0), centre, True)]
    if rho > 1e-9:
        out.append(Elem("A", P(rad - rho, t0), P(rad + rho, t0), e0, False))
    out.append(Elem("A", P(rad + rho, t0), P(rad + rho, t1), centre, False))
    if rho > 1e-9:
        out.append(Elem("A", P(rad + rho, t1), P(rad - rho, t1), e1, False))
    out.append(Elem("A", P(rad - rho, t1), P(rad - rho, tm), centre, True))
    return out


def offsets(d, rt, step):
    """Offsets (from the final path inwards) of the concentric roughing paths: the innermost lies
    within INNER_LOOP tool radii of the middle, neighbours at most ``step`` apart."""
    if d <= INNER_LOOP * rt:
        return [0.0]
    inner = INNER_LOOP * rt
    n = 1 + math.ceil((d - inner) / step - 1e-9)
    s = (d - inner) / (n - 1)
    return [(n - 1 - j) * s for j in range(n)]


def n_offsets(d, rt, step) -> int:
    """How many concentric paths offsets() makes (without building them)."""
    return 1 if d <= INNER_LOOP * rt else 1 + math.ceil((d - INNER_LOOP * rt) / step - 1e-9)


def region_budget(cy: Cycle, top, bottom, mid, midf, fald, units, fal, n_loops, per_loop, step_text, count=1,
                  helix_pitch=None):
    """The moves cut_region will make for ``count`` regions of ``n_loops`` paths of ``per_loop``
    elements each, checked against max_blocks before anything is built."""
    u = "_" if cy.name in ("POCKET3", "POCKET4") else ""
    rough = units in (0, 1)
    fin = units == 2 or (units == 0 and fal > 0)
    nr = n_levels(top, bottom + fald, mid) if rough else 0
    nf = n_levels(top, bottom, midf if midf > 0 else mid) if fin else 0
    per_level = n_loops * (per_loop + 1) + 3
    moves = nr * per_level + (per_level if rough and fald > 0 else 0) + nf * (per_loop + 3) + 6
    parts = [(max(nr, nf), f"infeeds of at most {u}MID {mid:g} over {top - bottom:g} mm"
              + (f" (finishing: MIDF {midf:g})" if nf > nr else "")),
             (n_loops, f"paths side by side {step_text}")]
    if helix_pitch:
        half_turns = math.ceil((top - bottom) / (helix_pitch / 2)) + 4 * nr
        moves += half_turns
        parts.append((half_turns, f"helix half-turns of _DP1 {helix_pitch:g} mm per turn"))
    if count > 1:
        parts.append((count, "slots (NUM)"))
    budget(cy, moves * count, parts)


def cut_region(cy: Cycle, rtp, safe, top, bottom, loops_rough, loops_fin, mid, midf, plunge, ffd, ffp1, ffp2,
               fald=0.0, helix=None):
    """Rough the loops level by level (plunge at the first loop's start), then finish along the
    final loop. ``loops_*`` are lists of CCW/CW element lists, inside first."""
    rough_levels = cy.levels(top, bottom + fald, mid) if loops_rough else []
    fin_levels = cy.levels(top, bottom, midf if midf > 0 else mid) if loops_fin else []
    first = (loops_rough or loops_fin)[0][0].start if (loops_rough or loops_fin) else None
    if first is None:
        return
    cy.start(rtp, first)
    cy.rapid(first, safe)
    z_prev = safe
    for lv in rough_levels:
        _plunge(cy, loops_rough[0], z_prev, lv, plunge, ffd, top, helix)
        for k, loop in enumerate(loops_rough):
            if k:
                cy.feed_to(loop[0].start, lv, ffp1)
            for e in loop:
                cy.run_elem(e, lv, ffp1)
        cy.feed_to(loops_rough[0][0].start, lv, ffp1)
        z_prev = lv
    if fald > 0 and loops_rough:  # floor allowance: clear the floor at the final depth
        _plunge(cy, loops_rough[0], z_prev, bottom, 1, ffd, top, None)
        for k, loop in enumerate(loops_rough):
            if k:
                cy.feed_to(loop[0].start, bottom, ffp1)
            for e in loop:
                cy.run_elem(e, bottom, ffp1)
        cy.feed_to(loops_rough[0][0].start, bottom, ffp1)
        z_prev = bottom
    for lv in fin_levels:
        loop = loops_fin[-1]
        if loops_rough:
            cy.feed_to(loop[0].start, cy.m.pos[2], ffp2)
            cy.feed_to(loop[0].start, lv, ffd)
        else:
            _plunge(cy, loop, z_prev, lv, plunge, ffd, top, None)
        for e in loop:
            cy.run_elem(e, lv, ffp2)
        z_prev = lv
    cy.feed_to(cy.pos2(), safe, ffd)
    cy.finish(rtp)


def _plunge(cy: Cycle, loop, z_prev, z, mode, ffd, top, helix):
    p = loop[0].start
    if mode == 0:  # vertical: G0 only down to where the material begins, the infeed itself at FFD
        cy.rapid(p, max(z_prev, z))
        cy.feed_to(p, z, ffd)
    elif mode == 2 and helix is not None:  # helix about the region centre
        c, r, pitch = helix
        s = (c[0] + r, c[1])
        cy.feed_to(s, z_prev, ffd)
        zc = z_prev
        while zc > z + EPS:
            zn = max(z, zc - pitch / 2)
            cy.m.arc(cy.src, (c[0] - r, c[1], zn), (c[0], c[1], zn), False)
            zc = zn
            if zc <= z + EPS:
                cy.m.arc(cy.src, (c[0] + r, c[1], zc), (c[0], c[1], zc), False)
                break
            zn = max(z, zc - pitch / 2)
            cy.m.arc(cy.src, (c[0] + r, c[1], zn), (c[0], c[1], zn), False)
            zc = zn
        cy.m.arc(cy.src, (c[0] - r, c[1], z), (c[0], c[1], z), False)  # flatten the ramp's floor
        cy.m.arc(cy.src, (c[0] + r, c[1], z), (c[0], c[1], z), False)
        cy.feed_to(p, z, ffd)
    elif mode == 3:  # oscillate along the first straight piece of the innermost path
        e = loop[0]
        if e.kind == "L" and length(e) > 1e-3:
            zm = (z_prev + z) / 2
            cy.feed_to(e.end, max(zm, z), ffd)
            cy.feed_to(e.start, z, ffd)
        else:
            cy.feed_to(p, z, ffd)
    else:  # vertical with G1
        cy.feed_to(p, z, ffd)


def _vari(cy: Cycle, key="VARI"):
    v = cy[key]
    if v < 0 or v != int(v):
        raise cy.err(f"{key} must be a whole number without a sign (got {v:g})")
    v = int(v)
    units, tens = v % 10, (v // 10) % 10
    if units not in (0, 1, 2):
        raise cy.err(f"{key} units digit must be 0 (complete), 1 (roughing) or 2 (finishing), got {units}")
    return units, tens


def _plunge_mode(cy, tens, allowed):
    if tens not in allowed:
        raise cy.err(f"VARI tens digit {tens} is not one of {', '.join(map(str, sorted(allowed)))}")
    return tens


def _loops_for(units, fal, build_rough, build_fin):
    rough = build_rough() if units in (0, 1) else []
    fin = build_fin() if (units == 2 or (units == 0 and fal > 0)) else []
    return rough, fin


def _orient(loops, ccw):
    return [lp if ccw else reverse(lp) for lp in loops]


# ---------------------------------------------------------------------------------------------
def _seg_dist(p1, p2, q1, q2):
    def pd(p, a, b):
        ab = _sub(b, a)
        L = _dot(ab, ab)
        t = 0.0 if L < 1e-18 else max(0.0, min(1.0, _dot(_sub(p, a), ab) / L))
        return _norm(_sub(p, (a[0] + t * ab[0], a[1] + t * ab[1])))
    d1, d2 = _sub(p2, p1), _sub(q2, q1)
    den = _cross(d1, d2)
    if abs(den) > 1e-14:
        t = _cross(_sub(q1, p1), d2) / den
        u = _cross(_sub(q1, p1), d1) / den
        if 0 <= t <= 1 and 0 <= u <= 1:
            return 0.0
    return min(pd(p1, q1, q2), pd(p2, q1, q2), pd(q1, p1, p2), pd(q2, p1, p2))


def _slot_count(cy: Cycle) -> int:
    """NUM: how many slots (default 1), a whole number."""
    num = cy["NUM"] if "NUM" in cy.given else 1
    if num < 1 or num != int(num) or num > NUM_LIMIT:
        raise cy.err(f"NUM must be a whole number of slots from 1 to {NUM_LIMIT} (got {num:.10g})")
    return int(num)


def _tool_fits_slot(cy: Cycle, wid: float, fal: float) -> None:
    """The tool, with the finishing allowance on both sides, fits the slot width."""
    if 2 * cy.rt > wid + 1e-9:
        raise cy.err(f"the tool (diameter {2 * cy.rt:g}) is wider than the slot (WID {wid:g})")
    if 2 * (cy.rt + fal) > wid + 1e-9:
        raise cy.err(f"the finishing allowance FAL {fal:g} leaves no room for the tool in the slot")


def slot1(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "NUM", "LENG", "WID", "RAD", "MID", "FAL", "MIDF")
    rt = cy.rt
    num = _slot_count(cy)
    leng, wid, fal = cy["LENG"], cy["WID"], cy["FAL"]
    _tool_fits_slot(cy, wid, fal)
    if leng < wid - 1e-9:
        raise cy.err(f"the slot length LENG {leng:g} is shorter than its width WID {wid:g}")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1, 3})
    inda = cy["INDA"] if cy["INDA"] != 0 else 360.0 / num
    c = (cy["CPA"], cy["CPO"])
    axes = []
    for k in range(num):
        ang = math.radians(cy["STA1"] + k * inda)
        u = (math.cos(ang), math.sin(ang))
        r0, r1 = cy["RAD"] + wid / 2, cy["RAD"] + leng - wid / 2
        axes.append((ang, (c[0] + r0 * u[0], c[1] + r0 * u[1]), (c[0] + r1 * u[0], c[1] + r1 * u[1])))
    for i in range(num):
        for j in range(i + 1, num):
            if _seg_dist(axes[i][1], axes[i][2], axes[j][1], axes[j][2]) < wid - 1e-6:
                raise cy.err(f"slots {i + 1} and {j + 1} overlap (width {wid:g}, angle step {inda:g} degrees)")
    ccw = cy.ccw(cy["CDIR"])
    bottom = cy.depth()
    safe = cy["RFP"] + cy["SDIS"]
    region_budget(cy, cy["RFP"], bottom, cy["MID"], cy["MIDF"], 0.0, units, fal,
                  n_offsets(max(wid / 2 - rt - fal, 0.0), rt, SIDE_STEP * rt), 9,
                  f"{SIDE_STEP * rt:g} mm apart (the tool radius {rt:g} mm)", count=num)
    for ang, p0, p1 in axes:
        mid = ((p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2)
        a, b = leng / 2 - rt, wid / 2 - rt

        def build(extra, a=a, b=b, mid=mid, ang=ang):
            return [rounded_rect_loop(a - extra - o, b - extra - o, b - extra - o, mid, ang)
                    for o in offsets(b - extra, rt, SIDE_STEP * rt)]
        rough, fin = _loops_for(units, fal, lambda: build(fal), lambda: [rounded_rect_loop(a, b, b, mid, ang)])
        cut_region(cy, cy["RTP"], safe, cy["RFP"], bottom, _orient(rough, ccw), _orient(fin, ccw), cy["MID"],
                   cy["MIDF"], mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"])


def slot2(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "NUM", "AFSL", "WID", "RAD", "MID", "FAL", "MIDF")
    rt = cy.rt
    num = _slot_count(cy)
    afsl, wid, rad, fal = cy["AFSL"], cy["WID"], cy["RAD"], cy["FAL"]
    _tool_fits_slot(cy, wid, fal)
    if rad - wid / 2 <= 1e-9:
        raise cy.err(f"the slot (width {wid:g}) does not fit on the radius RAD {rad:g}")
    if afsl <= 0 or afsl >= 360:
        raise cy.err(f"AFSL must be between 0 and 360 degrees (got {afsl:g})")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1, 3})
    inda = cy["INDA"] if cy["INDA"] != 0 else 360.0 / num
    # neighbours: the ends' circles of radius WID/2 must not overlap
    cap = 2 * math.degrees(math.asin(min(1.0, wid / (2 * rad))))
    if num > 1:
        gaps = [(((cy["STA1"] + (k + 1) * inda) - (cy["STA1"] + k * inda + afsl)) % 360.0) for k in range(num)]
        starts = sorted(((cy["STA1"] + k * inda) % 360.0) for k in range(num))
        spacing = min((starts[(k + 1) % num] - starts[k]) % 360.0 for k in range(num))
        if spacing < afsl + cap - 1e-6 or min(gaps) < cap - 1e-6:
            raise cy.err(f"the slots overlap: {num} slots of {afsl:g} degrees and width {wid:g} do not fit "
                         f"with the angle step {inda:g} degrees")
    elif afsl + cap > 360 + 1e-6:
        raise cy.err("the slot closes on itself")
    ccw = cy.ccw(cy["CDIR"])
    c = (cy["CPA"], cy["CPO"])
    bottom = cy.depth()
    safe = cy["RFP"] + cy["SDIS"]
    region_budget(cy, cy["RFP"], bottom, cy["MID"], cy["MIDF"], 0.0, units, fal,
                  n_offsets(max(wid / 2 - rt - fal, 0.0), rt, SIDE_STEP * rt), 5,
                  f"{SIDE_STEP * rt:g} mm apart (the tool radius {rt:g} mm)", count=num)
    for k in range(num):
        t0 = math.radians(cy["STA1"] + k * inda)
        t1 = t0 + math.radians(afsl)
        b = wid / 2 - rt

        def build(extra, t0=t0, t1=t1, b=b):
            return [arc_slot_loop(rad, b - extra - o, t0, t1, c) for o in offsets(b - extra, rt, SIDE_STEP * rt)]
        rough, fin = _loops_for(units, fal, lambda: build(fal), lambda: [arc_slot_loop(rad, b, t0, t1, c)])
        cut_region(cy, cy["RTP"], safe, cy["RFP"], bottom, _orient(rough, ccw), _orient(fin, ccw), cy["MID"],
                   cy["MIDF"], mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"])


def _rect_pocket(cy: Cycle, leng, wid, crad, centre, sta, mid, midf, fal, fald, units, mode, ffd, ffp1, ffp2,
                 cdir, rtp, rfp, sdis, bottom, step, helix_r=None, helix_pitch=None, circle=False):
    rt = cy.rt
    what = "pocket"
    if circle:
        if crad < rt - 1e-9:
            raise cy.err(f"the pocket radius {crad:g} is smaller than the tool radius {rt:g}")
    else:
        if min(leng, wid) < 2 * rt - 1e-9:
            raise cy.err(f"the tool (diameter {2 * rt:g}) is wider than the {what} ({leng:g} x {wid:g})")
        if crad < rt - 1e-9:
            raise cy.err(f"the corner radius CRAD {crad:g} is smaller than the tool radius {rt:g}")
        if crad > min(leng, wid) / 2 + 1e-9:
            raise cy.err(f"the corner radius CRAD {crad:g} is larger than half the pocket width")
    a, b, cr = leng / 2 - rt, wid / 2 - rt, crad - rt
    if min(a, b) - fal < -1e-9:
        raise cy.err(f"the finishing allowance {fal:g} leaves no room for the tool in the pocket")
    ang = math.radians(sta)
    ccw = cy.ccw(cdir)
    pitch = None
    if mode == 2:
        pitch = helix_pitch if helix_pitch and helix_pitch > 0 else max(rt / 2, 1e-3)
    mida_given = cy.name in ("POCKET3", "POCKET4") and cy["_MIDA"] > 0
    step_text = f"_MIDA {step:g} mm apart" if mida_given else f"{step:g} mm apart (the tool radius {rt:g} mm)"
    region_budget(cy, rfp, bottom, mid, midf, fald, units, fal, n_offsets(max(min(a, b) - fal, 0.0), rt, step),
                  9, step_text, helix_pitch=pitch)

    def build(extra):
        d = max(min(a, b) - extra, 0.0)
        return [rounded_rect_loop(max(a - extra - o, 0), max(b - extra - o, 0), cr - extra - o, centre, ang)
                for o in offsets(d, rt, step)]
    rough, fin = _loops_for(units, fal, lambda: build(fal), lambda: [rounded_rect_loop(a, b, cr, centre, ang)])
    helix = None
    if mode == 2:
        r = helix_r if helix_r and helix_r > 0 else rt / 2
        if r + rt > min(leng, wid) / 2 + 1e-9:
            raise cy.err(f"the helix radius {r:g} does not fit in the pocket with this tool")
        helix = (centre, r, pitch)
    cut_region(cy, rtp, rfp + sdis, rfp, bottom, _orient(rough, ccw), _orient(fin, ccw), mid, midf, mode, ffd, ffp1,
               ffp2, fald, helix)


def pocket1(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "LENG", "WID", "CRAD", "MID", "FAL", "MIDF")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1})
    _rect_pocket(cy, cy["LENG"], cy["WID"], cy["CRAD"], (cy["CPA"], cy["CPO"]), cy["STA1"], cy["MID"], cy["MIDF"],
                 cy["FAL"], 0.0, units, mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"], cy["CDIR"],
                 cy["RTP"], cy["RFP"], cy["SDIS"], cy.depth(), SIDE_STEP * cy.rt)


def pocket2(cy: Cycle):
    cy.need_radius()
    cy.unsigned("SDIS", "PRAD", "MID", "FAL", "MIDF")
    units, tens = _vari(cy)
    mode = _plunge_mode(cy, tens, {0, 1})
    r = cy["PRAD"]
    _rect_pocket(cy, 2 * r, 2 * r, r, (cy["CPA"], cy["CPO"]), 0.0, cy["MID"], cy["MIDF"], cy["FAL"], 0.0, units,
                 mode, cy["FFD"], cy["FFP1"], cy["FFP2"] or cy["FFP1"], cy["CDIR"], cy["RTP"], cy["RFP"], cy["SDIS"],
                 cy.depth(), SIDE_STEP * cy.rt, circle=True)


def _mida(cy: Cycle):
    mida = cy["_MIDA"]
    if mida < 0:
        raise cy.err("_MIDA is written without a sign")
    if mida > 2 * cy.rt + 1e-9:
        raise cy.err(f"_MIDA {mida:g} is larger than the tool diameter {2 * cy.rt:g}: material would be left")
    return mida if mida > 0 else SIDE_STEP * cy.rt


def pocket3(cy: Cycle):
    cy.need_radius()
    cy.unsigned("_SDIS", "_LENG", "_WID", "_CRAD", "_MID", "_FAL", "_FALD")
    units, tens = _vari(cy, "_VARI")
    mode = _plunge_mode(cy, tens, {0, 1, 2, 3})
    _rect_pocket(cy, cy["_LENG"], cy["_WID"], cy["_CRAD"], (cy["_PA"], cy["_PO"]), cy["_STA"], cy["_MID"], 0.0,
                 cy["_FAL"], cy["_FALD"] if units != 2 else 0.0, units, mode, cy["_FFD"], cy["_FFP1"], cy["_FFP1"],
                 cy["_CDIR"], cy["_RTP"], cy["_RFP"], cy["_SDIS"], cy.depth("_DP", None, "_RFP"), _mida(cy),
                 cy["_RAD1"], cy["_DP1"])


def pocket4(cy: Cycle):
    cy.need_radius()
    cy.unsigned("_SDIS", "_PRAD", "_MID", "_FAL", "_FALD")
    units, tens = _vari(cy, "_VARI")
    mode = _plunge_mode(cy, tens, {0, 1, 2})
    r = cy["_PRAD"]
    _rect_pocket(cy, 2 * r, 2 * r, r, (cy["_PA"], cy["_PO"]), 0.0, cy["_MID"], 0.0, cy["_FAL"],
                 cy["_FALD"] if units != 2 else 0.0, units, mode, cy["_FFD"], cy["_FFP1"], cy["_FFP1"], cy["_CDIR"],
                 cy["_RTP"], cy["_RFP"], cy["_SDIS"], cy.depth("_DP", None, "_RFP"), _mida(cy), cy["_RAD1"], cy["_DP1"],
                 circle=True)


def cycle71(cy: Cycle):
    cy.need_radius()
    cy.unsigned("_SDIS", "_MID", "_MIDA", "_FDP", "_FALD", "_FDP1")
    rt = cy.rt
    v = cy["_VARI"]
    if v < 0 or v != int(v):
        raise cy.err("_VARI must be a whole number without a sign")
    units, tens = int(v) % 10, (int(v) // 10) % 10
    if units not in (0, 1, 2):
        raise cy.err(f"_VARI units digit must be 1 (roughing) or 2 (finishing), got {units}")
    if tens not in (1, 2, 3, 4):
        raise cy.err(f"_VARI tens digit must be 1..4 (direction and one-way / zig-zag), got {tens}")
    leng, wid = cy["_LENG"], cy["_WID"]
    if leng == 0 or wid == 0:
        raise cy.err("_LENG and _WID must not be 0")
    along_first = tens in (1, 3)
    zigzag = tens in (3, 4)
    mida = cy["_MIDA"]
    if mida > 2 * rt + 1e-9:
        raise cy.err(f"_MIDA {mida:g} is larger than the tool diameter {2 * rt:g}: material would be left")
    step = mida if mida > 0 else FACE_STEP * rt
    ang = math.radians(cy["_STA"])
    corner = (cy["_PA"], cy["_PO"])
    u0, u1 = sorted((0.0, leng))
    v0, v1 = sorted((0.0, wid))
    if not along_first:  # cut along the second axis: swap the roles
        u0, u1, v0, v1 = v0, v1, u0, u1
    n = max(1, math.ceil((v1 - v0) / step - 1e-9))
    top, bottom, fald = cy["_RFP"], cy["_DP"], cy["_FALD"]
    nl = n_levels(top, bottom, cy["_MID"]) + 1
    budget(cy, nl * (3 * (n + 1) + 4), [(nl, f"infeeds of at most _MID {cy['_MID']:g} over {top - bottom:g} mm"),
                                        (n + 1, f"lines {step:g} mm apart" + (" (_MIDA)" if mida > 0 else
                                                                            f" (the tool radius {rt:g} mm)"))])
    vs = [v0 + (v1 - v0) * k / n for k in range(n + 1)]
    ext0 = rt + (cy["_FDP"] if cy["_FDP"] > 0 else cy["_SDIS"])
    ext1 = rt + cy["_FDP1"]

    def G(u, v):
        p = (u, v) if along_first else (v, u)
        return _rot(p, ang, corner)
    levels = []
    if units in (0, 1):
        levels += cy.levels(top, bottom + (fald if units == 1 or fald > 0 else 0.0), cy["_MID"])
    if units == 2 or (units == 0 and fald > 0):
        levels.append(bottom)
    f = cy["_FFP1"]
    safe = top + cy["_SDIS"]
    cy.start(cy["_RTP"], G(u0 - ext0, vs[0]))
    for j, lv in enumerate(levels):
        # one-way returns in G0 run _SDIS above the material this level cuts (its top is the level
        # before, or RFP), not above the level itself: that would cut the lines still to come
        back = (levels[j - 1] if j and levels[j - 1] > lv else top) + cy["_SDIS"]
        cy.rapid(G(u0 - ext0, vs[0]), max(safe, lv + cy["_SDIS"]) if cy.m.pos[2] > lv else cy.m.pos[2])
        cy.feed_to(G(u0 - ext0, vs[0]), lv, f)
        fwd = True
        for k, v in enumerate(vs):
            if fwd:
                a, b = G(u0 - ext0, v), G(u1 + ext1, v)
            else:
                a, b = G(u1 + ext1, v), G(u0 - ext0, v)
            if k:
                if zigzag:
                    cy.feed_to(a, lv, f)
                else:
                    cy.rapid(cy.pos2(), back)
                    cy.rapid(a, back)
                    cy.feed_to(a, lv, f)
            cy.feed_to(b, lv, f)
            if zigzag:
                fwd = not fwd
        cy.rapid(cy.pos2(), safe)
        cy.rapid(G(u0 - ext0, vs[0]), safe)
    cy.finish(cy["_RTP"])


RUNNERS = {"SLOT1": slot1, "SLOT2": slot2, "POCKET1": pocket1, "POCKET2": pocket2, "POCKET3": pocket3,
           "POCKET4": pocket4, "CYCLE71": cycle71, "CYCLE72": cycle72}


def run_cycle(m, name: str, args, src: Src, col: int, label: str | None = None) -> None:
    """Run the cycle ``name`` called at ``src`` (column ``col``) with evaluated ``args``
    [(value or None, column)] on the machine ``m`` (a Sinumerik interpreter); ``label`` names it in
    the messages (the ISO shell's "G83 (CYCLE83)")."""
    label = label or name
    if m.comp_buf is not None:
        raise m.error(src.line, 1, f"{label} cannot run with radius compensation G41/G42 on: program G40 first")
    _check_plane(m, name, src, label)
    cy = Cycle(m, name, args, src, col, label)
    motion = m.motion
    RUNNERS[name](cy)
    m.motion = motion


PATTERNS = ("HOLES1", "HOLES2", "CYCLE801")


def _check_plane(m, name: str, src: Src, label: str) -> None:
    """The plane (and machine) a cycle runs in: the milling cycles in G17; the turning cycles in G18
    on a lathe; the drilling cycles in G17, or on a lathe in G18 too, along Z on the spindle axis."""
    lathe = m.cfg.machine_kind == "lathe"
    if name in TURNING:
        if not lathe:
            raise m.error(src.line, 1, f"{label} is a turning cycle: it runs on a lathe ([machine] kind = \"lathe\")")
        if m.plane != "ZX":
            g = {"XY": "G17", "YZ": "G19"}[m.plane]
            raise m.error(src.line, 1, f"{label} turns in G18 (Z the longitudinal, X the transverse axis), not in "
                          f"{g}: program G18 before the call")
        return
    if name in DRILLING and lathe:
        if name in PATTERNS:
            raise m.error(src.line, 1, f"{label} on a lathe: a hole pattern lies off the spindle axis, and a lathe "
                          "drills on the axis (X0)")
        if m.plane in ("XY", "ZX"):
            if abs(m.pos[0]) > 1e-6 or abs(m.pos[1]) > 1e-6:
                raise m.error(src.line, 1, f"{label} on a lathe drills along Z on the spindle axis: the tool stands "
                              f"at X{m.pos[0] / x_factor(m.machine, True):g}, bring it to X0 first")
            return
    if m.plane != "XY" and name in DRILLING:
        g, axis = ("G18", "Y") if m.plane == "ZX" else ("G19", "X")
        raise m.error(src.line, 1, f"{label} in {g} drills along {axis}: the simulated tool stands along Z (a "
                      "vertical 3-axis machine), so drilling along another axis is not simulated; program the "
                      "holes in G17")
    if m.plane != "XY":
        raise m.error(src.line, 1, f"{label} is simulated in the G17 plane only")
