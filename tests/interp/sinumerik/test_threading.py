"""The Sinumerik thread cycle planner (interp/sinumerik/threading.py): pass depths for every VARI,
multi-start angles, taper and face leads, run-in and run-out, flank infeed, idle passes and the
refusals, each number derived here by hand from the rule it checks (docs/dialects/sinumerik-turning.md).
"""
from __future__ import annotations

import math

import pytest

from cutsim.interp.sinumerik.threading import (METRIC_PITCH, ThreadParamError, plan_cycle97, plan_cycle98,
                                               pitch)

TOL = 1e-9


def c97(**kw):
    """An M30x2 outside thread, 30 mm long from Z0 towards -Z, unless the test says otherwise."""
    base = dict(PIT=2.0, SPL=0.0, FPL=-30.0, DM1=30.0, DM2=30.0, APP=0.0, ROP=0.0, TDEP=1.2, FAL=0.2, IANG=0.0,
                NSP=0.0, NRC=4, NID=0, VARI=1, NUMT=1)
    base.update(kw)
    return base


def thread_seg(p):
    return next(s for s in p.path if s.kind == "thread")


# ---------------------------------------------------------------------------------------------
# pass depths
def test_vari1_outside_constant_infeed():
    # roughing depth TDEP - FAL = 1.0 in NRC = 4 equal steps, then FAL at TDEP, then NID idle passes
    plan = plan_cycle97(c97(NID=2))
    assert [p.kind for p in plan.passes] == ["rough"] * 4 + ["finish"] + ["idle"] * 2
    assert plan.depths() == pytest.approx([0.25, 0.5, 0.75, 1.0, 1.2, 1.2, 1.2])
    # outside: the tip goes towards the axis, X (a diameter) = 30 - 2 * depth
    assert [p.infeed.x for p in plan.passes] == pytest.approx([29.5, 29.0, 28.5, 28.0, 27.6, 27.6, 27.6])
    assert plan.outside and not plan.face


def test_vari2_inside_constant_infeed():
    # inside: DM is the tap hole; the tip goes away from the axis, X = 20 + 2 * depth
    plan = plan_cycle97(c97(DM1=20.0, DM2=20.0, TDEP=0.9, FAL=0.0, NRC=3, VARI=2))
    assert plan.depths() == pytest.approx([0.3, 0.6, 0.9])  # FAL 0: the last roughing cut is at TDEP
    assert [p.infeed.x for p in plan.passes] == pytest.approx([20.6, 21.2, 21.8])
    assert not plan.outside


@pytest.mark.parametrize("vari,sign", [(3, -1.0), (4, 1.0)])
def test_vari3_4_constant_cross_section(vari, sign):
    # a V profile cut to depth d has area proportional to d^2; equal areas: d_i = 1.0 * sqrt(i / 4)
    plan = plan_cycle97(c97(VARI=vari, NID=1))
    rough = [p.depth for p in plan.passes if p.kind == "rough"]
    assert rough == pytest.approx([0.5, math.sqrt(0.5), math.sqrt(0.75), 1.0])
    areas = [b * b - a * a for a, b in zip([0.0] + rough, rough)]
    assert areas == pytest.approx([0.25] * 4)  # (TDEP - FAL)^2 / NRC each
    assert [p.kind for p in plan.passes][4:] == ["finish", "idle"]
    assert plan.passes[-1].depth == pytest.approx(1.2)
    assert plan.passes[0].infeed.x == pytest.approx(30.0 + sign * 2 * 0.5)


@pytest.mark.parametrize("nrc", [1, 2, 5, 17])
@pytest.mark.parametrize("vari", [1, 2, 3, 4])
def test_every_vari_reaches_tdep_in_order(nrc, vari):
    tdep, fal = 1.5, 0.1
    plan = plan_cycle97(c97(VARI=vari, NRC=nrc, TDEP=tdep, FAL=fal, DM1=40, DM2=40))
    d = plan.depths()
    assert len(d) == nrc + 1
    assert all(b > a for a, b in zip(d, d[1:]))
    assert d[nrc - 1] == pytest.approx(tdep - fal) and d[-1] == pytest.approx(tdep)


