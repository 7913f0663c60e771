"""Lathe inserts in holders, grooving and full-profile thread inserts, inside and face tools:
removed volumes against closed-form geometry (docs/setup.md, ``[[tool]]``).

Expected numbers come from the tool's definition and the program, never from cutsim's sweep code.
Turned volumes are Pappus's: a region of area A whose centroid lies at radius r_c turned about
the axis sweeps 2 pi r_c A. The stock and every revolved cut share one polygon of n segments, so
every revolved volume is the true one times k = n sin(2 pi / n) / (2 pi); k is read from the
simulated stock's own volume against the true cylinder's (the report's ``stock_volume``).
A helical groove of cross-section A (in a half-plane through the axis) at centroid radius r_c and
lead P holds 2 pi r_c A / P of material per mm of length (the screw form of Pappus's theorem:
every point of the section moves 2 pi r per turn at right angles to the half-plane).

The square-shoulder test: a tool with a hand turns along Z to a shoulder and leaves it feeding
straight out; with its imaginary tip programmed, the material left in the corner is the spandrel
of the nose radius rn, a square rn x rn less a quarter circle, area (1 - pi/4) rn^2, its centroid
c rn = (10 - 3 pi) / (12 - 3 pi) rn from both sides of the corner.
"""
from __future__ import annotations

import math

import manifold3d as m3d
import numpy as np
import pytest

import cutsim
from cutsim.base.specs import ToolSpec

SPANDREL = (10.0 - 3.0 * math.pi) / (12.0 - 3.0 * math.pi)
TOL = 0.002


def _setup(tmp_path, stock: str, tool: str, machine: str = "", dialect: str = "cnc8x6") -> str:
    path = tmp_path / "s.toml"
    path.write_text(f'[machine]\nkind = "lathe"\ndialect = "{dialect}"\n{machine}\n[stock]\n{stock}\n\n[[tool]]\n{tool}\n')
    return str(path)


def _run(tmp_path, stock: str, tool: str, program: str, tol: float = TOL, machine: str = "", dialect: str = "cnc8x6"):
    return cutsim.simulate("p.nc", _setup(tmp_path, stock, tool, machine, dialect), text=program + "M30\n", tolerance=tol)


def _k(result, true_volume: float) -> float:
    """The polygon factor of the revolved stock (module docstring)."""
    return result.report["stock_volume"] / true_volume


def _slab(part: m3d.Manifold, z0: float, z1: float, r: float) -> float:
    """Volume of ``part`` between the heights z0 < z1."""
    box = m3d.Manifold.cube((4 * r, 4 * r, z1 - z0)).translate((-2 * r, -2 * r, z0))
    return (part ^ box).volume()


# -- ISO inserts in a holder: a square shoulder ---------------------------------------------------
SHAPES = ["C", "D", "T", "V", "W", "S", "R"]


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("rn", [0.0, 0.8, 1.6])
@pytest.mark.parametrize("side,hand", [("outside", "R"), ("outside", "L"), ("inside", "R"), ("inside", "L")])
def test_insert_turns_a_square_shoulder(tmp_path, shape, rn, side, hand):
    """Turn a diameter to a shoulder and leave it straight out: the part is the annulus less the
    spandrel the nose leaves in the corner, at any shape, nose radius, hand and side."""
    _square_shoulder(tmp_path, shape, rn, side, hand, "")


# every holder angle the docs name that each insert allows (kappa_r <= 180 - its corner angle)
APPROACHES = [(shape, kappa) for shape, corner in (("C", 80), ("D", 55), ("T", 60), ("V", 35), ("W", 80), ("S", 90))
              for kappa in (90.0, 93.0, 95.0, 107.5, 117.5) if kappa <= 180 - corner and (kappa > 90 or shape == "S")]


@pytest.mark.parametrize("shape,kappa", APPROACHES)
@pytest.mark.parametrize("side,hand", [("outside", "R"), ("inside", "L")])
def test_square_shoulder_at_every_approach_angle(tmp_path, shape, kappa, side, hand):
    """The same shoulder with the holder at kappa_r 93, 95, 107.5, 117.5 (90 for the square
    insert): the main edge leans kappa_r - 90 back from the face, so it never touches it and the
    part is the annulus less the nose's spandrel whatever the angle."""
    _square_shoulder(tmp_path, shape, 0.8, side, hand, f"\napproach = {kappa}")


