"""The part as a mesh that stays closed when it is read back by position, and its files.

manifold3d keeps its solids closed by *index*: two distinct vertices may lie 1e-9 mm apart (the
ends of a sliver the booleans left) or at the very same point (two sheets touching along an edge).
Every reader of an STL (float32 triangle soup), 3MF or GLB merges vertices by position, and then
such pairs become one vertex and edges shared by 4 or more faces: the file leaks although the solid
did not. ``closed_mesh`` makes the positions as distinct as the indices:

1. Snap: every coordinate is rounded to a grid of step ``h`` (``grid_step``): the float32 spacing
   at the part's largest coordinate, and at least 2**-16 mm, so the values are exact in float32
   (STL, GLB) and two distinct grid points stay distinct in metres at trimesh's merge precision
   (1e-8). Vertices closer than the grid now share a grid point.
2. Collapse: an edge whose two ends share a grid point is collapsed (its two triangles, now
   without area, are removed and one end takes the other's place) when the link condition holds,
   i.e. when the ends have no common neighbour besides the two opposite corners: the surface stays
   a closed 2-manifold, and since both ends are at the same point no other triangle changes shape.
3. Separate: vertices that still share a grid point with another one (sheets of the solid that
   touch along an edge or at a corner, or an edge the link condition kept) are moved to the
   nearest free grid point, the first one towards their own neighbours, so the sheets part by a
   grid step instead of overlapping.
4. Check: the result is checked the way a reader sees it (``closed_by_position``: merged by
   position, every edge has exactly two faces of opposite direction, no triangle loses a corner,
   positive volume). Distinct positions make it pass by construction, since the Manifold is closed
   by index; a mesh that fails all the same raises LeakyMeshError: a leaky file is never written.

manifold3d's own ``Manifold.simplify(eps)`` is not used: it collapses edges shorter than its
internal epsilon without any geometric check, and on a 1e-10 mm film (a pocket floor 1e-10 above
the stock bottom) it folds a wall into a triangle across the pocket, changing the volume by
3.3 mm^3 (tests/reports/test_export.py keeps that case).

Volume bound: every vertex moves by at most ``displacement`` D = sqrt(3)/2 h (the snap) plus
sqrt(3) h per grid ring of a separation; the collapse moves nothing. The volume swept by a
surface whose vertices move linearly by at most D is at most D times its largest area on the way,
so the written solid's volume differs from the solid's by at most

    |V_file - V_solid| <= D * (A_solid + A_file)

(A the surface areas; the sum covers the area change along the way). At 100 mm, h = 2**-16 mm and
D = 1.3e-5 mm: for a 70 x 100 mm thread part (A = 3.8e4 mm^2) the bound is 1 mm^3, the measured
change about 0.01 mm^3.

Everything here is deterministic (sorted keys, lowest index first, no randomness), so the same
solid gives the same bytes.
"""
from __future__ import annotations

import io
import json
import math
import struct
import zipfile
from dataclasses import dataclass

import numpy as np

MIN_GRID = 2.0 ** -16  # mm: 1.5e-5, so grid points stay 1.5e-8 m apart in a GLB (trimesh merges at 1e-8)


class LeakyMeshError(RuntimeError):
    """The part could not be written as a mesh closed by position (a bug in cutsim)."""


@dataclass(frozen=True)
class ClosedMesh:
    vertices: np.ndarray  # (n, 3) float64, on the grid, exact in float32, mm
    faces: np.ndarray  # (m, 3) int64, counter-clockwise seen from outside
    grid: float  # the grid step h (mm)
    collapsed: int  # edges collapsed (two triangles fewer each)
    separated: int  # vertices moved apart from another at the same grid point
    displacement: float  # D: how far any vertex moved (bound, mm)

    def volume(self) -> float:
        return signed_volume(self.vertices, self.faces)

    def area(self) -> float:
        return surface_area(self.vertices, self.faces)

    def volume_bound(self, solid_area: float) -> float:
        """|volume() - V_solid| <= this for a solid of surface area ``solid_area`` (module doc)."""
        return self.displacement * (solid_area + self.area())


def grid_step(max_abs: float) -> float:
    """The snap grid for a part whose coordinates are at most ``max_abs`` in magnitude: a power of
    two, at least the float32 spacing at ``max_abs`` (so multiples of it up to ``max_abs`` are
    exact in float32) and at least MIN_GRID."""
    if not (max_abs > 0 and math.isfinite(max_abs)):
        return MIN_GRID
    e = math.frexp(max_abs)[1]  # max_abs < 2**e
    return max(math.ldexp(1.0, e - 23), MIN_GRID)


