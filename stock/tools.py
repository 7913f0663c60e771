"""Tool shapes, built so that orientation and degeneracy cannot silently lose them.

Lathe tools are profiles in the (u, v) plane of the tool: u radial outwards from the tool point
(+X), v axial (+Z); the control point is the origin, the lowest point of the nose. Every profile
is returned as a simple counter-clockwise polygon of positive area (checked); mill bodies are
convex vertex clouds whose hull has positive volume (checked once per tool and tolerance).

The documented ranges of the tool keys (docs/setup.md, ``[[tool]]``) live here, in
``tool_problem``: the setup loader reports a value out of range at its key, and a tool built
in Python (a ``ToolSpec`` the loader never saw) is checked again before its shape is built. A shape
that still comes out (nearly) empty is a CutsimError naming the tool's ``[[tool]]`` table.
"""
from __future__ import annotations

import functools
import math

import manifold3d as m3d
import numpy as np

from cutsim.interp.errors import CutsimError
from cutsim.kinematics.paths import segment_angle

from cutsim.base.specs import ToolSpec

# -- documented ranges (docs/setup.md) ---------------------------------------------------------
SIZE_MIN = 0.001  # mm: every length of a tool (diameter, flute length, height, thickness, radii > 0)
SIZE_MAX = 10_000.0  # mm
ANGLE_MIN, ANGLE_MAX = 1.0, 179.0  # degrees: included angle of a thread or turning V
COORD_MAX = SIZE_MAX  # mm: profile tool points lie within +-COORD_MAX of the control point
# A region whose mean width (2 area / perimeter; a solid's 3 volume / surface) is below this is
# degenerate: a line, a point, or a sliver no machine could hold. It is a thousandth of SIZE_MIN,
# so every tool within the ranges stays far above it.
MIN_WIDTH = 1e-6  # mm

# Flutes longer than this many diameters make a body so thin that convex hulls (which merge
# points closer than a fraction of the cloud's size) lose its roundness.
MAX_FLUTE_RATIO = 1000.0

LATHE_KINDS = ("thread", "turning", "grooving", "profile")
SIDES = ("outside", "inside", "face")
HANDS = ("R", "L", "N")
MILL_KINDS = ("endmill", "ballmill")
POINT_ANGLE_MAX = 180.0  # degrees: a drill's included point angle (180: a flat end)


def _size(tool: ToolSpec, key: str, zero_ok: bool = False) -> tuple[str, str] | None:
    v = getattr(tool, key)
    if zero_ok and v == 0:
        return None
    if not (isinstance(v, (int, float)) and math.isfinite(v) and SIZE_MIN <= v <= SIZE_MAX):
        what = "0 or " if zero_ok else ""
        return key, f"must be {what}between {SIZE_MIN:g} and {SIZE_MAX:g} mm (got {v!r})"
    return None


def _choice(tool: ToolSpec, key: str, options: tuple[str, ...]) -> tuple[str, str] | None:
    v = getattr(tool, key)
    if v not in options:
        return key, f"must be one of {', '.join(repr(o) for o in options)} (got {v!r})"
    return None


def _insert_problem(tool: ToolSpec) -> tuple[str | None, str] | None:
    """Ranges of an ISO turning insert (docs/setup.md): shape, size, nose radius below half the
    inscribed circle, approach between 90 and 180 - the corner angle (the imaginary tip then lies
    on the nose: the main edge leaves it no lower than the feed and the minor edge clears the
    face)."""
    from .inserts import INSERT_SHAPES, corner_angle

    if tool.insert not in INSERT_SHAPES:
        return "insert", f"must be one of {', '.join(INSERT_SHAPES)} (got {tool.insert!r})"
    for key, zero_ok in (("size", False), ("tip_radius", True), ("thickness", False)):
        p = _size(tool, key, zero_ok)
        if p:
            return p
    if tool.insert != "R" and not tool.tip_radius < tool.size / 2.0:
        return "tip_radius", f"must be below half the insert's size ({tool.size / 2.0:g} mm) (got {tool.tip_radius!r})"
    eps = corner_angle(tool.insert)
    hi = 180.0 - eps if eps < 360.0 else 180.0
    a = tool.approach
    if a != 0 and not (math.isfinite(a) and 90.0 <= a <= hi):
        return "approach", (f"must be between 90 and {hi:g} degrees for a {tool.insert} insert (180 - its {eps:g} "
                            f"degree corner) (got {a!r})")
    return None


