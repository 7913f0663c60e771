"""The Sinumerik 840D language as machinists write it (issue 12): procedures, structured control
flow, jumps, typed variables, system variables and the setup's [variables], and the commands that
only warn. Numbers are worked out by hand from the programs.

Golden transcripts (``cutsim moves``) in tests/data/golden/sinumerik/lang/, regenerated with
CUTSIM_UPDATE_GOLDEN=1 and checked by hand:

- procs.mpf: RING(20) from (50, 50) runs four CCW quarter arcs of CR 20 (N takes its default 4):
  the K-th ends at the start plus 20·(cos 90K - cos 90(K-1), sin 90K - sin 90(K-1)), so
  (30, 70), (10, 50), (30, 30), (50, 50), all about (30, 50). RING is SAVE and wrote G91, yet N40
  X70 is absolute. DEEPER(ZZ, 2) changes ZZ through VAR: -1 - 2 = -3, so N60 goes to Z-3.
  L140(3) (from the setup's subprogram_path) steps Y to $AA_IW[Z] - 5·PASSES = 35, 40, 45 until
  PASSES is 0. RING(10, 2) turns two quarters of radius 10 from (70, 45): (60, 55) and (50, 45)
  about (60, 45). EDGE (a PROC of the same file) goes to (0, 0) and returns at its M2.
- control.mpf: IF true -> X10; WHILE NN<3 -> Y 5, 10, 15; FOR II=1 TO 2 -> X 20, 30; LOOP runs
  Z-1 once and leaves by GOTOF at XX=2; CASE NN (3) OF ... 3 GOTOF THREE -> X40; GOTOF 250 skips
  N240; the first MARK gives Y20; GOTOF N280 skips the second MARK; N280 (the third MARK) counts
  NN to 4 -> X44, and GOTOB MARK goes to the nearest MARK back, N280 (not the first one in the
  file), NN 5 -> X45; GOTOC to a missing label goes on without an alarm.
- variables.mpf: PTS[2,*] = (50, 60); AX[AXN] with AXIS AXN=Y moves Y to PTS[0,1] = 20;
  AX[X] = $A_DBB[5]·10 = 30 ([variables] "$A_DBB[5]" = 3); Z=$AA_IW[Z]/10 = 5; DEPTH_GUD 2.5 from
  the setup, doubled to 5 and kept; $A_DBB[5]=7 written and read back; BOOL DONE=5 is 1 -> Y11;
  ROUNDED = 7 MOD 4 = 3 and 7 DIV 2 = 3 -> X9; INT ROUNDED=2.5 rounds to 3, so NAME is
  "HOLE_3" and the jump to WRONG is not taken; G4 F1.5 dwells without a move; the file ends
  with a Ctrl-Z byte.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim import CutsimError
from cutsim.cli import main
from cutsim.interp import InterpConfig, canon, interpret

GOLDEN = Path(__file__).resolve().parents[2] / "data" / "golden" / "sinumerik" / "lang"
PROGRAMS = ["procs", "control", "variables"]


def run(text, name="t.mpf", variables=None, subprogram_path=(), max_blocks=5_000_000):
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: 5.0},
                       variables=variables or {}, subprogram_path=tuple(subprogram_path), max_blocks=max_blocks)
    return interpret(name, text, cfg)


def ends(prog):
    return [tuple(round(v, 6) for v in r.end) for r in prog.moves]


def error_of(text, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, **kw)
    return e.value


@pytest.mark.parametrize("name", PROGRAMS)
def test_golden_transcript(name):
    prog = GOLDEN / f"{name}.mpf"
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(GOLDEN / "setup.toml")])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / f"{name}.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


# -- procedures -----------------------------------------------------------------------------------
def test_a_spf_that_is_its_proc_runs_the_body(tmp_path):
    """The false accept of issue 12: PROC SUBA / G1 X10 / M17 in SUBA.spf ran as an empty body."""
    (tmp_path / "SUBA.spf").write_text("PROC SUBA\nG1 X10 F100\nM17\n")
    p = run("G0 X0 Y0 Z0\nSUBA\nG1 Y5\nM30\n", name=str(tmp_path / "main.mpf"))
    assert ends(p) == [(0, 0, 0), (10, 0, 0), (10, 5, 0)]
    assert p.moves[1].src.program.endswith("SUBA.spf") and p.moves[1].src.line == 2


def test_a_program_that_starts_with_proc_runs_it():
    p = run("PROC MAIN\nG0 X1 Y2 Z3\nM30\n")
    assert ends(p) == [(1, 2, 3)]


def test_default_empty_and_omitted_arguments():
    """PROC P(REAL A, REAL B=7, REAL C): P(1,,3) gives B its default 7; P(1) leaves C 0."""
    text = "P(1,,3)\nP(1)\nM30\nPROC P(REAL A, REAL B=7, REAL C)\nG1 X=A Y=B Z=C F100\nRET\n"
    assert ends(run(text)) == [(1, 7, 3), (1, 7, 0)]


def test_var_parameters_share_r_parameters_array_elements_and_variables():
    text = """DEF REAL ARR[2], VV=1