def test_idle_passes_repeat_the_finishing_path():
    plan = plan_cycle97(c97(NID=3))
    idle = [p for p in plan.passes if p.kind == "idle"]
    finish = next(p for p in plan.passes if p.kind == "finish")
    assert len(idle) == 3
    assert all(p.path == finish.path and p.number == finish.number + k + 1 for k, p in enumerate(idle))


# ---------------------------------------------------------------------------------------------
# starts, leads, run-in and run-out
def test_multistart_angles_and_order():
    # NUMT starts spread evenly from NSP: SF = NSP + j * 360 / NUMT; each start cut completely in turn
    plan = plan_cycle97(c97(NUMT=3, NSP=20.0))
    per_start = 5  # 4 roughing + 1 finishing cut
    assert [p.start_index for p in plan.passes] == [0] * per_start + [1] * per_start + [2] * per_start
    assert [plan.passes[k * per_start].sf for k in range(3)] == pytest.approx([20.0, 140.0, 260.0])
    assert all(p.path[0].start_angle == p.sf for p in plan.passes)
    wrapped = plan_cycle97(c97(NUMT=4, NSP=350.0, NRC=1, FAL=0.0))
    assert [p.sf for p in wrapped.passes] == pytest.approx([350.0, 80.0, 170.0, 260.0])


def test_numt_zero_is_one_start():
    assert plan_cycle97(c97(NUMT=0)).starts == 1


def test_run_in_and_run_out_cylinder():
    plan = plan_cycle97(c97(APP=3.0, ROP=2.0, NRC=1, FAL=0.0))
    (p,) = plan.passes
    assert [s.kind for s in p.path] == ["run-in", "thread", "run-out"]
    run_in, thread, run_out = p.path
    # the cut begins APP before SPL and ends ROP past FPL, at the cut's diameter 30 - 2 * 1.2
    assert (run_in.start.z, run_in.end.z) == pytest.approx((3.0, 0.0))
    assert (run_out.start.z, run_out.end.z) == pytest.approx((-30.0, -32.0))
    assert [x for s in p.path for x in (s.start.x, s.end.x)] == pytest.approx([27.6] * 6)
    # chained blocks: the spindle turns on; 3 mm at lead 2 is 1.5 turns = 540 degrees after SF
    assert thread.start_angle == pytest.approx(180.0)
    assert run_out.start_angle == pytest.approx((540.0 + 360.0 * 30.0 / 2.0) % 360.0)
    assert all(s.lead == 2.0 and s.lead_axis == "Z" for s in p.path)


def test_taper_lead_on_the_longer_axis_with_run_in():
    # DM 20 -> 30 over 40 mm: 5 mm of radius on 40 mm of Z, lead along Z; the slope 5/40 continues
    # over APP 4 (radius 10 - 0.5) and ROP 2 (radius 15 + 0.25)
    plan = plan_cycle97(c97(DM1=20.0, DM2=30.0, FPL=-40.0, APP=4.0, ROP=2.0, NRC=1, FAL=0.0, TDEP=1.0))
    (p,) = plan.passes
    run_in, thread, run_out = p.path
    assert thread.lead_axis == "Z" and thread.travel == pytest.approx(40.0)
    assert (thread.start.x, thread.end.x) == pytest.approx((18.0, 28.0))  # 20 - 2, 30 - 2
    assert (run_in.start.x, run_in.start.z) == pytest.approx((19.0 - 2.0, 4.0))
    assert (run_out.end.x, run_out.end.z) == pytest.approx((30.5 - 2.0, -42.0))


def test_steep_taper_is_a_face_thread_and_45_degrees_is_not():
    steep = plan_cycle97(c97(DM1=20.0, DM2=80.0, FPL=-10.0, NRC=1, FAL=0.0, TDEP=1.0))
    seg = thread_seg(steep.passes[0])
    assert steep.face and seg.lead_axis == "X"
    assert seg.travel == pytest.approx(30.0) and seg.turns == pytest.approx(15.0)  # radius 10 -> 40, lead 2
    # a face thread's depth runs along Z (outside: into the face, -Z); X stays on the thread line
    assert (seg.start.x, seg.start.z) == pytest.approx((20.0, -1.0))
    edge = plan_cycle97(c97(DM1=20.0, DM2=40.0, FPL=-10.0))  # 10 on the radius, 10 on Z: 45 degrees
    assert not edge.face and thread_seg(edge.passes[0]).lead_axis == "Z"


