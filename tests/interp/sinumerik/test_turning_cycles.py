"""The Sinumerik turning cycles in the interpreter (interp/sinumerik/turncycles.py): CYCLE97 and
CYCLE98 as G0 and chained G33 records at the call's line, CYCLE93 grooving, CYCLE94 / CYCLE96
undercuts and the drilling cycles along Z on a lathe. Every number is derived here by hand from the
rule it checks (docs/dialects/sinumerik-turning.md); the solids are measured after the cut.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

import cutsim
from cutsim.interp.canon import Arc, Feed, Rapid, SyncedFeed
import numpy as np

from cutsim.reports.measure import measure_thread, plane_section, radii_at


BAR = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = {dia}
start = [{sx}, 0.0, 10.0]
[stock]
shape = "revolve"
profile = {profile}
[[tool]]
number = 1
kind = "thread"
angle = 60.0
tip_radius = 0.0
side = "{side}"
[[tool]]
number = 2
kind = "grooving"
width = 3.0
corner_radius = 0.0
side = "{side}"
[[tool]]
number = 3
kind = "turning"
angle = 35.0
tip_radius = 0.0
[[tool]]
number = 4
kind = "drill"
diameter = 8.0
point_angle = 118.0
length = 60.0
[simulation]
tolerance = {tol}
"""
OUTSIDE = "[[0, 0], [15, 0], [15, -30], [0, -30]]"  # a bar of 30, 30 long
NUT = "[[8.188, 0], [20, 0], [20, -30], [8.188, -30]]"  # a nut: the bore 16.376 (M18x1.5's D1)


def run(tmp_path: Path, text: str, *, dia: bool = True, inside: bool = False, tol: float = 0.02, checks=False,
        profile: str | None = None):
    setup = tmp_path / "setup.toml"
    setup.write_text(BAR.format(dia="true" if dia else "false", sx=(60.0 if dia else 30.0),
                                profile=profile or (NUT if inside else OUTSIDE),
                                side="inside" if inside else "outside", tol=tol))
    return cutsim.simulate("turn.mpf", str(setup), text=text, checks=checks)


def moves_of(tmp_path: Path, text: str, **kw):
    """Only the interpreter: the records (cutsim.simulate would cut too)."""
    from cutsim import interp_config, load_setup
    from cutsim.interp import interpret

    setup = tmp_path / "setup.toml"
    inside = kw.pop("inside", False)
    dia = kw.pop("dia", True)
    setup.write_text(BAR.format(dia="true" if dia else "false", sx=60.0 if dia else 30.0, profile=OUTSIDE,
                                side="inside" if inside else "outside", tol=0.02))
    s = load_setup(str(setup))
    return interpret("turn.mpf", text, interp_config(s, s.machine.start)).records


# ---------------------------------------------------------------------------------------------
# CYCLE97 records
def c97(pit=2.0, spl=0.0, fpl=-20.0, dm=30.0, app=2.0, rop=2.0, tdep=1.2, fal=0.0, iang=0.0, nsp=0.0, nrc=2,
        nid=0, vari=1, numt=1, vrt=1.0):
    return f"CYCLE97({pit:g}, , {spl:g}, {fpl:g}, {dm:g}, {dm:g}, {app:g}, {rop:g}, {tdep:g}, {fal:g}, {iang:g}, " \
           f"{nsp:g}, {nrc}, {nid}, {vari}, {numt}, {vrt:g})"


def program(call: str, tool: int = 1, pre: str = "") -> str:
    return f"N10 T{tool} D1 M6\nN20 G18 G95 S300 M3 F0.1\nN30 G0 X40 Z5\n{pre}N40 {call}\nN50 G0 X60\nN60 M30\n"


