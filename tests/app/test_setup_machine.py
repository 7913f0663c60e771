"""What only the setup can say (docs/setup.md): [machine] axes, m_functions,
h_functions, subprogram_path, external_subprograms; [variables]; [work_offsets]; [[tool]] name; drill tools.

Every key: a good value reaches the interpreter's InterpConfig (cutsim.load_setup + interp_config),
and a bad one is exit 2 from the command line at the key's (or the array element's) SETUP:LINE:COL.
"""
from __future__ import annotations

import math
import os

import pytest
from click.testing import CliRunner

import cutsim
from cutsim import CutsimError, interp_config
from cutsim.cli import main
from cutsim.interp import DIALECTS

BASE = """\
[machine]
kind = "mill"
dialect = "sinumerik"

[stock]
shape = "box"
x = [0, 50]
y = [0, 40]
z = [-10, 0]

[[tool]]
number = 1
kind = "endmill"
diameter = 6
"""

PROGRAM = "G0 X10 Y10 Z5\nG1 Z-1 F100\nM30\n"


def with_machine(lines: str, base: str = BASE) -> str:
    """BASE with ``lines`` added at the end of [machine]."""
    return base.replace('dialect = "sinumerik"\n', 'dialect = "sinumerik"\n' + lines, 1)


def _write(tmp_path, text: str):
    p = tmp_path / "setup.toml"
    p.write_text(text)
    return p


def config(tmp_path, text: str):
    p = tmp_path / "setup.toml"
    p.write_text(text)
    return interp_config(cutsim.load_setup(str(p)), (0.0, 0.0, 0.0))


def _at(text: str, needle: str, last: bool = False) -> tuple[int, int]:
    """1-based line and column of the first (``last``: the last) ``needle`` in ``text`` (counted
    here, not by the loader)."""
    i = text.rindex(needle) if last else text.index(needle)
    return text.count("\n", 0, i) + 1, i - (text.rfind("\n", 0, i) + 1) + 1


def cli_error(tmp_path, text: str, needle: str, fragments, last: bool = False) -> str:
    """Run ``cutsim moves`` with the setup ``text``: exit 2, the message at ``needle``'s line:col."""
    setup = tmp_path / "setup.toml"
    setup.write_text(text)
    prog = tmp_path / "p.mpf"
    prog.write_text(PROGRAM)
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    line, col = _at(text, needle, last)
    assert res.exit_code == 2, res.output
    assert res.output.startswith(f"{setup}:{line}:{col}: error: "), (res.output, line, col)
    assert "Traceback" not in res.output
    for f in fragments:
        assert f in res.output, res.output
    return res.output


def test_defaults_are_empty(tmp_path):
    c = config(tmp_path, BASE)
    assert c.axes == {} and c.m_functions == frozenset() and c.h_functions == frozenset()
    assert c.variables == {} and c.work_offsets == {} and c.subprogram_path == () and c.tool_names == {}
    assert c.external_subprograms == frozenset()


def test_the_good_setup_runs(tmp_path):
    """All the new keys at once: the CLI interprets the program (exit 0)."""
    (tmp_path / "subs").mkdir()
    text = with_machine('axes = { A = "rotary" }\nm_functions = [20]\nh_functions = [7]\nsubprogram_path = ["subs"]\n'
                        'external_subprograms = ["L_VENDOR"]\n')
    text += '\n[variables]\n"$P_TOOLNO" = 1\n\n[work_offsets]\nG54 = [0, 0, 0]\n'
    setup = tmp_path / "setup.toml"
    setup.write_text(text.replace('diameter = 6\n', 'diameter = 6\nname = "MILL 6"\n'))
    prog = tmp_path / "p.mpf"
    prog.write_text(PROGRAM)
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 0, res.output


