"""One registry of dialects (interp.DIALECTS): a dialect is one module plus one entry. The toy
dialect (tests/support/toy_dialect.py) is registered here with one line and runs through the interpreter."""
from __future__ import annotations

import math

import pytest

from cutsim.interp import DIALECTS, Dialect, InterpConfig, available_dialects, canon, dialect_module, interpret
from cutsim.interp.core import sweep_degrees

TOY = Dialect("support.toy_dialect", True, (".toy",), "toy dialect of the tests")

# A groove on a 30 mm bar (X in diameters): in at X26, 20 mm along Z, out along a quarter circle
# of radius 2 about (X30, Z-22) to X30 (diameter: the radius 2 counts twice on X), then away.
PROGRAM = """\
T9 S500 M3 ; tool 9, spindle on
G0 X32 Z2
G0 X26
G1 Z-20 F0.2
G2 X30 Z-22 I2 K0 ; I is the centre's radius offset
G0 X32
G0 Z2
M30
G1 X0 ; after the end: never runs
"""


@pytest.fixture
def toy(monkeypatch):
    monkeypatch.setitem(DIALECTS, "toy", TOY)  # the one registry line a new dialect needs
    return "toy"


def test_every_registered_module_imports():
    assert available_dialects() == list(DIALECTS)
    for name in DIALECTS:
        assert callable(dialect_module(name).interpret)


def test_a_missing_module_is_not_hidden(monkeypatch):
    monkeypatch.setitem(DIALECTS, "ghost", Dialect(".no_such_module", False, (".nc",), "missing"))
    assert "ghost" in available_dialects()
    with pytest.raises(ModuleNotFoundError):
        interpret("p.nc", "G0 X1\n", InterpConfig(dialect="ghost"))


def test_toy_dialect_interprets(toy):
    cfg = InterpConfig(dialect=toy, machine_kind="lathe", diameter_programming=True, start=(40.0, 0.0, 10.0))
    prog = interpret("p.toy", PROGRAM, cfg)
    assert prog.blocks == 8  # the block after M30 does not run
    kinds = [type(r).__name__ for r in prog.records]
    assert kinds == ["Spindle", "ToolChange", "Rapid", "Rapid", "Feed", "Arc", "Rapid", "Rapid", "ProgramEnd"]
    arc = prog.records[5]
    assert isinstance(arc, canon.Arc) and arc.clockwise and arc.plane == "ZX"
    assert arc.start == (26.0, 0.0, -20.0) and arc.end == (30.0, 0.0, -22.0)
    # centre 2 mm (radius) beyond the start on X: X26 + 2*2 on the diameter
    assert arc.center == (30.0, 0.0, -20.0)
    assert sweep_degrees(arc.start, arc.end, arc.center, "ZX", True, True) == pytest.approx(90.0)  # a quarter
    assert sweep_degrees(arc.start, arc.end, arc.center, "ZX", False, True) == pytest.approx(270.0)
    assert math.isclose(prog.records[4].feed, 0.2)
    assert prog.final_position == (32.0, 0.0, 2.0)


def test_toy_dialect_errors_come_from_the_shared_executor(toy):
    from cutsim.interp import CutsimError

    cfg = InterpConfig(dialect=toy)
    with pytest.raises(CutsimError) as e:
        interpret("p.toy", "G0 X1\nG1 G0 X2\n", cfg)
    assert (e.value.line, e.value.col) == (2, 4) and "G0 conflicts with G1" in e.value.message
    with pytest.raises(CutsimError) as e:
        interpret("p.toy", "G33 Z1\n", cfg)
    assert (e.value.line, e.value.col) == (1, 1) and e.value.message == "unknown G code G33"


def test_toy_dialect_simulates_with_its_registry_defaults(toy, tmp_path):
    """Through cutsim.simulate: the setup accepts the registered name, and X is a diameter because
    the registry entry says so (the setup leaves diameter_programming out). The groove at X26 leaves
    a 26 mm diameter along it and the 30 mm bar beyond it."""
    import cutsim

    setup = tmp_path / "toy.toml"
    setup.write_text(f'[machine]\nkind = "lathe"\ndialect = "{toy}"\nstart = [40, 0, 10]\n\n'
                     '[stock]\nshape = "cylinder"\ndiameter = 30.0\nz = [-40.0, 0.0]\n\n'
                     '[[tool]]\nnumber = 9\nkind = "thread"\ntip_radius = 0.0\n\n[simulation]\ntolerance = 0.01\n')
    assert cutsim.load_setup(str(setup)).machine.diameter_programming is True
    res = cutsim.simulate("groove.toy", str(setup), text=PROGRAM)
    assert res.diameters_at(-10.0) == pytest.approx(26.0, abs=0.02)  # X26 on the diameter, within the chords
    assert res.diameters_at(-30.0) == pytest.approx(30.0, abs=0.02)  # never cut