def signed_volume(v: np.ndarray, f: np.ndarray) -> float:
    if len(f) == 0:
        return 0.0
    t = v[f]
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)


def surface_area(v: np.ndarray, f: np.ndarray) -> float:
    if len(f) == 0:
        return 0.0
    t = v[f]
    return float(np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum() / 2.0)


def closed_by_position(v: np.ndarray, f: np.ndarray, distinct: bool = False) -> str | None:
    """None if the mesh, read back by position, is a closed oriented surface of positive volume;
    else what is wrong. Positions are compared as a reader compares them: float32 values (STL)
    and trimesh's merge (coordinates rounded to 1e-8 of the unit) in mm and in metres (GLB).

    ``distinct``: the caller has found the vertices at pairwise distinct points of a grid of step
    at least MIN_GRID (``closed_mesh``: one sort of the integer grid coordinates). Then no reader
    can merge two: two of them differ by at least one step in some coordinate, exactly in float32,
    and by at least MIN_GRID x 1e5 > 1 unit where trimesh rounds (metres at 1e-8, the finer of its
    two merges), so the three sorts by position are skipped."""
    if len(f) == 0:
        return "no triangles"
    if f.min() < 0 or f.max() >= len(v) or not np.all(np.bincount(f.reshape(-1), minlength=len(v))):
        return "faces do not use every vertex exactly"
    if not np.array_equal(v.astype(np.float32).astype(np.float64), v):
        return "coordinates not exact in float32"
    if not distinct:
        for scale in (None, 1e8, 1e5):  # exact (float32), trimesh's merge in mm and in metres
            key = v if scale is None else np.round(v * scale)
            k = key[np.lexsort(key.T)]
            shared = int(np.all(k[1:] == k[:-1], axis=1).sum())
            if shared:
                return f"{shared} vertices share a position with another"
    # every position is a distinct vertex from here on: indices stand for positions
    if np.any((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])):
        return "a triangle has two corners at one position"
    n = len(v)
    a = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    b = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    # one sort of the undirected edges, the direction in the lowest bit: a closed oriented surface
    # has every edge exactly once each way, i.e. the sorted keys come in pairs (2 e, 2 e + 1)
    key = np.sort((np.minimum(a, b) * n + np.maximum(a, b)) * 2 + (a > b))
    lo, hi = key[0::2], key[1::2]
    if len(lo) != len(hi) or np.any(lo >> 1 != hi >> 1) or np.any(lo[1:] >> 1 == lo[:-1] >> 1) \
            or np.any(lo & 1) or not np.all(hi & 1):
        if np.any(key[1:] == key[:-1]):
            return "an edge is used twice in one direction (more than two faces or inconsistent winding)"
        return "an edge has only one face (a hole)"
    if not signed_volume(v, f) > 0:
        return "the volume is not positive"
    return None


def _shared_points(q: np.ndarray) -> list[np.ndarray]:
    """Groups (ascending vertex indices, groups in grid order) of vertices sharing a grid point."""
    order = np.lexsort(q.T[::-1])
    s = q[order]
    same = np.all(s[1:] == s[:-1], axis=1)
    if not same.any():
        return []
    starts = np.nonzero(np.concatenate([[True], ~same]))[0]
    ends = np.concatenate([starts[1:], [len(q)]])
    return [np.sort(order[a:b]) for a, b in zip(starts, ends) if b - a > 1]


class _Faces:
    """Vertex -> faces for the few vertices a collapse touches (built on demand from a CSR)."""

    def __init__(self, f: np.ndarray):
        self.f = f
        flat = f.reshape(-1)
        by_vertex = np.argsort(flat, kind="stable")
        self.order = by_vertex // 3
        self.start = np.searchsorted(flat[by_vertex], np.arange(int(flat.max()) + 2))
        self.cache: dict[int, set[int]] = {}

    def of(self, vert: int) -> set[int]:
        s = self.cache.get(vert)
        if s is None:
            s = self.cache[vert] = set(self.order[self.start[vert]:self.start[vert + 1]].tolist())
        return s

    def neighbours(self, vert: int) -> set[int]:
        return {int(x) for t in self.of(vert) for x in self.f[t]} - {vert}


