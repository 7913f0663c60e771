"""The Python API: simulate -> Result with part, mesh, report and measurements; the pytest helpers
give readable messages; part formats; the core imports and simulates without pyvista."""
import io
import json
import subprocess
import sys
import textwrap
import zipfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh

import cutsim
from cutsim import assert_checks_pass, assert_matches_design, assert_thread

HERE = Path(__file__).resolve().parents[1] / "data" / "programs" / "checks"


@pytest.fixture(scope="module")
def good():
    return cutsim.simulate(str(HERE / "multipass.nc"), str(HERE / "multipass.toml"))


@pytest.fixture(scope="module")
def bad():
    return cutsim.simulate(str(HERE / "multipass-shallow.nc"), str(HERE / "multipass.toml"))


def test_result(good):
    assert good.part.volume() > 0 and good.mesh().is_watertight
    assert good.passed and len(good.checks) == 2
    d = good.diameters_at(-20.0)
    assert np.allclose(d, 27.0, atol=0.02)
    assert abs(good.root_radius_at(-3.0) - 26.177 / 2) < 0.011
    t = good.thread(-6.0, -1.0)
    assert t["hand"] == "right" and abs(t["lead"] - 1.5) < 0.002 and t["starts"] == 1


def test_assert_thread(good, bad):
    assert_thread(good, z=(-6, -1), lead=1.5, root_diameter=26.177, tolerance=0.03, phase=[0], phase_z=3)
    with pytest.raises(AssertionError) as e:
        assert_thread(bad, z=(-6, -1), lead=1.5, root_diameter=26.177, tolerance=0.03)
    msg = str(e.value)
    assert "FAIL root_diameter: expected 26.177 +- 0.03 mm, measured 26.2" in msg
    assert "ok   lead" in msg
    with pytest.raises(AssertionError, match="check 'M27x1.5 thread'"):
        assert_checks_pass(bad)
    assert_checks_pass(good)


def test_assert_matches_design():
    good = cutsim.simulate(str(HERE / "slot.nc"), str(HERE / "slot.checks.toml"))
    assert_matches_design(good, HERE / "slot-design.stl", 0.02)
    design = trimesh.load(str(HERE / "slot-design.stl"))
    shallow = cutsim.simulate(str(HERE / "slot-shallow.nc"), str(HERE / "slot.checks.toml"))
    with pytest.raises(AssertionError, match=r"FAIL worst_deviation: expected 0.0 \+- 0.02 mm, measured 0.05"):
        assert_matches_design(shallow, design, 0.02)


def test_part_formats(tmp_path):
    outs = {}
    for fmt in ("stl", "3mf", "glb"):
        for k in (1, 2):
            out = tmp_path / f"{fmt}{k}"
            proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / "multipass.nc"), "--setup",
                                   str(HERE / "multipass.toml"), "--out", str(out), "--format", fmt, "-q"],
                                  capture_output=True, text=True)
            assert proc.returncode == 0, proc.stderr
            outs[fmt, k] = (out / f"part.{fmt}").read_bytes()
        assert outs[fmt, 1] == outs[fmt, 2], f"{fmt} output is not deterministic"
    vol = json.loads((tmp_path / "stl1" / "report.json").read_text())["part_volume"]
    assert abs(trimesh.load(io.BytesIO(outs["stl", 1]), file_type="stl").volume - vol) < 1.0
    glb = trimesh.load(io.BytesIO(outs["glb", 1]), file_type="glb", force="mesh")
    assert abs(glb.volume * 1e9 - vol) < 1.0  # glTF is in metres: 1 m^3 = 1e9 mm^3
    with zipfile.ZipFile(io.BytesIO(outs["3mf", 1])) as z:
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    ns = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
    v = np.array([[float(e.get(a)) for a in "xyz"] for e in root.iterfind(".//m:vertex", ns)])
    f = np.array([[int(e.get(a)) for a in ("v1", "v2", "v3")] for e in root.iterfind(".//m:triangle", ns)])
    assert abs(trimesh.Trimesh(v, f).volume - vol) < 1.0


def test_core_without_pyvista(tmp_path):
    code = textwrap.dedent(f"""
        import sys
        sys.modules["pyvista"] = None  # any import of pyvista now fails
        sys.modules["vtk"] = None
        import cutsim
        r = cutsim.simulate({str(HERE / 'multipass.nc')!r}, {str(HERE / 'multipass.toml')!r}, tolerance=0.05)
        assert r.part.volume() > 0 and r.report["checks"]
        assert "pyvista" not in [m for m in sys.modules if sys.modules[m] is not None]
        print("ok")
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stdout.strip() == "ok", proc.stderr
