"""[[check]] tables: each kind passes on a correct program and fails on a wrong one. Expected
values are analytic (program words, tool sizes), never read back from cutsim."""
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

import cutsim
from cutsim.interp.errors import CutsimError
from cutsim.testing import make_check_spec
from cutsim.reports.checks import evaluate

HERE = Path(__file__).resolve().parents[1] / "data" / "programs" / "checks"


def _sim(nc, toml, **kw):
    return cutsim.simulate(str(HERE / nc), str(HERE / toml), **kw)


@pytest.fixture(scope="module")
def lathe_good():
    return _sim("multipass.nc", "multipass.toml")


@pytest.fixture(scope="module")
def lathe_bad():  # last pass X26.277: 0.05 mm radially shallower
    return _sim("multipass-shallow.nc", "multipass.toml")


@pytest.fixture(scope="module")
def mill_good():
    return _sim("slot.nc", "slot.checks.toml")


def _by_name(result, name):
    return next(c for c in result.checks if c["name"] == name)


def _item(rec, q):
    return next(i for i in rec["items"] if i["quantity"] == q)


def test_thread_passes_on_the_program(lathe_good):
    rec = _by_name(lathe_good, "M27x1.5 thread")
    assert rec["passed"], rec
    assert abs(_item(rec, "lead")["measured"] - 1.5) < 0.002
    assert _item(rec, "hand")["measured"] == "right"
    assert _item(rec, "starts")["measured"] == 1
    assert abs(_item(rec, "root_diameter")["measured"] - 26.177) <= 0.02  # chords lie inside: <= 2 * tolerance
    assert abs(_item(rec, "phase[1]")["measured"]) < 1.0


def test_thread_fails_when_the_last_pass_is_shallow(lathe_bad):
    rec = _by_name(lathe_bad, "M27x1.5 thread")
    assert not rec["passed"]
    assert not _item(rec, "root_diameter")["passed"]
    assert abs(_item(rec, "root_diameter")["measured"] - 26.277) <= 0.02
    assert _item(rec, "lead")["passed"] and _item(rec, "phase[1]")["passed"]


def test_thread_wrong_phase_and_hand_fail(lathe_good):
    rec = lathe_good.check(kind="thread", z=[-6.0, -1.0], lead=1.5, hand="left", phase=[90.0], phase_z=3.0)
    assert not _item(rec, "hand")["passed"]
    rec = lathe_good.check(kind="thread", z=[-6.0, -1.0], lead=1.5, phase=[90.0], phase_z=3.0)
    assert not _item(rec, "phase[1]")["passed"]
    # the groove at angle 0 sits at z = 3 (mod 1.5): phase_z 3.375 is a quarter lead on -> phase -90
    rec = lathe_good.check(kind="thread", z=[-6.0, -1.0], lead=1.5, phase=[270.0], phase_z=3.375)
    assert rec["passed"], rec


def test_diameter(lathe_good):
    assert _by_name(lathe_good, "undercut")["passed"]  # the blank's undercut, diameter 25
    rec = lathe_good.check(kind="diameter", z=-20.0, expected=27.0, tolerance=0.02)
    assert rec["passed"], rec
    rec = lathe_good.check(kind="diameter", z=-3.0, expected=27.0, tolerance=0.02)  # threaded: min at the groove
    assert not _item(rec, "diameter_min")["passed"] and _item(rec, "diameter_max")["passed"]


def test_ramp_runout(examples):
    p = examples / "cnc8x6-lathe" / "runout-constant.nc"
    r = cutsim.simulate(str(p), str(p.with_suffix(".toml")), tolerance=0.01)
    # J12 at 12.5 degrees ending at Z-100: root radius 32 at Z-88 rising by 12*tan(12.5) at Z-100
    rise = math.tan(math.radians(12.5))
    good = dict(kind="ramp", z=[-98.0, -88.5], radius=[32 + 10 * rise, 32 + 0.5 * rise], tolerance=0.02, step=0.5)
    rec = r.check(**good)
    assert rec["passed"], rec
    wrong = dict(good, radius=[32 + 10 * math.tan(math.radians(15)), 32 + 0.5 * math.tan(math.radians(15))])
    assert not r.check(**wrong)["passed"]


def test_mill_checks_pass(mill_good):
    for rec in mill_good.checks:
        assert rec["passed"], rec
    assert abs(_item(_by_name(mill_good, "slot"), "width")["measured"] - 8.0) <= 0.01


