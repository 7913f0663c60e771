"""A mill helix rising at most the tolerance per turn is swept as the revolved tool
(stock/helix.py ``revolved_sweep``), checked against geometry: the annulus (flat end mill) and
Pappus (ball end mill about its own axis) over the helix's radial range and heights, the groove's
radii on half-lines at several angles, a helix just coarser than the tolerance still swept as the
screw, and the flute check along a joined helix (bisection) against checking every turn."""
import math

import manifold3d as m3d
import numpy as np
import pytest

import cutsim
from cutsim.base.specs import ToolSpec
from cutsim.interp.canon import Src
from cutsim.kinematics.paths import ArcGeom, SpatialPath
from cutsim.stock import mill_checks
from cutsim.stock.helix import arc_sweep, fine_pitch, revolved_sweep

SETUP = """[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 50.0]

[stock]
shape = "box"
x = [-40.0, 40.0]
y = [-40.0, 40.0]
z = [-20.0, 0.0]

[[tool]]
number = 1
kind = "{kind}"
diameter = 10.0
length = {length}

[simulation]
tolerance = {tol}
"""


def _run(tmp_path, program: str, kind: str = "endmill", length: float = 30.0, tol: float = 0.005):
    (tmp_path / "s.toml").write_text(SETUP.format(kind=kind, length=length, tol=tol))
    (tmp_path / "p.nc").write_text(program)
    return cutsim.simulate(str(tmp_path / "p.nc"), str(tmp_path / "s.toml"))


def _helix_program(x0: float, radius: float, z0: float, pitch: float, repeats: int) -> str:
    """Tool at (x0, 0), down to z0, then ``repeats + 1`` clockwise circles about (x0 + radius, 0)
    with the CNC8x6 helix (G10 pitch, G09, G73 repeats)."""
    return (f"N1 G00 X{x0:.4f} Y0 Z5.\nN2 G01 Z{z0:.4f} F500\nN3 Z{pitch:.4f} G10\n"
            f"N4 G09 G02 X{x0:.4f} Y0 I{radius:.4f} G73 L4 Q{repeats}\nN5 G98\nN6 G00 Z30.\n")


def test_fine_helix_removes_the_annulus(tmp_path):
    """1001 circles of radius 20 rising 0.004 per turn from Z-8 (tolerance 0.005): the groove is the
    annulus 15..25 from the lowest tip height to the top; the true floor lies within one pitch
    above the lowest tip (its turns are a pitch apart), the fold puts it half a pitch up."""
    R, r, z0, p, n = 20.0, 5.0, -8.0, -0.004, 1000
    res = _run(tmp_path, _helix_program(-R, R, z0, p, n))
    z_low = z0 + p * (n + 1)
    area = math.pi * ((R + r) ** 2 - (R - r) ** 2)
    removed = res.report["removed_volume"]
    assert area * (0.0 - z_low) - area * abs(p) <= removed <= area * (0.0 - z_low) + 1e-6 * removed
    assert abs(removed - area * (0.0 - z_low - abs(p) / 2)) <= 2e-5 * removed  # unbiased: the mid floor


def test_fine_helix_radii_at_several_angles(tmp_path):
    """The groove's walls on half-lines from the helix's axis at five angles, halfway down: R - r
    and R + r within the tolerance."""
    R, r, tol = 20.0, 5.0, 0.005
    res = _run(tmp_path, _helix_program(-R, R, -1.0, -0.003, 2000), tol=tol)
    z = -4.0
    box = m3d.CrossSection.square((80.0, 80.0)).translate((-40.0, -40.0))
    removed = box - res.part.slice(z)
    for deg in (0.0, 37.0, 90.0, 211.0, 300.0):
        ray = m3d.CrossSection.square((39.0, 1e-4)).translate((0.0, -5e-5)).rotate(deg)
        pts = np.vstack([np.asarray(p) for p in (removed ^ ray).to_polygons()])
        d = np.hypot(pts[:, 0], pts[:, 1])
        assert abs(d.min() - (R - r)) <= tol and abs(d.max() - (R + r)) <= tol, deg


