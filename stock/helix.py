"""The exact sweep of a vertical-axis milling tool along a circle or helix (G17 arcs).

A rotationally symmetric tool (axis +Z: flat, ball or bull-nose end mill; radius r, corner radius
rc, flute length L, control point = tip centre) whose tip moves on a helix about (cx, cy) with
radius R is invariant under the screw motion of the helix. Measure the travel by u >= 0 (radians
along the arc, polar angle psi = psi0 + s u, s = +-1) and the tip height by z(u) = z0 + k u. In
the unrolled frame (u, rho, v = z - z(u)) the sweep, away from the two ends of the move, is one
profile in (rho, v) extruded along u:

- the tool at travel u + delta covers the radius rho iff |delta| <= a(rho), the half angle of its
  footprint: a(rho) = acos((rho^2 + R^2 - r^2) / (2 rho R)), rho in [R - r, R + r];
- there it covers v in [k delta + b(d), k delta + L], b(d) the height of the tool's lower surface
  above the tip at distance d(rho, delta) from its axis (0 for a flat end mill);
- these intervals vary continuously with delta, so their union is one interval:
  lower(rho) = min over delta of (k delta + b(d)), upper(rho) = |k| a(rho) + L.
  For a flat end mill lower = -|k| a(rho); at constant Z the profile is the tool's own section.

The profile is only valid where every delta in [-a, a] lies on the move, i.e. for
u in [a_max, U - a_max] (a_max = asin(r / R), the largest a). Those two ends are covered by the
hulls of the tool's poses on chords over the first and last 2 a_max of travel: any point the tool
covers at travel u* has its angle within a_max of u*, so it is either in the profile sweep or in
one of the end hulls.

The middle is extruded (``n_divisions``) and ``warp_batch``ed onto the helix, like the lathe's
screw sweep. Stations are spaced by the chord angle at R + r and the radii scaled by
sqrt(D / sin D) (D the station angle), so each annular sector between two stations has exactly
the true area: the walls deviate both ways within the tolerance and volumes are unbiased.

Turns: when the move spans more than one turn and the profile is taller than the pitch (a long
tool on a steep cut), the turns overlap and one warped solid would intersect itself. Instead the
union of all turns is built directly over one turn of travel: at each angle it reaches from the
bottom of the lowest turn to the top of the highest one (the turn intervals overlap, so their union
is one interval), in two pieces narrower than a turn (the number of turns drops by one where the
last turn ends). Turns whose material below the stock top ``z_top`` lies inside another turn are
left out, and a top that is above ``z_top`` everywhere is flat (nothing above the stock top is
stock). When the profile is shorter than the pitch, the turns are disjoint and one solid over the
whole travel is valid; in between (taller than the pitch in the middle, shorter at the walls: a
ball deeper than its flutes) the travel is cut into chunks narrower than a turn. Pieces overlap
their neighbours by one station (see OVERLAP).

Not applicable (None, the caller sweeps hulls): no arc, not a mill, a footprint reaching over
the arc's axis (R - r <= tol), flutes ending on the corner, or an arc too short for a middle part.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import manifold3d as m3d
import numpy as np

from cutsim.kinematics.paths import ArcGeom, ArcRun, SpatialPath, segment_angle

from .sweeps import EDGE_STEPS, MAX_CHUNK_DEGREES
from .tools import MILL_KINDS, positive

DELTA_SAMPLES = 257  # grid of polar offsets for the numeric lower profile (then refined)


# -- the unrolled profile ------------------------------------------------------------------------
def footprint(rho: np.ndarray, R: float, r: float) -> np.ndarray:
    """Half angle a(rho) of the polar offsets a tool circle of radius ``r`` centred at radius ``R``
    covers at radius ``rho`` (0 outside [R - r, R + r]); needs R > r."""
    rho = np.asarray(rho, dtype=float)
    c = (rho * rho + R * R - r * r) / (2.0 * rho * R)
    return np.arccos(np.clip(c, -1.0, 1.0))


def tip_lift(d: np.ndarray, r: float, rc: float) -> np.ndarray:
    """Height of the tool's lower surface above its tip at distance ``d`` from the axis."""
    d = np.asarray(d, dtype=float)
    if rc <= 0:
        return np.zeros_like(d)
    e = np.clip(d - (r - rc), 0.0, rc)
    return rc - np.sqrt(np.maximum(rc * rc - e * e, 0.0))


