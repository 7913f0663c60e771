"""Centre drills and taps on a lathe's spindle axis against closed forms (docs/setup.md, [[tool]]).

A centre drill fed along Z at X0 with the spindle turning leaves the solid of revolution of its
section: frustums pi h (r1^2 + r1 r2 + r2^2) / 3 (pilot point, pilot, countersink) cut off at the
face. A tap under G33 makes the ISO 68-1 nut groove: at radius r the groove is
w(r) = P/8 + 2 tan 30 (D/2 - r) wide, so between the bore r_b and D/2 a helix of lead P holds
(2 pi / P) integral r w(r) dr per mm (the screw form of Pappus); its root is the tap's crest at
D/2, centred where a thread tool's point would be: z0 + P rho phi / 360 (mod P).
Revolved volumes carry the stock polygon's factor k (tests/stock/test_lathe_tools.py).
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import cutsim
from cutsim.base.specs import ToolSpec
from cutsim.interp.errors import CutsimError

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from test_lathe_tools import TOL, _k, _run, _slab  # noqa: E402

T30 = math.tan(math.radians(30.0))


def _frustums(rows: list[tuple[float, float]], depth: float) -> float:
    """Volume of the solid of revolution of the outline ``rows`` (r, height above the tip), tip at
    -depth, below the face z = 0."""
    vol = 0.0
    for (r0, v0), (r1, v1) in zip(rows, rows[1:]):
        if v1 <= v0:  # a flat step (a flat pilot end)
            continue
        top = min(v1, depth)
        if top <= v0:
            break
        r_top = r0 + (r1 - r0) * (top - v0) / (v1 - v0)
        vol += math.pi * (top - v0) * (r0 * r0 + r0 * r_top + r_top * r_top) / 3.0
    return vol


@pytest.mark.parametrize("countersink", [60.0, 90.0])
@pytest.mark.parametrize("d,body,pilot,point", [(2.5, 6.3, 3.1, 118.0), (1.0, 3.15, 1.3, 120.0), (4.0, 10.0, 5.0, 180.0)])
@pytest.mark.parametrize("frac", [0.3, 0.8])
def test_centre_drill_hole(tmp_path, countersink, d, body, pilot, point, frac):
    """Fed to where the countersink is ``frac`` of the way up to the body's diameter."""
    rp, rb = d / 2.0, body / 2.0
    hp = 0.0 if point == 180.0 else rp / math.tan(math.radians(point / 2.0))
    cone = (rb - rp) / math.tan(math.radians(countersink / 2.0))
    rows = [(0.0, 0.0), (rp, hp), (rp, pilot), (rb, pilot + cone), (rb, pilot + cone + 3 * body)]
    if hp == 0.0:
        rows = [(0.0, 0.0), (rp, 0.0)] + rows[2:]
    depth = pilot + frac * cone
    stock = "shape = \"cylinder\"\ndiameter = 30\nz = [-40, 0]"
    tool = (f'kind = "centredrill"\ndiameter = {d}\nbody_diameter = {body}\npilot_length = {pilot}\n'
            f'point_angle = {point}\ncountersink = {countersink}')
    res = _run(tmp_path, stock, tool, f"G00 X0 Z5.\nM03 S1200\nG01 Z{-depth:.6f} F0.05\nG00 Z5.\nX40.\n")
    assert res.report["warnings"] == []
    k = _k(res, math.pi * 225.0 * 40.0)
    expect = k * _frustums(rows, depth)
    assert abs(res.report["removed_volume"] - expect) <= 1e-6 * expect + 1e-4, (res.report["removed_volume"], expect)


def test_centre_drill_defaults_and_ranges(tmp_path):
    """DIN 333 A proportions by default; the countersink is 60 or 90 degrees; a centre drill is no
    mill tool."""
    t = ToolSpec(1, "centredrill", diameter=2.0, body_diameter=5.0, pilot_length=2.4, length=30.0)
    from cutsim.stock.tools import tool_problem

    assert tool_problem(t) is None
    assert tool_problem(ToolSpec(1, "centredrill", diameter=2.0, body_diameter=5.0, pilot_length=2.4,
                                 length=30.0, countersink=120.0))[0] == "countersink"
    assert tool_problem(ToolSpec(1, "centredrill", diameter=5.0, body_diameter=5.0, pilot_length=2.4,
                                 length=30.0))[0] == "body_diameter"
    setup = tmp_path / "m.toml"
    setup.write_text('[machine]\nkind = "mill"\ndialect = "cnc8x6"\n[stock]\nshape = "box"\nx = [0, 10]\n'
                     'y = [0, 10]\nz = [-5, 0]\n[[tool]]\nkind = "centredrill"\ndiameter = 2\n')
    with pytest.raises(CutsimError, match="does not fit a mill"):
        cutsim.simulate("p.nc", str(setup), text="M30\n", tolerance=TOL)


