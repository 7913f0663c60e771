"""Work limits: sweeps that would need more triangles than [simulation] max_triangles are refused
before they are built, at the line of the move responsible; hostile setups and mesh stocks are
errors at their key's line, never crashes; report.json stays strict JSON."""
from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
import trimesh

import cutsim
from conftest import EXAMPLES
from cutsim import CutsimError
from cutsim.kinematics.paths import segment_angle

LATHE = EXAMPLES / "cnc8x6-lathe"

THREAD = """\
N325 G00 G95 T9 S1000 M03
N330 G00 X26.618 Z3.
N335 G33 Z-19. I0. F{lead}
N340 G00 X29.
"""


def _strict(text: str):
    def bad(name):
        raise ValueError(f"not JSON: {name}")
    return json.loads(text, parse_constant=bad)


def test_fine_lead_thread_is_refused_naming_max_triangles(tmp_path):
    """G33 with lead 0.003 over 22 mm: 7333 turns; at 2 um every turn needs about 180 stations
    (the chord of a 13.3 mm radius at 0.002 mm is 1.99 degrees) of a profile of at least 3
    vertices, so the sweep needs more than 7333 * 180 * 2 * 3 = 7.9M triangles: refused at its
    line (3), nothing written. (A lead at or below the tolerance is the turned groove within it and
    runs: tests/stock/test_lathe_geometry.py.)"""
    prog = tmp_path / "fine.nc"
    prog.write_text(THREAD.format(lead="0.003"))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(prog), "--setup",
                           str(LATHE / "multipass.toml"), "--out", str(out), "-q"], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    assert f"{prog}:3:" in proc.stderr and "max_triangles" in proc.stderr and "Traceback" not in proc.stderr
    assert not out.exists()
    # the estimate in the message is at least the lower bound above
    stations = 22 / 0.003 * 360 / math.degrees(segment_angle(26.618 / 2, 0.002))
    est = int(proc.stderr.split("about ")[1].split(" triangles")[0].replace(",", ""))
    assert est >= 6 * stations


def test_raising_max_triangles_is_the_setting_named(tmp_path):
    """The same thread with a coarse lead passes by default and is refused under a small limit:
    the limit is what the message names."""
    prog = tmp_path / "t.nc"
    prog.write_text(THREAD.format(lead="1.5"))
    setup = tmp_path / "s.toml"
    base = (LATHE / "multipass.toml").read_text()
    setup.write_text(base)
    r = cutsim.simulate(str(prog), str(setup))
    assert r.report["removed_volume"] > 0
    setup.write_text(base + "\n[simulation]\nmax_triangles = 5000\n")
    with pytest.raises(CutsimError) as e:
        cutsim.simulate(str(prog), str(setup))
    assert (e.value.program, e.value.line) == (str(prog), 3)
    assert "max_triangles = 5,000" in e.value.message and "this thread cut" in e.value.message


def test_screw_estimate_matches_the_built_sweep():
    """The estimate before building equals the built sweep's triangles within 1 % (each pass swept
    on its own: grouping passes on one helix is switched off for this count)."""
    from cutsim.stock import budget, strategy_turning, sweeps, threads

    setup = cutsim.load_setup(str(LATHE / "multipass.toml"))
    built = []
    orig = sweeps.screw_sweep
    orig_motion = threads.motion

    def counting(*a, **k):
        out = orig(*a, **k)
        if len(a) < 6 and "zwindow" not in k:  # not the rebuilds near a rapid
            built.append(sum(s.num_tri() for s in out))
        return out

    estimates = []
    add = budget.Work.add

    def recording(self, tris, src, what):
        if what == "this thread cut":
            estimates.append(tris)
        return add(self, tris, src, what)

    strategy_turning.screw_sweep, threads.screw_sweep, budget.Work.add = counting, counting, recording
    threads.motion = lambda path: None
    try:
        cutsim.simulate(str(LATHE / "multipass.nc"), setup)
    finally:
        strategy_turning.screw_sweep, threads.screw_sweep, budget.Work.add = orig, orig, add
        threads.motion = orig_motion
    assert len(estimates) == 3 and len(built) == 3
    for est, n in zip(estimates, built):
        assert abs(est - n) <= 0.01 * n