def _square_shoulder(tmp_path, shape, rn, side, hand, extra):
    if shape == "R":
        if rn == 0.0:
            pytest.skip("a round insert's nose is the insert")
        nose = 2.2 + rn  # a round insert is its own nose: between half the depth of cut (4 mm inside, 5
        # outside) and the whole (its diameter reaches the surface, its corner lies below it)
        size = 2.0 * nose
        tool = f'kind = "turning"\ninsert = "R"\nsize = {size}\nside = "{side}"\nhand = "{hand}"'
    else:
        nose = rn
        tool = f'kind = "turning"\ninsert = "{shape}"\ntip_radius = {rn}\nside = "{side}"\nhand = "{hand}"{extra}'
    s = 1 if hand == "R" else -1  # R cuts towards -Z from above the bar, L towards +Z from below
    z_out, z_shoulder = (2.0, -20.0) if hand == "R" else (-52.0, -30.0)
    if side == "outside":
        stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
        r_cut, r_out, r_stock = 15.0, 21.0, 20.0
        true = math.pi * 20.0 ** 2 * 50.0
        length = 20.0
        annulus = math.pi * (r_stock ** 2 - r_cut ** 2) * length
        corner = r_cut + SPANDREL * nose
    else:
        # a bore the inserts fit in (a 35 degree V of 12.7 reaches 36 mm back from its point)
        stock = "shape = \"revolve\"\nprofile = [[25, 0], [40, 0], [40, -50], [25, -50]]"
        r_cut, r_out = 29.0, 24.0
        true = math.pi * (40.0 ** 2 - 25.0 ** 2) * 50.0
        length = 20.0
        annulus = math.pi * (r_cut ** 2 - 25.0 ** 2) * length
        corner = r_cut - SPANDREL * nose
    spandrel = 2.0 * math.pi * corner * (1.0 - math.pi / 4.0) * nose ** 2
    # from above the bar (clear of it by more than the insert's size), down beside or in the
    # bore, the pass, out, and back up
    program = (f"G00 Z{z_out:.3f}\nM03 S500\nX{2 * r_cut:.3f}\nG01 Z{z_shoulder:.3f} F0.2\n"
               f"X{2 * r_out:.3f}\nG00 Z30.\n")
    assert s * (z_out - z_shoulder) > 0
    res = _run(tmp_path, stock, tool, program, machine=f"start = [{2 * r_out}, 0, 30]")
    assert res.report["warnings"] == []
    k = _k(res, true)
    removed = res.report["removed_volume"]
    # the nose arc's chords (within TOL) around the corner ring, both ways
    slack = 2.0 * math.pi * corner * TOL * (nose + 1.0) + 1e-3 * k * annulus * 1e-3
    assert abs(removed - k * (annulus - spandrel)) <= slack, (removed, k * (annulus - spandrel), slack)


