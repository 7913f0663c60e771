"""Example programs: the repository's own (examples/, always run) and the manuals' (../shared).

Every ``examples/**/NAME.toml`` has a program ``NAME.nc``/``NAME.mpf`` beside it and simulates
through the CLI with exit 0, no warnings and all its checks passed. The check values of the
issue-15 thread example are recomputed here from the program's own numbers (so a comment and its
number cannot drift apart), the groove roots and phases are measured independently with trimesh
(tests/support/geometry.py), and a spoiled copy of the program must fail those checks. The Sinumerik
plate's design model is what make_design.py writes, byte for byte.
"""
from __future__ import annotations

import importlib.util
import json
import math
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from conftest import EXAMPLES, HAVE_SHARED, REPO_EXAMPLES, SKIP_REASON
from support.geometry import groove_roots, section, wrap
import cutsim
from cutsim.cli import main

PROGRAM_SUFFIXES = (".nc", ".mpf")

# ---------------------------------------------------------------- the repository's own examples

SETUPS = sorted(REPO_EXAMPLES.rglob("*.toml"))


def _program(setup: Path) -> Path:
    found = [setup.with_suffix(s) for s in PROGRAM_SUFFIXES if setup.with_suffix(s).is_file()]
    assert len(found) == 1, f"{setup}: expected one program beside it, found {found}"
    return found[0]


def _id(p: Path) -> str:
    return str(p.relative_to(REPO_EXAMPLES).with_suffix(""))


def _simulate(program: Path, setup: Path, out: Path, *extra: str):
    res = CliRunner().invoke(main, ["simulate", str(program), "--setup", str(setup), "--out", str(out), "-q", *extra])
    rep = json.loads((out / "report.json").read_text()) if (out / "report.json").is_file() else None
    return res, rep


def test_every_dialect_has_examples():
    dirs = {p.parent.name for p in SETUPS}
    assert {"cnc8x6-lathe", "cnc8x6-mill", "isg-lathe", "sinumerik", "rs274ngc"} <= dirs
    # every program has its setup too
    for prog in REPO_EXAMPLES.rglob("*"):
        if prog.suffix in PROGRAM_SUFFIXES:
            assert prog.with_suffix(".toml").is_file(), f"{prog} has no setup beside it"


@pytest.mark.parametrize("setup", SETUPS, ids=_id)
def test_repository_example_simulates_cleanly(setup, tmp_path):
    """Exit 0, no warnings, every check passed; an example with a design model also draws every
    view with --images (iso, top or section, deviation)."""
    program = _program(setup)
    checks = tomllib.loads(setup.read_text()).get("check", [])
    design = any(c["kind"] == "design" for c in checks)
    out = tmp_path / "out"
    res, rep = _simulate(program, setup, out, *(["--images"] if design else []))
    assert res.exit_code == 0, res.output
    assert rep["warnings"] == []
    failed = [c["name"] for c in rep["checks"] if not c["passed"]]
    assert failed == []
    assert len(rep["checks"]) == len(checks)
    assert rep["removed_volume"] > 0
    assert (out / "part.stl").stat().st_size > 84
    if design:
        from PIL import Image
        view = "top.png" if rep["machine"]["kind"] == "mill" else "section.png"
        for name in ("iso.png", view, "deviation.png"):
            with Image.open(out / name) as im:  # section.png: 360 to 768 high (docs/checks.md)
                assert im.size[0] == 1024 and (360 <= im.size[1] <= 768 if name == "section.png"
                                               else im.size[1] == 768), (name, im.size)
                # a drawn view, not a blank canvas: many distinct colours
                assert len(im.convert("RGB").getcolors(1 << 20) or []) > 50, name
        assert (out / "report.html").is_file()


# ------------------------------------------------- the issue-15 thread example, checked by hand

TWO_START = REPO_EXAMPLES / "cnc8x6-lathe" / "two-start-checked"