# -- [machine] axes ---------------------------------------------------------------------------------
def test_axes_reach_the_interpreter(tmp_path):
    c = config(tmp_path, with_machine('axes = { a = "rotary", W = "linear", C1 = "rotary", SP1 = "rotary" }\n'))
    assert c.axes == {"A": "rotary", "C1": "rotary", "SP1": "rotary", "W": "linear"}
    c = config(tmp_path, BASE + '\n[machine.axes]\nB = "rotary"\nU = "linear"\nV = "linear"\n')
    assert c.axes == {"B": "rotary", "U": "linear", "V": "linear"}


@pytest.mark.parametrize("axes,needle,fragments", [
    ('{ X = "linear" }', "X =", ["[machine.axes] X", "own axes X, Y, Z"]),
    ('{ A = "rotary", z2 = "linear" }', "z2", ["[machine.axes] z2", "own axes"]),
    ('{ Q = "rotary" }', "Q =", ["[machine.axes] Q", "an axis name is A, B, C, U, V or W"]),
    ('{ R1 = "rotary" }', "R1", ["an axis name is"]),
    ('{ "A 1" = "rotary" }', '"A 1"', ["an axis name is"]),
    ('{ A = "round" }', "A =", ["[machine.axes] A", '"rotary" or "linear"']),
    ('{ A = 1 }', "A =", ["[machine.axes] A", "must be a string"]),
    ('{ A = "rotary", a = "linear" }', "a =", ["axis A is declared twice"]),
    ('["A"]', "axes", ["[machine] axes", "must be a table"]),
])
def test_bad_axes(tmp_path, axes, needle, fragments):
    text = with_machine(f"axes = {axes}\n")
    cli_error(tmp_path, text, needle, fragments)


# -- [machine] m_functions / h_functions ------------------------------------------------------------
def test_machine_functions_reach_the_interpreter(tmp_path):
    c = config(tmp_path, with_machine("m_functions = [20, 70, 73, 70, 0, 99999]\nh_functions = [1, 2]\n"))
    assert c.m_functions == frozenset({0, 20, 70, 73, 99999}) and c.h_functions == frozenset({1, 2})


@pytest.mark.parametrize("line,needle,fragments", [
    ("m_functions = [20, 100000]", "100000", ["[machine] m_functions", "whole number from 0 to 99999", "100000"]),
    ("m_functions = [-1]", "-1", ["[machine] m_functions", "from 0 to 99999"]),
    ("m_functions = [20, 2.5]", "2.5", ["not 2.5"]),
    ("m_functions = [true]", "true", ["not True"]),
    ('m_functions = [20, "M73"]', '"M73"', ["write 'M73' as the number 73"]),
    ("m_functions = 20", "m_functions", ["[machine] m_functions", "must be a list"]),
    ("h_functions = [\n  1,\n  1e3,\n]", "1e3", ["[machine] h_functions", "an H function"]),
    ('h_functions = ["H5"]', '"H5"', ["write 'H5' as the number 5"]),
])
def test_bad_machine_functions(tmp_path, line, needle, fragments):
    cli_error(tmp_path, with_machine(line + "\n"), needle, fragments)


# -- [machine] subprogram_path ----------------------------------------------------------------------
def test_subprogram_path_is_absolute_from_the_setup_folder(tmp_path):
    (tmp_path / "subs").mkdir()
    (tmp_path / "lib" / "cycles").mkdir(parents=True)
    other = tmp_path / "elsewhere"
    other.mkdir()
    c = config(tmp_path, with_machine(f'subprogram_path = ["subs", "lib/cycles/", ".", "./subs", {str(other)!r}]\n'))
    assert c.subprogram_path == (str(tmp_path / "subs"), str(tmp_path / "lib" / "cycles"), str(tmp_path), str(other))
    assert all(os.path.isabs(p) for p in c.subprogram_path)