def test_retract_and_return_at_the_lift_level():
    # _VRT above the thread diameter at the start (1 mm when empty): X = DM + 2 * _VRT
    for vrt, lift in ((0.0, 32.0), (2.5, 35.0)):
        plan = plan_cycle97(c97(_VRT=vrt, APP=2.0, ROP=1.0))
        assert plan.home == pytest.approx(type(plan.home)(lift, 2.0))
        for p in plan.passes:
            assert (p.approach.x, p.approach.z) == pytest.approx((lift, p.infeed.z))  # straight in along X
            assert (p.retract.x, p.retract.z) == pytest.approx((lift, p.path[-1].end.z))  # straight out
        moves = plan.moves()
        assert moves[0] == ("G0", plan.home) and moves[-1] == ("G0", plan.home)
        assert [k for k, _ in moves[1:6]] == ["G0", "G0", "G33", "G33", "G33"]


# ---------------------------------------------------------------------------------------------
# flank infeed
def test_one_flank_infeed_keeps_the_trailing_flank():
    # IANG 30: the tip moves along the finished groove's flank, (TDEP - d) * tan 30 back towards the
    # start (+Z here, the cut runs to -Z); the tool flank at the surface stays at TDEP * tan 30
    t = math.tan(math.radians(30.0))
    plan = plan_cycle97(c97(IANG=30.0, APP=2.0, NID=1))
    for p in plan.passes:
        assert p.flank_offset == pytest.approx((1.2 - p.depth) * t)
        assert p.infeed.z == pytest.approx(2.0 + p.flank_offset)
        assert p.flank_offset + p.depth * t == pytest.approx(1.2 * t)
    assert plan.passes[-1].flank_offset == 0.0 and plan.passes[-2].flank_offset == 0.0  # finish, idle
    steps = [b.flank_offset - a.flank_offset for a, b in zip(plan.passes, plan.passes[1:4])]
    assert steps == pytest.approx([-0.25 * t] * 3)  # each roughing step of 0.25 moves 0.25 tan 30


def test_alternating_flank_infeed():
    # IANG -30: the same distances, on alternate flanks from cut to cut
    t = math.tan(math.radians(30.0))
    plan = plan_cycle97(c97(IANG=-30.0, NRC=4))
    expect = [(1.2 - d) * t * s for d, s in zip([0.25, 0.5, 0.75, 1.0], [1, -1, 1, -1])] + [0.0]
    assert [p.flank_offset for p in plan.passes] == pytest.approx(expect)


def test_alternating_on_a_taper_is_one_flank():
    plan = plan_cycle97(c97(IANG=-30.0, DM2=34.0))
    assert all(p.flank_offset >= 0.0 for p in plan.passes)


def test_face_thread_flank_offset_runs_along_x():
    t = math.tan(math.radians(20.0))
    plan = plan_cycle97(c97(DM1=20.0, DM2=60.0, FPL=0.0, IANG=20.0, NRC=2, FAL=0.0, TDEP=1.0))
    first = plan.passes[0]
    # cut from radius 10 outwards: "back" is towards the axis; 0.5 deep, offset (1 - 0.5) tan 20
    assert (first.infeed.x, first.infeed.z) == pytest.approx((20.0 - 2 * 0.5 * t, -0.5))


# ---------------------------------------------------------------------------------------------
# pitch and CYCLE98
def test_mpit_sizes():
    assert pitch({"MPIT": 30}) == 3.5 and pitch({"MPIT": 60}) == 5.5 and pitch({"MPIT": 3}) == 0.5
    assert pitch({"MPIT": 10, "PIT": 1.5}) == 1.5
    assert min(METRIC_PITCH) == 3 and max(METRIC_PITCH) == 60


