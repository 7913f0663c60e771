"""Material removal: every path's swept solid, subtracted from the stock in one batch.

Each path gets one sweep strategy (``sweep_kind``); STRATEGIES names the class of each kind,
which holds both its sweep and the estimate of its triangles (stock/strategy.py). The removal
runs every path through its strategy twice: first the estimates, over all paths before anything
is built (the budget, stock/budget.py), then the sweeps. Then the checks (stock/collisions.py)
and one batch subtract.

Order does not change the final part (subtraction commutes), so all solids are built first and
removed with one ``batch_boolean``. Order matters only for the warnings: a rapid (G00), or a cut
with the spindle stopped, is reported when it removes material that is still there at that moment,
i.e. from the stock minus the earlier cuts that overlap it.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field, fields
from typing import Callable

import manifold3d as m3d
import numpy as np

from cutsim.base.specs import StockSpec
from cutsim.kinematics.paths import GaugePath, PlanarPath, ScrewPath, SpatialPath

from . import budget, collisions, mill
from .budget import Built, Work
from .build import DEFAULT_MAX_TRIANGLES
from .cuts import Cut, Frame, frame_of
from .mill_checks import plunges
from .strategy import Run
from .strategy_checked import Gauge, Hull
from .strategy_milling import Helix, Level, Tube, check_resolved
from .strategy_turning import Profiles, Revolve, Screw, fine_screw
from .tools import check_tool

DEBRIS_VOLUME = 1e-6  # mm^3: a shell this small is a numerical artefact, not material

Progress = Callable[[str, int, int], None]

# The one table: each sweep kind's strategy, in the order their ``counted`` and ``finish`` run
# (the thread groups before the 2.5D levels; the 3D mill chain's batch counted last).
STRATEGIES = {cls.kind: cls for cls in (Screw, Revolve, Hull, Level, Helix, Tube, Gauge)}


@dataclass
class Removal:
    part: m3d.Manifold
    warnings: list = field(default_factory=list)  # (Src, message)
    solids: int = 0  # swept solids subtracted


# -- which sweep a path gets: the tool-kind predicates in one place ---------------------------
def is_mill_move(path) -> bool:
    """A move of a milling tool (the lathe's moves with the spindle stopped are spatial too)."""
    return isinstance(path, SpatialPath) and not path.tool.is_lathe_tool



def sweep_kind(path) -> str:
    """The one sweep strategy for ``path``, a key of STRATEGIES:

    - ``screw``: a spindle-synchronised cut (thread): the profile under screw motion, grouped by
      helix (stock/threads.py, stock/sweeps.py);
    - ``revolve``: a lathe move with the spindle turning: its 2D region, all unioned and revolved once;
    - ``hull``: a move swept on its own and checked against the stock as it is then: rapids,
      plunges of a tool that cannot cut at its centre, a lathe tool with the spindle stopped
      (one hull per segment);
    - ``level``: a flat end mill at constant Z: one 2D offset per Z level, extruded (stock/mill.py);
    - ``helix``: a mill on an arc or helix, consecutive arcs on one helix joined (stock/helix.py);
    - ``tube``: any other 3D mill feed, joined with the moves it continues: tubes along a ball-end
      mill's planar stretches (stock/tube.py), merged hulls of poses elsewhere;
    - ``gauge``: a move with no tool in the spindle: nothing swept, its gauge point checked
      against the stock as it is then (stock/gauge.py)."""
    if isinstance(path, GaugePath):
        return "gauge"
    if isinstance(path, ScrewPath):
        return "screw"
    if isinstance(path, PlanarPath):
        return "revolve"
    if not is_mill_move(path) or path.rapid or plunges(path):
        return "hull"
    if mill.batchable(path):
        return "level"
    return "helix" if path.arc is not None else "tube"


def remove(stock: m3d.Manifold, spec: StockSpec, paths: list, tol: float,
           progress: Progress | None = None, max_triangles: int = DEFAULT_MAX_TRIANGLES) -> Removal:
    """The part: ``stock`` minus what every path sweeps. Each path gets one sweep strategy
    (``sweep_kind``, STRATEGIES). Before any sweep is built the triangles the sweeps need are
    estimated (stock/budget.py); more than ``max_triangles`` held at once is a CutsimError at the
    line of the move responsible (``[simulation] max_triangles`` raises it)."""
    frame = frame_of(stock, spec, tol)
    for tool in {id(p.tool): p.tool for p in paths if getattr(p, "tool", None) is not None}.values():
        check_tool(tool)  # tools built in Python, not through the setup loader, meet the same ranges
    for tool in {id(p.tool): p.tool for p in paths if is_mill_move(p)}.values():
        check_resolved(tool, tol)
    paths = [fine_screw(p, tol) for p in drop_repeats(paths)]
    kinds = [sweep_kind(p) for p in paths]
    work = Work(max_triangles, stock.num_tri())
    run = Run(frame, tol, Profiles(frame, tol), work)
    strategies = {kind: cls(run) for kind, cls in STRATEGIES.items()}
    _each(paths, kinds, strategies, "estimate", run.flush_counts)
    for s in strategies.values():
        s.counted()
    _each(paths, kinds, strategies, "sweep", run.flush_cuts, progress)
    n = len(paths)
    for s in strategies.values():
        s.finish(n)
    if progress:
        progress("sweeping", n, n)
    built = Built(budget.BUILT_TRIANGLES)
    warnings = (collisions.collision_warnings(stock, run, built, progress)
                + collisions.gauge_warnings(stock, run, strategies["gauge"].moves, built, progress)
                + collisions.body_warnings(stock, run, built, progress))
    if run.levels or any(is_mill_move(p) for p in paths):
        warnings += collisions.flute_warnings(stock, run, paths, built)
        stock = mill.refined(stock)
    part, count = _subtract(stock, run.cuts, paths, frame, work, progress, built)
    return Removal(part, warnings, count)


def _each(paths: list, kinds: list[str], strategies: dict, step: str, flush, progress: Progress | None = None) -> None:
    """Every path through its strategy's ``step`` (estimate or sweep) in program order, the moves
    held back for joining flushed first where the path's kind ends them, and flushed at the end."""
    n = len(paths)
    for i, (path, kind) in enumerate(zip(paths, kinds)):
        if progress:
            progress("sweeping", i, n)
        s = strategies[kind]
        if s.ends_joins:
            flush()
        getattr(s, step)(i, path)
    flush()


def _subtract(stock: m3d.Manifold, cuts: list[Cut], paths: list, frame: Frame, work: Work,
              progress: Progress | None, built: Built | None = None) -> tuple[m3d.Manifold, int]:
    """One batch subtract; a program whose solids exceed CHUNK_TRIANGLES is subtracted in
    consecutive batches of about that size (cut order), each built just before and released
    after, so memory stays bounded however long the program is. Returns the part (debris
    dropped) and the number of solids subtracted."""
    regions = [c.region for c in cuts if c.region is not None]
    part, pending, keys, tris, count = stock, [], [], 0, 0
    if regions:
        union = m3d.CrossSection.batch_boolean(regions, m3d.OpType.Add)
        first = min(c.index for c in cuts if c.region is not None)
        work.add(2 * union.num_vert() * frame.nseg, paths[first].src, "the turning moves (one solid of revolution)")
        pending.append(frame.revolve(union))
        keys.append(None)
    for k, c in enumerate(cuts):
        if progress:
            progress("subtracting", k, len(cuts))
        sols = built.take(c) if built is not None else c.get()  # swept for a check: not again
        pending.extend(sols)
        keys.extend(c.keys if c.keys is not None and len(c.keys) == len(sols) else [None] * len(sols))
        tris += sum(sol.num_tri() for sol in sols)
        if tris > budget.CHUNK_TRIANGLES:
            part = m3d.Manifold.batch_boolean([part] + _outermost(pending, keys, frame.top), m3d.OpType.Subtract)
            part.num_tri()  # evaluate now so the batch's solids can be freed
            count += len(pending)
            pending, keys, tris = [], [], 0
    if pending:
        part = m3d.Manifold.batch_boolean([part] + _outermost(pending, keys, frame.top), m3d.OpType.Subtract)
        count += len(pending)
    part = drop_debris(part)
    if progress:
        progress("subtracting", len(cuts), len(cuts))
    return part, count



def _outermost(solids: list, keys: list, top: float) -> list:
    """``solids`` without the hulls of tool poses that lie inside another one of them below the
    stock's top ``top`` (``mill.nested``): a pass below another on the same XY path. The part is
    the same solid, but the coinciding walls of nested passes made the batch boolean cut them into
    slivers."""
    if sum(k is not None for k in keys) < 2:
        return solids
    inside = mill.nested(keys, top)
    return [s for s, drop in zip(solids, inside) if not drop]


@functools.lru_cache(maxsize=None)
def _key_fields(cls) -> tuple[str, ...]:
    """The fields of a path type that decide what it sweeps (all but its source line)."""
    return tuple(f.name for f in fields(cls) if f.name != "src")


def _path_key(path) -> tuple:
    """Everything that decides what ``path`` sweeps (not its source line), hashable."""
    key = [type(path).__name__]
    for name in _key_fields(type(path)):
        v = getattr(path, name)
        key.append((v.shape, v.tobytes()) if isinstance(v, np.ndarray) else v)
    return tuple(key)


def drop_repeats(paths: list) -> list:
    """``paths`` without the ones that repeat an earlier path exactly (a loop running the same
    moves again, a spring pass, a zero-length move written many times). Material only ever goes:
    a repeated sweep meets nothing its first run did not already take, so it removes nothing and
    touches no fresh stock (no warning can come from it). Order and source lines are kept."""
    seen, out = set(), []
    for path in paths:
        try:
            key = _path_key(path)
            if key in seen:
                continue
            seen.add(key)
        except TypeError:  # an unhashable field: keep the path
            pass
        out.append(path)
    return out


def drop_debris(part: m3d.Manifold) -> m3d.Manifold:
    """Remove zero-volume shells that coincident faces of nested cuts can leave behind; pieces with
    real volume (a part cut loose from the bar) stay."""
    if part.is_empty() or part.genus() >= 0:
        return part
    pieces = part.decompose()
    keep = [p for p in pieces if abs(p.volume()) > DEBRIS_VOLUME]
    if len(keep) == len(pieces):
        return part
    return m3d.Manifold.compose(keep) if keep else m3d.Manifold()