def test_mill_checks_fail_on_a_shallow_slot():
    r = _sim("slot-shallow.nc", "slot.checks.toml")
    failed = {c["name"] for c in r.checks if not c["passed"]}
    assert failed == {"slot", "volume #3", "design #4"}
    rec = _by_name(r, "design #4")
    # 0.05 mm over the slot's footprint, plus the chordal excess of the polygonal tool (< 0.8 mm^3)
    assert 0 <= rec["details"]["excess_volume"] - 0.05 * (8 * 30 + math.pi * 8) < 0.8
    assert abs(rec["details"]["worst_deviation"] - 0.05) < 0.005
    assert abs(rec["details"]["worst_location"][2] + 2.95) < 1e-6


def test_design_gouge_on_a_deep_slot():
    r = _sim("slot-deep.nc", "slot.checks.toml")
    rec = _by_name(r, "design #4")
    assert not rec["passed"]
    assert abs(rec["details"]["gouge_volume"] - 0.05 * (8 * 30 + math.pi * 8)) < 0.1
    assert abs(rec["details"]["worst_deviation"] + 0.05) < 0.005


def test_pocket_and_point_depth(mill_good):
    rec = mill_good.check(kind="pocket", at=[15.0, 20.0], size=[40.0, 8.0], floor=-3.0)
    # along X the slot is open at X0 (the mill entered from X-10): no closed gap there
    assert not _item(rec, "width_x")["passed"] and _item(rec, "width_y")["passed"] and _item(rec, "floor")["passed"]
    assert mill_good.check(kind="depth", at=[30.0, 20.0], z=-3.0)["passed"]
    assert not mill_good.check(kind="depth", at=[30.0, 20.0], z=-3.05)["passed"]


def test_cli_exit_status_and_report(tmp_path):
    for nc, status in (("multipass.nc", 0), ("multipass-shallow.nc", 1)):
        out = tmp_path / nc
        proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / nc), "--setup",
                               str(HERE / "multipass.toml"), "--out", str(out), "-q"], capture_output=True, text=True)
        assert proc.returncode == status, proc.stderr
        rep = json.loads((out / "report.json").read_text())
        assert [c["name"] for c in rep["checks"]] == ["M27x1.5 thread", "undercut"]
        for c in rep["checks"]:
            for it in c["items"]:
                assert {"quantity", "expected", "measured", "tolerance", "passed"} <= set(it)
    assert "FAIL root_diameter" in proc.stderr


@pytest.mark.parametrize("table,msg", [
    ('kind = "thread"\nz = [-6.0, -1.0]\nlead = 1.5\npitch = 2', "[[check]] #1 pitch: unknown key"),
    ('kind = "thread"\nz = [-1.0, -6.0]\nlead = 1.5', "[[check]] #1 z: must be [low, high]"),
    ('kind = "thread"\nz = [-6.0, -1.0]\nlead = 1.5\nstarts = 2\nphase = [0.0]\nphase_z = 3.0', "one angle per start"),
    ('kind = "slot"\nat = [1.0, 2.0]\ndirection = "y"', "a slot check needs a mill"),
    ('kind = "roundness"', "[[check]] #1 kind: must be one of"),
    ('kind = "diameter"\nz = -3.0', "[[check]] #1 expected: is required"),
    ('kind = "design"\npath = "nothere.stl"', "[[check]] #1 path: no such file"),
])
def test_bad_check_tables(tmp_path, table, msg):
    text = (HERE / "multipass.toml").read_text().split("[[check]]")[0] + "[[check]]\n" + table + "\n"
    setup = tmp_path / "s.toml"
    setup.write_text(text)
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(setup))
    assert msg in str(e.value)
    line = int(str(e.value).split(":")[1])
    assert line > text.count("\n") - table.count("\n") - 2  # points into the [[check]] table


def test_unmeasurable_values_are_none_not_nan():
    """A root the section cannot place (NaN) has no phase, and a NaN that reaches a check record
    is written as null (report.json is strict JSON; fuzz: a NaN phase spread ended in exit 3)."""
    import numpy as np

    from cutsim.reports.checks import _r
    from cutsim.reports.measure import thread_phases

    assert _r(float("nan")) is None and _r([1.0, float("inf")]) == [1.0, None]
    ph = thread_phases([(0.0, float("nan"), 10.0), (0.0, 0.5, 10.0)], 2.0, "right", 0.0)
    assert np.allclose(ph, [90.0])  # z = 0.5 on a 2 mm lead: a = 0.5 * 360 / 2 - 0
