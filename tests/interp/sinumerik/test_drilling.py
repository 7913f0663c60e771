"""Sinumerik drilling cycles (interp/sinumerik/drilling.py) and the drill tool (stock/tools.py).

On the solid: a drilled hole measured on the part mesh with plane sections and rays
(tests/support/sinumerik_measure.py, trimesh only) against the analytic cylinder + cone of the drill
(tip at the depth DP, the cone's height r / tan(point_angle / 2)); the removed volume against
pi r^2 h_cyl + pi r^2 h_cone / 3 within the chordal tolerance times the hole's wall area.

On the moves: the peck depths of CYCLE83 derived by hand from the manual's rules (the numbers are
written out in each test), the hole positions of HOLES1 / HOLES2 / CYCLE801 from their formulas,
and property tests (hypothesis, derandomized) over parameter ranges: every move stays on the hole's
axis, never goes below the final depth, reaches it, and the cycle ends on the retraction plane.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cutsim
from cutsim.interp import InterpConfig, interpret
from cutsim.interp import canon
from cutsim.interp.errors import CutsimError
from cutsim.setup import load_setup
from support.sinumerik_measure import floor_z, hsection, ray

TOL = 0.005
R = 4.25  # the 8.5 mm drill
SETUP = """
[machine]
kind = "mill"
dialect = "sinumerik"
start = [50.0, 50.0, 50.0]

[stock]
shape = "box"
x = [0.0, 100.0]
y = [0.0, 100.0]
z = [-40.0, 0.0]

[[tool]]
number = 1
kind = "endmill"
diameter = 8.5
length = 60.0

[[tool]]
number = 2
kind = "endmill"
diameter = 10.0
length = 60.0

[simulation]
tolerance = {tol}
"""
HEAD = "G17 G90\nT1 D1 M6\nS1000 M3 F100\n"


def drill_setup(tmp_path, angle=118.0, tol=TOL):
    """The setup with T1 an 8.5 mm drill of the given point angle (built as a ToolSpec: the test
    does not depend on the setup's [[tool]] keys)."""
    p = tmp_path / "setup.toml"
    p.write_text(SETUP.format(tol=tol))
    s = load_setup(str(p))
    tools = [dataclasses.replace(t, kind="drill", point_angle=angle) if t.number == 1 else t for t in s.tools]
    return dataclasses.replace(s, tools=tools)


def simulate(tmp_path, body, angle=118.0, tol=TOL):
    prog = tmp_path / "p.mpf"
    prog.write_text(HEAD + body + "\nM30\n")
    return cutsim.simulate(str(prog), drill_setup(tmp_path, angle, tol), tolerance=tol)


def moves(body, start=(50.0, 50.0, 50.0), head=HEAD, max_blocks=5_000_000):
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=start, tool_radii={1: R, 2: 5.0},
                       max_blocks=max_blocks)
    prog = interpret("p.mpf", head + body + "\nM30\n", cfg)
    return [r for r in prog.records if isinstance(r, canon.MOTIONS)], prog


def cone_height(angle, r=R):
    return 0.0 if angle >= 180 else r / math.tan(math.radians(angle / 2))


def hole_volume(depth, angle, r=R):
    hc = cone_height(angle, r)
    return math.pi * r * r * (depth - hc) + math.pi * r * r * hc / 3


def wall_area(depth, angle, r=R):
    hc = cone_height(angle, r)
    return 2 * math.pi * r * (depth - hc) + math.pi * r * math.hypot(r, hc) + (math.pi * r * r if hc == 0 else 0)


# ---------------------------------------------------------------------------------------------
# the hole on the solid
@pytest.mark.parametrize("angle", [118.0, 90.0, 180.0])
def test_cycle81_hole_is_drill_cylinder_and_cone(tmp_path, angle):
    # DP -20 is the tip (the tool's control point); the cylindrical wall ends r / tan(angle / 2)
    # above it: 4.25 / tan 59 deg = 2.5536 mm for 118 degrees, 4.25 for 90, 0 for a flat drill
    r = simulate(tmp_path, "G0 X40 Y60\nCYCLE81(10, 0, 2, -20)", angle=angle)
    m = r.mesh()
    assert r.report["warnings"] == []
    assert floor_z(m, (40.0, 60.0), 1.0) == pytest.approx(-20.0, abs=2 * TOL)
    hc = cone_height(angle)
    for rho in (1.0, 2.0, 3.0, 4.0):  # the floor is the cone: z = -20 + rho / tan(angle / 2)
        expect = -20.0 + (rho * hc / R)
        assert floor_z(m, (40.0 + rho, 60.0), 1.0) == pytest.approx(expect, abs=2 * TOL)
    for z in (-1.0, -10.0, -20.0 + hc + 0.5):
        segs = hsection(m, z)
        for a in range(0, 360, 30):
            u = (math.cos(math.radians(a)), math.sin(math.radians(a)))
            assert ray(segs, (40.0, 60.0), u) == pytest.approx(R, abs=TOL + 1e-6)
    v = hole_volume(20.0, angle)
    assert r.report["removed_volume"] == pytest.approx(v, abs=TOL * wall_area(20.0, angle))