def lower_profile(rho: np.ndarray, R: float, r: float, rc: float, k: float) -> np.ndarray:
    """lower(rho) = min over |delta| <= a(rho) of (k delta + b(d(rho, delta))): the bottom of the
    sweep below the tip's own height."""
    rho = np.atleast_1d(np.asarray(rho, dtype=float))
    a = footprint(rho, R, r)
    if rc <= 0:
        return -abs(k) * a
    if k == 0:
        return tip_lift(np.abs(rho - R), r, rc)

    # b is even in delta, so the minimum lies on the side where k delta < 0: t = |delta| in [0, a]
    def g(t):
        d = np.sqrt(np.maximum(rho[:, None] ** 2 + R * R - 2 * rho[:, None] * R * np.cos(t), 0.0))
        return -abs(k) * t + tip_lift(d, r, rc)

    frac = np.linspace(0.0, 1.0, DELTA_SAMPLES)
    vals = g(a[:, None] * frac[None, :])
    i = np.argmin(vals, axis=1)
    h = a / (DELTA_SAMPLES - 1)
    lo = np.maximum(a * frac[i] - h, 0.0)
    hi = np.minimum(a * frac[i] + h, a)
    best = vals[np.arange(len(rho)), i]
    phi = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(40):  # golden-section refinement inside the bracket of the grid minimum
        m1, m2 = hi - phi * (hi - lo), lo + phi * (hi - lo)
        g1, g2 = g(m1[:, None])[:, 0], g(m2[:, None])[:, 0]
        left = g1 < g2
        hi = np.where(left, m2, hi)
        lo = np.where(left, lo, m1)
    mid = (lo + hi) / 2
    return np.minimum(best, g(mid[:, None])[:, 0])


def upper_profile(rho: np.ndarray, R: float, r: float, k: float, length: float) -> np.ndarray:
    """upper(rho) = max over |delta| <= a(rho) of (k delta) + L: the top of the flutes."""
    return abs(k) * footprint(rho, R, r) + length


def sample_curve(f, nodes: list[float], tol: float, min_step: float = 1e-7) -> np.ndarray:
    """Abscissae of a polyline following v = f(rho) within ``tol`` (distance from the curve's midpoint
    to each chord), refined by bisection from the sorted ``nodes``."""
    xs = np.array(sorted(set(nodes)), dtype=float)
    while True:
        x0, x1 = xs[:-1], xs[1:]
        mid = (x0 + x1) / 2
        y0, y1, ym = f(x0), f(x1), f(mid)
        dx, dy = x1 - x0, y1 - y0
        dist = np.abs(ym - (y0 + y1) / 2) * dx / np.hypot(dx, dy)
        bad = (dist > tol) & (dx > 2 * min_step)
        if not np.any(bad):
            return xs
        xs = np.sort(np.concatenate([xs, mid[bad]]))


def unbiased(xs: np.ndarray, f) -> np.ndarray:
    """Heights at ``xs`` for the polyline of v = f(rho) whose integral is the curve's (Simpson on each
    segment): each vertex moves by the area its two segments miss over their half widths. The
    region above or below the polyline then has the curve's area, its edges deviate both ways."""
    y = f(xs)
    dx = np.diff(xs)
    e = (2.0 / 3.0) * (f((xs[:-1] + xs[1:]) / 2) - (y[:-1] + y[1:]) / 2) * dx  # area missed per segment
    num = np.concatenate([[0.0], e]) + np.concatenate([e, [0.0]])
    den = np.concatenate([[0.0], dx]) + np.concatenate([dx, [0.0]])
    return y + num / den


