"""2.5D milling: the region a flat end mill sweeps at constant Z is the tool-centre polyline offset
by the radius with round joins and caps (stock/mill.py ``buffer``). Checked against exact point
distances to the polyline (numpy, not the code under test) and analytic areas (Minkowski sums of
segments and discs), and through the whole pipeline on a zig-zag pocket."""
import math
import numpy as np
import pytest

import cutsim
from cutsim.stock import mill


def _seg_dist(q: np.ndarray, pl: np.ndarray) -> np.ndarray:
    """Distance of the points q (n, 2) to the polyline pl (k, 2), k >= 1."""
    if len(pl) == 1:
        return np.hypot(*(q - pl[0]).T)
    a, b = pl[:-1], pl[1:]
    d = b - a
    ll = np.maximum((d * d).sum(1), 1e-300)
    t = np.clip(((q[:, None, :] - a[None]) * d[None]).sum(-1) / ll[None], 0.0, 1.0)
    p = a[None] + t[..., None] * d[None]
    return np.hypot(*(q[:, None, :] - p).transpose(2, 0, 1)).min(1)


def _inside(q: np.ndarray, polys: list[np.ndarray]) -> np.ndarray:
    """Even-odd point-in-polygon of the region's outlines (outer and holes)."""
    ins = np.zeros(len(q), dtype=bool)
    for poly in polys:
        a, b = poly, np.roll(poly, -1, axis=0)
        ya, yb = a[:, 1][None], b[:, 1][None]
        y = q[:, 1:2]
        cross = (ya > y) != (yb > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = a[:, 0][None] + (y - ya) * (b[:, 0] - a[:, 0])[None] / (yb - ya)
        ins ^= (np.sum(cross & (q[:, 0:1] < xi), axis=1) % 2).astype(bool)
    return ins


@pytest.mark.parametrize("seed", range(6))
def test_offset_is_the_distance_band(seed):
    """Every point closer than r - tol to a polyline is inside, every point farther than r is
    outside: random polylines with reversals, self-crossings, repeated and single points."""
    rng = np.random.default_rng(seed)
    r, tol = float(rng.uniform(0.5, 3.0)), 0.002
    lines = []
    for _ in range(3):
        k = int(rng.integers(1, 12))
        pl = np.cumsum(rng.normal(0, 2.0, (k, 2)), axis=0) + rng.uniform(-5, 5, 2)
        if k > 3:
            pl[2] = pl[1]  # a repeated point
            pl = np.vstack([pl, pl[-2]])  # a reversal
        lines.append(pl)
    reg = mill.buffer(lines, r, tol)
    polys = reg.to_polygons()
    b = reg.bounds()
    g = rng.uniform([b[0] - 1, b[1] - 1], [b[2] + 1, b[3] + 1], (20000, 2))
    dist = np.min([_seg_dist(g, pl) for pl in lines], axis=0)
    ins = _inside(g, polys)
    assert np.all(ins[dist <= r - mill.ARC_FRACTION * tol - 3e-6])
    assert not np.any(ins[dist >= r + 3e-6])
    # the outline itself lies in the band r - ARC_FRACTION tol .. r
    v = np.vstack(polys)
    dv = np.min([_seg_dist(v, pl) for pl in lines], axis=0)
    assert np.all(dv <= r + 3e-6) and np.all(dv >= r - mill.ARC_FRACTION * tol - 3e-6)


def test_l_path_area_is_the_minkowski_sum():
    # segments of lengths a and b at a right angle: 2r(a + b) + 5/4 pi r^2 - r^2
    r, tol, a, b = 3.0, 0.002, 20.0, 10.0
    reg = mill.buffer([np.array([[0.0, 0.0], [a, 0.0], [a, b]])], r, tol)
    exact = 2 * r * (a + b) + 1.25 * math.pi * r * r - r * r
    round_len = 2 * math.pi * r  # two half-circle caps, the outer quarter and the rest of the corner
    assert exact - mill.ARC_FRACTION * tol * round_len <= reg.area() <= exact + 3e-6


def test_single_point_is_the_disc():
    r, tol = 5.0, 0.001
    reg = mill.buffer([np.array([[1.0, 2.0]])], r, tol)
    assert math.pi * r * r * (1 - 2 * mill.ARC_FRACTION * tol / r) <= reg.area() <= math.pi * r * r


def test_level_joins_continuing_moves():
    lv = mill.Level(0, None, None, -1.0, 0.01)
    lv.add(np.array([[0.0, 0.0, -1.0], [5.0, 0.0, -1.0]]))
    lv.add(np.array([[5.0, 0.0, -1.0], [5.0, 5.0, -1.0], [0.0, 5.0, -1.0]]))  # continues
    lv.add(np.array([[20.0, 0.0, -1.0], [25.0, 0.0, -1.0]]))  # a jump: a new polyline
    pls = lv.polylines()
    assert [len(p) for p in pls] == [4, 2]
    assert np.allclose(pls[0], [[0, 0], [5, 0], [5, 5], [0, 5]])


def _zigzag(passes: int, per: int, piece: float = 2.0, step: float = 0.5) -> str:
    lines = ["N1 G00 X0 Y0 Z5", "N2 G01 Z-2 F1000"]
    for p in range(passes):
        xs = [i * piece for i in range(per + 1)]
        if p % 2:
            xs = xs[::-1]
        if p:
            lines.append(f"Y{p * step:.3f}")
        lines += [f"X{x:.3f}" for x in xs[1:]]
    lines.append("G00 Z20")
    return "\n".join(lines) + "\n"


def zigzag_area(w: float, h: float, step: float, passes: int, r: float) -> float:
    """Area a disc of radius r sweeps along a zig-zag over [0, w] x [0, h] with passes ``step``
    apart (step <= r): the rectangle grown by r, less a scallop at each of the passes - 1 gaps
    between the connectors on the two sides (two circle caps of height step/2)."""
    hh = step / 2

    def prim(t):
        return (t * math.sqrt(r * r - t * t) + r * r * math.asin(t / r)) / 2

    scallop = 2 * (r * hh - prim(hh))
    return w * h + 2 * r * (w + h) + math.pi * r * r - (passes - 1) * scallop


def test_zigzag_pocket_volume(tmp_path):
    passes, per, r, tol = 41, 20, 3.0, 0.002
    w, h = per * 2.0, (passes - 1) * 0.5
    prog = tmp_path / "zz.nc"
    prog.write_text(_zigzag(passes, per))
    setup = tmp_path / "setup.toml"
    setup.write_text(f"""[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 20.0]

[stock]
shape = "box"
x = [-10.0, {w + 10}]
y = [-10.0, {h + 10}]
z = [-10.0, 0.0]

[[tool]]
number = 1
kind = "endmill"
diameter = {2 * r}
length = 20.0
""")
    res = cutsim.simulate(str(prog), str(setup), tolerance=tol)
    exact = zigzag_area(w, h, 0.5, passes, r) * 2.0
    # round outline: the four corners (one circle) and the scallops (two arcs of asin(0.25/r) each)
    round_len = 2 * math.pi * r + (passes - 1) * 2 * r * math.asin(0.25 / r)
    err = res.report["removed_volume"] - exact
    assert -mill.ARC_FRACTION * tol * round_len * 2.0 - 1e-3 <= err <= 1e-3