@pytest.mark.parametrize("line,needle,fragments", [
    ('subprogram_path = ["subs", "missing"]', '"missing"', ["[machine] subprogram_path", "no such folder", "missing"]),
    ('subprogram_path = ["p.mpf"]', '"p.mpf"', ["no such folder"]),  # a file is not a folder
    ('subprogram_path = ["subs", 3]', "3]", ["a folder is a non-empty string, not 3"]),
    ('subprogram_path = [""]', '""', ["a folder is a non-empty string"]),
    ('subprogram_path = "subs"', "subprogram_path", ["must be a list"]),
])
def test_bad_subprogram_path(tmp_path, line, needle, fragments):
    (tmp_path / "subs").mkdir()
    cli_error(tmp_path, with_machine(line + "\n"), needle, fragments)


# -- [machine] external_subprograms -----------------------------------------------------------------
def test_external_subprograms_reach_the_interpreter(tmp_path):
    """Upper-cased file names, the folder (after the last / or \\) removed, the extension kept."""
    c = config(tmp_path, with_machine('external_subprograms = ["0_Inicio_Prog.nc", "G803", "L_VENDOR", "CYCLE_ABC", '
                                      '"subs\\\\vendor\\\\my-cycle.spf", "/_N_CMA_DIR/_n_cyc_x_spf", " l100 "]\n'))
    assert c.external_subprograms == frozenset({"0_INICIO_PROG.NC", "G803", "L_VENDOR", "CYCLE_ABC", "MY-CYCLE.SPF",
                                                "_N_CYC_X_SPF", "L100"})
    assert config(tmp_path, with_machine("external_subprograms = []\n")).external_subprograms == frozenset()


@pytest.mark.parametrize("line,needle,fragments", [
    ('external_subprograms = ["G803", "g803"]', '"g803"', ["[machine] external_subprograms", "G803 is given twice",
                                                           "element 1"]),
    ('external_subprograms = ["L_VENDOR", "subs/l_vendor"]', '"subs/l_vendor"', ["L_VENDOR is given twice"]),
    ('external_subprograms = ["G803", ""]', '""]', ["a subprogram is a non-empty string"]),
    ('external_subprograms = ["  "]', '"  "', ["a subprogram is a non-empty string"]),
    ('external_subprograms = ["G803", 803]', "803]", ["a subprogram is a non-empty string", "not 803"]),
    ('external_subprograms = ["subs/"]', '"subs/"', ["is a folder: name the subprogram's file"]),
    ('external_subprograms = ["MY CYCLE"]', '"MY CYCLE"', ["letters, digits, _ . and -"]),
    ('external_subprograms = ["L(1)"]', '"L(1)"', ["letters, digits, _ . and -"]),
    ('external_subprograms = [".hidden"]', '".hidden"', ["not starting with . or -"]),
    ('external_subprograms = ["CYCLÉ"]', '"CYCLÉ"', ["letters, digits"]),
    (f'external_subprograms = ["{"A" * 65}"]', '"AAA', ["at most 64 characters (got 65)"]),
    ('external_subprograms = "L_VENDOR"', "external_subprograms", ["[machine] external_subprograms",
                                                                   "must be a list"]),
    ('external_subprograms = [\n  "G803",\n  ["L_VENDOR"],\n]', '["L_VENDOR"]', ["non-empty string"]),
])
def test_bad_external_subprograms(tmp_path, line, needle, fragments):
    cli_error(tmp_path, with_machine(line + "\n"), needle, fragments)


def test_a_64_character_name_is_accepted(tmp_path):
    c = config(tmp_path, with_machine(f'external_subprograms = ["{"b" * 64}"]\n'))
    assert c.external_subprograms == frozenset({"B" * 64})


# -- [variables] --------------------------------------------------------------------------------------
def on(dialect: str, text: str = BASE) -> str:
    return text.replace('dialect = "sinumerik"', f'dialect = "{dialect}"', 1)