def test_small_limit_refuses_a_slot_level_before_it_is_extruded(tmp_path):
    """A 10 mm end mill's L-shaped slot at 0.002 mm: each stadium has 2 * 57 vertices (half circles
    in chords of 3.24 degrees), their union well over 150, about 4 triangles per vertex once
    extruded (> 600). The rapid down beside the plate is two hulls of two 222-vertex tool bodies
    (< 1800 triangles), so under a limit of 2000 the level is what goes over: refused at its
    first move (line 3) before the prism is built."""
    setup = tmp_path / "s.toml"
    setup.write_text(_PLATE + "\n[simulation]\nmax_triangles = 2000\n")
    prog = tmp_path / "p.nc"
    prog.write_text("N10 T1 G00 X-10 Y50 Z5\nN20 G00 Z-3\nN30 G01 X80 F200\nN40 Y20\n")
    with pytest.raises(CutsimError) as e:
        cutsim.simulate(str(prog), str(setup))
    assert "max_triangles" in e.value.message and "Z level" in e.value.message
    assert e.value.line == 3


_PLATE = """\
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 30.0]

[stock]
shape = "box"
x = [0.0, 100.0]
y = [0.0, 100.0]
z = [-20.0, 0.0]

[[tool]]
number = 1
kind = "endmill"
diameter = 10.0
length = 25.0
"""


def test_nan_start_is_refused_and_report_is_strict_json(tmp_path):
    setup = tmp_path / "s.toml"
    base = (LATHE / "multipass.toml").read_text()
    setup.write_text(base.replace("diameter_programming = true", "diameter_programming = true\nstart = [nan, 40, 50]"))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(LATHE / "multipass.nc"), "--setup",
                           str(setup), "--out", str(out), "-q"], capture_output=True, text=True)
    line = setup.read_text().splitlines().index("start = [nan, 40, 50]") + 1
    assert proc.returncode == 2 and f"{setup}:{line}:1: error: [machine] start" in proc.stderr, proc.stderr
    setup.write_text(base.replace("diameter_programming = true", "diameter_programming = true\nstart = [60, 0, 50]"))
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(LATHE / "multipass.nc"), "--setup",
                           str(setup), "--out", str(out), "--tolerance", "0.02", "-q"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    rep = _strict((out / "report.json").read_text())
    assert all(math.isfinite(v) for v in rep["final_position"])


# -- mesh stock ------------------------------------------------------------------------------------
MESH_SETUP = """\
[machine]
kind = "mill"
dialect = "cnc8x6"

[stock]
shape = "mesh"
path = "{path}"

[[tool]]
kind = "endmill"
diameter = 6.0
"""


def _mesh_error(tmp_path, name: str, data: bytes | None = None, extra: str = "") -> CutsimError:
    if data is not None:
        (tmp_path / name).write_bytes(data)
    setup = tmp_path / "s.toml"
    setup.write_text(MESH_SETUP.format(path=name) + extra)
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(setup))
    assert e.value.program == str(setup)
    assert (e.value.line, e.value.col) == (7, 1), e.value  # the path key
    assert "[stock] path" in e.value.message
    return e.value


def _stl(mesh: trimesh.Trimesh) -> bytes:
    return mesh.export(file_type="stl")


def test_mesh_stock_errors_at_the_path_key(tmp_path):
    assert "empty" in _mesh_error(tmp_path, "empty.stl", b"").message
    junk = _mesh_error(tmp_path, "junk.stl", b"solid x\nfacet normal nonsense\n" * 3).message
    assert "cannot read" in junk or "no triangles" in junk
    box = trimesh.creation.box((10, 10, 10))
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-1], process=False)
    assert "not a closed solid" in _mesh_error(tmp_path, "open.stl", _stl(open_box)).message
    sphere = trimesh.creation.icosphere(subdivisions=4)  # 5120 triangles
    e = _mesh_error(tmp_path, "big.stl", _stl(sphere), "\n[simulation]\nmax_triangles = 1000\n")
    assert "5,120 triangles" in e.message and "max_triangles" in e.message
    far = box.copy()
    far.apply_translation((2e5, 0, 0))
    assert "beyond" in _mesh_error(tmp_path, "far.stl", _stl(far)).message


