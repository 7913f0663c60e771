"""Sinumerik lathe mode, the interpreter's records (docs/dialects/sinumerik-turning.md).

The records carry machine millimetres with X a radius (``diameter`` False). Every expected value
is derived by hand in the test's docstring or comment: a DIAMON X40 is the radius 20, a thread of
lead K over a travel L turns the spindle L/K times, so a chained block starts SF + 360 L/K degrees
(mod 360) on; a run-in DITS over which the lead rises linearly from 0 to K turns 2 DITS/K times
(its travel is K n^2 / (2 n_a) over n_a turns), a G34 from K over L ends at the lead
sqrt(K^2 + 2 F L) after (Ke - K)/F turns; under G96 the speed is 1000 S / (2 pi r) rpm.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings, strategies as st

from cutsim.interp import CutsimError, InterpConfig, canon, interpret


def run(text: str, kind: str = "lathe", diameter: bool = False, start=(50.0, 0.0, 10.0), **kw) -> canon.Program:
    cfg = InterpConfig(dialect="sinumerik", machine_kind=kind, diameter_programming=diameter, start=start, **kw)
    return interpret("t.mpf", text, cfg)


def ends(prog) -> list[tuple[float, float]]:
    """(X radius, Z) of every motion's end, rounded to 1e-6."""
    return [(round(r.end[0], 6) + 0.0, round(r.end[2], 6) + 0.0) for r in prog.moves]


def syncs(prog) -> list[canon.SyncedFeed]:
    return [r for r in prog.records if isinstance(r, canon.SyncedFeed)]


def fails(text: str, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, **kw)
    return e.value


# -- diameter programming ------------------------------------------------------------------------
def test_diameter_modes():
    """DIAMON: absolute and incremental X are diameters; DIAM90: diameters under G90, radii under
    G91 (and in IC(..)); DIAMOF and DIAMCYCOF: radii. X40 -> 20; G91 X-4 (DIAMON) -> 18; G91 X-4
    (DIAM90) -> 14; G90 X20 -> 10; X=IC(-2) -> 8; DIAMOF X20 -> 20; DIAMON X=AC(30) -> 15 (G91 still
    on); DIAMCYCOF X12 -> 12."""
    prog = run("DIAMON\nG0 X40 Z5\nG91 X-4\nDIAM90\nX-4\nG90 X20\nX=IC(-2)\nDIAMOF\nX20\nDIAMON G91\nX=AC(30)\n"
               "G90 DIAMCYCOF\nX12\nM30\n")
    assert [x for x, _ in ends(prog)] == [20.0, 18.0, 14.0, 10.0, 8.0, 20.0, 15.0, 12.0]
    assert all(not r.diameter for r in prog.moves)


def test_setup_with_diameters_starts_in_diamon():
    """[machine] diameter_programming = true: the start X60 is the diameter 60 (radius 30), X40 the
    radius 20."""
    prog = run("G0 X40 Z0\nM30\n", diameter=True, start=(60.0, 0.0, 5.0))
    assert prog.moves[0].start == (30.0, 0.0, 5.0) and ends(prog) == [(20.0, 0.0)]


def test_work_offset_and_trans_shift_x_as_a_radius():
    """G54 = (10, 0, -5) and TRANS X2 Z-3 are radius shifts: DIAMON X40 Z0 -> 20 + 2 + 10 = 32,
    0 - 3 - 5 = -8."""
    prog = run("G54 DIAMON\nTRANS X2 Z-3\nG0 X40 Z0\nM30\n", work_offsets={"G54": (10.0, 0.0, -5.0)})
    assert ends(prog) == [(32.0, -8.0)]


@pytest.mark.parametrize("centre", ["I0 K-10", "I=AC(20) K=AC(-10)"])
def test_arc_centre_under_diamon(centre):
    """A quarter circle from (r 10, Z0) to (r 20, Z-10) about (r 10, Z-10): the incremental I is a
    radius (a distance from the start), I=AC(..) a diameter (20 -> radius 10)."""
    prog = run(f"DIAMON\nG0 X20 Z0\nG3 X40 Z-10 {centre} F100\nM30\n")
    arc = prog.moves[-1]
    assert isinstance(arc, canon.Arc) and arc.center == (10.0, 0.0, -10.0) and arc.end == (20.0, 0.0, -10.0)


