"""The direct sweep of a milling tool along a circle or helix (stock/helix.py) against geometry:
annulus and annular-sector volumes of a flat end mill, Pappus for a ball end mill, an independent
depth-map integral for helices, and the union of hulls of the tool's poses (built here, from a
polygonal tool written in this file). Also the exact arc description the planner attaches to
G17 arcs and the joining of a helix programmed as one circle per turn."""
import math
from dataclasses import replace

import manifold3d as m3d
import numpy as np
import pytest
import trimesh

from conftest import EXAMPLES
from cutsim import interp_config, load_setup, read_program
from cutsim.interp import interpret
from cutsim.interp.canon import Src
from cutsim.kinematics import plan
from cutsim.kinematics.paths import ArcGeom, SpatialPath, arc_geom
from cutsim.stock.arrays import solid_arrays
from cutsim.stock.helix import arc_sweep, merge_arcs
from cutsim.base.specs import ToolSpec

FLAT = ToolSpec(1, "endmill", diameter=10.0, length=20.0)
BALL = ToolSpec(2, "ballmill", diameter=6.0, length=18.0, corner_radius=3.0)
BULL = ToolSpec(3, "endmill", diameter=8.0, length=20.0, corner_radius=1.5)


def _path(arc: ArcGeom, tool: ToolSpec, tol: float) -> SpatialPath:
    """The move as the planner hands it over: chords of the arc plus its exact description."""
    n = max(1, math.ceil(abs(arc.sweep) / (2 * math.acos(1 - tol / arc.radius))))
    return SpatialPath(Src("t.nc", 1, 1), tool, arc.pose(np.linspace(0.0, 1.0, n + 1)), False, arc=arc)


def _box(lo, hi) -> m3d.Manifold:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return m3d.Manifold.cube(tuple(hi - lo)).translate(tuple(lo))


def _cut(stock: m3d.Manifold, solids: list) -> tuple[m3d.Manifold, float]:
    """The part and the removed volume; both the solids' union and the part are valid."""
    union = m3d.Manifold.batch_boolean(solids, m3d.OpType.Add)
    assert union.status() == m3d.Error.NoError and union.volume() > 0
    part = m3d.Manifold.batch_boolean([stock] + solids, m3d.OpType.Subtract)
    assert part.status() == m3d.Error.NoError
    return part, stock.volume() - part.volume()


def _mesh(part: m3d.Manifold) -> trimesh.Trimesh:
    return trimesh.Trimesh(*solid_arrays(part), process=False)


# -- constant Z ------------------------------------------------------------------------------------
def test_flat_full_circle_is_the_annulus():
    tol, R, r, depth = 0.01, 30.0, 5.0, 3.0
    arc = ArcGeom(0.0, 0.0, R, 0.0, 2 * math.pi, -depth, -depth)
    solids = arc_sweep(_path(arc, FLAT, tol), tol, 0.0)
    part, vol = _cut(_box((-50, -50, -10), (50, 50, 0)), solids)
    assert part.genus() == 0 and len(part.decompose()) == 1
    exact = math.pi * ((R + r) ** 2 - (R - r) ** 2) * depth
    walls = 2 * math.pi * ((R + r) + (R - r)) * depth  # each within tol of its place
    assert abs(vol - exact) <= tol * walls, (vol, exact)
    # the walls, seen in the section y = 0 at mid depth: radii R - r and R + r on both sides
    segs = trimesh.intersections.mesh_plane(_mesh(part), [0, 1.0, 0], [0, 0, 0])
    a, b = segs[:, 0], segs[:, 1]
    m = (np.minimum(a[:, 2], b[:, 2]) < -1.5) & (np.maximum(a[:, 2], b[:, 2]) > -1.5)
    t = (-1.5 - a[m, 2]) / (b[m, 2] - a[m, 2])
    xs = np.sort(np.abs(a[m, 0] + t * (b[m, 0] - a[m, 0])))
    xs = xs[xs < 49.0]  # not the box's own faces
    assert np.allclose(xs, [R - r, R - r, R + r, R + r], atol=tol)


def test_flat_partial_arc_is_the_sector_and_two_half_discs():
    tol, R, r, depth, theta = 0.01, 30.0, 5.0, 3.0, 2.0
    arc = ArcGeom(0.0, 0.0, R, 0.3, -theta, -depth, -depth)  # clockwise
    part, vol = _cut(_box((-50, -50, -10), (50, 50, 0)), arc_sweep(_path(arc, FLAT, tol), tol, 0.0))
    assert part.genus() == 0
    exact = (theta * ((R + r) ** 2 - (R - r) ** 2) / 2 + math.pi * r * r) * depth
    perimeter = theta * (R + r) + theta * (R - r) + 2 * math.pi * r
    assert abs(vol - exact) <= tol * perimeter * depth, (vol, exact)