def test_cycle83_pecks_leave_the_same_hole(tmp_path):
    # chip removal (VARI 1), strokes 8, 6, 4, 2 ... : the pecks retrace the hole, the solid is the
    # CYCLE81 hole of the same depth (tip at -30)
    r = simulate(tmp_path, "G0 X50 Y50\nCYCLE83(10, 0, 2, -30, , , 8, 2, , , 1, 1)")
    m = r.mesh()
    assert floor_z(m, (50.0, 50.0), 1.0) == pytest.approx(-30.0, abs=2 * TOL)
    assert r.report["removed_volume"] == pytest.approx(hole_volume(30.0, 118.0), abs=TOL * wall_area(30.0, 118.0))
    assert r.report["warnings"] == []


def test_dpr_is_the_depth_below_rfp(tmp_path):
    # RFP -2 (a face 2 mm down: the stock top is 0, so the first 2 mm are drilled too), DPR 12:
    # the tip at -14
    r = simulate(tmp_path, "G0 X30 Y30\nCYCLE82(10, -2, 3, , 12, 1)")
    assert floor_z(r.mesh(), (30.0, 30.0), 1.0) == pytest.approx(-14.0, abs=2 * TOL)
    assert r.report["removed_volume"] == pytest.approx(hole_volume(14.0, 118.0), abs=TOL * wall_area(14.0, 118.0))


def test_mcall_holes2_drills_every_position(tmp_path):
    # four holes on radius 30 about (50, 50) from 45 degrees: (50 +- 21.2132, 50 +- 21.2132)
    r = simulate(tmp_path, "G0 Z10\nMCALL CYCLE81(10, 0, 2, -12)\nHOLES2(50, 50, 30, 45, 90, 4)\nMCALL\nG0 X50 Y50")
    m = r.mesh()
    c = 30 / math.sqrt(2)
    for sx in (-1, 1):
        for sy in (-1, 1):
            assert floor_z(m, (50 + sx * c, 50 + sy * c), 1.0) == pytest.approx(-12.0, abs=2 * TOL)
    assert floor_z(m, (50.0, 50.0), 1.0) == pytest.approx(0.0, abs=1e-9)  # MCALL alone ended the call
    assert r.report["removed_volume"] == pytest.approx(4 * hole_volume(12.0, 118.0),
                                                       abs=4 * TOL * wall_area(12.0, 118.0))


# ---------------------------------------------------------------------------------------------
# the moves
def zs(ms, kind=canon.Feed):
    return [round(m.end[2], 9) for m in ms if type(m) is kind]


def test_cycle81_sequence():
    # G0 down to RFP + SDIS = 2, G1 to DP -20 at the F in force, G0 up to RTP 10
    ms, _ = moves("G0 X40 Y60 Z20\nCYCLE81(10, 0, 2, -20)")
    seq = [(type(m).__name__, m.end) for m in ms[1:]]
    assert seq == [("Rapid", (40, 60, 2)), ("Feed", (40, 60, -20)), ("Rapid", (40, 60, 10))]
    assert ms[2].feed == 100


def test_cycle83_chip_removal_depths():
    # RFP 0, FDPR 8, DAM 2, DP -30: strokes 8; 8-2 = 6; 6-2 = 4; 4-2 = 2 is not above DAM: DAM 2
    # from then on (remaining 12: six strokes of 2); the first at F x FRF 0.5 = 50
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -30, , , 8, 2, , , 0.5, 1)")
    assert zs(ms) == [-8, -14, -18, -20, -22, -24, -26, -28, -30]
    feeds = [m.feed for m in ms if type(m) is canon.Feed]
    assert feeds[0] == 50 and set(feeds[1:]) == {100}
    # after each stroke G0 to RFP + SDIS = 2, G0 back to 0.6 mm above the depth reached (the
    # anticipation distance up to 30 mm of depth), the feed on from there
    starts = [round(m.start[2], 9) for m in ms if type(m) is canon.Feed]
    assert starts == [2, -7.4, -13.4, -17.4, -19.4, -21.4, -23.4, -25.4, -27.4]
    assert ms[-1].end == (50, 50, 10) and type(ms[-1]) is canon.Rapid


def test_cycle83_anticipation_beyond_30mm_and_dis1():
    # 60 mm deep: anticipation 60 / 50 = 1.2 mm; _DIS1 0.3 replaces it
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -60, , -20, , , , , , 1)")
    assert zs(ms) == [-20, -40, -60]  # DAM 0: strokes as long as the first
    assert [round(m.start[2], 9) for m in ms if type(m) is canon.Feed] == [2, -18.8, -38.8]
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -60, , -20, , , , , , 1, , , , , 0.3)")
    assert [round(m.start[2], 9) for m in ms if type(m) is canon.Feed] == [2, -19.7, -39.7]