def test_sinumerik_variables_reach_the_interpreter(tmp_path):
    text = BASE + """
[variables]
"$P_TOOLNO" = 3
"$a_dbb[ 5 ]" = 0
"$MA_JOG_VELO[X1]" = 2000.5
"$P_UIFR[1, X, TR]" = -2.5
" $TC_DP1[1,1] " = 120
MYDATA = "text as written"
"GUD_ARR[2]" = 4
FLAG = true
"""
    c = config(tmp_path, text)
    assert c.variables == {
        "$P_TOOLNO": 3.0, "$A_DBB[5]": 0.0, "$MA_JOG_VELO[X1]": 2000.5, "$P_UIFR[1,X,TR]": -2.5,
        "$TC_DP1[1,1]": 120.0, "MYDATA": "text as written", "GUD_ARR[2]": 4.0, "FLAG": 1.0}
    assert all(isinstance(v, float) for k, v in c.variables.items() if k != "MYDATA")


def test_isg_variables_reach_the_interpreter(tmp_path):
    text = on("isg", BASE + """
[variables]
V.G.NAME = 1
"V.E.SPEED" = 800
"v.g.wz[ 2 ].l" = true
"V.E.ARR[0][10]" = false
"V.G.TEXT" = "as written"
"V.A.ACS.X" = 12
"V.CYC.DEPTH" = 3

[variables.V.E]
COUNT = 7
""")
    c = config(tmp_path, text)
    assert c.variables == {"V.A.ACS.X": 12.0, "V.CYC.DEPTH": 3.0, "V.E.ARR[0][10]": 0.0, "V.E.COUNT": 7.0,
                           "V.E.SPEED": 800.0, "V.G.NAME": 1.0, "V.G.TEXT": "as written", "V.G.WZ[2].L": 1.0}


def test_isg_program_reads_the_setup_variables(tmp_path):
    """What the setup gives is what the program reads: X = V.E.X0 + V.G.STEP[1] * 2 + V.A.OFF.X."""
    setup = tmp_path / "setup.toml"
    setup.write_text(on("isg", BASE + '\n[variables]\n"V.E.X0" = 10\n"V.G.STEP[1]" = 2.5\n"V.A.OFF.X" = -1\n'))
    prog = tmp_path / "p.nc"
    prog.write_text("%P\nG00 Z5\nG01 X[V.E.X0 + V.G.STEP[1] * 2 + V.A.OFF.X] F100\nM30\n")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 0, res.output
    assert "FEED (25 20 5) -> (14 20 5) F100/min" in res.output  # from the start above the stock centre


@pytest.mark.parametrize("name", [e for d in DIALECTS.values() for e in d.variables.examples])
def test_every_example_a_message_lists_is_accepted(name):
    """The examples each dialect's message gives are names it accepts, and the message lists them."""
    owner = [d for d in DIALECTS.values() if name in d.variables.examples]
    assert all(d.variables.matches(name) and name in d.variables.accepts for d in owner)


