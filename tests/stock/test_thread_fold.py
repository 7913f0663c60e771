"""Thread cuts whose profile is wider than the lead (stock/threads.py ``fold``): the turns of such
a sweep overlap, so it is built as ONE turn of the union of the profile's lead-shifted copies.

Truth from the definition of the sweep, not from the code: the motion turns the frame by theta
and moves it by (a, p) theta in the meridian half-plane, so the half-plane at angle phi holds the
profile at every theta = phi + 2 pi k of the path, i.e. the union of the copies of the profile
shifted by k x (2 pi a, 2 pi p) for those k. The solid's volume is the integral over phi of that
section's radial moment (integral of r dA). For a V of half-angle 30 degrees with its tip at
radius r0, cut off u = h above the tip, and n copies spaced by the lead L along the axis, the
section is, at height u over the tip, n separate intervals 2 u tan30 wide while they are narrower
than L, then one interval (n - 1) L + 2 u tan30 long: its moment is a polynomial integral
(``strip_moment``)."""
import math

import manifold3d as m3d
import numpy as np
import pytest

from cutsim.kinematics.paths import ScrewPath
from cutsim.stock import sweeps, threads

TOL = 0.002
T30 = math.tan(math.radians(30.0))


def vee(h: float) -> m3d.CrossSection:
    return m3d.CrossSection([np.array([[0.0, 0.0], [h, -h * T30], [h, h * T30]])])


def strip_moment(r0: float, h: float, lead: float, n: int) -> float:
    """Integral of r over the union of n copies of ``vee(h)`` at radius r0 spaced ``lead`` along v."""
    if n <= 0:
        return 0.0
    us = min(h, lead / (2 * T30))  # the copies merge above this height

    def poly_int(c0: float, c1: float, a: float, b: float) -> float:
        # integral over u in [a, b] of (r0 + u) (c0 + c1 u)
        f = lambda u: r0 * c0 * u + (r0 * c1 + c0) * u * u / 2 + c1 * u ** 3 / 3  # noqa: E731
        return f(b) - f(a)

    return poly_int(0.0, n * 2 * T30, 0.0, us) + poly_int((n - 1) * lead, 2 * T30, us, h)


def screw(r0: float, z0: float, turns: float, lead: float, phi0: float = 0.0, r1: float | None = None) -> ScrewPath:
    return ScrewPath(src=None, tool=None, r0=r0, z0=z0, r1=r0 if r1 is None else r1, z1=z0 - lead * turns,
                     travel=lead * turns, revolutions=turns, phi0=phi0, sense=-1)


def union_volume(solids) -> float:
    return m3d.Manifold.batch_boolean(solids, m3d.OpType.Add).volume()


@pytest.mark.parametrize("turns", [12.5, 12.0, 7.3])
def test_single_wide_pass_removes_the_swept_volume(turns):
    # G33 with lead 0.1 and a V cut off 1.05 above its tip: 2 x 1.05 tan30 = 1.21 mm wide, 12
    # leads: every point of the groove lies in 12 turns of the tool
    r0, h, lead = 14.0, 1.05, 0.1
    g = threads.ScrewGroups(TOL)
    g.add(0, screw(r0, 3.0, turns, lead), [(0.0, 1.0, vee(h))])
    assert len(g.groups) == 1 and threads.wide(g.groups[0])
    sw = g.sweeps()
    assert all(p.revolutions * 360.0 <= sweeps.MAX_CHUNK_DEGREES + 1e-9 for p, _ in sw)
    assert sum(p.revolutions for p, _ in sw) == pytest.approx(1.0)  # one turn in all
    n = math.floor(turns)  # whole turns: phi in [0, psi] sees n + 1 copies, the rest n
    psi = 2 * math.pi * (turns - n)
    exact = psi * strip_moment(r0, h, lead, n + 1) + (2 * math.pi - psi) * strip_moment(r0, h, lead, n)
    vol = union_volume(g.solids())
    assert abs(vol - exact) <= 2e-4 * exact
    # the count before building (the removal's work estimate) is the folded sweep's
    tris = sum(s.num_tri() for s in g.solids())
    est = sum(threads.sweep_triangles(p, prof, TOL) for p, prof in sw)
    assert abs(est - tris) <= 0.01 * tris


def test_one_turn_pieces_fold_like_the_whole_pass():
    # the removal cuts a wide pass into one-turn pieces (each clipped where the stock is): pieces
    # of the same profile give the same solid as the whole pass
    r0, h, lead, turns = 14.0, 1.05, 0.1, 9.5
    whole = threads.ScrewGroups(TOL)
    whole.add(0, screw(r0, 3.0, turns, lead), [(0.0, 1.0, vee(h))])
    cut = threads.ScrewGroups(TOL)
    edges = [min(1.0, k / turns) for k in range(int(math.ceil(turns)) + 1)]
    cut.add(0, screw(r0, 3.0, turns, lead), [(a, b, vee(h)) for a, b in zip(edges, edges[1:])])
    assert len(cut.groups) == 1 and len(cut.sweeps()) == len(whole.sweeps())
    n, psi = 9, 2 * math.pi * 0.5
    exact = psi * strip_moment(r0, h, lead, n + 1) + (2 * math.pi - psi) * strip_moment(r0, h, lead, n)
    for g in (whole, cut):
        assert abs(union_volume(g.solids()) - exact) <= 2e-4 * exact


def test_fold_matches_a_fine_turn_by_turn_sweep_on_a_taper_with_two_passes():
    # a taper (the radius grows 0.05 per turn) and two passes of different depth starting 100
    # degrees apart on the same helix, against the plain sweep of every pass (turns overlapping,
    # unioned) at a tenth of the tolerance. The folded sweep's chords lie inside the true surface:
    # at 2 um on radius 13.2 the station angle is 0.035 rad and a chorded turn holds
    # 1 - angle^2 / 6 = 1 - 2.0e-4 of the swept area (measured -1.7e-4 on the wide pass above)
    lead, turns = 0.25, 6.0
    a = screw(12.0, 0.0, turns, lead, phi0=0.0, r1=12.0 + 0.05 * turns)
    b_phi = 100.0  # sense -1: 100 degrees on along the path is phi0 - 100, z0 - lead * 100 / 360
    b = screw(11.9 + 0.05 * b_phi / 360, -lead * b_phi / 360, turns - 1.0, lead, phi0=-b_phi,
              r1=11.9 + 0.05 * (b_phi / 360 + turns - 1.0))
    g = threads.ScrewGroups(TOL)
    g.add(0, a, [(0.0, 1.0, vee(0.9))])
    g.add(1, b, [(0.0, 1.0, vee(1.0))])
    assert len(g.groups) == 1 and threads.wide(g.groups[0])
    assert len(g.sweeps()) == 2  # two stretches of angle: both passes, and the first one alone
    folded = union_volume(g.solids())
    fine = TOL / 10
    plain = union_volume(sweeps.screw_sweep(a, vee(0.9), fine) + sweeps.screw_sweep(b, vee(1.0), fine))
    assert abs(folded - plain) <= 3e-4 * plain


def test_narrow_groups_are_not_folded():
    g = threads.ScrewGroups(TOL)
    g.add(0, screw(34.5, 105.0, 38.0, 1.5), [(0.0, 1.0, vee(0.8))])  # 0.92 mm wide, lead 1.5
    assert not threads.wide(g.groups[0])
    (p, prof), = g.sweeps()
    assert p.revolutions == pytest.approx(38.0)
    tris = sum(s.num_tri() for s in g.solids())
    assert abs(threads.sweep_triangles(p, prof, TOL) - tris) <= 0.01 * tris
