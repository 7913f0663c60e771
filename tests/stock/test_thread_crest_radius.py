"""A full-profile thread insert's ``crest_radius`` (docs/setup.md, "Lathe inserts"): the corners
between its flanks and its shoulders are rounded, so the crest's edges on the part are rounded
with that radius.

Derived by hand (ISO 68-1, H = sqrt(3)/2 P): the groove's flanks meet the crest's flat at a
corner of 120 degrees on the part, at an axial distance w from the groove's centre (outside w =
P/2 - P/16 = 7P/16, the bolt's crest flat P/8; inside w = P/2 - P/8 = 3P/8, the nut's P/4). A
rounding of radius r tangent to the flat and the flank has its centre r inside the crest level,
r tan 30 beyond the corner along the flat; at the corner's own z it lies r tan 30 from the
centre, so the outline there stands sqrt(r^2 - r^2 tan^2 30) = r sqrt(2/3) from the centre: r (1
- sqrt(2/3)) = 0.1835 r off the crest level (inwards outside, outwards inside), where without the
rounding it is the crest level itself. The middle of the flat stays at the crest level. The groove
centre lies at z = z0 + P rho phi / 360 (mod P) in the half-plane at phi (rho = +1 under M03, -1
under M04; tests/stock/test_axial_tools.py), z0 the start Z.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import cutsim
from cutsim.interp.errors import CutsimError

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from support.geometry import load, section  # noqa: E402

TOL = 0.002
P = 1.5
BIG_H = math.sqrt(3.0) / 2.0 * P
T30 = math.tan(math.radians(30.0))


def _radius_at(segs: np.ndarray, z: float, inside: bool) -> float:
    """The outline's radius at height z: the largest crossing outside, the smallest below the
    tube's outer wall inside."""
    z0, z1, r0, r1 = segs[:, 0, 1], segs[:, 1, 1], segs[:, 0, 0], segs[:, 1, 0]
    m = (np.minimum(z0, z1) <= z) & (np.maximum(z0, z1) >= z) & (np.abs(z1 - z0) > 1e-12)
    r = r0[m] + (z - z0[m]) / (z1[m] - z0[m]) * (r1[m] - r0[m])
    if inside:
        return float(np.min(r[r < 19.0]))
    return float(np.max(r))


def _cut(tmp_path, side: str, spindle: str, rc: float):
    if side == "outside":
        stock, r_crest, x_out = "shape = \"cylinder\"\ndiameter = 24.4\nz = [-30, 0]", 12.0, 26.0
        depth = 5.0 * BIG_H / 8.0  # crest (major) 5H/8 above the flat tip
        r_tip = r_crest - depth
    else:
        stock = "shape = \"revolve\"\nprofile = [[10.8, 0], [20, 0], [20, -30], [10.8, -30]]"
        r_tip, x_out = 12.0, 20.0  # the nut's root at D/2; its crest (D1/2) 5H/8 nearer the axis
        r_crest = r_tip - 5.0 * BIG_H / 8.0
    path = tmp_path / "s.toml"
    path.write_text(f'[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n[stock]\n{stock}\n[[tool]]\nkind = "thread"\n'
                    f'form = "full"\npitch = {P}\nside = "{side}"\nheight = 3\ncrest_radius = {rc}\n')
    program = f"G00 X{x_out} Z3.\n{spindle} S500\nX{2 * r_tip:.6f}\nG33 Z-20. F{P}\nG00 X{x_out}\nZ10.\nM30\n"
    res = cutsim.simulate("p.nc", str(path), text=program, tolerance=TOL)
    return res, r_crest


@pytest.mark.parametrize("side", ["outside", "inside"])
@pytest.mark.parametrize("spindle,rho", [("M03", 1), ("M04", -1)])
@pytest.mark.parametrize("frac", [0.0, 0.6, 1.0])
def test_the_crest_edges_are_rounded(tmp_path, side, spindle, rho, frac):
    inside = side == "inside"
    rmax = (P / 4.0 if inside else P / 8.0) / (2.0 * T30)  # the two roundings fill the flat
    rc = math.floor(frac * rmax * 1e6) / 1e6
    res, r_crest = _cut(tmp_path, side, spindle, rc)
    assert [w["line"] for w in res.report["warnings"]] in ([], [5])  # the retract out of the groove's end
    mesh = load(res)
    w = 7.0 * P / 16.0 if not inside else 3.0 * P / 8.0
    drop = rc * (1.0 - math.sqrt(2.0 / 3.0))
    sign = 1.0 if inside else -1.0  # off the crest level: outwards inside, inwards outside
    for phi in (37.3, 201.7):  # clear of the sweep's stations and the stock's seams
        segs = section(mesh, phi)
        zg0 = 3.0 + P * rho * phi / 360.0
        for k in range(-12, -3):  # grooves well inside z -20..0
            zg = zg0 + k * P
            for s in (1.0, -1.0):  # both edges of the crest beside this groove
                at_corner = _radius_at(segs, zg + s * w, inside)
                assert abs(at_corner - (r_crest + sign * drop)) <= 3 * TOL, (phi, k, s, at_corner, r_crest, drop)
            middle = _radius_at(segs, zg + P / 2.0, inside)
            assert abs(middle - r_crest) <= 2 * TOL, (phi, k, middle, r_crest)


@pytest.mark.parametrize("side,rc,msg", [
    ("outside", 0.17, "crest_radius: must be at most 0.162"),  # P / (16 tan 30) = 0.16238
    ("inside", 0.33, "crest_radius: must be at most 0.324"),  # P / (8 tan 30) = 0.32476
    ("outside", -0.1, "crest_radius: must be 0 or between"),
])
def test_crest_radius_range(tmp_path, side, rc, msg):
    path = tmp_path / "s.toml"
    path.write_text(f'[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n[stock]\nshape = "cylinder"\ndiameter = 30\n'
                    f'z = [-10, 0]\n[[tool]]\nkind = "thread"\nform = "full"\npitch = {P}\nside = "{side}"\n'
                    f'crest_radius = {rc}\n')
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(path))
    assert msg in str(e.value), str(e.value)
    assert ":13:" in str(e.value), str(e.value)  # at the key's line


def test_crest_radius_needs_a_full_profile(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n[stock]\nshape = "cylinder"\ndiameter = 30\n'
                    'z = [-10, 0]\n[[tool]]\nkind = "thread"\ncrest_radius = 0.1\n')
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(path))
    assert "crest_radius: is a key of a full-profile insert" in str(e.value), str(e.value)
