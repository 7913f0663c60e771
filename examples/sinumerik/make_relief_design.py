"""Write relief-shaft-design.stl, the design model of relief-shaft.mpf, with manifold3d.

The finished shaft as the program's contour describes it (not as cutsim simulates it): the
region between the axis and the radii 10 (Z0..-10), the flank to 8 at Z-16, the floor 8 to
Z-22, the flank to 13 at Z-28, the collar 13 to Z-35, then the bar's 15 to its end at Z-45,
revolved about Z. It is revolved with 88 segments, the ones cutsim revolves the bar of 30 with
at the setup's tolerance 0.01 (the chord of 360/88 degrees at radius 15 deviates 0.0087 mm), so
the part's facets and the design's lie on the same planes.

Run it from anywhere: ``python3 examples/sinumerik/make_relief_design.py``. The output is
byte-for-byte the same on every run (binary STL without a timestamp).
"""
from __future__ import annotations

import sys
from pathlib import Path

import manifold3d as m3d

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import make_design  # noqa: E402  (the plate's binary STL writer)
SEGMENTS = 88
OUTLINE = [(0, 0), (10, 0), (10, -10), (8, -16), (8, -22), (13, -28), (13, -35), (15, -35), (15, -45), (0, -45)]


def design() -> m3d.Manifold:
    region = m3d.CrossSection([[(float(r), float(z)) for r, z in OUTLINE[::-1]]])  # counter-clockwise
    return m3d.Manifold.revolve(region, circular_segments=SEGMENTS)


def stl_bytes(solid: m3d.Manifold) -> bytes:
    return make_design.stl_bytes(solid, "relief-shaft-design.stl: make_relief_design.py (manifold3d)")


def main(argv: list[str]) -> int:
    out = Path(argv[1]) if len(argv) > 1 else HERE / "relief-shaft-design.stl"
    out.write_bytes(stl_bytes(design()))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