def _bar_problem(tool: ToolSpec) -> tuple[str, str] | None:
    """A boring bar (``bar_diameter``, ``bar_reach``) belongs to an inside tool; its tool point
    stands out of it: the reach is more than half its diameter."""
    from .inserts import bar_reach

    if tool.bar_diameter == 0 and tool.bar_reach == 0:
        return None
    key = "bar_diameter" if tool.bar_diameter != 0 else "bar_reach"
    if tool.side != "inside":
        return key, 'is a boring bar\'s: only an inside tool (side = "inside") has one'
    if tool.bar_diameter == 0:
        return key, "is a boring bar's: give its bar_diameter too"
    p = _size(tool, "bar_diameter") or _size(tool, "bar_reach", zero_ok=True)
    if p:
        return p
    if not bar_reach(tool) > tool.bar_diameter / 2.0:
        return "bar_reach", (f"must be more than half the bar's diameter ({tool.bar_diameter / 2.0:g} mm): the "
                             f"tool point stands out of the bar (got {bar_reach(tool)!r})")
    return None


def _shank_problem(tool: ToolSpec) -> tuple[str, str] | None:
    """A holder's square shank (``shank``) belongs to an outside or face tool: 0 (no holder) or a size."""
    if tool.shank == 0:
        return None
    if tool.side == "inside":
        return "shank", "is an outside or face holder's: an inside tool's body is its boring bar (bar_diameter)"
    return _size(tool, "shank")


def _lathe_problem(tool: ToolSpec) -> tuple[str | None, str] | None:
    """Side and hand of a thread, turning or grooving tool; a turning insert, a grooving insert
    or a full-profile thread insert in range (the V of thread and turning tools: ``tool_problem``)."""
    p = (_choice(tool, "side", SIDES) or _choice(tool, "hand", HANDS) or _bar_problem(tool)
         or _shank_problem(tool))
    if p:
        return p
    if tool.kind == "turning" and tool.insert:
        return _insert_problem(tool) or ("", "")
    if tool.kind == "grooving":
        for key, zero_ok in (("width", False), ("height", False), ("thickness", False), ("corner_radius", True)):
            p = _size(tool, key, zero_ok)
            if p:
                return p
        if not tool.corner_radius <= min(tool.width / 2.0, tool.height):
            return "corner_radius", (f"must be at most half the width ({tool.width / 2.0:g} mm) and the height "
                                     f"(got {tool.corner_radius!r})")
        return ("", "")
    if tool.kind == "thread" and tool.form != "partial":
        if tool.form != "full":
            return "form", f"must be 'partial' or 'full' (got {tool.form!r})"
        for key, zero_ok in (("pitch", False), ("tip_radius", True), ("height", False), ("thickness", False)):
            p = _size(tool, key, zero_ok)
            if p:
                return p
        if tool.angle != 60.0:
            return "angle", f"a full-profile insert is the ISO metric 60 degree profile (got {tool.angle!r})"
        from .inserts import full_thread_depths

        h = math.sqrt(3.0) / 2.0 * tool.pitch
        if not tool.tip_radius <= h / 4.0:
            return "tip_radius", (f"must be at most H/4 = {h / 4.0:g} mm for pitch {tool.pitch:g} (the root's "
                                  f"rounding) (got {tool.tip_radius!r})")
        uc = full_thread_depths(tool)[2]
        if not tool.height > uc:
            return "height", f"must reach beyond the crest level, {uc:g} mm from the tip (got {tool.height!r})"
        p = _size(tool, "crest_radius", True)
        if p:
            return p
        rmax = crest_radius_max(tool)
        if not tool.crest_radius <= rmax:
            return "crest_radius", (f"must be at most {rmax:g} mm for pitch {tool.pitch:g} {tool.side} (its two "
                                    f"roundings fill the crest's flat) (got {tool.crest_radius!r})")
        return ("", "")
    if tool.crest_radius != 0:
        return "crest_radius", 'is a key of a full-profile thread insert (form = "full")'

    return None