def test_cycle97_records_at_the_call_line(tmp_path):
    # M30x2 two-start (PIT 4 the lead of each start), 3 cuts a start (NRC 2 + FAL 0.05), SF 30 / 210
    call = c97(pit=4.0, app=4.0, rop=2.0, tdep=1.227, fal=0.05, nsp=30.0, nrc=2, vari=1, numt=2)
    recs = moves_of(tmp_path, program(call))
    cyc = [r for r in recs if r.src.line == 4]
    synced = [r for r in cyc if isinstance(r, SyncedFeed)]
    assert len(synced) == 2 * 3 * 3  # starts x cuts x (run-in, thread, run-out)
    assert all(r.lead == 4.0 and r.lead_axis == "Z" and not r.diameter for r in synced)
    firsts = synced[0::3]
    # every cut's first G33 starts at SPL + APP = Z4 with SF = NSP + k * 360 / NUMT
    assert [r.start[2] for r in firsts] == pytest.approx([4.0] * 6)
    assert [r.start_angle for r in firsts] == pytest.approx([30.0] * 3 + [210.0] * 3)
    # chained: the thread block starts after 4 mm = 1 turn (angle unchanged), the run-out after 24 mm more
    assert [r.start_angle for r in synced[1:3]] == pytest.approx([30.0, (30.0 + 360.0 * 24.0 / 4.0) % 360.0])
    # depths (VARI 1, constant infeed): (1.227 - 0.05) * i / 2, then 1.227: radius 15 - depth
    assert [r.start[0] for r in firsts[:3]] == pytest.approx([15 - 0.5885, 15 - 1.177, 15 - 1.227])
    assert synced[2].end[2] == pytest.approx(-22.0)  # FPL - ROP
    # G0 only otherwise, lift 1 mm over the thread (radius 16), back to the home point (16, Z4)
    assert all(isinstance(r, (Rapid, SyncedFeed)) for r in cyc)
    assert cyc[-1].end == pytest.approx((16.0, 0.0, 4.0))


@pytest.mark.parametrize("dia", [True, False])
def test_cycle97_diameters_whatever_diamon_says(tmp_path, dia):
    # DM1 is a diameter under DIAMON and DIAMOF alike ([CYC] "General"): the root is radius 15 - 1.2
    recs = moves_of(tmp_path, program(c97(nrc=1), pre="" if dia else "N35 DIAMOF\n"), dia=dia)
    (thread,) = [r for r in recs if isinstance(r, SyncedFeed) and r.start[2] == 0.0]
    assert thread.start[0] == pytest.approx(13.8) and thread.end == pytest.approx((13.8, 0.0, -20.0))


@pytest.mark.parametrize("vari,inside,root", [
    (1, False, [15 - 0.6, 15 - 1.2]),  # constant infeed: 1.2 * i / 2
    (2, True, [8.188 + 0.406, 8.188 + 0.812]),  # inside: the tap hole 16.376 + depth
    (3, False, [15 - 1.2 * math.sqrt(0.5), 15 - 1.2]),  # constant cross-section: 1.2 * sqrt(i / 2)
    (4, True, [8.188 + 0.812 * math.sqrt(0.5), 8.188 + 0.812]),
])
def test_every_vari_infeeds_and_cuts_its_thread(tmp_path, vari, inside, root):
    """The G0 infeed of each cut at the hand-derived radius, then the solid: lead, starts and the
    root (outside 30 - 2 x 1.2 = 27.6; inside M18x1.5: 16.376 + 2 x 0.812 = 18.0)."""
    dm, tdep, pit = (16.376, 0.812, 1.5) if inside else (30.0, 1.2, 2.0)
    call = c97(pit=pit, dm=dm, tdep=tdep, nrc=2, fpl=-28.0, rop=4.0, app=2.0, vari=vari, numt=2 if vari > 2 else 1,
               nsp=40.0)
    res = run(tmp_path, program(call), inside=inside)
    firsts = [r for r in res.program.records if isinstance(r, SyncedFeed) and r.start[2] == pytest.approx(2.0)]
    assert [r.start[0] for r in firsts[:2]] == pytest.approx(root)
    got = measure_thread(res.part, -22.0, -6.0, inside=inside)
    starts = 2 if vari > 2 else 1
    assert got["lead"] == pytest.approx(pit, abs=0.005) and got["hand"] == "right"
    assert got["starts"] == starts
    want = 2 * (dm / 2 + tdep) if inside else dm - 2 * tdep
    # the sweep follows chords of the helices on the axis side (docs/setup.md): the root up to the
    # tolerance (0.02 on the radius) nearer the axis, deeper outside and shallower inside
    assert want - 2 * 0.02 - 0.005 <= got["root_diameter"] <= want + 0.005


