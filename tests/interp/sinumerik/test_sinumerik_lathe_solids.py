"""Sinumerik lathe mode end to end: the parts measured against numbers derived from the programs
(docs/dialects/sinumerik-turning.md), each with a deliberately wrong part that must fail.

- The example examples/sinumerik/thread-two-start: its check values follow from the program's own
  words (root diameter = the last X, phase = SF + 360 DITS / K at the Z the cut starts, the
  run-out's root line from its chained block), and spoiled copies fail them.
- A face thread (G33 X.. I..): its spiral's roots at r = r0 + I frac(-(phi + SF)/360) (mod I).
- G34/G35: the groove a tool leaves while the lead changes by F per turn lies, at the angle phi, where
  the revolutions n(z) = (sqrt(K^2 + 2 F (z0 - z)) - K) / F since the start satisfy
  n + phi / 360 = 0 (mod 1) (the constant-lead rule z = z0 - K n with n = -(phi + SF)/360 of
  docs/checks.md, with the travel K n + F n^2 / 2).
- G331/G332 and G63: an M10x1.5 tap's groove (as tests/interp/cnc8x6/test_lathe_holes.py).
- G42 with a nose radius: the chamfer and the taper turned exactly; without compensation they
  stay r (2 - sqrt 2) and r (3 - sqrt 5) / 2 too large radially (the nose's envelope).
- G96: the cycle time of a facing cut, integral of 2 pi r / (1000 v f) dr, with LIMS the limit
  below r = 1000 v / (2 pi LIMS).
"""
from __future__ import annotations

import math
import re
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cutsim
from cutsim.base.specs import MachineSpec, ToolSpec
from cutsim.interp import InterpConfig, interpret
from cutsim.kinematics import plan
from cutsim.kinematics.spindle import varying_spans

HERE = Path(__file__).resolve()
EXAMPLE = HERE.parents[3] / "examples" / "sinumerik" / "thread-two-start"
sys.path.insert(0, str(HERE.parents[1] / "cnc8x6"))
from test_lathe_holes import assert_m10_groove  # noqa: E402
from support.geometry import load, section, wrap  # noqa: E402

LATHE = """[machine]
kind = "lathe"
dialect = "sinumerik"
start = [40.0, 0.0, 50.0]
[stock]
shape = "cylinder"
diameter = {d}
z = [{z0}, 0]
[[tool]]
number = 1
{tool}
[simulation]
tolerance = {tol}
"""
THREAD_TOOL = 'kind = "thread"\nangle = 60.0'


def simulate(tmp_path, text: str, d: float = 30.0, z0: float = -40.0, tool: str = THREAD_TOOL, tol: float = 0.005):
    setup = tmp_path / "s.toml"
    setup.write_text(LATHE.format(d=d, z0=z0, tool=tool, tol=tol))
    return cutsim.simulate("p.mpf", str(setup), text=text)


# -- the example ----------------------------------------------------------------------------------
def _words(line: str) -> dict[str, float]:
    return {k: float(v) for k, v in re.findall(r"\b(X|Z|K|SF|DITS|DITE)=?(-?[\d.]+)", line.split(";")[0])}


def derived_checks(text: str) -> dict:
    """The example's check values from its words: the SF of each start, DITS, K, and of the last
    chain the lead-in (its first G33 block, from where the tool stands), the X of the thread and
    the run-out (its last block), each ramp as the line ((z0, r0), (z1, r1)) of its root."""
    sf, dits, k, x, z, chained = [], 0.0, None, None, None, False
    lead_in = run_out = root = phase_z = None
    for line in text.splitlines():
        w, g33 = _words(line), "G33" in line.split(";")[0]
        if "DITS" in w:
            dits = w["DITS"]
        if g33:
            sf += [w["SF"]] if "SF" in w else []
            k = w["K"]
            ramp = ((z, x / 2.0), (w["Z"], w["X"] / 2.0)) if "X" in w else None
            if not chained:
                lead_in, phase_z = ramp, z
            elif ramp:
                run_out = ramp
            else:
                root = x
        chained = g33
        x, z = w.get("X", x), w.get("Z", z)
    return {"phase": [a + 360.0 * dits / k for a in sf], "phase_z": phase_z, "lead": k, "root_diameter": root,
            "lead-in": lead_in, "run-out": run_out}


def on_line(line, z: float) -> float:
    (z0, r0), (z1, r1) = line
    return r0 + (r1 - r0) * (z - z0) / (z1 - z0)