@pytest.mark.parametrize("dialect,lines,needle,fragments", [
    # Sinumerik: system variables and global user data; no ISG names, no spaces or open brackets
    ("sinumerik", '"$A DBB[5]" = 0', '"$A DBB', ["[variables] $A DBB[5]", "a Sinumerik variable is"]),
    ("sinumerik", '"$P_TOOLNO[" = 0', '"$P_TOOLNO[', ["a Sinumerik variable is", "$MA_JOG_VELO[X1]"]),
    ("sinumerik", '"1ABC" = 0', '"1ABC"', ["a Sinumerik variable is"]),
    ("sinumerik", '"V.G.NAME" = 0', '"V.G.NAME"', ["[variables] V.G.NAME", "a Sinumerik variable is"]),
    ("sinumerik", "R4 = 1", "R4", ["R parameters are set in [parameters]"]),
    # ISG: V.E. and V.G. only, whole-number indexes as the program prints them
    ("isg", '"$P_TOOLNO" = 0', '"$P_TOOLNO"', ["an ISG variable the setup gives is the controller's",
                                                "V.G.WZ[2].L"]),
    ("isg", '"V.S.COUNT" = 0', '"V.S.COUNT"', ["[variables] V.S.COUNT", "declared in the program"]),
    ("isg", '"V.P.FLAG" = 0', '"V.P.FLAG"', ["[variables] V.P.FLAG", "declared in the program"]),
    ("isg", '"V..X" = 0', '"V..X"', ["an ISG variable"]),
    ("isg", '"V.G.ARR[X]" = 0', '"V.G.ARR[X]"', ["whole-number indexes"]),
    ("isg", '"V.G.ARR[02]" = 0', '"V.G.ARR[02]"', ["whole-number indexes"]),
    ("isg", '"V.G.ARR[1,2]" = 0', '"V.G.ARR[1,2]"', ["whole-number indexes"]),
    ("isg", "MYDATA = 0", "MYDATA", ["an ISG variable"]),
    ("isg", "[variables.V.L]\nCOUNT = 7", "COUNT", ["[variables] V.L.COUNT", "declared in the program"]),
    # CNC8x6 and RS274NGC read none: the message says where the values go
    ("cnc8x6", '"$P_TOOLNO" = 0', '"$P_TOOLNO"', ["CNC8x6 programs read no variables", "[parameters]"]),
    ("cnc8x6", "R4 = 1", "R4", ["[variables] R4", "R parameters are set in [parameters]"]),
    ("rs274ngc", '"#<_depth>" = 1', '"#<_depth>"', ["[variables] #<_depth>", "RS274NGC programs read no [variables]",
                                                   "parameter_file"]),
    ("rs274ngc", '"#5220" = 1', '"#5220"', ["parameter_file"]),
])
def test_names_a_dialect_refuses(tmp_path, dialect, lines, needle, fragments):
    text = on(dialect, BASE + "\n[variables]\n" + lines + "\n")
    cli_error(tmp_path, text, needle, fragments)


@pytest.mark.parametrize("lines,needle,fragments", [
    ('"$P_TOOLNO" = 1\n"$p_toolno" = 2', '"$p_toolno"', ["$P_TOOLNO is given twice"]),
    ('"$P_X" = [1, 2]', '"$P_X"', ["must be a number, a string or true/false"]),
    ('"$P_X" = nan', '"$P_X"', ["finite number"]),
    ('"$P_X" = 1e13', '"$P_X"', ["within -1e+12 to 1e+12"]),
    ('"$P_X" = "' + "s" * 201 + '"', '"$P_X"', ["at most 200 characters"]),
])
def test_bad_variables(tmp_path, lines, needle, fragments):
    text = BASE + "\n[variables]\n" + lines + "\n"
    cli_error(tmp_path, text, needle, fragments)


def test_variable_names_come_from_the_registry_entry(tmp_path, monkeypatch):
    """A dialect's [variables] names are its registry entry's (interp.VariableNames), not a branch
    of the setup loader: a plug-in with its own syntax gets exactly that syntax and its message;
    one without an entry accepts no names."""
    from cutsim.interp import Dialect, VariableNames

    names = VariableNames(r"@[0-9]+", "a toy variable is @ and a number (@1, @20)", ("@1", "@20"))
    monkeypatch.setitem(DIALECTS, "toy", Dialect("support.toy_dialect", False, (".toy",), "toy", variables=names))
    monkeypatch.setitem(DIALECTS, "bare", Dialect("support.toy_dialect", False, (".toy",), "bare"))
    setup = tmp_path / "setup.toml"
    setup.write_text(on("toy", BASE + '\n[variables]\n"@20" = 5\n'))
    assert cutsim.load_setup(str(setup)).variables == {"@20": 5.0}
    for dialect, line, message in (("toy", '"$P_TOOLNO" = 1', "a toy variable is @ and a number (@1, @20)"),
                                   ("bare", '"@20" = 1', "this dialect reads no [variables]")):
        text = on(dialect, BASE + "\n[variables]\n" + line + "\n")
        setup.write_text(text)
        with pytest.raises(cutsim.CutsimError) as e:
            cutsim.load_setup(str(setup))
        assert e.value.message.endswith(": " + message) and (e.value.line, e.value.col) == _at(text, line)


