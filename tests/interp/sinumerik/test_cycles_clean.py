"""Sinumerik cycles never trip cutsim's own checks: every cycle (SLOT1, SLOT2, POCKET1-4, CYCLE71,
CYCLE72) runs alone on a fresh block with several parameter sets (depth by DP and by DPR, one or
more infeeds, finishing allowances, tools from 6 mm up to the slot width, complete / roughing /
finishing, every infeed kind, every milling direction, positions and angles) and must give no
warning at all: no rapid (G00) into the material, nothing else from the cycle's own motion. A
correct cycle call is a correct program.

A few of the runs are also measured (tests/support/sinumerik_measure.py: plane sections of the part mesh,
no cutsim geometry): the width, length and floor depth come out as the parameters say.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import cutsim
from support.sinumerik_measure import floor_z, hsection, point_segment_distance, ray

TOL = 0.005
SETUP = """
[machine]
kind = "mill"
dialect = "sinumerik"
start = [{sx}, {sy}, 50.0]

[stock]
shape = "box"
x = [{x0}, {x1}]
y = [{y0}, {y1}]
z = [-20.0, 0.0]

[[tool]]
number = 1
kind = "endmill"
diameter = 10.0
length = 40.0

[[tool]]
number = 2
kind = "endmill"
diameter = 6.0
length = 40.0

