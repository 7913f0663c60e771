"""The written part files stay closed when read back by position (issue 10).

Every example (the repository's examples/**/*.toml and ../shared/examples/**) and every test
program with a setup is simulated, written as STL, 3MF and GLB and read back with trimesh's
default processing, which merges vertices by position. Each file must be watertight and a volume,
in its unit (mm; metres for GLB), with a volume within the export's bound of the solid:

    |V_file - V_solid| <= D * (A_solid + A_file)

D is how far the export may move the surface: half a diagonal of the snap grid (sqrt(3)/2 h, the
grid h being the float32 spacing at the part's largest coordinate but at least 2**-16 mm) plus the
collapse tolerance (and the separation steps when vertices had to be moved apart). The grid is
recomputed here from the part's bounding box, independently of cutsim's code.
"""
from __future__ import annotations

import io
import json
import math
import zipfile
from pathlib import Path

import manifold3d
import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cutsim
from conftest import EXAMPLES, ROOT
from cutsim.reports.mesh import FORMATS, closed_by_position, closed_mesh, part_bytes
from cutsim.reports.report import report_bytes

HERE = Path(__file__).resolve().parents[1]
PROGRAMS = HERE / "data" / "programs"  # the tests' own programs, ids tests/<folder>/<name>
PROGRAM_SUFFIXES = {".nc", ".mpf", ".spf"}

# Programs whose files leaked before the fix (edges shared by 4-14 faces once read back): they
# stay at their setup's tolerance. The other examples run at COARSE to keep the test short.
LEAKY = {
    "shared/isg-lathe/m70x1.5", "shared/isg-lathe/two-start", "shared/isg-lathe/taper",
    "shared/cnc8x6-lathe/taper", "examples/isg-lathe/taper", "examples/cnc8x6-lathe/taper",
    "examples/sinumerik/worksheet4", "examples/sinumerik/cycle72", "examples/sinumerik/plate",
    "examples/cnc8x6-lathe/three-start", "examples/cnc8x6-lathe/two-start-checked",
    "examples/isg-lathe/three-start", "tests/isg/three-start", "tests/isg/offset90",
}
COARSE = 0.02

# test programs that are error cases (nothing is written) or whose setup is not beside them
ERROR_PROGRAMS = {"mill/helix-endless.nc", "mill/helix-g98.nc", "mill/helix-missing.nc", "mill/helix-noq.nc",
                  "isg/seed-spelling.nc"}
DIR_SETUP = {"mill": "plate.toml", "isg": "three-start.toml"}


def _program_beside(toml: Path) -> Path:
    progs = sorted(p for p in toml.parent.iterdir() if p.stem == toml.stem and p.suffix.lower() in PROGRAM_SUFFIXES)
    assert progs, f"{toml}: an example setup without a program of the same name"
    return progs[0]


def _example_cases():
    cases = []
    for toml in sorted((ROOT / "examples").glob("**/*.toml")):
        rel = toml.relative_to(ROOT / "examples").with_suffix("")
        cases.append((f"examples/{rel.as_posix()}", toml))
    if EXAMPLES.is_dir():
        for toml in sorted(EXAMPLES.glob("**/*.toml")):
            rel = toml.relative_to(EXAMPLES).with_suffix("")
            cases.append((f"shared/{rel.as_posix()}", toml))
    return cases


def _test_program_cases():
    cases = []
    for prog in sorted(p for p in PROGRAMS.rglob("*") if p.suffix.lower() in PROGRAM_SUFFIXES):
        rel = prog.relative_to(PROGRAMS)
        if rel.as_posix() in ERROR_PROGRAMS:
            continue  # error programs: nothing is written
        setup = prog.with_suffix(".toml")
        if not setup.is_file() and rel.parts[0] == "checks":
            setup = prog.parent / ("multipass.toml" if prog.stem.startswith("multipass") else "slot.toml")
        elif not setup.is_file() and rel.parts[0] in DIR_SETUP:
            setup = prog.parent / DIR_SETUP[rel.parts[0]]
        if not setup.is_file():
            continue  # not a program with a setup
        cases.append((f"tests/{rel.with_suffix('').as_posix()}", prog, setup))
    if EXAMPLES.is_dir():  # the shared threads on the short bar (tests/interp/isg/test_isg.py)
        for name in ("m70x1.5", "two-start"):
            cases.append((f"tests/short/{name}", EXAMPLES / "isg-lathe" / f"{name}.nc", PROGRAMS / "isg" / "short.toml"))
    return cases


