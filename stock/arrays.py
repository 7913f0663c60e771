"""The one conversion between manifold3d solids and plain vertex and triangle arrays.

manifold3d keeps a solid's vertices in double precision; ``to_mesh`` hands them out rounded to
single precision, ``to_mesh64`` as they are. The measurements read the single-precision mesh
(their numbers are what they always were), the files a user gets are written from the exact one.
"""
from __future__ import annotations

import manifold3d as m3d
import numpy as np


def solid_arrays(solid: m3d.Manifold, exact: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3) float64, triangles (m, 3) int64) of ``solid``, both owning their data.
    ``exact``: the vertices in manifold3d's double precision (for the part files); otherwise its
    single-precision mesh widened to float64 (for measuring)."""
    m = solid.to_mesh64() if exact else solid.to_mesh()
    verts = np.array(np.asarray(m.vert_properties, dtype=np.float64)[:, :3])
    return verts, np.array(m.tri_verts, dtype=np.int64)


def solid_of(verts, faces) -> m3d.Manifold:
    """The manifold3d solid of a triangle mesh (vertices (n, 3), faces (m, 3) of vertex indices),
    its vertices in single precision as manifold3d's Mesh takes them. Its ``status()`` tells
    whether the mesh is a closed 2-manifold."""
    return m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(verts, dtype=np.float32),
                                 tri_verts=np.asarray(faces, dtype=np.uint32)))
