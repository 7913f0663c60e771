"""3D milling with a ball-end mill: CAM-style lines of many short moves (swept as mitred tubes,
stock/tube.py) and everything around them (end bodies, connecting moves, sharp bends) against
geometry computed here: the groove's circular section and a dense depth map of the ball's lowest
point. Nothing here calls cutsim's sweep code for an expected value."""
import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

import cutsim
from cutsim.stock import tube
from cutsim.base.specs import ToolSpec

PLATE = str(Path(__file__).resolve().parents[1] / "data" / "programs" / "mill" / "plate.toml")  # top Z0, T2: ball r = 3
R = 3.0
BALL = ToolSpec(2, "ballmill", diameter=6.0, length=20.0, corner_radius=3.0)


def _run(tmp_path, lines, tol):
    prog = tmp_path / "p.nc"
    prog.write_text("\n".join(lines) + "\n")
    return cutsim.simulate(str(prog), PLATE, tolerance=tol)


def test_groove_in_many_pieces_is_the_ball_circle(tmp_path):
    """A straight groove written as 24 moves of 5 mm: one tube. Its section is the ball circle and
    its volume the circular segment times the plate length."""
    tol = 0.002
    lines = ["N10 T2 G00 X-10 Y50 Z-2", "N20 G01 X-5 F300"] + [f"X{x}" for x in range(0, 115, 5)] + ["G00 Z30"]
    res = _run(tmp_path, lines, tol)
    mesh = res.mesh()
    segs = np.asarray(trimesh.intersections.mesh_plane(mesh, [1.0, 0, 0], [37.3, 0, 0]))[..., 1:]
    p = segs.reshape(-1, 2)
    groove = p[(p[:, 1] < -1e-6) & (p[:, 1] > -19.0) & (np.abs(p[:, 0] - 50.0) < 3.5)]
    assert len(groove) > 20
    d = np.hypot(groove[:, 0] - 50.0, groove[:, 1] - 1.0)  # ball centre 3 above the tip
    assert np.all(np.abs(d - R) <= tol + 1e-6)
    h = 2.0  # depth below the top: circular segment of the r = 3 circle, height 2
    area = R * R * math.acos((R - h) / R) - (R - h) * math.sqrt(2 * R * h - h * h)
    arc = 2 * R * math.acos((R - h) / R)
    removed = res.report["removed_volume"]
    assert abs(removed - area * 100.0) <= tol * arc * 100.0  # within the tolerance over the cut surface


def _depth_map_volume(polylines, step: float = 0.02, dx: float = 0.05) -> float:
    """Volume below the plate top Z0 and above the lowest point of a ball of radius R whose tip
    runs along the 3D ``polylines``, over the plate (x, y in [0, 100]): the polylines are sampled
    every ``step`` and each sample lowers the floor of the grid cells under its ball."""
    g = np.arange(dx / 2, 100.0, dx)
    floor = np.zeros((len(g), len(g)))  # [iy, ix]; the top is Z0
    w = int(math.ceil(R / dx)) + 1
    for pl in polylines:
        pl = np.asarray(pl, dtype=float)
        for a, b in zip(pl[:-1], pl[1:]):
            n = max(1, int(math.ceil(np.linalg.norm(b - a) / step)))
            for t in np.arange(n + 1) / n:
                px, py, pz = a + t * (b - a)
                ix, iy = int(px / dx), int(py / dx)
                xs, ys = slice(max(ix - w, 0), ix + w + 1), slice(max(iy - w, 0), iy + w + 1)
                d2 = (g[xs][None, :] - px) ** 2 + (g[ys][:, None] - py) ** 2
                low = np.where(d2 < R * R, pz + R - np.sqrt(np.clip(R * R - d2, 0, None)), np.inf)
                np.minimum(floor[ys, xs], low, out=floor[ys, xs])
    return float(np.sum(-np.clip(floor, None, 0.0)) * dx * dx)