def crest_radius_max(tool: ToolSpec) -> float:
    """The largest crest radius of a full-profile insert: each rounding of the crest's edges (the
    part's crest corner is 120 degrees) takes r tan 30 of the crest's flat, P/8 wide outside (the
    bolt's major diameter), P/4 inside (the nut's minor diameter): r <= P / (16 tan 30) = 0.108 P
    outside, P / (8 tan 30) = 0.217 P inside."""
    flat = tool.pitch / 4.0 if tool.side == "inside" else tool.pitch / 8.0
    return flat / (2.0 * math.tan(math.radians(30.0)))


def tool_problem(tool: ToolSpec) -> tuple[str | None, str] | None:
    """The first key of ``tool`` outside its documented range and why, or None. (key None: the
    tool as a whole.)"""
    if tool.kind in ("thread", "turning", "grooving"):
        p = _lathe_problem(tool)
        if p is not None:
            return p if p[0] else None
    if tool.kind in ("thread", "turning"):
        a = tool.angle
        if not (math.isfinite(a) and ANGLE_MIN <= a <= ANGLE_MAX):
            return "angle", f"must be between {ANGLE_MIN:g} and {ANGLE_MAX:g} degrees (got {a!r})"
        for key, zero_ok in (("tip_radius", True), ("height", False), ("thickness", False)):
            p = _size(tool, key, zero_ok)
            if p:
                return p
        if tool.tip_radius > 0:
            ut = nose_end(tool)
            if ut >= tool.height:
                return "tip_radius", (f"is too large for the tool's height: the nose arc of radius {tool.tip_radius:g} "
                                      f"meets the flanks {ut:g} mm out, not below height = {tool.height:g}")
        return None
    if tool.kind == "profile":
        p = _size(tool, "thickness")
        if p:
            return p
        why = polygon_problem(np.array(tool.points, dtype=float).reshape(-1, 2))
        return ("points", why) if why else None
    if tool.kind == "drill":
        for key in ("diameter", "length"):
            p = _size(tool, key)
            if p:
                return p
        a = tool.point_angle
        if not (isinstance(a, (int, float)) and math.isfinite(a) and ANGLE_MIN <= a <= POINT_ANGLE_MAX):
            return "point_angle", f"must be between {ANGLE_MIN:g} and {POINT_ANGLE_MAX:g} degrees (got {a!r})"
        if tool.length > MAX_FLUTE_RATIO * tool.diameter:
            return "length", (f"must be at most {MAX_FLUTE_RATIO:g} x the diameter ({MAX_FLUTE_RATIO * tool.diameter:g} mm) "
                              f"(got {tool.length!r})")
        h = point_height(tool)
        if tool.length < h:
            return "length", (f"must be at least the height of the point ({h:g} mm for a {a:g} degree point of "
                              f"diameter {tool.diameter:g}) (got {tool.length!r})")
        return None
    if tool.is_axial:
        return _axial_problem(tool)
    if tool.kind in MILL_KINDS:
        for key in ("diameter", "length"):
            p = _size(tool, key)
            if p:
                return p
        if tool.length > MAX_FLUTE_RATIO * tool.diameter:
            return "length", (f"must be at most {MAX_FLUTE_RATIO:g} x the diameter ({MAX_FLUTE_RATIO * tool.diameter:g} mm) "
                              f"(got {tool.length!r})")
        rc = tool.corner_radius
        r = tool.diameter / 2.0
        if not (math.isfinite(rc) and (rc == 0 or SIZE_MIN <= rc <= r * (1 + 1e-12))):
            return "corner_radius", f"must be 0 or between {SIZE_MIN:g} mm and half the diameter ({r:g}) (got {rc!r})"
        return None
    return "kind", f"is not a tool kind cutsim knows (got {tool.kind!r})"


