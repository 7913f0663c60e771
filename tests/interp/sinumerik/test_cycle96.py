"""CYCLE96 thread undercuts DIN 76 (interp/sinumerik/grooving.py, docs/dialects/sinumerik-turning.md
"CYCLE96"): the normal forms A (outside) and C (inside) and the short forms B and D, cut on a shaft or
in a bore ending at a shoulder and measured.

Every number is derived here by hand from the table of the docs (DIN 76-1 by pitch: the diameter
difference dd, the length g2 from the face, the radius r) and the contour rule: from the thread's
cylinder (outside d, inside the minor diameter D1 = D - 1.082532 P) g2 from the face, down the flank
at 30 degrees to the axis to the floor (outside d - dd, inside D + dd), along it and round the
fillet r tangent to the floor and the face. The part's volume is the stock's less the undercut's
ring, by Pappus (a frustum for the flank, a cylinder for the floor and the fillet's closed form),
compared as the share of the stock removed (the chordal error of the revolved solids mostly
cancels in the ratio).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import cutsim
from cutsim.interp.canon import Arc, Feed
from cutsim.reports.measure import plane_section, radii_at

SETUP = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [{sx}, 0.0, 20.0]
[stock]
shape = "revolve"
profile = {profile}
[[tool]]
number = 1
kind = "turning"
insert = "V"
size = {size}
tip_radius = 0.0
approach = 93.0
hand = "R"
[[tool]]
number = 2
kind = "turning"
insert = "V"
size = {size}
tip_radius = 0.0
approach = 93.0
hand = "R"
side = "inside"
[simulation]
tolerance = {tol}
"""
TAN30 = math.tan(math.radians(30.0))
FACE = -30.0  # the shoulder's face: the thread's cylinder from Z0 to here, the undercut before it
# DIN 76-1 by pitch, typed from the docs' table: (outside dd, A length, r, inside dd, C length) and
# the short lengths (B, D); the coarse thread of each pitch the tests cut
TABLE = {0.5: (0.8, 1.75, 0.2, 0.3, 2.7), 0.7: (1.1, 2.45, 0.4, 0.3, 3.8), 0.8: (1.3, 2.8, 0.4, 0.3, 4.2),
         1.0: (1.6, 3.5, 0.6, 0.5, 5.2), 1.25: (2.0, 4.4, 0.6, 0.5, 6.7), 1.5: (2.3, 5.2, 0.8, 0.5, 7.8),
         1.75: (2.6, 6.1, 1.0, 0.5, 9.1), 2.0: (3.0, 7.0, 1.0, 0.5, 10.3), 2.5: (3.6, 8.7, 1.2, 0.5, 13.0),
         3.0: (4.4, 10.5, 1.6, 0.5, 15.2), 3.5: (5.0, 12.0, 1.6, 0.5, 17.7), 4.0: (5.7, 14.0, 2.0, 0.5, 20.0),
         4.5: (6.4, 16.0, 2.0, 0.5, 23.0), 5.0: (7.0, 17.5, 2.5, 0.5, 26.0), 5.5: (7.7, 19.0, 3.2, 0.5, 28.0)}
SHORT = {0.5: (1.25, 2.0), 0.7: (1.75, 2.75), 0.8: (2.0, 3.0), 1.0: (2.5, 3.7), 1.25: (3.2, 4.9),
         1.5: (3.8, 5.6), 1.75: (4.3, 6.4), 2.0: (5.0, 7.3), 2.5: (6.3, 9.3), 3.0: (7.5, 10.7),
         3.5: (9.0, 12.7), 4.0: (10.0, 14.0), 4.5: (11.0, 16.0), 5.0: (12.5, 18.5), 5.5: (14.0, 20.0)}
SIZE = {0.5: 3, 0.7: 4, 0.8: 5, 1.0: 6, 1.25: 8, 1.5: 10, 1.75: 12, 2.0: 16, 2.5: 20, 3.0: 24, 3.5: 30,
        4.0: 36, 4.5: 42, 5.0: 48, 5.5: 56}


def undercut(d: int, pitch: float, form: str) -> dict:
    """The undercut's contour by hand: cyl (the thread's cylinder radius), floor (radius), g2, r,
    run (the flank's length along Z), sign (+1 outside: the floor below the cylinder)."""
    dd_o, g_a, r, dd_i, g_c = TABLE[pitch]
    outside = form in "AB"
    g2 = {"A": g_a, "B": SHORT[pitch][0], "C": g_c, "D": SHORT[pitch][1]}[form]
    cyl = d / 2.0 if outside else (d - 1.082532 * pitch) / 2.0
    floor = (d - dd_o) / 2.0 if outside else (d + dd_i) / 2.0
    return {"cyl": cyl, "floor": floor, "g2": g2, "r": r, "run": abs(cyl - floor) / TAN30, "outside": outside}