def test_wavy_raster_matches_the_depth_map(tmp_path):
    """Four raster lines over a wave (hills and valleys, 1 mm moves, 1 mm stepover) linked by
    moves at their ends, and a V groove whose 11 degree bend is too sharp for one tube: the
    removed volume agrees with the depth map within the tolerance over the cut area."""
    tol = 0.005
    xs = np.arange(10.0, 91.0, 1.0)
    wave = lambda x: -2.0 + 0.8 * np.sin(x / 7.0)  # noqa: E731
    lines = ["N10 T2 G00 X10 Y40 Z5", f"G01 Z{wave(10.0):.6f} F300"]
    raster = [(10.0, 40.0, 5.0)]
    for j in range(4):
        y = 40.0 + j
        seq = xs if j % 2 == 0 else xs[::-1]
        if j:
            lines.append(f"Y{y:.1f}")
        lines += [f"X{x:.1f} Z{wave(x):.6f}" for x in seq[1:]]
        raster += [(x, y, wave(x)) for x in seq]
    vx = np.arange(20.0, 81.0, 1.0)
    vz = -1.0 - 3.0 * (1.0 - np.abs(vx - 50.0) / 30.0)  # slopes -0.1 and +0.1: bend 2 atan 0.1
    lines += ["G00 Z5", "Y70", "X20", f"G01 Z{vz[0]:.6f}"] + [f"X{x:.1f} Z{z:.6f}" for x, z in zip(vx[1:], vz[1:])]
    lines += ["G00 Z30"]
    res = _run(tmp_path, lines, tol)
    assert not res.warnings
    expected = _depth_map_volume([raster, [(20.0, 70.0, 5.0)] + [(x, 70.0, z) for x, z in zip(vx, vz)]])
    cut_area = 86.0 * 9.0 + 66.0 * 6.0
    assert res.report["removed_volume"] == pytest.approx(expected, abs=tol * cut_area)


def test_stretches_follow_the_plane_and_the_bends():
    tol = 0.002
    x = np.arange(0.0, 11.0)
    flat = np.column_stack([x, np.zeros_like(x), np.full_like(x, -1.0)])
    assert tube.stretches(flat, BALL, tol, 5.0) == [(0, 10)]
    jog = flat.copy()
    jog[:, 2] -= 0.1 * x  # a ramp ...
    jog[6:, 1] += 0.01  # ... that leaves its vertical plane at point 6
    assert tube.stretches(jog, BALL, tol, 5.0) == [(0, 5), (6, 10)]
    level_jog = flat.copy()
    level_jog[6:, 1] += 0.01  # level: a 0.6 degree turn left and back is a waterline stretch
    assert tube.stretches(level_jog, BALL, tol, 5.0) == [(0, 10)]
    bend = flat.copy()
    bend[5:, 2] -= (x[5:] - 5) * math.tan(math.radians(10))  # a 10 degree bend at point 5
    assert tube.stretches(bend, BALL, tol, 5.0) == [(0, 5), (5, 10)]
    plunge = np.vstack([flat[:4], flat[3] - [0, 0, 3], flat[4:] - [0, 0, 3]])
    assert all(not (i < 3 < j) for i, j in tube.stretches(plunge, BALL, tol, 5.0))
    short = replace_length(BALL, 2.0)  # flutes do not reach the top: no tube
    assert tube.stretches(flat, short, tol, 5.0) == []


def replace_length(tool: ToolSpec, length: float) -> ToolSpec:
    from dataclasses import replace

    return replace(tool, length=length)


def test_ramp_in_pieces_is_one_exact_hull(tmp_path):
    """A flat end mill ramping down 2 mm over 20 mm, written as 10 moves: the pieces are collinear,
    so one hull of the poses sweeps them exactly. For |y| <= r the floor at x is the depth of the
    furthest disc centre that still covers x, so per y the removed area is k (L^2/2 + 2 w L), w =
    sqrt(r^2 - y^2), and the volume k L (L r + pi r^2)."""
    from cutsim.stock import mill

    tol = 0.002
    k, length, r = 0.1, 20.0, 5.0
    lines = ["N10 T1 G00 X20 Y50 Z5", "G01 Z0 F300"] + [f"X{20 + 2 * i} Z{-0.2 * i:.1f}" for i in range(1, 11)]
    res = _run(tmp_path, lines + ["G00 Z30"], tol)
    expected = k * length * (length * r + math.pi * r * r)
    floor_area = (length + 2 * r) * 2 * r
    assert res.report["removed_volume"] == pytest.approx(expected, abs=tol * floor_area)
    pts = np.column_stack([20 + 2 * np.arange(11), np.full(11, 50.0), -0.2 * np.arange(11)])
    assert mill.runs(pts, tol, True) == [(0, 10)]
    hill = pts.copy()
    hill[5, 2] += 0.01  # the middle pose 10 um above the chord: the hull would cut below it
    assert len(mill.runs(hill, tol, True)) > 1


def test_ball_climbing_out_of_the_stock_matches_the_depth_map(tmp_path):
    """A ball-end mill ramping up and out through the top, in two moves (hulls, not a tube): the
    ball centre is above the stock top along most of the way, where the tool's section at the
    stock top is smaller than its circle. Against the depth map of the ball's lowest point."""
    tol = 0.002
    lines = ["N10 T2 G00 X20 Y50 Z5", "G01 Z-2 F300", "X30 Z-0.5", "X40 Z1", "G00 Z30"]
    res = _run(tmp_path, lines, tol)
    expected = _depth_map_volume([[(20.0, 50.0, 5.0), (20.0, 50.0, -2.0), (30.0, 50.0, -0.5), (40.0, 50.0, 1.0)]])
    assert res.report["removed_volume"] == pytest.approx(expected, abs=tol * 30.0 * 6.0)