def test_cycle83_chip_breaking_and_last_two_strokes():
    # VARI 0: back 1 mm with G1 after each stroke. RFP 0, FDPR 8, DAM 3, DP -17: strokes 8; 8-3 = 5
    # (above 3); 5-3 = 2 is not above DAM: 3 is due, but only 4 remain (< 2 x 3): two strokes of 2
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -17, , , 8, 3, , , , 0)")
    feeds = [m for m in ms if type(m) is canon.Feed]
    assert [round(m.end[2], 9) for m in feeds] == [-8, -7, -13, -12, -15, -14, -17]
    assert not any(type(m) is canon.Rapid for m in ms[2:-1])  # no rapid inside the hole
    # _VRT 0.4 instead of 1 mm
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -17, , , 8, 3, , , , 0, , , 0.4)")
    assert zs(ms)[:2] == [-8, -7.6]


def test_cycle83_first_depth_beyond_the_hole_is_one_stroke():
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -5, , -8, , , , , , 1)")
    assert zs(ms) == [-5]


def test_cycle84_taps_at_the_pitch_per_revolution():
    # MPIT 10 = M10, pitch 1.5 mm per revolution, in and out to RFP + SDIS
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE84(10, 0, 2, -15, , , 3, 10, , 0, 200, 400)")
    feeds = [m for m in ms if type(m) is canon.Feed]
    assert [(m.end[2], m.feed, m.per_rev) for m in feeds] == [(-15, 1.5, True), (2, 1.5, True)]
    ms, prog = moves("G0 X50 Y50 Z20\nCYCLE84(10, 0, 2, -15, , , 3, , 1.25)\nG1 X60")
    feeds = [m for m in ms if type(m) is canon.Feed]
    assert [(m.feed, m.per_rev) for m in feeds] == [(1.25, True), (1.25, True), (100, False)]  # F restored


def test_cycle840_without_encoder_uses_the_feed():
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE840(10, 0, 2, -15, , , 0, 3, 1, 10)")
    feeds = [m for m in ms if type(m) is canon.Feed]
    assert [(m.end[2], m.feed, m.per_rev) for m in feeds] == [(-15, 100, False), (2, 100, False)]
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE840(10, 0, 2, -15, , , 0, 3, 0, 10)")
    assert [m.feed for m in ms if type(m) is canon.Feed] == [1.5, 1.5]


def test_boring_cycles():
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE85(10, 0, 2, -15, , , 80, 300)")
    assert [(type(m).__name__, m.end[2], getattr(m, "feed", None)) for m in ms[1:]] == [
        ("Rapid", 2, None), ("Feed", -15, 80), ("Feed", 2, 300), ("Rapid", 10, None)]
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE89(10, 0, 2, -15, , 1)")
    assert [(type(m).__name__, m.end[2]) for m in ms[1:]] == [("Rapid", 2), ("Feed", -15), ("Feed", 2), ("Rapid", 10)]
    for call in ("CYCLE86(10, 0, 2, -15, , 1, 3, 0.5, 0, 0.2, 0)", "CYCLE87(10, 0, 2, -15, , 4)",
                 "CYCLE88(10, 0, 2, -15, , 1, 3)"):
        ms, _ = moves("G0 X50 Y50 Z20\n" + call)
        assert [(type(m).__name__, m.end) for m in ms[1:]][1:2] == [("Feed", (50, 50, -15))]
        assert all(m.end[:2] == (50, 50) for m in ms)  # out along the bore's axis
        assert ms[-1].end == (50, 50, 10)


def holes_at(ms):
    """XY of every feed move down (where a hole is drilled)."""
    return [(round(m.end[0], 6), round(m.end[1], 6)) for m in ms if type(m) is canon.Feed and m.end[2] < m.start[2]]


def test_mcall_runs_after_every_positioning_block():
    body = ("G0 X10 Y10 Z10\nMCALL CYCLE81(10, 0, 2, -5)\nX20\nY30\nG1 X40 Y40\nZ12\nMCALL\nX70\n")
    ms, _ = moves(body)
    # not in the MCALL block; after X20, Y30, the G1 move and even the Z-only move; not after MCALL
    assert holes_at(ms) == [(20, 10), (20, 30), (40, 40), (40, 40)]


def test_holes1_row_from_the_nearer_end():
    # 4 holes on the line through (10, 20) at 30 degrees, the first 5 from it, 10 apart
    pts = [(10 + (5 + 10 * k) * math.cos(math.radians(30)), 20 + (5 + 10 * k) * math.sin(math.radians(30)))
           for k in range(4)]
    expect = [(round(x, 6), round(y, 6)) for x, y in pts]
    ms, _ = moves("MCALL CYCLE81(10, 0, 2, -5)\nHOLES1(10, 20, 30, 5, 10, 4)\nMCALL", start=(0, 0, 20))
    assert holes_at(ms) == expect
    ms, _ = moves("MCALL CYCLE81(10, 0, 2, -5)\nHOLES1(10, 20, 30, 5, 10, 4)\nMCALL", start=(90, 90, 20))
    assert holes_at(ms) == expect[::-1]