def subdivide_open(pts: np.ndarray, max_len: float) -> np.ndarray:
    """The polyline with extra collinear vertices so no edge is longer than ``max_len`` (the
    warped quads of a long edge on a helicoid are twisted; short edges keep them nearly flat)."""
    out = [pts[:1]]
    for p, q in zip(pts[:-1], pts[1:]):
        n = max(1, math.ceil(float(np.hypot(*(q - p))) / max_len))
        t = (np.arange(1, n + 1) / n)[:, None]
        out.append(p + t * (q - p))
    return np.vstack(out)


@dataclass(frozen=True)
class Profile:
    """The sampled profile: ``rho`` nodes, ``lower`` and ``upper`` at them (v relative to the tip)."""
    rho: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    length: float  # flute length: the minimum of ``upper`` (at the walls)

    def heights(self) -> tuple[float, float]:
        """The smallest and the largest height of the profile over rho."""
        h = self.upper - self.lower
        return float(h.min()), float(h.max())


def build_profile(R: float, r: float, rc: float, k: float, length: float, tol: float) -> Profile:
    """The profile of a tool (radius r, corner radius rc, flute length) on a helix of radius R
    rising k per radian: both curves sampled within ``tol`` on common nodes (the corner's ends
    are nodes), with unbiased heights."""
    lo, hi = R - r, R + r
    nodes = [lo, hi, R] + [x for x in (R - (r - rc), R + (r - rc)) if lo < x < hi]
    nodes += list(np.linspace(lo, hi, 9))
    low = sample_curve(lambda x: lower_profile(x, R, r, rc, k), nodes, tol)
    rho = low
    if k != 0:
        up = sample_curve(lambda x: upper_profile(x, R, r, k, length), list(low), tol)
        rho = up
    return Profile(rho, unbiased(rho, lambda x: lower_profile(x, R, r, rc, k)),
                   unbiased(rho, lambda x: upper_profile(x, R, r, k, length)), length)


def profile_polygon(prof: Profile, bottom: float, top: float, flat_top: bool, max_len: float) -> np.ndarray:
    """Closed polygon (rho, v): the lower curve shifted up by ``bottom``, the outer wall, the top
    (the upper curve shifted by ``top``, or flat at L + ``top`` when ``flat_top``), the inner wall.
    Sloped edges are cut to at most ``max_len``."""
    low = subdivide_open(np.column_stack([prof.rho, prof.lower + bottom]), max_len)
    if flat_top:
        up = np.array([[prof.rho[-1], prof.length + top], [prof.rho[0], prof.length + top]])
    else:
        up = subdivide_open(np.column_stack([prof.rho, prof.upper + top])[::-1], max_len)
    return np.vstack([low, up])


# -- the move ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Helix:
    """The move by its travel u in [0, U] (radians): psi = psi0 + s u, z = z0 + k u."""
    cx: float
    cy: float
    R: float
    psi0: float
    s: int
    U: float
    z0: float
    k: float

    @classmethod
    def of(cls, arc: ArcGeom) -> Helix:
        U = abs(arc.sweep)
        return cls(arc.cx, arc.cy, arc.radius, arc.psi0, 1 if arc.sweep > 0 else -1, U, arc.z0,
                   (arc.z1 - arc.z0) / U)

    def z(self, u):
        return self.z0 + self.k * np.asarray(u, dtype=float)

    def points(self, u: np.ndarray) -> np.ndarray:
        """Tip positions (k, 3) at the travels ``u``."""
        psi = self.psi0 + self.s * u
        return np.column_stack([self.cx + self.R * np.cos(psi), self.cy + self.R * np.sin(psi), self.z(u)])