@pytest.mark.parametrize("seed", range(6))
def test_random_planar_lines_tube_equals_hulls(seed, monkeypatch):
    """Random lines in a vertical plane (steps 0.05-3 mm, slopes up to 1.2 rad, bends small and
    large, in and out of the stock): the tubes and the tool's bodies give the volume of one convex
    hull per segment (exact for a convex tool on a straight move) within the tolerance over the
    cut surface, and the part is a valid solid."""
    import manifold3d as m3d

    from cutsim.stock import mill

    rng = np.random.default_rng(seed)
    box = m3d.Manifold.cube((200.0, 200.0, 20.0)).translate((-100.0, -100.0, -20.0))
    tol = 0.01
    for _ in range(5):
        n = int(rng.integers(6, 30))
        step = rng.uniform(0.05, 3.0, n)
        ang = np.clip(np.cumsum(rng.normal(0, rng.choice([0.01, 0.05, 0.3]), n)) + rng.uniform(-0.5, 0.5), -1.2, 1.2)
        x = np.concatenate([[0.0], np.cumsum(step * np.cos(ang))])
        z = np.clip(np.concatenate([[-2.0], -2.0 + np.cumsum(step * np.sin(ang))]), -15.0, 3.0)
        th = rng.uniform(0, 2 * math.pi)
        pts = np.column_stack([x * math.cos(th), x * math.sin(th), z])
        cap = mill.cap_height(0.0, tol)

        def removed(solids):
            part = m3d.Manifold.batch_boolean([box] + solids, m3d.OpType.Subtract)
            assert part.status() == m3d.Error.NoError
            return box.volume() - part.volume()

        with_tubes = removed(mill.hull_sweep(pts, BALL, tol, cap))
        monkeypatch.setattr(tube, "TUBE_MIN_SEGMENTS", 10 ** 9)
        monkeypatch.setattr(mill, "MAX_RUN", 2)
        per_segment = removed(mill.hull_sweep(pts, BALL, tol, cap))
        monkeypatch.undo()
        length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
        surface = (length + 2 * R) * (math.pi * R + 2 * 15.0)  # half cylinder + walls, generous
        assert abs(with_tubes - per_segment) <= tol * surface


def test_long_programs_are_swept_and_subtracted_in_pieces(tmp_path, monkeypatch):
    """With tiny pieces (chains cut every 7 poses, a subtract after every solid) the raster and
    V groove of the depth-map test remove the same volume: pieces bound memory, not the result."""
    from cutsim.stock import budget, mill

    monkeypatch.setattr(mill, "CHAIN_POINTS", 7)
    monkeypatch.setattr(budget, "CHUNK_TRIANGLES", 1)
    test_wavy_raster_matches_the_depth_map(tmp_path)


def test_waterline_polygon_matches_the_depth_map(tmp_path):
    """A ball-end mill on two level loops of 0.5 mm moves (a waterline finish, turning 1.9 degrees
    at every move, and a 90 degree corner too sharp for one tube): swept as level tubes, the
    removed volume agrees with the depth map."""
    tol = 0.005
    k = 200
    loop = [(50 + 15 * math.cos(2 * math.pi * i / k), 50 + 15 * math.sin(2 * math.pi * i / k)) for i in range(k + 1)]
    lines, path = ["N10 T2 G00 X65 Y50 Z5", "G01 Z-1 F300"], [(65.0, 50.0, 5.0)]
    for z in (-1.0, -1.6):
        lines.append(f"Z{z}")
        lines += [f"X{x:.6f} Y{y:.6f}" for x, y in loop[1:]]
        path += [(x, y, z) for x, y in loop]
    corner = [(65.0, 50.0), (65.0, 75.0), (90.0, 75.0)]  # then a corner
    lines += [f"X{x} Y{y}" for x, y in corner[1:]] + ["G00 Z30"]
    path += [(x, y, -1.6) for x, y in corner]
    res = _run(tmp_path, lines, tol)
    assert not res.warnings
    expected = _depth_map_volume([path])
    cut_area = 2 * math.pi * 15 * 6 + 50 * 6
    assert res.report["removed_volume"] == pytest.approx(expected, abs=tol * cut_area)