def test_holes2_default_angle_and_cycle801_meander():
    ms, _ = moves("MCALL CYCLE82(10, 0, 2, -5, , 0.5)\nHOLES2(50, 50, 20, 90, , 3)\nMCALL")
    # INDA empty: 360 / 3; angles 90, 210, 330
    expect = [(round(50 + 20 * math.cos(math.radians(a)), 6), round(50 + 20 * math.sin(math.radians(a)), 6))
              for a in (90, 210, 330)]
    assert holes_at(ms) == expect
    # a 3 x 2 grid from (10, 10), 15 apart along X (STA 0) and 20 across: row 1 forwards, row 2 back
    ms, _ = moves("MCALL CYCLE81(10, 0, 2, -5)\nCYCLE801(10, 10, 0, 15, 20, 3, 2)\nMCALL")
    assert holes_at(ms) == [(10, 10), (25, 10), (40, 10), (40, 30), (25, 30), (10, 30)]
    # turned by 90 degrees: the rows run along +Y, the columns to -X
    ms, _ = moves("MCALL CYCLE81(10, 0, 2, -5)\nCYCLE801(50, 10, 90, 15, 20, 2, 2)\nMCALL")
    assert holes_at(ms) == [(50, 10), (50, 25), (30, 25), (30, 10)]


def test_pattern_without_mcall_only_positions_and_warns():
    ms, prog = moves("G0 Z10\nHOLES2(50, 50, 20, 0, 90, 4)")
    assert holes_at(ms) == []
    assert [m.end for m in ms[1:]][:2] == [(70, 50, 10), (50, 70, 10)]
    assert any("without a modal cycle" in w for _, w in prog.warnings)


# ---------------------------------------------------------------------------------------------
# errors (the files under tests/data/bad/sinumerik/drill-*.mpf hold the column checks)
@pytest.mark.parametrize("call, text", [
    ("CYCLE81(10, 0, 2, 5)", "is not below the reference plane RFP 0"),
    ("CYCLE81(10, 0, 2, 0)", "is not below the reference plane"),
    ("CYCLE81(-5, 0, 2, -10)", "RTP -5 lies below the reference plane RFP 0"),
    ("CYCLE81(10, 0, -2, -10)", "SDIS is written without a sign"),
    ("CYCLE81(10, 0, 2, , -5)", "DPR is written without a sign"),
    ("CYCLE81(10, 0, 2)", "the depth is missing"),
    ("CYCLE83(10, 0, 2, -20, , , -3)", "FDPR is written without a sign"),
    ("CYCLE83(10, 0, 2, -20)", "the first drilling depth is missing"),
    ("CYCLE83(10, 0, 2, -20, , 3)", "FDEP 3 is not below the reference plane"),
    ("CYCLE83(10, 0, 2, -20, , , 5, , , , 1.5)", "FRF"),
    ("CYCLE83(10, 0, 2, -20, , , 5, , , , , 2)", "VARI must be 0 or 1"),
    ("CYCLE83(10, 0, 2, -20, , , 5, -1)", "DAM is written without a sign"),
    ("CYCLE84(10, 0, 2, -20, , , 3)", "no thread pitch"),
    ("CYCLE84(10, 0, 2, -20, , , 3, 7)", "MPIT must be a metric thread size"),
    ("CYCLE84(10, 0, 2, -20, , , 3, 10, 1.25)", "contradict"),
    ("CYCLE84(10, 0, 2, -20, , , 6, 10)", "SDAC must be"),
    ("CYCLE85(10, 0, 2, -20, , , 0, 100)", "FFR (the boring feed) must be positive"),
    ("CYCLE86(10, 0, 2, -20, , , 5)", "SDIR must be 3 or 4"),
    ("HOLES1(0, 0, 0, 0, 10, 0)", "NUM must be a whole number from 1 to 5,000,000 ([simulation] max_blocks)"),
    ("CYCLE801(0, 0, 0, 1, 1, 10, 2.5)", "NUM2 must be a whole number"),
    ("CYCLE81(10, 0, 2, -20, , , , , , 1)", "at most 9 parameters"),
    ("CYCLE82(10, 0, 2, -20, , 0, 1)", "_GMODE 1: a depth measured other than at the tool's tip"),
    ("CYCLE83(10, 0, 2, -20, , , 5, , , , , 1, 1)", "_AXN 1"),
])
def test_bad_parameters_are_errors_at_the_call(call, text):
    with pytest.raises(CutsimError) as e:
        moves("G0 X50 Y50 Z20\n" + call)
    assert e.value.line == 5 and text in e.value.message


