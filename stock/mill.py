"""Milling sweeps: the fast 2.5D path and the hulls of tool poses for every other mill move.

A flat end mill (no corner radius) that moves at constant Z sweeps a prism: the 2D region its
circle sweeps in the XY plane, from the tip Z up to Z + flute length. That region is the
Minkowski sum of the tool-centre polyline with the disc: the polyline offset by the radius with
round joins and caps. Consecutive moves of one Z level that continue each other are joined into
one polyline (arcs arrive as chords from the kinematics, vertices on the true arc) and all
polylines of a level (per tool, per run of moves between checked moves) are offset in one Clipper
call (``buffer``): flanks exactly at distance r from the path, round joins and caps with their
vertices on the circle at a fraction of the chordal tolerance. That region is extruded once.
Every other mill move (3D lines, helices, ball and bull-nose tools) is swept by ``hull_sweep``:
hulls of runs of tool poses (merged where that is exact within the tolerance) and, for a ball-end
mill, tubes (stock/tube.py); everything is subtracted in the one batch. The milling checks
(plunges, flute length) are in stock/mill_checks.py.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import manifold3d as m3d
import numpy as np
import pyclipper

from cutsim.kinematics.paths import SpatialPath, segment_angle

from cutsim.base.specs import ToolSpec

Z_EPS = 1e-9  # mm: a move whose Z varies less than this is a constant-Z move
# Faces of the stock are split to at most this fraction of its extent before the batch subtract:
# a pocket outline with tens of thousands of vertices on one big stock face makes the boolean's
# face triangulation quadratic; on small faces it stays linear.
REFINE_FRACTION = 1.0 / 64


def is_flat(tool: ToolSpec) -> bool:
    return tool.kind == "endmill" and tool.corner_radius <= 0.0 or tool.kind == "drill" and tool.point_angle >= 180.0


def is_constant_z(path: SpatialPath) -> bool:
    z = path.points[:, 2]
    if len(z) <= 16:  # most moves: plain floats are several times cheaper than two reductions
        zl = z.tolist()
        return max(zl) - min(zl) <= Z_EPS
    return float(z.max() - z.min()) <= Z_EPS


def batchable(path: SpatialPath) -> bool:
    """A feed move the fast path sweeps exactly: flat end mill, constant Z. Asked several times per
    move by the removal; the answer is kept on the (immutable) path."""
    b = path.__dict__.get("_batchable")
    if b is None:
        b = not path.rapid and not path.tool.is_lathe_tool and is_flat(path.tool) and is_constant_z(path)
        object.__setattr__(path, "_batchable", b)  # not a field: equality and replace() ignore it
    return b


def stadiums(pts: np.ndarray, r: float, tol: float, p1: np.ndarray | None = None) -> np.ndarray:
    """Counter-clockwise polygons (n-1, m, 2) of the regions a circle of radius ``r`` sweeps along
    each straight piece of the XY polyline ``pts`` (a single point gives a disc); with ``p1`` the
    pieces are ``pts[i] -> p1[i]``."""
    pts = np.asarray(pts, dtype=float)[:, :2]
    if p1 is None:
        if len(pts) == 1:
            pts = np.vstack([pts, pts])
        p0, p1 = pts[:-1], pts[1:]
    else:
        p0, p1 = pts, np.asarray(p1, dtype=float)[:, :2]
    k = max(2, math.ceil(math.pi / segment_angle(r, tol)))
    d = p1 - p0
    th = np.arctan2(d[:, 1], d[:, 0])  # zero-length pieces: any direction, the region is the disc
    a = np.linspace(-math.pi / 2, math.pi / 2, k + 1)
    a1 = th[:, None] + a[None, :]
    a0 = a1 + math.pi
    c1 = p1[:, None, :] + r * np.stack([np.cos(a1), np.sin(a1)], axis=-1)
    c0 = p0[:, None, :] + r * np.stack([np.cos(a0), np.sin(a0)], axis=-1)
    return np.concatenate([c1, c0], axis=1)


def region(polys: list[np.ndarray]) -> m3d.CrossSection:
    """Union of counter-clockwise polygons in one Clipper call (a clockwise one would count as a
    hole under the Positive rule: the union of stadiums must have positive area)."""
    reg = m3d.CrossSection(polys, m3d.FillRule.Positive)
    if len(polys) and not reg.area() > 0:
        raise RuntimeError("internal: the stadiums of a flat end mill's moves enclose no area")
    return reg


# Round joins and caps of the offset: chords within this fraction of the tolerance. Their vertices
# lie on the circle, so each chord cuts off 2/3 of its sagitta on average: at 1/8 the region's
# area is short by at most tol/12 per mm of round outline, an eighth of what chords at the full
# tolerance leave. The flanks are exact.
ARC_FRACTION = 1.0 / 8
GRID = 1e6  # Clipper works on integers: 1 nm


def buffer(polylines: list[np.ndarray], r: float, tol: float) -> m3d.CrossSection:
    """The region a disc of radius ``r`` sweeps along the XY polylines (each (k, 2), k >= 1; one
    point is a disc): their offset by ``r`` with round joins and round end caps, unioned. Exact
    up to the round parts, whose chords deviate at most ``ARC_FRACTION`` x ``tol`` inwards."""
    if not polylines:
        return m3d.CrossSection()
    off = pyclipper.PyclipperOffset()
    off.ArcTolerance = max(1.0, ARC_FRACTION * tol * GRID)
    paths = [np.round(np.asarray(pl, dtype=float)[:, :2] * GRID).astype(np.int64) for pl in polylines]
    off.AddPaths(paths, pyclipper.JT_ROUND, pyclipper.ET_OPENROUND)
    out = off.Execute(r * GRID)
    polys = [np.asarray(p, dtype=float) / GRID for p in out if len(p) >= 3]
    reg = m3d.CrossSection(polys, m3d.FillRule.Positive) if polys else m3d.CrossSection()
    if not reg.area() > 0:
        raise RuntimeError("internal: the offset of a flat end mill's path encloses no area")
    return reg


def prism(reg: m3d.CrossSection, z0: float, z1: float) -> m3d.Manifold:
    return m3d.Manifold.extrude(reg, z1 - z0).translate((0.0, 0.0, z0))


def path_region(path: SpatialPath, tol: float) -> m3d.CrossSection:
    return buffer([path.points[:, :2]], path.tool.diameter / 2.0, tol)


def constant_z_solid(path: SpatialPath, tol: float) -> m3d.Manifold:
    """The exact prism a flat end mill sweeps on one constant-Z move."""
    z = float(path.points[0, 2])
    return prism(path_region(path, tol), z, z + path.tool.length)


JOIN_EPS = 1e-9  # mm: a move continues the polyline when it starts this close to its end


@dataclass
class Level:
    index: int  # index of the first path of the level (its place in the cut order)
    src: object  # Src of that path
    tool: ToolSpec
    z: float
    tol: float
    moves: list = field(default_factory=list)  # each move's tip polyline (k, 3), in order
    _region: m3d.CrossSection | None = None

    def add(self, pts: np.ndarray) -> None:
        self.moves.append(pts)

    def polylines(self) -> list[np.ndarray]:
        """The XY polylines of the level: a move that starts where the one before it ended (within
        JOIN_EPS) continues its polyline, so the join between them is round, as swept."""
        if not self.moves:
            return []
        lens = np.fromiter((len(m) for m in self.moves), dtype=np.int64, count=len(self.moves))
        xy = np.concatenate(self.moves)[:, :2]
        ends = np.cumsum(lens)
        starts = ends - lens
        cont = np.all(np.abs(xy[starts[1:]] - xy[ends[:-1] - 1]) <= JOIN_EPS, axis=1)
        keep = np.ones(len(xy), dtype=bool)
        keep[starts[1:][cont]] = False  # a continuing move's first point is the last one's end
        new = np.zeros(len(xy), dtype=bool)
        new[starts[1:][~cont]] = True  # a move that does not continue starts a new polyline
        cuts = np.flatnonzero(new[keep])
        return np.split(xy[keep], cuts)

    def region(self) -> m3d.CrossSection:
        if self._region is None:
            self._region = buffer(self.polylines(), self.tool.diameter / 2.0, self.tol)
        return self._region

    def solid(self) -> m3d.Manifold:
        return prism(self.region(), self.z, self.z + self.tool.length)


class MillBatch:
    """Collects fast-path moves grouped by (run, tool, Z). A run ends at every move whose
    collisions are checked (rapids, plunges): the checks compare against the cuts before them,
    so no level may span such a move."""

    def __init__(self, tol: float):
        self.tol = tol
        self.run = 0
        self._levels: dict[tuple, Level] = {}

    def take(self, i: int, path: SpatialPath) -> bool:
        if not batchable(path):
            return False
        z = float(path.points[0, 2])
        key = (self.run, path.tool.number, round(z, 9))
        lv = self._levels.get(key)
        if lv is None:
            lv = self._levels[key] = Level(i, path.src, path.tool, z, self.tol)
        lv.add(path.points)
        return True

    def cut_run(self) -> None:
        self.run += 1

    def levels(self) -> list[Level]:
        return sorted(self._levels.values(), key=lambda lv: lv.index)

    def __bool__(self) -> bool:
        return bool(self._levels)


def refined(stock: m3d.Manifold) -> m3d.Manifold:
    """The stock with its faces split (same solid) so big 2.5D outlines subtract in linear time."""
    b = stock.bounding_box()
    ext = max(b[3] - b[0], b[4] - b[1], b[5] - b[2])
    return stock.refine_to_length(ext * REFINE_FRACTION) if ext > 0 else stock


def sweep(path: SpatialPath, tol: float, cap: float, poses: list | None = None) -> list[m3d.Manifold]:
    """Solids whose union a milling tool sweeps on one move: the exact prism for a flat end mill
    at constant Z (rapids too), else the hulls of ``hull_sweep`` below the height ``cap`` (with
    ``poses``: one entry per solid appended, as ``hull_sweep`` does)."""
    if is_flat(path.tool) and is_constant_z(path):
        if poses is not None:
            poses.append(None)
        return [constant_z_solid(path, tol)]
    return hull_sweep(path.points, path.tool, tol, cap, poses)


# -- 3D moves: hulls of tool poses, merged where that is exact within the tolerance --------------
# A mill's axis is +Z and above its tip it only widens to the cylinder, so where its flutes reach
# above the stock it is "upward closed": the tool at a point removes everything the tool at any
# point straight below it would remove above that point. Hence the tool swept along a polyline
# equals the tool swept over the polyline plus everything above it, and a run of poses whose convex
# hull lies above the polyline (a valley of a raster line, any straight line cut into pieces) is
# swept exactly by ONE hull of all its poses. Where the hull dips below the polyline (a hill) the
# run is cut so the excess stays within MERGE_FRACTION of the tolerance. Fewer, larger hulls make
# the union in the batch subtract several times cheaper on CAM rasters.
MERGE_FRACTION = 0.5
MAX_RUN = 48  # poses per merged hull
CAP_MARGIN = 0.05  # mm above the stock top where tool bodies are cut off


def cap_height(stock_top: float, tol: float) -> float:
    """Height above which no tool part can meet the stock: bodies are cut off there."""
    return stock_top + max(CAP_MARGIN, 10 * tol)


def below_cap(points: np.ndarray, cap: float) -> list[np.ndarray]:
    """The pieces of the tip polyline where the tip is not above ``cap`` (a tool whose tip is
    above the stock top touches nothing); segments that cross the cap end at the crossing."""
    pts = np.asarray(points, dtype=float)
    inside = pts[:, 2] <= cap
    if inside.all():
        return [pts]
    pieces, cur = [], []
    for k in range(len(pts)):
        p = pts[k]
        if k:
            q = pts[k - 1]
            if inside[k] != inside[k - 1]:  # crossing the cap: cut at the crossing point
                t = (cap - q[2]) / (p[2] - q[2])
                x = q + t * (p - q)
                x[2] = cap
                if inside[k]:
                    cur = [x]
                else:
                    cur.append(x)
                    pieces.append(np.array(cur))
                    cur = []
        if inside[k]:
            cur.append(p)
    if len(cur):
        pieces.append(np.array(cur))
    return [pc for pc in pieces if len(pc)]


def _lower_hull_gap(t: np.ndarray, z: np.ndarray) -> float:
    """Largest height of the points (t increasing) above their lower convex hull."""
    hull = [0]
    for i in range(1, len(t)):
        while len(hull) >= 2:
            a, b = hull[-2], hull[-1]
            if (t[b] - t[a]) * (z[i] - z[a]) - (z[b] - z[a]) * (t[i] - t[a]) <= 0:
                hull.pop()
            else:
                break
        hull.append(i)
    return float(np.max(z - np.interp(t, t[hull], z[hull])))


def run_deviation(pts: np.ndarray) -> float:
    """How far the convex hull of the poses ``pts`` reaches below the polyline through them (plus
    everything above it), bounded by 2 x the largest sideways distance from the vertical plane
    through the end points + the largest height above the lower hull in that plane; infinite when
    the points do not progress monotonically along the chord."""
    c = pts[-1, :2] - pts[0, :2]
    ln = math.hypot(c[0], c[1])
    if ln < 1e-9:
        return math.inf
    u = c / ln
    d = pts[:, :2] - pts[0, :2]
    t = d @ u
    if np.any(np.diff(t) <= 1e-9):
        return math.inf
    e = d @ np.array([-u[1], u[0]])
    return 2.0 * float(np.max(np.abs(e))) + _lower_hull_gap(t, pts[:, 2])


def runs(pts: np.ndarray, tol: float, mergeable: bool) -> list[tuple[int, int]]:
    """Index ranges (i, j) of the polyline ``pts`` each swept by one hull (consecutive ranges share
    their end point): greedy, as long as ``run_deviation`` stays within MERGE_FRACTION x tol."""
    n = len(pts)
    if n == 1:
        return [(0, 0)]
    if not mergeable:
        return [(i, i + 1) for i in range(n - 1)]
    lim = MERGE_FRACTION * tol
    out, i = [], 0
    while i < n - 1:
        j = i + 1
        while j + 1 < n and j + 1 - i < MAX_RUN and run_deviation(pts[i:j + 2]) <= lim:
            j += 1
        out.append((i, j))
        i = j
    return out


def hull_sweep(points: np.ndarray, tool: ToolSpec, tol: float, cap: float,
               poses: list | None = None) -> list[m3d.Manifold]:
    """Solids whose union is the mill swept along the tip polyline ``points``, below ``cap``: for a
    ball-end mill, mitred tubes along planar stretches (stock/tube.py) closed by the tool's body at
    their ends; everything else hulls of merged runs of poses. With ``poses`` (a list) one entry per
    returned solid is appended to it: the ``Poses`` a hull is the hull of, None for a tube."""
    from . import tube
    from .tools import full_height, mill_body

    def body(p: np.ndarray, h: float | None) -> np.ndarray:
        return mill_body(tool, tol, h)[0] + p

    rc = full_height(tool)  # the corner of a mill, the point of a drill

    def plane(p: np.ndarray) -> float:
        """Where the bodies of the poses ``p`` are cut off: above the stock and above every corner
        (the tool's section there is its full circle), so the hull of the cut bodies is the cut
        hull of the whole bodies."""
        return max(cap, float(p[:, 2].max()) + rc)

    out, keys = [], []
    for pts in below_cap(points, cap):
        h = cap - pts[:, 2]  # a single body needs no more than this
        closed = bool(np.all(pts[:, 2] + tool.length >= plane(pts)))  # flutes reach it at every pose
        pieces, ends = [], set()
        start = 0
        if closed and tube.is_ball(tool) and len(pts) > tube.TUBE_MIN_SEGMENTS:
            z_top = max(cap, float(pts[:, 2].max()) + tool.diameter / 2.0 + 1e-3)
            for i, j in tube.stretches(pts, tool, tol, z_top):
                # each tube's own top (no higher than the one checked): no coplanar tops to union
                own = max(cap, float(pts[i:j + 1, 2].max()) + tool.diameter / 2.0 + 1e-3)
                out.append(tube.tube(pts[i:j + 1], tool, tol, own))
                keys.append(None)
                ends.update((i, j))
                if i > start:
                    pieces.append((start, i))
                start = j
        if start < len(pts) - 1 or not pieces and not ends:
            pieces.append((start, len(pts) - 1))
        # a tube's end needs the tool's body there unless a hull piece beside it holds that pose
        # (adding it twice would put coincident faces into the union)
        ends -= {k for piece in pieces for k in piece}
        for k in sorted(ends):
            out.append(m3d.Manifold.hull_points(body(pts[k], h[k])))
            keys.append(Poses.of(tool, tol, pts[k:k + 1], [h[k]]))
        for a, b in pieces:
            sub = pts[a:b + 1]
            for i, j in runs(sub, tol, closed):
                run = sub[i:j + 1]
                top = plane(run)
                cut = bool(np.all(run[:, 2] + tool.length >= top))
                heights = [top - p[2] if cut else None for p in run]
                vertical = len(run) > 1 and bool(np.all(run[1:, :2] == run[:-1, :2]))
                if vertical and cut:
                    # a plunge or a retract with its bodies cut off at one plane: the body at the lower
                    # pose up to that plane holds the other; the hull of both bodies (the same ring at
                    # the plane twice, an ulp apart) can come out short of the hull of its own vertices
                    low = run[int(np.argmin(run[:, 2]))]
                    cloud = body(low, top - low[2])
                else:
                    cloud = np.vstack([body(p, hp) for p, hp in zip(run, heights)])
                    if vertical:
                        cloud = np.unique(cloud, axis=0)
                out.append(m3d.Manifold.hull_points(cloud))
                keys.append(Poses.of(tool, tol, run, heights))
    kept = [k for k, s in enumerate(out) if not s.is_empty()]
    if poses is not None:
        poses.extend(keys[k] for k in kept)
    return [out[k] for k in kept]


# -- nested sweeps: a pass below another one on the same XY path ------------------------------------
# A mill's body (tools.mill_body) is a stack of similar rings about its axis whose radius never
# shrinks upwards: the body with its tip at z and cut off at t lies inside the body at the same XY
# with its tip at z' <= z cut off at t' >= t (its section at every height is no smaller), provided
# neither is cut off inside its corner (there the top section is the true circle, which may stand
# out of the other's chords). So the hull of poses P lies inside the hull of poses Q when every pose
# of P has such a pose in Q: bitwise the same XY (the same ring vertices), a tip no higher, a top no
# lower. Above the stock's top there is no stock, so a top above it counts as the stock's top.
# The passes a cycle lays at every depth step on one XY path (and their plunges and retracts) are
# such hulls: the walls of their bodies' rings coincide exactly (same XY vertices, different heights
# and triangulations), and the batch boolean cuts such a shared wall into slivers: a cycle with many
# depth steps has dozens of hulls starting at one point that share the wall of one ring edge, and
# nearly all the triangles of the batch end up in that plane. A hull inside another removes
# nothing the other does not: it is left out of the subtract (``nested``), the part is the same
# solid.
NESTED_SCAN = 64  # most candidate hulls looked at per hull (the deepest first)


@dataclass(frozen=True)
class Poses:
    """The tool poses a convex hull sweep is the hull of: the tool, the tolerance its body was built
    at and one row (x, y, tip z, top z) per pose (top: where the body is cut off)."""
    tool: ToolSpec
    tol: float
    rows: np.ndarray

    @staticmethod
    def of(tool: ToolSpec, tol: float, pts: np.ndarray, heights: list) -> "Poses":
        """The poses ``pts`` with the heights above the tip their bodies are built to (None: the
        flute length; tools._mill_cloud and _drill_body: never more than the flute length)."""
        rows = np.empty((len(pts), 4))
        rows[:, :3] = pts
        rows[:, 3] = [p[2] + (tool.length if hp is None else min(tool.length, max(0.0, hp)))
                      for p, hp in zip(pts, heights)]
        return Poses(tool, tol, rows)


def nested(poses: list, top: float) -> list[bool]:
    """For each entry of ``poses`` (a ``Poses`` or None) whether its hull lies inside the hull of
    another entry below the height ``top`` (see above: the stock's top), so leaving it out of the
    union changes nothing below it. Of hulls inside each other (the same poses) the first is kept."""
    from .tools import full_height

    bodies: dict[tuple, int] = {}  # (tool, tolerance) -> a number: only the same body holds another
    index: dict[tuple, list] = {}  # (body, x, y) -> [(tip z, top, entry)] of poses that can hold others
    mine: dict[tuple, list] = {}  # (body, x, y, entry) -> [(tip z, top)]: the same, per entry
    full, rows = [], []  # per entry: all its bodies cut off above their corner; its rows as lists
    for k, ps in enumerate(poses):
        if ps is None:
            full.append(False)
            rows.append(None)
            continue
        b = bodies.setdefault((ps.tool, ps.tol), len(bodies))
        ok = (ps.rows[:, 3] - ps.rows[:, 2] >= full_height(ps.tool) - 1e-9).tolist()
        rs = ps.rows.tolist()
        full.append(all(ok))
        rows.append((b, rs))
        for (x, y, z, t), good in zip(rs, ok):
            if good:
                index.setdefault((b, x, y), []).append((z, t, k))
                mine.setdefault((b, x, y, k), []).append((z, t))
    for lst in index.values():
        lst.sort()

    def holds(a: int, b: int) -> bool:
        """Every pose of ``b`` has a pose of ``a`` at its XY, tip no higher, top no lower (below ``top``)."""
        body, rs = rows[b]
        for x, y, z, t in rs:
            t = min(t, top)
            if not any(zq <= z and tq >= t for zq, tq in mine.get((body, x, y, a), ())):
                return False
        return True

    out = [False] * len(poses)
    for b, ps in enumerate(poses):
        if not full[b]:
            continue
        body, rs = rows[b]
        x, y, z, t = rs[0]
        t = min(t, top)
        seen = set()
        for zq, tq, a in index.get((body, x, y), ())[:NESTED_SCAN]:
            if zq > z:
                break
            if a == b or a in seen or tq < t:
                continue
            seen.add(a)
            if holds(a, b) and (a < b or not full[a] or not holds(b, a)):
                out[b] = True
                break
    return out


class Chain:
    """Consecutive 3D feed moves of one tool that continue each other: their tip polylines are
    joined so ``hull_sweep`` can merge poses across move boundaries (a CAM raster is thousands of
    one-segment moves)."""

    def __init__(self):
        self.index = -1
        self.src = None
        self.tool: ToolSpec | None = None
        self.parts: list[np.ndarray] = []

    def continues(self, path: SpatialPath) -> bool:
        return (bool(self.parts) and path.tool == self.tool and
                bool(np.all(np.abs(self.parts[-1][-1] - path.points[0]) <= 1e-9)))

    def add(self, i: int, path: SpatialPath) -> None:
        if not self.parts:
            self.index, self.src, self.tool = i, path.src, path.tool
            self.parts.append(path.points)
        else:
            self.parts.append(path.points[1:])

    def take(self, tol: float) -> list[np.ndarray]:
        """The chain's tip polyline in pieces (each starts where the last ended), to be swept by
        ``hull_sweep`` one after the other: a long CAM program is then never all in memory as
        solids at once. A piece has at most CHAIN_POINTS poses, fewer for tools whose hulls are
        big (about PIECE_VERTICES body vertices per piece). The chain is empty afterwards."""
        from . import tube
        from .tools import mill_body

        pts = np.concatenate(self.parts)
        self.parts = []
        size = CHAIN_POINTS
        if not tube.is_ball(self.tool):  # a ball-end mill sweeps tubes (the same test as the estimate's)
            size = int(min(CHAIN_POINTS, max(50, PIECE_VERTICES // len(mill_body(self.tool, tol)[0]))))
        return [pts[i:i + size] for i in range(0, max(1, len(pts) - 1), size - 1)]


CHAIN_POINTS = 2001  # poses per piece of a chain swept at once
PIECE_VERTICES = 500_000  # tool-body vertices per piece (hulls of ~2 triangles per vertex)