def test_isg_dotted_name_given_twice(tmp_path):
    text = on("isg", BASE + '\n[variables]\nV.G.X.Y = 1\n"V.G.X.Y" = 2\n')
    cli_error(tmp_path, text, '"V.G.X.Y"', ["V.G.X.Y is given twice"])


def test_variables_must_be_a_table(tmp_path):
    text = "variables = 3\n" + BASE
    cli_error(tmp_path, text, "variables", ["[variables] must be a table"])


def test_dotted_variable_error_points_at_its_key(tmp_path):
    # V.G.NAME unquoted is a dotted key: the error is on its line (at the name's last part)
    text = on("isg", BASE + "\n[variables]\nV.G.NAME = [1]\n")
    cli_error(tmp_path, text, "NAME =", ["[variables] V.G.NAME", "must be a number"])


# -- [work_offsets] -----------------------------------------------------------------------------------
def test_work_offsets_reach_the_interpreter(tmp_path):
    text = BASE + "\n[work_offsets]\ng54 = [10, 20.5, -5]\nG599 = [0, 0, 100000]\nG505 = [-1, -2, -3]\nG57 = [1, 1, 1]\n"
    c = config(tmp_path, text)
    assert c.work_offsets == {"G54": (10.0, 20.5, -5.0), "G57": (1.0, 1.0, 1.0), "G505": (-1.0, -2.0, -3.0),
                              "G599": (0.0, 0.0, 100000.0)}
    isg = BASE.replace('"sinumerik"', '"isg"') + "\n[work_offsets]\nG58 = [1, 2, 3]\nG59 = [4, 5, 6]\n"
    c = config(tmp_path, isg)
    assert c.work_offsets == {"G58": (1.0, 2.0, 3.0), "G59": (4.0, 5.0, 6.0)}


@pytest.mark.parametrize("dialect,line,needle,fragments", [
    ("sinumerik", "G500 = [0, 0, 0]", "G500", ["[work_offsets] G500", "no work offset"]),
    ("sinumerik", "G53 = [0, 0, 0]", "G53", ["no work offset"]),
    ("sinumerik", "G58 = [0, 0, 0]", "G58", ["programmable axial offset"]),
    ("sinumerik", "G504 = [0, 0, 0]", "G504", ["G54 to G57 and G505 to G599"]),
    ("sinumerik", "G600 = [0, 0, 0]", "G600", ["G54 to G57 and G505 to G599"]),
    ("isg", "G505 = [0, 0, 0]", "G505", ["the work offsets of isg are G54 to G59"]),
    ("isg", "G92 = [0, 0, 0]", "G92", ["set by the program"]),
    ("sinumerik", "G54 = [1, 2]", "G54", ["three finite numbers [x, y, z]"]),
    ("sinumerik", "G54 = [1, 2, inf]", "G54", ["three finite numbers"]),
    ("sinumerik", "G54 = [1, 2, 1e6]", "G54", ["within -100000 to 100000 mm"]),
    ("sinumerik", "G54 = 5", "G54", ["must be a list"]),
    ("sinumerik", "G54 = [0, 0, 0]\ng54 = [1, 1, 1]", "g54", ["G54 is given twice"]),
])
def test_bad_work_offsets(tmp_path, dialect, line, needle, fragments):
    text = BASE.replace('"sinumerik"', f'"{dialect}"') + "\n[work_offsets]\n" + line + "\n"
    cli_error(tmp_path, text, needle, fragments)