CASES = [(cid, _program_beside(toml), toml) for cid, toml in _example_cases()] + _test_program_cases()


def grid_step(max_abs: float) -> float:
    """The float32 spacing at max_abs (a power of two), at least 2**-16 mm."""
    return max(2.0 ** (math.floor(math.log2(max_abs)) + 1 - 23), 2.0 ** -16)


def _load(data: bytes, fmt: str) -> trimesh.Trimesh:
    """The file read back with trimesh's default processing (vertices merged by position)."""
    return trimesh.load(io.BytesIO(data), file_type=fmt, force="mesh")


def assert_files_closed(part, cm, fmts=FORMATS):
    """Write ``cm`` (the closed mesh of ``part``) in every format, read each back by position and
    check it against the solid ``part``."""
    box = np.asarray(part.bounding_box(), dtype=float)
    h = grid_step(float(np.abs(box).max()))
    assert cm.grid == h
    d = cm.displacement  # half a grid diagonal, plus sqrt(3) h per ring of a separation
    if cm.separated == 0:
        assert d == math.sqrt(3) / 2 * h
    assert d >= math.sqrt(3) / 2 * h
    solid_volume, solid_area = part.volume(), part.surface_area()
    for fmt in fmts:
        data = part_bytes(cm.vertices, cm.faces, fmt)
        mesh = _load(data, fmt)
        scale = 1e-3 if fmt == "glb" else 1.0  # glTF is in metres
        assert mesh.is_watertight, fmt
        assert mesh.is_volume, fmt
        bound = d * (solid_area + mesh.area / scale ** 2)
        assert abs(mesh.volume / scale ** 3 - solid_volume) <= bound, fmt
        np.testing.assert_allclose(mesh.bounds / scale, box.reshape(2, 3), rtol=0, atol=d + 1e-12, err_msg=fmt)


@pytest.mark.parametrize("cid, program, setup", CASES, ids=[c[0] for c in CASES])
def test_written_part_is_closed(cid, program, setup):
    tol = None if cid in LEAKY else COARSE
    r = cutsim.simulate(str(program), str(setup), tolerance=tol, checks=False)
    if r.part.is_empty():
        pytest.skip("the program removes the whole stock")
    tol = r.report["tolerance"]
    cm = closed_mesh(r.part)
    assert cm.displacement <= tol / 10  # the export moves the surface by a small part of the tolerance
    assert_files_closed(r.part, cm)


def test_shared_examples_present():
    if not EXAMPLES.is_dir():
        pytest.skip(f"../shared/examples not found at {EXAMPLES}: only the repository's examples ran")
    assert any(c[0].startswith("shared/") for c in CASES)


# -- the stronger fixes: vertices that coincide in the solid itself -----------------------------
def _cube(x, y, z, s=10.0):
    return manifold3d.Manifold.cube((s, s, s)).translate((x, y, z))


@pytest.mark.parametrize("other, shared", [((10, 10, 0), 2), ((10, 10, 10), 1)], ids=["edge", "vertex"])
def test_solids_touching_along_an_edge_or_at_a_vertex(other, shared):
    # two 10 mm cubes touching along an edge (or at a corner): the union is closed by index, but
    # its vertices on the shared edge coincide, so by position the edge has four faces
    part = _cube(0, 0, 0) + _cube(*other)
    raw = part.to_mesh64()
    assert closed_by_position(np.asarray(raw.vert_properties, dtype=float),
                              np.asarray(raw.tri_verts, dtype=np.int64)) is not None
    cm = closed_mesh(part)
    assert cm.separated == shared  # the two ends of the shared edge, or the shared corner
    assert_files_closed(part, cm)
    assert abs(cm.volume() - 2000.0) <= cm.displacement * 2 * 1200.0  # two cubes, 600 mm^2 each