R5=10
INC(R5)
INC(ARR[1])
INC(VV)
G1 X=R5 Y=ARR[1] Z=VV F100
M30
PROC INC(VAR REAL V)
V=V+2.5
RET
"""
    assert ends(run(text)) == [(12.5, 2.5, 3.5)]


def test_locals_of_a_procedure_do_not_leak():
    e = error_of("SETX\nG1 X=LOC F100\nM30\nPROC SETX\nDEF REAL LOC=4\nRET\n")
    assert (e.line, e.col) == (2, 6) and "unknown variable 'LOC'" in e.message


def test_save_restores_the_modal_state_and_plain_procs_do_not():
    text = "G90 G17 F100\nKEEP\nG1 X10\nLOSE\nG1 X10\nM30\nPROC KEEP SAVE\nG91 G18 F50\nRET\nPROC LOSE\nG91\nRET\n"
    p = run(text)
    assert ends(p)[-1] == (20, 0, 50)  # after P2 (no SAVE) G91 stays: X10 is incremental
    assert ends(p)[0] == (10, 0, 50)  # KEEP's G91 and G18 are gone: G90, and the XY move is a line
    assert p.moves[0].feed == 50  # SAVE brings back the G functions, not F


def test_l_programs_with_parameters_and_repetitions(tmp_path):
    (tmp_path / "L7.spf").write_text("PROC L7(REAL STEP)\nG91 G1 X=STEP F100\nG90\nM17\n")
    p = run("L7(3)\nL7 P2\nM30\n", name=str(tmp_path / "m.mpf"))
    assert ends(p) == [(3, 0, 50), (3, 0, 50), (3, 0, 50)]  # L7 without its parameter: STEP 0


def test_subprogram_path_is_searched_after_the_program_folder(tmp_path):
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "HOLE.SPF").write_text("PROC HOLE(REAL DEPTH)\nG1 Z=-DEPTH F100\nRET\n")
    p = run("HOLE(4)\nM30\n", name=str(tmp_path / "m.mpf"), subprogram_path=[str(tmp_path / "lib")])
    assert ends(p) == [(0, 0, -4)]


def test_keywords_are_never_file_names(tmp_path):
    """STOPRE, TRANS and cycle names beside the program as files are not called."""
    for kw in ("STOPRE", "TRANS", "MSG"):
        (tmp_path / f"{kw.lower()}.mpf").write_text("G0 X99 Y99 Z99\nM17\n")
    p = run("G0 X1 Y1 Z1\nSTOPRE\nTRANS\nMSG(\"hi\")\nG0 X2\nM30\n", name=str(tmp_path / "m.mpf"))
    assert ends(p) == [(1, 1, 1), (2, 1, 1)]


def test_extern_declarations_are_accepted(tmp_path):
    (tmp_path / "CUT.spf").write_text("PROC CUT(REAL XX, VAR REAL YY)\nG1 X=XX F100\nYY=5\nRET\n")
    p = run("EXTERN CUT(REAL, VAR REAL)\nDEF REAL OUT\nCUT(4, OUT)\nG1 Y=OUT\nM30\n", name=str(tmp_path / "m.mpf"))
    assert ends(p) == [(4, 0, 50), (4, 5, 50)]


# -- control flow ---------------------------------------------------------------------------------
def test_goto_searches_forward_then_backward_and_gotof_gotob_their_way():
    text = """R1=0