def test_ball_about_its_own_axis_is_pappus(tmp_path):
    """A ball end mill (radius 5) on a helix of radius 3 reaches over the axis: the revolved ball
    from the axis out to 8 mm, its lowest point the lowest tip; volume by Pappus (the section
    integrated numerically here), floor half a pitch up."""
    R, r, z0, p, n = 3.0, 5.0, -2.0, -0.002, 3000
    res = _run(tmp_path, _helix_program(-R, R, z0, p, n), kind="ballmill", length=20.0)
    z_floor = z0 + p * (n + 1) + abs(p) / 2
    rho = np.linspace(0.0, R + r, 200001)
    bottom = z_floor + r - np.sqrt(np.maximum(r * r - (rho - R) ** 2, 0.0))
    exact = float(np.trapezoid(2 * math.pi * rho * (0.0 - bottom), rho))
    assert abs(res.report["removed_volume"] - exact) <= 2e-5 * exact


def _arc_path(pitch: float, turns: float, tool: ToolSpec, tol: float) -> SpatialPath:
    arc = ArcGeom(0.0, 0.0, 20.0, 0.0, -2 * math.pi * turns, -1.0, -1.0 - pitch * turns)
    n = max(1, math.ceil(abs(arc.sweep) / (2 * math.acos(1 - tol / arc.radius))))
    return SpatialPath(Src("t.nc", 1, 1), tool, arc.pose(np.linspace(0.0, 1.0, n + 1)), False, arc=arc)


@pytest.mark.parametrize("kind", ["endmill", "ballmill"])
def test_just_above_the_tolerance_goes_the_screw_way(kind):
    """A pitch 1 % above the tolerance is swept as the screw (warped pieces and end hulls), one at
    the tolerance as one revolved solid; both remove the same groove within one pitch's annulus."""
    tol = 0.01
    tool = ToolSpec(1, kind, diameter=10.0, length=20.0, corner_radius=5.0 if kind == "ballmill" else 0.0)
    stock = m3d.Manifold.cube((60.0, 60.0, 10.0)).translate((-30.0, -30.0, -10.0))
    coarse, fine = _arc_path(1.01 * tol, 3.0, tool, tol), _arc_path(tol, 3.0, tool, tol)
    assert fine_pitch(coarse.arc, tol) is None and revolved_sweep(coarse, tol) is None
    screw = arc_sweep(coarse, tol, 0.0)
    assert len(screw) > 1  # warped pieces plus the hulls at the ends
    assert fine_pitch(fine.arc, tol) == pytest.approx(tol)
    revolved = arc_sweep(fine, tol, 0.0)
    assert len(revolved) == 1 and revolved[0].genus() == 1  # one ring
    v_screw = stock.volume() - m3d.Manifold.batch_boolean([stock] + screw, m3d.OpType.Subtract).volume()
    v_rev = stock.volume() - m3d.Manifold.batch_boolean([stock] + revolved, m3d.OpType.Subtract).volume()
    assert abs(v_screw - v_rev) <= math.pi * (25.0 ** 2 - 15.0 ** 2) * 2 * tol


def test_less_than_a_turn_is_not_folded():
    """Below one whole turn some angles are never passed: no revolved solid, however flat."""
    tool = ToolSpec(1, "endmill", diameter=10.0, length=20.0)
    assert revolved_sweep(_arc_path(0.0, 0.99, tool, 0.01), 0.01) is None
    assert revolved_sweep(_arc_path(0.0, 1.0, tool, 0.01), 0.01) is not None


@pytest.mark.parametrize("enter", ["G00 Z-3.", "G01 Z0.5 F500"])
def test_flute_check_bisection_matches_every_turn(tmp_path, monkeypatch, enter):
    """A helix descending below its 2 mm flutes, entered by a rapid into the stock (the shank meets
    fresh material at the first circle) or from above (it never does): the same warnings with the
    joined helix bisected as with every circle checked on its own."""
    program = (f"N1 G00 X-20. Y0 Z5.\nN2 {enter}\nN3 Z-0.2 G10\nN4 G09 G02 X-20. Y0 I20. G73 L4 Q25\n"
               "N5 G98\nN6 G00 Z30.\n")
    fast = _run(tmp_path, program, length=2.0, tol=0.05).report["warnings"]
    monkeypatch.setattr(mill_checks, "_deepening_runs", lambda cands, paths, bottom: [[c] for c in cands])
    slow = _run(tmp_path, program, length=2.0, tol=0.05).report["warnings"]
    flutes = [w for w in fast if "flute length" in w["message"]]
    assert fast == slow
    assert bool(flutes) == enter.startswith("G00")
