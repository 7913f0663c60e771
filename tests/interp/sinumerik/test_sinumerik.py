"""Sinumerik 840D language core: block syntax, modal state, parameters and jumps, subprograms,
the contour editor's blocks and tool radius compensation, checked on the canonical moves
(numbers worked out by hand from the programs), plus every shipped Sinumerik example simulates."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

import cutsim
from cutsim import CutsimError
from cutsim.interp import InterpConfig, interpret
from cutsim.interp import canon
from cutsim.interp.sinumerik import contour as sinumerik_contour

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "sinumerik"


def moves(text, radii=None, start=(0.0, 0.0, 50.0), name="t.mpf"):
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=start, tool_radii=radii or {1: 5.0})
    return interpret(name, text, cfg)


def ends(prog):
    return [tuple(round(v, 6) for v in r.end) for r in prog.moves]


def test_words_comments_ac_ic_and_arcs():
    p = moves("""; a comment line
N10 G90 G17 F100 ; comment after a block
N20 G1 X10 Y10 Z0
N30 G91 X5 Y=AC(0)      ; incremental X, absolute Y
N40 G90 X=IC(5) Y20
N50 G2 X30 Y10 I0 J-10  ; centre incremental from the start
N60 G3 X40 Y20 CR=10    ; short arc by radius
N70 G2 X30 Y30 I=AC(30) J=AC(20)
N80 M30
""")
    assert ends(p) == [(10, 10, 0), (15, 0, 0), (20, 20, 0), (30, 10, 0), (40, 20, 0), (30, 30, 0)]
    arcs = [r for r in p.moves if isinstance(r, canon.Arc)]
    assert arcs[0].center == (20, 10, 0) and arcs[0].clockwise
    assert arcs[1].center[:2] == pytest.approx((30, 20)) and not arcs[1].clockwise  # CR=10, CCW, the short way
    assert arcs[2].center[:2] == (30, 20)
    assert all(r.src.line == i for r, i in zip(p.moves, (3, 4, 5, 6, 7, 8)))


def test_negative_cr_takes_the_long_way():
    p = moves("G90 G17 F100\nG1 X0 Y0 Z0\nG2 X20 Y0 CR=-10\nM30\n")
    arc = p.moves[-1]
    # from (0,0) to (20,0) radius 10 either way is a half circle: the centre is the chord's middle
    assert arc.center[:2] == pytest.approx((10, 0))
    p = moves("G90 G17 F100\nG1 X0 Y0 Z0\nG2 X10 Y10 CR=-10\nM30\n")
    c = p.moves[-1].center
    # CW over more than 180 degrees from (0,0) to (10,10): centre (10, 0)... mirrored: (0, 10)
    assert (round(c[0], 6), round(c[1], 6)) == (0, 10)


def test_parameters_def_jumps_repeat():
    p = moves("""G90 F100
R1=2 R2=R1*3+1       ; 7
DEF REAL STEP=2.5, CNT
CNT=0
LOOP:
G1 X=CNT*STEP Y=R2 Z=-R1
CNT=CNT+1
IF CNT<3 GOTOB LOOP
GOTOF SKIP
G1 X99                ; skipped
SKIP:
G1 Y=SQRT(16)+ABS(-1)
START:
G1 Z=R1
R1=R1+1
STOP:
REPEAT START STOP P=2
G1 X=COS(60)*10
M30
""")
    # the loop three times, X99 skipped, the section START..STOP once more twice, COS(60)*10 = 5
    assert ends(p) == [(0, 7, -2), (2.5, 7, -2), (5, 7, -2), (5, 5, -2), (5, 5, 2), (5, 5, 3), (5, 5, 4), (5, 5, 4)]


def test_repeat_label_and_subprograms():
    p = moves("""G90 F100
G1 X0 Y0 Z0
MARK:
G91 G1 X1
G90
REPEAT MARK P=2
HOLE P2
L10
M30
PROC HOLE
G91 G1 Y1
G90
RET
%_N_L10_SPF
G1 Z5
M17
""")
    assert ends(p) == [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0), (3, 1, 0), (3, 2, 0), (3, 2, 5)]
    assert p.moves[-1].src.calls == (("t.mpf", 8),)


def test_tool_change_and_spindle():
    p = moves("T2 D1\nM6\nS1500 M3\nM5\nM30\n", radii={1: 5.0, 2: 3.0})
    recs = [r for r in p.records if not isinstance(r, canon.ProgramEnd)]
    assert isinstance(recs[0], canon.ToolChange) and recs[0].tool == 2 and recs[0].src.line == 2
    assert [(r.direction, r.speed) for r in recs[1:]] == [(1, 1500), (0, 1500)]


def test_contour_editor_blocks_are_plain_g_blocks():
    p = moves(""";#7__DlgK contour definition begin - Don't change!;*GP*;*RO*