def test_cycle98_chain_records(tmp_path):
    # three segments: Z0 -> -10 lead 2, -10 -> -20 lead 3 (same diameter), -20 -> -25 to diameter 36
    # (3 on the radius over 5 on Z: longitudinal, lead 4); one cut, SF 30
    call = "CYCLE98(0, 30, -10, 30, -20, 30, -25, 36, 1, 0, 1, 0, 0, 30, 1, 0, 2, 3, 4, 1, 1)"
    recs = moves_of(tmp_path, program(call))
    synced = [r for r in recs if isinstance(r, SyncedFeed)]
    assert [(r.lead, r.lead_axis) for r in synced] == [(2.0, "Z"), (2.0, "Z"), (3.0, "Z"), (4.0, "Z")]
    turns = [1.0 / 2.0, 10.0 / 2.0, 10.0 / 3.0]  # run-in 1 mm, segment 1, segment 2
    want = [(30.0 + 360.0 * sum(turns[:k])) % 360.0 for k in range(4)]
    assert [r.start_angle for r in synced] == pytest.approx(want)
    assert synced[-1].end == pytest.approx((18.0 - 1.0, 0.0, -25.0))  # radius 18 less TDEP 1


EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "sinumerik" / "cycle97-m30x2.mpf"


@pytest.mark.parametrize("spoil,fails", [(None, set()), (("1.227, 0.05", "1.127, 0.05"), {"M30x2 two-start"}),
                                          (("29, 30, 5", "29, 120, 5"), {"M30x2 two-start"}),
                                          (("5, 2, 0, 0, 0", "5, 2.5, 0, 0, 0"), {"relief floor"})])
def test_example_checks_pass_and_fail_when_spoiled(spoil, fails):
    """The example's checks (derived in its setup's comments) pass; a thread 0.1 shallower (TDEP),
    its starts at NSP 120 instead of 30 (phases 120 / 300) or a relief 0.5 deeper each fail."""
    text = EXAMPLE.read_text()
    if spoil:
        assert spoil[0] in text
        text = text.replace(spoil[0], spoil[1], 1)
    res = cutsim.simulate(EXAMPLE.name, str(EXAMPLE.with_suffix(".toml")), text=text)
    failed = {c["name"] for c in res.report["checks"] if not c["passed"]}
    assert failed == fails


SHAFT = Path(__file__).resolve().parents[3] / "examples" / "sinumerik" / "turning-cycles.mpf"


@pytest.mark.parametrize("spoil,fails", [(None, set()),
                                          (('CYCLE96(24, -30, "A", 0)', 'CYCLE96(27, -30, "A", 0)'),
                                           {"DIN 76 undercut floor"}),  # M27: pitch 3, floor 22.6
                                          (('CYCLE94(32, -45, "E", 0)', 'CYCLE94(32, -44, "E", 0)'),
                                           {"DIN 509 undercut floor"}),  # 1 mm towards +Z: Z-44 on its face
                                          (("Z-30\nX32", "Z-30\nX32.1"), {"collar 32"})])
def test_turning_example_checks_pass_and_fail_when_spoiled(spoil, fails):
    text = SHAFT.read_text()
    if spoil:
        assert spoil[0] in text
        text = text.replace(spoil[0], spoil[1], 1)
    res = cutsim.simulate(SHAFT.name, str(SHAFT.with_suffix(".toml")), text=text)
    assert {c["name"] for c in res.report["checks"] if not c["passed"]} == fails