def test_example_check_values_follow_from_the_program():
    d = derived_checks(EXAMPLE.with_suffix(".mpf").read_text())
    checks = {c["name"]: c for c in tomllib.loads(EXAMPLE.with_suffix(".toml").read_text())["check"]}
    th = checks["M30x2 two-start"]
    assert (th["lead"], th["root_diameter"], th["phase_z"]) == (d["lead"], d["root_diameter"], d["phase_z"])
    assert th["phase"] == d["phase"] == [90.0, 270.0]
    for name in ("lead-in", "run-out"):
        ramp = checks[name]
        assert ramp["radius"] == pytest.approx([on_line(d[name], z) for z in ramp["z"]], abs=1e-6)
    # the thread check keeps clear of both ramps
    assert d["lead-in"][1][0] > th["z"][1] and th["z"][0] > d["run-out"][0][0]


@pytest.mark.parametrize("spoil,failing", [
    (("SF=180", "SF=190"), {"phase[2]"}),  # the second start 10 degrees late
    (("DITS=1", "DITS=1.5"), {"phase[1]", "phase[2]"}),  # a longer run-in: both starts 45 degrees late
    (("X27.546", "X27.446"), {"root_diameter"}),  # the last passes 0.05 deeper
])
def test_example_fails_when_spoiled(tmp_path, spoil, failing):
    text = EXAMPLE.with_suffix(".mpf").read_text()
    assert spoil[0] in text
    res = cutsim.simulate("p.mpf", str(EXAMPLE.with_suffix(".toml")), text=text.replace(spoil[0], spoil[1]))
    bad = {i["quantity"] for c in res.report["checks"] for i in c["items"] if not i["passed"]}
    assert failing <= bad and "lead" not in bad


# -- G34 / G35 -----------------------------------------------------------------------------------
def residuals(roots, z0: float, k: float, f: float) -> np.ndarray:
    """How far (mm along Z, at the local lead) each root (phi, z, r) lies from the groove the
    varying lead makes (``f`` signed: G34 > 0, G35 < 0; 0: a constant lead ``k``)."""
    phi, z = np.array([p for p, _, _ in roots]), np.array([z for _, z, _ in roots])
    n = (np.sqrt(k * k + 2 * f * (z0 - z)) - k) / f if f else (z0 - z) / k
    frac = n + phi / 360.0
    return np.abs(frac - np.round(frac)) * (k + f * n)


@pytest.mark.parametrize("code,k,f", [(34, 2.0, 0.05), (35, 3.0, -0.05)])
def test_varying_lead_grooves(tmp_path, code, k, f):
    """G34 K2 F0.05 / G35 K3 F0.05 from Z4 to Z-30 at X28: roots between Z-25 and Z-3 at r 14, on
    the varying-lead helix to 0.02 mm; the constant lead K would put them 0.1 mm or more off."""
    res = simulate(tmp_path, f"DIAMON G95 M3 S400\nG0 X34 Z4\nX28\nG{code} Z-30 K{k:g} F{abs(f):g}\nG0 X34\nM30\n")
    roots = res.thread(-25.0, -3.0)["roots"]
    assert len(roots) > 100
    assert np.allclose([r for _, _, r in roots], 14.0, atol=0.02)
    assert residuals(roots, 4.0, k, f).max() < 0.02
    assert residuals(roots, 4.0, k, 0.0).max() > 0.1


# -- a face thread --------------------------------------------------------------------------------
def face_roots(res, phi: float) -> np.ndarray:
    """Radii (10 < r < 16) where the face's outline in the half-plane at ``phi`` has a groove's root
    (the lowest z of a dip), from trimesh sections (tests/support/geometry.py)."""
    segs = section(load(res), phi)
    rs = np.arange(10.0, 16.0, 0.005)
    top = np.full(rs.shape, -np.inf)
    r0, r1, z0, z1 = segs[:, 0, 0], segs[:, 1, 0], segs[:, 0, 1], segs[:, 1, 1]
    for i, r in enumerate(rs):
        hit = (np.minimum(r0, r1) <= r) & (np.maximum(r0, r1) >= r) & (np.abs(r1 - r0) > 1e-12)
        t = (r - r0[hit]) / (r1[hit] - r0[hit])
        top[i] = np.max(z0[hit] + t * (z1[hit] - z0[hit]))
    low = (top[1:-1] < top[:-2]) & (top[1:-1] <= top[2:]) & (top[1:-1] < -0.7)
    return rs[1:-1][low]


