"""Lathe inserts as profiles: ISO turning inserts in a holder, grooving inserts, full-profile
thread inserts, and the orientation every lathe tool takes (hand, outside / inside / face).

Every profile is built in the frame of an outside tool of hand R: u radial outwards from the tool
point, v axial (+Z); the tool points to -u (and, for hand R, to -v: it cuts towards the chuck).
The control point (what X and Z program) is the origin: for a tool with a hand the theoretical
(imaginary) tip, the corner of the box around the nose (its lowest u and lowest v), for a neutral
tool the lowest point of the nose. ``orient`` then mirrors v for hand L, u for an inside tool
(pointing to +X, boring), and swaps u and v for a face tool (pointing to -Z).

ISO inserts are tangential polygons: every edge touches the inscribed circle of diameter
``size`` (the "IC" of the ISO code), so each shape is given by the turning angles of its outline
(``EXTERIOR``); every corner is rounded with the nose radius, as the insert is ground.
"""
from __future__ import annotations

import math

import numpy as np

from cutsim.base.specs import ToolSpec
from cutsim.kinematics.paths import segment_angle

# outside turning angles (degrees) of the outline from the nose corner on, per ISO shape letter;
# the nose corner's angle is 180 minus the first
EXTERIOR = {
    "C": (100.0, 80.0, 100.0, 80.0),  # rhombus 80
    "D": (125.0, 55.0, 125.0, 55.0),  # rhombus 55
    "V": (145.0, 35.0, 145.0, 35.0),  # rhombus 35
    "T": (120.0, 120.0, 120.0),  # triangle 60
    "S": (90.0, 90.0, 90.0, 90.0),  # square 90
    "W": (100.0, 20.0, 100.0, 20.0, 100.0, 20.0),  # trigon: corners of 80 and 160
}
INSERT_SHAPES = tuple(EXTERIOR) + ("R",)  # R: round
BAR_REACH_FACTOR = 0.7  # a boring bar's default reach: axis to tool point, x its diameter (catalogue bars 0.65-0.75)
CREST_OVERLAP = 1.0  # x the tolerance: how far a full-profile insert's shoulders reach beyond +-P/2
DEFAULT_APPROACH = 93.0  # degrees, or the largest the insert allows (180 - its corner angle)


def corner_angle(shape: str) -> float:
    """The nose corner's included angle of an ISO insert shape (degrees; 360 for a round one)."""
    return 360.0 if shape == "R" else 180.0 - EXTERIOR[shape][0]


def approach_of(tool: ToolSpec) -> float:
    """The holder's approach angle kappa_r (the main cutting edge against the feed direction):
    ``approach``, or DEFAULT_APPROACH when it is 0 (at most 180 - the corner angle)."""
    if tool.approach:
        return tool.approach
    return min(DEFAULT_APPROACH, 180.0 - corner_angle(tool.insert))


def _arc(c: tuple[float, float], r: float, a0: float, a1: float, tol: float) -> np.ndarray:
    """Points of the arc of radius ``r`` about ``c`` from angle ``a0`` to ``a1`` (degrees,
    a1 >= a0), chords within ``tol``; the directions 90, 180, 270 and 360 are vertices when on
    the arc, so the extremes of the nose (its lowest u and v) are exact."""
    if r <= 0 or a1 <= a0:
        return np.array([[c[0] + r * math.cos(math.radians(a0)), c[1] + r * math.sin(math.radians(a0))]])
    k = max(1, math.ceil(math.radians(a1 - a0) / segment_angle(r, tol)))
    angles = set(np.linspace(a0, a1, k + 1).tolist())
    angles |= {a for a in (90.0, 180.0, 270.0, 360.0) if a0 < a < a1}
    a = np.radians(np.array(sorted(angles)))
    return np.column_stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)])