def test_good_mesh_stock_loads_and_builds(tmp_path):
    box = trimesh.creation.box((10, 20, 30))
    (tmp_path / "b.stl").write_bytes(_stl(box))
    setup = tmp_path / "s.toml"
    setup.write_text(MESH_SETUP.format(path="b.stl"))
    s = cutsim.load_setup(str(setup))
    from cutsim.stock import build_stock

    solid = build_stock(s.stock, s.tolerance, s.path)
    assert solid.volume() == pytest.approx(6000.0, rel=1e-6)
    assert np.allclose(solid.bounding_box(), (-5, -10, -15, 5, 10, 15), atol=1e-5)


def test_fine_tolerance_on_a_huge_bar_is_refused_at_its_key(tmp_path):
    """A 200 m bar at 0.0001 mm (the finest tolerance): a circle of radius 1e5 needs
    pi / acos(1 - 1e-9) ~ 70k segments, 4 outline vertices -> ~0.56M triangles, over a limit of 0.3M."""
    setup = tmp_path / "s.toml"
    setup.write_text((LATHE / "multipass.toml").read_text().split("[stock]")[0] +
                     '[stock]\nshape = "cylinder"\ndiameter = 200000.0\nz = [-10, 0]\n\n[[tool]]\nkind = "thread"\n'
                     "\n[simulation]\ntolerance = 0.0001\nmax_triangles = 300000\n")
    with pytest.raises(CutsimError) as e:
        cutsim.load_setup(str(setup))
    assert "[stock] diameter" in e.value.message and "max_triangles" in e.value.message
    line = setup.read_text().splitlines().index("diameter = 200000.0") + 1
    assert e.value.line == line


AXIS_SETUP = """
[machine]
kind = "lathe"
dialect = "cnc8x6"
[machine.constants]
8 = 160000
[stock]
shape = "cylinder"
diameter = 7.7
z = [-9.0, 0.0]
[[tool]]
kind = "profile"
points = [[0.0, 0.0], [1.74, 7.55], [-1.74, 7.55]]
"""


@pytest.mark.parametrize("x, fails", [("X6.324", True), ("X12.", False)])
def test_thread_tool_reaching_the_spindle_axis_is_an_error(tmp_path, x, fails):
    """A 60 degree lead-in of E2 moves the tool point in by 2 tan 60 = 3.464 mm of radius: from
    X6.324 (radius 3.162) that is past the axis, and the profile reaches 1.74 mm behind its point.
    Exit 2 at the G33 line instead of a folded (inside-out) solid; from X12 it stays clear."""
    (tmp_path / "s.toml").write_text(AXIS_SETUP)
    (tmp_path / "p.nc").write_text(f"N10 G00 G95 T1 S1000 M03\nN40 G00 {x} Z2.733\nN45 G33 Z-6.697 F8 E2.\nN50\n")
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(tmp_path / "p.nc"), "--setup",
                           str(tmp_path / "s.toml"), "--out", str(tmp_path / "out"), "--tolerance", "0.05", "-q"],
                          capture_output=True, text=True)
    if fails:
        assert proc.returncode == 2, proc.stderr
        assert "p.nc:3:1: error: the tool reaches the spindle axis" in proc.stderr
        r = 6.324 / 2 - 2 * math.tan(math.radians(60))
        assert f"tool point at radius {r:.4f} mm" in proc.stderr
        assert not (tmp_path / "out").exists()
    else:
        assert proc.returncode == 0, proc.stderr


