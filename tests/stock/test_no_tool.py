"""Moves with no tool in the spindle (Sinumerik T0 M6; canon.ToolChange(tool=None)): they run, remove
nothing, and warn where the gauge point (the spindle nose) runs inside the material still there
(kinematics.GaugePath, stock/gauge.py). Expected lengths and volumes come from the geometry: a
segment clipped against a box, a slot of a flat end mill as a stadium prism."""
from __future__ import annotations

import json
import math

import manifold3d as m3d
import numpy as np
import pytest
from click.testing import CliRunner

import cutsim
from cutsim.base.specs import MachineSpec, StockSpec, ToolSpec
from cutsim.cli import main
from cutsim.interp import canon
from cutsim.kinematics import GaugePath, plan
from cutsim.stock import build_stock, remove
from cutsim.stock.gauge import inside_length

SETUP = """[machine]
kind = "mill"
dialect = "sinumerik"
start = [0.0, 0.0, 10.0]

[stock]
shape = "box"
x = [-20.0, 20.0]
y = [-20.0, 20.0]
z = [-10.0, 0.0]

[[tool]]
number = 1
kind = "endmill"
diameter = 10.0
length = 40.0
"""
STOCK = 40.0 * 40.0 * 10.0


def run(tmp_path, text: str) -> tuple[int, dict]:
    (tmp_path / "setup.toml").write_text(SETUP)
    (tmp_path / "p.mpf").write_text(text)
    res = CliRunner().invoke(main, ["simulate", str(tmp_path / "p.mpf"), "--setup", str(tmp_path / "setup.toml"),
                                    "--out", str(tmp_path / "out"), "-q"])
    assert "Traceback" not in res.output
    report = json.loads((tmp_path / "out" / "report.json").read_text()) if res.exit_code in (0, 1) else {}
    return res.exit_code, report


def test_the_cam_post_unload_runs_and_removes_nothing(tmp_path):
    # the reproducer: unload, preselect T1 (no M6), spindle on at S0, a feed at Z10 over the stock
    code, rep = run(tmp_path, "T00 M06\nT01\nS0 M03\nG01 X8. Y0.0 F3000\nM30\n")
    assert code == 0
    assert rep["removed_volume"] == pytest.approx(0.0, abs=1e-9)
    assert rep["part_volume"] == pytest.approx(STOCK, rel=1e-12)
    assert rep["warnings"] == []
    assert rep["final_position"] == [8.0, 0.0, 10.0]


def test_a_no_tool_feed_through_the_stock_warns_once_at_its_line(tmp_path):
    code, rep = run(tmp_path, "T0 M6\nG0 X-30 Y5 Z-5\nG1 X30 F300\nG0 Z10\nM30\n")
    assert code == 0
    assert rep["removed_volume"] == pytest.approx(0.0, abs=1e-9)
    assert [(w["line"], w["message"]) for w in rep["warnings"]] == [
        (3, "no tool in the spindle: its gauge point (the spindle nose) runs 40.000 mm inside the stock; "
            "the move removes nothing")]  # X-20 to X20: the stock's width


def test_what_the_tool_cut_before_is_no_longer_there(tmp_path):
    """T1 cuts a slot 2 deep from X-30 to X-10 at Y0; after T0 M6 the spindle nose goes down into
    the slot (no warning), then 1 mm into material still there at X0 and out again (a warning at
    each of those two lines).
    The part is the stock minus the slot: a 10 wide rectangle from the stock's edge at X-20 to
    X-10 plus the half disc of the tool at X-10, 2 deep."""
    code, rep = run(tmp_path, "T1 M6\nS1000 M3\nG0 X-30 Y0 Z-2\nG1 X-10 F300\nG0 Z10\nT0 M6\n"
                              "G0 X-15\nG1 Z-1.5\nG0 Z10\nX0\nG1 Z-1\nG0 Z10\nM30\n")
    assert code == 0
    slot = (10.0 * 10.0 + math.pi * 5.0 ** 2 / 2.0) * 2.0
    assert rep["removed_volume"] == pytest.approx(slot, rel=1e-3)  # the tool circle's chords: within 0.1 %
    assert rep["part_volume"] == pytest.approx(STOCK - slot, rel=1e-4)
    assert [(w["line"], w["message"].split(" runs ")[1][:9]) for w in rep["warnings"]] == [(11, "1.000 mm "),
                                                                                           (12, "1.000 mm ")]


def test_on_the_surface_is_not_inside(tmp_path):
    code, rep = run(tmp_path, "T0 M6\nG1 Z0 F300\nX15 Y15\nG0 Z10\nM30\n")  # down onto the top face, along it
    assert code == 0 and rep["warnings"] == []


