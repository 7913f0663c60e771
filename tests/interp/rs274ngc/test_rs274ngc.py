"""The rs274ngc dialect on its own (no LinuxCNC needed): expressions, parameters, O-words, motion,
offsets, tool lengths, canned cycles and threads, each against numbers worked out by hand from
the LinuxCNC G-code manual's rules (tests/interp/rs274ngc/test_rs274ngc_oracle.py compares with rs274 itself)."""
from __future__ import annotations

import math

import pytest

from cutsim.interp import interpret
from cutsim.interp.canon import Arc, Feed, Rapid, SyncedFeed, ToolChange
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.modal import InterpConfig


def run(text: str, tmp_path=None, name: str = "t.ngc", **cfg):
    return interpret(name, text, InterpConfig(dialect="rs274ngc", machine_kind=cfg.pop("kind", "mill"), **cfg))


def moves(text: str, **cfg):
    return [r for r in run(text, **cfg).records if isinstance(r, (Rapid, Feed, Arc, SyncedFeed))]


def x_of(expr: str) -> float:
    return moves(f"G21\n#1 = {expr}\nG0 X#1\nM2\n")[-1].end[0]


@pytest.mark.parametrize("expr, value", [
    ("[2 ** 3 ** 2]", 64.0),  # left to right: (2**3)**2
    ("[-2 ** 2]", 4.0),  # the sign belongs to the number
    ("[1 - 2 - 3]", -4.0), ("[10 / 4 / 5]", 0.5), ("[1 + 2 * 3 ** 2]", 19.0),
    ("[7 mod -3]", 1.0), ("[-7 mod 3]", 2.0),  # the result is made positive
    ("round[2.5]", 3.0), ("round[-2.5]", -3.0), ("fix[-2.5]", -3.0), ("fup[2.1]", 3.0),
    ("atan[1]/[-1]", 135.0), ("acos[0.5]", 60.0), ("asin[0.5]", 30.0), ("sin[30]", 0.5), ("cos[60]", 0.5),
    ("tan[45]", 1.0), ("sqrt[16]", 4.0), ("exp[ln[5]]", 5.0), ("abs[-3]", 3.0),
    ("[1 eq 1.00001]", 1.0), ("[1 ne 1.001]", 1.0), ("[3 and 0.5]", 1.0), ("[0 or 0]", 0.0), ("[0 xor 3]", 1.0),
    ("[1 lt 2 + 1]", 1.0), ("[1 lt 2 and 0]", 0.0), ("[2 ge 2]", 1.0), ("[2 gt 2]", 0.0), ("[2 le 1]", 0.0),
    # ROUND goes through a 32-bit int: out of its range x86 gives INT_MIN (rs274: round[tan[-90]])
    ("[round[tan[-90]] eq -2147483648]", 1.0), ("[round[3000000000] eq -2147483648]", 1.0),
    ("[round[-2147483648.6] eq -2147483648]", 1.0), ("[round[2147483647.2] eq 2147483647]", 1.0),
    # to the last bit as rs274 prints them (x 1e16 turns one unit in the last place into 71 or more):
    # ATAN and ACOS in double, times 180 in double, over pi in long double; COS in long double
    ("[[atan[7.17]/[2] - 74.41408572700749] * 10000000000000000]", 0.0),
    ("[[acos[0.8] - 36.86989764584401] * 10000000000000000]", 0.0),
    ("[[4 ** atan[7.17]/[2]] mod 20]", 4.0),  # a 6e44 power: the last bit decides the remainder
    ("[cos[90] * 100000000000000000000]", -2.508278806334166),
    # C's ceil/floor keep a zero's sign: fup[-0.15] is -0, and atan of -0 over a negative is -180
    ("atan[fup[-0.15]]/[-1]", -180.0), ("atan[fix[0.5]]/[-1]", 180.0),
])
def test_expressions(expr, value):
    assert x_of(expr) == pytest.approx(value, abs=1e-9)


def test_parameters_set_on_a_line_take_effect_after_it():
    m = moves("G21\n#1 = 2\n#1 = 5 G0 X#1\nG0 Y#1\n#<a> = [#<a> + 1]\nG0 Z#<a>\nM2\n")
    assert [m[0].end[0], m[1].end[1], m[2].end[2]] == [2.0, 5.0, 1.0]


