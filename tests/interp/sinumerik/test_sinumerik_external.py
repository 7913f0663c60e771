"""Sinumerik calls of subprograms the machine has but the simulator does not: the setup's
[machine] external_subprograms (docs/setup.md; docs/dialects/sinumerik.md, "Procedures and
subprograms"). A declared name whose file is not found is skipped with one warning per name and the
tool stays where it was; an undeclared one is exit 2 naming the key; a found file runs; the cycles
the simulator implements or refuses keep their meaning whether listed or not.

Golden transcript tests/data/golden/sinumerik/external/external.mpf (``cutsim moves``, regenerated with
CUTSIM_UPDATE_GOLDEN=1), checked by hand: G0 to (20, 30, 5); L_VENDOR (N40) is skipped, so N50's
G1 Z-2 starts at (20, 30, 5); N60 to (40, 30, -2); TOOLCHG(..) (N70) is skipped, so N80's G91 X10
Y5 goes from (40, 30, -2) to (50, 35, -2); EXTCALL of PROBE (N100, declared as vendor\\probe.spf),
PCALL of _N_L_VENDOR_SPF (N110) and L300 P2 (N120, declared as L300.SPF) make no move, so N130 goes
from (50, 35, -2) to (60, 40, -2); SQUARE is declared but subs/SQUARE.spf exists, so it runs: G91
X10, Y10, X-10, Y-10 from (60, 40): (70, 40), (70, 50), (60, 50), (60, 40); MCALL L_VENDOR makes
no call after N160 X70: (60, 40) -> (70, 40); G0 Z50.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim import CutsimError
from cutsim.cli import main
from cutsim.interp import InterpConfig, interpret

FOLDER = Path(__file__).resolve().parents[2] / "data" / "golden" / "sinumerik" / "external"
WARNING = ("{} is declared external in the setup ([machine] external_subprograms): its motion is not simulated, "
           "the tool is taken to stay where it was")
HEAD = "T1 D1 M6\nG0 X20 Y30 Z5\n"  # the tool stands at (20, 30, 5) before the call


def run(text, externals=(), name="t.mpf", subprogram_path=()):
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: 5.0},
                       external_subprograms=frozenset(externals), subprogram_path=tuple(subprogram_path))
    return interpret(name, text, cfg)


def ends(prog):
    return [tuple(round(v, 6) for v in r.end) for r in prog.moves]


def warnings(prog):
    return [(s.line, s.col, m) for s, m in prog.warnings]


def error_of(text, externals=(), **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, externals, **kw)
    return e.value


def test_golden_transcript():
    prog = FOLDER / "external.mpf"
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(FOLDER / "setup.toml")])
    assert res.exit_code == 0, res.output
    golden = prog.with_suffix(".txt")
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


def test_golden_warns_once_per_name(tmp_path):
    """L_VENDOR is called three times (N40, PCALL at N110, MCALL at N150): one warning, at N40's
    name; SQUARE runs (its file is found): no warning."""
    res = CliRunner().invoke(main, ["simulate", str(FOLDER / "external.mpf"), "--setup", str(FOLDER / "setup.toml"),
                                    "--out", str(tmp_path / "out"), "-q"])
    assert res.exit_code == 0, res.output
    prog = str(FOLDER / "external.mpf")
    expected = [f"{prog}:{line}:{col}: warning: {WARNING.format(name)}"
                for line, col, name in ((6, 5, "L_VENDOR"), (9, 5, "TOOLCHG"), (12, 6, "PROBE"), (14, 6, "L300"))]
    got = [ln for ln in res.output.splitlines() if "declared external" in ln]
    assert got == expected


# -- every call form: declared -> skipped, position unchanged; undeclared -> exit 2 naming the key ------
FORMS = [  # (the call, the name it uses, its column)
    ("L_VENDOR", "L_VENDOR", 1),
    ("L_VENDOR P3", "L_VENDOR", 1),
    ("L123", "L123", 1),
    ("L123 P2", "L123", 1),
    ("L_VENDOR(1, 2.5)", "L_VENDOR", 1),
    ('CYCLE_ABC(1, "S", X, , R1 + 2)', "CYCLE_ABC", 1),
    ("CYCLE123(10)", "CYCLE123", 1),
    ('CALL "L_VENDOR"', "L_VENDOR", 1),
    ('EXTCALL "L_VENDOR"', "L_VENDOR", 1),
    ('EXTCALL "D:\\progs\\l_vendor.spf"', "L_VENDOR", 1),
    ('EXTCALL "/_N_WKS_DIR/_N_L_VENDOR_SPF"', "L_VENDOR", 1),
    ("PCALL L_VENDOR", "L_VENDOR", 7),
    ("PCALL /_N_WKS_DIR/_N_PART_WPD/_N_L_VENDOR_SPF(4)", "L_VENDOR", 31),
    ("MCALL L_VENDOR", "L_VENDOR", 7),
    ("MCALL L123", "L123", 7),
]


@pytest.mark.parametrize("call,name,col", FORMS, ids=[f[0] for f in FORMS])
def test_a_declared_external_is_skipped(call, name, col):
    """The move after the call starts where the tool stood before it: G1 X40 from (20, 30, 5)
    and G91 Y-10 from there, (40, 20, 5); one warning at the call."""
    prog = run(HEAD + f"{call}\nG1 X40 F100\nG91 Y-10\nM30\n", [name])
    assert ends(prog) == [(20, 30, 5), (40, 30, 5), (40, 20, 5)]
    assert warnings(prog) == [(3, col, WARNING.format(name))]


@pytest.mark.parametrize("call,name,col", FORMS, ids=[f[0] for f in FORMS])
def test_an_undeclared_external_is_exit_2_naming_the_key(call, name, col):
    e = error_of(HEAD + f"{call}\nG1 X40 F100\nM30\n", ["OTHER"])
    assert (e.line, e.col) == (3, col), e
    assert f"{name} is not defined" in e.message or f"subprogram {name} (" in e.message, e.message
    assert f'[machine] external_subprograms = ["{name}"]' in e.message, e.message


@pytest.mark.parametrize("declared", ["L_VENDOR.SPF", "l_vendor.mpf", "L_VENDOR.NC", "_N_L_VENDOR_SPF", "L_VENDOR"])
def test_a_declared_file_name_matches_the_call(declared):
    """The setup keeps file names (upper case, no folder); a call names the subprogram without its
    extension or archive form."""
    prog = run(HEAD + "L_VENDOR\nM30\n", [declared.upper()])
    assert warnings(prog) == [(3, 1, WARNING.format("L_VENDOR"))]


def test_other_extensions_do_not_match():
    e = error_of(HEAD + "L_VENDOR\nM30\n", ["L_VENDOR.TXT", "L_VENDOR_X"])
    assert (e.line, e.col) == (3, 1) and "L_VENDOR is not defined" in e.message


def test_one_warning_per_name_in_a_loop():
    """Five calls of one name, two of another: two warnings, each at its first call."""
    text = HEAD + "DEF INT CNT\nFOR CNT = 1 TO 5\nL_VENDOR\nENDFOR\nCYCLE_ABC(1)\nCYCLE_ABC(2)\nG1 X21 F100\nM30\n"
    prog = run(text, ["L_VENDOR", "CYCLE_ABC"])
    assert warnings(prog) == [(5, 1, WARNING.format("L_VENDOR")), (7, 1, WARNING.format("CYCLE_ABC"))]
    assert ends(prog) == [(20, 30, 5), (21, 30, 5)]


def test_a_found_file_runs_even_when_declared(tmp_path):
    """L_VENDOR.spf beside the program: its G1 X50 runs, no warning."""
    (tmp_path / "L_VENDOR.spf").write_text("G1 X50 F100\nM17\n")
    prog = run(HEAD + "L_VENDOR\nG1 Y40\nM30\n", ["L_VENDOR"], name=str(tmp_path / "p.mpf"))
    assert ends(prog) == [(20, 30, 5), (50, 30, 5), (50, 40, 5)]
    assert warnings(prog) == []


def test_a_found_file_in_the_subprogram_path_runs_even_when_declared(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "CYCLE_ABC.SPF").write_text("PROC CYCLE_ABC(REAL D)\nG1 Z=-D F100\nRET\n")
    prog = run(HEAD + "CYCLE_ABC(3)\nM30\n", ["CYCLE_ABC"], name=str(tmp_path / "p.mpf"), subprogram_path=[str(subs)])
    assert ends(prog) == [(20, 30, 5), (20, 30, -3)]
    assert warnings(prog) == []


def test_a_proc_of_the_file_runs_even_when_declared():
    text = HEAD + "L_VENDOR\nM30\nPROC L_VENDOR\nG1 X25 F100\nRET\n"
    prog = run(text, ["L_VENDOR"])
    assert ends(prog) == [(20, 30, 5), (25, 30, 5)] and warnings(prog) == []


def test_the_skipped_calls_arguments_and_repeat_count_are_checked():
    """The arguments are evaluated (their errors count), bare names (axes, VAR targets) are not;
    the repeat count P is a whole number of at least 1."""
    e = error_of(HEAD + "CYCLE_ABC(1, 2 / 0)\nM30\n", ["CYCLE_ABC"])
    assert (e.line, e.col) == (3, 16) and "division by zero" in e.message
    e = error_of(HEAD + "CYCLE_ABC(UNSET_NAME + 1)\nM30\n", ["CYCLE_ABC"])
    assert e.line == 3 and "UNSET_NAME" in e.message
    e = error_of(HEAD + "L_VENDOR P2.5\nM30\n", ["L_VENDOR"])
    assert (e.line, e.col) == (3, 10) and "P (repeat count) must be a whole number" in e.message
    prog = run(HEAD + "CYCLE_ABC(Z, SOME_AXIS)\nM30\n", ["CYCLE_ABC"])
    assert len(warnings(prog)) == 1


def test_a_skipped_call_keeps_the_modal_state():
    """G91 before the call stays in force after it (nothing of the call runs, not even a RET)."""
    prog = run(HEAD + "G91\nL_VENDOR\nG1 X5 F100\nM30\n", ["L_VENDOR"])
    assert ends(prog) == [(20, 30, 5), (25, 30, 5)]


def test_a_block_with_a_skipped_call_runs_its_move_and_end():
    """The move of the block runs before the call (the order of a block: motion, then calls); M30 in
    the same block still ends the program."""
    prog = run(HEAD + "G1 X30 F100 L_VENDOR\nM30\n", ["L_VENDOR"])
    assert ends(prog) == [(20, 30, 5), (30, 30, 5)]
    prog = run(HEAD + "L_VENDOR M30\nG1 X99\n", ["L_VENDOR"])
    assert ends(prog) == [(20, 30, 5)]


# -- what the list cannot override ----------------------------------------------------------------------
def test_an_implemented_cycle_runs_whether_listed_or_not():
    """CYCLE81 drills (to DP -5 from RFP 0 + SDIS 2, back to RTP 10) with or without the name in the list."""
    text = HEAD + "CYCLE81(10, 0, 2, -5)\nM30\n"
    assert ends(run(text, ["CYCLE81"])) == ends(run(text)) == [(20, 30, 5), (20, 30, 2), (20, 30, -5), (20, 30, 10)]
    assert [w for w in warnings(run(text, ["CYCLE81"])) if "external" in w[2]] == []


def test_a_pocket_cycle_runs_whether_listed_or_not():
    text = HEAD + "POCKET1(10, 0, 2, -2, , 40, 30, 6, 50, 50, 0, 100, 100, 0, 2, 0, 0, 5, 0)\nM30\n"
    assert ends(run(text, ["POCKET1"])) == ends(run(text))
    assert len(ends(run(text))) > 5


def test_a_refused_siemens_cycle_stays_refused():
    """CYCLE99 (ShopTurn thread turning) is a Siemens cycle the simulator does not run: listing it
    does not make it cut nothing; the message says the list does not apply."""
    e = error_of(HEAD + "CYCLE99(0, 40, -30, 40, 2, 1, 0.92)\nM30\n", ["CYCLE99"])
    assert (e.line, e.col) == (3, 1)
    assert "CYCLE99 (ShopTurn thread turning) is not simulated yet: the coding of its call" in e.message
    assert "digits of _VARI" in e.message and "program the thread with CYCLE97(PIT, MPIT, SPL" in e.message
    assert "[machine] external_subprograms does not apply" in e.message
    assert "does not apply" not in error_of(HEAD + "CYCLE99(0, 40, -30, 40, 2, 1, 0.92)\nM30\n").message


def test_a_cycle800_swivel_stays_refused():
    e = error_of(HEAD + 'CYCLE800(0, "TC1", 200000, 57, 0, 0, 0, 30, 0, 0, 0, 0, 0, 1)\nM30\n', ["CYCLE800"])
    assert e.line == 3 and "CYCLE800" in e.message and "not modelled" in e.message


def test_a_contour_for_a_cycle_is_not_skipped():
    """The contour a cycle machines (_KNAME) is geometry, not a call: a listed but missing one is
    still an error."""
    text = HEAD + 'CYCLE72("KONT", 10, 0, 2, -2, 2, 0, 0, 100, 100, 11, 41, 1, 5, 100, 1, 5)\nM30\n'
    e = error_of(text, ["KONT"])
    assert e.line == 3 and "KONT" in e.message


def test_a_keyword_is_never_a_subprogram():
    """TRANS is a frame instruction, never a call of TRANS.spf, listed or not."""
    prog = run(HEAD + "TRANS X5\nG1 X0 F100\nM30\n", ["TRANS"])
    assert ends(prog) == [(20, 30, 5), (5, 30, 5)] and warnings(prog) == []


# -- the new call statements' bad forms -------------------------------------------------------------------
@pytest.mark.parametrize("call,col,fragment", [
    ("EXTCALL 5", 1, "EXTCALL needs a subprogram name as a string, not '5'"),
    ('EXTCALL "A B"', 1, "EXTCALL needs a subprogram name as a string"),
    ('EXTCALL "C:\\\\"', 1, "EXTCALL needs a subprogram name as a string"),
    ("EXTCALL", 8, "expression expected"),
    ("PCALL", 6, "PCALL needs a subprogram name"),
    ("PCALL /_N_WKS_DIR/", 19, "PCALL needs a subprogram name"),
    ("PCALL 5", 7, "PCALL needs a subprogram name"),
])
def test_bad_extcall_and_pcall(call, col, fragment):
    e = error_of(HEAD + f"{call}\nM30\n", ["L_VENDOR"])
    assert (e.line, e.col) == (3, col), e
    assert fragment in e.message, e.message


def test_extcall_and_pcall_run_a_found_subprogram(tmp_path):
    """EXTCALL "path\\SUB.SPF" and PCALL /path/SUB(args) find SUB beside the program by its name."""
    (tmp_path / "SUB.spf").write_text("PROC SUB(REAL DX=1)\nG91 G1 X=DX F100\nG90\nRET\n")
    text = HEAD + 'EXTCALL "E:\\CAM\\SUB.SPF"\nPCALL /_N_WKS_DIR/_N_A_WPD/_N_SUB_SPF(4)\nM30\n'
    prog = run(text, name=str(tmp_path / "p.mpf"))
    assert ends(prog) == [(20, 30, 5), (21, 30, 5), (25, 30, 5)]