def test_ball_arc_by_pappus():
    # tip 2 below the top: the ball's section below the top is the circular segment 1 below the
    # centre; revolved about the arc's axis over theta (centroid at R), plus the two half-tools at
    # the ends (together the spherical cap of height 2)
    tol, R, rb, theta = 0.01, 25.0, 3.0, 2.2
    arc = ArcGeom(0.0, 0.0, R, 0.3, theta, -2.0, -2.0)  # counter-clockwise
    part, vol = _cut(_box((-40, -40, -10), (40, 40, 0)), arc_sweep(_path(arc, BALL, tol), tol, 0.0))
    assert part.genus() == 0
    d = 1.0  # the ball's centre is 1 above the top: the section is the disc's part d below it
    seg = rb * rb * math.acos(d / rb) - d * math.sqrt(rb * rb - d * d)
    cap = math.pi * 2.0 ** 2 * (3 * rb - 2.0) / 3
    exact = seg * theta * R + cap
    arc_len = 2 * rb * math.acos(d / rb)  # the section's curved boundary
    bound = tol * (arc_len * theta * (R + rb) + 2 * math.pi * rb * 2.0)
    assert abs(vol - exact) <= bound, (vol, exact, bound)


# -- helices ---------------------------------------------------------------------------------------
def _flat_helix_volume(R, r, psi0, sweep, z0, z1, top, bottom, nr=300, nphi=3000) -> float:
    """Independent volume a flat end mill removes from the slab bottom..top along a helix: at a
    point (rho, phi) of the annulus the floor is the lowest tip height while the point is within
    the tool's footprint; the tool at travel u covers it iff the angle between them is at most
    a(rho), so the covering travels are intervals and z being linear the floor is at their ends."""
    U, s = abs(sweep), math.copysign(1.0, sweep)
    k = (z1 - z0) / U
    rho = R - r + (np.arange(nr) + 0.5) * (2 * r / nr)
    phi = (np.arange(nphi) + 0.5) * (2 * math.pi / nphi)
    total = 0.0
    for rr in rho:
        a = math.acos(min(1.0, (rr * rr + R * R - r * r) / (2 * rr * R)))
        ustar = (s * (phi - psi0)) % (2 * math.pi)  # first travel at the point's angle
        floor = np.full(nphi, np.inf)
        for n in range(-1, int(U / (2 * math.pi)) + 2):
            lo = np.clip(ustar + 2 * math.pi * n - a, 0.0, U)
            hi = np.clip(ustar + 2 * math.pi * n + a, 0.0, U)
            lowest = z0 + k * (lo if k >= 0 else hi)
            floor = np.where(hi > lo, np.minimum(floor, lowest), floor)
        depth = np.clip(top - np.maximum(floor, bottom), 0.0, None)
        total += float(depth.sum()) * (2 * math.pi / nphi) * rr * (2 * r / nr)
    return total


def _hulls(path: SpatialPath, tol: float, top: float) -> list:
    """The tool's poses on the chords, hull by hull: a polygonal tool with the circle's perimeter
    (ring radius r pi / (n sin(pi/n))), corner layers on the corner arc, cut off above ``top``."""
    t = path.tool
    r = t.diameter / 2.0
    rc = t.corner_radius
    n = max(8, math.ceil(math.pi / math.acos(1 - tol / r)))
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    ring = np.column_stack([np.cos(ang), np.sin(ang)]) * (r * math.pi / (n * math.sin(math.pi / n)))
    layers = []
    if rc > 0:
        m = max(1, math.ceil((math.pi / 2) / (2 * math.acos(1 - tol / rc))))
        for b in np.linspace(0, math.pi / 2, m + 1):
            rad = (r - rc + rc * math.sin(b)) / r
            layers.append(np.column_stack([ring * max(rad, 1e-6), np.full(n, rc - rc * math.cos(b))]))
    else:
        layers.append(np.column_stack([ring, np.zeros(n)]))
    body = np.vstack(layers)
    out = []
    for p0, p1 in zip(path.points[:-1], path.points[1:]):
        h = min(t.length, top - min(p0[2], p1[2]))
        if h <= 0:
            continue
        rad = 1.0 if h >= rc else (r - rc + math.sqrt(rc * rc - (rc - h) ** 2)) / r  # section at h
        tool = np.vstack([body[body[:, 2] < h], np.column_stack([ring * rad, np.full(n, h)])])
        out.append(m3d.Manifold.hull_points(np.vstack([tool + p0, tool + p1])))
    return out


