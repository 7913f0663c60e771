"""The cuts of one removal and the frame they are made in.

A ``Cut`` is what one path (or a group of joined paths) takes away: its solids, or a 2D region
to revolve with the other turning moves, or a recipe that builds its solids when they are needed,
with its bounding box and its place in program order. The ``Frame`` is where the stock is: the
cuts are clipped to it and tested against it before anything else is done with them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import manifold3d as m3d
import numpy as np

from cutsim.base.specs import StockSpec
from cutsim.kinematics.paths import circle_segments

from .build import stock_outline


@dataclass
class Cut:
    index: int
    solids: list  # Manifolds (screw, spatial) ...
    region: m3d.CrossSection | None  # ... or a 2D region to revolve
    lo: np.ndarray
    hi: np.ndarray
    near: Callable[[float, float], list] | None = None  # the solids restricted to heights z0..z1
    build: Callable[[], list] | None = None  # solids built when needed, not kept (long mill chains)
    keys: list | None = None  # per solid its mill.Poses (a hull of tool poses) or None, as last built

    def get(self) -> list:
        return self.build() if self.build is not None else self.solids


def bbox(solids: list[m3d.Manifold]):
    los, his = [], []
    for s in solids:
        b = s.bounding_box()
        los.append(b[:3])
        his.append(b[3:])
    return np.min(los, axis=0), np.max(his, axis=0)


def overlap(lo1, hi1, lo2, hi2) -> bool:
    return bool(np.all(lo1 <= hi2) and np.all(lo2 <= hi1))


def box_overlap(lo1, hi1, lo2, hi2) -> float:
    """Volume of the intersection of two boxes."""
    return float(np.prod(np.maximum(np.minimum(hi1, hi2) - np.maximum(lo1, lo2), 0.0)))


@dataclass
class Frame:
    """Where the stock is: its box, the radius a lathe profile is clipped at (the stock's largest
    radius plus a margin), its outline of revolution (None for a box or a mesh) and the segment
    count of its circles, so revolved cuts line up with the stock's faces."""
    lo: np.ndarray
    hi: np.ndarray
    r_clip: float
    margin: float
    outline: np.ndarray | None
    outline_cs: m3d.CrossSection | None
    nseg: int

    @property
    def top(self) -> float:
        return float(self.hi[2])

    def meets(self, lo, hi) -> bool:
        return overlap(lo, hi, self.lo, self.hi)

    def clip_keyed(self, solids: list[m3d.Manifold], keys: list) -> tuple[list[m3d.Manifold], list]:
        """``clip`` with a key per solid kept beside it (a clipped hull still lies inside any hull
        its whole lay in, up to what lies beyond the box, where there is no stock)."""
        out, kept = [], []
        for s, k in zip(solids, keys):
            c = self.clip([s])
            if c:
                out.append(c[0])
                kept.append(k)
        return out, kept

    def clip(self, solids: list[m3d.Manifold]) -> list[m3d.Manifold]:
        """``solids`` cut off by the planes of the stock's box (plus the margin) they reach beyond by
        more than the box's own size: the stock lies inside the box, so what it loses, and what a
        check finds, are unchanged. A tool far bigger than the stock then keeps only the few faces
        over the stock instead of hulls many times the stock's size."""
        lo, hi = self.lo - self.margin, self.hi + self.margin
        reach = CLIP_REACH * float(np.max(hi - lo))
        out = []
        for s in solids:
            b = s.bounding_box()
            for ax in range(3):
                if b[ax] < lo[ax] - reach:
                    s = s.trim_by_plane(tuple(float(k == ax) for k in range(3)), float(lo[ax]))
                if b[ax + 3] > hi[ax] + reach:
                    s = s.trim_by_plane(tuple(-float(k == ax) for k in range(3)), -float(hi[ax]))
            if not s.is_empty():
                out.append(s)
        return out

    def revolve(self, region: m3d.CrossSection) -> m3d.Manifold:
        return m3d.Manifold.revolve(region, circular_segments=self.nseg)


CLIP_REACH = 1.0  # sweeps reaching beyond the stock's box by more than this many times its size are cut off


def frame_of(stock: m3d.Manifold, spec: StockSpec, tol: float) -> Frame:
    sb = stock.bounding_box()
    slo, shi = np.array(sb[:3]), np.array(sb[3:])
    rmax = float(max(np.hypot(slo[0], slo[1]), np.hypot(shi[0], shi[1]), np.hypot(slo[0], shi[1]),
                     np.hypot(shi[0], slo[1])))
    margin = max(10 * tol, 0.05)
    outline = stock_outline(spec)
    # revolve cuts with the stock's own segment count (its true radius, not the bounding box's
    # corner): the faces of cut and stock then line up instead of crossing at every segment
    nseg = circle_segments(float(outline[:, 0].max()) if outline is not None else rmax, tol)
    outline_cs = m3d.CrossSection([outline], m3d.FillRule.Positive) if outline is not None else None
    return Frame(slo, shi, rmax + margin, margin, outline, outline_cs, nseg)
