"""The triangle budget of one removal: how much geometry it may hold at once.

Before anything is swept, every path's strategy counts the triangles its sweep will need
(``Strategy.estimate``, stock/strategy.py) into one ``Work``; more than ``[simulation]
max_triangles`` is refused at the line of the move that goes over it, before memory runs out.
While the checks run, the solids of lazily swept cuts that several checks ask for are kept in a
bounded cache (``Built``), and the batch subtract takes the cuts in batches of about
CHUNK_TRIANGLES.
"""
from __future__ import annotations

from cutsim.interp.errors import CutsimError

from .cuts import Cut, bbox

# Measured peak memory per counted triangle: about 600 bytes for a screw sweep built and
# subtracted from a bar (extrude + warp of 4M triangles: 2.3 GB), 650 for a thread whose turns
# overlap 6 deep (3.4M counted: 2.19 GB), 400 for one 11 deep (10.9M counted: 4.2 GB). Used for
# the message only.
BYTES_PER_TRIANGLE = 600

CHUNK_TRIANGLES = 1_000_000  # triangles of sweeps subtracted in one batch
BUILT_TRIANGLES = 1_000_000  # triangles of lazily swept cuts kept between checks


class Work:
    """The triangles of the solids a run holds at once (the stock, every sweep kept for the batch
    subtract, the largest piece of lazily swept mill moves), counted before anything is swept,
    path by path with the same strategy the sweep will use. More than ``limit`` is a CutsimError
    at the line of the move that goes over it."""

    def __init__(self, limit: int, stock_triangles: int):
        self.limit = int(limit)
        self.held = int(stock_triangles)

    def add(self, tris: int, src, what: str) -> None:
        self.held += int(tris)
        if self.held > self.limit:
            raise CutsimError(src.program, src.line, src.col, self.message(int(tris), what))

    def room(self) -> int:
        """Triangles that may still be added."""
        return self.limit - self.held

    def message(self, tris: int, what: str) -> str:
        gb = self.held * BYTES_PER_TRIANGLE / 1e9
        return (f"too much geometry: the sweeps would need about {self.held:,} triangles at once "
                f"({what}: about {tris:,}), more than [simulation] max_triangles = {self.limit:,}; this would take "
                f"about {gb:.1f} GB of memory: raise max_triangles in the setup or use a coarser tolerance")


class Built:
    """The solids of lazily swept cuts (3D mill chain pieces) with their boxes, kept across the
    checks that ask for them again, the least recently used dropped beyond ``limit`` triangles."""

    def __init__(self, limit: int):
        self.limit = limit
        self.held = 0
        self.solids: dict[int, tuple[Cut, list, int]] = {}  # id(cut) -> (cut, [(solid, lo, hi)], triangles)

    def get(self, cut: Cut) -> list:
        got = self.solids.pop(id(cut), None)
        if got is None:
            sols = [(s, *bbox([s])) for s in cut.get()]
            got = (cut, sols, sum(s.num_tri() for s, _, _ in sols))
            self.held += got[2]
        self.solids[id(cut)] = got  # the newest at the end
        while self.held > self.limit and len(self.solids) > 1:
            old = next(iter(self.solids))
            self.held -= self.solids.pop(old)[2]
        return got[1]

    def take(self, cut: Cut) -> list:
        """The solids of ``cut`` for the subtract, built ones handed over (and no longer kept)."""
        got = self.solids.pop(id(cut), None)
        if got is None:
            return cut.get()
        self.held -= got[2]
        return [s for s, _, _ in got[1]]