def test_subroutine_arguments_and_return_value():
    text = ("o<sq> sub\n#<r> = [#1 * #1]\no<sq> endsub [#<r> + #2]\nG21\n#1 = 7\n"
            "o<sq> call [3] [1]\nG0 X#<_value> Y#1\nM2\n")
    end = moves(text)[-1].end
    assert end[:2] == (10.0, 7.0)  # 3*3 + 1; #1 restored after the call


def test_loops_and_branches():
    text = ("G21 F100\n#1 = 0\no1 while [#1 lt 5]\n#1 = [#1 + 1]\no2 if [#1 eq 2]\no1 continue\no2 elseif [#1 eq 4]\n"
            "o1 break\no2 else\nG1 X#1\no2 endif\no1 endwhile\no3 repeat [2]\nG91 G1 Y1\no3 endrepeat\n"
            "#2 = 0\no4 do\n#2 = [#2 + 1]\no4 while [#2 lt 0]\nG90 G1 Z#2\nM2\n")
    ends = [m.end for m in moves(text)]
    assert ends == [(1, 0, 0), (3, 0, 0), (3, 1, 0), (3, 2, 0), (3, 2, 1)]  # a do loop runs once at least


def test_subroutine_from_a_file_beside_the_program(tmp_path):
    (tmp_path / "hole.ngc").write_text("o<hole> sub\nG91 G1 Z[-#1]\nG1 Z#1\no<hole> endsub\nM2\n")
    prog = tmp_path / "main.ngc"
    ends = [m.end for m in moves("G21 F50\no<hole> call [4]\nM2\n", name=str(prog))]
    assert ends == [(0, 0, -4), (0, 0, 0)]


def test_arc_by_radius_takes_the_short_or_long_way():
    short = moves("G21 G17 F100\nG2 X10 Y10 R10\nM2\n")[0]
    long_ = moves("G21 G17 F100\nG2 X10 Y10 R-10\nM2\n")[0]
    assert short.center[:2] == pytest.approx((10, 0)) and long_.center[:2] == pytest.approx((0, 10))
    assert short.clockwise and long_.clockwise


def test_helix_of_two_turns_is_two_arcs():
    arcs = moves("G21 G17 F100\nG2 X0 Y0 I5 J0 Z-4 P2\nM2\n")
    assert len(arcs) == 2 and all(a.full_turn and a.center[:2] == (5, 0) for a in arcs)
    assert [a.end[2] for a in arcs] == pytest.approx([-2.0, -4.0])  # z in proportion to the angle


@pytest.mark.parametrize("plane, words, centre", [("G18", "X0 Z0 I0 K5", (0, 0, 5)), ("G19", "Y0 Z0 J5 K0", (0, 5, 0))])
def test_full_circles_in_the_other_planes(plane, words, centre):
    arc = moves(f"G21 {plane} F100\nG3 {words}\nM2\n")[0]
    assert arc.full_turn and arc.center == centre and not arc.clockwise


def test_g7_diameters_g20_inches():
    m = moves("G21 G18 G7\nG0 X20\nG8 X20\nG20 G0 X1\nM2\n", kind="lathe")
    assert [r.end[0] for r in m] == [10.0, 20.0, 25.4]  # records hold radii in mm
    assert not any(r.diameter for r in m)


def test_work_offsets_g92_g10_g53_g28():
    cfg = dict(work_offsets={"G55": (10.0, 20.0, 0.0)})
    text = ("G21\nG55 G0 X0 Y0\nG54 G0 X10\nG92 X0\nG0 X5\nG92.1\nG10 L2 P1 X3\nG0 X0\nG0 X7\nG10 L20 P1 X0\n"
            "G0 X1\nG53 G0 X5\nG0 Y4\nG28.1\nG0 X0 Y0\nG28\nM2\n")
    ends = [m.end[:2] for m in moves(text, **cfg)]
    # G55: (10, 20); X10 in G54; G92 X0 there: X5 is machine 15; G10 L2 X3: X0 is 3; X7 is 10;
    # G10 L20 X0 at machine 10: X1 is 11; G53 X5 is machine 5; Y4; G28.1 there; (0,0) of G54 (10, 0)
    # and back to the stored (5, 4)
    assert ends == [(10, 20), (10, 20), (15, 20), (3, 20), (10, 20), (11, 20), (5, 20), (5, 4), (10, 0), (5, 4)]