@pytest.mark.parametrize("sf,ok", [(0, True), (90, False)])
def test_face_thread_spiral(tmp_path, sf, ok):
    """G33 X36 I2 at Z-0.8 from X16 (r 8 .. 18; the V's flank reaches 5.8 mm in from its point): the
    point passes the angle phi at the turns n = -(phi + SF)/360 (mod 1), at r = 8 + 2 n: the spiral's
    roots at r = 2 frac(-phi/360) (mod 2) for SF=0; SF=90 puts them 0.5 mm further in."""
    tool = 'kind = "thread"\nangle = 60.0\nside = "face"'
    res = simulate(tmp_path, f"DIAMON G95 M3 S300\nG0 X16 Z2\nZ-0.8\nG33 X36 I2 SF={sf}\nG0 Z5\nM30\n",
                   d=40.0, tool=tool)
    for phi in (33.3, 151.7, 262.9):
        roots = face_roots(res, phi)
        assert len(roots) >= 2, phi
        want = 2.0 * ((-phi / 360.0) % 1.0)
        off = np.abs(wrap(roots - want, 2.0))
        assert (off.max() < 0.02) == ok, (phi, roots)


# -- tapping --------------------------------------------------------------------------------------
TAP_SETUP = """[machine]
kind = "lathe"
dialect = "sinumerik"
start = [40.0, 0.0, 50.0]
[stock]
shape = "cylinder"
diameter = 40
z = [-50, 0]
[[tool]]
number = 1
kind = "drill"
diameter = 8.5
point_angle = 118
length = 60
[[tool]]
number = 2
kind = "tap"
diameter = 10
pitch = 1.5
length = 25
[simulation]
tolerance = 0.002
"""
DRILL = "DIAMON G95\nT1 S800 M3\nG0 X0 Z5\nG1 Z-25 F0.1\nG0 Z5\nM5\nT2 S200\nG0 Z3\n"  # T changes a lathe's tool


@pytest.mark.parametrize("tapping,rho", [
    ("G331 Z-16.5 K1.5\nG332 Z3\n", 1),  # 19.5 mm, 13 turns: the groove from Z3 at the zero mark
    ("G331 Z-16.5 K-1.5\nG332 Z3\n", -1),  # left-hand
    ("M3\nG63 Z-16.5 F1.5\nG63 Z3 M4\n", 1),  # floating: lead = F (G95)
])
def test_tapping_leaves_the_m10_groove(tmp_path, tapping, rho):
    setup = tmp_path / "s.toml"
    setup.write_text(TAP_SETUP)
    res = cutsim.simulate("p.mpf", str(setup), text=DRILL + tapping + "M5\nG0 X80 Z50\nM30\n")
    assert res.report["warnings"] == []
    assert_m10_groove(res, rho)


def test_tap_backed_out_on_another_helix_spoils_the_groove(tmp_path):
    """G63 back out under M3 again (no reversal): the tap strips its own thread, the groove check fails."""
    setup = tmp_path / "s.toml"
    setup.write_text(TAP_SETUP)
    res = cutsim.simulate("p.mpf", str(setup), text=DRILL + "M3\nG63 Z-16.5 F1.5\nG63 Z3 F1.0\nM5\nG0 X80 Z50\nM30\n")
    with pytest.raises(AssertionError):
        assert_m10_groove(res, 1)


# -- nose radius compensation ---------------------------------------------------------------------
NOSE = 0.8
TURNING = f'kind = "turning"\ninsert = "C"\ntip_radius = {NOSE}'
CONTOUR = "DIAMON G95 T1 D1 M3 S1000\nG0 X12 Z6\n{sel} G1 Z2 F0.1\nX20 Z-2\nZ-20\nX30 Z-30\nZ-45\nG40 X40\nG0 Z10\nM30\n"


@pytest.mark.parametrize("sel,chamfer,taper", [
    ("G42", 18.0, 25.0),  # compensated: the contour itself (r = 8 - z on the chamfer, 2r + z = 0 on the taper)
    ("G40", 18.0 + 2 * NOSE * (2 - math.sqrt(2)), 25.0 + NOSE * (3 - math.sqrt(5))),  # the nose's envelope
])
def test_nose_radius_compensation_turns_the_contour(tmp_path, sel, chamfer, taper):
    """Edge position 3: tip = centre + (-r, -r). Uncompensated the centre runs r + r off the
    chamfer's line x + z = 8 (x radius) along its normal (1, 1)/sqrt2, the part's surface r below it:
    x + z = 8 + r (2 - sqrt2); on the taper 2x + z = 0 (normal (2, 1)/sqrt5): 2x + z = r (3 - sqrt5)."""
    res = simulate(tmp_path, CONTOUR.format(sel=sel), d=32.0, tool=TURNING, tol=0.002)
    assert abs(float(np.median(res.diameters_at(-1.0))) - chamfer) < 0.01
    assert abs(float(np.median(res.diameters_at(-25.0))) - taper) < 0.01
    assert abs(float(np.median(res.diameters_at(-10.0))) - 20.0) < 0.01