def test_slivers_from_faces_a_nanometre_apart():
    # a slot whose side lies 1e-9 mm beside a pocket's side, and floors 1e-7 apart: the booleans
    # leave vertices closer than float32 can tell apart
    stock = manifold3d.Manifold.cube((40.0, 30.0, 10.0))
    cut = (manifold3d.Manifold.cube((10.0, 10.0, 5.0)).translate((5.0, 5.0, 5.0))
           + manifold3d.Manifold.cube((20.0, 3.0, 5.0 + 1e-7)).translate((15.0 - 1e-9, 10.0 - 1e-9, 5.0 - 1e-7))
           + manifold3d.Manifold.cylinder(5.0 + 1e-9, 3.0, 3.0, 64).translate((30.0, 20.0, 5.0)))
    part = stock - cut
    cm = closed_mesh(part)
    assert_files_closed(part, cm)


def test_film_a_tenth_of_a_nanometre_thick():
    # a pocket whose floor lies 1e-10 mm above the stock's bottom, beside a bore: the film is
    # collapsed, not folded (manifold3d's simplify folds the pocket wall across it: +3.3 mm^3)
    part = (manifold3d.Manifold.cube((20.0, 20.0, 20.0)) - manifold3d.Manifold.cylinder(10.0, 1.0, 1.0, 16)
            - manifold3d.Manifold.cube((2.5, 5.0, 2.5)).translate((0.0, 0.0, 1e-10)))
    cm = closed_mesh(part)
    assert cm.collapsed > 0
    assert_files_closed(part, cm)


@pytest.mark.parametrize("top", [1e-9, 1e-6])
def test_a_cone_cut_with_a_tip_of_a_nanometre(top):
    # a 256-sided cylinder tapering to a radius of 1e-9 (1e-6) mm: its top ring of 256 vertices
    # lies within one grid cell, and collapses to the apex of the true cone (radius 0) - 255
    # collapses, the cone's own triangle count
    block = manifold3d.Manifold.cube((20.0, 20.0, 20.0)).translate((-10.0, -10.0, -5.0))
    part = block - manifold3d.Manifold.cylinder(10.0, 5.0, top, 256)
    cone = block - manifold3d.Manifold.cylinder(10.0, 5.0, 0.0, 256)
    cm = closed_mesh(part)
    assert cm.collapsed == 255
    assert len(cm.faces) == cone.num_tri()
    assert_files_closed(part, cm)


def test_checkerboard_of_cubes_touching_along_edges():
    part = manifold3d.Manifold()
    for i in range(4):
        for j in range(4):
            if (i + j) % 2 == 0:
                part = part + _cube(i, j, 0.0, s=1.0)
    assert part.volume() == pytest.approx(8.0)
    cm = closed_mesh(part)
    assert cm.separated > 0
    assert_files_closed(part, cm)


# -- random solids with near-coincident faces ---------------------------------------------------
JITTER = st.sampled_from([0.0, 1e-10, 1e-9, 3e-8, 1e-7, 1e-6, 4e-6, -1e-9, -1e-7, -2e-6])
COORD = st.sampled_from([0.0, 2.5, 5.0, 7.5, 10.0, 12.5, 15.0, 20.0])


@st.composite
def cutters(draw):
    """(kind, position, size, extra): a box, a cylinder along z or a tilted cylinder."""
    kind = draw(st.sampled_from(["box", "cyl", "turned"]))
    pos = tuple(draw(COORD) + draw(JITTER) for _ in range(3))
    if kind == "box":
        return kind, pos, tuple(draw(st.sampled_from([2.5, 5.0, 7.5, 10.0])) + draw(JITTER) for _ in range(3)), None
    r = draw(st.sampled_from([1.0, 2.5, 5.0])) + draw(JITTER)
    segs = draw(st.sampled_from([16, 48, 90]))
    rot = (draw(st.sampled_from([0.0, 45.0, 90.0])), 0.0, draw(st.sampled_from([0.0, 1e-6, 30.0]))) if kind == "turned" else None
    return kind, pos, (r, segs), rot


def _solid(kind, pos, size, rot):
    if kind == "box":
        return manifold3d.Manifold.cube(size).translate(pos)
    c = manifold3d.Manifold.cylinder(10.0, size[0], size[0], size[1])
    if rot is not None:  # rotated: faces meet at shallow angles
        c = c.rotate(rot)
    return c.translate(pos)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(cutters(), min_size=1, max_size=6))