def test_diamon_on_a_mill_is_an_error_and_diamof_passes():
    e = fails("G17\nDIAMON\nM30\n", kind="mill", start=(0.0, 0.0, 50.0))
    assert (e.line, e.col) == (2, 1) and "needs a lathe" in e.message
    assert run("DIAMOF\nG0 X5\nM30\n", kind="mill", start=(0.0, 0.0, 50.0)).moves[0].end == (5.0, 0.0, 50.0)


# -- G33 ------------------------------------------------------------------------------------------
def test_longitudinal_face_and_taper_threads():
    """K along Z (longitudinal; a taper of 5 radial over 20 axial keeps K), I along X (face; a taper
    of 15 radial over 5 axial takes I)."""
    prog = run("DIAMON M3 S500\nG0 X27.4 Z4\nG33 Z-20 K2 SF=45\nG0 X10 Z0\nG33 X40 I1.5\nG0 X20 Z0\n"
               "G33 X30 Z-20 K2\nG0 X10 Z0\nG33 X40 Z-5 I3\nM30\n")
    s = syncs(prog)
    assert [(r.start, r.end, r.lead, r.lead_axis, r.start_angle) for r in s] == [
        ((13.7, 0.0, 4.0), (13.7, 0.0, -20.0), 2.0, "Z", 45.0),
        ((5.0, 0.0, 0.0), (20.0, 0.0, 0.0), 1.5, "X", 45.0),  # SF stays in force
        ((10.0, 0.0, 0.0), (15.0, 0.0, -20.0), 2.0, "Z", 45.0),
        ((5.0, 0.0, 0.0), (20.0, 0.0, -5.0), 3.0, "X", 45.0)]


def test_chained_blocks_continue_the_spindle_angle():
    """SF=30, K2 over 5 mm: 2.5 turns -> the next block starts at 30 + 900 = 930 = 210 degrees; K1.5
    over 3 mm: 2 turns -> 210 again. A G0 ends the chain: the next thread starts at SF, 30."""
    prog = run("M3 S500\nG0 X13 Z5\nG33 Z0 K2 SF=30\nZ-3 K1.5\nX15 Z-6 K1.5\nG0 X20\nZ5\nX13\nG33 Z0 K2\nM30\n")
    assert [round(r.start_angle, 9) for r in syncs(prog)] == [30.0, 210.0, 210.0, 30.0]


def test_sf_in_a_chained_block_acts_on_the_next_chain():
    prog = run("M3 S500\nG0 X13 Z5\nG33 Z0 K2 SF=30\nZ-3 K1.5 SF=90\nG0 X20\nZ5\nX13\nG33 Z0 K2\nM30\n")
    assert [round(r.start_angle, 9) for r in syncs(prog)] == [30.0, 210.0, 90.0]
    assert any("SF=90 in a chained thread block" in m for _, m in prog.warnings)


def test_dits_dite_run_in_and_run_out():
    """DITS=1 DITE=2, K4 from Z4 to Z-20 chained to a taper lift to (16, -24): the run-in Z4..Z3
    with the lead rising from 0 (lead change K^2 / (2 DITS) = 8) turns 2 DITS/K = 0.5 times (45 ->
    225); the thread Z3..Z-20 turns 23/4 = 5.75 times (-> 135); the last block's last 2 mm along Z
    (from (14.85, -22)) are the run-out, lead change -K^2 / (2 DITE) = -4, starting 0.5 turns after
    135, at 315. The first block keeps no run-out: the chain goes on."""
    prog = run("DIAMON M3 S500\nDITS=1 DITE=2\nG0 X27.4 Z4\nG33 Z-20 K4 SF=45\nG33 X32 Z-24 K4\nG0 X40\nM30\n")
    assert [(r.start, r.end, r.lead, round(r.start_angle, 9), r.lead_change) for r in syncs(prog)] == [
        ((13.7, 0.0, 4.0), (13.7, 0.0, 3.0), 0.0, 45.0, 8.0),
        ((13.7, 0.0, 3.0), (13.7, 0.0, -20.0), 4.0, 225.0, 0.0),
        ((13.7, 0.0, -20.0), (14.85, 0.0, -22.0), 4.0, 135.0, 0.0),
        ((14.85, 0.0, -22.0), (16.0, 0.0, -24.0), 4.0, 315.0, -4.0)]
    assert prog.warnings == []


def test_dite_at_the_program_end():
    """No block after the thread: the run-out still goes on it (the last 2 mm of Z3..Z-5)."""
    prog = run("M3 S500\nDITE=2\nG0 X13 Z3\nG33 Z-5 K1\n")
    assert [(r.start[2], r.end[2], r.lead_change) for r in syncs(prog)] == [(3.0, -3.0, 0.0), (-3.0, -5.0, -0.25)]