def stock(u: dict, d: float) -> str:
    """Outside: a bar of d to the face, a collar d + 20 behind it. Inside: the bore D1 from Z0 to
    the face, a bore of D1 - 6 (at least 2) behind it, the outside d + 20."""
    if u["outside"]:
        return f"[[0, 0], [{u['cyl']}, 0], [{u['cyl']}, {FACE}], [{d / 2 + 10}, {FACE}], [{d / 2 + 10}, -50], [0, -50]]"
    small = max(1.0, u["cyl"] - 3.0)
    return (f"[[{u['cyl']}, 0], [{d / 2 + 10}, 0], [{d / 2 + 10}, -50], [{small}, -50], [{small}, {FACE}], "
            f"[{u['cyl']}, {FACE}]]")


def cut(tmp_path: Path, d: int, pitch: float, form: str, vari: int = 0, tol: float = 0.005):
    u = undercut(d, pitch, form)
    size = 3.97 if u["cyl"] < 8 else 6.35  # the inside insert fits the bore
    (tmp_path / "setup.toml").write_text(SETUP.format(sx=d + 30, profile=stock(u, d), size=size, tol=tol))
    if u["outside"]:
        text = f"N10 G18 G90 G95 T1 D1\nN20 S500 M3 F0.1\nN30 G0 X{d + 10} Z5\n"
    else:
        text = f"N10 G18 G90 G95 T2 D1\nN20 S500 M3 F0.1\nN30 G0 X{2 * u['cyl'] - 2:.3f} Z5\n"
    text += f'N40 CYCLE96({d}, {FACE:g}, "{form}", {vari or (3 if u["outside"] else 2)})\nN50 G0 Z20\nN60 M30\n'
    return cutsim.simulate("c96.mpf", str(tmp_path / "setup.toml"), text=text, checks=False), u


def radius_at(part, z: float, outside: bool) -> float:
    """Outside the smallest outer radius at z (over 72 directions), inside the bore's radius (the
    section's nearest vertex to the axis: the revolved solid's vertices lie on the true circle)."""
    if outside:
        return float(radii_at(part, z).min())
    pts = np.concatenate(plane_section(part, "z", z))
    return float(np.hypot(pts[:, 0], pts[:, 1]).min())


def verdict(part, u: dict, tol: float) -> list[str]:
    """What of the undercut ``u`` the part does not show: the floor's radius halfway along it, the
    thread's cylinder 0.1 beyond its length, the flank 0.1 inside it (0.1 tan 30 off the cylinder)."""
    s = 1.0 if u["outside"] else -1.0  # the floor is s * depth below the cylinder
    mid = FACE + u["r"] + (u["g2"] - u["run"] - u["r"]) / 2.0
    want = [(mid, u["floor"], "floor"), (FACE + u["g2"] + 0.1, u["cyl"], "cylinder beyond"),
            (FACE + u["g2"] - 0.1, u["cyl"] - s * 0.1 * TAN30, "flank")]
    bad = []
    for z, r, what in want:
        got = radius_at(part, z, u["outside"])
        if abs(got - r) > tol:
            bad.append(f"{what} at Z{z:.3f}: radius {got:.4f}, expected {r:.4f}")
    return bad


def ring_volume(u: dict) -> float:
    """The undercut's ring (Pappus: the region between the cylinder and the contour revolved): the
    flank a frustum, the floor a cylinder, the fillet sum pi * integral of r(w)^2 with r(w) = c -/+
    sqrt(a^2 - w^2) over w in [0, a] = pi (c^2 a -/+ c pi a^2 / 2 + 2 a^3 / 3)."""
    R, rf, a = u["cyl"], u["floor"], u["r"]
    frustum = math.pi * u["run"] * (R * R + R * rf + rf * rf) / 3.0
    floor = math.pi * rf * rf * (u["g2"] - u["run"] - a)
    if u["outside"]:
        c = rf + a
        fillet = math.pi * (c * c * a - c * math.pi * a * a / 2.0 + 2.0 * a ** 3 / 3.0)
        return math.pi * R * R * u["g2"] - (frustum + floor + fillet)
    c = rf - a
    fillet = math.pi * (c * c * a + c * math.pi * a * a / 2.0 + 2.0 * a ** 3 / 3.0)
    return frustum + floor + fillet - math.pi * R * R * u["g2"]


