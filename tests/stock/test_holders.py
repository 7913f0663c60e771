"""Outside and face holders as solids: where a holder's body meets material still there when the
tool moves, a warning at the move's line (docs/setup.md, "Holders"); the body never cuts.

Every number below is derived by hand from the insert's geometry. A CNMG 120408 (80 degree
rhombus, inscribed circle d = 12.7, nose radius rn = 0.8) in a 93 degree holder of hand R: its
edges are l = d / sin 80 = 12.896 long; the control point T is the corner of the box around the
nose, so the nose's centre is C = T + (rn, rn) and its sharp corner S lies rn / sin 40 from C
against the corner's bisector, which points into the insert at kappa_r - 90 + 40 = 43 degrees
from +X towards +Z: S = C - 1.2446 (cos 43, sin 43) = T + (-0.1103, -0.0488). The main edge
leaves S at kappa_r - 90 = 3 degrees: it ends at E = S + l (cos 3, sin 3) = T + (12.768, 0.626),
where the holder's body begins (its face towards the part at X/2 = tool point + 12.768, its side
towards -Z at Z = tool point + 0.626, 25 mm wide: the ISO square nearest 2 d). The insert's far
corner (opposite the nose, its centre C' = 2 S - C + l (d1 + d2), d1 = (cos 3, sin 3),
d2 = (cos 83, sin 83)) reaches Z = tool point + C'_z + rn = + 13.377: a radial plunge clears the
material in front of the insert up to there, the body meets what lies from there to 0.626 + 25.
"""
from __future__ import annotations

import math

import pytest

import cutsim
from cutsim.interp.errors import CutsimError

L_EDGE = 12.7 / math.sin(math.radians(80.0))
RN = 0.8
S = (RN - RN / math.sin(math.radians(40.0)) * math.cos(math.radians(43.0)),
     RN - RN / math.sin(math.radians(40.0)) * math.sin(math.radians(43.0)))
E = (S[0] + L_EDGE * math.cos(math.radians(3.0)), S[1] + L_EDGE * math.sin(math.radians(3.0)))
FAR_Z = 2 * S[1] - RN + L_EDGE * (math.sin(math.radians(3.0)) + math.sin(math.radians(83.0))) + RN
SHANK = 25.0

SETUP = """\
[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [100.0, 0.0, 20.0]

[stock]
shape = "cylinder"
diameter = {diameter}
z = [-60.0, 0.0]

[[tool]]
number = 1
{tool}

[simulation]
tolerance = 0.002
"""
CNMG = 'kind = "turning"\ninsert = "C"\nsize = 12.7\ntip_radius = 0.8\napproach = 93.0\nhand = "R"'


def _run(tmp_path, program: str, tool: str, diameter: float = 40.0):
    prog, setup = tmp_path / "p.nc", tmp_path / "s.toml"
    prog.write_text(program)
    setup.write_text(SETUP.format(diameter=diameter, tool=tool))
    return cutsim.simulate(str(prog), str(setup))


def _holder(res) -> list:
    return [(w["line"], w["message"]) for w in res.warnings if "holder" in w["message"]]


def _volume(message: str) -> float:
    return float(message.split("stock: ")[1].split(" mm^3")[0])


def _plunge(depth: float) -> str:
    """A radial plunge into the Ø40 bar at Z-40 (the body's band Z-39.4..-14.4 stays on the bar)."""
    return f"""\
N10 G00 G95 T1 S1000 M03
N20 G00 X44. Z-40.
N30 G01 X{40.0 - 2.0 * depth:.4f} F0.1
N40 G00 X44.
N50 X100. Z20.
N60 M05
"""


def test_the_derived_numbers():
    assert L_EDGE == pytest.approx(12.896, abs=5e-4)
    assert E == pytest.approx((12.768, 0.626), abs=5e-4)
    assert FAR_Z == pytest.approx(13.377, abs=5e-4)