def test_work_offsets_come_from_the_registry_entry(tmp_path, monkeypatch):
    """A dialect's settable offsets are its registry entry's (interp.WorkOffsets), not a branch of
    the setup loader: a registered dialect with its own list gets exactly that list and messages."""
    from cutsim.interp import DIALECTS, Dialect, WorkOffsets

    offsets = WorkOffsets(("G54", "G154"), "G54 and G154", (("G55", "on Toy G55 is a tool offset"),))
    monkeypatch.setitem(DIALECTS, "toy", Dialect("support.toy_dialect", False, (".toy",), "toy", offsets))
    setup = tmp_path / "setup.toml"
    toy = BASE.replace('"sinumerik"', '"toy"') + "\n[work_offsets]\n"
    setup.write_text(toy + "G154 = [1, 2, 3]\n")
    assert cutsim.load_setup(str(setup)).work_offsets == {"G154": (1.0, 2.0, 3.0)}
    for line, message in (("G55 = [0, 0, 0]", "[work_offsets] G55: on Toy G55 is a tool offset; the settable "
                                              "offsets are G54 and G154"),
                          ("G56 = [0, 0, 0]", "[work_offsets] G56: the work offsets of toy are G54 and G154")):
        setup.write_text(toy + line + "\n")
        with pytest.raises(cutsim.CutsimError) as e:
            cutsim.load_setup(str(setup))
        assert e.value.message == message and (e.value.line, e.value.col) == _at(toy + line, line[:3])
    assert DIALECTS["isg"].work_offsets == WorkOffsets()  # G54 to G59, nothing refused


# -- [[tool]] name ------------------------------------------------------------------------------------
def test_tool_names_reach_the_interpreter(tmp_path):
    text = BASE + '\n[[tool]]\nnumber = 7\nkind = "drill"\ndiameter = 8.5\nname = "DRILL 8.5"\n' \
                  '\n[[tool]]\nnumber = 8\nkind = "endmill"\ndiameter = 10\nname = "Fraeser_10"\n'
    c = config(tmp_path, text)
    assert c.tool_names == {"DRILL 8.5": 7, "Fraeser_10": 8}  # as written; the unnamed tool 1 has none
    s = cutsim.load_setup(str(tmp_path / "setup.toml"))
    assert [t.name for t in s.tools] == ["", "DRILL 8.5", "Fraeser_10"]


@pytest.mark.parametrize("name,needle,fragments", [
    ('""', 'name = ""', ["[[tool]] #1 name", "1 to 32 characters"]),
    ('"' + "D" * 33 + '"', "name =", ["1 to 32 characters"]),
    ('" DRILL"', "name =", ["spaces at either end"]),
    ("'A\"B'", "name =", ["without quotes"]),
    ('"A\\tB"', "name =", ["control characters"]),
    ("5", "name =", ["[[tool]] #1 name", "must be a string"]),
])
def test_bad_tool_names(tmp_path, name, needle, fragments):
    text = BASE.replace("diameter = 6\n", f"diameter = 6\nname = {name}\n")
    cli_error(tmp_path, text, needle, fragments)


def test_tool_names_are_unique_ignoring_case(tmp_path):
    text = BASE.replace("diameter = 6\n", 'diameter = 6\nname = "Drill"\n') + \
        '\n[[tool]]\nnumber = 2\nkind = "endmill"\ndiameter = 4\nname = "DRILL"\n'
    cli_error(tmp_path, text, 'name = "DRILL"', ["[[tool]] #2 name", "differs only in case from 'Drill'",
                                                  "tool 1"])
    text = text.replace('name = "DRILL"', 'name = "Drill"')
    cli_error(tmp_path, text, 'name = "Drill"', ["'Drill' names tool 1 already"], last=True)


# -- drill tools ----------------------------------------------------------------------------------------
def test_drill_defaults_and_values(tmp_path):
    text = BASE + '\n[[tool]]\nnumber = 2\nkind = "drill"\ndiameter = 8.5\n' \
                  '\n[[tool]]\nnumber = 3\nkind = "drill"\ndiameter = 10\nlength = 40\npoint_angle = 180\n'
    p = tmp_path / "setup.toml"
    p.write_text(text)
    s = cutsim.load_setup(str(p))
    d = s.tools[1]
    assert (d.kind, d.diameter, d.length, d.point_angle) == ("drill", 8.5, 85.0, 118.0)  # length: 10 x diameter
    assert not d.is_lathe_tool
    flat = s.tools[2]
    assert (flat.diameter, flat.length, flat.point_angle) == (10.0, 40.0, 180.0)
    assert interp_config(s, (0, 0, 0)).tool_radii == {1: 3.0, 2: 4.25, 3: 5.0}