def stock_volume(u: dict, d: float) -> float:
    big = d / 2 + 10
    if u["outside"]:
        return math.pi * (u["cyl"] ** 2 * -FACE + big ** 2 * (50 + FACE))
    small = max(1.0, u["cyl"] - 3.0)
    return math.pi * ((big ** 2 - u["cyl"] ** 2) * -FACE + (big ** 2 - small ** 2) * (50 + FACE))


# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("d,pitch,form", [(30, 3.5, "A"), (30, 3.5, "B"), (30, 3.5, "C"), (30, 3.5, "D"),
                                          (12, 1.75, "D"),
                                          (8, 1.25, "B")])
def test_contour_records_and_the_part(tmp_path, d, pitch, form):
    """The records of the undercut (the cylinder g2 from the face, the floor after the 30 degree
    flank, the fillet's centre r off the floor and the face) and the part: its diameters and its
    volume (the stock's less the ring, by Pappus)."""
    res, u = cut(tmp_path, d, pitch, form)
    cyc = [r for r in res.program.records if r.src.line == 4 and isinstance(r, (Feed, Arc))]
    s = 1.0 if u["outside"] else -1.0
    pts = [(r.end[0], r.end[2]) for r in cyc[:4]]
    assert pts[0] == pytest.approx((u["cyl"], FACE + u["g2"]))
    assert pts[1] == pytest.approx((u["floor"], FACE + u["g2"] - u["run"]))
    assert pts[2] == pytest.approx((u["floor"], FACE + u["r"]))
    assert pts[3] == pytest.approx((u["floor"] + s * u["r"], FACE))
    assert isinstance(cyc[3], Arc) and cyc[3].center == pytest.approx((u["floor"] + s * u["r"], 0.0, FACE + u["r"]))
    assert verdict(res.part, u, 0.01) == []
    removed = 1.0 - res.report["part_volume"] / res.report["stock_volume"]  # the ring's share of the stock
    assert removed == pytest.approx(ring_volume(u) / stock_volume(u, d), rel=3e-3)


@pytest.mark.parametrize("pitch", sorted(SHORT))
@pytest.mark.parametrize("short,normal", [("B", "A"), ("D", "C")])
def test_short_forms_over_every_pitch(tmp_path, pitch, short, normal):
    """Every tabulated pitch, both short forms, cut on the coarse thread of that pitch: the part
    shows its undercut (floor, length, flank); the normal form's part does not pass as the short
    one (it is longer), nor the short one as the normal one."""
    d = SIZE[pitch]
    res, u = cut(tmp_path, d, pitch, short, tol=0.01)
    assert verdict(res.part, u, 0.02) == []
    assert verdict(res.part, undercut(d, pitch, normal), 0.02) != []
    res_n, u_n = cut(tmp_path, d, pitch, normal, tol=0.01)
    assert verdict(res_n.part, u_n, 0.02) == []
    assert verdict(res_n.part, u, 0.02) != []


@pytest.mark.parametrize("vari,form,z0", [(4, "B", FACE - 9.0), (1, "D", FACE - 12.7)])
def test_short_forms_towards_minus_z(tmp_path, vari, form, z0):
    """_VARI 4 (outside, hand L) and 1 (inside, hand L): the cylinder runs from the face towards
    -Z, the undercut's start g2 below it."""
    from cutsim import interp_config, load_setup
    from cutsim.interp import interpret

    u = undercut(30, 3.5, form)
    (tmp_path / "setup.toml").write_text(SETUP.format(sx=60, profile=stock(u, 30), size=6.35, tol=0.01))
    s = load_setup(str(tmp_path / "setup.toml"))
    text = f'N10 G18 G90 G95 T1 D1\nN20 S500 M3 F0.1\nN30 G0 X{60 if form == "B" else 20} Z5\n' \
           f'N40 CYCLE96(30, {FACE:g}, "{form}", {vari})\nN50 M30\n'
    recs = interpret("c96.mpf", text, interp_config(s, s.machine.start)).records
    cyc = [r for r in recs if r.src.line == 4 and isinstance(r, (Feed, Arc))]
    assert (cyc[0].end[0], cyc[0].end[2]) == pytest.approx((u["cyl"], z0))
    assert (cyc[1].end[0], cyc[1].end[2]) == pytest.approx((u["floor"], z0 + u["run"]))
    assert (cyc[2].end[0], cyc[2].end[2]) == pytest.approx((u["floor"], FACE - u["r"]))