def test_plain_v_leaves_a_cone_not_a_shoulder(tmp_path):
    """The same program with the neutral 55 degree V (the old ``turning`` tool) undercuts the
    shoulder with its leading flank, a cone 5 tan 27.5 = 2.6 mm long: the test above can tell a
    square shoulder from a cone."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    program = "G00 X42. Z2.\nM03 S500\nX30.\nG01 Z-20. F0.2\nX42.\nG00 Z2.\n"
    res = _run(tmp_path, stock, 'kind = "turning"\ntip_radius = 0.0', program)
    k = _k(res, math.pi * 400.0 * 50.0)
    cone = 2.0 * math.pi * (15.0 + 2.0 * 5.0 / 3.0) * 0.5 * 5.0 * 5.0 * math.tan(math.radians(27.5))
    assert abs(res.report["removed_volume"] - k * (math.pi * (400.0 - 225.0) * 20.0 + cone)) < 1.0


def test_approach_to_the_face_is_not_a_rapid_cut(tmp_path):
    """A 93 degree holder's insert stands clear of the face at Z2 over a bar of 40: the approach
    X30 Z2 touches nothing (the plain V's trailing flank reaches 83.9 mm^3 into the face)."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    program = "G00 X50. Z2.\nM03 S500\nX30.\nG01 Z-10. F0.2\nX42.\nG00 Z2.\n"
    res = _run(tmp_path, stock, 'kind = "turning"\ninsert = "C"\napproach = 93', program, tol=0.01)
    assert res.report["warnings"] == []
    v = _run(tmp_path, stock, 'kind = "turning"', program, tol=0.01)
    assert v.report["warnings"], "the plain V should reach into the face"


# -- grooving ------------------------------------------------------------------------------------
@pytest.mark.parametrize("hand,z_ctrl", [("R", -20.0), ("L", -17.0), ("N", -18.5)])
@pytest.mark.parametrize("rc", [0.0, 0.3])
def test_groove_is_the_insert_width(tmp_path, hand, z_ctrl, rc):
    """A plunge to X30 with a 3 mm insert: a groove z -20..-17 (the control point at the
    corner towards -Z for hand R, towards +Z for L, the middle for N), 5 mm deep, its bottom
    corners the insert's radii: annulus less two spandrels."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    tool = f'kind = "grooving"\nwidth = 3\ncorner_radius = {rc}\nhand = "{hand}"'
    program = f"G00 X42. Z{z_ctrl}\nM03 S500\nG01 X30. F0.05\nG00 X42.\n"
    res = _run(tmp_path, stock, tool, program)
    k = _k(res, math.pi * 400.0 * 50.0)
    groove = math.pi * (400.0 - 225.0) * 3.0
    spandrels = 2 * 2.0 * math.pi * (15.0 + SPANDREL * rc) * (1.0 - math.pi / 4.0) * rc ** 2
    # the corner arcs' chords (within TOL) over a quarter circle each
    slack = 2 * 2.0 * math.pi * (15.0 + rc) * TOL * (math.pi / 2.0 * rc) + 0.02
    assert abs(res.report["removed_volume"] - k * (groove - spandrels)) <= slack
    part = res.part
    assert _slab(part, -20.0 + 0.01, -17.0 - 0.01, 20.0) < _slab(part, -17.0 + 0.01, -14.0 - 0.01, 20.0) * 0.6


@pytest.mark.parametrize("hand,z_ctrl", [("R", -20.0), ("L", -17.0), ("N", -18.5)])
@pytest.mark.parametrize("rc", [0.0, 0.3])
def test_inside_groove_is_the_insert_width(tmp_path, hand, z_ctrl, rc):
    """An inside grooving insert (mirrored in X: the same corner towards -Z for hand R) plunged
    from a bore of 25 out to r 28: a ring z -20..-17, 3 deep, its floor corners (at r 28) the
    insert's radii: pi (28^2 - 25^2) 3 less two spandrel rings at r 28 - 0.2234 rc."""
    stock = "shape = \"revolve\"\nprofile = [[25, 0], [40, 0], [40, -50], [25, -50]]"
    tool = f'kind = "grooving"\nwidth = 3\ncorner_radius = {rc}\nhand = "{hand}"\nside = "inside"'
    program = f"G00 X46. Z2.\nM03 S500\nZ{z_ctrl}\nG01 X56. F0.05\nG00 X46.\nZ2.\n"
    res = _run(tmp_path, stock, tool, program, machine="start = [46, 0, 30]")
    assert res.report["warnings"] == []
    k = _k(res, math.pi * (40.0 ** 2 - 25.0 ** 2) * 50.0)
    groove = math.pi * (28.0 ** 2 - 25.0 ** 2) * 3.0
    spandrels = 2 * 2.0 * math.pi * (28.0 - SPANDREL * rc) * (1.0 - math.pi / 4.0) * rc ** 2
    slack = 2 * 2.0 * math.pi * 28.0 * TOL * (math.pi / 2.0 * rc) + 0.02
    assert abs(res.report["removed_volume"] - k * (groove - spandrels)) <= slack
    part = res.part  # the ring is where the program puts it: less material there than beside it
    inner = m3d.Manifold.cylinder(3.0, 26.5, circular_segments=256)
    assert _slab(part - inner.translate((0, 0, -20.0)), -20.0 + 0.01, -17.0 - 0.01, 40.0) < \
        _slab(part - inner.translate((0, 0, -17.0)), -17.0 + 0.01, -14.0 - 0.01, 40.0) * 0.95


@pytest.mark.parametrize("hand,r_lo", [("R", 12.0), ("L", 9.0), ("N", 10.5)])
@pytest.mark.parametrize("rc", [0.0, 0.3])
def test_face_groove_is_the_insert_width(tmp_path, hand, r_lo, rc):
    """A face grooving insert (X and Z swapped: its control point the corner towards -X for hand
    R, towards +X for L, the middle for N) at X24 plunged along -Z 3 deep into the end face: a
    ring r_lo .. r_lo + 3, pi ((r_lo + 3)^2 - r_lo^2) 3, less the two floor spandrels at radii
    r_lo + 0.2234 rc and r_lo + 3 - 0.2234 rc (each (1 - pi/4) rc^2)."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    tool = f'kind = "grooving"\nwidth = 3\ncorner_radius = {rc}\nhand = "{hand}"\nside = "face"'
    program = "G00 X24. Z2.\nM03 S500\nG01 Z-3. F0.05\nG00 Z2.\n"
    res = _run(tmp_path, stock, tool, program, machine="start = [24, 0, 30]")
    assert res.report["warnings"] == []
    k = _k(res, math.pi * 400.0 * 50.0)
    ring = math.pi * ((r_lo + 3.0) ** 2 - r_lo ** 2) * 3.0
    spandrels = 2.0 * math.pi * (2.0 * r_lo + 3.0) * (1.0 - math.pi / 4.0) * rc ** 2
    slack = 2 * 2.0 * math.pi * (r_lo + 3.0) * TOL * (math.pi / 2.0 * rc) + 0.02
    assert abs(res.report["removed_volume"] - k * (ring - spandrels)) <= slack, (res.report["removed_volume"], k * (ring - spandrels))


@pytest.mark.parametrize("shape", ["C", "D", "T", "V", "W", "S"])
@pytest.mark.parametrize("rn", [0.4, 1.2])
def test_face_insert_faces_to_a_square_wall(tmp_path, shape, rn):
    """A face tool of hand R (X and Z swapped: it points at the end face and feeds towards the
    axis, cutting edge position 3) faces 3 deep from beyond the bar in to X24 and leaves straight
    out along +Z: the face recess r 12 .. 20, 3 deep, less the spandrel the nose leaves in the
    corner at r 12, z -3 (centroid r 12 + 0.2234 rn)."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    tool = f'kind = "turning"\ninsert = "{shape}"\ntip_radius = {rn}\nside = "face"\nhand = "R"'
    program = "G00 X44. Z2.\nM03 S500\nZ-3.\nG01 X24. F0.1\nZ2.\nG00 X60.\n"
    res = _run(tmp_path, stock, tool, program, machine="start = [60, 0, 30]")
    assert res.report["warnings"] == []
    k = _k(res, math.pi * 400.0 * 50.0)
    recess = math.pi * (20.0 ** 2 - 12.0 ** 2) * 3.0
    spandrel = 2.0 * math.pi * (12.0 + SPANDREL * rn) * (1.0 - math.pi / 4.0) * rn ** 2
    slack = 2.0 * math.pi * 12.0 * TOL * (rn + 1.0) + 1e-6 * k * recess
    assert abs(res.report["removed_volume"] - k * (recess - spandrel)) <= slack, (res.report["removed_volume"], k * (recess - spandrel))


@pytest.mark.parametrize("shape,corner", [("D", 55.0), ("V", 35.0), ("T", 60.0)])
@pytest.mark.parametrize("rn", [0.0, 0.4])
def test_neutral_insert_plunges_its_v(tmp_path, shape, corner, rn):
    """A neutral holder (hand N) points the corner's bisector straight at the part, its control
    point the lowest point of the nose: plunged 1.5 deep into a bar of 40 it cuts the V of the
    corner angle with the nose radius (tests/stock/test_tool_properties.py's half width v(u)),
    a ring of 2 pi integral (18.5 + u) 2 v(u) du (quadrature of the closed-form v)."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    tool = f'kind = "turning"\ninsert = "{shape}"\ntip_radius = {rn}\nhand = "N"'
    res = _run(tmp_path, stock, tool, "G00 X44. Z-20.\nM03 S500\nG01 X37. F0.05\nG00 X44.\n",
               machine="start = [44, 0, 30]")
    assert res.report["warnings"] == []
    h = math.radians(corner / 2.0)
    ut = rn * (1.0 - math.sin(h))

    def v(u):
        return np.where(u <= ut, np.sqrt(np.clip(rn * rn - (rn - u) ** 2, 0.0, None)),
                        u * math.tan(h) + rn * (1.0 - math.sin(h)) / math.cos(h))

    u = np.linspace(0.0, 1.5, 200001)
    f = 2.0 * math.pi * (18.5 + u) * 2.0 * v(u)
    expect = float(np.sum((f[1:] + f[:-1]) * 0.5 * np.diff(u)))
    k = _k(res, math.pi * 400.0 * 50.0)
    assert abs(res.report["removed_volume"] - k * expect) <= 2e-3 * expect + 0.02, (res.report["removed_volume"], k * expect)


# -- threads inside, outside, full profile ------------------------------------------------------
TUBE = "shape = \"revolve\"\nprofile = [[11, 0], [20, 0], [20, -30], [11, -30]]"
TUBE_TRUE = math.pi * (400.0 - 121.0) * 30.0


def _groove_per_mm(depth: float, r_base: float, inward: bool, lead: float) -> float:
    """Material per mm of a 60 degree sharp V groove ``depth`` deep cut from a surface at
    ``r_base`` (outwards into the wall for an inside thread, inwards for an outside one)."""
    area = depth ** 2 * math.tan(math.radians(30.0))
    rc = r_base + depth / 3.0 if inward else r_base - depth / 3.0
    return 2.0 * math.pi * rc * area / lead


@pytest.mark.parametrize("spindle,z_end,z_start", [("M03", -20.0, 3.0), ("M04", -20.0, 3.0)])
def test_inside_thread_cuts_only_its_groove(tmp_path, spindle, z_end, z_start):
    """The issue's reproducer: an inside thread tool in a bore of 22 cuts a 0.5 mm groove into
    the wall, nothing else (the whole wall went before)."""
    tool = 'kind = "thread"\nside = "inside"\nheight = 4'
    program = f"G00 X20. Z{z_start}\n{spindle} S500\nX23.\nG33 Z{z_end} F1.5\nG00 X20.\nZ10.\n"
    res = _run(tmp_path, TUBE, tool, program)
    k = _k(res, TUBE_TRUE)
    per_mm = _groove_per_mm(0.5, 11.0, True, 1.5)
    # the stock in a slab clear of the ends, less what the helix takes (the slab is not whole
    # turns: a helical groove holds the same material in every mm)
    stock_slab = k * math.pi * (400.0 - 121.0) * 10.0
    removed = stock_slab - _slab(res.part, -15.0, -5.0, 20.0)
    # the sweep's stations follow chords of the helices, within TOL of them: at most a layer TOL
    # thick across the groove's mouth (2 x 0.5 tan 30 wide) either way
    slack = 2.0 * math.pi * 11.5 * (2.0 * 0.5 * math.tan(math.radians(30.0))) * TOL / 1.5 * 10.0
    assert abs(removed - k * per_mm * 10.0) <= slack, (removed, per_mm * 10.0, slack)
    # only the retract out of the groove's end touches the wall (a ring, as docs/setup.md says)
    assert [w["line"] for w in res.report["warnings"]] in ([], [5])


def _groove_moments(depth: float, half_tip: float, rr: float, r_tip: float, sign: int) -> tuple[float, float]:
    """(area, first moment about the axis) of a 60 degree groove's section from its tip (at radius
    ``r_tip``) ``depth`` towards the crest (``sign`` +1: outwards): half-width w(u) at u from the
    tip is half_tip + u tan30 for a flat tip, sqrt(rr^2 - (rr - u)^2) on a nose of radius rr up
    to u = rr/2 and (u + rr) tan30 beyond; integrated numerically on a fine grid."""
    u = np.linspace(0.0, depth, 400001)
    t30 = math.tan(math.radians(30.0))
    if rr:
        w = np.where(u <= rr / 2.0, np.sqrt(np.maximum(0.0, rr ** 2 - (rr - u) ** 2)), (u + rr) * t30)
    else:
        w = half_tip + u * t30
    area = np.trapezoid(2.0 * w, u)
    return float(area), float(np.trapezoid(2.0 * w * (r_tip + sign * u), u))


@pytest.mark.parametrize("side", ["outside", "inside"])
@pytest.mark.parametrize("root", [0.0, 0.125])
def test_full_profile_thread_cuts_its_crest(tmp_path, side, root):
    """A full-profile insert of pitch 1.5 at its full depth cuts the crest too: outside on a bar
    of 24.4 everything beyond the major radius 12 goes (its shoulders), inside in a bore of 21.6
    everything within D1/2 = 12 - 5H/8; between, the ISO 68-1 groove (tip flat P/4 outside, P/8
    inside, or rounded with ``tip_radius``; crest 7H/8 resp. 3H/4 above the fundamental apex)."""
    p = 1.5
    big_h = math.sqrt(3.0) / 2.0 * p
    rr = root * p
    t30 = math.tan(math.radians(30.0))
    if side == "outside":
        stock = "shape = \"cylinder\"\ndiameter = 24.4\nz = [-30, 0]"
        r_lo, r_hi = 0.0, 12.2
        apex_to_crest, flat = 7.0 * big_h / 8.0, p / 8.0
        r_crest, sign = 12.0, 1
    else:
        stock = "shape = \"revolve\"\nprofile = [[10.8, 0], [20, 0], [20, -30], [10.8, -30]]"
        r_lo, r_hi = 10.8, 20.0
        apex_to_crest, flat = 3.0 * big_h / 4.0, p / 16.0
        r_crest, sign = 12.0 - 5.0 * big_h / 8.0, -1
    tip_trunc = rr if rr else flat / t30
    depth = apex_to_crest - tip_trunc
    r_tip = r_crest - sign * depth
    x_out = 26.0 if side == "outside" else 20.0
    program = f"G00 X{x_out} Z3.\nM03 S500\nX{2 * r_tip:.6f}\nG33 Z-20. F{p}\nG00 X{x_out}\nZ10.\n"
    tool = f'kind = "thread"\nform = "full"\npitch = {p}\ntip_radius = {rr}\nside = "{side}"\nheight = 3'
    res = _run(tmp_path, stock, tool, program)
    k = _k(res, math.pi * (r_hi ** 2 - r_lo ** 2) * 30.0)
    area, moment = _groove_moments(depth, 0.0 if rr else flat, rr, r_tip, sign)
    beyond = abs(r_hi ** 2 - r_crest ** 2) if side == "outside" else r_crest ** 2 - r_lo ** 2
    expect = k * (math.pi * beyond * 10.0 + 2.0 * math.pi * moment / p * 10.0)
    removed = k * math.pi * (r_hi ** 2 - r_lo ** 2) * 10.0 - _slab(res.part, -15.0, -5.0, 20.0)
    slack = 2.0 * math.pi * 12.2 * p * TOL / p * 10.0  # a layer TOL thick over the whole pitch (chords)
    assert abs(removed - expect) <= slack, (removed, expect, slack)
    assert all(w["line"] == 5 for w in res.report["warnings"])


# -- cutting edge positions ----------------------------------------------------------------------
@pytest.mark.parametrize("kind,extra,side,expect", [
    ("turning", {"insert": "C", "hand": "R"}, "outside", 3),
    ("turning", {"insert": "C", "hand": "L"}, "outside", 4),
    ("turning", {"insert": "C", "hand": "R"}, "inside", 2),
    ("turning", {"insert": "C", "hand": "L"}, "inside", 1),
    ("turning", {"insert": "D", "hand": "N"}, "outside", 8),
    ("turning", {"insert": "D", "hand": "N"}, "inside", 6),
    ("turning", {"insert": "D", "hand": "N"}, "face", 7),
    ("thread", {}, "outside", 8),
    ("thread", {}, "inside", 6),
    ("grooving", {"hand": "R", "width": 3.0}, "outside", 3),
    ("turning", {}, "outside", 8),
    ("profile", {"points": ((0.0, 0.0), (1.0, 1.0), (1.0, -1.0))}, "outside", 9),
])
def test_edge_position(kind, extra, side, expect):
    """The cutting edge position from where the tool's point lies from its nose centre (X up,
    Z right; docs/setup.md's figure)."""
    assert ToolSpec(1, kind, side=side, **extra).edge_position == expect