def test_a_lathe_without_a_tool_cuts_nothing():
    """The kinematics and the geometry are dialect-neutral: a record list with the spindle emptied
    on a lathe: a turning feed 5 mm into a 40 mm bar (at radius 15 over 10 mm) warns and removes
    nothing; the same with the tool removes the ring and the cone its flank leaves."""
    tool = ToolSpec(1, "turning", angle=55.0)
    machine = MachineSpec(kind="lathe", diameter_programming=True)
    spec = StockSpec("cylinder", diameter=40.0, z=(-50.0, 0.0))
    stock = build_stock(spec, 0.01)
    src = canon.Src("t", 3)
    moves = [canon.Spindle(canon.Src("t", 1), 1, 500.0), canon.Rapid(src, (50.0, 0.0, 2.0), (30.0, 0.0, 2.0), True),
             canon.Feed(canon.Src("t", 4), (30.0, 0.0, 2.0), (30.0, 0.0, -10.0), True, 0.1, True)]
    for change, cut in ((canon.ToolChange(canon.Src("t", 2), None), False), (canon.ToolChange(canon.Src("t", 2), 1), True)):
        program = canon.Program("t", "cnc8x6", [change] + moves)
        pl = plan(program, machine, [tool], 0.01)
        assert all(isinstance(p, GaugePath) for p in pl.paths) != cut
        removal = remove(stock, spec, pl.paths, 0.01)
        removed = stock.volume() - removal.part.volume()
        if cut:
            # the ring, plus what the leading flank (27.5 degrees off the radial) takes below Z-10:
            # the triangle z > -10 - (r - 15) tan 27.5, revolved: 2 pi tan 27.5 * int (r^2 - 15 r) dr
            flank = 2 * math.pi * math.tan(math.radians(27.5)) * ((20 ** 3 - 15 ** 3) / 3 - 15 * (20 ** 2 - 15 ** 2) / 2)
            assert removed == pytest.approx(math.pi * (20.0 ** 2 - 15.0 ** 2) * 10.0 + flank, rel=2e-3)
        else:
            assert removed == pytest.approx(0.0, abs=1e-9)
            assert [(s.line, m.split(" runs ")[1][:6]) for s, m in removal.warnings] == [(4, "10.000")]


def _clip(a, b, lo, hi) -> tuple[float, float] | None:
    """The parameters [t0, t1] of segment a->b inside the box (Liang-Barsky)."""
    t0, t1 = 0.0, 1.0
    for k in range(3):
        d = b[k] - a[k]
        if abs(d) < 1e-12:
            if not lo[k] < a[k] < hi[k]:
                return None
            continue
        u, v = sorted(((lo[k] - a[k]) / d, (hi[k] - a[k]) / d))
        t0, t1 = max(t0, u), min(t1, v)
    return (t0, t1) if t1 > t0 else None


def test_inside_length_is_the_segment_clipped_by_the_box():
    """Property test over 300 random segments against a box: the length inside is the clipped
    segment's, whenever the clipped piece's middle lies deeper than a few tolerances (a piece that
    only touches the box within the tolerance counts as not inside, by definition)."""
    rng = np.random.default_rng(20261126)
    lo, hi = np.array([-20.0, -15.0, -10.0]), np.array([20.0, 15.0, 0.0])
    box = m3d.Manifold.cube(tuple(hi - lo)).translate(tuple(lo))
    tol = 0.002
    checked = 0
    for _ in range(300):
        a, b = rng.uniform(lo - 15, hi + 15), rng.uniform(lo - 15, hi + 15)
        span = _clip(a, b, lo, hi)
        got = inside_length(box, np.array([a, b]), tol)
        if span is None:
            assert got == 0.0
            continue
        mid = a + (b - a) * (0.5 * sum(span))
        if min(np.min(mid - lo), np.min(hi - mid)) < 5 * tol:
            continue
        checked += 1
        assert got == pytest.approx((span[1] - span[0]) * float(np.linalg.norm(b - a)), abs=1e-6)
    assert checked > 50


LATHE = """[machine]
kind = "lathe"
dialect = "{dialect}"
diameter_programming = true

[stock]
shape = "cylinder"
diameter = 40.0
z = [-50.0, 0.0]

[[tool]]
number = {number}
kind = "turning"
angle = 55.0
tip_radius = 0.0
"""


@pytest.mark.parametrize("dialect", ["cnc8x6", "isg"])
def test_t0_elsewhere_is_the_tool_numbered_0(tmp_path, dialect):
    """CNC8x6 and ISG define no empty spindle: T0 without a tool 0 in the setup is exit 2 at its
    block; with [[tool]] number = 0 it is that tool, which cuts (a 0.5 mm deep pass from Z2 to Z-10)."""
    prog = tmp_path / "p.nc"
    prog.write_text("N10 G00 X50 Z2 T0 M03 S500\nN20 X38\nN30 G01 Z-10 F0.2\nN40 G00 X50\nN50 M30\n")
    for number, code in ((1, 2), (0, 0)):
        setup = tmp_path / "s.toml"
        setup.write_text(LATHE.format(dialect=dialect, number=number))
        out = tmp_path / f"out{number}"
        res = CliRunner().invoke(main, ["simulate", str(prog), "--setup", str(setup), "--out", str(out), "-q"])
        assert res.exit_code == code, res.output
        if code == 2:
            assert res.output.startswith(f"{prog}:1:1: error: tool T0 is not in the setup (tools: T1)")
            assert "only on a Sinumerik" in res.output
        else:
            # the ring r 19..20 over Z0..-10 and what the leading flank takes below Z-10
            flank = 2 * math.pi * math.tan(math.radians(27.5)) * ((20 ** 3 - 19 ** 3) / 3 - 19 * (20 ** 2 - 19 ** 2) / 2)
            removed = json.loads((out / "report.json").read_text())["removed_volume"]
            assert removed == pytest.approx(math.pi * (20 ** 2 - 19 ** 2) * 10 + flank, rel=3e-3)