def _thread_blocks(text: str):
    """(start X, start Z, I, E, J, end Z, lead) of every G33 block, the start being the
    position the block before leaves the tool at (a straight thread: X and Z only)."""
    x = z = None
    out = []
    for line in text.splitlines():
        words = dict(re.findall(r"([A-Z])(-?[\d.]+)", line.split('"')[0]))
        if "G" in words and words["G"] == "33":
            out.append((x, z, float(words["I"]), float(words["E"]), float(words["J"]),
                        float(words["Z"]), float(words["F"])))
        x = float(words["X"]) if "X" in words else x
        z = float(words["Z"]) if "Z" in words else z
    return out


def test_two_start_check_values_follow_from_the_program():
    text = TWO_START.with_suffix(".nc").read_text()
    setup = tomllib.loads(TWO_START.with_suffix(".toml").read_text())
    code = setup["machine"]["constants"]["8"]
    assert code // 100000 == 1                      # axis 1 = X, angle mode
    t = math.tan(math.radians(code % 100000 / 1000.0))
    blocks = _thread_blocks(text)
    assert len(blocks) == 6 and sorted({b[2] for b in blocks}) == [0.0, 180.0]
    x_last, z0, _i, e, j, z_end, lead = blocks[-1]
    assert all(b[1] == z0 and b[3:] == (e, j, z_end, lead) for b in blocks)
    root = x_last - 2 * e * t                       # X after the lead-in of the deepest pass
    assert min(b[0] for b in blocks) == x_last
    checks = {c["name"]: c for c in setup["check"]}
    th = checks["two-start thread"]
    assert th["root_diameter"] == pytest.approx(root, abs=1e-4)
    assert th["lead"] == lead and th["starts"] == 2 and th["phase_z"] == z0
    assert th["phase"] == [0.0, 180.0]
    assert z0 - e > th["z"][1] and th["z"][0] > z_end + j   # inside the full-depth thread
    lead_in = lambda z: x_last / 2 - (z0 - z) * t            # noqa: E731
    runout = lambda z: root / 2 + (z_end + j - z) * t        # noqa: E731
    for name, f in (("lead-in", lead_in), ("runout", runout)):
        c = checks[name]
        assert c["radius"] == pytest.approx([f(c["z"][0]), f(c["z"][1])], abs=1e-4), name
        assert max(c["radius"]) < setup["stock"]["profile"][1][0]   # the ramp is in the bar
    assert checks["bar below the thread"]["z"] < z_end + j - (18 - root / 2) / t - 1  # below where it leaves


@pytest.fixture(scope="module")
def two_start():
    return cutsim.simulate(str(TWO_START.with_suffix(".nc")), str(TWO_START.with_suffix(".toml")))


def test_two_start_roots_and_phases_measured_with_trimesh(two_start):
    """Independently of cutsim's checks: in the half-plane at angle phi the groove roots lie at
    z = 1 + 4 * (phi + a) / 360 (mod 4) for a = 0 and 180, i.e. every 2 mm, at radius 16.773."""
    mesh = two_start.mesh()
    root_r = (37.8332 - 2 * 8 * math.tan(math.radians(15))) / 2
    for phi in (0.0, 45.0, 130.0, 270.0):
        roots = groove_roots(section(mesh, phi), -22.0, -8.0, below=17.5, min_gap=0.6)
        assert len(roots) >= 6, (phi, roots)      # 14 mm of full-depth thread, roots 2 apart
        assert np.all(np.abs(roots[:, 1] - root_r) < 0.012), (phi, roots)
        assert np.all(np.abs(wrap(roots[:, 0] - (1.0 + 4.0 * phi / 360.0), 2.0)) < 0.01), (phi, roots)
        # the two starts alternate: consecutive roots 2 mm apart, same start every 4 mm
        assert np.allclose(np.diff(roots[:, 0]), 2.0, atol=0.01)