# -- taps ----------------------------------------------------------------------------------------
D, P = 10.0, 1.5
H = math.sqrt(3.0) / 2.0 * P
BORE = D / 2.0 - 5.0 * H / 8.0  # D1 / 2 of ISO 68-1
STOCK = f'shape = "revolve"\nprofile = [[{BORE:.6f}, 0], [10, 0], [10, -30], [{BORE:.6f}, -30]]'
TAP = f'kind = "tap"\ndiameter = {D}\npitch = {P}\nlength = 25'
TAP_IN = "G00 X0 Z3.\n{spindle} S200\nG33 Z-19.5 F1.5\n"  # 15 leads: the zero pulse meets the end


def _groove_per_mm(rb: float) -> float:
    def integral(r: float) -> float:  # of r w(r)
        return (P / 8.0 + 2.0 * T30 * D / 2.0) * r * r / 2.0 - 2.0 * T30 * r ** 3 / 3.0
    return 2.0 * math.pi / P * (integral(D / 2.0) - integral(rb))


@pytest.mark.parametrize("spindle,rho", [("M03", 1), ("M04", -1)])
def test_tap_thread_root_and_phase(tmp_path, spindle, rho):
    from support.geometry import load, section, wrap

    res = _run(tmp_path, STOCK, TAP, TAP_IN.format(spindle=spindle))
    assert res.report["warnings"] == []
    mesh = load(res)
    for phi in (37.3, 151.9, 263.1):
        pts = section(mesh, phi).reshape(-1, 2)
        near = pts[(pts[:, 1] < -2.0) & (pts[:, 1] > -12.0) & (pts[:, 0] < 9.0)]
        root = near[near[:, 0] > D / 2.0 - 3 * TOL]
        assert len(root) >= 6, phi
        assert float(near[:, 0].max()) <= D / 2.0 + 1e-6
        expect = 3.0 + P * rho * phi / 360.0
        assert np.all(np.abs(wrap(root[:, 1] - expect, P)) < P / 16.0 + 0.01), (phi, root[:5])


@pytest.mark.parametrize("spindle", ["M03", "M04"])
def test_tap_groove_volume(tmp_path, spindle):
    """The slab -14..-4 (clear of the chamfer: full thread from -19.5 + 4.5) loses the groove."""
    res = _run(tmp_path, STOCK, TAP, TAP_IN.format(spindle=spindle))
    k = _k(res, math.pi * (100.0 - BORE ** 2) * 30.0)
    removed = k * math.pi * (100.0 - BORE ** 2) * 10.0 - _slab(res.part, -14.0, -4.0, 10.0)
    expect = 10.0 * _groove_per_mm(BORE)
    assert abs(removed - expect) <= 0.005 * expect, (removed, expect)


def test_tap_return_removes_nothing_more(tmp_path):
    """Backing out with M04 and G33 from where the zero pulse meets the helix again (15 leads in)
    follows the same helix: nothing more goes. Backing out with M03 (the other hand), or from a
    depth off the helix's phase (Z-19: 14 2/3 leads), strips the thread."""
    ref = _run(tmp_path, STOCK, TAP, TAP_IN.format(spindle="M03")).part.volume()
    back = _run(tmp_path, STOCK, TAP, TAP_IN.format(spindle="M03") + "M04\nG33 Z3. F1.5\nM05\nG00 Z10.\n")
    assert back.report["warnings"] == []
    assert abs(back.part.volume() - ref) < 1e-3
    wrong_hand = _run(tmp_path, STOCK, TAP, TAP_IN.format(spindle="M03") + "G33 Z3. F1.5\n").part.volume()
    assert ref - wrong_hand > 10.0
    off = "G00 X0 Z3.\nM03 S200\nG33 Z-19. F1.5\n"
    ref_off = _run(tmp_path, STOCK, TAP, off).part.volume()
    off_back = _run(tmp_path, STOCK, TAP, off + "M04\nG33 Z3. F1.5\n").part.volume()
    assert ref_off - off_back > 10.0