def _axial_problem(tool: ToolSpec) -> tuple[str | None, str] | None:
    """Ranges of a centre drill or a tap (docs/setup.md)."""
    from .axial import COUNTERSINKS, countersink_top

    keys = ("diameter", "pilot_length", "body_diameter", "length") if tool.kind == "centredrill" else (
        "diameter", "pitch", "length")
    for key in keys:
        p = _size(tool, key)
        if p:
            return p
    if tool.kind == "tap":
        if not tool.pitch <= tool.diameter / 2.0:
            return "pitch", f"must be at most half the diameter ({tool.diameter / 2.0:g} mm) (got {tool.pitch!r})"
        if not (math.isfinite(tool.chamfer) and 0.0 <= tool.chamfer <= tool.length):
            return "chamfer", f"must be between 0 and the thread length ({tool.length:g} mm) (got {tool.chamfer!r})"
        if tool.length > MAX_FLUTE_RATIO * tool.diameter:
            return "length", (f"must be at most {MAX_FLUTE_RATIO:g} x the diameter ({MAX_FLUTE_RATIO * tool.diameter:g} "
                              f"mm) (got {tool.length!r})")
        return None
    a = tool.point_angle
    if not (isinstance(a, (int, float)) and math.isfinite(a) and ANGLE_MIN <= a <= POINT_ANGLE_MAX):
        return "point_angle", f"must be between {ANGLE_MIN:g} and {POINT_ANGLE_MAX:g} degrees (got {a!r})"
    if tool.countersink not in COUNTERSINKS:
        return "countersink", f"must be 60 or 90 degrees (got {tool.countersink!r})"
    if not tool.body_diameter > tool.diameter:
        return "body_diameter", f"must be larger than the pilot's diameter ({tool.diameter:g} mm) (got {tool.body_diameter!r})"
    hp = point_height(tool)
    if not tool.pilot_length > hp:
        return "pilot_length", (f"must be more than the height of the pilot's point ({hp:g} mm) "
                                f"(got {tool.pilot_length!r})")
    top = countersink_top(tool)
    if not tool.length >= top:
        return "length", f"must reach at least the top of the countersink ({top:g} mm from the tip) (got {tool.length!r})"
    if tool.length > MAX_FLUTE_RATIO * tool.body_diameter:
        return "length", (f"must be at most {MAX_FLUTE_RATIO:g} x the body diameter (got {tool.length!r})")
    return None


def tool_error(tool: ToolSpec, message: str) -> CutsimError:
    """An error about ``tool``'s shape, at the line of its [[tool]] table."""
    return CutsimError(tool.source or "<setup>", tool.line, tool.col, f"[[tool]] T{tool.number}: {message}")


def check_tool(tool: ToolSpec) -> None:
    """Raise the CutsimError of ``tool_problem`` (for tools that did not come through the loader)."""
    p = tool_problem(tool)
    if p is not None:
        key, why = p
        raise tool_error(tool, f"{key + ': ' if key else ''}{why}")