# ---------------------------------------------------------------------------------------------
# CYCLE93
def test_cycle93_corners_and_groove(tmp_path):
    # VARI 5: longitudinal, outside, starting point on the right: the groove from SPL -10 towards -Z,
    # WIDG 8, DIAG 4 on the bar of 30: floor diameter 22 from Z-18 to Z-10. FAL 0.2 / 0.2, IDEP 2.
    # The grooving tool (width 3, hand R: its control point the corner towards -Z) roughs with its
    # span inside Z -17.8 .. -10.2 in 3 plunges (ceil((7.6 - 3) / 3) + 1) to radius 15 - 3.8 = 11.2,
    # each in two infeeds of 1.9; finishing: the tool's +Z corner down the wall at -10 (control
    # -13), along the floor (radius 11) to the control point at -18, then up.
    call = "CYCLE93(30, -10, 8, 4, 0, 0, 0, 0, 0, 0, 0, 0.2, 0.2, 2, 0, 5, 1)"
    res = run(tmp_path, program(call, tool=2), tol=0.01)
    feeds = [r for r in res.program.records if isinstance(r, Feed) and r.src.line == 4]
    plunges = [r.end for r in feeds if r.end[0] == pytest.approx(11.2)]
    assert [p[2] for p in plunges] == pytest.approx([-13.2, -15.5, -17.8])
    assert [r.end[0] for r in feeds[:2]] == pytest.approx([13.1, 11.2])
    fin = [(round(r.end[0], 6), round(r.end[2], 6)) for r in feeds[-5:]]
    assert fin == [(15.0, -13.0), (11.0, -13.0), (11.0, -18.0), (15.0, -18.0), (11.0, -18.0)]
    # the solid: 22 in the groove, 30 beside it; the walls at -10 and -18
    for z, d in ((-14.0, 22.0), (-10.5, 22.0), (-17.5, 22.0), (-9.5, 30.0), (-18.5, 30.0)):
        assert 2 * radii_at(res.part, z).min() == pytest.approx(d, abs=0.03), z


def test_cycle93_flank_angles(tmp_path):
    # VARI 1 (start on the left, the groove towards +Z) from SPL -20, WIDG 4 at the base, DIAG 3,
    # ANG1 = ANG2 = 30: the base from -20 + 3 tan 30 = -18.268 to -14.268, the top to -12.536
    t = math.tan(math.radians(30.0))
    call = "CYCLE93(30, -20, 4, 3, 0, 30, 30, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1)"
    res = run(tmp_path, program(call, tool=2), tol=0.01)
    feeds = [r.end for r in res.program.records if isinstance(r, Feed) and r.src.line == 4]
    # finishing flank 1 with the -Z corner (the control point), base until the +Z corner reaches zb2
    assert (feeds[-4][0], feeds[-4][2]) == pytest.approx((12.0, -20.0 + 3 * t))
    assert (feeds[-3][0], feeds[-3][2]) == pytest.approx((12.0, -20.0 + 3 * t + 4.0 - 3.0))
    # the solid at mid-depth (radius 13.5): the flanks 1.5 tan 30 in from the top edges
    zs = [-20.0 + 1.5 * t + 0.05, -12.536 - 1.5 * t - 0.05]
    for z in zs:
        assert radii_at(res.part, z).min() == pytest.approx(13.5, abs=0.15)
    assert 2 * radii_at(res.part, -16.27).min() == pytest.approx(24.0, abs=0.03)


# ---------------------------------------------------------------------------------------------
# CYCLE94 / CYCLE96
SHOULDER = "[[0, 0], [15, 0], [15, -40], [25, -40], [25, -60], [0, -60]]"  # 30 up to a shoulder 50 at Z-40


def test_cycle94_form_e_corners(tmp_path):
    # SPD 30 (over 18 up to 80): R0.6 x 0.3, width 2.5, ramp 15 degrees; _VARI 3 (outside, the
    # cylinder towards +Z from the face at -40): from (15, -37.5) down to 14.7 at -37.5 - 0.3 / tan 15,
    # the floor to -39.4, the fillet about (15.3, -39.4) to the face at radius 15.3
    recs = moves_of(tmp_path, program('CYCLE94(30, -40, "E", 3)', tool=3))
    cyc = [r for r in recs if r.src.line == 4 and isinstance(r, (Feed, Arc))]
    pts = [(round(r.end[0], 6), round(r.end[2], 6)) for r in cyc]
    run15 = 0.3 / math.tan(math.radians(15.0))
    assert pts[:4] == [(15.0, -37.5), (14.7, round(-37.5 - run15, 6)), (14.7, -39.4), (15.3, -40.0)]
    arc = cyc[3]
    assert isinstance(arc, Arc) and arc.clockwise and arc.center == pytest.approx((15.3, 0.0, -39.4))