@dataclass(frozen=True)
class Piece:
    """Stations j0..j1 of the middle, each carrying the turns n in [n_lo, n_hi] (travel u + 2 pi n)."""
    j0: int
    j1: int
    n_lo: int
    n_hi: int


# Neighbouring pieces overlap by one station: the same surfaces, exactly coincident (same vertices,
# same orientation), unite cleanly, while two end caps meeting face to face leave zero-volume
# shells behind in the union.
OVERLAP = 1


def stations(U: float, a_max: float, M: int) -> int:
    """Number J of station steps (2 pi / M each) of the middle, which starts at travel a_max and ends
    at most a_max before U; more than a turn ends at least 3 steps past a whole number of turns
    (so the merged pieces below overlap their neighbours and stay narrower than a turn)."""
    J = math.floor((U - 2 * a_max) / (2 * math.pi / M) + 1e-9)
    if J >= M and J % M < 2 + OVERLAP:
        J -= J % M + 1
    return J


def merged_pieces(J: int, M: int, k: float, H_ok: bool, z_at, reach_top) -> list[Piece] | None:
    """Pieces covering the first turn of the stations 0..J (M per turn, J >= M), each the union of
    the turns over it: turns n = 0..nmax exist at station j while j + n M <= J, so the count drops by
    one after station jj = J mod M. ``z_at(j)`` is the tip height at station j, ``reach_top(z)``
    whether a turn whose tip is at z reaches above the stock top. Turns whose part below the top is
    inside another one's are left out; None when the kept turns must be merged but the profile is
    lower than the pitch somewhere (the turn intervals would not overlap)."""
    n0, jj = divmod(J, M)
    raw = [(0, jj, n0), (jj - OVERLAP, M + OVERLAP, n0 - 1)]
    out = []
    for j0, j1, nmax in raw:
        lo, hi = 0, nmax
        if k > 0:  # the first turn is the lowest: keep turns up to the first one reaching the top
            hi = next((n for n in range(nmax + 1) if reach_top(z_at(j0) + 2 * math.pi * k * n)), nmax)
        elif k < 0:  # the last turn is the lowest: keep turns from the last one reaching the top
            lo = next((n for n in range(nmax, -1, -1) if reach_top(z_at(j1) + 2 * math.pi * k * n)), 0)
        else:
            hi = 0
        if hi > lo and not H_ok:
            return None
        out.append(Piece(j0, j1, lo, hi))
    return out


def single_range(J: int, k: float, z_at, above) -> tuple[int, int] | None:
    """Stations of the middle, as one solid over all its turns (turns disjoint), without the
    stretch whose whole profile is above the stock top (``above(z)`` for a tip at z)."""
    j0, j1 = 0, J
    if k > 0:
        j1 = next((j for j in range(J + 1) if above(z_at(j))), J)
    elif k < 0:
        j0 = next((j for j in range(J, -1, -1) if above(z_at(j))), 0)
    return (j0, j1) if j1 > j0 else None


def chunks(j0: int, j1: int, M: int) -> list[Piece]:
    """Stations j0..j1 in pieces narrower than a turn, each overlapping the one before."""
    w = max(1, math.floor(M * MAX_CHUNK_DEGREES / 360.0))
    return [Piece(max(j0, j - OVERLAP), min(j + w, j1), 0, 0) for j in range(j0, j1, w)]


def plan(J: int, M: int, k: float, prof: Profile, z_at, top: float) -> list[Piece]:
    """The pieces of the middle: below a turn one piece; over more turns the merged first turn when
    the profile is taller than the pitch, one solid when it is shorter (the turns are disjoint),
    else chunks narrower than a turn."""
    if J < M:  # less than a turn: no angle is swept twice
        return [Piece(0, J, 0, 0)]
    pitch = 2 * math.pi * abs(k)
    h_min, h_max = prof.heights()
    pieces = merged_pieces(J, M, k, h_min > pitch * (1 + 1e-6) + 1e-9, z_at, lambda z: z + prof.length >= top)
    if pieces is not None:
        return pieces
    rng = single_range(J, k, z_at, lambda z: z + float(prof.lower.min()) > top)
    if rng is None:
        return []
    if h_max < pitch * (1 - 1e-6) - 1e-9:
        return [Piece(*rng, 0, 0)]
    return chunks(*rng, M)