HERE: R1=R1+1
G1 X=R1 F100
IF R1==1 GOTO HERE
IF R1==2 GOTOF HERE
M30
HERE: G1 Y7
M30
"""
    # R1=1: GOTO HERE finds the HERE after it first (line 7) -> Y7 and the end
    assert ends(run(text)) == [(1, 0, 50), (1, 7, 50)]


def test_gotof_to_a_block_number_and_gotoc_to_nothing():
    p = run("GOTOF 30\nN20 G1 X9 F100\nN30 G1 X1 F100\nGOTOC NOWHERE\nGOTOF N50\nN40 X9\nN50 X2\nM30\n")
    assert ends(p) == [(1, 0, 50), (2, 0, 50)]


def test_nested_structures_and_repeat_until():
    text = """DEF INT AA, BB
FOR AA=1 TO 3
  BB=0
  REPEAT
    BB=BB+1
    IF AA==2
      G1 X=AA*10+BB F100
    ENDIF
  UNTIL BB>=2
ENDFOR
G1 Y=AA
M30
"""
    assert ends(run(text)) == [(21, 0, 50), (22, 0, 50), (22, 4, 50)]  # FOR leaves AA at 4


def test_a_for_loop_whose_end_is_below_its_start_does_not_run():
    assert ends(run("DEF INT II\nFOR II=5 TO 1\nG1 X=II F100\nENDFOR\nG1 Y=II F100\nM30\n")) == [(0, 5, 50)]


def test_case_with_strings_and_default():
    text = 'DEF STRING[8] KIND="B"\nCASE KIND OF "A" GOTOF LA "B" GOTOF LB DEFAULT GOTOF LC\nLA: X1\nLB: G1 X2 F100\nLC: Y3\nM30\n'
    assert ends(run(text)) == [(2, 0, 50), (2, 3, 50)]
    assert ends(run(text.replace('"B"\n', '"Q"\n'))) == [(0, 3, 50)]


def test_an_endless_loop_is_found_without_the_block_limit():
    e = error_of("LOOP\nG1 X1 F100\nENDLOOP\n")
    assert e.line == 3 and "does not end" in e.message


def test_nested_repeat_is_counted_before_it_runs():
    """Eight nested REPEAT ... P=9999 would run about 10^32 blocks. The second REPEAT (line 3) would
    run 9 999 passes of AA plus the first REPEAT's 9 999 repeats of AA: 9 999 · 10 001 = 99 999 999
    blocks, more than max_blocks: refused there before it runs (the old executor ran until
    max_blocks, in time exponential in the nesting)."""
    lines = ["AA: G1 X1 F100"] + [f"L{k}{k}: REPEAT AA P=9999" for k in range(1, 9)] + ["M30"]
    e = error_of("\n".join(lines) + "\n")
    assert e.line == 3 and "would run about 99,999,999 blocks" in e.message


# -- expressions and variables ---------------------------------------------------------------------
@pytest.mark.parametrize("expr, value", [
    ("2+3*4==14", 1),  # comparisons bind weakest
    ("1 OR 0 AND 0", 1),  # AND before OR
    ("NOT 0 AND 1", 1),  # NOT first
    ("1 XOR 1 OR 1", 1),  # XOR before OR
    ("7 DIV 2 + 7 MOD 4", 6),
    ("-7 DIV 2", -3),  # DIV truncates towards 0
    ("5 B_AND 3 + 1", 4),  # + before B_AND: 5 & 4
    ("12 B_OR 3 B_XOR 1", 14),  # B_XOR before B_OR: 12 | 2
    ("10EX-1*30", 30),  # the manuals' exponent
])
def test_operator_priorities_of_the_manual(expr, value):
    assert ends(run(f"R1={expr}\nG1 X=R1 F100\nM30\n")) == [(value, 0, 50)]


def test_string_concatenation_and_comparison():
    text = 'DEF STRING[20] SS\nSS="R" << 1+2 << "_" << 0.5\nIF SS=="R3_0.5" GOTOF OK\nM30\nOK: G1 X1 F100\nM30\n'
    assert ends(run(text)) == [(1, 0, 50)]


def test_int_variables_round_and_bool_is_0_or_1():
    p = run("DEF INT II=2.5, JJ=-2.5, KK=2.4\nDEF BOOL BB=-3\nG1 X=II Y=JJ Z=KK+BB F100\nM30\n")
    assert ends(p) == [(3, -3, 3)]


def test_two_dimensional_arrays_are_row_by_row():
    p = run("DEF REAL MM[2,3]=SET(1,2,3,4,5,6)\nG1 X=MM[1,0] Y=MM[0,2] Z=MM[1,2] F100\nM30\n")
    assert ends(p) == [(4, 3, 6)]


def test_system_variables_come_from_the_setup_and_writes_are_kept():
    p = run("R1=$P_TOOLNO+$A_DBB[R2+5]\n$A_DBB[5]=R1*2\nG1 X=R1 Y=$A_DBB[5] F100\nM30\n",
            variables={"$P_TOOLNO": 3, "$A_DBB[5]": 1})
    assert ends(p) == [(4, 8, 50)]


def test_an_unset_system_variable_names_the_setup_key():
    e = error_of("G1 X=$AA_IW[X] F100\n")
    assert (e.line, e.col) == (1, 6)
    assert e.message.startswith("$AA_IW[X] is not known") and '[variables] "$AA_IW[X]"' in e.message


def test_global_user_data_from_the_setup():
    p = run("G1 X=RADIUS_GUD F100\nRADIUS_GUD=RADIUS_GUD+1\nG1 Y=RADIUS_GUD\nM30\n", variables={"RADIUS_GUD": 6})
    assert ends(p) == [(6, 0, 50), (6, 7, 50)]


def test_dwell_does_not_move_or_change_the_feed():
    p = run("G1 X1 F100\nG4 F2\nG4 S10\nG1 X2\nM30\n")
    assert ends(p) == [(1, 0, 50), (2, 0, 50)] and p.moves[1].feed == 100


def test_dwell_needs_its_time():
    e = error_of("G4\n")
    assert (e.line, e.col) == (1, 1) and "G4 needs its dwell time" in e.message


# -- commands that only warn, file ends --------------------------------------------------------------
def test_one_warning_per_command_kind():
    text = ('MSG("a" << 1)\nMSG("b")\nSTOPRE\nSTOPRE\nWHENEVER $AA_IW[X]>1 DO M3\nID=2 WHEN $A_IN[1]==1 DO R1=2\n'
            'DISPLOF\nFGROUP(X, Y)\nG1 X1 F100\nM30\n')
    p = run(text)
    kinds = [m.split(" ")[0] for _, m in p.warnings]
    assert kinds == ["MSG", "STOPRE", "WHENEVER", "ID", "DISPLOF", "FGROUP"]
    assert '"a1"' in p.warnings[0][1]
    assert ends(p) == [(1, 0, 50)]


def test_setal_stops_the_program():
    e = error_of("SETAL(65000)\nG1 X1 F100\n")
    assert (e.line, e.col) == (1, 1) and "alarm" in e.message


def test_ctrl_z_nul_and_headers_at_the_file_ends():
    p = run("%_N_PART_MPF\n;$PATH=/_N_WKS_DIR/_N_P_WPD\nG1 X1 F100\nM30\n\x1a\x00\n\x1a")
    assert ends(p) == [(1, 0, 50)]


def test_proc_parameters_may_be_named_like_addresses():
    """PROC CONTOUR(REAL X, REAL Y), as in the manual: inside, a parameter named like an address is the
    parameter (B=B*2 assigns it)."""
    p = run("CTWO(3, 4)\nM30\nPROC CTWO(REAL B, REAL C)\nB=B*2\nG1 X=B Y=C F100\nRET\n")
    assert ends(p) == [(6, 4, 50)]
    assert isinstance(p.moves[0], canon.Feed)


def test_idioms_of_machine_builders():
    """Computed jumps (GOTOF "STEP_" << NR), datum writes with axis and keyword indices, H auxiliary
    functions, SPOS/LIMS settings (one warning each) and B=DC(..)-style absolute values."""
    text = """DEF INT NR=2
