"""Sinumerik axis functions (interp/sinumerik/axes.py): AXNAME, AXSTRING, SPI, AXTOSPI and AX[..]
with any AXIS expression. End points worked out by hand from the programs and the setup's values
(a GUD naming the axis, a user array INI[..] from [variables], the plane's axes $P_AXN1..3)."""
from __future__ import annotations

import pytest

from cutsim.interp import canon
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.modal import InterpConfig
from cutsim.interp.sinumerik import Sinumerik

HEAD = "T1 D1 M6\nG0 X1 Y2 Z30\n"
VARIABLES = {"AXIS_EW": "Y", "INI[107]": 12.5, "INI[54]": 300.0, "$AA_IW[X]": 3.0, "AX_NAMES[1]": "B"}


def run(text: str):
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: 5.0},
                       axes={"B": "rotary", "SP1": "rotary", "W": "linear"}, variables=dict(VARIABLES))
    m = Sinumerik("t.mpf", cfg)
    return m, m.run(HEAD + text + "\nM30\n")


def ends(text: str) -> list:
    return [(r.src.line, tuple(round(v, 9) for v in r.end)) for r in run(text)[1].moves[1:]]


def err(text: str) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text)
    return e.value


def test_the_cam_form_axname_of_a_gud_and_a_user_array():
    # AXIS_EW = "Y": Y goes to INI[107] = 12.5 at F = INI[54] = 300
    _, p = run("G90 G01 AX[AXNAME(AXIS_EW)]=INI[107] F=INI[54]")
    f = p.moves[-1]
    assert isinstance(f, canon.Feed) and f.src.line == 3
    assert f.end == (1.0, 12.5, 30.0) and f.feed == 300.0


def test_axis_variables_and_expressions():
    text = "\n".join([
        'DEF AXIS AXV=AXNAME("x")',  # 3: lower case names the X axis
        "AX[AXV]=5 G1 F100",  # 4: X5
        "AXV=Z",  # 5
        "AX[AXV]=IC(-4)",  # 6: Z 30 - 4 = 26
        "G18",  # 7: the plane Z X, its third axis Y
        "AX[$P_AXN3]=7",  # 8: Y7
        'G17 AX[AXNAME(AXSTRING(X))]=$AA_IW[AXNAME("X")] + 1',  # 9: X = $AA_IW[X] + 1 = 4
        "AXV=AXNAME(AX_NAMES[1])",  # 10: a GUD array element naming B
        "AX[AXV]=30 AX[Y]=-1",  # 11: B turns (no move of its own), Y-1
    ])
    assert ends(text) == [(4, (5.0, 2.0, 30.0)), (6, (5.0, 2.0, 26.0)), (8, (5.0, 7.0, 26.0)), (9, (4.0, 7.0, 26.0)),
                          (11, (4.0, -1.0, 26.0))]


def test_spindles_as_axes():
    m, p = run('DEF STRING[8] TXT\nTXT=AXSTRING(SPI(2))\nR1=AXTOSPI(SPI(3))\nR2=AXTOSPI(AXNAME("s12"))\n'
               'R3=TXT=="S2"\nAX[SPI(1)]=90\nAX[AXNAME("SP1")]=45')
    assert (m.params["R1"], m.params["R2"], m.params["R3"]) == (3.0, 12.0, 1.0)
    assert len(p.moves) == 1  # neither the spindle nor the declared SP1 moves the tool
    msgs = [(s.line, msg) for s, msg in p.warnings]
    assert any(line == 8 and "positions spindle 1" in msg for line, msg in msgs)
    assert any(line == 9 and "rotary axis SP1 moves" in msg for line, msg in msgs)


def test_trans_and_system_variables_take_axis_expressions():
    # TRANS X10 through AX[..]: G0 X0 is machine X10; the system variable index evaluated to its name
    assert ends('TRANS AX[AXNAME("X")]=10\nG0 X0 Y0\nG1 F100 X=$AA_IW[AXSTRING(X)]') == [
        (4, (10.0, 0.0, 30.0)), (5, (13.0, 0.0, 30.0))]


def test_rot_and_mirror_take_axis_expressions():
    # ROT Z90: X10 is (0, 10); MIRROR X0 (replacing the rotation): X10 is (-10, 0)
    assert ends('ROT AX[AXNAME("Z")]=90\nG0 X10 Y0\nMIRROR AX[$P_AXN1]=0\nG0 X10 Y0') == [
        (4, (0.0, 10.0, 30.0)), (6, (-10.0, 0.0, 30.0))]


@pytest.mark.parametrize("text, line, col, fragment", [
    ('G1 F100 AX[AXNAME("Q1")]=5', 3, 9, "axis Q1 is not on this machine"),
    ("G1 F100 AX[Q]=5", 3, 9, "axis Q is not on this machine"),
    ('DEF AXIS AXV=AXNAME("A")', 3, 10, "axis A is not on this machine"),
    ("DEF AXIS AXV\nAXV=U", 4, 1, "axis U is not on this machine"),
    ("R1=AXTOSPI(X)", 3, 4, "axis X is no spindle"),
    ("R1=AXTOSPI(AXNAME(\"S100\"))", 3, 1, "axis S100 is not on this machine"),
    ("R1=SPI(0)", 3, 4, "SPI(0): a spindle number is a whole number from 1 to 99"),
    ("R1=AXNAME(5)", 3, 4, "AXNAME takes a string"),
    ('R1=AXNAME("1X")', 3, 1, '"1X" is no axis name'),
    ("G1 F100 AX[R1]=5", 3, 9, "an axis name is expected here, not the number 0"),
])
def test_bad_axis_expressions(text, line, col, fragment):
    e = err(text)
    assert (e.line, e.col) == (line, col) and fragment in e.message, e.message


def test_an_axis_parameter_of_a_proc(tmp_path):
    """PROC MOVEAX(AXIS AXP, REAL POS): the caller passes an axis bare, by AXNAME or by $P_AXN3."""
    (tmp_path / "MOVEAX.spf").write_text("PROC MOVEAX(AXIS AXP, REAL POS)\nAX[AXP]=POS\nRET\n")
    cfg = InterpConfig(dialect="sinumerik", machine_kind="mill", start=(0.0, 0.0, 50.0), tool_radii={1: 5.0})
    text = HEAD + 'G1 F100\nMOVEAX(Y, 7)\nMOVEAX(AXNAME("X"), 4)\nMOVEAX($P_AXN3, 25)\nMOVEAX(Q, 1)\nM30\n'
    with pytest.raises(CutsimError) as e:
        Sinumerik(str(tmp_path / "main.mpf"), cfg).run(text)
    assert (e.value.line, e.value.col) == (7, 8) and "axis Q is not on this machine" in e.value.message
    p = Sinumerik(str(tmp_path / "main.mpf"), cfg).run(text.replace("MOVEAX(Q, 1)\n", ""))
    assert [r.end for r in p.moves[1:]] == [(1.0, 7.0, 30.0), (4.0, 7.0, 30.0), (4.0, 7.0, 25.0)]