def _collapse(q: np.ndarray, f: np.ndarray, groups: list[np.ndarray] | None = None
              ) -> tuple[np.ndarray, np.ndarray, int]:
    """Collapse the edges whose ends share a grid point (module doc, step 2; ``groups``: those
    points' ``_shared_points(q)`` when known). Returns the grid coordinates and faces of the
    result (unused vertices dropped, order kept) and the count."""
    groups = _shared_points(q) if groups is None else groups
    if not groups:
        return q, f, 0
    f = f.copy()
    faces = _Faces(f)
    dead_face = np.zeros(len(f), dtype=bool)
    dead_vert = np.zeros(len(q), dtype=bool)
    count = 0
    for group in groups:
        members = group.tolist()
        member_set = set(members)
        changed = True
        while changed:  # a collapse can make two other members adjacent
            changed = False
            for a in members:
                if dead_vert[a]:
                    continue
                for b in sorted(faces.neighbours(a) & member_set):
                    if b < a or dead_vert[a] or dead_vert[b]:
                        continue
                    shared = faces.of(a) & faces.of(b)
                    if len(shared) != 2:
                        continue  # not an edge (or a non-manifold one: left to the separation)
                    t0, t1 = sorted(shared)
                    c = next(int(x) for x in f[t0] if x != a and x != b)
                    d = next(int(x) for x in f[t1] if x != a and x != b)
                    if c == d or faces.neighbours(a) & faces.neighbours(b) != {c, d}:
                        continue  # link condition: the collapse would pinch the surface
                    acd = any(c in f[t] and d in f[t] for t in faces.of(a))
                    bcd = any(c in f[t] and d in f[t] for t in faces.of(b))
                    if acd and bcd:
                        continue  # a tetrahedron-like cap would flatten to a double face
                    dead_face[[t0, t1]] = True
                    for t in (t0, t1):
                        for x in f[t]:
                            faces.of(int(x)).discard(t)
                    for t in sorted(faces.of(b)):
                        f[t][f[t] == b] = a
                        faces.of(a).add(t)
                    faces.cache[b] = set()
                    dead_vert[b] = True
                    count += 1
                    changed = True
    f = f[~dead_face]
    keep = ~dead_vert
    new_index = np.cumsum(keep) - 1
    return q[keep], new_index[f], count


def _separate(q: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, int, int]:
    """Move every vertex that shares a grid point with a lower-numbered one to the nearest free
    grid point (rings of growing Chebyshev radius), within a ring the one most in the direction
    of its own neighbours. Returns the grid coordinates, the vertices moved and the largest ring."""
    groups = _shared_points(q)
    movers = [int(i) for g in groups for i in g[1:]]
    if not movers:
        return q, 0, 0
    q = q.copy()
    faces = _Faces(f)
    occupied = set(map(tuple, q.tolist()))
    worst = 0
    for i in sorted(movers):
        nb = sorted(faces.neighbours(i))
        d = q[nb].mean(axis=0) - q[i] if nb else np.zeros(3)
        ln = float(np.linalg.norm(d))
        d = d / ln if ln > 0 else np.array([1.0, 0.0, 0.0])
        for r in range(1, 1 << 10):
            rng = np.arange(-r, r + 1)
            offs = np.stack(np.meshgrid(rng, rng, rng, indexing="ij"), axis=-1).reshape(-1, 3)
            offs = offs[np.abs(offs).max(axis=1) == r]
            score = np.round(offs @ d / np.linalg.norm(offs, axis=1), 12)
            order = np.lexsort((offs[:, 2], offs[:, 1], offs[:, 0], -score))
            spot = next((s for s in (tuple((q[i] + offs[k]).tolist()) for k in order) if s not in occupied), None)
            if spot is not None:
                occupied.add(spot)
                q[i] = spot
                worst = max(worst, r)
                break
    return q, len(movers), worst


def closed_mesh(part) -> ClosedMesh:
    """The part (a manifold3d.Manifold) as a mesh closed by position (module doc)."""
    from cutsim.stock.arrays import solid_arrays

    v, f = solid_arrays(part, exact=True)
    if len(f) == 0:
        return ClosedMesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), MIN_GRID, 0, 0, 0.0)
    h = grid_step(float(np.abs(v).max()))
    q = np.round(v / h).astype(np.int64)
    groups = _shared_points(q)
    collapsed = separated = rings = 0
    if groups:  # most parts: none, and nothing to collapse or separate
        q, f, collapsed = _collapse(q, f, groups)
        q, separated, rings = _separate(q, f)
    out = q.astype(np.float64) * h
    # no vertex moved by the separation: _shared_points found the grid points distinct (module doc, 4)
    why = closed_by_position(out, f, distinct=separated == 0)
    if why is not None:
        raise LeakyMeshError(f"the part cannot be written as a closed mesh: {why}")
    return ClosedMesh(out, f, h, collapsed, separated, math.sqrt(3.0) * h * (0.5 + rings))