IF $P_SEARCH OR $P_SIM GOTOF START
START: $P_UIFR[1, X, TR]=-56.5
GOTOF "STEP_" << NR
STEP_1: G1 X1 F100
STEP_2: G1 X=$P_UIFR[1,X,TR]+60 F100
H20 H2=5 SPOS=90 SPOS[1]=IC(10) LIMS=3000
G1 X=DC(5) Y=ACP(2)
M30
"""
    p = run(text, variables={"$P_SEARCH": 0, "$P_SIM": 0})
    assert ends(p) == [(3.5, 0, 50), (5, 2, 50)]
    assert [m.split(" ")[0] for _, m in p.warnings] == ["H", "SPOS", "LIMS"]


def test_a_computed_destination_must_be_a_label():
    e = error_of('GOTOF "A B"\n')
    assert (e.line, e.col) == (1, 1) and "is no label" in e.message


def test_repeatb_call_gud_arrays_and_string_functions():
    """REPEATB LAB P=2 runs the LAB block twice more (X 3, 4, 5); CALL NM calls the PROC the string
    names; _ZSFR[0] comes from [variables]; R1 = STRLEN("SUBX") 4 + NUMBER("1.5") + LN(EXP(2)) 2
    + BOUND(0, 3, 7) 3 + ROUNDUP(1.2) 2 = 12.5."""
    text = """DEF STRING[10] NM="SUBX"