REPEAT_SETUP = """
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 10.0]
[stock]
shape = "box"
x = [-20.0, 20.0]
y = [-20.0, 20.0]
z = [-10.0, 0.0]
[[tool]]
number = 3
kind = "ballmill"
diameter = 6.0
[simulation]
tolerance = 0.01
"""


def test_repeated_moves_remove_what_one_removes(tmp_path):
    """A plunge written 300 times (299 zero-length moves) removes what one plunge removes: a ball
    of radius 3 sunk 3.5 mm = hemisphere 2/3 pi r^3 + cylinder pi r^2 (3.5 - r), within the chordal
    tolerance times the cut's surface (2 pi r^2 + 2 pi r 0.5). Repeats of an earlier path are not
    swept again (they meet nothing the first run did not take)."""
    (tmp_path / "s.toml").write_text(REPEAT_SETUP)
    removed = {}
    for copies in (1, 300):
        body = "N30 G01 Z-3.5 F100\n" * copies
        prog = tmp_path / f"p{copies}.nc"
        prog.write_text(f"N10 G00 G17 G90 T3 S1000 M03\nN20 G00 X0 Y0 Z5\n{body}N40 G00 Z10\nN50 M30\n\n")
        r = cutsim.simulate(str(prog), str(tmp_path / "s.toml"))
        assert r.report["moves"] >= copies and not r.warnings
        removed[copies] = r.report["removed_volume"]
    expected = 2 / 3 * math.pi * 27 + math.pi * 9 * 0.5
    area = 2 * math.pi * 9 + 2 * math.pi * 3 * 0.5
    assert removed[1] == pytest.approx(expected, abs=0.01 * area)
    assert removed[300] == removed[1]


def test_needle_thin_thread_tool_at_a_coarse_tolerance_is_an_input_error(tmp_path):
    """A 1 degree thread tool 2 mm deep is about 0.02-0.03 mm wide where it cuts; on a 120 mm lead
    (47 degree helix) at tolerance 0.1 its chorded sweep folds over itself. That is exit 2 at the
    G33 line naming a finer tolerance, not an internal error (fuzz finding)."""
    (tmp_path / "s.toml").write_text('[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n[stock]\nshape = "cylinder"\n'
                                     'diameter = 40.0\nz = [-100.0, 0.0]\n[[tool]]\nnumber = 5\nkind = "thread"\n'
                                     'angle = 1.001\n')
    (tmp_path / "p.nc").write_text("N10 G00 G95 T5 D5 R12=120.0\nN20 G00 X50. Z10.\nN30 M04 S60\nN40 X36.\n"
                                   "N50 G33 Z-110. FR12 I0.\nN60 G00 X50.\nN70 Z10.\nN80 M05\n\n")
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(tmp_path / "p.nc"), "--setup",
                           str(tmp_path / "s.toml"), "--out", str(tmp_path / "out"), "--tolerance", "0.1", "-q"],
                          capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    assert "p.nc:5:1: error: the swept solid of this thread cut folds over itself" in proc.stderr
    assert "Traceback" not in proc.stderr and not (tmp_path / "out").exists()


# -- mill bodies counted in the estimate (fuzz: a ball-end mill at 1e-5 mm ran 30 s / died at 3 GB) --
MILL_SETUP = """\
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [-5.0, -5.0, 10.0]
[stock]
shape = "box"
x = [0.0, 25.0]
y = [0.0, 22.0]
z = [-6.5, 0.0]
[[tool]]
number = 1
kind = "ballmill"
diameter = 4.0
length = 12.0
[simulation]
tolerance = {tol}
max_triangles = {limit}
"""

MILL_PROG = """\
N10 G00 G17 G90 T1 S1000 M03
N20 G00 X12. Y11. Z5.
N30 G01 Z-3.6 F100
N40 G01 X20. Y19.
N50 G00 Z20.
"""