def test_cycle94_form_f_and_the_solid(tmp_path):
    # form F adds the face relief t2 0.2 at 8 degrees: the fillet meets the face 0.2 into the shoulder
    # (-40.2), the relief returns to the face at radius 15.3 + 0.2 / tan 8
    res = run(tmp_path, program('CYCLE94(30, -40, "F", 3)', tool=3), profile=SHOULDER, tol=0.005)
    cyc = [r for r in res.program.records if r.src.line == 4 and isinstance(r, (Feed, Arc))]
    assert (cyc[3].end[0], cyc[3].end[2]) == pytest.approx((15.3, -40.2))
    assert (cyc[4].end[0], cyc[4].end[2]) == pytest.approx((15.3 + 0.2 / math.tan(math.radians(8.0)), -40.0))
    # the part: the floor at 29.4 between the ramp and the fillet, 30 beyond the undercut
    assert 2 * radii_at(res.part, -38.9).min() == pytest.approx(29.4, abs=0.02)
    assert 2 * radii_at(res.part, -36.0).min() == pytest.approx(30.0, abs=0.02)


def test_cycle96_form_a_corners_and_the_solid(tmp_path):
    # DIATH 30: M30 coarse pitch 3.5 -> DIN 76 A: diameter 30 - 5 = 25, length 12, radius 1.6, flank
    # 30 degrees to the axis: from (15, -28) down 2.5 to 12.5 over 2.5 / tan 30, the floor to -38.4,
    # the fillet to the face at radius 14.1
    res = run(tmp_path, program('CYCLE96(30, -40, "A", 3)', tool=3), profile=SHOULDER, tol=0.005)
    cyc = [r for r in res.program.records if r.src.line == 4 and isinstance(r, (Feed, Arc))]
    pts = [(round(r.end[0], 6), round(r.end[2], 6)) for r in cyc]
    assert pts[:4] == [(15.0, -28.0), (12.5, round(-28.0 - 2.5 / math.tan(math.radians(30.0)), 6)), (12.5, -38.4),
                       (14.1, -40.0)]
    assert 2 * radii_at(res.part, -35.0).min() == pytest.approx(25.0, abs=0.02)
    assert 2 * radii_at(res.part, -27.0).min() == pytest.approx(30.0, abs=0.02)


# ---------------------------------------------------------------------------------------------
# drilling on the lathe
@pytest.mark.parametrize("pre,plane", [("", "G18"), ("N35 G17\n", "G17")])
def test_drilling_along_z_on_the_spindle_axis(tmp_path, pre, plane):
    # CYCLE81 at X0: G0 to RFP + SDIS = Z2, G1 to DP -15, G0 back to RTP 10 (the drill of 8 leaves a
    # bore of 8 down to the start of its point, -15 + 4 / tan 59)
    text = f"N10 T4 D1 M6\nN20 G18 G95 S800 M3 F0.1\nN30 G0 X0 Z20\n{pre}N40 CYCLE81(10, 0, 2, -15)\nN50 M30\n"
    res = run(tmp_path, text, profile=OUTSIDE)
    cyc = [r for r in res.program.records if r.src.line == 5 - (0 if pre else 1)]
    assert [(type(r).__name__, r.end) for r in cyc] == [("Rapid", (0.0, 0.0, 2.0)), ("Feed", (0.0, 0.0, -15.0)),
                                                         ("Rapid", (0.0, 0.0, 10.0))]
    tip = -15.0 + 4.0 / math.tan(math.radians(59.0))
    for z, bore in ((tip + 0.5, 4.0), (-1.0, 4.0)):
        pts = np.concatenate(plane_section(res.part, "z", z))
        assert np.linalg.norm(pts, axis=1).min() == pytest.approx(bore, abs=0.02)
    assert len(plane_section(res.part, "z", -16.0)) == 1  # below the point: the bar's outline alone