G17 G90 ;*GP*
G1 X13 Y69.65 F100 ;*GP*
G3 X28 Y54.65 I=AC(28) J=AC(69.65) ;*GP*
;CON,0,0.000,2,2,MST:2,1,AX:X,Y,1,J;*GP**RO*
;ACCW,EX:28,EY:54.65,RAD:15;*GP*;*RO*
;#End contour definition end - Don't change!;*GP*;*RO*
M30
""")
    assert ends(p) == [(13, 69.65, 50), (28, 54.65, 50)]
    assert p.moves[1].center == (28, 69.65, 50)


def test_g42_outside_a_square_goes_round_the_corners():
    # CCW square 0..20 with G42 (tool right of the path = outside), tool radius 5
    p = moves("""G90 G17 F100
G0 X-10 Y-10 Z-1
G42 G1 X0 Y0
X20
Y20
X0
Y0
G40 X-10 Y-10
M30
""")
    e = ends(p)[1:]
    assert e == [(0, -5, -1), (20, -5, -1), (25, 0, -1), (25, 20, -1), (20, 25, -1), (0, 25, -1), (-5, 20, -1),
                 (-5, 0, -1), (-10, -10, -1)]
    corner = p.moves[3]
    assert isinstance(corner, canon.Arc) and corner.center == (20, 0, -1) and not corner.clockwise


def test_g41_inside_a_square_meets_at_the_corners():
    p = moves("""G90 G17 F100