[[tool]]
number = 3
kind = "endmill"
diameter = 16.0
length = 40.0
"""
BOX = ((0.0, 100.0), (0.0, 100.0))

# A boss 60 x 60 with corners of radius 8 about (50, 50), run clockwise from the middle of its left
# edge: with G41 (tool left of the travel) the tool runs outside the boss.
BOSS = """BOSS_A:
G17 G90
G1 X20 Y50
G1 X20 Y72
G2 X28 Y80 CR=8
G1 X72 Y80
G2 X80 Y72 CR=8
G1 X80 Y28
G2 X72 Y20 CR=8
G1 X28 Y20
G2 X20 Y28 CR=8
G1 X20 Y50
BOSS_E:
"""
# the seed's free contour (seed 003), milled on its outside with G41
SEED = """KONT_A:
G17 G90
G1 X13 Y69.65
G3 X28 Y54.65 I=AC(28) J=AC(69.65)
G2 X47.741 Y37.856 I=AC(28) J=AC(34.65)
G1 X52.435 Y8.951
G2 X44.714 Y3.998 I=AC(47.5) J=AC(8.15)
G3 X11.286 I=AC(28) J=AC(-20.915)
G2 X3.565 Y8.951 I=AC(8.5) J=AC(8.15)
G1 X8.259 Y37.856
G2 X28 Y54.65 I=AC(28) J=AC(34.65)
G3 X43 Y69.65 I=AC(28) J=AC(69.65)
KONT_E:
"""


def run(tmp_path, tool, call, tail="", box=BOX, start=(50.0, 50.0), spindle="M3", tol=TOL):
    setup = tmp_path / "setup.toml"
    setup.write_text(SETUP.format(sx=start[0], sy=start[1], x0=box[0][0], x1=box[0][1], y0=box[1][0], y1=box[1][1]))
    prog = tmp_path / "p.mpf"
    prog.write_text(f"G17 G90\nT{tool} D1\nM6\nS2000 {spindle} F300\n{call}\nM30\n{tail}")
    return cutsim.simulate(str(prog), str(setup), tolerance=tol)


def clean(r):
    """The run made no warning and the cycle cut something."""
    assert r.report["warnings"] == [], r.report["warnings"]
    assert r.report["removed_volume"] > 1.0


# (tool, parameters): every infeed kind (VARI tens 0 G0, 1 G1, 2 helix, 3 oscillating), every
# machining type (units 0 complete, 1 roughing, 2 finishing on the fresh block), CDIR 0..3
CASES = {
    "SLOT1": [
        (1, "10, 0, 2, -6, , 3, 30, 12, 50, 50, 10, 20, 120, 100, 300, 3, 0, 0, 0"),
        (2, "10, 0, 1, , 5, 4, 25, 8, 50, 50, 8, 45, 90, 80, 250, 2, 1, 0.3, 10, 2.5, 200"),
        (1, "5, 0, 2, -4, , 2, 28, 12, 40, 55, 5, 0, 180, 100, 300, 0, 2, 0.5, 30"),
        (1, "10, 0, 2, -5, , 1, 30, 14, 30, 30, 0, 30, 0, 100, 300, 2.5, 3, 0.4, 1"),
        (1, "10, 0, 2, -5, , 1, 30, 14, 30, 30, 0, 30, 0, 100, 300, 2.5, 3, 0.4, 2, 2.5"),
        (3, "10, 0, 2, -3, , 2, 40, 16, 50, 50, 6, 90, 180, 100, 300, 1.5, 0, 0, 0"),
    ],
    "SLOT2": [
        (1, "10, 0, 2, -5, , 3, 60, 12, 50, 50, 30, 10, 120, 100, 300, 2.5, 0, 0, 0"),
        (2, "10, 0, 1, , 4, 2, 90, 10, 50, 50, 25, 0, 180, 80, 250, 2, 1, 0.5, 10, 4, 200"),
        (3, "10, 0, 2, -3, , 1, 200, 16, 50, 50, 30, 45, 0, 100, 300, 0, 2, 0, 30"),
        (1, "10, 0, 2, -4, , 4, 40, 12, 50, 50, 35, 0, 90, 100, 300, 2, 3, 0.3, 2"),
    ],
    "POCKET1": [
        (1, "10, 0, 2, -5, , 40, 24, 8, 50, 50, 30, 100, 300, 2.5, 0, 0, 0"),
        (1, "10, 0, 2, , 6, 60, 30, 5, 50, 50, 0, 100, 300, 2, 1, 0.5, 10, 3, 200"),
        (3, "10, 0, 1, -4, , 50, 40, 10, 45, 55, -20, 100, 300, 0, 2, 0.2, 10"),
        (2, "10, 0, 2, -3, , 30, 20, 3, 50, 50, 0, 100, 300, 1.5, 3, 0.5, 2"),
    ],
    "POCKET2": [
        (1, "10, 0, 2, -4, , 14, 50, 50, 100, 300, 2, 0, 0.5, 0"),
        (3, "10, 0, 2, , 5, 25, 50, 50, 100, 300, 2.5, 1, 0, 10"),
        (2, "10, 0, 2, -3, , 8, 30, 70, 100, 300, 0, 2, 0.3, 1"),
        (1, "10, 0, 2, -3, , 12, 60, 40, 100, 300, 1.5, 3, 0.3, 2"),
    ],
    "POCKET3": [
        (1, "10, 0, 2, -4, 36, 22, 6, 50, 50, 15, 2, 0.4, 0.3, 300, 100, 0, 20, 5, , , , 3, 2"),
        (2, "10, 0, 2, -5, 50, 30, 4, 50, 50, 0, 2.5, 0, 0, 300, 100, 1, 0"),
        (1, "10, 0, 2, -3, 40, 40, 10, 50, 50, 45, 1.5, 0.3, 0, 300, 100, 2, 31, 8"),
        (3, "10, 0, 2, -4, 30, 20, 8, 50, 50, 0, 0, 0.2, 0.2, 300, 100, 3, 10, 12"),
        (1, "10, 0, 2, -4, 40, 30, 6, 50, 50, 0, 2, 0.3, 0, 300, 100, 0, 2"),
    ],
    "POCKET4": [
        (1, "10, 0, 2, -3, 13, 40, 60, 3, 0, 0, 300, 100, 0, 10"),
        (1, "10, 0, 2, -6, 20, 50, 50, 2, 0.3, 0.2, 300, 100, 1, 20, 6, , , 4, 1.5"),
        (2, "10, 0, 2, -4, 15, 50, 50, 2, 0.5, 0, 300, 100, 2, 0"),
        (3, "10, 0, 1, -2, 25, 50, 50, 1, 0, 0, 300, 100, 3, 1, 15"),
        (1, "10, 0, 2, -4, 18, 50, 50, 2, 0.4, 0, 300, 100, 0, 12"),
    ],
    # the face covers the whole block (face milling of the blank)
    "CYCLE71": [
        (1, "10, 0, 2, -1.5, 0, 0, 100, 100, 0, 1, 6, 5, 0, 500, 31, 2"),
        (1, "10, 0, 1, -3, 0, 0, 100, 100, 0, 1.5, 8, 5, 0, 500, 11, 2"),
        (3, "10, 0, 2, -2, 100, 100, -100, -100, 0, 1, 12, 3, 0.5, 500, 22, 3"),
        (2, "10, 0, 2, -1, 0, 0, 100, 100, 0, 0, 0, 0, 0, 500, 42, 0"),
        (1, "10, 0, 1, -2.4, 100, 0, 100, 100, 90, 0.8, 7, 2, 0.3, 500, 20, 1"),
    ],
    "CYCLE72": [
        (1, '"BOSS_A:BOSS_E", 10, 0, 2, -5, 2.5, 0.5, 0, 300, 100, 0, 41, 1, 5, 0, 1, 5'),
        (2, '"BOSS_A:BOSS_E", 10, 0, 2, -4, 2, 0.3, 0.2, 300, 100, 1, 41, 2, 6, 0, 2, 6'),
        (1, '"BOSS_A:BOSS_E", 10, 0, 1, -3, 0, 0, 0, 300, 100, 2, 41, 3, 8, 200, 3, 8'),
        (3, '"BOSS_A:BOSS_E", 10, 0, 2, -2, 1, 0, 0, 300, 100, 0, 40, 1, 10, 0, 1, 10'),
        (1, '"KONT_A:KONT_E", 10, 0, 2, -5, 5, 0, 0, 300, 100, 0, 41, 1, 10, 0, 1, 10'),
    ],
}
PARAMS = [(name, tool, p) for name, cases in CASES.items() for tool, p in cases]


@pytest.mark.parametrize("name, tool, params", PARAMS,
                         ids=[f"{n}-{k}" for n, cases in CASES.items() for k in range(len(cases))])
def test_cycle_makes_no_warning(tmp_path, name, tool, params):
    tail, box, start = "", BOX, (50.0, 50.0)
    if "BOSS" in params:
        tail = BOSS
    elif "KONT" in params:
        tail, box, start = SEED, ((-20.0, 76.0), (-35.0, 69.65)), (28.0, 90.0)
    clean(run(tmp_path, tool, f"{name}({params})", tail, box, start))


def test_cycle_makes_no_warning_with_m4(tmp_path):
    # climb milling with the spindle turning M4 runs the other way round: still clean
    clean(run(tmp_path, 1, "POCKET1(10, 0, 2, -5, , 40, 24, 8, 50, 50, 30, 100, 300, 2.5, 0, 0.3, 0)",
              spindle="M4"))


def across(segs, c, u):
    """Width of the cavity through c perpendicular to u, and its length along u."""
    n = np.array([-u[1], u[0]])
    return ray(segs, c, n) + ray(segs, c, -n), ray(segs, c, u) + ray(segs, c, -u)


def test_slot1_by_dpr_width_and_depth(tmp_path):
    # 4 slots WID 8, LENG 25, from RAD 8 about (50, 50) at 45 + k 90 degrees; DPR 5 below RFP 0
    # in steps of MID 2, FAL 0.3 finished with the 6 mm tool
    r = run(tmp_path, 2, "SLOT1(10, 0, 1, , 5, 4, 25, 8, 50, 50, 8, 45, 90, 80, 250, 2, 1, 0.3, 10, 2.5, 200)",
            tol=0.002)
    clean(r)
    m = r.mesh()
    hs = hsection(m, -2.5)
    for k in range(4):
        a = math.radians(45 + 90 * k)
        u = np.array([math.cos(a), math.sin(a)])
        c = np.array([50.0, 50.0]) + u * (8 + 25 / 2)
        w, length = across(hs, c, u)
        assert w == pytest.approx(8.0, abs=0.005)
        assert length == pytest.approx(25.0, abs=0.005)
        assert floor_z(m, c, 5.0) == pytest.approx(-5.0, abs=0.002)
    area = 8 * 17 + math.pi * 16
    assert r.report["removed_volume"] == pytest.approx(4 * area * 5, rel=5e-4)


def test_pocket1_by_dpr_with_allowance(tmp_path):
    # 60 x 30 pocket, corner radius 5, centred (50, 50), DPR 6 in steps of 2, FAL 0.5 finished
    r = run(tmp_path, 1, "POCKET1(10, 0, 2, , 6, 60, 30, 5, 50, 50, 0, 100, 300, 2, 1, 0.5, 10, 3, 200)", tol=0.002)
    clean(r)
    m = r.mesh()
    hs = hsection(m, -3.0)
    w, length = across(hs, np.array([50.0, 50.0]), np.array([1.0, 0.0]))
    assert w == pytest.approx(30.0, abs=0.005)
    assert length == pytest.approx(60.0, abs=0.005)
    for p in ((50, 50), (24, 38), (76, 62)):
        assert floor_z(m, p, 5.0) == pytest.approx(-6.0, abs=0.002)
    area = 60 * 30 - (4 - math.pi) * 25
    assert r.report["removed_volume"] == pytest.approx(area * 6, rel=5e-4)


def test_cycle71_one_way_deeper_steps_than_sdis(tmp_path):
    # one-way along X with infeeds of 1.5 and a safety distance of only 1: the returns in G0 stay
    # above the material of the level; the whole top comes down to -3
    r = run(tmp_path, 1, "CYCLE71(10, 0, 1, -3, 0, 0, 100, 100, 0, 1.5, 8, 5, 0, 500, 11, 2)", tol=0.002)
    clean(r)
    m = r.mesh()
    assert m.bounds[1][2] == pytest.approx(-3.0, abs=0.002)
    assert r.report["part_volume"] == pytest.approx(100 * 100 * 17, rel=5e-4)


def test_cycle72_boss_wall(tmp_path):
    # the boss outline is the finished wall: every sample of its edges lies on the section
    r = run(tmp_path, 1, 'CYCLE72("BOSS_A:BOSS_E", 10, 0, 2, -5, 2.5, 0.5, 0, 300, 100, 0, 41, 1, 5, 0, 1, 5)',
            BOSS, tol=0.002)
    clean(r)
    m = r.mesh()
    hs = hsection(m, -2.5)
    pts = [(20, 40), (20, 60), (35, 80), (65, 80), (80, 45), (60, 20), (30, 20),
           (28 - 8 / math.sqrt(2), 72 + 8 / math.sqrt(2))]
    assert max(point_segment_distance(hs, p) for p in pts) < 0.005
    assert floor_z(m, (15.0, 50.0), 5.0) == pytest.approx(-5.0, abs=0.002)  # beside the boss
    assert floor_z(m, (50.0, 50.0), 5.0) == pytest.approx(0.0, abs=0.002)  # the boss's top


# -- random parameter sets (fixed seed): depth, infeed, allowances, machining type, infeed kind,
# direction and tool drawn around the cases above
from cutsim.interp import InterpConfig, canon, interpret  # noqa: E402
from cutsim.interp.sinumerik.cycle import SPECS  # noqa: E402

RADII = {1: 5.0, 2: 3.0, 3: 8.0}
TENS = {"SLOT1": (0, 1, 3), "SLOT2": (0, 1, 3), "POCKET1": (0, 1), "POCKET2": (0, 1), "POCKET3": (0, 1, 2, 3),
        "POCKET4": (0, 1, 2)}
DRAW = {"DP": (-1, -2.5, -4, -6), "MID": (0, 0.7, 1.5, 2.5, 4), "FAL": (0, 0.2, 0.5), "MIDF": (0, 1, 2),
        "SDIS": (0.5, 1, 2), "CDIR": (0, 1, 2, 3), "FALD": (0, 0.2), "FDP": (0, 2, 5), "FDP1": (0, 1, 3),
        "AS1": (1, 2, 3), "AS2": (1, 2, 3), "LP1": (3, 5, 8), "LP2": (3, 5, 8), "STA": (0, 15, 90),
        "STA1": (0, 20, 45)}


def random_case(rng, name):
    tool, params = rng.choice(CASES[name])
    names = [p.name for p in SPECS[name]]
    ps = params.split(", ")
    ps += [""] * (len(names) - len(ps))
    for k, n in enumerate(names):
        key = n.lstrip("_")
        if key in DRAW and rng.random() < 0.6:
            ps[k] = str(rng.choice(DRAW[key]))
        if key == "DPR" and ps[k] and rng.random() < 0.5:
            ps[k] = str(rng.choice((1, 3, 5)))
        if key == "VARI":
            if name == "CYCLE71":
                ps[k] = str(10 * rng.choice((1, 2, 3, 4)) + rng.choice((1, 2)))
            elif name == "CYCLE72":
                ps[k] = str(rng.choice((0, 1, 2)))
            else:
                ps[k] = str(10 * rng.choice(TENS[name]) + rng.choice((0, 1, 2)))
    if name != "CYCLE71" and rng.random() < 0.5:
        tool = rng.choice((1, 2, 3))
    return tool, ", ".join(ps).rstrip(", ")


def cycle_program(name, tool, params, spindle="M3"):
    tail = BOSS if "BOSS" in params else SEED if "KONT" in params else ""
    return f"G17 G90\nT{tool} D1\nM6\nS2000 {spindle} F300\n{name}({params})\nM30\n{tail}"


@pytest.mark.parametrize("name", list(CASES))
def test_random_parameters_no_rapid_down_into_the_block(name):
    """200 random parameter sets per cycle, interpreter only: every rapid that goes down ends at
    RFP (0) + SDIS or higher (a rapid that ends lower would go into the block). At least half the
    sets must be valid so the check is not empty."""
    import random
    rng = random.Random(20261123)
    valid = 0
    for _ in range(200):
        tool, params = random_case(rng, name)
        sdis = float(params.split(", ")[3 if name == "CYCLE72" else 2] or 0)
        cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(50.0, 50.0, 50.0), tool_radii=RADII)
        try:
            prog = interpret("p.mpf", cycle_program(name, tool, params, rng.choice(("M3", "M4"))), cfg)
        except cutsim.CutsimError:
            continue
        valid += 1
        for r in prog.moves:
            if isinstance(r, canon.Rapid) and r.end[2] < r.start[2] - 1e-9:
                assert r.end[2] >= sdis - 1e-9, (params, r)
    assert valid >= 100


@pytest.mark.parametrize("name", list(CASES))
def test_random_parameters_make_no_warning(tmp_path, name):
    """Two random parameter sets per cycle through the whole simulation: no warning."""
    import random
    rng = random.Random(sum(map(ord, name)))
    done = 0
    while done < 2:
        tool, params = random_case(rng, name)
        tail, box, start = "", BOX, (50.0, 50.0)
        if "BOSS" in params:
            tail = BOSS
        elif "KONT" in params:
            tail, box, start = SEED, ((-20.0, 76.0), (-35.0, 69.65)), (28.0, 90.0)
        try:
            r = run(tmp_path, tool, f"{name}({params})", tail, box, start)
        except cutsim.CutsimError:
            continue
        clean(r)
        done += 1