def test_cycle98_chain_continues_the_spindle():
    v = dict(PO1=0.0, DM1=30.0, PO2=-10.0, DM2=30.0, PO3=-20.0, DM3=36.0, PO4=-25.0, DM4=56.0, APP=1.0, ROP=0.0,
             TDEP=1.0, FAL=0.0, IANG=0.0, NSP=30.0, NRC=1, NID=0, PP1=2.0, PP2=3.0, PP3=4.0, VARI=1, NUMT=1)
    (p,) = plan_cycle98(v).passes
    kinds = [(s.kind, s.lead_axis, s.lead) for s in p.path]
    # segment 3 rises 10 on the radius over 5 of Z: steeper than 45 degrees, its lead along X
    assert kinds == [("run-in", "Z", 2.0), ("thread", "Z", 2.0), ("thread", "Z", 3.0), ("thread", "X", 4.0)]
    turns = [0.5, 10.0 / 2.0, 10.0 / 3.0]  # run-in 1 mm, segment 1, segment 2
    angles = [30.0 + 360.0 * sum(turns[:k]) for k in range(4)]
    assert [s.start_angle for s in p.path] == pytest.approx([a % 360.0 for a in angles])
    assert [s.end for s in p.path[:-1]] == [s.start for s in p.path[1:]]  # no gap in the chain


# ---------------------------------------------------------------------------------------------
# refusals, each naming its parameter
BAD = [
    (dict(PIT=-2.0), "PIT"),
    (dict(PIT=0.0), "PIT"),
    (dict(PIT=0.0, MPIT=7), "MPIT"),
    (dict(PIT=2.0, MPIT=10), "MPIT"),
    (dict(VARI=5), "VARI"),
    (dict(VARI=0), "VARI"),
    (dict(TDEP=0.0), "TDEP"),
    (dict(FAL=1.2), "FAL"),
    (dict(FAL=-0.1), "FAL"),
    (dict(NRC=0), "NRC"),
    (dict(NRC=2.5), "NRC"),
    (dict(NID=-1), "NID"),
    (dict(NUMT=1.5), "NUMT"),
    (dict(NSP=360.0), "NSP"),
    (dict(NSP=-5.0), "NSP"),
    (dict(IANG=90.0), "IANG"),
    (dict(DM1=0.0), "DM1"),
    (dict(FPL=0.0), "FPL"),
    (dict(APP=-1.0), "APP"),
    (dict(ROP=-1.0), "ROP"),
    (dict(_VRT=-1.0), "_VRT"),
    (dict(DM1=2.0, DM2=2.0, TDEP=1.5, FAL=0.0), "TDEP"),
    (dict(DM1=20.0, DM2=60.0, FPL=0.0, APP=15.0), "APP"),
    (dict(VARI=2, DM1=4.0, DM2=4.0, _VRT=3.0), "_VRT"),
    (dict(SPL="A"), "SPL"),
]


@pytest.mark.parametrize("change,name", BAD)
def test_cycle97_refuses_naming_the_parameter(change, name):
    with pytest.raises(ThreadParamError) as e:
        plan_cycle97(c97(**change))
    assert e.value.param == name and name in str(e.value)
    assert isinstance(e.value, ValueError)


def test_move_budget_names_nrc():
    with pytest.raises(ThreadParamError) as e:
        plan_cycle97(c97(NRC=5000, NUMT=50), max_moves=100_000)
    assert e.value.param == "NRC" and "max_blocks" in str(e.value)
    assert len(plan_cycle97(c97(NRC=50), max_moves=100_000).passes) == 51


def test_cycle98_refuses_a_chain_that_turns_back():
    v = dict(PO1=0.0, DM1=30.0, PO2=-10.0, DM2=30.0, PO3=-5.0, DM3=30.0, PO4=-20.0, DM4=30.0, TDEP=1.0, NRC=1,
             PP1=2.0, PP2=2.0, PP3=2.0, VARI=1)
    with pytest.raises(ThreadParamError) as e:
        plan_cycle98(v)
    assert e.value.param == "PO3"
    with pytest.raises(ThreadParamError) as e:
        plan_cycle98({**v, "PO3": -15.0, "PP2": 0.0})
    assert e.value.param == "PP2"


