"""Thread cuts grouped by helix (stock/threads.py): passes on one helix become one sweep of their
unioned profiles. Volumes are checked against the screw-motion form of Pappus' theorem: a region
of the meridian half-plane swept by rotation theta with any axial/radial drift removes
theta x (integral of the radius over the region) when its turns do not overlap."""
import math

import manifold3d as m3d
import numpy as np
import pytest

from cutsim.kinematics.paths import RampGeom, ScrewPath
from cutsim.stock import threads

TOL = 0.002
LEAD = 1.5


def vee(depth: float, top: float = 0.3, half: float = 30.0, dv: float = 0.0) -> m3d.CrossSection:
    """Thread-tool profile in the path frame: tip at (0, dv), flanks at +-half degrees, cut off
    ``depth + top`` above the tip (u outwards)."""
    h = depth + top
    w = h * math.tan(math.radians(half))
    return m3d.CrossSection([np.array([[0.0, dv], [h, dv - w], [h, dv + w]])])


def path(r0: float, z0: float, z1: float, phi0: float = 0.0, r1: float | None = None, ramps=()) -> ScrewPath:
    turns = abs(z1 - z0) / LEAD
    return ScrewPath(src=None, tool=None, r0=r0, z0=z0, r1=r0 if r1 is None else r1, z1=z1,
                     travel=abs(z1 - z0), revolutions=turns, phi0=phi0, sense=-1, ramps=tuple(ramps))


def radial_moment(poly: np.ndarray, r0: float) -> float:
    """Integral of the radius r0 + u over a polygon (u, v) (Green's theorem)."""
    u, v = poly[:, 0] + r0, poly[:, 1]
    un, vn = np.roll(u, -1), np.roll(v, -1)
    cross = u * vn - un * v
    return abs(float(np.sum((u + un) * cross) / 6.0))


def union_volume(solids) -> float:
    return m3d.Manifold.batch_boolean(solids, m3d.OpType.Add).volume()


def test_infeed_passes_are_one_sweep_of_the_deepest_profile():
    # five radial infeed passes and a spring pass on one helix, profiles cut at r = 35.05
    g = threads.ScrewGroups(TOL)
    depths = [0.23, 0.46, 0.69, 0.92, 0.92]
    for k, d in enumerate(depths):
        r0 = 35.0 - d
        g.add(k, path(r0, 105.0, 48.0, phi0=0.0), [(0.0, 1.0, vee(d, top=0.05))])
    sw = g.sweeps()
    assert len(sw) == 1 and not g.single
    theta = 2 * math.pi * 57.0 / LEAD
    deepest = np.array([[0.0, 0.0], [0.97, -0.97 * math.tan(math.radians(30))],
                        [0.97, 0.97 * math.tan(math.radians(30))]])
    exact = theta * radial_moment(deepest, 35.0 - 0.92)
    vol = union_volume(g.solids())
    assert abs(vol - exact) <= 2e-4 * exact


def test_flank_infeed_passes_union_their_shifted_profiles():
    # the second pass starts 0.2 mm further along Z (flank infeed): same helix, profile shifted
    g = threads.ScrewGroups(TOL)
    g.add(0, path(34.5, 105.0, 48.0), [(0.0, 1.0, vee(0.5))])
    g.add(1, path(34.5, 105.2, 48.2), [(0.0, 1.0, vee(0.5))])
    sw = g.sweeps()
    assert len(sw) == 1
    # the union of two equal vees shifted by 0.2 along v, swept over the common range: compare
    # with the sum of the two minus their overlap (a vee of the same shape, 0.2 / (2 tan 30) lower)
    h, t = 0.8, math.tan(math.radians(30))
    one = radial_moment(np.array([[0.0, 0.0], [h, -h * t], [h, h * t]]), 34.5)
    s = 0.2 / (2 * t)  # the overlap's tip is this far up
    ov = radial_moment(np.array([[s, 0.1], [h, 0.1 - (h - s) * t], [h, 0.1 + (h - s) * t]]), 34.5)
    exact = 2 * math.pi * 57.0 / LEAD * (2 * one - ov)  # one range: both span the same angles
    vol = union_volume(g.solids())
    indiv = union_volume([x for p in (path(34.5, 105.0, 48.0), path(34.5, 105.2, 48.2))
                          for x in threads.screw_sweep(p, vee(0.5), TOL)])
    assert abs(vol - indiv) <= 2e-4 * indiv
    assert abs(vol - exact) <= 1e-3 * exact