def test_drill_default_length_is_capped(tmp_path):
    """10 x a 2000 mm diameter would be 20000 mm: the default stops at the 10000 mm a length may have."""
    s = cutsim.load_setup(str(_write(tmp_path, BASE + '\n[[tool]]\nnumber = 2\nkind = "drill"\ndiameter = 2000\n')))
    assert s.tools[1].length == 10000.0


def test_drill_point_must_fit_its_length(tmp_path):
    """A 10 mm drill at 90 degrees has a point 5 / tan(45) = 5 mm long: length 5.01 is accepted, 4.99 is not."""
    base = BASE + '\n[[tool]]\nnumber = 2\nkind = "drill"\ndiameter = 10\npoint_angle = 90\n'
    assert config(tmp_path, base + "length = 5.01\n").tool_radii[2] == 5.0
    cli_error(tmp_path, base + "length = 4.99\n", "length = 4.99", ["[[tool]] #2 length", "height of the point"])
    # at 60 degrees the point is 5 / tan(30) = 8.66 mm long
    h = 5 / math.tan(math.radians(30))
    assert config(tmp_path, base.replace("= 90", "= 60") + f"length = {h + 0.01:.3f}\n")
    cli_error(tmp_path, base.replace("= 90", "= 60") + f"length = {h - 0.01:.3f}\n", "length =", ["height of the point"])


@pytest.mark.parametrize("lines,needle,fragments", [
    ("diameter = 8\npoint_angle = 0", "point_angle", ["[[tool]] #2 point_angle", "between 1 and 180 degrees"]),
    ("diameter = 8\npoint_angle = 180.5", "point_angle", ["between 1 and 180 degrees"]),
    ("diameter = 8\npoint_angle = nan", "point_angle", ["must be a number"]),
    ('diameter = 8\npoint_angle = "118"', "point_angle", ["must be a number"]),
    ("diameter = 0", "diameter", ["[[tool]] #2 diameter", "between 0.001 and 10000 mm"]),
    ("diameter = 8\nlength = 20000", "length", ["[[tool]] #2 length", "between 0.001 and 10000 mm"]),
    ("diameter = 8\ncorner_radius = 1", "corner_radius", ["unknown key for a drill tool", "point_angle"]),
    ("length = 50", "[[tool]]", ["[[tool]] #2 diameter", "is required"]),  # a missing key: at its table
])
def test_bad_drills(tmp_path, lines, needle, fragments):
    text = BASE + '\n[[tool]]\nnumber = 2\nkind = "drill"\n' + lines + "\n"
    cli_error(tmp_path, text, needle, fragments, last=True)


def test_endmill_does_not_fit_a_lathe(tmp_path):
    """A drill works on a lathe's spindle axis (tests/stock/test_lathe_tools.py); an end mill does not."""
    text = ('[machine]\nkind = "lathe"\ndialect = "sinumerik"\n\n[stock]\nshape = "cylinder"\ndiameter = 30\n'
            'z = [-40, 0]\n\n[[tool]]\nnumber = 1\nkind = "endmill"\ndiameter = 8\n')
    cli_error(tmp_path, text, 'kind = "endmill"', ["[[tool]] #1 kind", "a endmill tool does not fit a lathe"])


def test_load_setup_raises_cutsim_error(tmp_path):
    """The Python API raises the same error the CLI prints."""
    p = tmp_path / "setup.toml"
    text = with_machine('axes = { Y = "linear" }\n')
    p.write_text(text)
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(p))
    assert (e.value.line, e.value.col) == _at(text, "Y =") and "own axes" in e.value.message