def test_two_start_checks_fail_on_a_spoiled_program(tmp_path):
    """The last passes 0.1 mm (diameter) shallower and the second start at I170 instead of I180:
    the root diameter, the second phase and both ramps must fail (exit 1)."""
    text = TWO_START.with_suffix(".nc").read_text()
    text = text.replace("X37.8332", "X37.9332").replace("I180.", "I170.")
    prog = tmp_path / "two-start-checked.nc"
    prog.write_text(text)
    setup = tmp_path / "two-start-checked.toml"
    setup.write_text(TWO_START.with_suffix(".toml").read_text())
    res, rep = _simulate(prog, setup, tmp_path / "out")
    assert res.exit_code == 1, res.output
    failed = {(c["name"], i["quantity"]) for c in rep["checks"] for i in c["items"] if not i["passed"]}
    assert ("two-start thread", "root_diameter") in failed
    assert ("two-start thread", "phase[2]") in failed
    assert ("two-start thread", "phase[1]") not in failed
    assert {"lead-in", "runout"} <= {name for name, _q in failed}
    assert not any(name in ("bar below the thread", "shoulder") for name, _q in failed)


SHAFT = REPO_EXAMPLES / "cnc8x6-lathe" / "shaft-m30x2"
UNDERCUT = {"undercut d_g (27 h13)", "undercut flank at D27.4 (g1 4.51)", "undercut flank at D27.6 (30 degrees, g2 6.987)",
            "undercut r 1 at the shoulder"}


@pytest.mark.parametrize("old, new, failing", [
    # too shallow: the floor at 27.2 (above 27 h13), the flank 0.105 higher, so 0.105 sqrt(3) = 0.18
    # further towards -Z at every diameter; the r 1 at the shoulder lies 0.105 higher too
    ("N170 G01 X26.99", "N170 G01 X27.2", UNDERCUT),
    # too narrow: the flank's foot 0.5 nearer the shoulder (g1 4.01 < 4.5): the flank's checks fail,
    # the floor and the corner at the shoulder do not
    ("Z-27.758", "Z-28.258", {"undercut flank at D27.4 (g1 4.51)", "undercut flank at D27.6 (30 degrees, g2 6.987)"}),
])
def test_shaft_undercut_checks_fail_on_a_wrong_undercut(tmp_path, old, new, failing):
    """The DIN 76-1 form A undercut of shaft-m30x2 (its setup derives every number): a wrong one
    fails exactly its own checks; the thread and the shoulder stay good."""
    text = SHAFT.with_suffix(".nc").read_text()
    assert old in text
    r = cutsim.simulate("shaft-m30x2-wrong.nc", str(SHAFT.with_suffix(".toml")), text=text.replace(old, new))
    failed = {c["name"] for c in r.checks if not c["passed"]}
    assert failed == failing, (failed, [c for c in r.checks if not c["passed"]])


# ------------------------------------------------------------- the Sinumerik plate's design model

def test_plate_design_is_what_make_design_writes():
    path = REPO_EXAMPLES / "sinumerik" / "make_design.py"
    spec = importlib.util.spec_from_file_location("make_design", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    design = mod.design()
    assert design.status().name == "NoError" and design.genus() == 0
    # 120 x 80 x 20 minus the pockets and the slot, as the program's comments give them
    rect = 40 * 30 - (4 - math.pi) * 6 ** 2
    expect = 120 * 80 * 20 - rect * 6 - math.pi * 12 ** 2 * 8 - (80 * 6 + math.pi * 3 ** 2) * 3
    assert design.volume() == pytest.approx(expect, rel=2e-5)   # 240-gons: -0.0114 % of the circles
    assert mod.stl_bytes(design) == (REPO_EXAMPLES / "sinumerik" / "plate-design.stl").read_bytes()


# ------------------------------------------------------------ the manuals' programs (../shared)

SHARED_PROGRAMS = sorted(p for p in EXAMPLES.glob("*/*") if p.suffix in (".nc", ".mpf", ".spf")) if HAVE_SHARED else []
SUPPORTED = set(__import__("cutsim.interp", fromlist=["x"]).available_dialects())


def _dialect(p):
    return cutsim.load_setup(str(p.with_suffix(".toml"))).machine.dialect


@pytest.mark.parametrize("program", SHARED_PROGRAMS or [pytest.param(None, marks=pytest.mark.skip(reason=SKIP_REASON))],
                         ids=lambda p: f"{p.parent.name}/{p.name}" if p else "shared-absent")
def test_manual_example_simulates(program):
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