def test_g34_g35_record_the_change_of_lead():
    """G34 K2 F0.1 over 24 mm: lead change +0.1 (the end lead sqrt(4 + 4.8) = 2.966479 after 9.66479
    turns: the chained G35 starts 45 + 3479.32 = 284.326 degrees on); G35: -0.05. F is the lead
    change only: the following G1 feeds at the F0.2 before."""
    prog = run("DIAMON M3 S500 G95 F0.2\nG0 X27.4 Z4\nSF=45\nG34 Z-20 K2 F0.1\nG35 Z-30 K3 F0.05\nG1 X40\nM30\n")
    s = syncs(prog)
    assert [(r.lead, r.lead_change) for r in s] == [(2.0, 0.1), (3.0, -0.05)]
    turns = (math.sqrt(4.0 + 2 * 0.1 * 24) - 2.0) / 0.1
    assert s[1].start_angle == pytest.approx((45.0 + 360.0 * turns) % 360.0, abs=1e-9)
    assert prog.moves[-1].feed == 0.2


def test_threads_under_frames():
    """TRANS Z-10 moves the thread (Z4 -> Z-6); MIRROR Z0 mirrors it (Z-4 .. Z20), the lead stays;
    under G70 K0.1 is 2.54 mm per turn."""
    s = syncs(run("M3 S500\nTRANS Z-10\nG0 X13 Z4\nG33 Z-20 K2\nMIRROR Z0\nG0 X13 Z4\nG33 Z-20 K2\n"
                  "TRANS\nG70 G0 X0.5 Z0.2\nG33 Z-0.8 K0.1\nM30\n"))
    assert [(r.start[2], r.end[2], r.lead) for r in s] == [(-6.0, -30.0, 2.0), (-4.0, 20.0, 2.0),
                                                           (5.08, pytest.approx(-20.32), pytest.approx(2.54))]


@pytest.mark.parametrize("text,line,col,fragment", [
    ("G0 X10 Z0\nG33 X40 Z-5 K2\n", 2, 13, "programmed on I"),
    ("G0 X10 Z0\nG33 X12 Z-20 I2\n", 2, 14, "programmed on K"),
    ("G0 X10 Z0\nG33 Z-20 J2\n", 2, 10, "no Y axis"),
    ("G0 X10 Z0\nG33 Z-20 K2 I2\n", 2, 13, "two leads"),
    ("G0 X10 Z0\nG33 Z-20\n", 2, 5, "needs its lead"),
    ("G0 X10 Z0\nG33 Z-20 K-2\n", 2, 10, "greater than 0"),
    ("G0 X10 Z0\nG33 K2\n", 2, 5, "without an end point"),
    ("G0 X10 Z0\nG33 Z-20 K2 SF=360\n", 2, 13, "SF (the thread's start angle) = 360"),
    ("G0 X10 Z0\nDITS=-2\n", 2, 1, "DITS = -2"),
    ("G0 X10 Z0\nDITS=30\nG33 Z-20 K2\n", 3, 10, "DITS=30: the run-in is not shorter"),
    ("G0 X10 Z0\nDITE=20\nG33 Z-20 K2\nG0 X20\n", 3, 1, "DITE=20: the run-out is not shorter"),
    ("G0 X10 Z0\nG35 Z-20 K1 F0.1\n", 2, 13, "brings the lead 1 to zero after 5 mm"),
    ("G0 X10 Z0\nG34 Z-20 K1\n", 2, 10, "needs F"),
    ("G0 X10 Z0\nROT RPL=30\nG33 Z-20 K2\n", 3, 10, "rotated frame"),
    ("G0 X10 Z0\nG1 Z-5 K2 F100\n", 2, 8, "address K has no meaning in a G1 block"),
    ("G17 T1 D1\nG41 G0 X10 Z0\n", 2, 1, "G41 on a lathe in the plane XY"),
])
def test_thread_errors_at_the_word(text, line, col, fragment):
    e = fails("M3 S500\n" + text + "M30\n", tool_noses={1: (0.4, 3)}, tool_radii={1: 0.0})
    assert (e.line - 1, e.col) == (line, col) and fragment in e.message, e


@pytest.mark.parametrize("text,col,fragment", [("G33 Z-5 K1", 1, "needs a lathe"), ("G331 Z-5 K1", 1, "needs a lathe"),
                                               ("G63 Z-5", 1, "needs a lathe"), ("G0 Z5 SF=10", 7, "belongs to thread cutting")])
