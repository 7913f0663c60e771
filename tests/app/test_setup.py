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
    assert s.max_blocks == 1_000_000
    s, _ = load(tmp_path, BASE + "\n[simulation]\nmax_blocks = 1000\n")
    assert s.max_blocks == 1000
    for bad, why in (("0", "at least 1"), ("1e6", "whole number"), ('"many"', "whole number")):
        e = error(tmp_path, BASE + f"\n[simulation]\nmax_blocks = {bad}\n")
        assert "[simulation] max_blocks" in e.message and why in e.message and e.line == 15


# -- ranges, wrong types and where they are reported ------------------------------------------------
def _at(text: str, needle: str) -> tuple[int, int]:
    """1-based line and column of the first ``needle`` in ``text`` (the expected error position)."""
    i = text.index(needle)
    line = text.count("\n", 0, i) + 1
    return line, i - (text.rfind("\n", 0, i) + 1) + 1


BODY = BASE.split("\n\n", 1)[1]  # everything after the [machine] table


@pytest.mark.parametrize("text,needle,fragments", [
    # a top-level table given as a value of another type: at that key
    ("machine = 5\n" + BODY, "machine", ["[machine] must be a table, not 5"]),
    ("simulation = 1\n" + BASE, "simulation", ["[simulation] must be a table"]),
    ("parameters = [1]\n" + BASE, "parameters", ["[parameters] must be a table"]),
    ("stock = \"bar\"\n" + BASE.replace("[stock]\nshape = \"cylinder\"\ndiameter = 30.0\nz = [-40.0, 0.0]\n", ""),
     "stock", ["[stock] must be a table"]),
    # array elements that are not tables: at the element
    ("tool = [1, 2]\n" + BASE.replace('[[tool]]\nnumber = 9\nkind = "thread"\n', ""), "1, 2",
     ["[[tool]] #1 must be a table, not 1"]),
    ("check = 3\n" + BASE, "check = 3", ["[[check]]"]),
    # nested tables of the wrong type
    (BASE.replace('dialect = "cnc8x6"', 'dialect = "cnc8x6"\nconstants = 5'), "constants",
     ["[machine] constants", "must be a table"]),
    # numbers out of range or not finite
    (BASE.replace('shape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]',
                  'shape = "box"\nx = [0, inf]\ny = [0, 1]\nz = [0, 1]'), "x = [0, inf]", ["[stock] x", "finite"]),
    (BASE.replace("diameter = 30.0", "diameter = 1e-9"), "diameter", ["[stock] diameter", "0.001"]),
    (BASE.replace("diameter = 30.0", "diameter = nan"), "diameter", ["[stock] diameter", "must be a number"]),
    (BASE.replace("z = [-40.0, 0.0]", "z = [-40.0, -39.9999]"), "z = ", ["[stock] z", "at least 0.001 mm"]),
    (BASE.replace("z = [-40.0, 0.0]", "z = [-1e6, 0.0]"), "z = ", ["[stock] z", "100000"]),
    (BASE.replace('dialect = "cnc8x6"', 'dialect = "cnc8x6"\nstart = [nan, 40, 50]'), "start",
     ["[machine] start", "finite"]),
    (BASE.replace('dialect = "cnc8x6"', 'dialect = "cnc8x6"\nstart = [1e9, 40, 50]'), "start",
     ["[machine] start", "100000"]),
    (BASE.replace('dialect = "cnc8x6"', 'dialect = "cnc8x6"\nrapid = 1e300'), "rapid", ["[machine] rapid"]),
    (BASE + "[parameters]\nR4 = 1e300\n", "R4", ["[parameters] R4", "within"]),
    (BASE + "[machine.constants]\n8 = -inf\n", "8 =", ["[machine.constants] 8", "must be a number"]),
    (BASE + "[simulation]\nmax_triangles = 10\n", "max_triangles", ["[simulation] max_triangles", "1,000"]),
    (BASE + "[simulation]\nmax_blocks = 10000000000000\n", "max_blocks", ["[simulation] max_blocks"]),
    (BASE.replace('shape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]',
                  'shape = "revolve"\nprofile = [\n  [0, 0],\n  [10, 0],\n  [10, 1e-4],\n  [0, 1e-4],\n]'),
     "profile", ["[stock] profile", "0.001"]),
])
def test_bad_setup_at_its_line_and_column(tmp_path, text, needle, fragments):
    e = error(tmp_path, text)
    assert (e.line, e.col) == _at(text, needle), (str(e), _at(text, needle))
    for f in fragments:
        assert f in e.message, e.message