# ---------------------------------------------------------------------------------------------
# over the documented range
def _random_case(rng):
    dm1 = rng.uniform(6.0, 120.0)
    taper = rng.random() < 0.3
    length = rng.uniform(2.0, 60.0)
    tdep = rng.uniform(0.1, min(3.0, dm1 / 4))
    return c97(PIT=rng.choice([0.5, 1.0, 1.5, 2.0, 3.5]), SPL=rng.uniform(-20, 20), DM1=dm1,
               DM2=dm1 + (rng.uniform(-0.4, 0.4) * length if taper else 0.0), APP=rng.uniform(0, 5),
               ROP=rng.uniform(0, 3), TDEP=tdep, FAL=rng.uniform(0, tdep * 0.5), IANG=rng.uniform(-45, 45),
               NSP=rng.uniform(0, 359.9), NRC=rng.randint(1, 20), NID=rng.randint(0, 3), VARI=rng.randint(1, 4),
               NUMT=rng.randint(0, 6), _VRT=rng.uniform(0, 3)), length


@pytest.mark.parametrize("seed", range(200))
def test_plan_invariants(seed):
    import random

    rng = random.Random(seed)
    v, length = _random_case(rng)
    v["FPL"] = v["SPL"] + length * rng.choice([-1, 1])
    plan = plan_cycle97(v)
    starts = max(1, v["NUMT"])
    t = math.tan(math.radians(abs(v["IANG"])))
    side = -1.0 if v["VARI"] in (1, 3) else 1.0
    slope = (v["DM2"] - v["DM1"]) / 2.0 / (v["FPL"] - v["SPL"])  # radius per mm of Z
    for j in range(starts):
        d = plan.depths(j)
        assert all(b >= a - TOL for a, b in zip(d, d[1:])) and d[-1] == pytest.approx(v["TDEP"])
    for p in plan.passes:
        assert p.sf == pytest.approx((v["NSP"] + p.start_index * 360.0 / starts) % 360.0)
        assert abs(p.flank_offset) == pytest.approx((v["TDEP"] - p.depth) * t, abs=1e-9)
        for a, b in zip(p.path, p.path[1:]):  # chained: no gap, the spindle angle turns on
            assert a.end == b.start
            turned = a.start_angle + 360.0 * a.travel / a.lead - b.start_angle
            assert min(turned % 360.0, -turned % 360.0) < 1e-6
        back = -math.copysign(1.0, v["FPL"] - v["SPL"])  # the flank offset's positive side, along Z
        for s in p.path:  # every point of the cut: on the thread's line moved `depth` in and the offset along
            for q in (s.start, s.end):
                on_line = v["DM1"] / 2.0 + slope * (q.z - back * p.flank_offset - v["SPL"])
                assert q.radius - on_line == pytest.approx(side * p.depth, abs=1e-9)
        # G0 in and out run along X only, between the lift level and the cut
        assert p.approach.z == pytest.approx(p.infeed.z) and p.retract.z == pytest.approx(p.path[-1].end.z)
        assert (p.approach.x - p.infeed.x) * side < 0


# ---------------------------------------------------------------------------------------------
# G34 / G35
def test_varying_lead():
    from cutsim.interp.sinumerik.threading import varying_lead

    # K 2, F 0.1 over 10 mm: Ke^2 = 4 + 2 * 0.1 * 10 = 6; revolutions (Ke - Ka) / F
    end, turns = varying_lead(2.0, 0.1, 10.0, True)
    assert end == pytest.approx(math.sqrt(6.0)) and turns == pytest.approx((math.sqrt(6.0) - 2.0) / 0.1)
    # the travel over those revolutions, summed from K(n) = 2 + 0.1 n: 2 n + 0.05 n^2 = 10
    assert 2.0 * turns + 0.05 * turns * turns == pytest.approx(10.0)
    end, turns = varying_lead(2.0, 0.1, 10.0, False)  # Ke^2 = 4 - 2 = 2
    assert end == pytest.approx(math.sqrt(2.0)) and 2.0 * turns - 0.05 * turns * turns == pytest.approx(10.0)
    assert varying_lead(1.5, 0.0, 30.0, True) == (1.5, 20.0)
    with pytest.raises(ThreadParamError) as e:
        varying_lead(2.0, 0.1, 25.0, False)  # the lead reaches 0 after 4 / 0.2 = 20 mm
    assert e.value.param == "F" and "20 mm" in str(e.value)


