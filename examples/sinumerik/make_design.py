"""Write plate-design.stl, the design model of plate.mpf, with manifold3d.

The finished plate as the program's comments describe it (not as cutsim simulates it):
a 120 x 80 x 20 block with its top at Z0 (faced from Z1), minus
- a rectangular pocket 40 x 30 with corner radius 6 centred (35, 40), floor Z-6 (POCKET1),
- a round pocket of radius 12 centred (90, 40), floor Z-8 (POCKET2),
- a slot 6 wide with round ends from (20, 12) to (100, 12), floor Z-3 (6 mm end mill).

Run it from anywhere: ``python3 examples/sinumerik/make_design.py``. The output is
byte-for-byte the same on every run (fixed segment counts, binary STL without a timestamp).
"""
from __future__ import annotations

import math
import struct
import sys
from pathlib import Path

import manifold3d as m3d
import numpy as np

HERE = Path(__file__).resolve().parent
SEGMENTS = 240          # per full circle: chord error 12 * (1 - cos(0.75 deg)) = 0.001 mm at the round pocket


def _arc(cx: float, cy: float, r: float, a0: float, a1: float) -> list[tuple[float, float]]:
    n = max(2, round(SEGMENTS * (a1 - a0) / 360.0))
    return [(cx + r * math.cos(math.radians(a0 + (a1 - a0) * i / n)),
             cy + r * math.sin(math.radians(a0 + (a1 - a0) * i / n))) for i in range(n + 1)]


def _prism(outline: list[tuple[float, float]], z0: float, z1: float) -> m3d.Manifold:
    cs = m3d.CrossSection([outline])
    return m3d.Manifold.extrude(cs, z1 - z0).translate((0.0, 0.0, z0))


def rounded_rectangle(cx, cy, length, width, r):
    hx, hy = length / 2 - r, width / 2 - r
    pts = (_arc(cx + hx, cy - hy, r, -90, 0) + _arc(cx + hx, cy + hy, r, 0, 90)
           + _arc(cx - hx, cy + hy, r, 90, 180) + _arc(cx - hx, cy - hy, r, 180, 270))
    return pts


def stadium(x0, x1, y, r):
    return _arc(x1, y, r, -90, 90) + _arc(x0, y, r, 90, 270)


def design() -> m3d.Manifold:
    above = 1.0     # cutters reach above the top so the faces do not coincide
    plate = m3d.Manifold.cube((120.0, 80.0, 20.0)).translate((0.0, 0.0, -20.0))
    pocket = _prism(rounded_rectangle(35.0, 40.0, 40.0, 30.0, 6.0), -6.0, above)
    round_pocket = _prism(_arc(90.0, 40.0, 12.0, 0, 360)[:-1], -8.0, above)
    slot = _prism(stadium(20.0, 100.0, 12.0, 3.0), -3.0, above)
    return plate - pocket - round_pocket - slot


def stl_bytes(solid: m3d.Manifold, title: str = "plate-design.stl: make_design.py (manifold3d)") -> bytes:
    """Binary STL of ``solid``, ``title`` in its 80-byte header (no timestamp: the same bytes every run)."""
    mesh = solid.to_mesh()
    v = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    tri = np.asarray(mesh.tri_verts, dtype=np.int64)
    a, b, c = v[tri[:, 0]], v[tri[:, 1]], v[tri[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    rec = np.zeros(len(tri), dtype=[("n", "<f4", 3), ("v", "<f4", 9), ("attr", "<u2")])
    rec["n"] = n
    rec["v"] = np.hstack([a, b, c])
    header = title.encode("ascii").ljust(80, b" ")
    return header + struct.pack("<I", len(tri)) + rec.tobytes()


def main(argv: list[str]) -> int:
    out = Path(argv[1]) if len(argv) > 1 else HERE / "plate-design.stl"
    out.write_bytes(stl_bytes(design()))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