def _ball_hull_triangles(r: float, tol: float, a, b) -> int:
    """Triangles of the hull of a ball of radius r (vertices at the chordal tolerance: a ring of
    2 pi / theta and a quarter arc of (pi / 2) / theta layers, theta the chord angle) at two poses."""
    th = segment_angle(r, tol)
    n = math.ceil(2 * math.pi / th)
    k = math.ceil(math.pi / 2 / th)
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    pts = [[0.0, 0.0, 0.0]]
    for phi in np.linspace(0, math.pi / 2, k + 1)[1:]:
        pts += [[r * math.sin(phi) * math.cos(t), r * math.sin(phi) * math.sin(t), r - r * math.cos(phi)] for t in ang]
    body = np.array(pts)
    import manifold3d as m3d
    return m3d.Manifold.hull_points(np.vstack([body + a, body + b])).num_tri()


def test_fine_ball_mill_is_refused_before_it_is_swept(tmp_path):
    """A 4 mm ball-end mill at 0.0001 mm: each pose of its body is a hemisphere of about 25,000
    vertices, so the hull of the plunge (N30) alone has about 50,000 triangles (computed here from
    the sphere, not by cutsim). Under max_triangles = 60,000 the two feed moves (about 100,000)
    must be refused at the first of them, naming the key; the old estimate (4 triangles per ring
    vertex and segment) let it through to the booleans."""
    hull = _ball_hull_triangles(2.0, 1e-4, [12.0, 11.0, 0.05], [12.0, 11.0, -3.6])
    assert hull > 40_000
    setup = tmp_path / "s.toml"
    setup.write_text(MILL_SETUP.format(tol=1e-4, limit=60_000))
    prog = tmp_path / "p.nc"
    prog.write_text(MILL_PROG)
    with pytest.raises(CutsimError) as e:
        cutsim.simulate(str(prog), str(setup))
    assert e.value.line == 3 and "max_triangles = 60,000" in str(e.value)
    est = int(str(e.value).split("about ")[1].split(" triangles")[0].replace(",", ""))
    assert est >= 2 * hull


def test_mill_estimate_bounds_the_built_hulls():
    """For short 3D polylines of a flat, a bull-nose and a ball-end mill, the estimate of a chain
    piece is at least the triangles ``hull_sweep`` builds (it is checked against the limit before
    anything is built, so it must not undercount) and within a small factor of them."""
    import cutsim.stock.strategy_milling as R
    from cutsim.base.specs import ToolSpec
    from cutsim.stock import mill

    rng = np.random.default_rng(7)
    for kind, d, rc in [("endmill", 6.0, 0.0), ("endmill", 6.0, 1.0), ("ballmill", 4.0, 2.0)]:
        tool = ToolSpec(number=1, kind=kind, diameter=d, corner_radius=rc, length=20.0)
        for tol in (0.01, 0.001):
            for _ in range(3):
                pts = np.cumsum(rng.uniform(-3, 3, size=(4, 3)), axis=0) + [0, 0, -2.0]
                cap = mill.cap_height(0.0, tol)
                built = sum(s.num_tri() for s in mill.hull_sweep(pts, tool, tol, cap))
                est = R.chain_piece_triangles(pts, tool, tol, cap)
                assert built <= est <= 8 * max(built, 1), (kind, tol, built, est)