G0 X10 Y10 Z-1
G41 G1 X10 Y0
X20
Y20
X0
Y0
X10
G40 Y10
M30
""")
    assert ends(p)[1:] == [(10, 5, -1), (15, 5, -1), (15, 15, -1), (5, 15, -1), (5, 5, -1), (10, 5, -1), (10, 10, -1)]


def test_g41_arc_radius_changes():
    # a CCW half circle of radius 20 about (0,0); G41 (left = towards the centre) -> radius 15
    p = moves("G90 G17 F100\nG0 X20 Y-10 Z0\nG41 G1 X20 Y0\nG3 X-20 Y0 CR=20\nG40 G1 X-20 Y-10\nM30\n")
    arc = p.moves[2]
    assert arc.start[:2] == pytest.approx((15, 0)) and arc.end[:2] == pytest.approx((-15, 0))
    with pytest.raises(CutsimError) as e:
        moves("G90 G17 F100\nG0 X20 Y-10 Z0\nG41 G1 X20 Y0\nG3 X-20 Y0 CR=20\nG40 G1 X-20 Y-10\nM30\n",
              radii={1: 25.0})
    assert e.value.line == 4 and "does not fit" in e.value.message


@pytest.mark.parametrize("excess, refused", [(0.5e-6, False), (5e-6, True), (5e-5, True)])
def test_cr_circle_may_be_too_small_by_one_micron_only(excess, refused):
    """A CR= half circle whose chord exceeds 2 CR: within 1e-6 mm it is the half circle (centre at
    the chord's middle); beyond it is refused, also within the core's wider default slack 1e-4."""
    text = f"G90 G17 F100\nG1 X0 Y0 Z0\nG2 X{20 + excess:.7f} Y0 CR=10\nM30\n"
    if refused:
        with pytest.raises(CutsimError) as e:
            moves(text)
        assert e.value.line == 3 and "CR=10 is too small" in e.value.message
    else:
        assert moves(text).moves[-1].center[:2] == pytest.approx(((20 + excess) / 2, 0), abs=1e-9)


@pytest.mark.parametrize("text, line, col, message", [
    ("G1 X10\nG7 X1\n", 2, 1, "unknown G code G7"),
    ("G1 X1.2.3\n", 1, 5, "malformed number"),
    ("GOTOF NOWHERE\n", 1, 1, "label NOWHERE does not exist"),
    ("G1 X=FOO+1\n", 1, 6, "unknown variable 'FOO'"),
    ("G1 X0 Y0\nG2 X30 Y0 CR=10\n", 2, 11, "CR=10 is too small"),
    ("F100\nKONTUR7\n", 2, 1, "subprogram KONTUR7 is not defined"),
    ("G1 X10 X20\n", 1, 8, "appears twice"),
    ("G1 X10 & Y\n", 1, 8, "unexpected character '&'"),
    ("LOOP:\nGOTOB LOOP\n", 2, 1, "does not end"),
    ("SLOT9(1, 2)\n", 1, 1, "unknown cycle"),
    ("G2 X10 Y10\n", 1, 1, "needs its centre"),
    ("M6\n", 1, 1, "M6 without a tool"),
    ("T9 M6\n", 1, 1, "T9 is not in the setup"),
])
def test_errors_have_line_and_column(text, line, col, message):
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0, 0, 0), tool_radii={1: 5.0}, max_blocks=1000)
    with pytest.raises(CutsimError) as e:
        interpret("t.mpf", text, cfg)
    assert (e.value.line, e.value.col) == (line, col)
    assert message in e.value.message


PROGRAMS = sorted(EXAMPLES.glob("*.mpf"))


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.name)
def test_sinumerik_example_simulates(program):
    r = cutsim.simulate(str(program), str(program.with_suffix(".toml")), tolerance=0.01)
    assert r.part.status().name == "NoError"
    assert r.report["removed_volume"] > 0
    assert r.report["dialect"] == "sinumerik"


def test_g41_concave_line_arc_corner_is_cut_back():
    # line (0,0)->(20,0), then a CCW arc about (10,10) to (20,20): the path turns left by 45 degrees;
    # G41 (left, radius 5): the offset line Y=5 meets the offset arc (radius sqrt(200)-5) at
    # X = 10 + sqrt((sqrt(200)-5)^2 - 25)
    p = moves("G90 G17 F100\nG0 X0 Y-10 Z0\nG41 G1 X0 Y0\nX20\nG3 X20 Y20 I=AC(10) J=AC(10)\nG40 G1 X30 Y30\nM30\n")
    r2 = math.sqrt(200) - 5
    xi = 10 + math.sqrt(r2 * r2 - 25)
    e = [m.end[:2] for m in p.moves]
    assert e[1] == pytest.approx((0, 5))
    assert e[2] == pytest.approx((xi, 5))
    assert e[3] == pytest.approx((10 + r2 / math.sqrt(2), 10 + r2 / math.sqrt(2)))
    assert p.moves[3].start[:2] == pytest.approx((xi, 5)) and p.moves[3].center[:2] == (10, 10)


def test_cycle72_contour_from_a_subprogram_and_a_file(tmp_path):
    body = "G17 G90\nG1 X0 Y0\nG1 X20\nG1 Y20\n"
    main = ("T1 D1 M6\nF100\nCYCLE72(\"{}\", 10, 0, 2, -3, 3, 0, 0, 300, 100, 0, 42, 1, 5, 0, 1, 5)\nM30\n")
    p1 = moves(main.format("KONT") + "PROC KONT\n" + body + "RET\n")
    (tmp_path / "kont2.spf").write_text(body + "M17\n")
    p2 = moves(main.format("KONT2"), name=str(tmp_path / "main.mpf"))
    for p in (p1, p2):
        cuts = [m for m in p.moves if m.end[2] == -3 and m.start[2] == -3]
        # G42 (right of travel): the first edge X 0..20 at Y=0 is offset to Y=-5, the second to X=25,
        # with a quarter circle about the corner (20, 0); straight approach and retract of 5
        assert [tuple(round(v, 6) for v in m.end[:2]) for m in cuts] == [(0, -5), (20, -5), (25, 0), (25, 20), (25, 25)]
        assert all(m.src.line == 3 for m in cuts)


def test_cycle72_contour_file_errors_are_its_own(tmp_path):
    """Only a name that is neither a PROC nor a NAME.spf is "contour not found"; an error inside
    the contour's file is reported at its own file and line."""
    main = "T1 D1 M6\nF100\nCYCLE72(\"{}\", 10, 0, 2, -3, 3, 0, 0, 300, 100, 0, 42, 1, 5, 0, 1, 5)\nM30\n"
    (tmp_path / "kont3.spf").write_text("G17 G90\nG1 X0 Y0\nG1 X20 Y=\nM17\n")
    with pytest.raises(CutsimError) as e:
        moves(main.format("KONT3"), name=str(tmp_path / "main.mpf"))
    assert (e.value.program, e.value.line, e.value.col) == (str(tmp_path / "kont3.spf"), 3, 10)
    assert "expression expected" in e.value.message
    with pytest.raises(CutsimError) as e:
        moves(main.format("KONT4"), name=str(tmp_path / "main.mpf"))
    assert (e.value.line, e.value.col) == (3, 1) and "contour KONT4 not found" in e.value.message


def test_cycle72_unexpected_errors_are_not_turned_into_contour_messages(monkeypatch):
    """A fault inside the contour code (injected here) is not reported as a contour problem: it
    propagates, and the CLI reports it as an internal error (exit 3)."""
    def broken(*args):
        raise ZeroDivisionError("injected")
    monkeypatch.setattr(sinumerik_contour, "contour_records", broken)
    text = ("T1 D1 M6\nF100\nCYCLE72(\"KONT\", 10, 0, 2, -3, 3, 0, 0, 300, 100, 0, 42, 1, 5, 0, 1, 5)\nM30\n"
            "PROC KONT\nG17 G90\nG1 X0 Y0\nG1 X20\nRET\n")
    with pytest.raises(ZeroDivisionError):
        moves(text)


def test_slot1_oscillating_infeed_ramps():
    p = moves("T1 D1 M6\nF100\nSLOT1(10, 0, 2, -4, , 1, 30, 10, 0, 0, 0, 0, 0, 100, 300, 2, 0, 0, 30)\nM30\n")
    ramps = [m for m in p.moves if isinstance(m, canon.Feed) and m.start[2] != m.end[2]
             and (m.start[0], m.start[1]) != (m.end[0], m.end[1])]
    # two depth steps of 2 mm, each reached by going along the slot axis and back, half the way
    # down each way; the first starts at the safety plane RFP + SDIS = 2
    assert [round(m.start[2] - m.end[2], 6) for m in ramps] == [2, 2, 1, 1]
    assert all(abs(m.end[1]) < 1e-9 for m in ramps)


def test_dpr_wins_over_dp():
    p = moves("T1 D1 M6\nF100\nPOCKET2(10, 2, 1, -50, 3, 5, 0, 0, 100, 300, 0, 0, 0, 10)\nM30\n")
    assert min(m.end[2] for m in p.moves) == pytest.approx(-1.0)


def test_endless_gotob_is_found_at_its_line_without_the_block_limit():
    """A backward jump that comes back with every parameter unchanged loops forever: reported at
    the GOTOB at once (the block limit is set far away), while a counted loop runs to its end."""
    text = "R1=0\nLOOP:\nR1=R1+1\nG1 X=R1 F100\nIF R1<5 GOTOB LOOP\nAGAIN:\nG1 X0\n  GOTOB AGAIN\nM30\n"
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0, 0, 0), max_blocks=10**9)
    with pytest.raises(CutsimError) as e:
        interpret("t.mpf", text, cfg)
    assert (e.value.line, e.value.col) == (8, 3)
    assert "loops forever" in e.value.message
    prog = interpret("t.mpf", text.replace("  GOTOB AGAIN\n", ""), cfg)
    xs = [m.end[0] for m in prog.moves]
    assert xs == [1.0, 2.0, 3.0, 4.0, 5.0, 0.0]  # the counted loop ran five times


