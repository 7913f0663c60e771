"""Tool shapes over the whole tool space: removed volumes against analytic geometry.

Every expected number here comes from the tool's definition (docs/setup.md) and the program by
closed-form geometry, never from cutsim's sweep code; cutsim is run through its public API
(``cutsim.load_setup`` on a TOML written here, ``cutsim.simulate(name, setup, text=...)``).

The lathe V (thread and turning tools) in its own (u, v) plane, u radial from the control point,
v axial: a nose circle of radius rho centred at (rho, 0) (its lowest point is the control point),
flanks of half angle h = angle / 2 tangent to it, cut off at u = height. Its half width is

    v(u) = sqrt(rho^2 - (rho - u)^2)               for u <= ut = rho (1 - sin h)  (the nose)
    v(u) = u tan h + rho (1 - sin h) / cos h        for ut <= u <= height          (the flanks)

and the moments below are integrals of v in closed form.

Hypothesis runs a fixed number of derandomised examples per property (CI is deterministic).
"""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cutsim
from conftest import EXAMPLES
from cutsim import CutsimError
from cutsim.base.specs import ToolSpec

SIM = settings(max_examples=25, deadline=None, derandomize=True, database=None,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
FAST = settings(max_examples=60, deadline=None, derandomize=True, database=None)


# -- the analytic V ------------------------------------------------------------------------------
class V:
    """A thread/turning tool's profile as analytic functions (see the module docstring)."""

    def __init__(self, angle: float, rho: float, height: float):
        self.h = math.radians(angle) / 2.0
        self.s, self.c, self.t = math.sin(self.h), math.cos(self.h), math.tan(self.h)
        self.rho, self.height = rho, height
        self.ut = rho * (1.0 - self.s)
        self.b = rho * (1.0 - self.s) / self.c if rho > 0 else 0.0

    def v(self, u: float) -> float:
        if u <= self.ut:
            return math.sqrt(max(0.0, self.rho ** 2 - (self.rho - u) ** 2))
        return u * self.t + self.b

    def moments(self, U: float, r0: float) -> tuple[float, float]:
        """(int_0^U v du, int_0^U (r0 + u) v du): half the area and half the first moment about
        the axis of the profile up to u = U, the control point at radius r0."""
        rho = self.rho
        a = m = 0.0
        un = min(U, self.ut)
        if un > 0:  # nose: x = u - rho, v = sqrt(rho^2 - x^2)
            def f1(x):
                return 0.5 * (x * math.sqrt(max(0.0, rho * rho - x * x)) + rho * rho * math.asin(max(-1.0, min(1.0, x / rho))))

            def f2(x):
                return -max(0.0, rho * rho - x * x) ** 1.5 / 3.0

            x0, x1 = -rho, un - rho
            a += f1(x1) - f1(x0)
            m += (r0 + rho) * (f1(x1) - f1(x0)) + f2(x1) - f2(x0)
        if U > self.ut:  # flanks: v = t u + b
            u0, u1 = self.ut, U
            t, b = self.t, self.b
            a += t * (u1 ** 2 - u0 ** 2) / 2 + b * (u1 - u0)
            m += (r0 * b * (u1 - u0) + (r0 * t + b) * (u1 ** 2 - u0 ** 2) / 2 + t * (u1 ** 3 - u0 ** 3) / 3)
        return a, m

    def nose_length(self, U: float) -> float:
        """Length of the nose arc (both sides) within u <= U."""
        if self.rho <= 0:
            return 0.0
        un = min(U, self.ut)
        return 2.0 * self.rho * math.acos(max(-1.0, 1.0 - un / self.rho))


def test_v_moments_against_quadrature():
    """The closed forms above against numeric quadrature of v (the test's own arithmetic)."""
    from scipy.integrate import quad

    for angle, rho, U, r0 in ((60, 0.05, 0.41, 13.1), (55, 0.4, 2.0, 13.0), (1, 3.0, 2.0, 5.0), (179, 1.0, 0.8, 20.0),
                              (90, 2.0, 6.0, 1.0), (30, 0.0, 3.0, 7.0)):
        g = V(angle, rho, 10.0)
        pts = [g.ut] if 0 < g.ut < U else None
        qa = quad(g.v, 0, U, points=pts, epsabs=1e-13, epsrel=1e-12, limit=200)[0]
        qm = quad(lambda u: (r0 + u) * g.v(u), 0, U, points=pts, epsabs=1e-13, epsrel=1e-12, limit=200)[0]
        a, m = g.moments(U, r0)
        assert a == pytest.approx(qa, rel=1e-9, abs=1e-12) and m == pytest.approx(qm, rel=1e-9, abs=1e-12)


# -- running cutsim ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("toolprops")


def num(x: float, digits: int = 4) -> float:
    """``x`` rounded as it is written into the program or setup (the analytic side uses this)."""
    return float(f"{x:.{digits}f}")


def simulate(workdir, setup: str, program: str):
    path = workdir / "setup.toml"
    path.write_text(setup)
    return cutsim.simulate("prop.nc", cutsim.load_setup(str(path)), text=program)


def lathe_setup(radius: float, z0: float, tool: str, tol: float) -> str:
    return (f'[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n\n[stock]\nshape = "cylinder"\n'
            f'diameter = {2 * radius}\nz = [{z0}, 0.0]\n\n[[tool]]\nnumber = 1\n{tool}\n'
            f'[simulation]\ntolerance = {tol}\n')


def v_tool(kind: str, angle: float, rho: float, height: float) -> str:
    return f'kind = "{kind}"\nangle = {angle}\ntip_radius = {rho}\nheight = {height}\n'


# -- the shapes themselves, over the whole documented ranges (fast: no simulation) --------------
@FAST
@given(angle=st.floats(1.0, 179.0), rho_frac=st.one_of(st.just(0.0), st.floats(0.0, 1.0)),
       height=st.floats(0.001, 10_000.0), tol=st.floats(1e-4, 1.0), kind=st.sampled_from(["thread", "turning"]))
def test_v_profile_area_over_the_ranges(angle, rho_frac, height, tol, kind):
    """Every thread/turning tool within the documented ranges builds a counter-clockwise profile
    whose area is the analytic 2 int_0^height v du, less at most the nose arc's chord segments:
    vertices lie on the arc, so each chord cuts off a segment of area <= tol x its length, i.e.
    0 <= exact - built <= tol x nose length (plus float rounding)."""
    from cutsim.stock.tools import SIZE_MIN, lathe_profile, signed_area

    s = math.sin(math.radians(angle) / 2)
    rho = rho_frac * min(10_000.0, 0.999 * height / (1 - s))  # the nose must end below the height
    if 0 < rho < SIZE_MIN:
        rho = 0.0
    g = V(angle, rho, height)
    poly = lathe_profile(ToolSpec(1, kind, angle=angle, tip_radius=rho, height=height), tol)
    area = signed_area(poly)
    exact = 2 * g.moments(height, 0.0)[0]
    assert area > 0
    slack = 1e-9 * exact + 1e-12
    assert -slack <= exact - area <= tol * g.nose_length(height) + slack


@FAST
@given(d=st.floats(0.001, 10_000.0), length_frac=st.floats(0.0, 1.0), rc_frac=st.floats(0.0, 1.0),
       kind=st.sampled_from(["flat", "bull", "ball"]), rel_tol=st.floats(-4.0, 0.0))
def test_mill_body_volume_over_the_ranges(d, length_frac, rc_frac, kind, rel_tol):
    """Every mill within the documented ranges has a body (the hull of ``mill_body``) whose volume
    is the analytic solid of revolution within tol x its curved surface (its vertices stand off the
    circles so chords cut both ways, never by more than the tolerance). The tolerance (within its
    range 1e-4 .. 1 mm) is at least 1e-4 x the radius: a corner of radius r has about
    sqrt(r / tol) vertices around and along it, so a 10 m bull nose at 1e-4 mm would be 10^7
    vertices (a memory limit, not a shape question). Flutes up to 100 diameters (the range allows
    1000): manifold's hull merges points closer than a fraction of the cloud's size, which on a
    long thin cloud is more than a small tolerance (sweeps cut bodies off just above the stock)."""
    import manifold3d as m3d

    from cutsim.stock.tools import mill_body

    r = d / 2
    tol = min(1.0, max(1e-4, r * 10.0 ** rel_tol))
    length = 0.001 + length_frac * (min(10_000.0, 100 * d) - 0.001)
    rc = {"flat": 0.0, "ball": r, "bull": max(0.001, rc_frac * r)}[kind]
    tool = ToolSpec(1, "ballmill" if kind == "ball" else "endmill", diameter=d, length=length,
                    corner_radius=min(rc, r))
    vol = m3d.Manifold.hull_points(mill_body(tool, tol)[0]).volume()
    exact = body_volume(r, tool.corner_radius, length)
    curved = 2 * math.pi * r * length + math.pi * r * r
    assert vol > 0
    assert abs(vol - exact) <= tol * curved + 1e-9 * exact


# -- turning: Pappus ----------------------------------------------------------------------------
@SIM
@given(radius=st.floats(5.0, 40.0), depth_frac=st.floats(0.02, 0.95), length=st.floats(1.0, 30.0),
       angle=st.floats(1.0, 179.0), rho=st.one_of(st.just(0.0), st.floats(0.001, 3.0)),
       extra=st.floats(0.05, 12.0))
def test_turning_pass_volume(workdir, radius, depth_frac, length, angle, rho, extra):
    """A straight turning pass to diameter 2 r0 over z in [ze, 0] (the tool comes in radially at
    zs in the air above the bar and leaves radially at ze) removes, by Pappus, the region
    r0 <= r <= r0 + U (U = min(height, R - r0)), ze - v(r - r0) <= z <= 0:

        V = 2 pi [ -ze (rt^2 - r0^2) / 2 + int_0^U (r0 + u) v(u) du ],   rt = r0 + U

    plus, for a tool shorter than the cut (height < R - r0), the ring its top edge cuts on the way
    out at ze: pi (R^2 - rt^2) x (min(0, ze + v(height)) - (ze - v(height))).

    Bound: the revolved surfaces are chords of their circles, within tol radially, so they move
    the volume by at most tol x their area projected on the radial direction, 2 pi int r |dz| <=
    2 pi R x 2 (the region's z extent); the nose arc is chords within tol on the profile, at most
    tol x 2 pi R x its length. |V - exact| <= 2 pi R tol (2 z_extent + nose length)."""
    tol = 0.005
    depth = num(max(0.05, depth_frac * min(4.0, radius - 1.0)))
    s = math.sin(math.radians(angle) / 2)
    height = num(rho * (1 - s) + extra)
    rho = num(rho)
    if rho * (1 - s) >= height:
        rho = 0.0
    angle = num(angle)
    g = V(angle, rho, height)
    R = radius = num(radius)
    r0 = num(R - depth)
    U = min(height, R - r0)
    zs = num(g.v(U) + 1.0)
    ze = num(-length)
    z0 = -(length + g.v(U) + 2.0)
    prog = (f"N10 G95 S800 M03\nN20 G00 X{2 * (R + 1):.4f} Z{zs:.4f}\nN30 G01 X{2 * r0:.4f} F0.2\n"
            f"N40 Z{ze:.4f}\nN50 X{2 * (R + 1):.4f}\nN60 G00 Z{zs + 5:.4f}\nN70 M30\n")
    res = simulate(workdir, lathe_setup(R, z0, v_tool("turning", angle, rho, height), tol), prog)
    rt = r0 + U
    exact = 2 * math.pi * (-ze * (rt * rt - r0 * r0) / 2 + g.moments(U, r0)[1])
    if U < R - r0:
        vh = g.v(height)
        exact += math.pi * (R * R - rt * rt) * (min(0.0, ze + vh) - (ze - vh))
    z_extent = -ze + g.v(U)
    bound = 2 * math.pi * R * tol * (2 * z_extent + g.nose_length(U))
    assert abs(res.report["removed_volume"] - exact) <= bound, (res.report["removed_volume"], exact, bound)


# -- profile tools: a two-pronged grooving tool, plunged -----------------------------------------
@SIM
@given(radius=st.floats(5.0, 40.0), depth_frac=st.floats(0.02, 0.9), a=st.floats(0.1, 5.0), b=st.floats(0.1, 5.0),
       gap=st.floats(0.1, 5.0), prong=st.floats(0.1, 10.0), bar=st.floats(0.1, 5.0), reverse=st.booleans(),
       roll=st.integers(0, 7))
def test_profile_tool_plunge_volume(workdir, radius, depth_frac, a, b, gap, prong, bar, reverse, roll):
    """A profile tool shaped like a fork (two prongs of widths a and b, a gap between them, joined
    by a bar behind them; not convex, so its sweep goes through a triangulation), its points given
    in either direction from any vertex, plunged radially into a bar to radius r0 and withdrawn.
    Each prong cuts a ring from r0 to the bar's surface R; the bar behind the prongs cuts the gap
    from r0 + prong outwards:

        V = pi (R^2 - r0^2) (a + b) + pi (R^2 - min(R, r0 + prong)^2) gap

    Bound: the profile is exact (straight edges); the revolved walls are chords within tol
    radially: |V - exact| <= tol x 2 pi int r |dz| <= tol 2 pi R x 2 (a + gap + b)."""
    tol = 0.005
    a, b, gap, prong, bar = (num(x) for x in (a, b, gap, prong, bar))
    R = num(radius)
    r0 = num(R - max(0.05, depth_frac * (R - 0.5)))
    lo, g0, g1, hi = -a / 2, a / 2, a / 2 + gap, a / 2 + gap + b  # v of the prongs' sides
    pts = [(0, lo), (prong + bar, lo), (prong + bar, hi), (0, hi), (0, g1), (prong, g1), (prong, g0), (0, g0)]
    pts = pts[roll:] + pts[:roll]
    if reverse:
        pts = pts[::-1]
    tool = 'kind = "profile"\npoints = [' + ", ".join(f"[{u:.4f}, {v:.4f}]" for u, v in pts) + "]\n"
    zg = num(-(hi - lo) - 2.0)
    prog = (f"N10 G95 S800 M03\nN20 G00 X{2 * (R + 1):.4f} Z{zg:.4f}\nN30 G01 X{2 * r0:.4f} F0.1\n"
            f"N40 X{2 * (R + 1):.4f}\nN50 M30\n")
    res = simulate(workdir, lathe_setup(R, 2 * zg, tool, tol), prog)
    exact = math.pi * (R * R - r0 * r0) * (a + b) + math.pi * (R * R - min(R, r0 + prong) ** 2) * gap
    bound = tol * 2 * math.pi * R * 2 * (a + gap + b)
    assert abs(res.report["removed_volume"] - exact) <= bound, (res.report["removed_volume"], exact, bound)


# -- threads: screw motion -----------------------------------------------------------------------
def thread_bound(tol, R, Ls, lead, g: V, U):
    """Bound for a screw sweep through a slab of length Ls. The sweep's surfaces between stations
    are chords of the helices (z exact, within tol radially) and the bar's wall is chords of its
    circle: at most tol x their area projected on the radial direction, per turn 2 pi int r |dz|
    over the profile's outline <= 2 pi R x 4 v(U); the nose arc's chords add tol x 2 pi R x its
    length per turn. The profile edges are cut short so the warped quads stay nearly flat; we
    allow twice the sum for their residual twist."""
    return 2 * tol * 2 * math.pi * (Ls / lead) * R * (4 * g.v(U) + g.nose_length(U))


@SIM
@given(radius=st.floats(5.0, 40.0), angle=st.floats(1.0, 179.0), rho=st.one_of(st.just(0.0), st.floats(0.001, 1.0)),
       extra=st.floats(0.05, 5.0), depth_frac=st.floats(0.05, 1.0), gap=st.floats(1.1, 3.0),
       slab=st.floats(2.0, 8.0))
def test_thread_volume_screw_motion(workdir, radius, angle, rho, extra, depth_frac, gap, slab):
    """One G33 pass right through a bar (it starts and ends in the air beyond both faces) with
    turns that do not overlap (lead > the profile's width at the bar's surface). The map
    (u, v, phi) -> screw position has Jacobian r and is one-to-one, so the removed volume is

        V = (2 pi / lead) x Ls x iint_Q r dA = (2 pi / lead) Ls x 2 int_0^U (r0 + u) v(u) du

    with Q the profile inside the bar (u <= U = min(height, R - r0)): every point of Q crosses the
    whole slab of length Ls, i.e. Ls / lead turns. Tolerance: ``thread_bound``."""
    tol = 0.005
    s = math.sin(math.radians(angle) / 2)
    height = num(rho * (1 - s) + extra)
    rho = num(rho)
    if rho * (1 - s) >= height:
        rho = 0.0
    angle = num(angle)
    g = V(angle, rho, height)
    R = num(radius)
    # the deepest cut whose groove is at most 10 mm wide at the surface
    umax = min(3.0, R - 1.0, height)
    while g.v(umax) > 5.0:
        umax /= 1.5
    r0 = num(R - max(0.01, depth_frac * umax))
    U = min(height, R - r0)
    width = 2 * g.v(U)
    lead = num(max(0.2, width * gap), 3)
    assert lead > width
    Ls = num(slab, 2)
    clear = g.v(U) + 1.0
    zs, ze = num(clear), num(-Ls - clear)
    prog = (f"N10 G95 S800 M03\nN20 G00 X{2 * (R + 2):.4f} Z{zs:.4f}\nN30 X{2 * r0:.4f}\n"
            f"N40 G33 Z{ze:.4f} I0 F{lead:.3f}\nN50 G00 X{2 * (R + 2):.4f}\nN60 Z{zs:.4f}\nN70 M30\n")
    res = simulate(workdir, lathe_setup(R, -Ls, v_tool("thread", angle, rho, height), tol), prog)
    exact = 2 * math.pi / lead * Ls * 2 * g.moments(U, r0)[1]
    bound = thread_bound(tol, R, Ls, lead, g, U)
    assert abs(res.report["removed_volume"] - exact) <= bound, (res.report["removed_volume"], exact, bound)


# -- mills: a straight line at constant depth ----------------------------------------------------
def segment_area(rc: float, d: float) -> float:
    """Area of the part of a disc of radius rc within d of its lowest point (d <= 2 rc)."""
    return rc * rc * math.acos((rc - d) / rc) - (rc - d) * math.sqrt(max(0.0, 2 * rc * d - d * d))


def body_volume(r: float, rc: float, d: float) -> float:
    """Volume of a mill (radius r, corner radius rc) below height d above its tip: pi int rho(z)^2
    dz with rho = (r - rc) + sqrt(rc^2 - (rc - z)^2) on the corner, r above it."""
    a, D = r - rc, min(d, rc)
    vol = math.pi * a * a * D
    if rc > 0:
        vol += math.pi * (a * segment_area(rc, D) + rc * rc * D - (rc ** 3 - (rc - D) ** 3) / 3)
    return vol + math.pi * r * r * max(0.0, d - rc)


def silhouette_area(r: float, rc: float, d: float) -> float:
    """Area of the mill's outline seen along a horizontal line, below height d above its tip."""
    D = min(d, rc)
    area = 2 * (r - rc) * d + (segment_area(rc, D) if rc > 0 else 0.0)
    return area + 2 * rc * max(0.0, d - rc)


MILL_PLATE = """[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, {top}]

[stock]
shape = "box"
x = [{lo}, {hi}]
y = [{lo}, {hi}]
z = [{zlo}, 0.0]

[[tool]]
number = 1
{tool}
[simulation]
tolerance = {tol}
"""


@SIM
@given(kind=st.sampled_from(["flat", "ball", "bull"]), d=st.floats(0.5, 20.0), rc_frac=st.floats(0.05, 0.95),
       depth_frac=st.floats(0.05, 1.5), length=st.floats(0.0, 40.0), theta=st.floats(0.0, 2 * math.pi),
       pieces=st.integers(1, 6), extra=st.floats(1.0, 20.0))
def test_mill_line_volume(workdir, kind, d, rc_frac, depth_frac, length, theta, pieces, extra):
    """A mill plunges into a plate, runs a straight line of ``length`` at tip depth ``depth`` in
    ``pieces`` collinear moves, and leaves upwards. The tool below the plate's top is a convex body
    K, so the swept volume is vol(K) + length x (K's outline seen along the line) (Steiner for a
    segment); the plunge and the retract stay inside it (the tool is upward closed):

        flat:  stadium x depth = (2 r length + pi r^2) depth
        ball:  depth <= r: length x segment + spherical cap; deeper: length (pi r^2 / 2 + 2 r (depth -
               r)) + hemisphere + pi r^2 (depth - r)   (half-cylinder + hemispherical ends)
        bull:  the same with the torus corner (``silhouette_area``, ``body_volume``).

    Bound: flat faces are exact; the curved ones are chords within tol of the tool's circles
    (stadium ends inscribed; hulls, tubes with vertices standing off to keep sector areas), so
    |V - exact| <= tol x curved area <= tol (length (2 depth + 2 r) + 2 pi r depth + pi r^2)."""
    tol = 0.005
    d = num(d)
    r = d / 2
    rc = {"flat": 0.0, "ball": r, "bull": num(max(0.001, rc_frac * r))}[kind]
    depth = num(depth_frac * max(r, 0.2) if kind != "flat" else max(0.05, depth_frac * 5.0))
    tlen = num(depth + extra)
    if kind == "ball":
        tool = f'kind = "ballmill"\ndiameter = {d}\nlength = {tlen}\n'
    else:
        tool = f'kind = "endmill"\ndiameter = {d}\nlength = {tlen}\ncorner_radius = {rc}\n'
    e = np.array([math.cos(theta), math.sin(theta)])
    p0 = np.round(-length / 2 * e, 4)
    p1 = np.round(length / 2 * e, 4)
    half = length / 2 + r + 2.0
    setup = MILL_PLATE.format(top=depth + tlen + 5, lo=-half, hi=half, zlo=-(depth + 5), tool=tool, tol=tol)
    lines = [f"N10 T1 G00 X{p0[0]:.4f} Y{p0[1]:.4f} Z2", f"N20 G01 Z{-depth:.4f} F200"]
    for k in range(1, pieces + 1):
        q = p0 + (p1 - p0) * k / pieces
        lines.append(f"N{20 + 10 * k} X{q[0]:.4f} Y{q[1]:.4f}")
    lines.append(f"N{30 + 10 * pieces} G00 Z{depth + tlen + 5:.4f}")
    res = simulate(workdir, setup, "\n".join(lines) + "\n")
    L = float(np.hypot(*(p1 - p0)))
    exact = body_volume(r, rc, depth) + L * silhouette_area(r, rc, depth)
    bound = tol * (L * (2 * depth + 2 * r) + 2 * math.pi * r * depth + math.pi * r * r)
    assert abs(res.report["removed_volume"] - exact) <= bound, (res.report["removed_volume"], exact, bound)
    assert not res.warnings, res.warnings


# -- the two regressions of issue 10 -------------------------------------------------------------
TURN_PROGRAM = "N10 G95 S800 M03\nN20 G00 X32. Z2.\nN30 G01 X26. F0.2\nN40 Z-20.\nN50 X32.\nN60 G00 Z5.\nN70 M30\n"


def test_turning_with_the_default_tool(workdir):
    """Issue 10: the default turning tool (55 degrees, tip radius 0.4, height 10) on a bar of
    diameter 30 over z in [-40, 0], turned to diameter 26 down to Z-20. By Pappus (see
    test_turning_pass_volume) V = 2 pi [20 (15^2 - 13^2) / 2 + int_0^2 (13 + u) v(u) du]: the pass
    itself (pi (15^2 - 13^2) 20 = 3518.6) plus the nose's and the leading flank's wedge at Z-20.
    It used to remove 1513.6 mm^3 (half the profile dropped) and leave the bar at diameter 29.996."""
    tol = 0.002
    res = simulate(workdir, lathe_setup(15.0, -40.0, 'kind = "turning"\n', tol), TURN_PROGRAM)
    g = V(55.0, 0.4, 10.0)
    exact = 2 * math.pi * (20.0 * (15 ** 2 - 13 ** 2) / 2 + g.moments(2.0, 13.0)[1])
    assert exact == pytest.approx(3654.24, abs=0.01)  # the arithmetic, checked once by hand
    bound = 2 * math.pi * 15.0 * tol * (2 * (20.0 + g.v(2.0)) + g.nose_length(2.0))
    assert abs(res.report["removed_volume"] - exact) <= bound
    # the diameter at Z-10: the revolved polygon has a vertex at r = 13 and chords within tol inside
    dia = res.diameters_at(-10.0)
    assert np.all(dia <= 26.0 + 1e-6) and np.all(dia >= 26.0 - 2 * tol)


def test_multipass_thread_with_a_tip_radius(workdir):
    """Issue 10: the CNC8x6 multipass example with ``tip_radius = 0.05`` removed 6.17 mm^3 and
    every thread check read None. All three passes follow one helix (each re-synchronised at the
    zero pulse, I0), and a shallower V is inside the deeper one moved outwards (v grows with u), so
    the removed material is the last pass's sweep (X26.177) inside the blank: the slab z in [-8, 0]
    of radius 13.5 (the undercut below, radius 12.5, is deeper than the root 13.0885; the sweep
    starts at Z3 and ends at Z-9, beyond both ends of the slab by more than the groove's half
    width 0.27). Screw motion: V = (2 pi / 1.5) x 8 x 2 int_0^U (r0 + u) v(u) du with r0 =
    13.0885, U = 0.4115 (test_thread_volume_screw_motion; bound ``thread_bound``)."""
    src = (EXAMPLES / "cnc8x6-lathe" / "multipass.toml").read_text()
    assert "tip_radius = 0.0" in src
    path = workdir / "multipass.toml"
    path.write_text(src.replace("tip_radius = 0.0", "tip_radius = 0.05"))
    setup = cutsim.load_setup(str(path))
    res = cutsim.simulate(str(EXAMPLES / "cnc8x6-lathe" / "multipass.nc"), setup)
    tol = setup.tolerance
    g = V(60.0, 0.05, 10.0)
    r0 = 26.177 / 2
    U = 13.5 - r0
    exact = 2 * math.pi / 1.5 * 8.0 * 2 * g.moments(U, r0)[1]
    assert exact == pytest.approx(54.244, abs=0.001)  # with tip_radius = 0: 43.78 (a narrower V)
    assert abs(res.report["removed_volume"] - exact) <= thread_bound(tol, 13.5, 8.0, 1.5, g, U)
    # the thread reads: lead 1.5, one right-hand start, root at the programmed diameter (the nose's
    # lowest point; the helix chords may cut up to tol deeper, i.e. 2 tol on the diameter)
    th = res.thread(-6.0, -1.0)
    assert th["lead"] == pytest.approx(1.5, abs=0.005)
    assert th["starts"] == 1 and th["hand"] == "right"
    assert 26.177 - 2 * tol - 1e-4 <= th["root_diameter"] <= 26.177 + 1e-4


# -- errors: ranges at the key, degenerate shapes at the [[tool]] table ---------------------------
LATHE_HEAD = '[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n\n[stock]\nshape = "cylinder"\ndiameter = 30\nz = [-40, 0]\n\n'
MILL_HEAD = '[machine]\nkind = "mill"\ndialect = "cnc8x6"\n\n[stock]\nshape = "box"\nx = [0, 10]\ny = [0, 10]\nz = [-5, 0]\n\n'


@pytest.mark.parametrize("head,tool,key,fragment", [
    (MILL_HEAD, 'kind = "endmill"\ndiameter = 1e300', "diameter", "between 0.001 and 10000 mm"),
    (MILL_HEAD, 'kind = "endmill"\ndiameter = 0.0001', "diameter", "between 0.001 and 10000 mm"),
    (MILL_HEAD, 'kind = "ballmill"\ndiameter = 6\nlength = 20000', "length", "between 0.001 and 10000 mm"),
    (MILL_HEAD, 'kind = "endmill"\ndiameter = 6\ncorner_radius = 3.5', "corner_radius", "half the diameter"),
    (LATHE_HEAD, 'kind = "thread"\nangle = 0.5', "angle", "between 1 and 179 degrees"),
    (LATHE_HEAD, 'kind = "turning"\nheight = 0', "height", "between 0.001 and 10000 mm"),
    (LATHE_HEAD, 'kind = "turning"\ntip_radius = 0.0001', "tip_radius", "0 or between 0.001"),
    (LATHE_HEAD, 'kind = "turning"\ntip_radius = 30\nheight = 5', "tip_radius", "too large for the tool's height"),
    (LATHE_HEAD, 'kind = "profile"\npoints = [[0, 0], [1, 1], [2, 2]]', "points", "no area"),
    (LATHE_HEAD, 'kind = "profile"\npoints = [[0, 0], [2, 2], [2, 0], [0, 2]]', "points", "crosses itself"),
    (LATHE_HEAD, 'kind = "profile"\npoints = [[0, 0], [4, 4], [4, 0], [0, 1]]', "points", "crosses itself"),
    (MILL_HEAD, 'kind = "endmill"\ndiameter = 0.01\nlength = 20', "length", "at most 1000 x the diameter"),
    (LATHE_HEAD, 'kind = "profile"\npoints = [[0, 0], [2e4, 0], [0, 1]]', "points", "within +-10000 mm"),
])
def test_tool_out_of_range_is_an_error_at_its_key(workdir, head, tool, key, fragment):
    text = head + "[[tool]]\n" + tool + "\n"
    path = workdir / "bad.toml"
    path.write_text(text)
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(path))
    line = next(n for n, t in enumerate(text.splitlines(), 1) if t.startswith(key + " ="))
    assert (e.value.program, e.value.line, e.value.col) == (str(path), line, 1)
    assert f"[[tool]] #1 {key}:" in e.value.message and fragment in e.value.message, e.value.message


