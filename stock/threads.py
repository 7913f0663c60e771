"""Thread cuts grouped by helix: one screw sweep per group instead of one per pass.

A screw path without ramps moves the tool profile by a one-parameter motion of the spindle angle
theta (radians): the profile's frame sits at radius cr + a theta and height cz + p theta in the
half-plane at angle theta (a = 0 for a straight thread, p = 0 for a face spiral). Two paths with
the same a and p are the same motion applied to profiles that differ by a fixed offset
(cr2 - cr1, cz2 - cz1) in that half-plane; theta and theta + 2 pi are the same rotation, so a
path's theta range may be shifted by whole turns (its offset by (a, p) x 2 pi per turn). Hence the
union of their sweeps over one theta range is the sweep of the union of their offset profiles:
exact, not an approximation. Infeed passes, spring passes and flank-infeed passes of one thread
are one group; taper passes too where the taper and lead agree.

- The starts of a multi-start thread are separate groups: profiles join a group only when their
  offset profile overlaps the group's (passes of one start nest; the grooves of two starts do
  not), so a group's profile stays narrower than the lead like each pass.
- A group whose profile is wider than its lead (its turns would overlap: a fine lead, a deep
  tool) is folded onto one turn (``fold``): the union of its profiles shifted by whole leads,
  swept over one turn in a few stretches.
- Where the members' theta ranges differ the group is split at every range end; each stretch
  sweeps the union of the members that cover it.
- Paths with lead-in or runout ramps are not grouped (the ramps are kinks of their own), nor are
  paths without rotation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import manifold3d as m3d
import numpy as np

from cutsim.kinematics.paths import ScrewPath, segment_angle

from .sweeps import EDGE_STEPS, MAX_CHUNK_DEGREES, edge_pieces, screw_sweep, screw_twist

REL_EPS = 1e-9  # relative: two motions (a, p) agree within this
THETA_EPS = 1e-9  # rad: range ends closer than this are one


@dataclass
class _Member:
    index: int
    path: ScrewPath
    parts: list  # (s0, s1, CrossSection) as for screw_sweep


@dataclass
class _Piece:
    """One profile on the group's motion: the profile in the group's frame, theta range."""
    profile: m3d.CrossSection
    lo: float
    hi: float


@dataclass
class _Group:
    a: float
    p: float
    cr: float
    cz: float
    travel_per_rad: float
    pieces: list = field(default_factory=list)
    box: tuple = (math.inf, math.inf, -math.inf, -math.inf)  # profile bounds in the group frame
    src: object = None  # the first member's source line: errors of the group's sweep name it


def motion(path: ScrewPath) -> tuple[float, float, float, float, float] | None:
    """(a, p, cr, cz, theta0) of a path without ramps: pose(theta) = (cr + a theta, cz + p theta),
    theta from theta0 over path.sense x 2 pi x revolutions; None when the path is not groupable."""
    if path.ramps or not path.revolutions > 0:
        return None
    big = path.sense * 2.0 * math.pi * path.revolutions
    a = (path.r1 - path.r0) / big
    p = (path.z1 - path.z0) / big
    th0 = math.radians(path.phi0)
    return a, p, path.r0 - a * th0, path.z0 - p * th0, th0


def _close(x: float, y: float, scale: float) -> bool:
    return abs(x - y) <= REL_EPS * max(scale, 1e-12)


def bounds(path: ScrewPath, parts: list) -> tuple[np.ndarray, np.ndarray]:
    """A box holding the sweep of ``parts`` along ``path`` (poses at the range ends and ramp
    kinks, where r and z are extreme, plus the profile's reach)."""
    s = np.array(sorted({p for s0, s1, _ in parts for p in [s0, s1] +
                         [b for b in path.breakpoints() if s0 < b < s1]}))
    r, z, _ = path.pose(s)
    ub = np.array([pr.bounds() for _, _, pr in parts])  # (umin, vmin, umax, vmax)
    rout = float(r.max() + ub[:, 2].max())
    return (np.array([-rout, -rout, float(z.min() + ub[:, 1].min())]),
            np.array([rout, rout, float(z.max() + ub[:, 3].max())]))


class ScrewGroups:
    """Collects the thread cuts of a program (``add``) and sweeps them grouped (``solids``)."""

    def __init__(self, tol: float):
        self.tol = tol
        self.groups: list[_Group] = []
        self.single: list[_Member] = []

    def __bool__(self) -> bool:
        return bool(self.groups or self.single)

    def add(self, index: int, path: ScrewPath, parts: list) -> None:
        m = motion(path)
        if m is None:
            self.single.append(_Member(index, path, parts))
            return
        a, p, cr, cz, th0 = m
        big = path.sense * 2.0 * math.pi * path.revolutions
        for s0, s1, prof in parts:
            t0, t1 = th0 + big * s0, th0 + big * s1
            self._place(path, a, p, cr, cz, prof, min(t0, t1), max(t0, t1))

    def _place(self, path, a, p, cr, cz, prof, lo, hi) -> None:
        scale = max(abs(a), abs(p))
        turn = 2.0 * math.pi
        for g in self.groups:
            if not (_close(a, g.a, scale) and _close(p, g.p, scale)):
                continue
            # shift by whole turns so the offset is nearest the group's frame
            k = round((g.cz - cz) / (p * turn)) if abs(p) >= abs(a) else round((g.cr - cr) / (a * turn))
            dr, dz = cr + a * turn * k - g.cr, cz + p * turn * k - g.cz
            prof_g = prof.translate((dr, dz))
            b = prof_g.bounds()
            if b[0] <= g.box[2] and g.box[0] <= b[2] and b[1] <= g.box[3] and g.box[1] <= b[3]:
                g.pieces.append(_Piece(prof_g, lo - turn * k, hi - turn * k))
                g.box = (min(g.box[0], b[0]), min(g.box[1], b[1]), max(g.box[2], b[2]), max(g.box[3], b[3]))
                return
        g = _Group(a, p, cr, cz, path.travel / (2.0 * math.pi * path.revolutions), src=path.src)
        g.pieces.append(_Piece(prof, lo, hi))
        g.box = tuple(prof.bounds())
        self.groups.append(g)

    def sweeps(self) -> list[tuple[ScrewPath, m3d.CrossSection]]:
        """(path, profile) per stretch of each group: the group's motion over the stretch and the
        union of the profiles of the members that cover it; a group whose profiles are wider
        than its lead folded onto one turn (``fold``)."""
        out = []
        for g in self.groups:
            if wide(g):
                out.extend((_group_path(g, lo, hi), prof) for lo, hi, prof in fold(g))
                continue
            ends = sorted({e for pc in g.pieces for e in (pc.lo, pc.hi)})
            cuts = [ends[0]]
            for e in ends[1:]:
                if e - cuts[-1] > THETA_EPS:
                    cuts.append(e)
            for lo, hi in zip(cuts, cuts[1:]):
                mid = 0.5 * (lo + hi)
                profs = [pc.profile for pc in g.pieces if pc.lo - THETA_EPS <= mid <= pc.hi + THETA_EPS]
                if not profs:
                    continue
                prof = profs[0] if len(profs) == 1 else m3d.CrossSection.batch_boolean(profs, m3d.OpType.Add)
                out.append((_group_path(g, lo, hi), prof))
        return out

    def solids(self) -> list[m3d.Manifold]:
        """Every collected cut swept: one sweep per group stretch, the ungrouped paths as they are."""
        out = []
        for path, prof in self.sweeps():
            out.extend(screw_sweep(path, prof, self.tol))
        for m in self.single:
            for s0, s1, prof in m.parts:
                out.extend(screw_sweep(m.path, prof, self.tol, s0, s1))
        return out


def turn_shift(g: _Group) -> tuple[float, float]:
    """How far the group's frame moves in the half-plane per turn: (2 pi a, 2 pi p)."""
    return 2.0 * math.pi * g.a, 2.0 * math.pi * g.p


OVERLAP_EPS = 1e-9  # relative area: profiles that only touch their next turn's copy are not wide


def wide(g: _Group) -> bool:
    """The group's profiles reach into their own copy one turn on (a profile wider than the lead:
    fine leads, a thread tool deeper than the lead allows): its turns would overlap each other."""
    profs = [pc.profile for pc in g.pieces]
    u = profs[0] if len(profs) == 1 else m3d.CrossSection.batch_boolean(profs, m3d.OpType.Add)
    area = u.area()
    return area > 0 and (u ^ u.translate(turn_shift(g))).area() > OVERLAP_EPS * area


# Folding a group onto one turn. The group's motion M(theta) (rotation by theta, the frame moved
# by (a, p) theta in the half-plane) satisfies M(theta + 2 pi k) = M(theta) T(k D), T(k D) the
# shift by k D = k (2 pi a, 2 pi p) in the half-plane. A piece (profile P, angles lo..hi) at angle
# phi0 + phi + 2 pi k is therefore M(phi0 + phi) applied to T(k D) P: over one turn of phi the
# whole group is the sweep of the union of the copies T(k D) P of every piece at every k whose
# angle phi0 + phi + 2 pi k falls in the piece's range. That set changes only where phi passes a
# range end (mod 2 pi): between two such ends it is one profile, swept once (exactly the same solid,
# not an approximation). A single pass of N turns becomes one turn of N lead-shifted copies plus
# the last partial turn of N + 1: no turn overlaps another, where the turn-by-turn sweep stacked
# width / lead turns over every point of the groove for the subtract to intersect.
def fold(g: _Group) -> list[tuple[float, float, m3d.CrossSection]]:
    """(lo, hi, profile) whose sweeps along the group's motion (each less than one turn, at most
    MAX_CHUNK_DEGREES: never overlapping itself) union to the group's sweep."""
    turn = 2.0 * math.pi
    dr, dz = turn_shift(g)
    phi0 = min(pc.lo for pc in g.pieces)
    ends = {0.0, turn}
    for pc in g.pieces:
        for e in (pc.lo, pc.hi):
            x = math.fmod(e - phi0, turn)
            ends.add(x if x > THETA_EPS and turn - x > THETA_EPS else 0.0)
    cuts = [0.0]
    for e in sorted(ends)[1:]:
        if e - cuts[-1] > THETA_EPS:
            cuts.append(e)
    cuts[-1] = turn
    out = []
    for lo, hi in zip(cuts, cuts[1:]):
        mid = phi0 + 0.5 * (lo + hi)
        copies = []
        for pc in g.pieces:
            ka = math.ceil((pc.lo - mid) / turn)
            kb = math.floor((pc.hi - mid) / turn)
            copies.extend(pc.profile.translate((k * dr, k * dz)) for k in range(ka, kb + 1))
        if not copies:
            continue
        prof = copies[0] if len(copies) == 1 else m3d.CrossSection.batch_boolean(copies, m3d.OpType.Add)
        k = max(1, math.ceil(math.degrees(hi - lo) / MAX_CHUNK_DEGREES))
        edges = np.linspace(phi0 + lo, phi0 + hi, k + 1)
        out.extend((float(a), float(b), prof) for a, b in zip(edges, edges[1:]))
    return out


def sweep_triangles(path: ScrewPath, prof: m3d.CrossSection, tol: float) -> int:
    """Triangles of ``screw_sweep(path, prof, tol)`` for one stretch of ``sweeps()`` (no ramps),
    counted without building it: per chunk, two per profile vertex (after ``subdivide``) and
    station, and both caps. No stretch's turns overlap each other (a narrow profile's turns lie
    side by side, a wide group is folded to less than a turn per stretch), so this is the work."""
    if prof.is_empty():
        return 0
    b = prof.bounds()
    reach = max(path.r0, path.r1) + b[2]
    step = math.degrees(segment_angle(reach, tol))
    total = 360.0 * path.revolutions
    lead = path.travel / path.revolutions if path.revolutions > 0 else math.inf
    chunks = 1 if b[3] - b[1] < 0.999 * lead else max(1, math.ceil(total / MAX_CHUNK_DEGREES))
    n = max(1, math.ceil(total / chunks / step))
    max_len = EDGE_STEPS * math.sqrt(tol * reach)
    twist = screw_twist(path, prof, tol)
    nv = sum(int(edge_pieces(poly, max_len, twist).sum()) for poly in prof.to_polygons())
    return chunks * (2 * nv * n + 2 * nv)


def _group_path(g: _Group, lo: float, hi: float) -> ScrewPath:
    """The group's motion from theta = lo to hi as a screw path (phi growing: sense +1)."""
    span = hi - lo
    return ScrewPath(src=g.src, tool=None, r0=g.cr + g.a * lo, z0=g.cz + g.p * lo, r1=g.cr + g.a * hi,
              z1=g.cz + g.p * hi, travel=g.travel_per_rad * span, revolutions=span / (2.0 * math.pi),
              phi0=math.degrees(lo), sense=1)
