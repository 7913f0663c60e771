"""Sweep strategies: how each kind of path becomes cuts, and what that costs before it is built.

Every path gets one sweep kind (``removal.sweep_kind``: screw, revolve, hull, level, helix, tube,
gauge) and each kind one ``Strategy`` class that holds both halves of its work side by side:

- ``estimate``: the triangles its sweep will need, counted into the run's budget
  (stock/budget.py) over all paths in program order before anything is built;
- ``sweep``: its solids (or 2D region, or a recipe that builds them when they are subtracted),
  added to the run's cuts in program order.

The strategies of one removal share a ``Run``. Some moves are held back to be joined with the
next ones (a 3D mill chain, consecutive arcs on one helix): the strategy holding them is the run's
``pending`` one, and a path of a kind that ``ends_joins`` has them swept (or counted) first.
The strategies live in strategy_turning.py (screw, revolve), strategy_milling.py (level, helix,
tube) and strategy_checked.py (hull, gauge: moves checked against the stock as it is then).
"""
from __future__ import annotations

import manifold3d as m3d
import numpy as np

from . import mill
from .budget import Work
from .cuts import Cut, Frame, bbox


class Run:
    """What the strategies of one removal share: the stock's frame, the chordal tolerance, the
    lathe tools' profiles, the height above which no tool meets the stock (``cap``), the budget,
    the cuts in program order, the moves whose collisions are checked, the 2.5D levels (a checked
    move or a move without a tool ends them: no level may span it) and the strategy holding moves
    back for joining."""

    def __init__(self, frame: Frame, tol: float, profile, work: Work):
        self.f, self.tol, self.profile, self.work = frame, tol, profile, work
        self.cap = mill.cap_height(frame.top, tol)
        self.cuts: list[Cut] = []
        self.checks: list[tuple[Cut, object]] = []  # (the cut to check, its path)
        self.bodies: list[tuple[Cut, object]] = []  # (a tool body's region on a move, the move): checked, never cut
        self.levels = mill.MillBatch(tol)
        self.pending: Strategy | None = None

    def add_cut(self, index: int, solids: list, keys: list | None = None) -> Cut | None:
        """A cut of ``solids`` (clipped to the frame; with ``keys``: one per solid, kept beside it),
        unless nothing of it reaches the stock's box."""
        if keys is not None:
            solids, keys = self.f.clip_keyed(solids, keys)
        else:
            solids = self.f.clip(solids)
        if solids:
            lo, hi = bbox(solids)
            if self.f.meets(lo, hi):
                self.cuts.append(Cut(index, solids, None, lo, hi, keys=keys))
                return self.cuts[-1]
        return None

    def region_cut(self, i: int, region: m3d.CrossSection, path) -> None:
        """A cut that is ``region`` revolved (unioned with the other regions, revolved once); a
        rapid's is checked against the stock as it is then."""
        if self.f.outline_cs is not None and (region ^ self.f.outline_cs).area() <= 0:
            return
        b = region.bounds()
        r_out = max(abs(b[0]), abs(b[2]))
        cut = Cut(i, [], region, np.array([-r_out, -r_out, b[1]]), np.array([r_out, r_out, b[3]]))
        if self.f.meets(cut.lo, cut.hi):
            self.cuts.append(cut)
            if getattr(path, "rapid", False):
                self.checks.append((cut, path))

    def hold(self, strategy: "Strategy") -> None:
        """``strategy`` now holds moves back for joining (the run's pending strategy)."""
        self.pending = strategy

    def flush_counts(self) -> None:
        """Count the moves held back for joining."""
        held, self.pending = self.pending, None
        if held is not None:
            held.count_held()

    def flush_cuts(self) -> None:
        """Sweep the moves held back for joining."""
        held, self.pending = self.pending, None
        if held is not None:
            held.sweep_held()


class Strategy:
    """One sweep kind: ``estimate`` and ``sweep`` of a path of that kind, with the state the kind
    keeps over one removal (one instance per run)."""

    kind = ""
    ends_joins = True  # the moves held back for joining are swept (counted) before a path of this kind

    def __init__(self, run: Run):
        self.run = run

    def estimate(self, i: int, path) -> None:
        """Count the triangles the sweep of ``path`` (the ``i``-th path) will hold into ``run.work``."""

    def sweep(self, i: int, path) -> None:
        """Add the cuts of ``path`` (the ``i``-th path) to the run."""

    def counted(self) -> None:
        """After the last path's estimate: count what is swept only when all moves are known."""

    def finish(self, n: int) -> None:
        """After the last path's sweep (``n`` paths): sweep what needs all its moves known."""

    def count_held(self) -> None:
        """Count the moves this strategy held back for joining."""

    def sweep_held(self) -> None:
        """Sweep the moves this strategy held back for joining."""