# -- constant cutting speed -----------------------------------------------------------------------
def _face_time(lims: str) -> float:
    cfg = InterpConfig(dialect="sinumerik", machine_kind="lathe", start=(15.0, 0.0, -1.0))
    prog = interpret("t.mpf", f"G95 G96 S200 {lims} M3\nG1 X0 F0.2\nM30\n", cfg)
    return plan(prog, MachineSpec(kind="lathe"), [ToolSpec(1, "thread")], 0.01).cycle_time


def test_g96_facing_time():
    """Facing from r 15 to 0 at 0.2 mm/rev, 200 m/min: t = pi 15^2 / (1000 200 0.2) min; with LIMS
    5000 the speed stops rising below r_l = 1000 200 / (2 pi 5000) = 6.366: t = pi (15^2 - r_l^2) /
    40000 + r_l / (0.2 5000) min."""
    assert _face_time("") == pytest.approx(60.0 * math.pi * 225.0 / 40000.0, rel=1e-9)
    rl = 200000.0 / (2 * math.pi * 5000.0)
    assert _face_time("LIMS=5000") == pytest.approx(60.0 * (math.pi * (225.0 - rl * rl) / 40000.0 + rl / 1000.0),
                                                    rel=1e-9)


@settings(max_examples=200, deadline=None)
@given(k=st.floats(0.2, 6.0), f=st.floats(0.001, 0.5), sign=st.sampled_from([1, -1]), travel=st.floats(1.0, 80.0),
       tol=st.sampled_from([0.001, 0.005, 0.02]))
def test_varying_lead_pieces_stay_within_the_tolerance(k, f, sign, travel, tol):
    """kinematics.spindle.varying_spans: each constant-lead piece's chord of the travel
    T(n) = K n + c n^2 / 2 is off by at most tol (sampled), the pieces join and end at the travel;
    half as many pieces (each twice as long, c dn^2 / 8 four times as large) would be off by more
    than tol whenever more than one piece is needed."""
    c = sign * f
    if k * k + 2 * c * travel <= 0.01:
        return  # a G35 that stops before the end: refused by the interpreter
    spans = varying_spans(k, c, travel, tol)

    def worst(pieces):
        n0, out = 0.0, 0.0
        for t0, t1, dn in pieces:
            n = np.linspace(n0, n0 + dn, 41)
            true = k * n + c * n * n / 2
            chord = t0 + (t1 - t0) * (n - n0) / dn
            out = max(out, float(np.abs(true - chord).max()))
            n0 += dn
        return out
    assert worst(spans) <= tol * (1 + 1e-6)
    assert spans[-1][1] == travel and all(a[1] == pytest.approx(b[0]) for a, b in zip(spans, spans[1:]))
    if len(spans) > 2:
        pairs = [(a[0], b[1], a[2] + b[2]) for a, b in zip(spans[::2], spans[1::2])]
        assert worst(pairs) > tol


def test_trans_and_work_offset_move_the_thread(tmp_path):
    """G54 Z-2 and TRANS Z-3 (radius shifts too: X unchanged as a radius): the thread programmed from
    Z9 at SF=0 is cut from Z4 (9 - 2 - 3), lead 2, root X27.6 -> its phase is 0 at Z4."""
    text = "G54 DIAMON G95 M3 S400\nTRANS Z-3\nG0 X34 Z9\nX27.6\nG33 Z-20 K2 SF=0\nG0 X34\nM30\n"
    setup = tmp_path / "s.toml"
    setup.write_text(LATHE.format(d=30.0, z0=-40.0, tool=THREAD_TOOL, tol=0.005) + "[work_offsets]\nG54 = [0.0, 0.0, -2.0]\n")
    res = cutsim.simulate("p.mpf", str(setup), text=text)
    rec = res.check(kind="thread", z=[-16.0, -2.0], lead=2.0, root_diameter=27.6, phase=[0.0], phase_z=4.0)
    assert rec["passed"], rec
    wrong = res.check(kind="thread", z=[-16.0, -2.0], lead=2.0, phase=[0.0], phase_z=9.0)  # the offsets ignored
    assert not wrong["passed"]