def test_tap_off_the_axis_and_drill_g33_refused(tmp_path):
    with pytest.raises(CutsimError, match="a tap cuts its thread on the spindle axis"):
        _run(tmp_path, STOCK, TAP, "G00 X1. Z3.\nM03 S200\nG33 Z-10. F1.5\n")
    drill = 'kind = "drill"\ndiameter = 8'
    with pytest.raises(CutsimError, match='kind = "tap"'):
        _run(tmp_path, STOCK, drill, "G00 X0 Z3.\nM03 S200\nG33 Z-10. F1.5\n")


def _groove(d: float, p: float, rb: float) -> float:
    """Material per mm of the ISO 68-1 nut groove of M d x p between the bore rb and d/2."""
    def integral(r: float) -> float:
        return (p / 8.0 + 2.0 * T30 * d / 2.0) * r * r / 2.0 - 2.0 * T30 * r ** 3 / 3.0
    return 2.0 * math.pi / p * (integral(d / 2.0) - integral(rb))


@pytest.mark.parametrize("d,p,depth_frac,chamfer,tol", [
    (3.0, 0.5, 1.0, 1.5, 0.002), (6.0, 1.0, 0.6, 0.0, 0.002), (16.0, 2.0, 0.8, 6.0, 0.01),
    (24.0, 1.5, 1.0, 3.0, 0.005), (4.0, 1.0, 0.3, 4.0, 0.002)])
def test_tap_groove_over_the_range(tmp_path, d, p, depth_frac, chamfer, tol):
    """Coarse and fine pitches, a bore from D1 (depth_frac 1: the full 5H/8) to a shallow thread,
    chamfers from none to 4 pitches: the slab clear of the chamfer loses the groove per mm."""
    h = math.sqrt(3.0) / 2.0 * p
    rb = d / 2.0 - depth_frac * 5.0 * h / 8.0
    ro = d / 2.0 + 5.0
    leads = math.ceil((10.0 + chamfer + 3.0) / p)
    z_end = 3.0 - leads * p
    stock = f'shape = "revolve"\nprofile = [[{rb:.6f}, 0], [{ro}, 0], [{ro}, -30], [{rb:.6f}, -30]]'
    tool = f'kind = "tap"\ndiameter = {d}\npitch = {p}\nchamfer = {chamfer}\nlength = {2 * d + 20}'
    res = _run(tmp_path, stock, tool, f"G00 X0 Z3.\nM03 S200\nG33 Z{z_end:.6f} F{p}\nM04\nG33 Z3. F{p}\n", tol=tol)
    assert res.report["warnings"] == []
    area = math.pi * (ro * ro - rb * rb)
    k = _k(res, area * 30.0)
    z1 = z_end + chamfer + 1.0
    removed = k * area * 8.0 - _slab(res.part, z1, z1 + 8.0, ro)
    expect = 8.0 * _groove(d, p, rb)
    # the sweep's chords lie on the axis side of the helices (docs/setup.md): the groove comes out
    # shallower, by at most a layer ``tol`` thick over its surface (flanks and root: 1.375 P of
    # profile per pitch at full depth, 2 pi r of it per turn), never deeper
    layer = tol * 1.375 * 2.0 * math.pi * (d / 2.0) * 8.0
    assert -layer <= removed - expect <= 1e-3 * expect, (removed, expect, layer)


def test_axial_defaults_from_the_setup(tmp_path):
    """The loader's defaults (docs/setup.md): DIN 333 A proportions, a form C chamfer of 3 pitches,
    a thread length of 2 D; a key of another kind is refused at its line."""
    setup = tmp_path / "s.toml"
    setup.write_text('[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n[stock]\nshape = "cylinder"\ndiameter = 30\n'
                     'z = [-40, 0]\n[[tool]]\nkind = "centredrill"\ndiameter = 2\n[[tool]]\nkind = "tap"\n'
                     'diameter = 10\npitch = 1.5\n')
    cd, tap = cutsim.load_setup(str(setup)).tools
    assert (cd.body_diameter, cd.pilot_length, cd.countersink, cd.point_angle, cd.length) == (5.0, 2.4, 60.0, 118.0, 30.0)
    assert (tap.chamfer, tap.length) == (4.5, 20.0)
    setup.write_text(setup.read_text() + "countersink = 60\n")
    with pytest.raises(CutsimError, match=r"s.toml:15:1: .*countersink: unknown key for a tap tool"):
        cutsim.load_setup(str(setup))