def test_tool_table_lengths(tmp_path):
    tbl = tmp_path / "t.tbl"
    tbl.write_text("T1 P1 Z10 D6 ; ten long\nT2 P2 Z25\n")
    recs = run("G21\nG0 Z50\nT1 M6\nG0 Z0\nG43\nG0 Z0\nG43 H2\nG0 Z0\nG49 G0 Z0\nM2\n", tool_table=str(tbl)).records
    m = [r for r in recs if isinstance(r, Rapid)]
    assert any(isinstance(r, ToolChange) and r.tool == 1 for r in recs)
    # no G43: the tip is 10 below the programmed point; G43 (tool 1): on it; H2 (25): 15 above; G49
    assert [r.end[2] for r in m] == [50, -10, 0, 15, -10]


def test_drilling_cycles_by_hand():
    # G99 G81 from Z10: to R, feed to the bottom, back to R; G91 L3 steps X by 5 each hole
    m = moves("G21 F100\nG0 Z10\nG91 G99 G81 X5 R-8 Z-7 L3\nG80\nM2\n")
    feeds = [r.end for r in m if isinstance(r, Feed)]
    assert feeds == [(5, 0, -5), (10, 0, -5), (15, 0, -5)]  # R = 10 - 8 = 2, bottom 2 - 7 = -5
    peck = moves("G21 F100\nG0 Z10\nG90 G98 G83 X0 Y0 R2 Z-5 Q3\nM2\n")
    z = [round(r.end[2], 4) for r in peck]
    # G0 Z10, over the hole at that height, down to R2; pecks of 3 from R: -1, -4, -5, each time back
    # to R and down to 0.254 mm (0.010 in) above the last depth; G98: out to the initial Z10
    assert z == [10, 10, 2, -1, 2, -0.746, -4, 2, -3.746, -5, 10]



def test_g7_cycle_along_x_reads_r_and_q_as_lengths():
    # G19 drills along X. In G7 only the X word (the bottom) is a diameter: X4 is radius 2; R8 and Q2
    # are lengths (8 from the axis, pecks of 2). From X10 (X20 programmed): over the hole at X10, to
    # R 8, pecks to 6, 4 and the bottom 2, each time back up 0.254 mm (0.010 in); G99: out to R 8
    m = moves("G21 G19 G90 G7 G99 F100\nG0 X20 Y0 Z0\nG73 Y1 Z1 R8 X4 Q2\nG80\nM2\n", kind="lathe")
    x = [round(r.end[0], 4) for r in m]
    assert x == [10, 10, 8, 6, 6.254, 4, 4.254, 2, 8]
    # G91: R counts from the initial level (10 + 1 = 11: R lies above, so up to it first), the bottom
    # X-6 is a diameter: 11 - 3 = 8
    inc = moves("G21 G19 G90 G7 G99 F100\nG0 X20 Y0 Z0\nG91 G81 Y1 Z1 R1 X-6\nG80\nM2\n", kind="lathe")
    assert [round(r.end[0], 4) for r in inc] == [10, 11, 11, 8, 11]

def test_threads_are_spindle_synchronised():
    m = moves("G21 G18 S300 M3\nG0 X10 Z5\nG33 Z-20 K1.5\nG0 X20\nG17 G0 X0 Y0 Z5\nG33.1 Z-10 K1\nM2\n")
    syncs = [r for r in m if isinstance(r, SyncedFeed)]
    assert syncs[0].lead == 1.5 and syncs[0].end == (10, 0, -20)
    assert [s.end for s in syncs[1:]] == [(0, 0, -10), (0, 0, 5)]  # rigid tapping: in and out