def test_flute_check_after_cleared_levels(tmp_path):
    """A 6 mm end mill with 5 mm flutes: a slot at Z-3 (flutes reach the top), the same plunge and
    slot at Z-8 (the material above the flutes is gone: no warning, the check's hit is taken off
    by the earlier cuts), then a plunge to Z-8 in fresh stock (line 11): the shank (radius
    r = 3 - 2 tol, a polygon within tol inside that circle) meets the 3 mm above Z-3, so the
    warning's volume is 3 pi r^2 within the polygon's deficit (3 pi ((r - tol)^2 .. r^2))."""
    setup = tmp_path / "s.toml"
    setup.write_text("""\
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 10.0]
[stock]
shape = "box"
x = [-20.0, 20.0]
y = [-20.0, 20.0]
z = [-10.0, 0.0]
[[tool]]
number = 1
kind = "endmill"
diameter = 6.0
length = 5.0
[simulation]
tolerance = 0.01
""")
    prog = tmp_path / "p.nc"
    prog.write_text("""\
N10 G00 G17 G90 T1 S1000 M03
N20 G00 X-5. Y-8. Z2.
N30 G01 Z-3. F100
N40 G01 X5.
N50 G00 Z2.
N60 G00 X-5.
N70 G01 Z-8.
N80 G01 X5.
N90 G00 Z2.
N100 G00 X-5. Y8.
N110 G01 Z-8.
N120 G01 X5.
N130 G00 Z20.
""")
    res = cutsim.simulate(str(prog), str(setup))
    flutes = [(w["line"], w["message"]) for w in res.warnings if "flute length" in w["message"]]
    assert len(flutes) == 1, flutes
    line, msg = flutes[0]
    assert line == 11, flutes
    vol = float(msg.split("(")[-1].split(" mm^3")[0])
    r = 3.0 - 2 * 0.01
    assert 3 * math.pi * (r - 0.01) ** 2 <= vol <= 3 * math.pi * r * r, vol


def _thread_counts(grouped: bool, setup, prog: str):
    """(estimates added for thread cuts, triangles of the thread sweeps built for the subtract)."""
    from cutsim.stock import budget, strategy_turning, sweeps, threads

    built, estimates = [], []
    orig, orig_motion, add = sweeps.screw_sweep, threads.motion, budget.Work.add

    def counting(*a, **k):
        out = orig(*a, **k)
        if len(a) < 6 and "zwindow" not in k:  # not the rebuilds near a rapid
            built.append(sum(s.num_tri() for s in out))
        return out

    def recording(self, tris, src, what):
        if "thread" in what:
            estimates.append(tris)
        return add(self, tris, src, what)

    strategy_turning.screw_sweep, threads.screw_sweep, budget.Work.add = counting, counting, recording
    if not grouped:
        threads.motion = lambda path: None
    try:
        cutsim.simulate(prog, setup)
    finally:
        strategy_turning.screw_sweep, threads.screw_sweep, budget.Work.add = orig, orig, add
        threads.motion = orig_motion
    return estimates, built


def test_grouped_thread_estimate_matches_the_grouped_sweep():
    """The multipass thread's passes lie on one helix and are swept as one group: the estimate
    counts that group's sweep (within 1 % of the triangles built), not every pass on its own,
    so it is below the sum of the passes swept one by one (what the estimate counted before)."""
    setup = cutsim.load_setup(str(LATHE / "multipass.toml"))
    prog = str(LATHE / "multipass.nc")
    est, built = _thread_counts(True, setup, prog)
    assert len(est) == len(built) >= 1
    assert abs(sum(est) - sum(built)) <= 0.01 * sum(built)
    _, single = _thread_counts(False, setup, prog)
    assert len(single) > len(built) and sum(built) < sum(single)


def test_mill_narrower_than_the_tolerance_is_refused_at_its_table(tmp_path):
    """A 2 um ball-end mill (radius 0.001 mm) at tolerance 0.05 mm: the chords of its circle would
    cross its axis, so it is an error at its [[tool]] table (line 10 of this setup) naming the
    tolerance that resolves it (the radius); at that tolerance the same move runs."""
    setup = tmp_path / "s.toml"
    setup.write_text(MILL_SETUP.format(tol=0.05, limit=3_000_000).replace("diameter = 4.0", "diameter = 0.002")
                     .replace("length = 12.0", "length = 1.0"))
    assert setup.read_text().splitlines()[9] == "[[tool]]"
    prog = tmp_path / "p.nc"
    prog.write_text("N10 G00 G17 G90 T1 S1000 M03\nN20 G00 X12. Y11. Z1.\nN30 G01 Z-0.5 F100\nN40 X13.\nN50 G00 Z5.\n")
    with pytest.raises(CutsimError) as e:
        cutsim.simulate(str(prog), str(setup))
    assert e.value.line == 10 and "tolerance of at most 0.001 mm" in str(e.value)
    cutsim.simulate(str(prog), str(setup), tolerance=0.001)
