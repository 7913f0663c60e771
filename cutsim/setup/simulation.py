"""The [simulation] table: tolerance, fail_on_warning, max_blocks, max_triangles (docs/setup.md).
Read first: the stock is checked against the tolerance and the triangle limit."""
from __future__ import annotations

from typing import NamedTuple

from cutsim.interp.core.modal import MAX_BLOCKS
from cutsim.stock.build import DEFAULT_MAX_TRIANGLES

from .limits import MAX_BLOCKS_LIMIT, MAX_TRIANGLES_RANGE, MIN_TOLERANCE
from .reader import Locator, Reader

DEFAULT_TOLERANCE = 0.002  # mm


class Simulation(NamedTuple):
    tolerance: float
    fail_on_warning: bool
    max_blocks: int
    max_triangles: int


def read_simulation(loc: Locator, table: dict | None) -> Simulation:
    """[simulation]: tolerance, fail_on_warning, max_blocks, max_triangles (read first: the
    stock is checked against the tolerance and the triangle limit)."""
    if table is None:
        return Simulation(DEFAULT_TOLERANCE, False, MAX_BLOCKS, DEFAULT_MAX_TRIANGLES)
    s = Reader(loc, table, "simulation")
    tol = s.get("tolerance", float, DEFAULT_TOLERANCE, check=lambda v: MIN_TOLERANCE <= v <= 1.0, why="must be between 0.0001 and 1 mm")
    fow = s.get("fail_on_warning", bool, False)
    max_blocks = s.get("max_blocks", int, MAX_BLOCKS, check=lambda v: 1 <= v <= MAX_BLOCKS_LIMIT,
                       why=f"must be at least 1 and at most {MAX_BLOCKS_LIMIT:,}")
    lo, hi = MAX_TRIANGLES_RANGE
    max_tri = s.get("max_triangles", int, DEFAULT_MAX_TRIANGLES, check=lambda v: lo <= v <= hi,
                    why=f"must be a whole number from {lo:,} to {hi:,}")
    s.done()
    return Simulation(tol, fow, max_blocks, max_tri)