def test_program_moves_in_diameter_and_radius():
    from cutsim.interp.sinumerik.threading import program_moves

    plan = plan_cycle97(c97(NRC=1, FAL=0.0, APP=2.0))
    dia = program_moves(plan, True, y=0.0)
    rad = program_moves(plan, False, y=0.0)
    assert dia[0] == ("G0", (32.0, 0.0, 2.0)) and rad[0] == ("G0", (16.0, 0.0, 2.0))  # home: 30 + 2 * 1 mm
    g33 = [m for m in dia if m[0] == "G33"]
    # run-in end, thread end; X at the root 30 - 2 * 1.2 on the diameter, 13.8 on the radius
    assert g33[0] == ("G33", (27.6, 0.0, 0.0), 2.0, "Z", 0.0)
    assert g33[1][1] == pytest.approx((27.6, 0.0, -30.0)) and g33[1][4] == pytest.approx(0.0)  # 2 mm = 1 turn
    assert [m for m in rad if m[0] == "G33"][1][1] == pytest.approx((13.8, 0.0, -30.0))
    assert len(dia) == len(plan.moves())


# ---------------------------------------------------------------------------------------------
# the planned passes cut the thread they describe (records through the kinematics and the stock)
SETUP = """
machine = { kind = "lathe", dialect = "sinumerik", diameter_programming = true, start = [40.0, 0.0, 10.0] }
stock = { shape = "revolve", profile = [[0, 0], [15, 0], [15, -40], [0, -40]] }  # a 30 mm bar, 40 long
tool = [{ number = 1, kind = "thread", angle = 60.0, tip_radius = 0.0 }]
simulation = { tolerance = 0.01 }
"""


def _cut(tmp_path, plan):
    """The plan's moves as records (the calls the interpreter will make) cut from a 30 mm bar."""
    import cutsim
    from cutsim.interp.canon import Src
    from cutsim.interp.core.modal import InterpConfig, ModalMachine
    from cutsim.kinematics import plan as make_plan
    from cutsim.stock import build_stock, remove

    (tmp_path / "setup.toml").write_text(SETUP)
    setup = cutsim.load_setup(str(tmp_path / "setup.toml"))
    m = ModalMachine("cycle97", InterpConfig("sinumerik", "lathe", True, (40.0, 0.0, 10.0)))
    src = Src("cycle97", 1)
    m.tool(src, 1, 1)
    m.spindle(src, 1, 300.0)
    for mv in program_moves_of(plan):
        if mv[0] == "G0":
            m.rapid(src, mv[1])
        else:
            m.synced(src, *mv[1:])
    stock = build_stock(setup.stock, setup.tolerance, setup.path, max_triangles=setup.max_triangles,
                        where=setup.stock_where)
    pl = make_plan(m.program, setup.machine, setup.tools, setup.tolerance)
    part = remove(stock, setup.stock, pl.paths, setup.tolerance, None, max_triangles=setup.max_triangles).part
    return cutsim.Result(setup, m.program, pl, stock, part)


def program_moves_of(plan):
    from cutsim.interp.sinumerik.threading import program_moves

    return program_moves(plan, True)


@pytest.mark.parametrize("iang", [0.0, 29.0, -29.0])
def test_two_start_cycle97_cuts_its_thread(tmp_path, iang):
    from cutsim.testing import assert_thread

    # lead PIT 4 in 2 starts (grooves 2 apart), depth 1.227: root 30 - 2 * 1.227 = 27.546; every
    # cut's G33 starts at SPL + APP = Z4 where start k waits for NSP + k * 180 = 30, 210 degrees.
    # Flank infeed (IANG 29, one flank or alternating) keeps the finishing cut on that helix.
    v = dict(PIT=4.0, SPL=0.0, FPL=-24.0, DM1=30.0, DM2=30.0, APP=4.0, ROP=2.0, TDEP=1.227, FAL=0.05,
             IANG=iang, NSP=30.0, NRC=5, NID=1, VARI=3, NUMT=2)
    result = _cut(tmp_path, plan_cycle97(v))
    assert_thread(result, (-18.0, -4.0), 4.0, starts=2, root_diameter=27.546, phase=[30.0, 210.0], phase_z=4.0)