def test_a_93_degree_holder_plunged_past_its_main_edge_warns_at_the_line(tmp_path):
    """Plunged 0.5 mm deeper than E: the body meets the ring r = 19.5..20 over Z from the insert's
    far corner to the body's far side, 0.626 + 25 - 13.377 = 12.249 mm: pi (20^2 - 19.5^2) 12.249.
    One warning for the tool (the retract after it is not repeated)."""
    depth = E[0] + 0.5
    res = _run(tmp_path, _plunge(depth), CNMG)
    got = _holder(res)
    assert [line for line, _ in got] == [3], got
    assert "25 x 25 mm shank" in got[0][1] and f"{E[0]:.3f} mm behind" in got[0][1]
    expected = math.pi * (20.0 ** 2 - 19.5 ** 2) * (E[1] + SHANK - FAR_Z)
    assert _volume(got[0][1]) == pytest.approx(expected, rel=5e-3)
    assert [w for w in res.warnings if "holder" not in w["message"]] == []


def test_the_same_plunge_shallower_than_the_main_edge_does_not_warn(tmp_path):
    """0.25 mm less deep than E: the body stays 0.25 mm off the bar; the part is what the insert cut."""
    res = _run(tmp_path, _plunge(E[0] - 0.25), CNMG)
    assert res.warnings == []


def test_no_holder_with_shank_zero(tmp_path):
    """shank = 0: the tool is its insert, as before holders: the deep plunge cuts the same part silently."""
    deep = _plunge(E[0] + 0.5)
    res = _run(tmp_path, deep, CNMG + "\nshank = 0.0")
    assert res.warnings == []
    assert res.part.volume() == _run(tmp_path, deep, CNMG).part.volume()


def test_a_face_holder_plunged_past_its_main_edge_warns(tmp_path):
    """The same insert on a face (side = "face": X and Z swapped) plunged along -Z into the end face
    of a Ø80 bar at X20 (r = 10): the body, an axial band r = 10 + 0.626 .. 10 + 25.626, begins
    12.768 behind the tool point; 0.5 deeper it meets the disc Z-0.5..0 from the insert's far
    corner, r = 10 + 13.377, to r = 35.626: pi (35.626^2 - 23.377^2) 0.5. 0.25 less deep: none."""
    tool = CNMG + '\nside = "face"'
    prog = "N10 G00 G95 T1 S800 M03\nN20 G00 X20. Z2.\nN30 G01 Z{z:.4f} F0.05\nN40 G00 Z2.\nN50 X100. Z20.\nN60 M05\n"
    got = _holder(_run(tmp_path, prog.format(z=-(E[0] + 0.5)), tool, diameter=80.0))
    assert [line for line, _ in got] == [3], got
    r_in, r_out = 10.0 + FAR_Z, 10.0 + E[1] + SHANK
    assert _volume(got[0][1]) == pytest.approx(math.pi * (r_out ** 2 - r_in ** 2) * 0.5, rel=5e-3)
    assert _run(tmp_path, prog.format(z=-(E[0] - 0.25)), tool, diameter=80.0).warnings == []


PARTING = 'kind = "grooving"\nwidth = 3.0\ncorner_radius = 0.0\nheight = 12.0\nhand = "R"'


def test_a_parting_blade_deeper_than_its_reach_warns(tmp_path):
    """A 3 mm blade reaching 12 mm (height), hand R, in its default 20 mm holder, plunged at Z-30
    into the Ø40 bar to X10 (r 5, 15 deep): the holder, from r = 5 + 12 = 17 and Z-30 to Z-10,
    meets the ring r = 17..20 beside the 3 mm the blade cut: pi (20^2 - 17^2) (20 - 3)."""
    prog = "N10 G00 G95 T1 S600 M03\nN20 G00 X44. Z-30.\nN30 G01 X{x:g} F0.05\nN40 G00 X44.\nN50 X100. Z20.\nN60 M05\n"
    got = _holder(_run(tmp_path, prog.format(x=10.0), PARTING))
    assert [line for line, _ in got] == [3], got
    assert "20 x 20 mm shank" in got[0][1]
    assert _volume(got[0][1]) == pytest.approx(math.pi * (20.0 ** 2 - 17.0 ** 2) * 17.0, rel=5e-3)
    # within its reach (X18: 11 deep, the holder from r 21) nothing
    assert _run(tmp_path, prog.format(x=18.0), PARTING).warnings == []


