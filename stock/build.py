"""The initial stock as a manifold, discretised by the one chordal tolerance."""
from __future__ import annotations

import os

import manifold3d as m3d
import numpy as np

from cutsim.interp.errors import CutsimError
from cutsim.kinematics.paths import circle_segments

from cutsim.base.specs import StockSpec

from .arrays import solid_of

# The most triangles of solids a run may hold at once ([simulation] max_triangles, docs/setup.md):
# measured peak memory is 400-650 bytes per counted triangle (a thread of 3.4M counted triangles,
# lead 0.045 over 22 mm: 2.19 GB), so the default keeps a run within about 2 GB.
DEFAULT_MAX_TRIANGLES = 3_000_000


def stock_outline(spec: StockSpec) -> np.ndarray | None:
    """(r, z) outline of a stock of revolution (counter-clockwise), None for box and mesh."""
    if spec.shape == "cylinder":
        r = spec.diameter / 2
        z0, z1 = spec.z
        return np.array([[0, z0], [r, z0], [r, z1], [0, z1]], dtype=float)
    if spec.shape == "revolve":
        pts = np.array(spec.profile, dtype=float)
        area = 0.5 * np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1])
        return pts if area > 0 else pts[::-1]
    return None


def build_stock(spec: StockSpec, tol: float, setup_path: str = "", *, max_triangles: int = DEFAULT_MAX_TRIANGLES,
                where: tuple[int, int] = (0, 0)) -> m3d.Manifold:
    """The stock solid. More than ``max_triangles`` (a fine tolerance on a big stock of revolution)
    is a CutsimError at ``where`` in the setup (the key that sizes the stock)."""
    outline = stock_outline(spec)
    if outline is not None:
        rmax = float(outline[:, 0].max())
        nseg = circle_segments(rmax, tol)
        tris = 2 * len(outline) * nseg
        if tris > max_triangles:
            raise CutsimError(setup_path, *where, f"[stock] at the tolerance {tol:g} mm the stock would have about "
                                                  f"{tris:,} triangles, more than [simulation] max_triangles = "
                                                  f"{max_triangles:,}")
        cs = m3d.CrossSection([outline], m3d.FillRule.Positive)
        return m3d.Manifold.revolve(cs, circular_segments=nseg)
    if spec.shape == "box":
        lo = np.array([spec.x[0], spec.y[0], spec.z[0]])
        hi = np.array([spec.x[1], spec.y[1], spec.z[1]])
        return m3d.Manifold.cube(hi - lo).translate(lo)
    return load_mesh_stock(spec.path, setup_path, where=where, max_triangles=max_triangles)


MESH_BYTES_PER_TRIANGLE = 300  # more file than this per allowed triangle is refused before reading (ASCII STL ~250)
_MESH_CACHE: dict = {}  # the last mesh read: (path, mtime, size, limits) -> Manifold (the setup loader checks it first)


def load_mesh_stock(path: str, setup_path: str = "", *, where: tuple[int, int] = (0, 0),
                    max_triangles: int = DEFAULT_MAX_TRIANGLES, max_coord: float = 1e5,
                    min_size: float = 1e-3) -> m3d.Manifold:
    """A closed mesh file as the stock. Unreadable, empty, open, not 2-manifold, more triangles than
    ``max_triangles``, beyond ``max_coord`` or thinner than ``min_size``: a CutsimError at ``where``
    in the setup (the line of its ``path`` key)."""
    import trimesh

    file = setup_path or path

    def error(text: str) -> CutsimError:
        return CutsimError(file, *where, f"[stock] path: {text}")

    try:
        st = os.stat(path)
    except OSError as e:
        raise error(f"cannot read the stock mesh {path}: {e.strerror}") from None
    key = (path, st.st_mtime_ns, st.st_size, max_triangles, max_coord, min_size)
    if key in _MESH_CACHE:
        return _MESH_CACHE[key]
    if st.st_size == 0:
        raise error(f"the stock mesh {path} is empty")
    if st.st_size > MESH_BYTES_PER_TRIANGLE * max_triangles:
        raise error(f"the stock mesh {path} ({st.st_size:,} bytes) is too big for [simulation] max_triangles = "
                    f"{max_triangles:,}")
    try:
        mesh = trimesh.load(path, force="mesh", process=True)
        faces = np.asarray(mesh.faces)
        verts = np.asarray(mesh.vertices, dtype=float)
    except Exception as e:  # noqa: BLE001 - trimesh raises many types for unreadable files
        text = str(e) or type(e).__name__
        raise error(f"cannot read the stock mesh {path}: {text[:200]}") from None
    if len(faces) == 0 or len(verts) == 0:
        raise error(f"the stock mesh {path} has no triangles")
    if len(faces) > max_triangles:
        raise error(f"the stock mesh {path} has {len(faces):,} triangles, more than [simulation] max_triangles = "
                    f"{max_triangles:,}")
    if not np.all(np.isfinite(verts)) or np.abs(verts).max() > max_coord:
        raise error(f"the stock mesh {path} reaches beyond {max_coord:g} mm from the origin")
    if not mesh.is_watertight or not mesh.is_volume:
        raise error(f"the stock mesh {path} is not a closed solid")
    ext = verts.max(axis=0) - verts.min(axis=0)
    if ext.min() < min_size:
        raise error(f"the stock mesh {path} is thinner than {min_size:g} mm")
    solid = solid_of(verts, faces)
    if solid.status() != m3d.Error.NoError or solid.is_empty():
        raise error(f"the stock mesh {path} is not a valid 2-manifold ({solid.status().name})")
    _MESH_CACHE.clear()
    _MESH_CACHE[key] = solid
    return solid