# -- thread hand, taper and face ----------------------------------------------------------------
@pytest.mark.parametrize("spindle,rho", [("M03", 1), ("M04", -1)])
def test_inside_thread_hand(tmp_path, spindle, rho):
    """The inside groove's root in the half-plane at phi lies where the tool point passes phi:
    z = z0 - sigma L (rho phi) / 360 (mod L), feeding sigma = -1 from z0 = 3 (tests/test_lathe_geometry
    derives it): M03 a right-hand thread, M04 a left-hand one, as outside."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from support.geometry import load, section, wrap

    tool = 'kind = "thread"\nside = "inside"\nheight = 4'
    res = _run(tmp_path, TUBE, tool, f"G00 X20. Z3.\n{spindle} S500\nX23.\nG33 Z-20. F1.5\nG00 X20.\nZ10.\n")
    mesh = load(res)
    for phi in (0.0, 90.0, 200.0, 321.7):
        pts = section(mesh, phi).reshape(-1, 2)
        roots = pts[(pts[:, 0] > 11.5 - 5 * TOL) & (pts[:, 0] < 15.0) & (pts[:, 1] < -2.0) & (pts[:, 1] > -18.0)]
        assert len(roots) >= 10, phi
        expect = 3.0 + 1.5 * rho * phi / 360.0
        assert np.all(np.abs(wrap(roots[:, 1] - expect, 1.5)) < 0.02), (phi, roots[:5])


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
def test_inside_taper_thread(tmp_path, dialect):
    """An inside taper thread (G33 with X and Z: 1:12 on the diameter; CNC8x6 F1.5, ISG K1.5, both
    the lead along Z, the larger travel) in a taper bore: the
    groove per mm at the middle of the slab is the V's, its depth 0.5 everywhere (the tool
    follows the bore's taper), so the slab loses 2 pi r_c A / P per mm with r_c at the slab's
    middle radius (a cone: exact, r_c varies linearly with z)."""
    stock = "shape = \"revolve\"\nprofile = [[11, 0], [20, 0], [20, -30], [12.25, -30]]"
    # bore r = 11 - z / 24 (1:12 on the diameter), the tool point 0.5 beyond it
    program = ("G00 X20. Z3.\nM03 S500\nX" + f"{2 * (11.5 - 3.0 / 24.0):.6f}" +
               "\nG33 X" + f"{2 * (11.5 + 20.0 / 24.0):.6f}" + " Z-20. F1.5\nG00 X20.\nZ10.\n")
    if dialect == "isg":  # G51: X in diameters, as on CNC8x6
        program = "G51\n" + program.replace(" F1.5", " K1.5")
    tool = 'kind = "thread"\nside = "inside"\nheight = 4'
    res = _run(tmp_path, stock, tool, program, dialect=dialect)
    assert all(w["line"] == (5 if dialect == "cnc8x6" else 6) for w in res.report["warnings"])
    true = math.pi * 30.0 * (400.0 - (11.0 ** 2 + 11.0 * 12.25 + 12.25 ** 2) / 3.0)
    k = _k(res, true)

    def cone(z0: float, z1: float) -> float:  # the stock between heights z0 < z1
        ra, rb = 11.0 - z1 / 24.0, 11.0 - z0 / 24.0
        return math.pi * (z1 - z0) * (400.0 - (ra * ra + ra * rb + rb * rb) / 3.0)

    removed = k * cone(-15.0, -5.0) - _slab(res.part, -15.0, -5.0, 20.0)
    # depth measured along X; the V stands square to the axis, the bore slopes 1/24: its section
    # in the bore is the V's up to first order in the slope (1/24^2 = 0.2 %)
    area = 0.25 * math.tan(math.radians(30.0))
    expect = k * 2.0 * math.pi * (11.0 + 10.0 / 24.0 + 0.5 / 3.0) * area / 1.5 * 10.0
    assert abs(removed - expect) <= 0.01 * expect, (removed, expect)


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
def test_face_thread_scroll(tmp_path, dialect):
    """A G33 along X with a face tool (CNC8x6 F2; ISG I2, the lead along X as a radial distance)
    cuts a scroll (an Archimedean spiral groove) into the end face: between radii r1 and r2 it
    holds A 2 pi / P (r2^2 - r1^2) / 2 of material (every mm of radius holds the groove's section
    A swept round at that radius, once per lead P)."""
    stock = "shape = \"cylinder\"\ndiameter = 60\nz = [-10, 0]"
    tool = 'kind = "thread"\nside = "face"\nheight = 3'
    machine = "start = [64, 0, 5]"
    program = "G00 X64. Z2.\nM03 S300\nZ-0.5\nG33 X10. F2.\nG00 Z5.\n"
    if dialect == "isg":  # G51: X in diameters, as on CNC8x6
        program = "G51\n" + program.replace(" F2.", " I2.")
    res = _run(tmp_path, stock, tool, program, machine=machine, dialect=dialect)
    bare = _run(tmp_path, stock, tool, ("G51\n" if dialect == "isg" else "") + "G00 X64. Z5.\n", machine=machine,
                dialect=dialect)
    # the retract out of the groove's end
    assert [w["line"] for w in res.report["warnings"]] == [5 if dialect == "cnc8x6" else 6]
    window = m3d.Manifold.revolve(m3d.CrossSection([np.array([[10.0, -2.0], [25.0, -2.0], [25.0, 1.0], [10.0, 1.0]])]),
                                  circular_segments=4096)
    removed = (bare.part ^ window).volume() - (res.part ^ window).volume()
    area = 0.25 * math.tan(math.radians(30.0))
    expect = area * 2.0 * math.pi / 2.0 * (25.0 ** 2 - 10.0 ** 2) / 2.0
    assert abs(removed - expect) <= 2e-3 * expect, (removed, expect)


# -- axial tools on a lathe --------------------------------------------------------------------
@pytest.mark.parametrize("point_angle", [118.0, 90.0, 180.0])
def test_drill_on_the_spindle_axis(tmp_path, point_angle):
    """A drill of 10 fed along Z at X0 with the spindle turning drills its hole: a cylinder of
    radius 5 down to where the point begins, the point's cone (height 5 / tan(angle/2)) below,
    the tip at Z-20: pi r^2 (20 - hp) + pi r^2 hp / 3."""
    stock = "shape = \"cylinder\"\ndiameter = 40\nz = [-50, 0]"
    tool = f'kind = "drill"\ndiameter = 10\npoint_angle = {point_angle}\nlength = 60'
    res = _run(tmp_path, stock, tool, "G00 X0 Z5.\nM03 S800\nG01 Z-20. F0.1\nG00 Z5.\nX50.\n")
    assert res.report["warnings"] == []
    k = _k(res, math.pi * 400.0 * 50.0)
    hp = 0.0 if point_angle == 180.0 else 5.0 / math.tan(math.radians(point_angle / 2.0))
    expect = math.pi * 25.0 * (20.0 - hp) + math.pi * 25.0 * hp / 3.0
    # the hole's polygon has the stock's segment count (k); the point's vertex is exact
    assert abs(res.report["removed_volume"] - k * expect) <= 1e-6 * expect + 1e-3, (res.report["removed_volume"], expect)


def test_shoulder_example_fails_when_spoiled(tmp_path):
    """examples/cnc8x6-lathe/shoulder-93 passes its checks (tests/app/test_examples.py) and fails
    them with the plain V for the insert (a cone behind the shoulder), a finishing pass 0.1 mm
    shallower, the shoulder shifted 0.1 mm (every pass to Z-19.9) or a holder of the wrong hand
    (hand L: its minor edge leads towards -Z, its rapids into the bar warn, no square shoulder)."""
    from conftest import REPO_EXAMPLES

    base = REPO_EXAMPLES / "cnc8x6-lathe" / "shoulder-93"
    setup, program = base.with_suffix(".toml").read_text(), base.with_suffix(".nc").read_text()
    v_tool = setup.replace('insert = "C"\nsize = 12.7\ntip_radius = 0.8\napproach = 93.0\nhand = "R"', "")
    left = setup.replace('hand = "R"', 'hand = "L"')
    assert v_tool != setup and left != setup and "Z-20." in program
    for text, prog, failing, warns in (
            (v_tool, program, {"behind the shoulder", "shoulder face", "removed"}, False),
            (setup, program.replace("N110 X30.", "N110 X30.2"), {"turned", "removed"}, False),
            (setup, program.replace("Z-20.", "Z-19.9"), {"shoulder face", "removed"}, False),
            (left, program, {"behind the shoulder", "shoulder face", "removed"}, True)):
        path = tmp_path / "s.toml"
        path.write_text(text)
        res = cutsim.simulate("p.nc", str(path), text=prog)
        assert {c["name"] for c in res.report["checks"] if not c["passed"]} == failing
        assert bool(res.report["warnings"]) == warns


def test_nut_example_fails_when_spoiled(tmp_path):
    """examples/cnc8x6-lathe/nut-m24x1.5 passes its checks (tests/app/test_examples.py) and fails
    its volume and its M24x1.5-6H thread with the last thread pass at X23.9 instead of X24.1 (the
    groove 0.1 mm shallower, the shoulders no longer reaching the bore: about 95 mm^3 less, and the
    major diameter under 24)."""
    from conftest import REPO_EXAMPLES

    base = REPO_EXAMPLES / "cnc8x6-lathe"
    program = (base / "nut-m24x1.5.nc").read_text()
    spoiled = program.replace("N170 X24.1", "N170 X23.9")
    assert spoiled != program
    res = cutsim.simulate("p.nc", str(base / "nut-m24x1.5.toml"), text=spoiled)
    assert {c["name"] for c in res.report["checks"] if not c["passed"]} == {"removed", "M24x1.5-6H"}