def test_a_hand_l_blade_holds_its_body_towards_minus_z(tmp_path):
    """Hand L mirrors the holder: the blade's control corner towards +Z, its holder Z-50..-30 when
    the corner is at Z-30; plunged to X10 it meets the ring r 17..20 over 20 - 3 mm likewise."""
    prog = "N10 G00 G95 T1 S600 M03\nN20 G00 X44. Z-30.\nN30 G01 X10. F0.05\nN40 G00 X44.\nN50 X100. Z20.\nN60 M05\n"
    got = _holder(_run(tmp_path, prog, PARTING.replace('hand = "R"', 'hand = "L"')))
    assert [line for line, _ in got] == [3], got
    assert _volume(got[0][1]) == pytest.approx(math.pi * (20.0 ** 2 - 17.0 ** 2) * 17.0, rel=5e-3)


@pytest.mark.parametrize("tool, size", [
    (CNMG, 25.0),  # 2 x 12.7 = 25.4: 25
    (CNMG.replace("size = 12.7", "size = 9.525").replace("tip_radius = 0.8", "tip_radius = 0.4"), 20.0),  # 19.05
    (CNMG.replace("size = 12.7", "size = 6.35").replace("tip_radius = 0.8", "tip_radius = 0.4"), 12.0),  # 12.7
    (PARTING, 20.0),
    (PARTING.replace("width = 3.0", "width = 4.0"), 25.0),
    ('kind = "thread"', 20.0),
    ('kind = "turning"\nside = "inside"', 0.0),  # an inside tool's body is its boring bar
])
def test_default_shanks(tmp_path, tool, size):
    from cutsim.setup import load_setup

    path = tmp_path / "s.toml"
    path.write_text(SETUP.format(diameter=40.0, tool=tool))
    assert load_setup(str(path)).tools[0].shank == size


@pytest.mark.parametrize("extra, key", [
    ("shank = -1.0", "shank"),
    ('shank = 20.0\nside = "inside"', "shank"),
])
def test_shank_ranges_are_errors_at_the_key(tmp_path, extra, key):
    with pytest.raises(CutsimError) as e:
        _run(tmp_path, _plunge(1.0), 'kind = "grooving"\n' + extra)
    assert f"{key}: " in e.value.message, e.value


# -- over the documented range: where the body begins, and the verdicts either side of it ----------
# Every edge of an ISO insert touches its inscribed circle (radius d/2), so an edge between corners
# of interior angles a and b is (d/2) (cot(a/2) + cot(b/2)) long; the main edge runs from the nose
# (corner angle eps) to the next corner (NEXT).
NEXT = {"C": 100.0, "D": 125.0, "V": 145.0, "T": 60.0, "S": 90.0, "W": 160.0}
EPS = {"C": 80.0, "D": 55.0, "V": 35.0, "T": 60.0, "S": 90.0, "W": 80.0}


def _cot(deg: float) -> float:
    return 1.0 / math.tan(math.radians(deg))


def _edge_end(shape: str, size: float, rn: float, kappa: float) -> tuple[float, float]:
    """E (hand R, from the control point) by hand: S = C - rn / sin(eps/2) (cos b, sin b), b = kappa
    - 90 + eps/2, C = (rn, rn); E = S + l (cos(kappa - 90), sin(kappa - 90))."""
    eps = EPS[shape]
    b = math.radians(kappa - 90.0 + eps / 2.0)
    k = rn / math.sin(math.radians(eps / 2.0))
    s = (rn - k * math.cos(b), rn - k * math.sin(b))
    edge = size / 2.0 * (_cot(eps / 2.0) + _cot(NEXT[shape] / 2.0))
    a = math.radians(kappa - 90.0)
    return s[0] + edge * math.cos(a), s[1] + edge * math.sin(a)


def _random_inserts(n: int, seed: int):
    import random

    rnd = random.Random(seed)
    for _ in range(n):
        shape = rnd.choice(sorted(EPS))
        size = rnd.choice([6.35, 9.525, 12.7, 15.875])
        rn = rnd.choice([0.0, 0.2, 0.4, 0.8, 1.2])
        kappa = rnd.uniform(90.0, 180.0 - EPS[shape])
        yield shape, size, rn, round(kappa, 2)