def test_mcall_checks_its_cycle_at_the_mcall_block():
    with pytest.raises(CutsimError) as e:
        moves("G0 X50 Y50 Z20\nMCALL CYCLE81(10, 0, 2, 5)\nX10\n")
    assert e.value.line == 5 and "not below the reference plane" in e.value.message
    with pytest.raises(CutsimError) as e:
        moves("MCALL POCKET2(10, 0, 2, -5, , 10, 50, 50)")
    assert e.value.line == 4 and "drilling cycles" in e.value.message


def test_too_many_pecks_is_an_error_before_any_move():
    with pytest.raises(CutsimError) as e:
        moves("G0 X50 Y50 Z20\nCYCLE83(10, 0, 2, -20, , , 0.0001, , , , , 1)", max_blocks=10_000)
    assert "max_blocks" in e.value.message and e.value.line == 5


# ---------------------------------------------------------------------------------------------
# properties over parameter ranges
def fx(v: float) -> str:
    """A value as the program writes it (4 decimals); the test computes with what is written."""
    return f"{v:.4f}"


@settings(derandomize=True, max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rfp=st.floats(-20, 20), sdis=st.floats(0, 5), depth=st.floats(0.01, 80), up=st.floats(0, 30),
       first=st.floats(0.05, 40), dam=st.floats(0, 10), mdep=st.floats(0, 5), vari=st.sampled_from([0, 1]),
       vrt=st.floats(0, 3), x=st.floats(-50, 50), y=st.floats(-50, 50))
def test_cycle83_stays_on_the_axis_between_dp_and_rtp(rfp, sdis, depth, up, first, dam, mdep, vari, vrt, x, y):
    rfp, sdis, depth, up, first, dam, mdep, vrt, x, y = (float(fx(v)) for v in (rfp, sdis, depth, up, first, dam, mdep,
                                                                                vrt, x, y))
    dp, rtp = rfp - depth, rfp + up
    ms, _ = moves(f"G0 X{fx(x)} Y{fx(y)} Z{fx(rtp + 50)}\n"
                  f"CYCLE83({fx(rtp)}, {fx(rfp)}, {fx(sdis)}, {fx(dp)}, , , {fx(first)}, {fx(dam)}, , , , {vari}, , "
                  f"{fx(mdep)}, {fx(vrt)})", start=(0.0, 0.0, 100.0))
    cyc = ms[2:]
    assert all(m.end[:2] == (x, y) and m.start[:2] == (x, y) for m in cyc)
    assert min(m.end[2] for m in cyc) == pytest.approx(dp, abs=1e-9)
    assert all(m.end[2] >= dp - 1e-9 for m in cyc)
    assert cyc[-1].end[2] == pytest.approx(rtp, abs=1e-9) and type(cyc[-1]) is canon.Rapid
    # a rapid never goes deeper than the feed has cut (nor below the safety plane before the first)
    deepest = rfp + sdis
    for m in cyc:
        if type(m) is canon.Rapid:
            assert m.end[2] >= deepest - 1e-9
        deepest = min(deepest, m.end[2])


@settings(derandomize=True, max_examples=80, deadline=None)
@given(name=st.sampled_from(["CYCLE81", "CYCLE82", "CYCLE85", "CYCLE86", "CYCLE87", "CYCLE88", "CYCLE89",
                             "CYCLE84", "CYCLE840"]),
       rfp=st.floats(-20, 20), sdis=st.floats(0, 5), depth=st.floats(0.01, 80), up=st.floats(0, 30),
       relative=st.booleans())
def test_every_cycle_reaches_dp_and_ends_at_rtp(name, rfp, sdis, depth, up, relative):
    rfp, sdis, depth, up = (float(fx(v)) for v in (rfp, sdis, depth, up))
    dp, rtp = rfp - depth, rfp + up
    d = f", {fx(depth)}" if relative else f"{fx(dp)}, "
    extra = {"CYCLE85": ", 1, 100, 200", "CYCLE86": ", 1, 3", "CYCLE87": ", 3", "CYCLE88": ", 1, 4",
             "CYCLE84": ", 0, 3, 8", "CYCLE840": ", 0, 0, 3, 0, 8"}.get(name, "")
    ms, _ = moves(f"G0 X5 Y5 Z{fx(rtp + 10)}\n{name}({fx(rtp)}, {fx(rfp)}, {fx(sdis)}, {d}{extra})",
                  start=(0, 0, 100.0))
    cyc = ms[2:]
    assert min(m.end[2] for m in cyc) == pytest.approx(dp, abs=1e-9)
    assert all(m.end[2] >= dp - 1e-9 and m.end[:2] == (5, 5) for m in cyc)
    assert cyc[-1].end[:2] == (5, 5) and cyc[-1].end[2] == pytest.approx(rtp, abs=1e-9)