def warp_piece(h: Helix, poly: np.ndarray, u_a: float, M: int, scale: float, pc: Piece) -> m3d.Manifold:
    """The polygon (rho, v) extruded over the stations j0..j1 (travel u_a + j 2 pi / M) and warped
    onto the helix: x = cx + scale rho cos psi, y = cy + scale rho sin psi, z = z(u) + v. The angle
    is taken from j mod M so stations a whole turn apart lie in exactly the same vertical plane."""
    flip = h.s > 0  # psi growing with the extrusion axis turns the solid inside out: mirror v
    cs = m3d.CrossSection([(poly * [1.0, -1.0])[::-1] if flip else poly], m3d.FillRule.Positive)
    n = pc.j1 - pc.j0
    solid = m3d.Manifold.extrude(cs, 1.0, n_divisions=n - 1)
    step = 2 * math.pi / M

    def warp(p):
        j = pc.j0 + np.rint(np.clip(p[:, 2], 0.0, 1.0) * n)
        psi = h.psi0 + h.s * (u_a + np.mod(j, M) * step)
        rho = p[:, 0] * scale
        v = -p[:, 1] if flip else p[:, 1]
        return np.column_stack([h.cx + rho * np.cos(psi), h.cy + rho * np.sin(psi), h.z(u_a + j * step) + v])

    return positive(solid.warp_batch(warp), "a mill on a circle or helix")


def end_hulls(tool, h: Helix, u0: float, u1: float, step: float, tol: float, cap: float) -> list[m3d.Manifold]:
    """The mill's hull sweep (``mill.hull_sweep``) along chords of the travel u0..u1, below ``cap``."""
    from .mill import hull_sweep

    n = max(1, math.ceil((u1 - u0) / step))
    return hull_sweep(h.points(np.linspace(u0, u1, n + 1)), tool, tol, cap)


def applicable(path: SpatialPath, tol: float) -> bool:
    """A milling tool (flutes above its corner) on an exact circle/helix that does not reach over
    the axis of the arc."""
    t, arc = path.tool, path.arc
    if arc is None or t.kind not in MILL_KINDS or abs(arc.sweep) < 1e-9:
        return False
    if arc.radius - t.diameter / 2.0 <= tol:  # the footprint would contain the axis: hulls
        return False
    if t.length <= min(t.corner_radius, t.diameter / 2.0):  # flutes end on the corner: narrower top
        return False
    # the chords must be those of this arc (a caller that moved the points must drop the arc)
    ends = arc.pose(np.array([0.0, 1.0]))
    return bool(np.allclose(ends, path.points[[0, -1]], rtol=0.0, atol=1e-6))


def merge_arcs(paths: list[SpatialPath]) -> list[SpatialPath]:
    """The paths with each run of consecutive arcs of one tool on one helix joined (``ArcRun``)."""
    runs: list[ArcRun] = []
    for p in paths:
        if not (runs and runs[-1].extend(p)):
            runs.append(ArcRun(len(runs), p))
    return [r.path() for r in runs]


# -- a helix finer than the tolerance: the revolved tool ----------------------------------------
def fine_pitch(arc: ArcGeom, tol: float) -> float | None:
    """The helix's rise per turn when it runs at least one whole turn and rises (or falls) at most
    ``tol`` per turn, else None: such a helix is swept as the revolved tool (``revolved_sweep``)."""
    U = abs(arc.sweep)
    if U < 2 * math.pi * (1 - 1e-12):
        return None
    pitch = abs(arc.z1 - arc.z0) * 2 * math.pi / U
    return pitch if pitch <= tol * (1 + 1e-9) else None  # a pitch written as the tolerance, up to rounding