# -- limits: the values just inside every limit still run (tests/interp/sinumerik/test_bad_sinumerik.py: just outside)
def test_values_at_the_limits_run():
    chain = "+".join(["1"] * 250)  # a block of 499 characters before its comment
    nested = "(" * 31 + "2" + ")" * 31  # 31 parentheses + the expression itself: 32 levels
    p = moves(f"""G90 G17 F99999.9999 S99999 T32000 D0
G1 X99999.9999 Y-99999.9999 Z0
R9999={nested}
R1={chain} ; {"a comment of any length " * 40}
G1 X=R1 Y=R9999 Z=12345678901234567890/1000000000000000
G1 X0.0000000000000000001
M30
""")
    assert ends(p) == [(99999.9999, -99999.9999, 0), (250, 2, 12345.678901), (0, 2, 12345.678901)]


def test_unicode_minus_and_strings_stay_accepted():
    p = moves('MSG("Fräsen − ž")\nG1 X−10 Y5 Z0 F100\nM30\n')
    assert ends(p) == [(-10, 5, 0)]


def test_cycle_moves_up_to_max_blocks_run():
    # POCKET2 radius 14, 10 mm tool, 4 infeeds: estimated about 100 moves, runs under a limit of 200
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(50.0, 50.0, 50.0), tool_radii={1: 5.0},
                       max_blocks=200)
    p = interpret("t.mpf", "G17 G90 S1000 M3 F300\nPOCKET2(10, 0, 2, -4, , 14, 50, 50, 100, 300, 1, 0, 0, 0)\nM30\n", cfg)
    assert 20 < len(p.moves) <= 200
    assert min(r.end[2] for r in p.moves) == pytest.approx(-4.0)