def test_huge_diameter_exits_2_not_3(workdir):
    """``diameter = 1e300`` used to be an internal error (exit 3); now exit 2 at the key."""
    setup = workdir / "huge.toml"
    setup.write_text(MILL_HEAD + '[[tool]]\nkind = "endmill"\ndiameter = 1e300\n')
    prog = workdir / "huge.nc"
    prog.write_text("N10 G00 X5 Y5 Z5\n")
    p = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(prog), "--setup", str(setup), "--out",
                        str(workdir / "huge-out")], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    line = setup.read_text().splitlines().index("diameter = 1e300") + 1
    assert f"{setup}:{line}:1: error: [[tool]] #1 diameter:" in p.stderr


def test_degenerate_python_tools_name_their_table(workdir):
    """Tools built in Python skip the loader: a profile that encloses no area, or a V outside the
    ranges, is a CutsimError at the line the ToolSpec says it came from, when it is built."""
    path = workdir / "ok.toml"
    path.write_text(LATHE_HEAD + '[[tool]]\nkind = "turning"\n')
    setup = cutsim.load_setup(str(path))
    assert (setup.tools[0].source, setup.tools[0].line) == (str(path), 10)  # its [[tool]] header
    from dataclasses import replace

    good = setup.tools[0]
    for bad, fragment in ((dict(kind="profile", points=((0.0, 0.0), (1.0, 1e-9), (2.0, 0.0))), "no area"),
                          (dict(angle=0.0), "angle"), (dict(height=float("nan")), "height")):
        setup.tools[0] = replace(good, **bad)
        with pytest.raises(CutsimError) as e:
            cutsim.simulate("turn.nc", setup, text=TURN_PROGRAM)
        assert (e.value.program, e.value.line) == (str(path), 10) and "[[tool]] T1:" in e.value.message
        assert fragment in e.value.message, e.value.message