def lower_section(tool, tol: float) -> np.ndarray:
    """The tool's lower surface as a polyline (d, b) from its axis (d = 0) to its radius: b the
    height above the tip at distance d (a drill's cone; a mill's flat end and corner arc, whose
    inner vertices stand out so each chord's segment has the arc's area). Every point of it lies
    within ``tol`` of the true surface."""
    from .tools import point_height

    r = tool.diameter / 2.0
    if tool.kind == "drill":
        return np.array([[0.0, 0.0], [r, point_height(tool)]])
    rc = min(max(tool.corner_radius, 0.0), r)
    if rc <= 0:
        return np.array([[0.0, 0.0], [r, 0.0]])
    k = max(1, math.ceil((math.pi / 2) / segment_angle(rc, tol)))
    a = np.linspace(0.0, math.pi / 2, k + 1)
    f = np.where((a > 0) & (a < math.pi / 2), math.sqrt((a[1] - a[0]) / math.sin(a[1] - a[0])), 1.0)
    arc = np.column_stack([(r - rc) + rc * f * np.sin(a), rc - rc * f * np.cos(a)])
    return arc if r - rc <= 0 else np.vstack([[0.0, 0.0], arc])


def revolved_region(tool, R: float, zlo: float, zhi: float, tol: float, cap: float) -> m3d.CrossSection:
    """The (rho, z) region the tool covers when its tip, at radius ``R`` from an axis, takes every
    height zlo..zhi and every angle about that axis: at rho it reaches from zlo + b(|rho - R|) (the
    tool's nearest point to its own axis at that radius is |rho - R| away) up to zhi + the flute
    length, cut off at ``cap`` (nothing above can meet the stock) and at the axis."""
    sec = lower_section(tool, tol)
    r = tool.diameter / 2.0
    left = np.column_stack([R - sec[::-1, 0], zlo + sec[::-1, 1]])
    right = np.column_stack([R + sec[1:, 0], zlo + sec[1:, 1]])
    top = zhi + tool.length
    poly = np.vstack([left, right, [[R + r, top], [R - r, top]]])
    region = m3d.CrossSection([poly], m3d.FillRule.Positive)
    lo = zlo - 1.0
    box = m3d.CrossSection.square((R + r + 1.0, min(top, cap) - lo)).translate((0.0, lo))
    return region ^ box


def revolved_sweep(path: SpatialPath, tol: float, z_top: float = math.inf) -> list[m3d.Manifold] | None:
    """The sweep of a tool whose tip runs at least one whole turn of a helix rising at most ``tol``
    per turn (``fine_pitch``), as ONE solid of revolution about the helix's axis instead of the
    turns (a CNC8x6 G09 helix of 20,000 circles a micrometre apart); None for other paths.

    Why it is exact within the tolerance: at every angle about the axis the tip passes at heights
    one pitch p apart, the first within p of the lowest height zlo and the last within p of the
    highest zhi (a whole turn at least). The revolved tool over the tip heights zlo + p/2 ..
    zhi - p/2 (``revolved_region``) therefore lies within p/2 of the true sweep (a pass is within
    p/2 of every height it needs) and the true sweep within p/2 of it (a pass covers no point
    below the lowest pose's lower surface nor above the highest pose's flutes): the floor and the
    top deviate both ways by at most p/2 and the volume is unbiased. The rest of the tolerance,
    (tol - p/2), is split between the section's corner chords and the revolution's segments,
    whose radii are scaled by sqrt(D / sin D) (D the segment angle) so each sector has the true
    area: every point of the solid lies within ``tol`` of the true swept solid."""
    fine = _fine_region(path, tol, z_top)
    if fine is None:
        return None
    region, e = fine
    if region.is_empty():
        return []
    n = revolve_segments(region, e)
    arc = path.arc
    step = 2 * math.pi / n
    region = region.scale((math.sqrt(step / math.sin(step)), 1.0))
    solid = m3d.Manifold.revolve(region, circular_segments=n).translate((arc.cx, arc.cy, 0.0))
    return [positive(solid, "a tool on a helix finer than the tolerance")]


