"""report.json fields from the canonical records: last_cut_position (where the last cutting motion
leaves the tool, as opposed to final_position after a retract) and where subprogram warnings were
called from."""
from __future__ import annotations

import math
import tomllib

import pytest

import cutsim
from conftest import EXAMPLES
from cutsim.interp import InterpConfig, interpret


def _interpret(example: str):
    nc = EXAMPLES / example
    setup = tomllib.loads(nc.with_suffix(".toml").read_text())
    m = setup["machine"]
    cfg = InterpConfig(dialect=m["dialect"], machine_kind=m["kind"], diameter_programming=m.get("diameter_programming", False),
                       start=tuple(m["start"]), constants={int(k): v for k, v in m.get("constants", {}).items()})
    return interpret(nc.name, nc.read_text(), cfg)


def test_helix_last_cut_is_the_end_of_the_helix():
    # N50 cuts 21 full circles (Q20) and N60 half a circle to X200 Y0, Z rising 1.05 per turn;
    # N80 then rapids to X100 Y0 Z40
    prog = _interpret("cnc8x6-mill/helix.nc")
    pitch, turns = 1.05, 20 + 1 + 0.5
    assert prog.last_cut_position == pytest.approx((200.0, 0.0, turns * pitch), abs=1e-9)
    assert turns * pitch == pytest.approx(22.575)
    assert prog.final_position == pytest.approx((100.0, 0.0, 40.0))


def test_thread_last_cut_includes_the_runout():
    # N30 G33 to X64 Z-100 with a 12 mm runout at 12.5 degrees towards +X (machine constant 8):
    # the tool leaves the thread 12 tan(12.5) further out in radius, twice that in diameter
    prog = _interpret("cnc8x6-lathe/runout-constant.nc")
    x = 64.0 + 2 * 12.0 * math.tan(math.radians(12.5))
    assert prog.last_cut_position == pytest.approx((x, 0.0, -100.0), abs=1e-9)
    assert prog.final_position == pytest.approx((64.0, 0.0, -100.0))  # N50 rapids back


def test_report_without_a_cut(tmp_path):
    setup = tmp_path / "s.toml"
    setup.write_text('[machine]\nkind = "mill"\ndialect = "cnc8x6"\nstart = [0, 0, 50]\n'
                     '[stock]\nshape = "box"\nx = [0, 10]\ny = [0, 10]\nz = [0, 10]\n'
                     '[[tool]]\nkind = "endmill"\ndiameter = 2.0\n')
    prog = tmp_path / "p.nc"
    prog.write_text("N10 G00 X20 Y20\nN20 G01 X30 F100\nN30 G00 Z60\n")
    r = cutsim.simulate(str(prog), str(setup), tolerance=0.1)
    assert r.report["last_cut_position"] == [30.0, 20.0, 50.0]
    assert r.report["final_position"] == [30.0, 20.0, 60.0]
    prog.write_text("N10 G00 X20 Y20\nN30 G00 Z60\n")
    r = cutsim.simulate(str(prog), str(setup), tolerance=0.1)
    assert r.report["last_cut_position"] is None