G1 X=_ZSFR[0] F100
LAB: G91 X1
REPEATB LAB P=2
G90
CALL NM
R1=STRLEN(NM)+NUMBER("1.5")+LN(EXP(2))+BOUND(0,3,7)+ROUNDUP(1.2)
G1 Y=R1
M30
PROC SUBX
G1 Z-1
RET
"""
    p = run(text, variables={"_ZSFR[0]": 2})
    assert ends(p) == [(2, 0, 50), (3, 0, 50), (4, 0, 50), (5, 0, 50), (5, 0, -1), (5, 12.5, -1)]


def test_array_var_parameters():
    text = """DEF REAL PTS[3]=SET(1, 2, 3)
DOUBLE(PTS)
G1 X=PTS[0] Y=PTS[1] Z=PTS[2] F100
M30
PROC DOUBLE(VAR REAL ARR[])
DEF INT KK
FOR KK=0 TO 2
  ARR[KK]=ARR[KK]*2
ENDFOR
RET
"""
    assert ends(run(text)) == [(2, 4, 6)]
    e = error_of("DEF REAL VV\nDOUBLE(VV)\nM30\nPROC DOUBLE(VAR REAL ARR[])\nRET\n")
    assert (e.line, e.col) == (2, 8) and "is an array" in e.message


def test_r_index_assignment_scoped_def_and_unsupported_path_words():
    p = run("R[2+1]=5\nDEF CHAN REAL CC=2\nG1 X=R3+CC F100\nWAITP(X)\nM30\n")
    assert ends(p) == [(7, 0, 50)] and p.warnings[-1][1].startswith("WAITP")
    e = error_of("G1 X10 ANG=30 F100\n")  # (RND=, CHF=: tests/interp/sinumerik/test_sinumerik_corner.py)
    assert (e.line, e.col) == (1, 8) and e.message == "ANG= (a contour angle) is not supported by the simulator"


def test_subprograms_in_the_archive_folder_spf_dir(tmp_path):
    """A Siemens archive keeps main programs in MPF.DIR and subprograms in SPF.DIR beside it."""
    (tmp_path / "MPF.DIR").mkdir()
    (tmp_path / "SPF.DIR").mkdir()
    (tmp_path / "SPF.DIR" / "_N_FACE_SPF.SPF").write_text("%_N_FACE_SPF\nPROC FACE(REAL ZZ)\nG1 Z=ZZ F100\nRET\n")
    p = run("FACE(-2)\nM30\n", name=str(tmp_path / "MPF.DIR" / "_N_MAIN_MPF.MPF"))
    assert ends(p) == [(0, 0, -2)]


def test_system_variables_the_simulation_knows():
    """$P_AXN3 in G18 is Y (the third axis of ZX: Z, X, then Y); $P_TOOLNO is the tool after M6,
    $P_F the modal feed; $P_SEARCH and $P_SIM are 0 (the real run, not a block search)."""
    text = ("T2 D1 M6\nG18\nDEF AXIS AA\nAA=$P_AXN3\nAX[AA]=5 F100\nG17 G1 X=$P_TOOLNO Z=$P_F/100\n"
            "IF $P_SEARCH OR $P_SIM GOTOF EE\nG1 Z7\nEE: M30\n")
    cfg_radii = {1: 5.0, 2: 3.0}
    p = interpret("t.mpf", text, InterpConfig(dialect="sinumerik", machine_kind="mill", tool_radii=cfg_radii))
    assert ends(p) == [(0, 5, 0), (2, 5, 1), (2, 5, 7)]
    p = run("R1=$P_SIM\nG1 X=R1 F100\nM30\n", variables={"$P_SIM": 1})  # the setup wins
    assert ends(p) == [(1, 0, 50)]