def test_mcall_of_subprograms():
    # MCALL SPOT (no parameters), MCALL BORE(3) (a PROC with a parameter), MCALL L77: each runs after
    # every positioning block, the subprogram's own moves do not call it again, MCALL alone ends it
    body = ("G0 X10 Y10 Z5\nMCALL SPOT\nX20\nX30 Y30\nMCALL BORE(3)\nX40\nMCALL L77\nX50\nMCALL\nX60\nM30\n"
            "PROC SPOT\nG1 Z-1\nG0 Z5\nRET\nPROC BORE(REAL DEPTH)\nG1 Z=-DEPTH\nG0 Z5\nRET\nPROC L77\nG1 Z-4\nG0 Z5\nRET")
    ms, _ = moves(body)
    assert holes_at(ms) == [(20, 10), (30, 30), (40, 30), (50, 30)]
    assert [m.end[2] for m in ms if type(m) is canon.Feed] == [-1, -1, -3, -4]
    assert ms[-1].end == (60, 30, 5)


def test_modal_cycle_runs_in_the_workpiece_coordinates(monkeypatch):
    # G54 = (100, 0, -10) and TRANS X10 Y5 Z-2: WCS -> machine adds (110, 5, -12). The modal CYCLE81
    # after X20 (machine X130, Y15) goes to RFP + SDIS = 2 -> -10, drills to DP -5 -> -17, back to
    # RTP 10 -> -2; HOLES1 puts holes at WCS (10, 0) and (20, 0), from the nearer end (20, 0)
    from cutsim.interp.sinumerik import machine as sinumerik_machine
    monkeypatch.setattr(sinumerik_machine, "MODAL_CYCLES_IN_WCS", True)  # the machine side's guard
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: R},
                       work_offsets={"G54": (100.0, 0.0, -10.0)})
    text = (HEAD + "G54\nTRANS X10 Y5 Z-2\nG0 X10 Y10 Z20\nMCALL CYCLE81(10, 0, 2, -5)\nX20\n"
            "HOLES1(0, 0, 0, 10, 10, 2)\nMCALL\nTRANS\nM30\n")
    ms = [r for r in interpret("p.mpf", text, cfg).records if isinstance(r, canon.MOTIONS)]
    feeds = [(m.start, m.end) for m in ms if type(m) is canon.Feed]
    assert feeds == [((130, 15, -10), (130, 15, -17)), ((130, 5, -10), (130, 5, -17)), ((120, 5, -10), (120, 5, -17))]
    assert ms[-1].end == (120, 5, -2)


def test_cycle84_in_steps_and_pitch_units():
    # _VARI 1: steps of _DAM 4 to DP -10 (-4, -8, -10), back 0.5 (_VRT) after each; _VARI 2: out to
    # RFP + SDIS = 2 after each; PIT 20 threads per inch (_PTAB 2) is 25.4 / 20 = 1.27 mm
    head = "G0 X50 Y50 Z20\nCYCLE84(10, 0, 2, -10, , , 3, , 1.5, 0, 300, 300, , , , "
    ms, _ = moves(head + "1, 4, 0.5)")
    assert zs(ms) == [-4, -3.5, -8, -7.5, -10, 2]
    ms, _ = moves(head + "2, 4)")
    assert zs(ms) == [-4, 2, -8, 2, -10, 2]
    ms, _ = moves("G0 X50 Y50 Z20\nCYCLE84(10, 0, 2, -10, , , 3, , 20, 0, 300, 300, , 2)")
    assert [m.feed for m in ms if type(m) is canon.Feed] == [1.27, 1.27]
    with pytest.raises(CutsimError) as e:
        moves("G0 X50 Y50 Z20\nCYCLE84(10, 0, 2, -10, , , 3, , 1.5, 0, 300, 300, 1)")
    assert "_AXN 1" in e.value.message


# ---------------------------------------------------------------------------------------------
# the drill's body (stock/tools.py)
@pytest.mark.parametrize("angle", [118.0, 90.0, 140.0, 180.0])
def test_drill_body_is_cylinder_on_cone(angle):
    from cutsim.base.specs import ToolSpec
    from cutsim.stock.tools import checked_mill, mill_body, point_height

    t = ToolSpec(number=1, kind="drill", diameter=8.5, length=40.0, point_angle=angle)
    assert point_height(t) == pytest.approx(cone_height(angle))
    tol = 0.01
    pts = mill_body(t, tol)[0]
    assert pts[:, 2].min() == 0.0 and pts[:, 2].max() == 40.0
    if angle < 180:  # the tip is the one lowest vertex, on the axis
        low = pts[pts[:, 2] == 0.0]
        assert low.tolist() == [[0.0, 0.0, 0.0]]
    # every vertex on the true surface within the tolerance: radius r above the point, z tan(a/2) on it
    rad = np.hypot(pts[:, 0], pts[:, 1])
    hc = cone_height(angle)
    want = np.where(pts[:, 2] >= hc - 1e-12, R, pts[:, 2] * (R / hc if hc else 0.0))
    assert np.all(np.abs(rad - want) <= tol + 1e-12)
    v = math.pi * R * R * (40.0 - hc) + math.pi * R * R * hc / 3
    area = 2 * math.pi * R * (40.0 - hc) + math.pi * R * math.hypot(R, hc)
    assert checked_mill(t, tol) == pytest.approx(v, abs=tol * area)
    # cut off inside the point: the section there has the cone's radius
    top = 0.5 * hc if hc else 1.0
    cut = mill_body(t, tol, top)[0]
    assert cut[:, 2].max() == pytest.approx(top)
    assert np.hypot(cut[:, 0], cut[:, 1]).max() == pytest.approx(top * R / hc if hc else R, abs=tol)