TAP = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [60.0, 0.0, 20.0]
[stock]
shape = "revolve"
profile = [[0, 0], [15, 0], [15, -30], [0, -30]]
[[tool]]
number = 1
kind = "drill"
diameter = 8.5
point_angle = 118.0
length = 60.0
[[tool]]
number = 2
kind = "tap"
diameter = 10.0
pitch = 1.5
length = 25.0
[simulation]
tolerance = 0.01
"""


def test_cycle83_and_cycle84_tap_m10_on_the_spindle_axis(tmp_path):
    # CYCLE83 (deep hole, chip breaking: FDPR 8, DAM 4, back 1 mm) to Z-22, then CYCLE84 M10x1.5
    # (PIT 1.5) from RFP + SDIS = Z2 to Z-15: G331 in, 17 / 1.5 = 11 1/3 turns, ending at 120 degrees;
    # G332 out on the same helix with the spindle reversed, starting at -120 = 240 degrees
    (tmp_path / "setup.toml").write_text(TAP)
    text = ("N10 T1 D1 M6\nN20 G18 G95 S800 M3 F0.1\nN30 G0 X0 Z20\nN40 CYCLE83(10, 0, 2, -22, , -8, , 4, 0, 0, 1, 0)\n"
            "N50 T2 D1 M6\nN60 S200 M3\nN70 CYCLE84(10, 0, 2, -15, , 0, 3, , 1.5, 0, 200, 200)\nN80 M30\n")
    res = cutsim.simulate("tap.mpf", str(tmp_path / "setup.toml"), text=text)
    drill = [r.end[2] for r in res.program.records if r.src.line == 4 and isinstance(r, Feed)]
    assert drill == pytest.approx([-8.0, -7.0, -12.0, -11.0, -16.0, -15.0, -19.0, -18.0, -22.0])
    taps = [r for r in res.program.records if isinstance(r, SyncedFeed)]
    got = [v for r in taps for v in (r.start[2], r.end[2], r.lead, r.start_angle)]
    assert got == pytest.approx([2.0, -15.0, 1.5, 0.0, -15.0, 2.0, 1.5, 240.0])
    spindle = [r.direction for r in res.program.records if r.src.line == 7 and type(r).__name__ == "Spindle"]
    assert spindle == [1, -1, 1]  # in under M3, out reversed, M3 again
    got = measure_thread(res.part, -12.0, -4.0, inside=True)
    assert got["lead"] == pytest.approx(1.5, abs=0.005) and got["hand"] == "right" and got["starts"] == 1
    assert got["root_diameter"] == pytest.approx(10.0, abs=0.03)  # the tap's major diameter


# (the refusals, each at its parameter: tests/data/bad/sinumerik/lathe/cycle*.mpf, run with the lathe's other
# bad programs by tests/interp/sinumerik/test_bad_sinumerik.py)


# ---------------------------------------------------------------------------------------------
# CYCLE93 over its range: the groove check (docs/checks.md) passes on the derived numbers and fails
# on numbers 0.1 off
def _groove_case(seed: int):
    import random

    rng = random.Random(seed)
    inside = rng.random() < 0.4
    right = rng.random() < 0.5
    widg = round(rng.uniform(3.2, 9.0), 2)  # at least the tool's 3 (FAL2 0)
    diag = round(rng.uniform(0.8, 3.5 if not inside else 2.5), 2)
    spl = round(rng.uniform(-20.0, -12.0), 2) if right else round(rng.uniform(-26.0, -18.0), 2)
    idep = rng.choice([0.0, 0.7, 1.5])
    vari = (7 if right else 3) if inside else (5 if right else 1)
    spd = 16.376 if inside else 30.0
    return inside, right, widg, diag, spl, idep, vari, spd


@pytest.mark.parametrize("seed", range(6))
def test_cycle93_grooves_over_the_range(tmp_path, seed):
    from cutsim.reports.checks import evaluate
    from cutsim.testing import make_check_spec

    inside, right, widg, diag, spl, idep, vari, spd = _groove_case(seed)
    call = f"CYCLE93({spd:g}, {spl:g}, {widg:g}, {diag:g}, 0, 0, 0, 0, 0, 0, 0, 0, 0, {idep:g}, 0, {vari}, 1)"
    start = "N30 G0 X12 Z5\n" if inside else "N30 G0 X40 Z5\n"
    text = f"N10 T2 D1 M6\nN20 G18 G95 S300 M3 F0.1\n{start}N40 {call}\nN50 M30\n"
    res = run(tmp_path, text, inside=inside, tol=0.005)
    # hand-derived: the groove spans SPL .. SPL -/+ WIDG, its floor SPD -/+ 2 DIAG
    lo, hi = (spl - widg, spl) if right else (spl, spl + widg)
    floor = spd + 2 * diag if inside else spd - 2 * diag
    good = dict(at=(lo + hi) / 2, side="inside" if inside else "outside", width=widg, diameter=floor,
                center=(lo + hi) / 2, reach=4.0, tolerance=0.03)
    ok = evaluate(make_check_spec(res, good, "groove"), res)
    assert ok["passed"], ok
    for key, off in (("width", 0.1), ("diameter", -0.1 if not inside else 0.1), ("center", 0.1)):
        bad = evaluate(make_check_spec(res, {**good, key: good[key] + off}, "groove"), res)
        assert not bad["passed"], (key, bad)


# ---------------------------------------------------------------------------------------------
# CYCLE95 (longitudinal outside: VARI 1, 5, 9)
C95_SETUP = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [60.0, 0.0, 20.0]
[stock]
shape = "revolve"
profile = [[0, 0], [15, 0], [15, -40], [0, -40]]
[[tool]]
number = 1
kind = "turning"
insert = "V"
size = 9.525
tip_radius = 0.0
approach = 93.0
hand = "R"
[simulation]
tolerance = 0.005
"""
C95 = """N10 G18 G90 G95 DIAMON
N20 T1 D1
N30 S500 M3 F0.2
N40 G0 X40 Z5
N50 CYCLE95("KONT_A:KONT_E", 1.5, 0.1, 0.2, 0, 0.25, 0.1, 0.1, {vari}, 0, 0, 1)
N60 G0 X60 Z20
N70 M30
KONT_A: G1 X16 Z0
X20 Z-2
Z-12
G2 X26 Z-15 CR=3
G1 Z-22
X30
KONT_E: Z-30
"""