# -- polygons ------------------------------------------------------------------------------------
def signed_area(poly: np.ndarray) -> float:
    """Shoelace area: positive for a counter-clockwise polygon."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def perimeter(poly: np.ndarray) -> float:
    return float(np.sum(np.hypot(*(np.roll(poly, -1, axis=0) - poly).T)))


def polygon_problem(poly: np.ndarray, limit: float | None = COORD_MAX) -> str | None:
    """Why ``poly`` is not a usable tool region (None if it is): too few points, coordinates not
    finite or beyond ``limit``, a self-crossing outline (the region it encloses would depend on a
    fill rule), or (almost) no area."""
    if poly.ndim != 2 or poly.shape[1] != 2 or len(poly) < 3:
        return "must be a polygon of at least 3 points"
    if not np.all(np.isfinite(poly)) or limit is not None and np.max(np.abs(poly)) > limit:
        return f"coordinates must lie within +-{limit:g} mm of the control point"
    a = signed_area(poly)
    per = perimeter(poly)
    # a simple outline: the regions by the non-zero and even-odd rules are the shoelace area (a
    # crossing outline has lobes of opposite sign or counted twice, and those differ)
    nz = m3d.CrossSection([poly], m3d.FillRule.NonZero).area()
    eo = m3d.CrossSection([poly], m3d.FillRule.EvenOdd).area()
    eps = 1e-6 * abs(a) + 1e-7 * per  # Clipper rounds the coordinates: about 1e-8 mm x the outline
    if abs(nz - abs(a)) > eps or abs(eo - abs(a)) > eps:
        return "the polygon crosses itself"
    if per <= 0 or 2.0 * abs(a) / per < MIN_WIDTH:
        return "the polygon encloses (almost) no area"
    return None


def counter_clockwise(poly: np.ndarray) -> np.ndarray:
    """``poly`` in counter-clockwise order (explicitly normalised, never assumed)."""
    poly = np.asarray(poly, dtype=float)
    return poly if signed_area(poly) > 0 else poly[::-1].copy()


def nose_end(tool: ToolSpec) -> float:
    """u where the nose arc of a thread/turning tool meets its flanks (0 without a nose)."""
    half = math.radians(tool.angle) / 2.0
    return tool.tip_radius * (1.0 - math.sin(half))


def v_profile(angle: float, tip_radius: float, height: float, tol: float) -> np.ndarray:
    """Counter-clockwise polygon of a V of included ``angle`` (degrees) pointing to -u, its flanks
    tangent to a nose circle of ``tip_radius`` whose lowest point is the origin, cut off at u =
    ``height``. The nose arc is chords within ``tol`` with vertices on the circle (one at the
    origin: the control point is exact); the flanks are exact. The sharp V's apex lies
    tip_radius (1 / sin(angle / 2) - 1) behind the origin, so at u >= the nose the profile is
    2 (u + that) tan(angle / 2) wide."""
    half = math.radians(angle) / 2.0
    s, c, t = math.sin(half), math.cos(half), math.tan(half)
    h, rho = height, tip_radius
    if rho <= 0:
        w = h * t
        return np.array([[0.0, 0.0], [h, -w], [h, w]])
    wh = h * t + rho * (1.0 - s) / c  # half-width at the height
    span = math.pi / 2 - half  # nose arc: polar angle a from the origin's -u direction, |a| <= span
    k = max(1, math.ceil(span / segment_angle(rho, tol)))
    a = np.linspace(span, -span, 2 * k + 1)  # upper tangent point, down through the origin, lower one
    arc = np.column_stack([rho - rho * np.cos(a), rho * np.sin(a)])
    arc[k] = (0.0, 0.0)
    return np.vstack([arc, [[h, -wh], [h, wh]]])


def lathe_profile(tool: ToolSpec, tol: float) -> np.ndarray:
    """Counter-clockwise simple polygon (k, 2) of a lathe tool's cutting profile, with positive
    area (a CutsimError at the tool's [[tool]] table otherwise)."""
    check_tool(tool)
    from . import axial, inserts

    if tool.kind == "profile":
        poly = np.array(tool.points, dtype=float)
    elif tool.kind == "turning" and tool.insert:
        poly = inserts.orient(inserts.insert_profile(tool, tol), tool)
    elif tool.kind == "grooving":
        poly = inserts.orient(inserts.groove_profile(tool, tol), tool)
    elif tool.kind == "thread" and tool.form == "full":
        poly = inserts.orient(inserts.full_thread_profile(tool, tol), tool)
    elif tool.kind in ("thread", "turning"):
        poly = v_profile(tool.angle, tool.tip_radius, tool.height, tol)
        if tool.side != "outside":
            poly = inserts.orient(poly, tool)
    elif tool.kind == "drill":
        poly = drill_section(tool)
    elif tool.is_axial:
        poly = axial.section(tool)
    else:
        raise tool_error(tool, f"a {tool.kind} is not a lathe tool")
    poly = counter_clockwise(poly)
    # (a V within the ranges may be wider than the points of a profile tool may reach)
    why = polygon_problem(poly, COORD_MAX if tool.kind == "profile" else None)
    if why:
        raise tool_error(tool, f"the tool's profile is unusable: {why}")
    return poly


def drill_section(tool: ToolSpec) -> np.ndarray:
    """A drill on a lathe, moved with the spindle turning: its whole axial section (both sides of
    its axis, tip at the origin), whose revolved sweep is the hole it drills on the spindle axis
    and, off the axis, the ring a drill sweeps on a turning part (the revolve keeps r >= 0)."""
    r, hp, top = tool.diameter / 2.0, point_height(tool), tool.length
    if hp <= 0:
        return np.array([[-r, 0.0], [r, 0.0], [r, top], [-r, top]])
    return np.array([[0.0, 0.0], [r, hp], [r, top], [-r, top], [-r, hp]])


def convex_pieces(poly: np.ndarray) -> list[np.ndarray]:
    """The polygon itself if convex, else the triangles of a triangulation (each convex); all
    counter-clockwise, whatever the orientation of ``poly``."""
    poly = counter_clockwise(poly)
    d = np.diff(np.vstack([poly, poly[:2]]), axis=0)
    cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    if np.all(cross >= -1e-12):
        return [poly]
    tris = m3d.triangulate([poly])
    return [counter_clockwise(poly[list(t)]) for t in np.asarray(tris)]


def lathe_body(tool: ToolSpec, tol: float) -> list[np.ndarray]:
    """3D convex pieces (vertex arrays) of a lathe tool: its profile in the XZ plane, ``thickness``
    thick along Y (used when the spindle stands still)."""
    if tool.is_axial:  # a solid of revolution on the spindle axis: its frustums
        from . import axial

        check_tool(tool)
        return axial.body(tool, tol)
    out = []
    t = tool.thickness / 2.0
    prof = lathe_profile(tool, tol)
    for piece in convex_pieces(prof):
        out.append(np.vstack([np.column_stack([piece[:, 0], np.full(len(piece), y), piece[:, 1]]) for y in (-t, t)]))
    vol = sum(m3d.Manifold.hull_points(p).volume() for p in out)
    if not vol >= 0.5 * signed_area(prof) * tool.thickness:
        raise tool_error(tool, f"the tool's plate (profile x thickness {tool.thickness:g} mm) encloses (almost) no volume "
                               f"({vol:.3g} mm^3)")
    return out


# -- mills ---------------------------------------------------------------------------------------
def mill_body(tool: ToolSpec, tol: float, height: float | None = None) -> list[np.ndarray]:
    """Convex vertex cloud of a milling cutter's fluted part, tip centre at the origin, axis +Z
    (flat, bull-nose: corner radius, ball: corner radius = radius). With ``height`` below the flute
    length the body is cut off at that height (a plane section of the true tool): the part of the
    tool above the stock top never meets material and only costs triangles. The whole body is
    checked once per tool and tolerance (``checked_mill``): positive volume, in range."""
    checked_mill(tool, tol)
    return [_mill_cloud(tool, tol, height)]


@functools.lru_cache(maxsize=256)
def checked_mill(tool: ToolSpec, tol: float) -> float:
    """Volume of the whole fluted body's hull; a CutsimError at the tool's table when a size is not
    finite or too large, or the body is (nearly) empty. Cached: hull sweeps ask for every pose.
    (Not the lower ends of the ranges: the collision checks sweep the tool shrunk by a few
    tolerances, which may take a tool at the smallest size below it.)"""
    if tool.kind not in MILL_KINDS and tool.kind != "drill":
        raise tool_error(tool, f"a {tool.kind} tool is not a mill")
    if tool.kind == "drill":
        check_tool(tool)
    for key in ("diameter", "length", "corner_radius"):
        v = getattr(tool, key)
        if not (math.isfinite(v) and 0 <= v <= SIZE_MAX):
            raise tool_error(tool, f"{key} must be between {SIZE_MIN:g} and {SIZE_MAX:g} mm (got {v!r})")
    hull = m3d.Manifold.hull_points(_mill_cloud(tool, tol, None))
    vol, area = hull.volume(), hull.surface_area()
    if not (vol > 0 and area > 0 and 3.0 * vol / area >= MIN_WIDTH):
        raise tool_error(tool, f"the tool's body encloses (almost) no volume ({vol:.3g} mm^3)")
    return vol


def point_height(tool: ToolSpec) -> float:
    """A drill's point: how far above the tip the cone of the included ``point_angle`` reaches the
    full diameter, r / tan(point_angle / 2) (0 for a flat 180 degree end)."""
    half = math.radians(tool.point_angle) / 2.0
    return 0.0 if tool.point_angle >= POINT_ANGLE_MAX else (tool.diameter / 2.0) / math.tan(half)


def full_height(tool: ToolSpec) -> float:
    """Height above the tip from which the tool's section is its full circle: the corner radius of
    a mill, the point of a drill."""
    if tool.kind == "drill":
        return point_height(tool)
    return min(tool.corner_radius, tool.diameter / 2.0)


def _drill_cloud(tool: ToolSpec, n: int, ring: np.ndarray, top: float) -> np.ndarray:
    """A drill: the tip (the control point) at the origin, the cone of the point up to its full
    diameter, the cylinder above it up to ``top``; the rings as the mills' (perimeter-true)."""
    r = tool.diameter / 2.0
    hp = point_height(tool)
    pts = []
    if hp > 0:
        pts.append(np.array([[0.0, 0.0, 0.0]]))
    for z in (min(hp, top), top) if top > hp else (top,):
        rad = r if hp <= 0 else r * min(1.0, z / hp)
        if rad > 1e-12:
            pts.append(np.column_stack([ring * rad, np.full(n, z)]))
    if len(pts) == 1 and len(pts[0]) == 1:  # cut off at the very tip: a point
        return pts[0]
    return np.vstack(pts)


def _mill_cloud(tool: ToolSpec, tol: float, height: float | None) -> np.ndarray:
    """The body's vertex cloud cut off at ``height`` (None: the whole flute length). Hull sweeps ask
    for one body per pose: the whole body is built once per tool and tolerance (``_full_cloud``)
    and a cut one from its layers (``_mill_layers``), with the same vertices as built one by one."""
    if tool.kind == "drill":
        return _drill_body(tool, tol, height)
    top = tool.length if height is None else min(tool.length, max(0.0, height))
    if top == tool.length:
        return _full_cloud(tool, tol)
    return _layers_cloud(_mill_layers(tool, tol), tool, top)


def _drill_body(tool: ToolSpec, tol: float, height: float | None) -> np.ndarray:
    r = tool.diameter / 2.0
    top = tool.length if height is None else min(tool.length, max(0.0, height))
    n = max(8, math.ceil(2 * math.pi / segment_angle(r, tol)))
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    ring = np.column_stack([np.cos(ang), np.sin(ang)]) * (math.pi / (n * math.sin(math.pi / n)))
    return _drill_cloud(tool, n, ring, top)


@functools.lru_cache(maxsize=256)
def _full_cloud(tool: ToolSpec, tol: float) -> np.ndarray:
    cloud = _layers_cloud(_mill_layers(tool, tol), tool, tool.length)
    cloud.flags.writeable = False  # shared by every pose: callers add the pose (a new array)
    return cloud


@functools.lru_cache(maxsize=256)
def _mill_layers(tool: ToolSpec, tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ring (n, 2) of unit radius and the corner's layers (radius, z) of a mill, from the tip up
    (a flat end mill: the one layer at the tip)."""
    r = tool.diameter / 2.0
    rc = min(tool.corner_radius, r)
    n = max(8, math.ceil(2 * math.pi / segment_angle(r, tol)))
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    # Vertices a little outside the circle so the polygon has the circle's perimeter, hence its
    # mean width: the walls a sweep cuts deviate both ways within the tolerance, unbiased in volume.
    ring = np.column_stack([np.cos(ang), np.sin(ang)]) * (math.pi / (n * math.sin(math.pi / n)))
    rad, zs = [], []
    if rc > 0:
        k = max(1, math.ceil((math.pi / 2) / segment_angle(rc, tol)))
        # the corner arc's inner vertices stand out so each chord's triangle has the sector's
        # area (as the ring's vertices do around the axis): hull sweeps are unbiased in volume
        delta = (math.pi / 2) / k
        f = math.sqrt(delta / math.sin(delta))
        for i, a in enumerate(np.linspace(0, math.pi / 2, k + 1)):
            s = f if 0 < i < k else 1.0
            zs.append(rc - rc * s * math.cos(a))
            rad.append((r - rc) + rc * s * math.sin(a))
    else:
        zs.append(0.0)
        rad.append(r)
    return ring, np.array(rad), np.array(zs)


def _layers_cloud(layers: tuple, tool: ToolSpec, top: float) -> np.ndarray:
    """The mill's cloud up to ``top``: the corner's layers below it, then the section at ``top``."""
    ring, rad, zs = layers
    r = tool.diameter / 2.0
    rc = min(tool.corner_radius, r)
    if rc > 0:
        below = np.flatnonzero(zs >= top)
        m = int(below[0]) if len(below) else len(zs)  # the layers up to the first at or above the top
        rad, zs = rad[:m], zs[:m]
    rads = list(rad)
    heights = list(zs)
    if top < rc:  # the cut falls on the corner: its section circle
        rads.append((r - rc) + math.sqrt(max(0.0, rc * rc - (rc - top) ** 2)))
        heights.append(top)
    elif top > 0.0 or rc > 0:
        rads.append(r)
        heights.append(top)
    n = len(ring)
    out = []
    for rd, z in zip(rads, heights):
        if rd > 1e-12:
            layer = np.empty((n, 3))
            layer[:, :2] = ring * rd
            layer[:, 2] = z
            out.append(layer)
        else:
            out.append(np.array([[0.0, 0.0, z]]))
    return np.vstack(out)


# -- swept solids --------------------------------------------------------------------------------
def positive(solid: m3d.Manifold, what: str) -> m3d.Manifold:
    """``solid`` after checking it is a valid manifold that is not inside out (a warp that flipped
    the orientation gives a negative volume, which the batch boolean would silently misuse). Such a
    solid is a bug in cutsim, not in the input: a RuntimeError (exit status 3)."""
    if solid.status() != m3d.Error.NoError:
        raise RuntimeError(f"internal: the swept solid of {what} is not a valid manifold ({solid.status().name})")
    if solid.volume() < 0:
        raise RuntimeError(f"internal: the swept solid of {what} is inside out (volume {solid.volume():.6g} mm^3)")
    return solid