@pytest.mark.parametrize("shape, size, rn, kappa", list(_random_inserts(40, 20261126)))
def test_the_body_begins_where_the_main_edge_ends(shape, size, rn, kappa):
    from cutsim.base.specs import ToolSpec
    from cutsim.stock.inserts import holder_start

    tool = ToolSpec(1, "turning", insert=shape, size=size, tip_radius=rn, approach=kappa, shank=25.0)
    assert holder_start(tool) == pytest.approx(_edge_end(shape, size, rn, kappa), abs=1e-9)


@pytest.mark.parametrize("shape, size, rn, kappa, hand, side", [
    ("D", 15.875, 0.8, 93.0, "R", "outside"),
    ("T", 9.525, 0.4, 91.0, "L", "outside"),
    ("V", 9.525, 0.2, 107.5, "R", "face"),
    ("S", 12.7, 1.2, 90.0, "L", "face"),
])
def test_plunges_either_side_of_the_body(tmp_path, shape, size, rn, kappa, hand, side):
    """0.2 short of the depth where the body begins: no warning; 0.3 beyond it: a warning at the
    plunge (an outside plunge at Z-30 into a Ø80 bar, a face plunge at X40 into its end face)."""
    depth = _edge_end(shape, size, rn, kappa)[0]
    tool = (f'kind = "turning"\ninsert = "{shape}"\nsize = {size}\ntip_radius = {rn}\napproach = {kappa}\n'
            f'hand = "{hand}"\nside = "{side}"')
    if side == "outside":
        prog = "N10 G00 G95 T1 S800 M03\nN20 G00 X84. Z-30.\nN30 G01 X{:.4f} F0.1\nN40 G00 X84.\nN50 X100. Z20.\n"
        moves = [80.0 - 2.0 * (depth + d) for d in (-0.2, 0.3)]
    else:
        prog = "N10 G00 G95 T1 S800 M03\nN20 G00 X40. Z2.\nN30 G01 Z{:.4f} F0.05\nN40 G00 Z2.\nN50 X100. Z20.\n"
        moves = [-(depth + d) for d in (-0.2, 0.3)]
    short = _run(tmp_path, prog.format(moves[0]), tool, diameter=80.0)
    assert short.warnings == []
    deep = _holder(_run(tmp_path, prog.format(moves[1]), tool, diameter=80.0))
    assert [line for line, _ in deep] == [3], deep


COLLAR = """\
[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [50.0, 0.0, 20.0]

[stock]
shape = "revolve"
profile = [[0, 0], [20, 0], [20, -10], [15, -10], [15, -60], [0, -60]]

[[tool]]
number = 1
kind = "thread"
form = "full"
pitch = 2.0
height = 4.0
{hand}
"""


@pytest.mark.parametrize("hand, warns", [("", True), ('hand = "L"', False)])
def test_a_thread_cut_towards_a_collar_needs_a_left_hand_holder(tmp_path, hand, warns):
    """A Ø30 shaft with a Ø40 collar at Z-10..0; an M30x2 full-profile insert (height 4) cuts one
    pass at X27.712 from Z-40 towards the collar, to Z-12. Its holder begins 4 above the tip
    (r 17.856 < 20) and is 20 wide: hand R (the default) holds it towards +Z from the insert's side
    at -P/2, Z-13..7 at the end of the pass, over the collar: a warning at the G33 (line 4); hand L
    holds it towards -Z, Z-31..-11, clear of the collar."""
    prog, setup = tmp_path / "p.nc", tmp_path / "s.toml"
    prog.write_text("N10 G00 G95 T1 S800 M03\nN20 G00 X32. Z-40.\nN30 X27.712\nN40 G33 Z-12. I0. F2.\n"
                    "N50 G00 X32.\nN60 X50. Z20.\nN70 M05\n")
    setup.write_text(COLLAR.format(hand=hand))
    got = _holder(cutsim.simulate(str(prog), str(setup)))
    assert [line for line, _ in got] == ([4] if warns else []), got