def test_starts_of_a_two_start_thread_are_separate_groups():
    g = threads.ScrewGroups(TOL)
    lead = 2 * LEAD  # 2 starts, pitch 1.5: the second start is half a lead (180 degrees) on
    for k, phi in enumerate((0.0, 180.0)):
        turns = 57.0 / lead
        p = ScrewPath(src=None, tool=None, r0=34.5, z0=105.0, r1=34.5, z1=48.0, travel=57.0,
                      revolutions=turns, phi0=phi, sense=-1)
        g.add(k, p, [(0.0, 1.0, vee(0.5))])
        g.add(k + 2, p, [(0.0, 1.0, vee(0.3))])  # a shallower pass of the same start
    assert len(g.groups) == 2 and len(g.sweeps()) == 2


def test_ranges_that_differ_are_split():
    # a pass over z 105..48 and a deeper one over 90..60 only: three stretches
    g = threads.ScrewGroups(TOL)
    g.add(0, path(34.5, 105.0, 48.0), [(0.0, 1.0, vee(0.5))])
    g.add(1, path(34.3, 90.0, 60.0), [(0.0, 1.0, vee(0.7))])
    sw = g.sweeps()
    assert len(sw) == 3
    h1, h2, t = 0.8, 1.0, math.tan(math.radians(30))
    shallow = radial_moment(np.array([[0.0, 0.0], [h1, -h1 * t], [h1, h1 * t]]), 34.5)
    deep = radial_moment(np.array([[0.0, 0.0], [h2, -h2 * t], [h2, h2 * t]]), 34.3)  # holds the shallow
    per_mm = 2 * math.pi / LEAD
    exact = per_mm * (27.0 * shallow + 30.0 * deep)
    vol = union_volume(g.solids())
    assert abs(vol - exact) <= 2e-4 * exact


def test_taper_passes_on_one_cone_group():
    # 1:16 taper (radius falls 57/32 mm over the length): two infeed passes on the same cone
    g = threads.ScrewGroups(TOL)
    drop = 57.0 / 32.0
    for k, d in enumerate((0.3, 0.6)):
        g.add(k, path(35.0 - d, 105.0, 48.0, r1=35.0 - d - drop), [(0.0, 1.0, vee(d))])
    assert len(g.groups) == 1 and len(g.sweeps()) == 1
    # not the same cone (another taper): two groups
    g.add(2, path(34.4, 105.0, 48.0, r1=34.4 - 2 * drop), [(0.0, 1.0, vee(0.6))])
    assert len(g.groups) == 2


def test_paths_with_ramps_are_not_grouped():
    g = threads.ScrewGroups(TOL)
    ramp = RampGeom(start=50.0, length=7.0, offset=1.0, axis="r")
    g.add(0, path(34.5, 105.0, 48.0, ramps=[ramp]), [(0.0, 1.0, vee(0.5))])
    g.add(1, path(34.5, 105.0, 48.0), [(0.0, 1.0, vee(0.5))])
    assert len(g.single) == 1 and len(g.groups) == 1


@pytest.mark.parametrize("phi0", [0.0, 37.0, 400.0])
def test_phase_and_whole_turns(phi0):
    # a pass entering the same helix one lead later (one turn on: phi0 - 360 with sense -1, or
    # phi0 itself, the same rotation) joins the group; the sweep is the union of the two sweeps
    g = threads.ScrewGroups(TOL)
    a = path(34.5, 105.0, 48.0, phi0=phi0)
    b = path(34.3, 105.0 - LEAD, 48.0, phi0=phi0)
    g.add(0, a, [(0.0, 1.0, vee(0.5))])
    g.add(1, b, [(0.0, 1.0, vee(0.7))])
    assert len(g.groups) == 1 and len(g.sweeps()) == 2  # the first turn holds the shallow pass only
    h1, h2, t = 0.8, 1.0, math.tan(math.radians(30))
    shallow = radial_moment(np.array([[0.0, 0.0], [h1, -h1 * t], [h1, h1 * t]]), 34.5)
    deep = radial_moment(np.array([[0.0, 0.0], [h2, -h2 * t], [h2, h2 * t]]), 34.3)
    exact = 2 * math.pi * (1.0 * shallow + 55.5 / LEAD * deep)
    vol = union_volume(g.solids())
    assert abs(vol - exact) <= 2e-4 * exact