@pytest.mark.parametrize("body, line, what", [
    ("IF R1==1\nG1 X20\nELSE\nG1 X40\nENDIF\n", 3, "IF"),
    ("WHILE R1<2\nG1 X=R1*10\nR1=R1+1\nENDWHILE\n", 3, "WHILE"),
    ("FOR R2=1 TO 2\nG1 X=R2*10\nENDFOR\n", 3, "FOR"),
    ("CASE R1 OF 1 GOTOF A1 DEFAULT GOTOF A2\nA1: G1 X20\nA2: G1 Y20\n", 3, "CASE"),
])
def test_cycle72_contour_with_control_flow_is_refused(tmp_path, body, line, what):
    """The contour's blocks run in a sandbox line after line: an IF/ELSE there would run both
    branches (a contour the controller never cuts), so control structures are errors at their
    line, in the contour's own file."""
    main = ("R1=1\nT1 D1 M6\nF100\nCYCLE72(\"{}\", 10, 0, 2, -3, 3, 0, 0, 300, 100, 0, 42, 1, 5, 0, 1, 5)\nM30\n")
    contour = "G17 G90\nG1 X0 Y0\n" + body + "G1 Y30\n"
    with pytest.raises(CutsimError) as e:
        moves(main.format("KONT") + "PROC KONT\n" + contour + "RET\n")
    assert (e.value.program, e.value.line) == ("t.mpf", 6 + line) and f"{what} is not allowed" in e.value.message
    (tmp_path / "kont5.spf").write_text(contour + "M17\n")
    with pytest.raises(CutsimError) as e:
        moves(main.format("KONT5"), name=str(tmp_path / "main.mpf"))
    assert (e.value.program, e.value.line) == (str(tmp_path / "kont5.spf"), line)
    assert f"{what} is not allowed" in e.value.message


@pytest.mark.parametrize("comp, radius", [(41, 25.0), (42, 15.0)])
def test_full_circle_under_radius_compensation(comp, radius):
    """A full circle G2 of radius 20 about (0, 0) from (-20, 0) (clockwise: upwards at the start) with
    a 10 mm tool: G41 keeps the tool left of travel, outside (radius 25), G42 inside (radius 15).
    The circle runs as its two halves through the opposite point; approach and departure straight."""
    p = moves(f"T1 D1 M6\nG0 X-40 Y0 Z10\nG1 Z-2 F300\nG{comp} X-20 Y0\nG2 X-20 Y0 I20 J0\nG40 G1 X-40\nM30\n")
    mv = p.moves
    arcs = [m for m in mv if isinstance(m, canon.Arc)]
    assert [(a.start[:2], a.end[:2], a.center[:2], a.clockwise) for a in arcs] == [
        ((-radius, 0), (radius, 0), (0, 0), True), ((radius, 0), (-radius, 0), (0, 0), True)]
    assert all(a.src.line == 5 for a in arcs)
    assert mv[mv.index(arcs[0]) - 1].end == (-radius, 0, -2)  # the approach
    assert mv[-1].end == (-40, 0, -2) and mv[-1].start == (-radius, 0, -2)  # the departure


def test_cycle72_full_circle_contour():
    """A contour that is one full circle (radius 20 about (50, 50)), milled outside (_RL 41 on a
    clockwise circle: left of travel is outside) with a 10 mm tool: the tool centre runs at radius
    25, as two halves, at the depth -3."""
    p = moves("T1 D1 M6\nF100\nCYCLE72(\"RING\", 10, 0, 2, -3, 3, 0, 0, 300, 100, 0, 41, 1, 5, 0, 1, 5)\nM30\n"
              "PROC RING\nG17 G90\nG0 X30 Y50\nG2 X30 Y50 I20 J0\nRET\n")
    arcs = [m for m in p.moves if isinstance(m, canon.Arc)]
    assert len(arcs) == 2 and all(a.end[2] == -3 and a.center[:2] == (50, 50) and a.clockwise for a in arcs)
    assert [a.start[:2] for a in arcs] == [(25, 50), (75, 50)] and arcs[-1].end[:2] == (25, 50)