@pytest.mark.parametrize("kw, key", [({"point_angle": 0.5}, "point_angle"), ({"point_angle": 181.0}, "point_angle"),
                                     ({"length": 2.0}, "length"), ({"diameter": 0.0}, "diameter")])
def test_drill_ranges(kw, key):
    from cutsim.base.specs import ToolSpec
    from cutsim.stock.tools import tool_problem

    t = ToolSpec(**{"number": 1, "kind": "drill", "diameter": 8.5, "length": 40.0, "point_angle": 118.0, **kw})
    assert tool_problem(t)[0] == key


# ---------------------------------------------------------------------------------------------
# the ISO shell G81 ... G89 / G80 (G98 / G99)
def test_iso_g81_and_g83_holes_on_the_solid(tmp_path):
    """G81 and G83 in ISO form leave the drill's cylinder and cone with the tip at Z (the pecks of
    G83 retrace the hole); the initial level Z20 and the R plane 2 lie above the stock: nothing
    else is cut."""
    r = simulate(tmp_path, "G0 X30 Y30 Z20\nG98 G81 X30 Y30 Z-15 R2 F100\nG83 X70 Y60 Z-25 R2 Q6\nG80 G0 Z50")
    m = r.mesh()
    assert r.report["warnings"] == []
    assert floor_z(m, (30.0, 30.0), 1.0) == pytest.approx(-15.0, abs=2 * TOL)
    assert floor_z(m, (70.0, 60.0), 1.0) == pytest.approx(-25.0, abs=2 * TOL)
    for c, depth in (((30.0, 30.0), 15.0), ((70.0, 60.0), 25.0)):
        segs = hsection(m, -depth / 2)
        for a in range(0, 360, 45):
            u = (math.cos(math.radians(a)), math.sin(math.radians(a)))
            assert ray(segs, c, u) == pytest.approx(R, abs=TOL + 1e-6)
    v = hole_volume(15.0, 118.0) + hole_volume(25.0, 118.0)
    assert r.report["removed_volume"] == pytest.approx(v, abs=TOL * (wall_area(15.0, 118.0) + wall_area(25.0, 118.0)))


def test_iso_cycle_is_modal_until_g80_or_a_motion_code():
    mv, _ = moves("G0 X10 Y10 Z30\nG99 G81 Z-5 R3 F100\nX20\nF200\nM8\nY20\nG80\nX30\nG81 X40 Z-2 R1\nG1 X50\n")
    holes = [(m.end[0], m.end[1]) for m in mv if isinstance(m, canon.Feed) and m.end[2] < 0]
    # the G81 block drills where the tool stands; F200 and M8 alone drill nothing; after G80 and
    # after G1 the blocks only move
    assert holes == [(10, 10), (20, 10), (20, 20), (40, 20)]
    assert mv[-1].end == (50, 20, 1) and isinstance(mv[-1], canon.Feed)  # G1 at the level G99 left: R1
    assert mv[-2].end == (40, 20, 1)  # G99: back to R


def test_iso_cycle_waits_through_a_subprogram_call(tmp_path):
    """L100 alone in cycle mode is the subprogram call it is in Siemens mode (no repeat count); the
    subprogram's X moves drill, as the modal cycle is still on."""
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: R})
    (tmp_path / "L100.spf").write_text("X30\nM17\n")
    prog = interpret(str(tmp_path / "p.mpf"), HEAD + "G0 X10 Y10 Z20\nG81 Z-4 R2\nL100\nG80\nM30\n", cfg)
    holes = [(m.end[0], m.end[1]) for m in prog.moves if isinstance(m, canon.Feed) and m.end[2] == -4]
    assert holes == [(10, 10), (30, 10)]


def test_cycle72_contour_with_an_iso_cycle_is_refused():
    with pytest.raises(CutsimError) as e:
        moves("F100\nCYCLE72(\"KK\", 10, 0, 2, -3, 3, 0, 0, 300, 100, 0, 42, 1, 5, 0, 1, 5)\nM30\n"
              "PROC KK\nG0 X0 Y0\nG81 X10 Z-4 R2\nRET", head="G17 G90\nT2 D1 M6\n")
    assert e.value.line == 8 and "G81 is not allowed there" in e.value.message


def test_iso_g98_returns_to_the_initial_level_of_the_mode():
    """The initial level is where the tool stood when the mode began (Z30), not where a later hole
    started from; a new cycle code keeps it and the hole data (R, Z)."""
    mv, _ = moves("G0 X10 Y10 Z30\nG99 G81 Z-5 R3 F100\nX20\nG98 G82 X30\n")
    assert [m.end[2] for m in mv if m.end[:2] == (30, 10)] == [3, -5, 30]  # at R already: in, out to 30