# ---- files -----------------------------------------------------------------------------------

def stl_bytes(verts: np.ndarray, faces: np.ndarray) -> bytes:
    """Binary STL with unit normals, little-endian, zero header: same mesh, same bytes."""
    tri = verts[faces].astype(np.float64)
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(nrm, axis=1, keepdims=True)
    nrm = np.divide(nrm, ln, out=np.zeros_like(nrm), where=ln > 0)
    rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = nrm
    rec["v"] = tri
    header = b"cutsim binary STL".ljust(80, b"\0")
    return header + np.uint32(len(faces)).astype("<u4").tobytes() + rec.tobytes()


def threemf_bytes(verts: np.ndarray, faces: np.ndarray) -> bytes:
    """A minimal 3MF package (core spec: one mesh object, unit millimetre), written without lxml.
    Coordinates are written as the shortest decimal that reads back as the same double, so the
    file holds exactly the checked positions; zip entries carry a fixed date so the bytes depend
    only on the mesh."""
    v = "".join(f'<vertex x="{x!r}" y="{y!r}" z="{z!r}"/>'
                for x, y, z in np.asarray(verts, dtype=np.float64).tolist())
    t = "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in np.asarray(faces, dtype=np.int64).tolist())
    model = ('<?xml version="1.0" encoding="UTF-8"?>\n'
             '<model unit="millimeter" xml:lang="en-US" '
             'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">'
             '<resources><object id="1" type="model" name="part"><mesh>'
             f"<vertices>{v}</vertices><triangles>{t}</triangles></mesh></object></resources>"
             '<build><item objectid="1"/></build></model>\n')
    types = ('<?xml version="1.0" encoding="UTF-8"?>\n'
             '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
             '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
             '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
             "</Types>\n")
    rels = ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
            'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for name, text in (("[Content_Types].xml", types), ("_rels/.rels", rels), ("3D/3dmodel.model", model)):
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            z.writestr(info, text.encode("utf-8"))
    return buf.getvalue()


def glb_bytes(verts: np.ndarray, faces: np.ndarray) -> bytes:
    """Binary glTF 2.0: one mesh (float32 positions in mm, uint32 indices, no normals: viewers
    shade flat) under one node scaled by 0.001, so the scene is in metres as glTF requires while
    the stored positions are exactly the checked ones. Fixed JSON key order: same mesh, same bytes."""
    pos = np.ascontiguousarray(verts, dtype="<f4")
    idx = np.ascontiguousarray(faces, dtype="<u4")
    pos_b, idx_b = pos.tobytes(), idx.tobytes()  # both multiples of 4 bytes
    lo = pos.min(axis=0).tolist() if len(pos) else [0.0, 0.0, 0.0]
    hi = pos.max(axis=0).tolist() if len(pos) else [0.0, 0.0, 0.0]
    doc = {
        "asset": {"version": "2.0", "generator": "cutsim"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "part", "mesh": 0, "scale": [0.001, 0.001, 0.001]}],
        "meshes": [{"name": "part", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": idx.size, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos_b), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos_b), "byteLength": len(idx_b), "target": 34963},
        ],
        "buffers": [{"byteLength": len(pos_b) + len(idx_b)}],
    }
    if len(idx) == 0:  # nothing left of the part: an empty node (glTF forbids empty accessors and buffers)
        doc = {k: doc[k] for k in ("asset", "scene", "scenes", "nodes")}
        doc["nodes"] = [{"name": "part", "scale": [0.001, 0.001, 0.001]}]
    js = json.dumps(doc, separators=(",", ":"), allow_nan=False).encode("utf-8")
    js += b" " * (-len(js) % 4)
    binary = pos_b + idx_b
    chunks = struct.pack("<I4s", len(js), b"JSON") + js
    if binary:
        chunks += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


FORMATS = ("stl", "3mf", "glb")


def part_bytes(verts: np.ndarray, faces: np.ndarray, fmt: str = "stl") -> bytes:
    """The part file in ``fmt``: "stl" (binary, mm), "3mf" (unit millimetre) or "glb" (metres)."""
    if fmt == "stl":
        return stl_bytes(verts, faces)
    if fmt == "3mf":
        return threemf_bytes(verts, faces)
    if fmt == "glb":
        return glb_bytes(verts, faces)
    raise ValueError(f"unknown part format {fmt!r}")