def _c95(tmp_path, vari):
    (tmp_path / "setup.toml").write_text(C95_SETUP)
    return cutsim.simulate("c95.mpf", str(tmp_path / "setup.toml"), text=C95.format(vari=vari))


def test_cycle95_roughing_levels_and_the_finished_part(tmp_path):
    # the material between the contour and its largest radius 15, from its start Z0: roughed from
    # radius 15 down to 8 + FALX 0.2 in ceil(6.8 / 1.5) = 5 equal cuts of 1.36, each along Z to the
    # contour moved by FALX 0.2 / FALZ 0.1, then up along it over the level before (VARI 9)
    res = _c95(tmp_path, 9)
    rough = [r for r in res.program.records if r.src.line == 5 and isinstance(r, Feed) and r.feed == 0.25]
    levels = sorted({round(r.start[0], 6) for r in rough if r.start[0] == r.end[0] and r.start[2] == 1.1},
                    reverse=True)
    assert levels == pytest.approx([15 - 1.36 * k for k in range(1, 6)])
    # the level 13.64 meets the shoulder (Z-22 + 0.1); the level 12.28 the fillet (centre (13.2, -11.9)
    # moved by the allowances): z = -11.9 - sqrt(9 - 0.92^2)
    ends = {round(r.start[0], 2): r.end[2] for r in rough if r.start[2] == 1.1 and r.start[0] == r.end[0]}
    assert ends[13.64] == pytest.approx(-21.9) and ends[12.28] == pytest.approx(-11.9 - math.sqrt(9 - 0.92 ** 2))
    # finishing on the contour at F0.1; the part: 18 at Z-1 (the chamfer), 20, the fillet, 26, 30
    fin = [r for r in res.program.records if r.src.line == 5 and getattr(r, "feed", None) == 0.1]
    assert (fin[0].end[0], fin[0].end[2]) == (8.0, 0.0) and isinstance(fin[3], Arc)
    for z, d in ((-1.0, 18.0), (-7.0, 20.0), (-13.5, 2 * (13 - math.sqrt(9 - 1.5 ** 2))), (-18.0, 26.0),
                 (-26.0, 30.0), (-35.0, 30.0)):
        assert 2 * radii_at(res.part, z).min() == pytest.approx(d, abs=0.02), z