@pytest.mark.parametrize("body, line, col, text", [
    ("G0 X1 R2", 4, 7, "the address R belongs to the ISO drilling cycles"),
    ("G1 X1 Q3", 4, 7, "the address Q belongs to the ISO drilling cycles"),
    ("G91 G81 X1 Z-5 R2", 4, 5, "G91"),
    ("G0 Z10\nG83 X1 Z-5 R2", 5, 1, "G83 needs the peck depth Q"),
    ("G0 Z10\nG81 X1 R2", 5, 1, "G81 needs the depth of the hole: Z"),
    ("G0 Z10\nG81 X1 Z-3", 5, 1, "G81 needs the R plane"),
    ("G0 Z10\nG87 X1 Z-5 R2", 5, 1, "G87 (back boring) is not simulated"),
    ("G0 Z10\nG81 X1 Z-5 R2 K3", 5, 15, "repeat count"),
    ("G0 Z10\nG0 G81 X1 Z-5 R2", 5, 1, "G0 and the drilling cycle G81 in one block"),
    ("G0 Z10\nG81 G82 X1 Z-5 R2", 5, 5, "G82 conflicts with G81"),
    ("G0 Z10\nG81 X1 Z5 R2", 5, 1, "G81 (as CYCLE81: RFP = R, DP = Z, RTP = the return level): the final drilling depth 5"),
    ("G0 Z1\nG98 G81 X1 Z-5 R2", 5, 5, "the retraction plane RTP 1 lies below the reference plane RFP 2"),
    ("MCALL CYCLE81(10, 0, 2, -5)\nG81 X1 Z-5 R2", 5, 1, "while the modal call MCALL CYCLE81 is active"),
    ("G0 Z10\nG82 X1 Z-5 R2 P500\nG80 X3 P2", 6, 8, "P (repeat count) only goes with a subprogram call"),
    ("G0 Z10\nG81 X1 Z-5 R2\nMCALL CYCLE81(10, 0, 2, -3)\nF100\nY3", 8, 1, "are both active"),
    ("G0 Z10\nG81 X1 Z-5 R2\nX2 Y3 Z4", 6, 1, "the final drilling depth 4 (DP)"),  # the hole's own block
    ("G0 Z10\nG81 X1 Z-5 R2\nX5 L3", 6, 4, "a repeat count of the drilling cycle G81"),
])
def test_iso_errors(body, line, col, text):
    with pytest.raises(CutsimError) as e:
        moves(body)
    assert (e.value.line, e.value.col) == (line, col) and text in e.value.message, e.value


def test_a_grid_of_5000_holes_runs_and_max_blocks_bounds_it():
    """CYCLE801 100 x 50 (5,000 holes, as a real program writes): every hole is drilled, the grid
    meanders (row 2 backwards); a pattern whose holes alone exceed [simulation] max_blocks is
    refused before any move (4 moves per hole at least with a modal cycle)."""
    body = "G0 X0 Y0 Z20\nMCALL CYCLE81(10, 0, 1, -3)\nCYCLE801(30, 20, 0, 10, 15, 100, 50)\nMCALL"
    mv, _ = moves(body)
    holes = [m.end[:2] for m in mv if isinstance(m, canon.Feed) and m.end[2] == -3]
    assert len(holes) == 5000 and len(set(holes)) == 5000
    assert holes[0] == (30, 20) and holes[99] == (30 + 99 * 10, 20) and holes[100] == (30 + 99 * 10, 35)
    assert holes[-1] == (30, 20 + 49 * 15)  # 50 rows: the last (even count) runs backwards
    with pytest.raises(CutsimError) as e:
        moves(body, max_blocks=19_999)
    assert e.value.line == 6 and "5,000 holes, at least 4 move(s) each" in e.value.message
    assert "max_blocks = 19,999" in e.value.message
    moves(body, max_blocks=20_500)  # 5,000 x 4 moves fit


@pytest.mark.parametrize("plane, axis", [("G18", "Y"), ("G19", "X")])
def test_drilling_in_another_plane_is_refused_with_the_axis(plane, axis):
    """The simulated tool stands along Z: CYCLE81 in G18 would drill along Y (a horizontal
    spindle), which the simulator cannot cut; an error names the axis, also for MCALL and the ISO
    shell."""
    for body, line in ((f"{plane}\nCYCLE81(10, 0, 2, -5)", 5), (f"{plane}\nMCALL CYCLE81(10, 0, 2, -5)", 5),
                       (f"{plane}\nG0 Z10\nG81 X1 Z-5 R2", 6)):
        with pytest.raises(CutsimError) as e:
            moves(body)
        assert e.value.line == line and f"in {plane} drills along {axis}" in e.value.message, e.value