def _same_solid(stock, mine: list, hulls: list, bound: float) -> tuple[float, float]:
    pa, va = _cut(stock, mine)
    pb, vb = _cut(stock, hulls)
    assert pa.genus() == 0 and len(pa.decompose()) == 1
    assert (pb - pa).volume() <= bound and (pa - pb).volume() <= bound, ((pb - pa).volume(), (pa - pb).volume(), bound)
    return va, vb


def test_flat_helix_against_the_depth_map_and_the_hulls():
    # a helical entry: 3 turns down 2 per turn into a slab, the flutes reach above it all the time
    tol, R, r = 0.02, 20.0, 5.0
    arc = ArcGeom(0.0, 0.0, R, 0.3, 3 * 2 * math.pi, 0.5, -5.5)
    path = _path(arc, FLAT, tol)
    stock = _box((-30, -30, -10), (30, 30, 0))
    exact = _flat_helix_volume(R, r, 0.3, arc.sweep, 0.5, -5.5, 0.0, -10.0)
    mine = arc_sweep(path, tol, 0.0)
    surface = 2 * math.pi * 2 * R * 6.0 + 4 * math.pi * R * r  # walls (at most 6 deep) and floor
    va, vb = _same_solid(stock, mine, _hulls(path, tol, 0.05 + 10 * tol), tol * surface)
    assert abs(va - exact) <= tol * surface / 4, (va, exact)
    assert len(mine) < 50  # a few warped pieces and the hulls at the two ends, not a hull per chord


@pytest.mark.parametrize("tool,z0,z1,turns", [
    (BALL, 0.5, -5.5, 3.0),  # descending ball
    (BULL, -6.0, 0.3, -2.5),  # rising bull-nose, clockwise
    (replace(BALL, length=3.5), 0.5, -6.1, 3.3),  # flutes shorter than the cut: turns in chunks
    (replace(FLAT, length=2.5), -7.0, -0.4, -3.3),  # short flutes, turns merged into one
    (replace(FLAT, diameter=6.0, length=2.5), 0.5, -15.1, 2.6),  # pitch above the profile: one solid
])
def test_helix_equals_the_union_of_hulls(tool, z0, z1, turns):
    tol, R = 0.04, 20.0
    arc = ArcGeom(0.0, 0.0, R, 0.3, turns * 2 * math.pi, z0, z1)
    path = _path(arc, tool, tol)
    stock = _box((-30, -30, -20), (30, 30, 0))
    r = tool.diameter / 2
    surface = 2 * math.pi * 2 * R * max(-z0, -z1) + 4 * math.pi * R * r * abs(turns)
    va, vb = _same_solid(stock, arc_sweep(path, tol, 0.0), _hulls(path, tol, 0.05 + 10 * tol), tol * surface)
    assert abs(va - vb) <= tol * surface


def test_without_a_top_every_turn_is_kept():
    tol = 0.02
    arc = ArcGeom(0.0, 0.0, 20.0, 0.3, 2.5 * 2 * math.pi, 0.5, -4.5)
    path = _path(arc, FLAT, tol)
    stock = _box((-30, -30, -10), (30, 30, 0))
    _, v_top = _cut(stock, arc_sweep(path, tol, 0.0))
    _, v_all = _cut(stock, arc_sweep(path, tol))
    assert abs(v_top - v_all) <= 1e-6 * v_all


def test_not_applicable_returns_none():
    tol = 0.02
    arc = ArcGeom(0.0, 0.0, 20.0, 0.0, math.pi, -1.0, -2.0)
    path = _path(arc, FLAT, tol)
    assert arc_sweep(path, tol, 0.0) is not None
    assert arc_sweep(replace(path, arc=None), tol, 0.0) is None
    assert arc_sweep(replace(path, tool=ToolSpec(1, "turning")), tol, 0.0) is None
    assert arc_sweep(replace(path, tool=replace(BALL, length=2.0)), tol, 0.0) is None  # flutes end on the ball
    # points moved without the arc (e.g. a shifted copy for a check): the chords are the truth
    assert arc_sweep(replace(path, points=path.points + [0, 0, 0.01]), tol, 0.0) is None
    # the tool reaches over the axis of the arc
    small = replace(arc, radius=4.0)
    assert arc_sweep(_path(small, FLAT, tol), tol, 0.0) is None
    # too short for a part between the two ends (each 2 asin(r/R) of hulls)
    short = replace(arc, sweep=0.4)
    assert arc_sweep(_path(short, FLAT, tol), tol, 0.0) is None