def test_turning_codes_on_a_mill(text, col, fragment):
    e = fails("G17 M3 S500\n" + text + "\nM30\n", kind="mill", start=(0.0, 0.0, 50.0))
    assert (e.line, e.col) == (2, col) and fragment in e.message


# -- tapping -------------------------------------------------------------------------------------
def test_rigid_tapping():
    """G331 Z-16 K1.5 from Z3: 19 mm = 12 2/3 turns under M3 (K > 0), ending 240 degrees past the
    zero mark; G332 reverses the spindle and starts at -240 = 120 degrees in its own direction (the
    same helix); the spindle stands after it. K-1 taps left-hand (M4)."""
    prog = run("M3 S200\nG0 X0 Z3\nG331 Z-16 K1.5\nG332 Z3\nG0 Z5\nG331 Z-5 K-1\nG332 Z5\nM30\n")
    s = syncs(prog)
    assert [(r.end[2], r.lead, round(r.start_angle, 9)) for r in s] == [(-16.0, 1.5, 0.0), (3.0, 1.5, 120.0),
                                                                       (-5.0, 1.0, 0.0), (5.0, 1.0, 0.0)]
    dirs = [r.direction for r in prog.records if isinstance(r, canon.Spindle)]
    assert dirs == [1, 1, -1, 0, -1, 1, 0]


@pytest.mark.parametrize("text,line,col,fragment", [
    ("G0 X0 Z3\nG331 Z-10 X2 K1\n", 2, 11, "X must stay"),
    ("G0 X0 Z3\nG332 Z5\n", 2, 6, "right after the G331"),
    ("G0 X0 Z3\nG331 Z-10 K1\nG332 Z5 K2\n", 3, 9, "must be the G331's"),
    ("G0 X0 Z3\nG331 Z-10\n", 2, 6, "needs its pitch"),
    ("G0 X0 Z3\nG331 Z-10 I1\n", 2, 11, "programmed on K"),
    ("M5\nG0 X0 Z3\nG63 Z-10 F1\n", 3, 5, "spindle turning"),
    ("G0 X0 Z3\nG63 Z-10 K1 F1\n", 2, 10, "address K has no meaning in a G63 block"),
])
def test_tapping_errors_at_the_word(text, line, col, fragment):
    e = fails("M3 S500 G95\n" + text + "M30\n")
    assert (e.line - 1, e.col) == (line, col) and fragment in e.message, e


def test_floating_tapping():
    """G63 Z-10 F1.25 under G95: lead 1.25 along Z, from the zero mark; G63 Z5 M4 reverses the
    spindle from there: 15 mm = 12 turns, the end angle 0 -> the reverse starts at 0 on the same
    helix. Under G94 F500 S400: lead 500/400 = 1.25."""
    s = syncs(run("G95 M3 S400\nG0 X0 Z5\nG63 Z-10 F1.25\nG63 Z5 M4\nG94 M3\nG63 Z-10 F500\nM30\n"))
    assert [(r.end[2], r.lead, r.start_angle) for r in s] == [(-10.0, 1.25, 0.0), (5.0, 1.25, 0.0),
                                                              (-10.0, 1.25, 0.0)]


# -- constant cutting speed -----------------------------------------------------------------------
def test_constant_cutting_speed():
    """G96 S200 LIMS=2000 at the radius 50: 1000 * 200 / (2 pi 50) = 636.62 rpm, the record carries
    the cutting speed and the limit; G97 at the radius 0 freezes the limit 2000, G97 at the radius
    20 (after G96 again) 1000 * 200 / (2 pi 20) = 1591.55."""
    prog = run("DIAMON G95\nG96 S200 LIMS=2000 M3\nG1 X0 Z0 F0.2\nG97\nX40\nG96 S200\nG97\nM30\n", diameter=True,
               start=(100.0, 0.0, 10.0))
    sp = [r for r in prog.records if isinstance(r, canon.Spindle)]
    assert sp[0].speed == pytest.approx(1000 * 200 / (2 * math.pi * 50)) and (sp[0].css, sp[0].limit) == (200, 2000)
    assert (sp[1].speed, sp[1].css) == (2000, 0.0)
    assert sp[-1].speed == pytest.approx(1000 * 200 / (2 * math.pi * 20)) and sp[-1].css == 0.0


