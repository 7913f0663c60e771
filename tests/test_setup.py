"""The setup loader: defaults, and every error naming the file, the line, the table and the key."""
from __future__ import annotations

import pytest

import cutsim
from cutsim import CutsimError

BASE = """\
[machine]
kind = "lathe"
dialect = "cnc8x6"

[stock]
shape = "cylinder"
diameter = 30.0
z = [-40.0, 0.0]

[[tool]]
number = 9
kind = "thread"
"""


def load(tmp_path, text):
    p = tmp_path / "setup.toml"
    p.write_text(text)
    return cutsim.load_setup(str(p)), p


def error(tmp_path, text) -> CutsimError:
    p = tmp_path / "setup.toml"
    p.write_text(text)
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(p))
    assert str(e.value).startswith(f"{p}:")
    return e.value


def test_defaults(tmp_path):
    s, _ = load(tmp_path, BASE)
    assert s.tolerance == 0.002
    assert s.machine.diameter_programming is True  # CNC8x6 lathes program diameters
    assert s.machine.m03 == "positive"
    assert s.machine.start is None
    t = s.tools[0]
    assert (t.number, t.kind, t.angle, t.tip_radius) == (9, "thread", 60.0, 0.0)
    assert s.fail_on_warning is False and s.parameters == {} and s.constants == {}


def test_constants_parameters_and_start(tmp_path):
    s, _ = load(tmp_path, BASE.replace('dialect = "cnc8x6"\n', 'dialect = "cnc8x6"\nstart = [80, 0, 20]\n'
                                       'm03 = "negative"\n[machine.constants]\n8 = 4000000\n[parameters]\nR04 = -120.0\n'))
    assert s.machine.start == (80.0, 0.0, 20.0) and s.machine.m03 == "negative"
    assert s.constants == {8: 4000000.0} and s.parameters == {4: -120.0}


@pytest.mark.parametrize("insert_after,line_text,fragments", [
    ('dialect = "cnc8x6"', 'colour = "red"', ["[machine]", "colour", "unknown key"]),
    ('z = [-40.0, 0.0]', 'length = 3.0', ["[stock]", "length", "unknown key"]),
    ('kind = "thread"', 'diameter = 3.0', ["[[tool]] #1", "diameter", "unknown key for a thread tool"]),
    ('kind = "thread"', 'angle = "sixty"', ["[[tool]] #1", "angle", "must be a number"]),
    ('kind = "thread"', 'angle = 200.0', ["[[tool]] #1", "angle", "between"]),
    ('dialect = "cnc8x6"', 'm03 = "sideways"', ["[machine]", "m03", "positive or negative"]),
    ('dialect = "cnc8x6"', 'start = [1, 2]', ["[machine]", "start", "three finite numbers"]),
])
def test_bad_key_named_with_its_line(tmp_path, insert_after, line_text, fragments):
    text = BASE.replace(insert_after, insert_after + "\n" + line_text, 1)
    e = error(tmp_path, text)
    assert e.line == text.splitlines().index(line_text) + 1
    for f in fragments:
        assert f in e.message, e.message


def test_bad_values_in_existing_keys(tmp_path):
    e = error(tmp_path, BASE.replace("diameter = 30.0", "diameter = -30.0"))
    assert e.line == 7 and "[stock] diameter" in e.message and "from 0.001" in e.message
    e = error(tmp_path, BASE.replace("z = [-40.0, 0.0]", "z = [0.0, -40.0]"))
    assert e.line == 8 and "[stock] z" in e.message
    e = error(tmp_path, BASE.replace('dialect = "cnc8x6"', 'dialect = "fanuc"'))
    assert e.line == 3 and "[machine] dialect" in e.message
    e = error(tmp_path, BASE + "\n[simulation]\ntolerance = 0.0\n")
    assert "[simulation] tolerance" in e.message and e.line == 15


def test_structure_errors(tmp_path):
    e = error(tmp_path, BASE + "\n[spindle]\nmax = 3\n")
    assert "unknown table [spindle]" in e.message and e.line == 14
    e = error(tmp_path, BASE.replace("[[tool]]\nnumber = 9\nkind = \"thread\"\n", ""))
    assert "at least one [[tool]]" in e.message
    e = error(tmp_path, BASE.replace('kind = "thread"', 'kind = "endmill"\ndiameter = 6.0'))
    assert "[[tool]] #1 kind" in e.message and "does not fit a lathe" in e.message
    e = error(tmp_path, BASE + "\n[[tool]]\nnumber = 9\nkind = \"thread\"\n")
    assert "[[tool]] #2 number" in e.message and "defined twice" in e.message
    e = error(tmp_path, BASE.replace("[stock]", "[stock"))
    assert e.line == 5 and "not valid TOML" in e.message
    e = error(tmp_path, BASE + "\n[parameters]\nP4 = 1.0\n")
    assert "[parameters] P4" in e.message


def test_max_blocks(tmp_path):
    s, _ = load(tmp_path, BASE)
    assert s.max_blocks == 5_000_000
    s, _ = load(tmp_path, BASE + "\n[simulation]\nmax_blocks = 1000\n")
    assert s.max_blocks == 1000
    for bad, why in (("0", "at least 1"), ("1e6", "whole number"), ('"many"', "whole number")):
        e = error(tmp_path, BASE + f"\n[simulation]\nmax_blocks = {bad}\n")
        assert "[simulation] max_blocks" in e.message and why in e.message and e.line == 15