def test_level_stretches_turn_until_the_mitre_is_too_far_out():
    tol = 0.002
    k = 100
    ang = 2 * math.pi * np.arange(k + 1) / k  # 3.6 degree turns on a radius 20 loop: 0.063 rad
    loop = np.column_stack([20 * np.cos(ang), 20 * np.sin(ang), np.full(k + 1, -1.0)])
    limit = tube.max_turn(R, tol)
    assert limit < 2 * math.pi / k  # 3.6 degrees is too sharp at 2 um: every joint splits
    assert tube.stretches(loop, BALL, tol, 5.0) == []
    # at 10 um every turn fits, but one tube round the closed loop would overlap itself: halves
    assert tube.stretches(loop, BALL, 0.01, 5.0) == [(0, k // 2), (k // 2, k)]
    assert tube.stretches(loop[: k // 2 + 1], BALL, 0.01, 5.0) == [(0, k // 2)]
    assert tube.is_level(loop)


NESTED_SETUP = """
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 30.0]

[stock]
shape = "box"
x = [0.0, 100.0]
y = [0.0, 100.0]
z = [-4.0, 0.0]

[[tool]]
number = 2
kind = "ballmill"
diameter = 6.0
length = 20.0
"""


def test_nested_passes_on_one_path_are_one_solid(tmp_path, monkeypatch):
    """Two passes of a ball-end mill along one XY path (plunge at P, line to Q), at Z-2 and at Z-8,
    through a 4 mm plate (c41710: CYCLE71 at 17 depth steps gave 2.5M triangles of slivers on the
    walls the passes share, 132 s): each body of the shallow pass and of both plunges lies in a body
    of the deep pass (same XY, tip lower, flutes above the stock), so only the deep line's hull is
    subtracted. The deep ball's equator (Z-5) is below the plate, so the part is the plate minus the
    stadium prism of radius r around PQ: volume 4 (2 r L + pi r^2) within the tolerance over the
    slot's walls, and the slot adds at most a bounded number of triangles to the plate's. (This
    small case does not breed slivers without the fix; the solid count is what catches it.)"""
    import manifold3d as m3d

    from cutsim.stock import mill

    tol, r = 0.01, 3.0
    p, q = (20.0, 30.0), (70.0, 60.0)
    lines = ["N10 T2 G00 X20 Y30 Z5", "G01 Z-2 F300", "X70 Y60", "G00 Z5", "X20 Y30",
             "G01 Z-8", "X70 Y60", "G00 Z30"]
    (tmp_path / "s.toml").write_text(NESTED_SETUP)
    (tmp_path / "p.nc").write_text("\n".join(lines) + "\n")
    seen = []
    batch = m3d.Manifold.batch_boolean

    def record(parts, op):
        if op == m3d.OpType.Subtract:
            seen.append(len(parts))
        return batch(parts, op)

    monkeypatch.setattr(m3d.Manifold, "batch_boolean", staticmethod(record))
    res = cutsim.simulate(str(tmp_path / "p.nc"), str(tmp_path / "s.toml"), tolerance=tol)
    monkeypatch.undo()
    length = math.hypot(q[0] - p[0], q[1] - p[1])
    exact = 4.0 * (2 * r * length + math.pi * r * r)
    walls = 4.0 * (2 * length + 2 * math.pi * r)
    assert res.report["removed_volume"] == pytest.approx(exact, abs=tol * walls)
    assert res.report["warnings"] == []
    assert seen[-1] == 2  # the plate and the deep line's hull: the other three lie inside it
    # by geometry: below the plate's top the shallow line's hull lies inside the deep one's
    tool = ToolSpec(2, "ballmill", diameter=6.0, length=20.0, corner_radius=3.0)
    cap = mill.cap_height(0.0, tol)
    keys: list = []
    deep = mill.hull_sweep(np.array([[*p, -8.0], [*q, -8.0]]), tool, tol, cap, keys)
    shallow = mill.hull_sweep(np.array([[*p, -2.0], [*q, -2.0]]), tool, tol, cap, keys)
    assert len(deep) == len(shallow) == 1
    below = shallow[0].trim_by_plane((0.0, 0.0, -1.0), 0.0)  # z <= 0
    assert (below - deep[0]).volume() <= 1e-9 * below.volume()
    assert mill.nested(keys, 0.0) == [False, True]
    # the plate's faces (refined before the subtract) plus the slot: each of the prism's 2 (n + 2)
    # vertices (its n-gon's two halves and the support points) adds at most a few triangles to the
    # top, the bottom and the walls
    n = max(8, math.ceil(2 * math.pi / (2 * math.acos(1 - tol / r))))
    plate = mill.refined(m3d.Manifold.cube((100.0, 100.0, 4.0))).num_tri()
    assert res.report["triangles"] <= plate + 16 * (n + 2)