def test_setup_tool_table_key(tmp_path):
    from cutsim.setup import load_setup
    (tmp_path / "t.tbl").write_text("T1 P1 Z10\n")
    base = '[stock]\nshape = "box"\nx = [0, 1]\ny = [0, 1]\nz = [-1, 0]\n[[tool]]\nnumber = 1\nkind = "endmill"\ndiameter = 6\n'
    (tmp_path / "a.toml").write_text('[machine]\nkind = "mill"\ndialect = "rs274ngc"\ntool_table = "t.tbl"\n' + base)
    assert load_setup(str(tmp_path / "a.toml")).tool_table == str(tmp_path / "t.tbl")
    (tmp_path / "b.toml").write_text('[machine]\nkind = "mill"\ndialect = "isg"\ntool_table = "t.tbl"\n' + base)
    with pytest.raises(CutsimError, match="only the rs274ngc dialect"):
        load_setup(str(tmp_path / "b.toml"))


def test_bad_tool_table_names_its_line(tmp_path):
    tbl = tmp_path / "t.tbl"
    tbl.write_text("T1 P1 Z10\nT1 P2 Z3\n")
    with pytest.raises(CutsimError) as e:
        run("G21\nM2\n", tool_table=str(tbl))
    assert str(e.value).startswith(f"{tbl}:2:1: error: tool 1 is listed twice")


def test_trig_as_linuxcnc_computes_it():
    # LinuxCNC evaluates in x87 long double: cos[90] is -2.5e-20, not the double's 6.1e-17
    assert x_of("[cos[90] * 100000000000000000000]") == pytest.approx(-2.5082788, abs=1e-6)
    assert math.isclose(x_of("[sin[90]]"), 1.0)


def test_g43_1_sets_only_the_axes_it_names(tmp_path):
    tbl = tmp_path / "t.tbl"
    tbl.write_text("T1 P1 X1.5 Z0\n")
    # G43 H1: X offset 1.5 (the tip is where the program says); G43.1 Z2 keeps X 1.5 and sets Z 2:
    # the machine does not move, the next moves land 2 higher in Z and still on X
    m = moves("G21\nT1 M6\nG43 H1\nG0 X10 Z0\nG43.1 Z2\nG0 X20 Z0\nM2\n", tool_table=str(tbl))
    assert [r.end for r in m][-2:] == [(10, 0, 0), (20, 0, 2)]


def test_position_parameters_read_x_as_a_radius_in_g7():
    # G7 halves X words, not the position #<_x> and #5420 report (rs274 2.9: X10 in G8, then in G7
    # #<_x> is 10, and G0 X#<_x> goes to radius 5)
    m = moves("G21 G18\nG0 X10\nG7\nG0 X#<_x>\nG0 X[#5420 * 4]\nM2\n", kind="lathe")
    assert [r.end[0] for r in m] == [10.0, 5.0, 10.0]


def test_numbered_subprograms_by_m98_and_m99():
    # O100 (after the end, as Fanuc-style programs keep them) runs L2 times; it calls O200 once per
    # run; #1 is the caller's (set to 3 inside, seen after), #<a> is local to each call
    text = ("G21 F100\n#1 = 7\n#<a> = 2\nM98 P100 L2\nG90 G0 X#1 Y#<a>\nM98 P100 L0\nM30\n"
            "O100\n#<a> = 9\nG91 G1 X1\nM98 P200\n#1 = 3\nM99\nO200\nG91 G1 Y1\nM99\n")
    ends = [m.end[:2] for m in moves(text)]
    assert ends == [(1, 0), (1, 1), (2, 1), (2, 2), (3, 2)]


def test_m99_in_the_main_program_ends_it_and_an_o_line_in_sequence_runs_on():
    # as rs274 2.9 runs them: "O100" reached in sequence is passed, its M99 is then the program end
    text = "G21 F100\nO100\nG91 G1 X1\nM99\nG1 Y5\nM2\n"
    assert [m.end[:2] for m in moves(text)] == [(1, 0)]


@pytest.mark.parametrize("text, message", [
    ("G21\nM98\nM2\n", "needs the subprogram number P"),
    ("G21\nM98 P5\nM2\nO6\nM99\n", "O5 is not in this program"),
    ("G21\nM98 P5 L-1\nM2\nO5\nM99\n", "whole number"),
    ("G21\nG0 X1 M98 P5\nM2\nO5\nM99\n", "stands alone"),
    ("G21\nM98 P5\nM2\nO5\nO5\nM99\n", "defined twice"),
    ("G21\no<s> call\nM2\no<s> sub\nM99\no<s> endsub\n", "inside an o-word subroutine"),
])
def test_m98_m99_refusals(text, message):
    with pytest.raises(CutsimError, match=message):
        moves(text)