def test_dotted_keys_and_inline_tables_are_located(tmp_path):
    # `machine.kind` written as a dotted key on line 4: the error names line 4, the column of `kind`
    text = "# setup\n\n\nmachine.kind = \"lathes\"\nmachine.dialect = \"cnc8x6\"\n" + BODY
    e = error(tmp_path, text)
    assert (e.line, e.col) == (4, 9) and "[machine] kind" in e.message
    text = ('stock.shape = "cylinder"\nstock.diameter = 30.0\n\nstock.z = [0.0, -40.0]\n' +
            BASE.replace('[stock]\nshape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]\n', ""))
    e = error(tmp_path, text)
    assert (e.line, e.col) == (4, 7) and "[stock] z" in e.message
    text = ('stock = {shape = "cylinder", diameter = 30.0, z = [0, inf]}\n' +
            BASE.replace('[stock]\nshape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]\n', ""))
    e = error(tmp_path, text)
    assert (e.line, e.col) == _at(text, "z = [0, inf]") and "[stock] z" in e.message
    # an array of inline tables: the second tool's key
    text = ('tool = [\n  {number = 9, kind = "thread"},\n  {number = 8, kind = "thread", angle = "x"},\n]\n' +
            BASE.replace('[[tool]]\nnumber = 9\nkind = "thread"\n', ""))
    e = error(tmp_path, text)
    assert (e.line, e.col) == _at(text, 'angle = "x"') and "[[tool]] #2 angle" in e.message
    # multi-line arrays (lines starting with "[") are values, not table headers
    text = BASE.replace('shape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]',
                        'shape = "revolve"\nprofile = [\n  [0, 0],\n  [10, 0],\n  [10, 5],\n]\ncolour = 1')
    e = error(tmp_path, text)
    assert (e.line, e.col) == _at(text, "colour") and "[stock] colour: unknown key" in e.message
    # the second [[tool]] table's key
    text = BASE + '\n[[tool]] # two\nnumber = 8\nkind = "thread"\nangle = 500\n'
    e = error(tmp_path, text)
    assert (e.line, e.col) == _at(text, "angle = 500") and "[[tool]] #2 angle" in e.message


def test_byte_order_mark_is_accepted(tmp_path):
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + BASE.encode())
    s = cutsim.load_setup(str(p))
    assert s.stock.diameter == 30.0 and s.tools[0].number == 9


def test_non_utf8_setup_names_the_bad_byte(tmp_path):
    p = tmp_path / "latin.toml"
    text = BASE.replace('kind = "thread"', 'kind = "thr\xe9ad"')
    p.write_bytes(text.encode("latin-1"))
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(p))
    assert (e.value.line, e.value.col) == _at(text, "\xe9") and "not UTF-8" in e.value.message
    p.write_bytes(b"\xef\xbb\xbf" + 'a = "\xe9"\n'.encode("latin-1"))  # after a BOM, columns count from the text
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(p))
    assert (e.value.line, e.value.col) == (1, 6)


def test_max_triangles(tmp_path):
    from cutsim.stock.build import DEFAULT_MAX_TRIANGLES

    s, _ = load(tmp_path, BASE)
    assert s.max_triangles == DEFAULT_MAX_TRIANGLES
    s, _ = load(tmp_path, BASE + "\n[simulation]\nmax_triangles = 20000000\n")
    assert s.max_triangles == 20_000_000
    e = error(tmp_path, BASE + "\n[simulation]\nmax_triangles = 1.5e7\n")
    assert "[simulation] max_triangles" in e.message and "whole number" in e.message and e.line == 15


def test_big_revolve_profile_over_the_limit(tmp_path):
    """2000 outline points on a 30 mm bar at 0.002 mm: ~ 2 * 2000 * 216 segments > 100k triangles."""
    pts = [[0, 0]] + [[15 + (i % 2) * 0.01, -i * 0.01] for i in range(2000)] + [[0, -20]]
    text = BASE.replace('shape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]',
                        f'shape = "revolve"\nprofile = {pts}') + "\n[simulation]\nmax_triangles = 100000\n"
    e = error(tmp_path, text)
    assert (e.line, e.col) == _at(text, "profile") and "max_triangles" in e.message


def test_toml_error_at_the_end_of_the_file(tmp_path):
    # tomllib gives no position for errors at the end of the document: the end of the text is it
    e = error(tmp_path, "[machi")
    assert (e.line, e.col) == (1, 7) and "not valid TOML" in e.message
    e = error(tmp_path, '[machine]\nkind = "lathe"\nx = [1,\n')
    assert (e.line, e.col) == (4, 1)


@pytest.mark.parametrize("where,text", [
    ("[stock] diameter", BASE.replace("diameter = 30.0", "diameter = " + "9" * 400)),
    ("[stock] z", BASE.replace("z = [-40.0, 0.0]", "z = [-" + "9" * 400 + ", 0.0]")),
    ("[[tool]] #1 tip_radius", BASE + "tip_radius = " + "1" * 320 + "\n"),
], ids=["scalar", "pair", "tool"])
def test_an_integer_too_big_for_a_float_is_an_error_at_its_key(tmp_path, where, text):
    """TOML integers have no size limit; one past the float range (1.8e308) is a bad number at its
    key, not an OverflowError (fuzz case 20261124/1517 exited 3), and the message stays short."""
    e = error(tmp_path, text)
    assert where in e.message and len(e.message) < 200


def test_max_blocks_ceiling_is_ten_million(tmp_path):
    """docs/setup.md: max_blocks is a whole number from 1 to 10,000,000 (every executed move is held
    until the run ends, about 0.65 KB each); one more is an error at the key."""
    s, _ = load(tmp_path, BASE + "\n[simulation]\nmax_blocks = 10000000\n")
    assert s.max_blocks == 10_000_000
    e = error(tmp_path, BASE + "\n[simulation]\nmax_blocks = 10000001\n")
    assert "[simulation] max_blocks" in e.message and "10,000,000" in e.message


def test_number_with_more_digits_than_python_converts(tmp_path):
    """tomllib raises a plain ValueError (not TOMLDecodeError) for an integer of more than 4300
    digits: it is a TOML error at the number, not an internal error."""
    e = error(tmp_path, "[machine]\nkind = " + "1" * 5000 + "\n")
    assert (e.line, e.col) == (2, 8) and "too many digits" in str(e)
