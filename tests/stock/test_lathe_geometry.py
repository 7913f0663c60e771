"""The simulated thread solids against analytic geometry, measured independently of cutsim.

Every number asserted here comes from the program and the conventions (conventions.md), never
from cutsim: the part is sliced with trimesh in the axial half-plane at angle ``phi`` and the
groove roots are the local minima of the outer profile r(z) (tests/support/geometry.py).

Groove phase. With the spindle turning ``rho`` (+1 M03, -1 M04) and the tool feeding ``sigma``
(+1 towards +Z, -1 towards -Z) from ``z0`` after waiting for the start angle ``a`` past the zero
pulse, the spindle angle is theta = a + 360*(z - z0)*sigma/L and the tool meets the workpiece at
phi = -rho*theta. Hence a groove at the fixed angle phi lies at

    z = z0 - sigma * L * (rho*phi + a) / 360      (mod L)

which for M03 feeding -Z is conventions.md's z = z0 + L*(phi + a)/360 (right-hand), and flips the
hand when either the spindle or the feed direction is reversed.

Roots. Within the half-plane at phi the screw sweep contains the tool profile exactly where the
tool passes phi, so each root is the tool point at that instant: r = programmed X/2, or on a
ramp r = r0 +/- d*tan(alpha) with d the axial distance into the ramp. Between the sweep's
stations the solid follows chords of the helix, which lie inside it by at most the tolerance, so
the roots may be up to ``tol`` deeper than programmed and never shallower.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import cutsim
from conftest import EXAMPLES
from support.geometry import groove_roots, load, outer_radius, section, wrap

LATHE = EXAMPLES / "cnc8x6-lathe"
TOL = 0.002  # chordal tolerance of the runs that check micrometres
PHIS = (0.0, 90.0, 200.0, 321.7)


def run(name: str, tol: float = TOL):
    return cutsim.simulate(str(LATHE / f"{name}.nc"), str(LATHE / f"{name}.toml"), tolerance=tol)


def phase_z(phi, z0, lead, a=0.0, rho=1, sigma=-1):
    """Axial position of the groove at angle phi, modulo the lead (see the module docstring)."""
    return z0 - sigma * lead * (rho * phi + a) / 360.0


def assert_roots(roots, expect_r, tol, what):
    """Every root at most ``tol`` deeper than the programmed radius and not shallower, give or
    take the rounding of float32 mesh vertices (one float32 step at r = 128 is 7.6e-6 mm)."""
    err = roots[:, 1] - expect_r
    slack = np.spacing(np.float32(np.max(roots[:, 1]))).item()
    assert np.all(err <= slack) and np.all(err >= -tol - slack), f"{what}: root errors {err}"


def assert_phase(roots, z0, lead, tol, **kw):
    for phi, rts in roots.items():
        dz = wrap(rts[:, 0] - phase_z(phi, z0, lead, **kw), lead)
        assert np.all(np.abs(dz) < tol), f"phi={phi}: groove off its helix by {dz}"


# -- multipass: three passes, one groove (re-synchronised at the zero pulse) -------------------

@pytest.fixture(scope="module")
def multipass():
    r = run("multipass")
    mesh = r.mesh()
    return r, {phi: groove_roots(section(mesh, phi), -8.0, 0.0, 13.45, 0.5) for phi in PHIS}


def test_multipass_root_diameter(multipass):
    _, roots = multipass
    for phi, rts in roots.items():
        assert len(rts) >= 4, (phi, rts)  # 8 mm of thread at lead 1.5, minus the range margins
        assert_roots(rts, 26.177 / 2, TOL, f"phi={phi}")


def test_multipass_passes_share_one_right_hand_groove(multipass):
    # M03 feeding -Z from Z3: right-hand, z = 3 + 1.5*phi/360 (mod 1.5). A pass that drifted
    # would show as a second, shallower root per lead.
    _, roots = multipass
    assert_phase(roots, 3.0, 1.5, 1e-4)
    for rts in roots.values():
        assert np.all(np.diff(rts[:, 0]) > 1.5 - 1e-3)


# -- start offset, M04: left-hand thread rotated 180 degrees -------------------------------------

def test_start_offset_left_hand_180():
    r = run("start-offset")
    mesh = r.mesh()
    for phi in PHIS:
        rts = groove_roots(section(mesh, phi), 199.9, 203.0, 17.45, 0.5)
        assert len(rts) >= 1
        assert_roots(rts, 34.0 / 2, TOL, f"phi={phi}")
        # M04 (rho=-1) feeding -Z (sigma=-1) from Z205 with I180: z = 205 + 1.5*(180 - phi)/360
        dz = wrap(rts[:, 0] - phase_z(phi, 205.0, 1.5, a=180.0, rho=-1, sigma=-1), 1.5)
        assert np.all(np.abs(dz) < 1e-4), (phi, dz)
        # and not the right-hand groove, nor the unrotated left-hand one
        assert np.all(np.abs(wrap(rts[:, 0] - phase_z(phi, 205.0, 1.5, a=180.0), 1.5)) > 0.05) or phi in (0.0, 180.0)
        assert np.all(np.abs(wrap(rts[:, 0] - phase_z(phi, 205.0, 1.5, a=0.0, rho=-1), 1.5)) > 0.7)


# -- lead-in: X71.798 -> X64 over the first 12 mm at 18 degrees (R16 = 118.0) --------------------

def test_lead_in_ramp_and_phase():
    r = run("lead-in")
    mesh = r.mesh()
    tan18 = math.tan(math.radians(18.0))
    r_start, z_start = 71.798 / 2, -100.0
    r_end = r_start - 12.0 * tan18  # 31.999965: X64 after 12 mm
    assert r_end == pytest.approx(32.0, abs=5e-5)
    on_ramp = 0
    for phi in (45.0, 200.0, 300.0, 10.0):
        rts = groove_roots(section(mesh, phi), -100.0, 0.0, 35.69, 2.0)
        # M04 feeding +Z: right-hand, z = -100 + 6*phi/360 (mod 6)
        dz = wrap(rts[:, 0] - phase_z(phi, z_start, 6.0, rho=-1, sigma=1), 6.0)
        assert np.all(np.abs(dz) < 1e-4), (phi, dz)
        d = rts[:, 0] - z_start
        expect = np.where(d < 12.0, r_start - d * tan18, r_end)
        assert_roots(rts, expect, TOL, f"phi={phi}")
        on_ramp += int(np.sum(d < 12.0))
        assert len(rts) >= 15
    assert on_ramp >= 5


# -- lead-in with the lead-in axis programmed: the thread ends at the programmed X ------------------
# The manual's lead-in example (X71.798 Z-100, 18 degrees from R16, E12.) with X60. added to the
# thread block. The lead-in ramps from the start point (seed 000, 5.3) and the thread ends at the
# programmed end point like every G33: its line runs from where the manual's straight thread would
# start, r0' = 71.798/2 - 12*tan 18 (the lead-in's reach), to r = 30 at Z3, and over the first
# 12 mm the tool comes in to that line from the start, 12*tan 18 outside it at Z-100 and on it
# at Z-88. Without X the same block cuts the manual's straight thread at r0'.

LEADIN_SETUP = (LATHE / "lead-in.toml").read_text() if LATHE.is_dir() else ""
LEADIN_TAPER = ("N10 M04  S50\nN20 X71.798  Z-100.  R16=118.0\nN30 X60. Z3 F6.0 E12. G33\nN40\n"
                "N50 X80. Z3 G0\n")


def leadin_line(z):
    """Root radius the taper lead-in cuts at height z (see above)."""
    tan18 = math.tan(math.radians(18.0))
    r0 = 71.798 / 2 - 12.0 * tan18
    d = z + 100.0  # lead-axis travel from the start
    line = r0 + (30.0 - r0) * d / 103.0
    return np.where(d < 12.0, line + (12.0 - d) * tan18, line)


def test_lead_in_with_x_programmed_ends_at_x_and_warns():
    from cutsim.interp import InterpConfig, interpret
    cfg = InterpConfig(dialect="cnc8x6", diameter_programming=True, start=(80.0, 0.0, -110.0),
                       constants={8: 15160000})
    taper = interpret("t.nc", LEADIN_TAPER, cfg)
    assert taper.last_cut_position == pytest.approx((60.0, 0.0, 3.0), abs=1e-12)  # was X56.202 (60 - 3.798)
    (src, msg), = taper.warnings
    assert src.line == 3 and "X60. programmed" in msg and "tapers" in msg
    straight = 71.798 - 2 * 12.0 * math.tan(math.radians(18.0))  # 63.99993: the manual's X64
    plain = interpret("t.nc", LEADIN_TAPER.replace("X60. Z3", "Z3"), cfg)
    assert plain.last_cut_position == pytest.approx((straight, 0.0, 3.0), abs=1e-12) and plain.warnings == []
    # X programmed at the straight thread's value: the same cut as without X, nothing to warn about
    same = interpret("t.nc", LEADIN_TAPER.replace("X60. Z3", f"X{straight:.6f} Z3"), cfg)
    assert same.warnings == []
    assert same.last_cut_position == pytest.approx(plain.last_cut_position, abs=1e-6)


def test_lead_in_taper_roots(tmp_path):
    (tmp_path / "s.toml").write_text(LEADIN_SETUP)
    r = cutsim.simulate("taper-lead-in.nc", str(tmp_path / "s.toml"), tolerance=TOL, text=LEADIN_TAPER)
    assert any("tapers" in w["message"] for w in r.warnings), r.warnings
    mesh = r.mesh()
    on_ramp = 0
    for phi in (45.0, 200.0, 300.0, 10.0):
        rts = groove_roots(section(mesh, phi), -100.0, 0.0, 35.69, 2.0)
        dz = wrap(rts[:, 0] - phase_z(phi, -100.0, 6.0, rho=-1, sigma=1), 6.0)  # M04 feeding +Z
        assert np.all(np.abs(dz) < 1e-4), (phi, dz)
        assert_roots(rts, leadin_line(rts[:, 0]), TOL, f"phi={phi}")
        on_ramp += int(np.sum(rts[:, 0] < -88.0))
        assert len(rts) >= 15
    assert on_ramp >= 5


# -- runouts: the last 12 mm of Z-100 climb outwards -------------------------------------------------

@pytest.mark.parametrize("name,angle", [("runout-constant", 12.5), ("runout-parameter", 20.0)])
def test_runout_ramp_and_phase(name, angle):
    r = run(name)
    mesh = r.mesh()
    tana = math.tan(math.radians(angle))
    on_ramp = 0
    for phi in (0.0, 90.0, 200.0, 321.7):
        # stay 2.5 mm clear of Z-100, where runout-constant's N50 rapid revolves a ring
        rts = groove_roots(section(mesh, phi), -98.0, 0.0, 35.69, 2.0)
        dz = wrap(rts[:, 0] - phase_z(phi, 5.0, 6.0), 6.0)  # M03 feeding -Z from Z5: right-hand
        assert np.all(np.abs(dz) < 1e-4), (phi, dz)
        d = -88.0 - rts[:, 0]  # distance into the runout, which starts 12 mm before Z-100
        expect = np.where(d > 0, 32.0 + d * tana, 32.0)
        assert_roots(rts, expect, TOL, f"{name} phi={phi}")
        on_ramp += int(np.sum(d > 0))
    assert on_ramp >= 4


# -- taper: roots on the cone 113 -> 123 over Z3..-100 ---------------------------------------------

def test_taper_roots_follow_the_cone():
    tol = TOL
    r = run("taper", tol)
    mesh = r.mesh()
    cone = lambda z: 113.0 + (3.0 - z) * 10.0 / 103.0  # noqa: E731
    for phi in (0.0, 200.0):
        segs = section(mesh, phi)
        rts = groove_roots(segs, -97.0, 0.0, 200.0, 0.5)
        crest = outer_radius(segs, rts[:, 0] + 0.75)  # half a lead away: the uncut cone stock
        rts = rts[rts[:, 1] < crest - 0.1]
        assert len(rts) >= 60
        assert_phase({phi: rts}, 3.0, 1.5, 1e-4)
        assert_roots(rts, cone(rts[:, 0]), tol, f"taper phi={phi}")


# -- large lead: 250 mm/rev from R10 ------------------------------------------------------------

def test_large_lead_250():
    r = run("large-lead", 0.005)
    mesh = r.mesh()
    # M03 feeding +Z from Z-60: left-hand, z = -60 - 250*phi/360 (mod 250); one groove per angle
    for phi in (90.0, 180.0, 200.0, 250.0):
        rts = groove_roots(section(mesh, phi), 0.0, 150.0, 29.9, 5.0)
        assert len(rts) == 1, (phi, rts)
        dz = wrap(rts[:, 0] - phase_z(phi, -60.0, 250.0, sigma=1), 250.0)
        assert abs(dz[0]) < 1e-3, (phi, dz)
        assert_roots(rts, 25.0, 0.005, f"phi={phi}")


# -- removed volume of one full-depth pass through a plain bar ------------------------------------

VOLUME_SETUP = """[machine]
kind = "lathe"
dialect = "cnc8x6"
start = [40.0, 0.0, 8.0]
[stock]
shape = "cylinder"
diameter = 30.0
z = [-32.0, 0.0]
[[tool]]
number = 1
kind = "thread"
angle = 60.0
"""
# X22 from Z8 to Z-40: the 60-degree V (half width 4*tan30 = 2.31 at the bar surface) enters and
# leaves through the end faces; rapids at Z8 and Z-40 stay clear of the bar.
VOLUME_PROGRAM = "N10 G00 G95 M03 S200 X22. Z8.\nN20 G33 Z-40. F8. I0.\nN30 G00 X40.\n"


def screw_volume(R, r0, lead, length, half_angle):
    """Exact volume a screw sweep of a V (tip at r0) removes from a bar of radius R and length
    ``length`` when the sweep runs through both end faces and ``length`` is a whole number of
    leads. At angle phi the section holds one V per lead at z_k = c(phi) + k*lead; over a turn
    c sweeps one lead, so sum_k and the phi integral become (2*pi/lead) * integral dc, and
    integral dc of the V's part inside the slab = length * (V's area moment):
        V = (2*pi/lead) * length * int_{r0}^{R} r * 2*(r - r0)*tan(half) dr
          = (2*pi/lead) * length * 2*tan(half) * ((R^3 - r0^3)/3 - r0*(R^2 - r0^2)/2).
    """
    t = math.tan(math.radians(half_angle))
    return 2 * math.pi / lead * length * 2 * t * ((R**3 - r0**3) / 3 - r0 * (R**2 - r0**2) / 2)


def _volume_error(tmp_path, tol):
    (tmp_path / "bar.toml").write_text(VOLUME_SETUP)
    r = cutsim.simulate("bar.nc", str(tmp_path / "bar.toml"), tolerance=tol, text=VOLUME_PROGRAM)
    assert r.warnings == []
    removed = r.stock.volume() - r.part.volume()
    truth = screw_volume(15.0, 11.0, 8.0, 32.0, 30.0)  # 3172.94 mm^3
    return removed / truth - 1.0


def test_full_pass_removes_the_screw_volume(tmp_path):
    # measured: -0.009 % at tol 0.002 (profile edges subdivided to chord length; the residual is
    # the polygonal bar, which holds slightly less material than the round one)
    assert abs(_volume_error(tmp_path, 0.002)) < 1e-3


def test_full_pass_volume_within_0_05_percent(tmp_path):
    assert abs(_volume_error(tmp_path, 0.002)) < 5e-4


def test_lead_finer_than_the_tolerance_is_the_turned_groove(tmp_path):
    """G33 with a lead of 1 um at tolerance 0.2 (fuzz seed 20261126 case 42440: 12,000 turns, the
    screw sweep's teeth 1 um wide took minutes): within the tolerance the cut is the revolved
    sweep of the profile along the path (stock/strategy_turning.py fine_screw), so at every angle the part's
    radius over the cut length is the programmed X/2 = 14 within the tolerance, and the bar keeps
    its 15 mm radius above the tool's start."""
    (tmp_path / "fine.nc").write_text("N10 M03 S100 X28. Z2.\nN20 G33 Z-20. F0.001\nN30 G00 X40.\n")
    (tmp_path / "fine.toml").write_text(
        '[machine]\nkind = "lathe"\ndialect = "cnc8x6"\ndiameter_programming = true\nstart = [40.0, 0.0, 5.0]\n'
        '[stock]\nshape = "cylinder"\ndiameter = 30.0\nz = [-12.0, 0.0]\n'
        '[[tool]]\nnumber = 1\nkind = "thread"\nangle = 60.0\n')
    tol = 0.2
    res = cutsim.simulate(str(tmp_path / "fine.nc"), str(tmp_path / "fine.toml"), tolerance=tol)
    mesh = load(res)
    assert mesh.is_watertight and mesh.is_volume
    zs = np.linspace(-11.5, -0.5, 23)
    for phi in PHIS:
        r = outer_radius(section(mesh, phi), zs)
        assert np.all(np.abs(r - 14.0) <= tol + 1e-5), (phi, r)