@pytest.mark.parametrize("units, move, f, feed", [
    ("G21", "X10", 3.0, 30.0),  # 10 mm in 1/3 min
    ("G21", "X0.034", 2.55, 0.1),  # 0.0867 mm/min: LinuxCNC's floor of 0.1 units per minute
    ("G20", "X0.001", 2.0, 2.54),  # 0.002 in/min: the floor, 0.1 in/min
])
def test_inverse_time_feed_is_length_times_f_at_least_a_tenth_unit_per_minute(units, move, f, feed):
    m = moves(f"{units}\nG93 G1 {move} F{f}\nM2\n")
    assert m[-1].feed == pytest.approx(feed)


def test_g87_back_bores_through_its_offset_point():
    # G98 G87 X10 Y5 R3 Z-15 I2 J-1 K-8 from Z20: the hole (10, 5), the offset point (10 + 2, 5 - 1);
    # in at the offset point from R down to the bottom Z-15, over to the hole, feed up to the top
    # K-8 and back to the bottom, out through the offset point to the initial level 20, over the hole
    m = moves("G21 F100 S500 M3\nG0 X0 Y0 Z20\nG98 G87 X10 Y5 R3 Z-15 I2 J-1 K-8\nG80\nM2\n")[1:]
    ends = [(r.end, type(r).__name__) for r in m]
    assert ends == [((10, 5, 20), "Rapid"), ((10, 5, 3), "Rapid"), ((12, 4, 3), "Rapid"), ((12, 4, -15), "Rapid"),
                    ((10, 5, -15), "Rapid"), ((10, 5, -8), "Feed"), ((10, 5, -15), "Feed"),
                    ((12, 4, -15), "Rapid"), ((12, 4, 20), "Rapid"), ((10, 5, 20), "Rapid")]


def test_g87_in_g91_tops_from_the_bottom_and_keeps_ijk():
    # G91 from Z10: R-2 is 8, the bottom Z-10 from R is -2, K3 the top 3 above it (1); the second
    # block (X5, no I J K) keeps I1 J0 K3: the offset point 1 mm along X from the hole at X10
    m = moves("G21 F100 S500 M3\nG0 X0 Y0 Z10\nG91 G99 G87 X5 R-2 Z-10 I1 J0 K3\nX5\nG90 G80\nM2\n")
    feeds = [r.end for r in m if isinstance(r, Feed)]
    assert feeds == [(5, 0, 1), (5, 0, -2), (10, 0, 1), (10, 0, -2)]
    assert (11, 0, -2) in [r.end for r in m if isinstance(r, Rapid)]


def test_a_cycle_after_g92_3_compares_its_initial_level_with_r_as_rs274_holds_them():
    # G20: G92 Z-15.565 at Z-10.025 makes the offset 25.831; the first G81 retracts to R 4.569 (G99:
    # its initial level -15.565 is under R); G92.3 moves rs274's program Z by 4.569 + 25.831 - 25.831,
    # a last bit under 4.569 in doubles, and that is the next series' initial level: its second block
    # (R4.569 again, after R6.241) goes down to R where the tool stands, before the next hole
    assert (4.569 + 25.831) - 25.831 < 4.569
    text = ("G20 G90 F100\nG0 Z-10.025\nG92 Z-15.565\nG98 G81 X12.155 R4.569 Z0.118\nG0 Y-4.841\n"
            "{}G81 X16.294 Y19.605 R6.241 Z0.118\nX12.155 R4.569\nM2\n")
    inch = 25.4
    for g92_3, down in (("G92.3\n", True), ("", False)):
        m = moves(text.format(g92_3))
        first = max(i for i, r in enumerate(m) if isinstance(r, Feed) and r.end[0] == pytest.approx(16.294 * inch))
        after = m[first + 2]  # after the feed down and the rapid out
        if down:
            assert after.end[0] == pytest.approx(16.294 * inch) and after.end[2] < after.start[2]
        else:
            assert after.end[0] == pytest.approx(12.155 * inch) and after.end[2] == pytest.approx(after.start[2])