def revolve_segments(region: m3d.CrossSection, tol: float) -> int:
    """Segments of a revolution of ``region`` whose chords at its largest radius deviate at most
    ``tol``."""
    from cutsim.kinematics.paths import circle_segments

    return circle_segments(max(region.bounds()[2], tol), tol)


def revolved_triangles(path: SpatialPath, tol: float, z_top: float = math.inf) -> int | None:
    """Triangles of ``revolved_sweep`` without building the solid (None: not such a path)."""
    fine = _fine_region(path, tol, z_top)
    if fine is None:
        return None
    region, e = fine
    return 0 if region.is_empty() else 2 * region.num_vert() * revolve_segments(region, e)


def _fine_region(path: SpatialPath, tol: float, z_top: float) -> tuple[m3d.CrossSection, float] | None:
    """The region ``revolved_sweep`` revolves and the tolerance its discretisation gets, or None
    when the path is no helix finer than ``tol``."""
    arc = path.arc
    pitch = fine_pitch(arc, tol) if arc is not None and not path.tool.is_lathe_tool else None
    if pitch is None:
        return None
    from .mill import cap_height

    e = (tol - pitch / 2.0) / 2.0
    zlo, zhi = min(arc.z0, arc.z1) + pitch / 2.0, max(arc.z0, arc.z1) - pitch / 2.0
    return revolved_region(path.tool, arc.radius, zlo, zhi, e, cap_height(z_top, tol)), e


def arc_sweep(path: SpatialPath, tol: float, z_top: float = math.inf) -> list[m3d.Manifold] | None:
    """Solids whose union is what the tool sweeps along ``path.arc`` within ``tol``, except parts
    above the stock top ``z_top`` (left out where that is cheaper); None when not applicable (no
    arc, not a mill, footprint over the arc's axis, arc too short for a middle part): the caller
    sweeps hulls."""
    from .mill import cap_height

    fine = revolved_sweep(path, tol, z_top)
    if fine is not None:
        return fine
    if not applicable(path, tol):
        return None
    t = path.tool
    r = t.diameter / 2.0
    h = Helix.of(path.arc)
    a_max = math.asin(r / h.R)
    M = max(8, math.ceil(2 * math.pi / segment_angle(h.R + r, tol)))
    step = 2 * math.pi / M
    J = stations(h.U, a_max, M)
    if J < 1:
        return None
    u_a, u_b = a_max, a_max + J * step
    prof = build_profile(h.R, r, min(max(t.corner_radius, 0.0), r), h.k, t.length, tol)
    top = cap_height(z_top, tol)  # nothing above this height can meet the stock

    def z_at(j):
        return float(h.z(u_a + j * step))

    max_len = EDGE_STEPS * math.sqrt(tol * (h.R + r))
    scale = math.sqrt(step / math.sin(step))  # sectors between stations get the true area
    out = []
    for pc in plan(J, M, h.k, prof, z_at, top):
        shifts = [2 * math.pi * h.k * n for n in (pc.n_lo, pc.n_hi)]
        bottom, up = min(shifts), max(shifts)
        zmin = min(z_at(pc.j0), z_at(pc.j1))
        if zmin + bottom + float(prof.lower.min()) > top:
            continue
        poly = profile_polygon(prof, bottom, up, zmin + up + prof.length >= top, max_len)
        out.append(warp_piece(h, poly, u_a, M, scale, pc))
    chord = segment_angle(h.R + r, tol)
    out += end_hulls(t, h, 0.0, u_a + a_max, chord, tol, top)
    out += end_hulls(t, h, u_b - a_max, h.U, chord, tol, top)
    return out