def tangential_polygon(ext: tuple[float, ...], rho: float, rn: float, a_in: float,
                       tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Counter-clockwise outline of an insert whose edges touch a circle of radius ``rho`` about
    the origin, the first edge's outward normal at ``a_in`` degrees and each next one turned by
    ``ext``; every corner rounded with radius ``rn``. Returns (outline, centre of the first
    corner's arc: the nose)."""
    normals = a_in + np.concatenate([[0.0], np.cumsum(ext)])  # edge i has normal normals[i]
    inner = rho - rn
    pts, nose = [], None
    for i in range(len(ext)):
        al, be = normals[i], normals[i + 1]
        mid = math.radians(0.5 * (al + be))
        d = inner / math.cos(math.radians(0.5 * (be - al)))
        c = (d * math.cos(mid), d * math.sin(mid))
        if nose is None:
            nose = np.array(c)
        pts.append(_arc(c, rn, al, be, tol))
    return np.vstack(pts), nose


def insert_profile(tool: ToolSpec, tol: float) -> np.ndarray:
    """An ISO turning insert in its holder, outside hand R frame (module docstring): the main
    cutting edge leaves the nose at kappa_r - 90 degrees from +u towards +Z, the insert lying
    between it and the minor edge, ``corner_angle`` further round; hand N points the corner's
    bisector at -u."""
    rho, rn = tool.size / 2.0, tool.tip_radius
    neutral = tool.hand == "N"
    if tool.insert == "R":
        poly = _arc((rho, 0.0 if neutral else rho), rho, 0.0, 360.0, tol)[:-1]
        return poly
    eps = corner_angle(tool.insert)
    a_in = 90.0 + eps / 2.0 if neutral else approach_of(tool) + eps
    poly, nose = tangential_polygon(EXTERIOR[tool.insert], rho, rn, a_in, tol)
    tip = nose - (rn, 0.0 if neutral else rn)
    return poly - tip


def groove_profile(tool: ToolSpec, tol: float) -> np.ndarray:
    """A grooving or parting insert: its cutting edge ``width`` wide at u = 0 with both corners
    rounded by ``corner_radius``, its sides reaching ``height`` out (the depth it can plunge).
    Hand R: the control point is the corner towards -Z; N: the middle of the edge."""
    w, h, rc = tool.width, tool.height, tool.corner_radius
    v0 = -w / 2.0 if tool.hand == "N" else 0.0
    lower = _arc((rc, v0 + rc), rc, 180.0, 270.0, tol)
    upper = _arc((rc, v0 + w - rc), rc, 90.0, 180.0, tol)
    return np.vstack([lower, [[h, v0], [h, v0 + w]], upper])


def full_thread_depths(tool: ToolSpec) -> tuple[float, float, float]:
    """(flat half-width at the tip or 0, apex-to-tip distance, tip-to-crest distance) of a
    full-profile ISO metric insert (ISO 68-1 basic profile, H = sqrt(3)/2 P): outside its tip
    forms the bolt's root, flat P/4 wide (H/4 above the fundamental triangle's apex) or rounded
    with ``tip_radius``, and its shoulders the crest at the major diameter, 7H/8 above the apex;
    inside its tip forms the nut's root at the major diameter, flat P/8 (H/8), and its shoulders
    the nut's crest at the minor diameter, 3H/4 above the apex."""
    p = tool.pitch
    big_h = math.sqrt(3.0) / 2.0 * p
    t30 = math.tan(math.radians(30.0))
    inside = tool.side == "inside"
    apex_to_crest = 0.75 * big_h if inside else 0.875 * big_h
    if tool.tip_radius > 0:
        half, ta = 0.0, tool.tip_radius  # a 60 degree V's nose: lowest point r above the apex
    else:
        half = p / 16.0 if inside else p / 8.0
        ta = half / t30
    return half, ta, apex_to_crest - ta


def full_thread_profile(tool: ToolSpec, tol: float) -> np.ndarray:
    """A full-profile ISO metric thread insert (``full_thread_depths``), pointing to -u, centred:
    60 degree flanks up to the crest level (the corners to the shoulders rounded with
    ``crest_radius``: the crest's edges on the part), then shoulders out to +-(P/2 + ``tol``) (each pass
    cuts half of the crest on either side; the next turn the other half) and sides up to
    ``height``.

    The shoulders overlap the next turn's by ``tol`` on either side (``CREST_OVERLAP``): cut
    exactly P wide, neighbouring turns would only touch along a helical surface that each sweep
    facets with its own diagonals (stock/sweeps.py), the two facetings bowing apart for one hand
    and leaving a sliver of uncut stock up to the blank's diameter on the crest (every left-hand
    thread did, M03 feeding +Z or M04 feeding -Z). Overlapping, the turns are one profile folded
    onto a turn (stock/threads.py) and the crest is cut whole; the overlap changes only the
    crest's axial ends of the thread, within the tolerance."""
    half, ta, uc = full_thread_depths(tool)
    t30 = math.tan(math.radians(30.0))
    wc = (uc + ta) * t30  # half-width at the crest level
    p2 = tool.pitch / 2.0 + CREST_OVERLAP * tol
    if tool.tip_radius > 0:
        tip = _arc((tool.tip_radius, 0.0), tool.tip_radius, 120.0, 240.0, tol)
    else:
        tip = np.array([[0.0, half], [0.0, -half]])
    rc = tool.crest_radius
    # the corner between a flank and a shoulder rounded with rc (the crest's edge on the part): the
    # centre rc below the shoulder and rc tan 30 beyond the corner, the arc from the flank (60
    # degrees from the shoulder's normal) to the shoulder
    lower = _arc((uc - rc, -(wc + rc * t30)), rc, 0.0, 60.0, tol)[::-1] if rc > 0 else np.array([[uc, -wc]])
    upper = _arc((uc - rc, wc + rc * t30), rc, -60.0, 0.0, tol)[::-1] if rc > 0 else np.array([[uc, wc]])
    rest = np.array([[uc, -p2], [tool.height, -p2], [tool.height, p2], [uc, p2]])
    return np.vstack([tip, lower, rest, upper])


def orient(poly: np.ndarray, tool: ToolSpec) -> np.ndarray:
    """The profile from the outside hand R frame into the tool's own: v mirrored for hand L (a
    turning insert or grooving tool), u for an inside tool, u and v swapped for a face tool."""
    out = np.array(poly, dtype=float)
    if tool.hand == "L" and (tool.kind == "grooving" or tool.kind == "turning" and tool.insert):
        out[:, 1] = -out[:, 1]
    if tool.side == "inside":
        out[:, 0] = -out[:, 0]
    elif tool.side == "face":
        out = out[:, ::-1].copy()
    return out


def bar_reach(tool: ToolSpec) -> float:
    """From the boring bar's axis to the tool point (radially), mm: ``bar_reach``, or
    BAR_REACH_FACTOR x ``bar_diameter`` when it is 0."""
    return tool.bar_reach or BAR_REACH_FACTOR * tool.bar_diameter


def bar_section(tool: ToolSpec, start: float, length: float) -> np.ndarray:
    """The boring bar of an inside tool in the workpiece's X-Z plane, relative to the tool point:
    the band its round body covers across X (its axis ``bar_reach`` towards the spindle axis from
    the tool point, ``bar_diameter`` wide) from ``start`` above the tool point (behind the insert)
    ``length`` along +Z, out of the bore towards the turret. Revolved about the spindle axis this
    is what the bar meets of a part turning past it: exact for a round bar, at every angle."""
    x0 = -bar_reach(tool) - tool.bar_diameter / 2.0
    x1 = x0 + tool.bar_diameter
    z0, z1 = start, start + length
    return np.array([[x0, z0], [x1, z0], [x1, z1], [x0, z1]])


def bar_message(tool: ToolSpec, vol: float) -> str:
    return (f"the boring bar of T{tool.number} (diameter {tool.bar_diameter:g} mm, its axis {bar_reach(tool):g} mm "
            f"from the tool point) meets the stock: {vol:.3f} mm^3 (too thick for this bore)")


# -- holders of outside and face tools --------------------------------------------------------------
SHANKS = (12.0, 16.0, 20.0, 25.0, 32.0, 40.0, 50.0)  # ISO 5610 square shanks (h = b), mm
SHANK = 20.0  # mm: the default shank of a V turning or thread tool and of a narrow grooving tool
GROOVE_WIDE = 3.0  # mm: a grooving insert wider than this sits in a 25 mm holder by default


def default_shank(kind: str, insert: str, size: float, width: float) -> float:
    """The square shank an outside or face holder has unless the setup gives ``shank``: for an ISO
    turning insert the ISO 5610 square nearest twice its inscribed circle (a 12.7 mm CNMG 1204 in a
    25 x 25 holder, a 9.525 mm one in a 20 x 20), for a grooving insert 20 (25 wider than 3 mm),
    for a V or thread tool 20."""
    if kind == "turning" and insert:
        return min(SHANKS, key=lambda s: (abs(s - 2.0 * size), s))
    if kind == "grooving" and width > GROOVE_WIDE:
        return 25.0
    return SHANK


def main_edge_end(tool: ToolSpec) -> np.ndarray:
    """(u, v) of the far end of an ISO insert's main cutting edge, the sharp corner after the nose,
    from the control point, outside hand R frame (a neutral insert: the end of either edge; a
    round insert: its centre). Where the holder's body begins."""
    rho, rn = tool.size / 2.0, tool.tip_radius
    neutral = tool.hand == "N"
    if tool.insert == "R":
        return np.array([rho, 0.0 if neutral else rho])
    eps = corner_angle(tool.insert)
    a_in = 90.0 + eps / 2.0 if neutral else approach_of(tool) + eps
    _, nose = tangential_polygon(EXTERIOR[tool.insert], rho, rn, a_in, 1.0)
    sharp, _ = tangential_polygon(EXTERIOR[tool.insert], rho, 0.0, a_in, 1.0)
    return sharp[1] - (nose - (rn, 0.0 if neutral else rn))


def holder_start(tool: ToolSpec) -> tuple[float, float]:
    """(u0, v0) of an outside or face holder's body in the outside hand R frame: its face towards
    the part at u0 above the tool point, its side towards -Z at v0. An ISO insert's holder begins
    where the main cutting edge ends (``main_edge_end``: the edge stands free, the body behind it),
    a grooving blade's at ``height`` (its reach) flush with the edge's corner towards -Z, a V or
    thread tool's at ``height`` flush with the profile's side towards -Z."""
    if tool.kind == "turning" and tool.insert:
        u0, v0 = main_edge_end(tool)
        return float(u0), float(v0)
    if tool.kind == "grooving":
        return tool.height, 0.0
    if tool.kind == "thread" and tool.form == "full":
        return tool.height, -tool.pitch / 2.0
    half = math.radians(tool.angle) / 2.0
    w = tool.height * math.tan(half) + tool.tip_radius * (1.0 - math.sin(half)) / math.cos(half)
    return tool.height, -w


def holder_section(tool: ToolSpec, reach: float) -> np.ndarray | None:
    """The holder's body of an outside or face tool in the workpiece's X-Z plane, relative to the
    tool point: a square shank ``shank`` wide from ``holder_start`` back to ``reach`` from the tool
    point (radially; a face tool's axially), towards +Z from its side (hand R), towards -Z (hand L)
    or centred on the tool point (hand N; a thread tool's hand places only its holder). Revolved
    about the spindle axis this is what the body meets of a part turning past it (the shank's face
    towards the part lies at the tool point's height). None when the body begins beyond ``reach``."""
    u0, v0 = holder_start(tool)
    if reach <= u0:
        return None
    b = tool.shank
    if tool.hand == "N":
        v0 = -b / 2.0
    poly = np.array([[u0, v0], [reach, v0], [reach, v0 + b], [u0, v0 + b]])
    if tool.hand == "L":
        poly[:, 1] = -poly[:, 1]
    return poly[:, ::-1].copy() if tool.side == "face" else poly


def body_message(tool: ToolSpec, vol: float) -> str:
    """The warning for a tool's body (boring bar or holder) meeting ``vol`` mm^3 of material."""
    if tool.bar_diameter:
        return bar_message(tool, vol)
    u0 = holder_start(tool)[0]
    return (f"the holder of T{tool.number} ({tool.shank:g} x {tool.shank:g} mm shank, {u0:.3f} mm behind the tool "
            f"point) meets the stock: {vol:.3f} mm^3 (deeper than the insert reaches)")