def test_random_cuts_write_closed_files(cuts):
    part = manifold3d.Manifold.cube((20.0, 20.0, 20.0))
    for c in cuts:
        part = part - _solid(*c)
    if part.is_empty():
        return
    cm = closed_mesh(part)
    assert closed_by_position(cm.vertices, cm.faces) is None
    assert_files_closed(part, cm, fmts=("stl",))


# -- same input, same bytes; what the CLI writes ------------------------------------------------
def test_same_run_gives_the_same_bytes(tmp_path):
    from click.testing import CliRunner

    from cutsim.cli import main

    prog, setup = ROOT / "examples" / "sinumerik" / "cycle72.mpf", ROOT / "examples" / "sinumerik" / "cycle72.toml"
    r = cutsim.simulate(str(prog), str(setup), checks=False)
    m = r.mesh()
    assert m.units == "mm"
    cm = closed_mesh(r.part)  # computed again: the same arrays
    assert np.array_equal(m.vertices, cm.vertices) and np.array_equal(m.faces, cm.faces)
    expected = {fmt: part_bytes(m.vertices, m.faces, fmt) for fmt in FORMATS}

    def run(fmt, out):
        res = CliRunner().invoke(main, ["simulate", str(prog), "--setup", str(setup), "--out", str(out),
                                        "--format", fmt, "-q"])
        assert res.exit_code == 0, res.output
        return (out / f"part.{fmt}").read_bytes(), (out / "report.json").read_bytes()

    # each CLI run is a simulation of its own: its bytes equal those of the API run above
    for fmt in FORMATS:
        data, _ = run(fmt, tmp_path / fmt)
        assert data == expected[fmt], fmt
        mesh = _load(data, fmt)
        assert mesh.is_watertight and mesh.is_volume
    assert run("stl", tmp_path / "again") == run("stl", tmp_path / "stl")


def test_units():
    part = _cube(-5.0, 0.0, 2.0, s=10.0)
    cm = closed_mesh(part)
    glb = _load(part_bytes(cm.vertices, cm.faces, "glb"), "glb")
    np.testing.assert_allclose(glb.bounds, [[-0.005, 0.0, 0.002], [0.005, 0.01, 0.012]], atol=1e-12)
    with zipfile.ZipFile(io.BytesIO(part_bytes(cm.vertices, cm.faces, "3mf"))) as z:
        assert 'unit="millimeter"' in z.read("3D/3dmodel.model").decode()
    tmf = _load(part_bytes(cm.vertices, cm.faces, "3mf"), "3mf")
    np.testing.assert_allclose(tmf.bounds, [[-5.0, 0.0, 2.0], [5.0, 10.0, 12.0]], atol=0)
    # the GLB's node carries the scale; its stored positions are the checked millimetres
    raw = part_bytes(cm.vertices, cm.faces, "glb")
    doc = json.loads(raw[20:20 + int.from_bytes(raw[12:16], "little")])
    assert doc["nodes"][0]["scale"] == [0.001, 0.001, 0.001]
    assert doc["accessors"][0]["max"] == [5.0, 10.0, 12.0]


def test_empty_part_files():
    empty = manifold3d.Manifold.cube((1.0, 1.0, 1.0)) - manifold3d.Manifold.cube((3.0, 3.0, 3.0)).translate((-1, -1, -1))
    cm = closed_mesh(empty)
    assert len(cm.faces) == 0
    for fmt in FORMATS:
        assert len(_load(part_bytes(cm.vertices, cm.faces, fmt), fmt).faces) == 0


# -- report.json is strict JSON -----------------------------------------------------------------
@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_report_never_holds_nan_or_infinity(bad):
    report = {"program": "p.nc", "part_volume": 1.0, "checks": [{"name": "d", "measured": [1.0, bad]}]}
    with pytest.raises(ValueError, match=r"checks\[0\]\.measured\[1\]"):
        report_bytes(report)


def test_report_is_strict_json():
    def no_constants(name):
        raise AssertionError(f"non-standard JSON constant {name}")

    r = cutsim.simulate(str(PROGRAMS / "mill" / "slot.nc"), str(PROGRAMS / "mill" / "plate.toml"), tolerance=0.05)
    text = report_bytes(r.report).decode("utf-8")
    assert json.loads(text, parse_constant=no_constants) == json.loads(json.dumps(r.report))
