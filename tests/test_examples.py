"""Every shipped example simulates to a closed solid (the manuals' programs must all run)."""
import json
import subprocess
import sys

import pytest

from conftest import EXAMPLES
import cutsim

PROGRAMS = sorted(p for p in EXAMPLES.glob("*/*") if p.suffix in (".nc", ".mpf", ".spf"))
SUPPORTED = set(__import__("cutsim.interp", fromlist=["x"]).available_dialects())


def _dialect(p):
    return cutsim.load_setup(str(p.with_suffix(".toml"))).machine.dialect


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_example_simulates(program):
    if _dialect(program) not in SUPPORTED:
        pytest.skip(f"dialect {_dialect(program)} not implemented yet")
    r = cutsim.simulate(str(program), str(program.with_suffix(".toml")), tolerance=0.01)
    assert r.part.status().name == "NoError"
    assert r.part.volume() > 0
    assert r.report["removed_volume"] > 0
    assert r.part.genus() >= 0


def test_runout_constant_reports_rapid_into_bar(examples, tmp_path):
    prog = examples / "cnc8x6-lathe" / "runout-constant.nc"
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(prog), "--setup",
                           str(prog.with_suffix(".toml")), "--out", str(out), "--tolerance", "0.01", "-q"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    rep = json.loads((out / "report.json").read_text())
    lines = [w["line"] for w in rep["warnings"]]
    assert 5 in lines  # N50 G0 back down to X64 at Z-100 rapids into the bar
    assert "runout-constant.nc:5:" in proc.stderr
    for key in ("program", "dialect", "machine", "blocks", "moves", "stock_volume", "part_volume",
                "removed_volume", "cycle_time_s", "warnings", "checks"):
        assert key in rep
    assert (out / "part.stl").stat().st_size > 84