# -- the planner's arcs ----------------------------------------------------------------------------
def test_arc_geom_only_for_circles_in_xy():
    g = arc_geom((10, 0, 0), (0, 10, -1), (0, 0, 0), "XY", False, False)
    assert g.radius == pytest.approx(10) and g.sweep == pytest.approx(math.pi / 2)
    assert g.psi0 == pytest.approx(0) and (g.z0, g.z1) == (0.0, -1.0)
    assert arc_geom((10, 0, 0), (0, 10, 0), (0, 0, 0), "XY", True, False).sweep == pytest.approx(-1.5 * math.pi)
    assert arc_geom((10, 0, 0), (0, 11, 0), (0, 0, 0), "XY", False, False) is None  # a spiral
    assert arc_geom((10, 0, 0), (0, 0, 10), (0, 0, 0), "ZX", False, False) is None
    # a following arc on the same helix joins; another centre, sense or pitch does not
    a = ArcGeom(0, 0, 10, 0.0, math.pi, 0.0, -1.0)
    b = ArcGeom(0, 0, 10, math.pi, math.pi, -1.0, -2.0)
    assert a.joined(b) == ArcGeom(0, 0, 10, 0.0, 2 * math.pi, 0.0, -2.0)
    assert a.joined(replace(b, cx=1.0)) is None
    assert a.joined(replace(b, sweep=-math.pi, psi0=math.pi)) is None
    assert a.joined(replace(b, z1=-3.0)) is None


def test_helix_nc_joins_into_one_helix_and_cuts_the_trench():
    prog = EXAMPLES / "cnc8x6-mill" / "helix.nc"
    setup = load_setup(str(prog.with_suffix(".toml")))
    tol = 0.02
    program = interpret(str(prog), read_program(str(prog)), interp_config(setup, setup.machine.start))
    paths = plan(program, setup.machine, setup.tools, tol).paths
    arcs = [p for p in paths if p.arc is not None]
    assert len(arcs) == 22  # 21 full circles and a half circle, each with its exact arc
    for p in arcs:  # the chords start and end on the arc
        assert np.allclose(p.arc.pose(np.array([0.0, 1.0])), p.points[[0, -1]], atol=1e-9)
    joined = merge_arcs(paths)
    assert len(joined) == len(paths) - 21
    h = [p for p in joined if p.arc is not None]
    assert len(h) == 1
    g = h[0].arc
    assert (g.cx, g.cy, g.radius) == (100.0, 0.0, 100.0) and g.psi0 == pytest.approx(math.pi)
    assert g.sweep == pytest.approx(-21.5 * 2 * math.pi) and g.z1 == pytest.approx(21.5 * 1.05)
    assert np.array_equal(h[0].points, np.vstack([arcs[0].points] + [p.points[1:] for p in arcs[1:]]))
    # the trench in the plate (x 10..190, z 0..20) against the depth map of the first turn
    solids = arc_sweep(h[0], tol, 20.0)
    assert len(solids) < 50
    part, vol = _cut(_box((10, -120, 0), (190, 120, 20)), solids)
    assert part.genus() == 0
    exact = _trench_volume()
    surface = 2 * 2 * math.pi * 100 * 20 + 4 * math.pi * 100 * 5
    assert abs(vol - exact) <= tol * surface / 4, (vol, exact)


def _trench_volume(nr=300, nphi=4000) -> float:
    """helix.nc's trench: the floor at a point is the tool's height when it first reaches it
    (clockwise from the angle pi, 1.05 up per turn, radius 5 on the circle of radius 100 about
    (100, 0)); the plate keeps 10 <= x <= 190."""
    rho = 95 + (np.arange(nr) + 0.5) * (10 / nr)
    total = 0.0
    for rr in rho:
        delta = math.acos((rr * rr + 100 * 100 - 25) / (2 * rr * 100))
        a1, a2 = math.acos(90 / rr), math.acos(-90 / rr)
        for lo, hi in ((a1, a2), (-a2, -a1)):
            phi = lo + (np.arange(nphi) + 0.5) * ((hi - lo) / nphi)
            u = (math.pi - phi) % (2 * math.pi)
            floor = np.where((u <= delta) | (u >= 2 * math.pi - delta), 0.0, 1.05 * (u - delta) / (2 * math.pi))
            total += float(np.sum(20.0 - floor)) * ((hi - lo) / nphi) * rr * (10 / nr)
    return total