# -- tool nose radius compensation ----------------------------------------------------------------
def test_nose_radius_compensation_with_the_edge_position():
    """G42, nose radius 0.8, cutting edge position 3 (the tip at centre + (-r, -r) in (X, Z)): the
    program's contour (r 10 from Z2 to Z-20, a face to r 20) is where the tip's edges touch. The
    nose centre runs at r 10.8 (right of the travel towards -Z); the control point is r below and
    r towards -Z of it: (10, 2 - 0.8) at the straight approach's end, (10, -20.8) at the end of the
    cylinder, then the G40 departure to the programmed (20, -20)."""
    prog = run("DIAMON T1 D1\nG18 G0 X12 Z6\nG42 G1 X20 Z2 F0.2\nZ-20\nG40 X40\nM30\n",
               tool_noses={1: (0.8, 3)}, tool_radii={1: 0.0})
    assert ends(prog) == [(6.0, 6.0), (10.0, 1.2), (10.0, -20.8), (20.0, -20.0)]


def test_sf_in_the_block_that_ends_a_chain_does_not_warn():
    prog = run("M3 S500\nG0 X13 Z5\nG33 Z0 K2 SF=30\nG0 X20 SF=90\nZ5\nX13\nG33 Z0 K2\nM30\n")
    assert [round(r.start_angle, 9) for r in syncs(prog)] == [30.0, 90.0] and prog.warnings == []


@pytest.mark.parametrize("frame,z,lead", [("TRANS Z-10", (4.0, -30.0), 2.0), ("SCALE Z2", (4.0, -40.0), 4.0)])
def test_a_cycles_thread_is_mapped_under_a_frame(frame, z, lead):
    """A cycle's moves run in the WCS and are mapped into the machine afterwards (machine.run_mapped):
    a thread from where the tool stands (machine Z4) to (13, -20) in the WCS ends at Z-20-10 under
    TRANS Z-10; SCALE Z2 doubles the end's Z (-40) and the lead along Z (2 -> 4)."""
    from cutsim.interp.sinumerik import Sinumerik
    from cutsim.interp.sinumerik import machine, turning
    m = Sinumerik("t.mpf", InterpConfig(dialect="sinumerik", machine_kind="lathe", start=(13.0, 0.0, 4.0)))
    m.run(f"{frame}\n")
    src = canon.Src("t.mpf", 9)
    machine.run_mapped(m, m.machine, lambda: turning.emit(m, src, (13.0, 0.0, -20.0), 2.0, "Z", 30.0))
    rec = m.program.records[-1]
    assert isinstance(rec, canon.SyncedFeed) and (rec.start[2], rec.end[2], rec.lead) == (z[0], z[1], lead)
    assert rec.start_angle == 30.0


@settings(max_examples=150, deadline=None)
@given(k=st.sampled_from([0.5, 1.0, 1.25, 1.5, 2.0, 3.5, 6.0]), sf=st.integers(0, 359),
       dits=st.sampled_from([0.0, 0.5, 1.0, 2.5]), dite=st.sampled_from([0.0, 0.5, 2.0]),
       l1=st.integers(4, 40), l2=st.integers(4, 40))
def test_chain_angles_over_the_documented_range(k, sf, dits, dite, l1, l2):
    """A chain of two longitudinal blocks (L1, L2 mm at lead K) with run-in DITS and run-out DITE:
    the pieces start at SF; SF + 360 (2 DITS / K) (after the run-in); SF + 360 (2 DITS + L1 - DITS)/K
    (the second block); that + 360 (L2 - DITE)/K (the run-out), all mod 360; the run-in's lead
    change K^2/(2 DITS), the run-out's -K^2/(2 DITE)."""
    prog = run(f"M3 S500\nDITS={dits:g} DITE={dite:g}\nG0 X13 Z0\nG33 Z-{l1} K{k:g} SF={sf}\nZ-{l1 + l2} K{k:g}\n"
               "G0 X20\nM30\n")
    want, changes = [float(sf)], [k * k / (2 * dits)] if dits else []
    if dits:
        want.append(sf + 720.0 * dits / k)
    want.append(sf + 360.0 * (dits + l1) / k)
    changes += [0.0, 0.0]
    if dite:
        want.append(want[-1] + 360.0 * (l2 - dite) / k)
        changes.append(-k * k / (2 * dite))
    s = syncs(prog)
    got = [r.start_angle for r in s]
    assert len(got) == len(want)
    assert all(abs((g - w + 180.0) % 360.0 - 180.0) < 1e-6 for g, w in zip(got, want)), (got, want)
    assert [r.lead_change for r in s] == pytest.approx(changes)
    assert s[-1].end[2] == -(l1 + l2) and all(a.end == b.start for a, b in zip(s, s[1:]))
