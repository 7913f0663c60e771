"""The ISG language of real TwinCAT CNC programs (issue 16): control structures, expressions,
variables, # commands, work offsets, global subprograms, machine functions and extra axes.

Golden transcripts (tests/data/golden/isg/lang/<name>.nc -> <name>.txt, run with setup.toml there;
regenerate with CUTSIM_UPDATE_GOLDEN=1 and review the diff). Every number was checked by hand
against the program and the TwinCAT CNC programming manual's semantics:

- control.nc: $WHILE P1 < 3 feeds to X0, X10, X20 (Y5 Z-1); $FOR P2 = 1..4 moves to Y10 (P2 = 1)
  and Y30 (P2 = 3): P2 = 2 is skipped by $CONTINUE and $BREAK leaves at P2 = 4; $SWITCH 4 runs
  $CASE 4 (X44) and falls through to $CASE 5 (X55) up to its $BREAK; $DO ... $ENDDO P3 < 2 runs
  twice (Z-2, Z-3); $IF .. $GOTO [DONE] and $GOTO N370 jump over X99 and X98; N370: G00 Z10.
- expressions.nc: [2 + 3 * 4] = 14 and [[2 + 3] * 4] = 20; 2 ** 3 = 8; 11 MOD 3 = 2;
  SIN[30] * 10 = COS[60] * 10 = 5 (degrees); SQRT[16] + SQR[3] = 13; ABS[-7] = 7;
  INT[-2.7] + 10 = 8 (truncation); FRACT[2.75] * 4 = 3; ROUND[2.5] = 3; ATAN2[1, 1] = 45;
  TAN[45] * 20 = 20; EXP[0] + LN[1] = 1; P1 = 6: P1 / 4 = 1.5, -P1 = -6; the AND/&&/NOT and
  OR conditions are true (X50, Y50); "X 52.5 Y 10" with spaces and an unclosed "(" comment.
- variables.nc: V.P.XS[0..2] = 10, 20, 30 at Y = V.L.STEP = 5, Z = -V.P.DEPTH = -2 for
  P2 = 0 .. V.E.PASSES - 1 (V.E.PASSES = 3 from the setup); V.P.DEPTH becomes 3; the local
  subprogram's own V.L.STEP = 7 gives X30 + 7 = 37 at Z-3 while the main program's V.L.STEP
  stays 5 (Y10 after the call); V.E.MODE == "FINISH" (a string from the setup) raises to
  V.G.SAFE_Z = 25.
- commands.nc: #MSG, #FLUSH WAIT, #HSC pass; the #COMMENT block is not read; G54 (10, 20, 0)
  puts X0 Y0 at machine (10, 20); G55 (50, 50, -5) puts X0 Y0 at (50, 50), Z (not programmed)
  stays -1; G53 G00 Z10; #CS ON [5, 5, 0, 0, 0, 0] puts X1 Y1 at (6, 6), #CS OFF back at
  (1, 1); G92 X5 Y5 (a reference point offset, added like a zero offset) puts X10 Y10 at
  machine (15, 15); M200=40, H7, M110 are machine functions of the setup; A90 is tracked, X20
  goes to 25.
- lathe-loop.nc (its own lathe setup): seed 004's M70x1.5 with the passes from
  $FOR P1 = 1..4, X[70 - 0.46 * P1] = 69.54, 69.08, 68.62, 68.16 (diameters, G51; start X150
  radius = 300), each pass LL PASS: G33 Z48 K1.5 from Z105, out to X72, back to Z105.
- global.nc: L CYCLE [NAME = pocket_sub.nc @P1 = 4 @P2 = -1.5] runs the file beside it: from
  (10, 10, 2) incrementally Z[@P2 - 2] = -3.5 down to Z-1.5, a 4 mm square back to (10, 10) and
  Z[2 - @P2] = +3.5 up to Z2; then L pocket_sub [@P1 = 2, @P2 = -3]: Z-3 and a 2 mm square.
- compensation.nc: G41 with the setup's tool 1 (diameter 6, r = 3) round a contour run clockwise
  (up X0, a half circle G02 X20 Y20 R10 about (10, 20), down X20, back along Y0): the left of the
  travel is outside. The approach (-10, -10) -> (0, 0) moved 3 to its left meets x = -3 at
  y = 3*sqrt(2) - 3 = 1.2426 (an inside corner); the line ends at (-3, 20), where the arc, now of
  radius 13 about (10, 20), starts tangentially and ends at (23, 20); the right-angle corner at
  (20, 0) becomes the extended lines' intersection (23, -3) (G25); the line y = -3 meets the
  departure moved left at (3*sqrt(2) - 3, -3) = (1.2426, -3); the departure ends at (-10, -10).
- modal-cycle.nc: L CYCLE [NAME = peck.nc MODAL_MOVE @P1 = 3] runs peck.nc (down 3 incrementally at
  F100, back up) at the call (0, 0, 5) and again after each block with a motion: N30 X10 (a rapid:
  the cycle's G91 G01 F100 end with it), N40 G01 Y10 F200; not after N50 M08 (no motion) nor after
  #DISABLE MODAL CYCLE (N70 X20 feeds at F200 alone). N80 G81[2, 4] runs G81.nc once (the manual's
  implicit calls are not modal): down 2 at F50 to Z3, rapid up 4 to Z7; N90 X30 feeds again with
  G01 F200 (a call with parameters restores them). N100 G803 is declared external in setup.toml:
  no motion; N110 G00 Z20 rises from (30, 10, 7).
- rotation.nc: #ROTATION ON [ANGLE = 30] turns the 10 mm square (10,0) (10,10) (0,10) (0,0) about
  the origin: (x cos30 - y sin30, x sin30 + y cos30) = (8.660254, 5), (3.660254, 13.660254),
  (-5, 8.660254), (0, 0) (reached by the incremental G91 Y-10, which turns too), (8.660254, 5).
  #CS ON [50, 50, 0, 0, 0, 90]: program (x, y) is machine (50 - y, 50 + x): X10 Y0 -> (50, 60); the
  counter-clockwise G03 to X0 Y10 about the program origin (I-10) is counter-clockwise from (50, 60)
  to (40, 50) about (50, 50); X0 Y0 -> (50, 50); G91 X5 -> (50, 55). #ROTATION ON [ANGLE -90
  CENTER1 = 20 CENTER2 = 0]: X20 Y10 is (0, 10) from the centre, turned by -90 degrees (10, 0):
  (30, 0). G21 mirrors X: X10 Y0 -> (-10, 0); G03 X0 Y10 I-10 (counter-clockwise about (0, 0) in the
  program) runs clockwise from (-10, 0) to (0, 10); G02 X-10 Y0 R10 (program: clockwise about
  (-10, 10), the shorter arc) runs counter-clockwise from (0, 10) to (10, 0) about (10, 10). G20
  ends it; G351 Y-1 mirrors Y alone: X5 Y5 -> (5, -5); G351 Y1 ends it.
- real-forms.nc (its own setup): forms of real WAAM and bioprinter programs. The header's text after
  the name is a title; L vendor_start.nc and the macro "ARC_ON" are declared external, "ARC_OFF" is
  taken to come from the skipped vendor_start.nc (no motion). G92 X100 Y50 Z10 puts X0 Y0 Z0 at machine (100, 50, 10). The first #VAR gives
  V.P.LAYER = [1, 0.5]: X[10 * 1] -> (110, 50, 10), Z0.5 -> 10.5; the second #VAR, run where it
  stands, gives [2, 1.5]: X20 -> (120, 50, 10.5), Z1.5 -> 11.5. V.G.NP[1].V.X = 200 and
  V.G.NP[1].V.Y = -200 / 4 = -50 write G54's offset; after G92 X0 Y0 Z0, G54 X1 Y1 goes to
  (201, -49), Z (not programmed) stays 11.5; V.G.NP_AKT.V.Z = -10 moves the active offset at once:
  Z5 -> machine -5.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main
from cutsim.interp import CutsimError, InterpConfig, interpret
from cutsim.interp import canon

HERE = Path(__file__).resolve().parents[2]  # tests/
GOLDEN = HERE / "data" / "golden" / "isg" / "lang"
SETUP = GOLDEN / "setup.toml"
NAMES = ["control", "expressions", "variables", "commands", "global", "lathe-loop", "compensation", "modal-cycle", "rotation",
         "real-forms"]


@pytest.mark.parametrize("name", NAMES)
def test_isg_language_golden(name):
    prog = GOLDEN / f"{name}.nc"
    own = prog.with_suffix(".toml")  # a program with its own setup (the lathe), else setup.toml
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(own if own.is_file() else SETUP)])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / f"{name}.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


# -- unit checks on the interpreter (InterpConfig built directly) -------------------------------------
def cfg(**kw) -> InterpConfig:
    base = dict(dialect="isg", machine_kind="mill", start=(0.0, 0.0, 50.0))
    base.update(kw)
    return InterpConfig(**base)


def run(text: str, name: str = "t.nc", **kw) -> canon.Program:
    return interpret(name, text, cfg(**kw))


def fails(text: str, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, **kw)
    return e.value


def ends(prog) -> list:
    return [m.end for m in prog.moves]


def test_passive_commands_warn_once_each():
    prog = run("%P\n#FLUSH WAIT\n#FLUSH WAIT\n#MSG [\"a\"]\n#CONTOUR MODE ON [DEV PATH_DEV=0.08]\nG01 X1 F100\nM30\n")
    msgs = [m for _, m in prog.warnings]
    assert sum("#FLUSH" in m for m in msgs) == 1 and sum("#MSG" in m for m in msgs) == 1
    assert sum("#CONTOUR" in m for m in msgs) == 1
    assert ends(prog) == [(1.0, 0.0, 50.0)]


@pytest.mark.parametrize("text, what", [
    ("#TRAFO ON", "kinematic transformation"),
    ("#RTCP ON", "RTCP"),
    ("#MCS ON", "machine coordinates"),
    ("#CS ON [0, 0, 10, 30, 0, 45]", "rotation about X by 30 degrees"),
    ("#CS ON [0, 0, 10, 0, -15, 0]", "rotation about Y by -15 degrees"),
    ("#CS DEF [2] [0, 0, 10, 5, 5, 0]", "rotation about X by 5 degrees and about Y by 5 degrees"),
    ("G68 X0 Z1 R30", "G68 takes the centre in the axes of the plane XY, not Z"),
    ("G351 X-1 Y2", "G351 Y2: the value is -1 (mirroring on) or 1 (off)"),
    ("G351 X-1 G01 Y2", "G351 must stand alone"),
    ("G351", "G351 needs at least one axis"),
    ("#ROTATION ON [ANGEL=30]", "ANGLE, CENTER1 or CENTER2 expected"),
    ("G237 G41 D1", "G41 under G237 (perpendicular selection/deselection of tool radius compensation)"),
    ("G74 Z1", "homing"),
    ("#FOO", "#FOO is not known"),
])
def test_what_changes_the_path_unmodelled_is_exit_2(text, what):
    e = fails(f"%P\nG01 X1 F100\n{text}\nG01 X2\nM30\n")
    assert e.line == 3 and what in e.message, str(e)


def test_off_forms_pass():
    prog = run("%P\n#TRAFO OFF\n#RTCP OFF\n#MCS OFF\n#CS OFF\n#CS OFF ALL\nG40 G01 X1 F100\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0)]


def test_cs_def_then_on_by_id_and_nesting():
    prog = run("%P\n#CS DEF [2] [10, 0, 0]\nG00 X1\n#CS ON [2]\nG00 X1\n#CS ON [0, 5, 0]\nG00 X1 Y1\n"
               "#CS OFF\nG00 X1 Y1\n#CS OFF\nG00 X1 Y1\nM30\n")
    assert [e[:2] for e in ends(prog)] == [(1, 0), (11, 0), (11, 6), (11, 1), (1, 1)]


def test_external_variable_unset_names_the_setup_key():
    e = fails("%P\nP1 = V.E.FEED_OVR\nM30\n")
    assert (e.line, e.col) == (2, 6)
    assert 'V.E.FEED_OVR' in e.message and '[variables] "V.E.FEED_OVR"' in e.message


def test_machine_function_undeclared_names_the_setup_key():
    e = fails("%P\nM200=40\nM30\n")
    assert (e.line, e.col) == (2, 1) and "[machine] m_functions" in e.message
    assert ends(run("%P\nM200=40 G01 X3 F10\nM30\n", m_functions=frozenset({200}))) == [(3.0, 0.0, 50.0)]
    e = fails("%P\nH5\nM30\n")
    assert "[machine] h_functions" in e.message


def test_extra_axis_tracked_with_one_warning_and_undeclared_refused():
    prog = run("%P\nG01 A10 X1 F100\nA20\nB0\nM30\n", axes={"A": "rotary", "B": "rotary"})
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    assert sum("axis A" in m for _, m in prog.warnings) == 1
    assert not any("axis B" in m for _, m in prog.warnings)  # B0: it did not move
    e = fails("%P\nG01 C10 F100\nM30\n")
    assert (e.line, e.col) == (2, 5) and "[machine] axes" in e.message


def test_work_offset_without_setup_value_is_zero_with_a_warning():
    prog = run("%P\nG56 G00 X1\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    assert any("G56" in m and "[work_offsets]" in m for _, m in prog.warnings)


def test_g161_absolute_circle_centre():
    # from (10, 0) a half circle to (-10, 0) about the absolute centre (0, 0); with G54 (5, 5, 0)
    # the centre is machine (5, 5)
    prog = run("%P\nG54 G00 X10 Y0\nG161 G02 X-10 Y0 I0 J0 F100\nM30\n", work_offsets={"G54": (5.0, 5.0, 0.0)})
    arc = prog.moves[-1]
    assert arc.center[:2] == (5.0, 5.0) and arc.end[:2] == (-5.0, 5.0)


def test_for_loop_with_negative_step_and_variables():
    prog = run("%P\n#VAR\nV.P.I = 0\n#ENDVAR\n$FOR V.P.I = 3, 1, -1\nG01 X[V.P.I] F100\n$ENDFOR\nM30\n")
    assert [e[0] for e in ends(prog)] == [3, 2, 1]


def test_endless_loop_stops_at_max_blocks():
    e = fails("%P\n$WHILE 1\nG01 X1 F100\n$ENDWHILE\nM30\n", max_blocks=1000)
    assert "max_blocks" in e.message and "loop" in e.message


def test_string_macro_and_deferred_macro_from_a_called_file(tmp_path):
    (tmp_path / "defs.nc").write_text('"MOVE" = "G01 X7 F100"\nM29\n')
    prog = run('%P\nL defs.nc\n"MOVE"\nM30\n', name=str(tmp_path / "main.nc"))
    assert ends(prog) == [(7.0, 0.0, 50.0)]


def test_global_subprogram_from_the_setup_path(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "UP1.NC").write_text("G01 X[@P1] F100\nM17\n")
    prog = run("%P\nL up1 [@P1 = 4]\nM30\n", name=str(tmp_path / "main.nc"), subprogram_path=(str(subs),))
    assert ends(prog) == [(4.0, 0.0, 50.0)]
    assert prog.moves[0].src.program == str(subs / "UP1.NC") and prog.moves[0].src.calls == ((str(tmp_path / "main.nc"), 2),)


def test_implicit_subroutine_call_runs_its_file(tmp_path):
    # G805[x, y, z]: the machine maker's subprogram G805.nc gets the list as @P1, @P2, @P3
    (tmp_path / "G805.nc").write_text("G00 X[@P1] Y[@P2] Z[@P3]\nM17\n")
    prog = run("%P\nG805[1, 2, 3]\nM30\n", name=str(tmp_path / "main.nc"))
    assert ends(prog) == [(1.0, 2.0, 3.0)]
    e = fails("%P\nG803\nM30\n", name=str(tmp_path / "main.nc"))
    assert "implicit subroutine call" in e.message and "(G803)" in e.message
    # #FILE NAME [G80 = ..] names the file behind G80; "G80 [2]" with a space takes its list too
    (tmp_path / "weld.nc").write_text("G01 X[@P1] F100\nM17\n")
    prog = run('%P\n#FILE NAME [G80 = "weld.nc"]\nG80 [2]\nM30\n', name=str(tmp_path / "main.nc"))
    assert ends(prog) == [(2.0, 0.0, 50.0)]


def test_continued_block_and_main_ended_by_m29():
    prog = run("%SUB\nG01 X1 \\\n  Y2 F100\nM29\n")
    assert ends(prog) == [(1.0, 2.0, 50.0)]
    assert any("M29 ends a subprogram" in m for _, m in prog.warnings)


def test_label_with_colon_and_jump_backwards():
    prog = run("%P\nP1 = 0\nN10: P1 = P1 + 1\nG01 X[P1] F100\n$IF P1 < 3 $GOTO N10\nM30\n")
    assert [e[0] for e in ends(prog)] == [1, 2, 3]


def test_header_with_a_space_and_further_mains_warn(tmp_path):
    prog = run("% ai_poc_48\nG01 X1 F100\nM30\n%second\nG01 X9\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    assert any("'%second'" in m and "not run" in m for _, m in prog.warnings)


def test_lm06_style_call_of_a_global_file(tmp_path):
    # "LM06": L followed directly by the file name M06 (M06.nc beside the program)
    (tmp_path / "M06.nc").write_text("%M06\nG00 Z30\nM29\n")
    prog = run("%P\nT1 LM06\nG01 X1 F100\nM30\n", name=str(tmp_path / "main.nc"))
    assert ends(prog) == [(0.0, 0.0, 30.0), (1.0, 0.0, 30.0)]


def test_recursive_global_call_is_refused(tmp_path):
    (tmp_path / "a.nc").write_text("L b.nc\nM29\n")
    (tmp_path / "b.nc").write_text("L a.nc\nM29\n")
    e = fails("%P\nL a.nc\nM30\n", name=str(tmp_path / "main.nc"))
    assert "recursive subprogram call" in e.message and "a.nc -> b.nc -> a.nc" in e.message


def test_g80_alone_is_cycle_off_and_g81_is_an_implicit_call(tmp_path):
    prog = run("%P\nG71 G80 G90\nG01 X1 F100\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0)] and any("G80" in m for _, m in prog.warnings)
    # G81..G89 are implicit calls like G800 (manual: called once, "no modal effect"): without a file, exit 2
    e = fails("%P\nG81 Z-5\nM30\n")
    assert (e.line, e.col) == (2, 1) and "implicit subroutine call" in e.message
    assert "external_subprograms" in e.message
    # with its file beside the program it runs once, at the end of its block, with its argument list
    (tmp_path / "G81.nc").write_text("G91 G01 Z[-@P1] F100\nZ[@P1]\nG90\nM17\n")
    prog = run("%P\nG00 X10 Y5 Z2\nG81[4]\nX20\nM30\n", name=str(tmp_path / "main.nc"))
    assert ends(prog) == [(10.0, 5.0, 2.0), (10.0, 5.0, -2.0), (10.0, 5.0, 2.0), (20.0, 5.0, 2.0)]
    # a G80.nc on the search path makes G80 a call too
    (tmp_path / "G80.nc").write_text("G00 Z30\nM17\n")
    prog = run("%P\nG80\nM30\n", name=str(tmp_path / "main.nc"))
    assert ends(prog) == [(0.0, 0.0, 30.0)]


EXTERNAL_MSG = "is declared external in the setup ([machine] external_subprograms)"


def test_external_subprograms_are_accepted_without_motion(tmp_path):
    # the setup declares what the machine has: a controller path, a cycle without .nc, an implicit G code,
    # a local name; each call keeps the tool where it was, with one warning per name
    ext = frozenset({"0_INICIO_PROG.NC", "SPIGOT.ECY", "G803", "VENDOR"})
    text = ("%P\nG00 X5 Y6 Z7\nL C:\\Users\\Public\\Subprg\\0_Inicio_Prog.nc\nL 0_inicio_prog\n"
            "L CYCLE [NAME = Spigot.nc @P1 = 2 @P2 = V.L.X]\nG803\nLL VENDOR\nG01 X8 F100\nM30\n")
    e = fails(text, name=str(tmp_path / "main.nc"), external_subprograms=ext)
    assert "V.L.X" in e.message and e.line == 5  # the call's parameters are still evaluated
    text = text.replace(" @P2 = V.L.X", "")
    prog = run(text, name=str(tmp_path / "main.nc"), external_subprograms=ext)
    assert ends(prog) == [(5.0, 6.0, 7.0), (8.0, 6.0, 7.0)]
    msgs = [(src.line, m) for src, m in prog.warnings if EXTERNAL_MSG in m]
    assert [line for line, _ in msgs] == [3, 5, 6, 7]
    assert msgs[0][1].startswith("0_Inicio_Prog.nc is declared external") and "stay where it was" in msgs[0][1]


def test_external_declaration_only_covers_missing_files(tmp_path):
    (tmp_path / "G803.nc").write_text("G00 Z40\nM17\n")
    (tmp_path / "sub.nc").write_text("G01 X3 F100\nM17\n")
    prog = run("%P\nG803\nL sub.nc\nM30\n", name=str(tmp_path / "main.nc"),
               external_subprograms=frozenset({"G803", "SUB.NC"}))
    assert ends(prog) == [(0.0, 0.0, 40.0), (3.0, 0.0, 40.0)]
    assert not [m for _, m in prog.warnings if EXTERNAL_MSG in m]


def test_undeclared_missing_file_names_the_setup_key(tmp_path):
    e = fails("%P\nL C:\\cnc\\other.nc\nM30\n", name=str(tmp_path / "main.nc"),
              external_subprograms=frozenset({"SUB.NC"}))
    assert (e.line, e.col) == (2, 3) and "[machine] external_subprograms = [\"other.nc\"]" in e.message


def test_dwell_forms_do_not_move_or_change_the_spindle():
    # the manual's G04 forms: first main axis, a bare time, a parameter, revolutions of the spindle
    prog = run("%P\nM3 S200\nG04 X4.5\nG04 3.0\nP1 = 2\nG04 P1\nG04 S10\n#TIME 2\nG01 X1 F100\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    assert [r.speed for r in prog.records if isinstance(r, canon.Spindle)] == [200.0]


def test_conditional_interpretation():
    prog = run("%P\n#IF V.E.START_VALUE == TRUE\nG01 X1 F100\n#ELSE\nG01 X2 F40\n#ENDIF\nM30\n",
               variables={"V.E.START_VALUE": 0.0})
    assert ends(prog) == [(2.0, 0.0, 50.0)]


@pytest.mark.parametrize("code", ["G5.4", "G9.1", "G80.5", "G805.2"])
def test_fractional_g_code_is_unknown(code):
    e = fails(f"%P\n{code}\nM30\n")
    assert (e.line, e.col) == (2, 1) and f"unknown G code {code}" in e.message


def test_error_command_stops_and_fgroup_passes():
    e = fails('%P\n#FGROUP [X, Y, Z]\n$IF 1 == 1\n#ERROR [ID=1 RC=2]\n$ENDIF\nM30\n')
    assert (e.line, e.col) == (4, 1) and "#ERROR" in e.message


def test_distance_control_off_passes_on_is_refused():
    # the manual's deselect forms: <axis>[DIST_CTRL [WAIT] OFF [NO_MOVE]] and FREEZE move nothing here
    prog = run("%P\nG01 X1 F100\nZ[DIST_CTRL OFF NO_MOVE] ; off\nZ[DIST_CTRL WAIT FREEZE]\nG01 X2\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0), (2.0, 0.0, 50.0)]
    assert sum("DIST_CTRL" in m for _, m in prog.warnings) == 1
    e = fails("%P\nG01 X1 F100\nZ[DIST_CTRL DRYRUN CONST_DIST SET_DIST=[2*0.5]]\nM30\n")
    assert (e.line, e.col) == (3, 1) and "DRYRUN" in e.message


# -- rotation and mirroring ------------------------------------------------------------------------------
SQUARE = "G01 X0 Y0 F100\nX20\nY20\nX0\nY0\n"


def feeds(prog) -> list:
    return [(tuple(round(v, 9) for v in m.start), tuple(round(v, 9) for v in m.end)) for m in prog.moves]


def test_mirrored_compensation_swaps_the_side():
    # manual: under G41 the path after mirroring is computed right of the (mirrored) contour: G21 + G41
    # round the square is the hand-mirrored square (x -> -x) with G42
    mirrored = run("%P\nG21\nG00 X10 Y-10 Z-1\nG41\n" + SQUARE + "G40 G00 X10 Y-10\nM30\n", tool_radii={1: 2.0})
    by_hand = run("%P\nG00 X-10 Y-10 Z-1\nG42\n" + SQUARE.replace("X20", "X-20") +
                  "G40 G00 X-10 Y-10\nM30\n", tool_radii={1: 2.0})
    assert feeds(mirrored) == feeds(by_hand)
    # the program's square runs counter-clockwise with G41: the tool is inside it, 2 from each side; the
    # mirrored square's inside corners (-18, 2), (-18, 18), (-2, 18) (the fourth is left by the departure)
    corners = {m[1][:2] for m in feeds(mirrored)}
    assert {(-18.0, 2.0), (-18.0, 18.0), (-2.0, 18.0)} <= corners


def test_rotated_compensation_is_the_rotated_path():
    rotated = run("%P\n#ROTATION ON [ANGLE=90]\nG00 X-10 Y-10 Z-1\nG41\n" + SQUARE + "G40 G00 X-10 Y-10\nM30\n",
                  tool_radii={1: 2.0})
    plain = run("%P\nG00 X-10 Y-10 Z-1\nG41\n" + SQUARE + "G40 G00 X-10 Y-10\nM30\n", tool_radii={1: 2.0})
    # a quarter turn: (x, y) -> (-y, x), exactly
    assert feeds(rotated) == [((-a[1], a[0], a[2]), (-b[1], b[0], b[2])) for a, b in feeds(plain)]


def test_plane_change_deselects_the_contour_rotation():
    prog = run("%P\n#ROTATION ON [ANGLE=90]\nG01 X10 F100\nG18 X20\nM30\n")
    # X10 turned a quarter: (0, 10); after G18 the rotation is off: X20, Y stays where the tool is
    assert feeds(prog)[0][1] == (0.0, 10.0, 50.0) and feeds(prog)[-1][1] == (20.0, 10.0, 50.0)
    assert any("deselects the contour rotation" in m for _, m in prog.warnings)


def test_g161_centre_in_rotated_coordinates():
    # G161: I/J are the absolute centre (program frame); #CS turned 90 degrees at (0, 0): (x, y) -> (-y, x)
    prog = run("%P\n#CS ON [0, 0, 0, 0, 0, 90]\nG01 X10 Y0 F100\nG161 G03 X0 Y10 I0 J0\nM30\n")
    arc = prog.moves[-1]
    assert (arc.start, arc.end, arc.center, arc.clockwise) == ((0.0, 10.0, 50.0), (-10.0, 0.0, 50.0),
                                                               (0.0, 0.0, 50.0), False)


@pytest.mark.parametrize("text, line, col, what", [
    ("#CS ON [0, 0, 0, 0, 0, 30]\nG18\nG02 X10 Z0 I5 K0", 4, 1, "tilted plane"),
    ("G41\nG01 X10 Y0 F100\nG21\nX20", 4, 1, "rotation or mirroring changed while tool radius compensation"),
    ("#ROTATION ON [ANGLE=10]\nG33 Z-10 K1", 3, 1, "G33 in rotated or mirrored coordinates"),
])
def test_rotation_limits_are_exit_2(text, line, col, what):
    e = fails(f"%P\n{text}\nM30\n", tool_radii={1: 2.0})
    assert (e.line, e.col) == (line, col) and what in e.message, str(e)


def test_rotation_on_a_lathe_is_exit_2():
    e = fails("%P\nG21\nM30\n", machine_kind="lathe")
    assert (e.line, e.col) == (2, 1) and "on a lathe" in e.message


def test_g68_rotates_about_its_centre_and_g69_ends_it():
    # G68 R90 about (10, 0): X20 Y0 is (10, 0) from the centre, a quarter turn (0, 10): (10, 10); a
    # centre axis not programmed is where the tool is (X5 -> centre (5, 2) for the second rotation)
    prog = run("%P\nG68 R90 X10 Y0\nG01 X20 Y0 F100\nG69\nX30\nG00 X5 Y2\nG68 R180 Y2\nG01 X6 Y2\nM30\n")
    assert feeds(prog) == [((0.0, 0.0, 50.0), (10.0, 10.0, 50.0)), ((10.0, 10.0, 50.0), (30.0, 10.0, 50.0)),
                           ((30.0, 10.0, 50.0), (5.0, 2.0, 50.0)), ((5.0, 2.0, 50.0), (4.0, 2.0, 50.0))]


def test_local_cycle_call_and_modal_local_cycle():
    # LL CYCLE [NAME = DOWN @P1 = 2]: the local subprogram with its own @P1; its G91 G01 end with it
    sub = "%L DOWN\nG91 G01 Z[-@P1] F100\nZ[@P1]\nM17\n"
    prog = run(sub + "%P\nG00 X1 Z5\nLL CYCLE [NAME = DOWN @P1 = 2]\nX3\n"
               "LL CYCLE [NAME = DOWN MODAL_MOVE @P1 = 1]\nX4\n#DISABLE MODAL CYCLE\nX5\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 5.0), (1.0, 0.0, 3.0), (1.0, 0.0, 5.0), (3.0, 0.0, 5.0),
                          (3.0, 0.0, 4.0), (3.0, 0.0, 5.0), (4.0, 0.0, 5.0), (4.0, 0.0, 4.0), (4.0, 0.0, 5.0),
                          (5.0, 0.0, 5.0)]
    assert [type(m).__name__ for m in prog.moves][3] == "Rapid"


# -- forms of real programs (issue 16 corpus): titles, #VAR where it stands, external macros, NP ------
def test_header_text_after_the_name_is_a_title_with_one_warning():
    prog = run("% 1x10 dots right 24 well plate\nG01 X1 F100\nM30\n")
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    assert [m for _, m in prog.warnings if "title" in m] == [
        "the text after the program name '%1x10' ('dots right 24 well plate') is taken as the program's title "
        "(write a title in parentheses)"]


def test_local_subprogram_header_with_text_is_still_an_error():
    e = fails("%L SUB extra\nM29\n%P\nM30\n")
    assert (e.line, e.col) == (1, 8) and "unexpected text after the program name" in e.message


def test_var_block_runs_where_it_stands():
    text = ("%P\nG01 X1 F100\n#VAR\nV.P.A = 2\nV.L.B[2] = [3, 4]\n#ENDVAR\nXV.P.A YV.L.B[1]\nV.P.A = 7\n"
            "#VAR\nV.P.A = 5\n#ENDVAR\nXV.P.A\nM30\n")
    # the second #VAR sets V.P.A back to 5 although the program wrote 7 between them
    assert ends(run(text)) == [(1.0, 0.0, 50.0), (2.0, 4.0, 50.0), (5.0, 4.0, 50.0)]


def test_var_at_level_start_is_known_before_a_later_redeclaration():
    # the level knows each name from its start with its first declaration's value
    text = "%P\n#VAR\nV.P.A = 1\n#ENDVAR\nXV.P.A F100\n#VAR\nV.P.A = 3\n#ENDVAR\nXV.P.A\nM30\n"
    assert ends(run(text)) == [(1.0, 0.0, 50.0), (3.0, 0.0, 50.0)]


def test_macro_declared_external_passes_with_one_warning():
    text = '%P\n"ARC_ON"\nG01 X1 F100\n"Arc_On"\nM30\n'
    prog = run(text, external_subprograms=frozenset({"ARC_ON"}))
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    msgs = [m for _, m in prog.warnings if "macro" in m]
    # one warning per declared name (the setup's names compare without case)
    assert len(msgs) == 1 and "its effect is not simulated" in msgs[0]


def test_macro_not_declared_names_the_setup_key():
    e = fails('%P\nG01 X1 F100\n  "ARC_ON"\nM30\n', external_subprograms=frozenset({"OTHER"}))
    assert (e.line, e.col) == (3, 3) and "[machine] external_subprograms = [\"ARC_ON\"]" in e.message


def test_a_defined_macro_is_expanded_even_when_declared_external():
    text = '"ARC_ON" = "G01 X5 F100"\n%P\n"ARC_ON"\nM30\n'
    prog = run(text, external_subprograms=frozenset({"ARC_ON"}))
    assert ends(prog) == [(5.0, 0.0, 50.0)] and not [m for _, m in prog.warnings if "macro" in m]


def test_zero_offset_table_variables():
    text = ("%P\nV.G.NP[3].V.Z = -2\nG56 G01 X0 Z0 F100\nV.G.NP[3].V.X = 5\nX0\nG56 X0\n"
            "X[V.G.NP_AKT.V.X + V.G.NP[3].V.Z]\nM30\n")
    # G56 is V.G.NP[3]; a table write acts from the next selection (N5 X0 stays at 0, N6 G56 X0 at 5)
    prog = run(text, work_offsets={"G56": (1.0, 1.0, 1.0)})
    assert ends(prog) == [(1.0, 0.0, -2.0), (1.0, 0.0, -2.0), (5.0, 0.0, -2.0), (8.0, 0.0, -2.0)]


@pytest.mark.parametrize("text, col, what", [
    ("V.G.NP[7].V.X = 1", 1, "V.G.NP[1] (G54) .. V.G.NP[6] (G59)"),
    ("V.G.NP[1].V.X = \"A\"", 1, "a zero offset is a number"),
    ("X[V.G.NP[0].V.Y]", 3, "V.G.NP[1] (G54) .. V.G.NP[6] (G59)"),
])
def test_zero_offset_variable_errors(text, col, what):
    e = fails(f"%P\n{text}\nM30\n")
    assert (e.line, e.col) == (2, col) and what in e.message, str(e)


def test_undefined_macro_after_a_skipped_external_subprogram_is_taken_to_be_its():
    text = '%P\nG01 X1 F100\nL C:\\vendor\\start.nc\n"ARC_ON"\nX2\n"ARC_ON"\nM30\n'
    prog = run(text, external_subprograms=frozenset({"START.NC"}))
    assert ends(prog) == [(1.0, 0.0, 50.0), (2.0, 0.0, 50.0)]
    msgs = [m for _, m in prog.warnings if "macro" in m]
    assert msgs == ['macro "ARC_ON" is defined by no file: taken to be defined by the external start.nc (declared in '
                    '[machine] external_subprograms and not simulated); its effect is not simulated (it is taken to '
                    'move nothing)']


def test_undefined_macro_before_the_external_call_is_still_an_error():
    e = fails('%P\n"ARC_ON"\nL start.nc\nM30\n', external_subprograms=frozenset({"START.NC"}))
    assert (e.line, e.col) == (2, 1) and 'macro "ARC_ON" is not defined' in e.message


def test_vp_declared_in_a_local_subprogram_is_program_global():
    # manual: user variables are created in the main program or a subprogram; V.P. ones are global
    text = "%L SUB\n#VAR\nV.P.G = 5\n#ENDVAR\nG01 YV.P.G F100\nM29\n%P\nLL SUB\nXV.P.G\nM30\n"
    assert ends(run(text)) == [(0.0, 5.0, 50.0), (5.0, 5.0, 50.0)]


def test_vp_written_after_a_skipped_external_is_taken_to_be_declared_by_it():
    text = "%P\nL steuer.up\nV.P.LEN = 20\nG01 XV.P.LEN F100\nM30\n"
    prog = run(text, external_subprograms=frozenset({"STEUER.UP"}))
    assert ends(prog) == [(20.0, 0.0, 50.0)]
    assert any("V.P.LEN is declared by no #VAR: taken to be declared by the external steuer.up" in m
               for _, m in prog.warnings)


@pytest.mark.parametrize("text, what", [
    ("V.P.LEN = 20", "V.P.LEN is not declared"),  # no external subprogram skipped before it
    ("L steuer.up\nV.P.ARR[2] = 1", "V.P.ARR[2] is not declared"),  # an array's size is unknown
    ("L steuer.up\nG01 XV.P.LEN F100", "V.P.LEN is not declared"),  # read before any write
])
def test_vp_undeclared_stays_an_error(text, what):
    e = fails(f"%P\n{text}\nM30\n", external_subprograms=frozenset({"STEUER.UP"}))
    assert what in e.message, str(e)


def test_group_weighting_value_after_a_blank():
    # the manual's HSC examples write "N10 G131 50" / "N20 G133 50" (also G131=50)
    prog = run("%P\nN10 G131 50\nN20 G133 [V.E.W * 2]\nG134 150 G01 X1 F100\nM30\n", variables={"V.E.W": 40.0})
    assert ends(prog) == [(1.0, 0.0, 50.0)]
    assert sum("G131" in m for _, m in prog.warnings) == 1


def test_group_weighting_value_is_evaluated():
    e = fails("%P\nG131 [1/0]\nM30\n")
    assert e.line == 2 and "division by zero" in e.message, str(e)


def test_delete_removes_user_variables():
    # the timber CAM program: #DELETE V.P.FEEDPAR, then a #VAR declares it again with new values
    text = ("%P\n#VAR\nV.P.F[2] = [1, 2]\nV.L.A = 5\n#ENDVAR\nG01 XV.P.F[1] F100\n#DELETE V.P.F, V.L.A\n"
            "#VAR\nV.P.F[2] = [3, 4]\n#ENDVAR\nXV.P.F[1]\nM30\n")
    assert ends(run(text)) == [(2.0, 0.0, 50.0), (4.0, 0.0, 50.0)]


@pytest.mark.parametrize("text, line, what", [
    ("#VAR\nV.P.F = 1\n#ENDVAR\nG01 X1 F100\n#DELETE V.P.F\nXV.P.F", 7, "V.P.F is not declared"),
    ("#DELETE V.P.G", 2, "#DELETE V.P.G: the variable does not exist"),
    ("#DELETE V.E.SPEED", 2, "only user variables V.P., V.L. and V.S. can be deleted"),
])
def test_delete_errors(text, line, what):
    e = fails(f"%P\n{text}\nM30\n")
    assert e.line == line and what in e.message, str(e)


def test_cycle_parameter_valid():
    # manual (error ID 21544): V.G.@P[i].VALID tells a cycle whether its call programmed @Pi
    text = ("%L CYC\n$IF V.G.@P[1].VALID\nG01 X@P1 F100\n$ENDIF\n$IF V.G.@P[1+1].VALID == 0\nG01 Y9\n$ENDIF\nM29\n"
            "%P\nLL CYCLE [NAME = CYC @P1 = 4]\nM30\n")
    assert ends(run(text)) == [(4.0, 0.0, 50.0), (4.0, 9.0, 50.0)]


@pytest.mark.parametrize("text, what", [
    ("$IF V.G.@P[1].VALID\n$ENDIF", "read outside a cycle (the controller's error 21544"),
    ("%L SUB\nX[V.G.@P[1].VALID]\nM29\n%Q\nLL SUB", "read outside a cycle"),  # LL name is no cycle
    ("%L CYC\nV.G.@P[1].VALID = 1\nM29\n%Q\nLL CYCLE [NAME = CYC @P1 = 1]", "is read-only"),
])
def test_cycle_parameter_valid_errors(text, what):
    e = fails(text if text.startswith("%") else f"%P\n{text}\nM30\n")
    assert what in e.message, str(e)


def test_active_tool_radius_is_read_from_the_setup_tool():
    # V.G.WZ_AKT.R: the radius G41/G42 use (the active [[tool]]'s diameter / 2, 0 after D0), or what the
    # program wrote; a tool the setup does not have falls back to [variables]
    text = "%P\nG01 X[V.G.WZ_AKT.R] F100\nT2\nX[V.G.WZ_AKT.R]\nD0\nX[V.G.WZ_AKT.R + 1]\nV.G.WZ_AKT.R = 7\nXV.G.WZ_AKT.R\nM30\n"
    prog = run(text, tool_radii={1: 3.0, 2: 5.0})
    assert ends(prog) == [(3.0, 0.0, 50.0), (5.0, 0.0, 50.0), (1.0, 0.0, 50.0), (7.0, 0.0, 50.0)]
    assert ends(run("%P\nT9\nG01 X[V.G.WZ_AKT.R] F100\nM30\n", tool_radii={1: 3.0},
                    variables={"V.G.WZ_AKT.R": 4.0})) == [(4.0, 0.0, 50.0)]


def test_active_tool_radius_given_in_the_setup_wins_with_a_warning_when_it_differs():
    prog = run("%P\nG01 X[V.G.WZ_AKT.R] F100\nX[V.G.WZ_AKT.R * 2]\nM30\n", tool_radii={1: 3.0},
               variables={"V.G.WZ_AKT.R": 4.0})
    assert ends(prog) == [(4.0, 0.0, 50.0), (8.0, 0.0, 50.0)]
    assert sum("the active tool (T1) has the radius 3" in m for _, m in prog.warnings) == 1
    same = run("%P\nG01 X[V.G.WZ_AKT.R] F100\nM30\n", tool_radii={1: 3.0}, variables={"V.G.WZ_AKT.R": 3.0})
    assert not [m for _, m in same.warnings if "WZ_AKT" in m]