def test_cycle95_roughing_only_leaves_the_allowances(tmp_path):
    res = _c95(tmp_path, 1)
    assert not [r for r in res.program.records if getattr(r, "feed", None) == 0.1]
    for z, d in ((-7.0, 20.4), (-18.0, 26.4)):  # + 2 FALX
        assert 2 * radii_at(res.part, z).min() == pytest.approx(d, abs=0.02), z


def test_cycle98_cuts_each_segment_at_its_lead(tmp_path):
    # a chain on the bar of 30: Z0 -> -12 at lead 2, -12 -> -24 at lead 3, -24 -> -28 at lead 3; APP 2
    # in the air, ROP 3 off the bar's end at -30; TDEP 1: root 28 all along
    call = "CYCLE98(0, 30, -12, 30, -24, 30, -28, 30, 2, 3, 1, 0, 0, 0, 2, 0, 2, 3, 3, 1, 1)"
    res = run(tmp_path, program(call))
    first = measure_thread(res.part, -10.0, -3.0)
    second = measure_thread(res.part, -22.0, -15.0)
    assert first["lead"] == pytest.approx(2.0, abs=0.005) and second["lead"] == pytest.approx(3.0, abs=0.005)
    for got in (first, second):
        assert got["hand"] == "right" and 28.0 - 0.045 <= got["root_diameter"] <= 28.005


def test_cycle93_chamfer_and_roundings(tmp_path):
    # VARI 5 (right: the groove Z-10 .. -18, floor 22) with RCO1 -1 (a chamfer of length 1, CHF: legs
    # 1 / (2 sin 45) = 0.7071), RCI1 0.5 and RCI2 0.5 (fillets at the base), RCO2 0.8 (a rounding)
    call = "CYCLE93(30, -10, 8, 4, 0, 0, 0, -1, 0.8, 0.5, 0.5, 0, 0, 0, 0, 5, 1)"
    res = run(tmp_path, program(call, tool=2), tol=0.005)
    leg = 1.0 / (2 * math.sin(math.radians(45.0)))
    arcs = [r for r in res.program.records if isinstance(r, Arc) and r.src.line == 4]
    # the tool's +Z corner (control point 3 to its -Z side) traces side 1: the fillet RCI1 about
    # (11.5, -10.5) -> the control point's centre at -13.5; the far corner (the control point
    # itself) traces side 2 from the rounding RCO2 about (14.2, -18.8) and RCI2 about (11.5, -17.5)
    centres = sorted((round(a.center[0], 6), round(a.center[2], 6)) for a in arcs)
    assert centres == [(11.5, -17.5), (11.5, -13.5), (14.2, -18.8)]
    chamfer = [r for r in res.program.records if isinstance(r, Feed) and r.src.line == 4
               and r.start[0] == pytest.approx(15.0) and r.end[0] == pytest.approx(15.0 - leg)]
    assert len(chamfer) == 1 and chamfer[0].end[2] == pytest.approx(-10.0 - 3.0)
    # the part, on each feature
    for z, r in ((-9.6, 15.0 - (leg - 0.4)), (-18.4, 14.2 + math.sqrt(0.8 ** 2 - 0.4 ** 2)),
                 (-10.2, 11.5 - math.sqrt(0.25 - 0.3 ** 2)), (-14.0, 11.0), (-17.8, 11.5 - math.sqrt(0.25 - 0.3 ** 2))):
        assert radii_at(res.part, z).min() == pytest.approx(r, abs=0.01), z
