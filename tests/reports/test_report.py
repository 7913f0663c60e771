"""report.json fields from the canonical records: last_cut_position (where the last cutting motion
leaves the tool, as opposed to final_position after a retract) and where subprogram warnings were
called from."""
from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import pytest
from click.testing import CliRunner

import cutsim
from conftest import EXAMPLES
from cutsim.cli import main
from cutsim.interp import InterpConfig, interpret
from cutsim.reports.report import warning_text

HERE = Path(__file__).resolve().parents[1]


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


SUBS = """%L Innen
N200 G01 X60 Z95 ; no F programmed: a warning at this line, per call site
N210 G00 X150
N220 M29
%L Aussen
N100 LL Innen
N110 M29
%Haupt
N10 G00 X150 Z200
N20 M03 S400
N30 LL Aussen
N40 M30
"""


def test_subprogram_warning_says_where_it_was_called_from(tmp_path):
    prog = tmp_path / "subs.nc"
    prog.write_text(SUBS)
    out = tmp_path / "out"
    res = CliRunner().invoke(main, ["simulate", str(prog), "--setup", str(HERE / "data" / "programs" / "isg" / "short.toml"), "--out", str(out), "-q"])
    assert res.exit_code == 0, res.output
    err = res.stderr if hasattr(res, "stderr") else res.output
    # Innen's line 2 runs from Aussen's call at line 6, which runs from the main program's line 11
    assert f"{prog}:2:1: warning: feed motion with no feed rate" in err
    assert err.rstrip().endswith(f"(called from {prog}:6, from {prog}:11)")
    (w,) = json.loads((out / "report.json").read_text())["warnings"]
    assert (w["line"], w["called_from"]) == (2, [6, 11])


def test_main_program_warning_has_no_call_sites(tmp_path):
    prog = tmp_path / "main.nc"
    prog.write_text("%Haupt\nN10 G00 X150 Z200\nN20 G01 X60 Z95\nN30 M30\n")
    r = cutsim.simulate(str(prog), str(HERE / "data" / "programs" / "isg" / "short.toml"), tolerance=0.1)
    (w,) = r.report["warnings"]
    assert w["line"] == 3 and "called_from" not in w


def test_sinumerik_spf_warning_names_its_file_and_the_caller(tmp_path):
    setup = tmp_path / "s.toml"
    setup.write_text('[machine]\nkind = "mill"\ndialect = "sinumerik"\nstart = [0, 0, 50]\n'
                     '[stock]\nshape = "box"\nx = [0, 10]\ny = [0, 10]\nz = [0, 10]\n'
                     '[[tool]]\nkind = "endmill"\ndiameter = 2.0\n')
    (tmp_path / "outer.spf").write_text("G0 Z40\nINNER\nM17\n")
    (tmp_path / "inner.spf").write_text("G1 X30 Y30\nM17\n")  # no F: a warning on inner.spf line 1
    main = tmp_path / "main.mpf"
    main.write_text("T1 D1 M6\nG0 X20 Y20 Z60\nOUTER\nM30\n")
    r = cutsim.simulate(str(main), str(setup), tolerance=0.1)
    (w,) = r.report["warnings"]
    assert (w["program"], w["line"]) == (str(tmp_path / "inner.spf"), 1)
    assert w["called_from"] == [2, 3]
    assert w["called_from_programs"] == [str(tmp_path / "outer.spf"), str(main)]
    assert warning_text(w).endswith(f"(called from {tmp_path / 'outer.spf'}:2, from {main}:3)")
    # errors while running a .spf line name that file too
    (tmp_path / "inner.spf").write_text("G1 X30 Y30 F100\nGOTOF NOWHERE\nM17\n")
    with pytest.raises(cutsim.CutsimError) as e:
        cutsim.simulate(str(main), str(setup), tolerance=0.1)
    assert (e.value.program, e.value.line) == (str(tmp_path / "inner.spf"), 2)
