"""Cutter radius compensation of the rs274ngc dialect (G40/G41/G42/G41.1/G42.1) against numbers worked
out by hand from LinuxCNC's rules (docs/dialects/rs274ngc.md, "Cutter radius compensation"); the
comparison with rs274 itself is tests/interp/rs274ngc/test_rs274ngc_oracle.py (comp-*.ngc, the samples,
the random programs)."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from cutsim.interp import interpret
from cutsim.interp.canon import Arc, Feed, Rapid
from cutsim.interp.core.modal import InterpConfig
from cutsim.interp.errors import CutsimError


def moves(text: str, tmp_path, table: str = "T1 P1 D10\nT2 P2 D4 Q3\n", kind: str = "mill"):
    tbl = tmp_path / "t.tbl"
    tbl.write_text(table)
    cfg = InterpConfig(dialect="rs274ngc", machine_kind=kind, tool_table=str(tbl))
    return [r for r in interpret("t.ngc", text, cfg).records if isinstance(r, (Rapid, Feed, Arc))]


def ends(ms):
    return [tuple(round(v, 6) for v in m.end) for m in ms]


def test_convex_corner_entry_and_departure(tmp_path):
    # tool 1: diameter 10, r = 5. The entry (0,0) -> (50,0) ends r to the left of its end: (50, 5); the
    # right turn down to (50,-50) is convex for G41: an arc of r about the corner (50,0) to (55,0); the
    # line runs at x = 55; after G40 the departure goes straight from (55,-50) to its programmed point
    ms = moves("G21 F100\nG41 D1\nG1 X50 Y0\nG1 X50 Y-50\nG40\nG1 X100 Y-100\nM2\n", tmp_path)
    assert ends(ms) == [(50, 5, 0), (55, 0, 0), (55, -50, 0), (100, -100, 0)]
    arc = ms[1]
    assert isinstance(arc, Arc) and arc.clockwise and arc.center[:2] == (50, 0)
    assert ms[3].start == (55, -50, 0)


@pytest.mark.parametrize("turn_deg", [30, 90, 135])
def test_concave_corner_trims_back_by_r_over_tan_half(tmp_path, turn_deg):
    # a left turn by t under G41 is concave: the entry (offset to y = 5) ends where the offset lines meet,
    # r * tan(t / 2) short of (50, 5) along it; the second line's end is r to its left
    r, t = 5.0, math.radians(turn_deg)
    ex, ey = 50 + 40 * math.cos(t), 40 * math.sin(t)
    ms = moves(f"G21 F100\nG41 D1\nG1 X50 Y0\nG1 X{ex:.6f} Y{ey:.6f}\nM2\n", tmp_path)
    assert ms[0].end[:2] == pytest.approx((50 - r * math.tan(t / 2), r))
    assert ms[1].end[:2] == pytest.approx((ex - r * math.sin(t), ey + r * math.cos(t)), abs=1e-6)


def test_arcs_offset_inside_and_outside(tmp_path):
    # G41 along +X, then a counter-clockwise half circle of radius 20 about (70, -20), which starts
    # downwards (a right turn: convex, an arc of r = 5 about (50, -20)); its left is the centre: the tool
    # runs on 20 - 5; the clockwise half circle after it (tangent) on 20 + 5 (outside)
    ms = moves("G21 F100\nG0 X0 Y-20\nG41 D1\nG1 X50 Y-20\nG3 X90 Y-20 I20 J0\nG2 X130 Y-20 I20 J0\n"
               "G1 X200\nM2\n", tmp_path)
    arcs = [m for m in ms if isinstance(m, Arc)]
    assert [round(math.dist(a.end[:2], a.center[:2]), 6) for a in arcs] == [5.0, 15.0, 25.0]
    assert arcs[1].end[:2] == pytest.approx((85, -20))  # left of the arc's end tangent (up): towards the centre
    assert ms[-1].end[:2] == pytest.approx((200, -15))


@pytest.mark.parametrize("turn, arcs", [(0.04, 0), (0.06, 1)])
def test_corners_under_0_05_rad_get_no_arc(tmp_path, turn, arcs):
    y = -50 * math.tan(turn)  # a right turn: convex under G41
    ms = moves(f"G21 F100\nG41 D1\nG1 X50 Y0\nG1 X100 Y{y:.6f}\nM2\n", tmp_path)
    assert sum(isinstance(m, Arc) for m in ms) == arcs


def test_a_rapid_goes_straight_round_a_convex_corner(tmp_path):
    ms = moves("G21 F100\nG41 D1\nG0 X50 Y0\nG0 X50 Y-50\nM2\n", tmp_path)
    assert [type(m) for m in ms] == [Rapid, Rapid, Rapid] and ends(ms)[1] == (55, 0, 0)


@pytest.mark.parametrize("width, ok", [(10.5, True), (9.5, False)])
def test_a_slot_narrower_than_the_tool_is_a_gouge(tmp_path, width, ok):
    # into a slot of the given width and out along its other side: the tool (diameter 10) fits in 10.5
    text = f"G21 F100\nG0 X0 Y-20\nG41 D1\nG1 X0 Y0\nG1 Y30\nG1 X-{width}\nG1 Y0\nG1 X-30\nM2\n"
    if ok:
        ms = moves(text, tmp_path)
        assert ms[2].end[0] == pytest.approx(-5) and ms[3].end[0] == pytest.approx(-width + 5)
    else:
        with pytest.raises(CutsimError, match="concave corner cannot be reached by the tool without gouging"):
            moves(text, tmp_path)


@pytest.mark.parametrize("text, message", [
    ("G41 D1\nG1 X4\n", "entry move is not greater than the tool radius"),
    ("G41 D1\nG1 X50\nG3 X58 I4\n", "Tool radius not less than arc radius"),
    ("G41 D1\nG1 X50\nG43\n", "cannot change the tool length offset"),
    ("G41 D1\nG1 X50\nG18\n", "cannot change the plane"),
    ("G41 D1\nG1 X50\nG81 X0 Y0 Z-1 R1\n", "canned cycles: not simulated with cutter radius compensation on"),
    ("G41 D1\nG1 X50\nG40\nG2 X60 R5\n", "must be straight"),
    ("G19\nG41 D1\n", "G17 and G18 only"),
    ("G41 D2\n", "needs the plane G18"),  # tool 2 has an orientation (Q): a lathe tool
    ("G41 D7\n", "requested tool 7 not found"),
])
def test_refusals(tmp_path, text, message):
    with pytest.raises(CutsimError, match=message):
        moves(f"G21 F100\n{text}M2\n", tmp_path)


@pytest.mark.parametrize("orientation", range(1, 10))
def test_lathe_orientation_moves_the_path_by_the_nose_radius(tmp_path, orientation):
    # G41.1 D2 (nose radius 1): the path with orientation L is the one without (L0) moved by r along each
    # axis the orientation points on (none for 9), the same for every point
    text = "G21 G18 F100\nG0 X20 Z5\nG42.1 D2 L{} G1 X10 Z2\nG1 Z-20\nG1 X20 Z-25\nG40 G0 X30\nM2\n"
    base = [m.end for m in moves(text.format(0), tmp_path)]
    moved = [m.end for m in moves(text.format(orientation), tmp_path)]
    shifts = {(round(b[0] - a[0], 9), round(b[2] - a[2], 9)) for a, b in zip(base[1:-1], moved[1:-1])}
    assert len(shifts) == 1
    dx, dz = shifts.pop()
    assert {abs(dx), abs(dz)} <= {0.0, 1.0} and (dx, dz) != (0.0, 0.0) or orientation == 9


BOSS = Path(__file__).resolve().parents[3] / "examples" / "rs274ngc" / "boss-g42"


@pytest.mark.parametrize("old, new, failing", [
    ("", "", set()),  # as written: every check holds
    # G41: the tool on the boss's side of its outline, 10 mm inside each wall: the boss's top is cut
    # beside the wall and the floor no longer reaches 10 mm outside it
    ("G42 D1", "G41 D1", {"boss top, just inside its right wall", "floor just outside the right wall",
                          "floor at the cut's outer edge beside the right side",
                          "floor 9.9 mm diagonally off the boss's corner (the corner arc)"}),
    # no compensation: the tool's centre on the outline, the cut reaches only 5 mm beyond it
    ("G42 D1", "G40", {"boss top, just inside its right wall", "floor at the cut's outer edge beside the right side",
                       "floor 9.9 mm diagonally off the boss's corner (the corner arc)"}),
])
def test_the_boss_example_checks_fail_on_a_wrong_side(old, new, failing):
    import cutsim

    text = BOSS.with_suffix(".nc").read_text()
    assert old in text
    r = cutsim.simulate("boss-g42.nc", str(BOSS.with_suffix(".toml")), text=text.replace(old, new))
    failed = {c["name"] for c in r.checks if not c["passed"]}
    assert failed == failing, (failed, [c for c in r.checks if not c["passed"]])
