"""The initial stock as a manifold, discretised by the one chordal tolerance."""
from __future__ import annotations

import manifold3d as m3d
import numpy as np

from cutsim.interp.errors import CutsimError
from cutsim.kinematics.paths import circle_segments

from .specs import StockSpec


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


def build_stock(spec: StockSpec, tol: float, setup_path: str = "") -> m3d.Manifold:
    outline = stock_outline(spec)
    if outline is not None:
        rmax = float(outline[:, 0].max())
        cs = m3d.CrossSection([outline], m3d.FillRule.Positive)
        return m3d.Manifold.revolve(cs, circular_segments=circle_segments(rmax, tol))
    if spec.shape == "box":
        lo = np.array([spec.x[0], spec.y[0], spec.z[0]])
        hi = np.array([spec.x[1], spec.y[1], spec.z[1]])
        return m3d.Manifold.cube(hi - lo).translate(lo)
    return load_mesh_stock(spec.path, setup_path)


def load_mesh_stock(path: str, setup_path: str = "") -> m3d.Manifold:
    import trimesh

    where = setup_path or path
    try:
        mesh = trimesh.load(path, force="mesh", process=True)
    except Exception as e:  # trimesh raises many types for unreadable files
        raise CutsimError(where, 0, 0, f"cannot read the stock mesh {path}: {e}") from None
    if not mesh.is_watertight or not mesh.is_volume:
        raise CutsimError(where, 0, 0, f"the stock mesh {path} is not a closed solid")
    solid = m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                  tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))
    if solid.status() != m3d.Error.NoError or solid.is_empty():
        raise CutsimError(where, 0, 0, f"the stock mesh {path} is not a valid 2-manifold ({solid.status().name})")
    return solid
