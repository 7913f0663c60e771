"""Milling: exact milled solids against analytic geometry (stadium, disc, ball circle, helical trench),
the helix/jump errors and the milling warnings. Every expected number comes from geometry, and
every measurement from trimesh (tests/support/geometry.py style), never from cutsim's own sweep code."""
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from conftest import EXAMPLES
import cutsim

HERE = Path(__file__).resolve().parents[1] / "data" / "programs" / "mill"
PLATE = str(HERE / "plate.toml")


def _sim(name, tol=0.01, setup=PLATE):
    return cutsim.simulate(str(HERE / name), setup, tolerance=tol)


def _yz_section(mesh: trimesh.Trimesh, x: float) -> np.ndarray:
    """Segments (n, 2, 2) of (y, z) where the plane X = x cuts the mesh surface."""
    segs = trimesh.intersections.mesh_plane(mesh, plane_normal=[1.0, 0, 0], plane_origin=[x, 0, 0])
    return np.asarray(segs)[..., 1:]


def _xz_section(mesh: trimesh.Trimesh, y: float) -> np.ndarray:
    segs = trimesh.intersections.mesh_plane(mesh, plane_normal=[0, 1.0, 0], plane_origin=[0, y, 0])
    return np.asarray(segs)[..., [0, 2]]


def _crossings(segs: np.ndarray, z: float) -> np.ndarray:
    """Horizontal coordinates where the section boundary crosses height ``z`` (sorted)."""
    a, b = segs[:, 0], segs[:, 1]
    m = (np.minimum(a[:, 1], b[:, 1]) < z) & (np.maximum(a[:, 1], b[:, 1]) > z)
    t = (z - a[m, 1]) / (b[m, 1] - a[m, 1])
    return np.sort(a[m, 0] + t * (b[m, 0] - a[m, 0]))


def _inner(xs: np.ndarray, lo: float = 0.0, hi: float = 100.0) -> np.ndarray:
    """Drop the crossings of the plate's own outer faces."""
    return xs[(xs > lo + 1e-6) & (xs < hi - 1e-6)]


def _floor(segs: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Heights of horizontal section segments lying within ``lo..hi`` horizontally."""
    pts = segs.reshape(-1, 2)
    flat = np.abs(segs[:, 0, 1] - segs[:, 1, 1]) < 1e-9
    inside = (segs[:, :, 0].min(axis=1) >= lo) & (segs[:, :, 0].max(axis=1) <= hi)
    above = segs[:, 0, 1] > -19.0  # not the plate's bottom face
    keep = flat & inside & above
    return segs[keep][:, 0, 1] if np.any(keep) else pts[:0, 1]


# -- straight slot: a stadium ------------------------------------------------------------------
def test_slot_is_the_stadium():
    r = _sim("slot.nc")
    mesh = r.mesh()
    assert mesh.is_watertight
    # width at the middle of the slot, halfway down: the flanks at y = 50 -+ 5
    ys = _inner(_crossings(_yz_section(mesh, 50.0), -1.5))
    assert len(ys) == 2
    assert abs(ys[0] - 45.0) <= 0.002 and abs(ys[1] - 55.0) <= 0.002
    # floor at Z-3 across the slot
    fl = _floor(_yz_section(mesh, 50.0), 45.0, 55.0)
    assert len(fl) and np.all(np.abs(fl + 3.0) <= 0.002)
    # stadium: 60 long between the centres, radius 5, 3 deep
    vol = (60 * 10 + math.pi * 25) * 3
    assert abs(r.report["removed_volume"] - vol) <= 5e-4 * vol
    assert r.report["warnings"] == []


def test_full_circle_pocket_is_the_disc():
    r = _sim("pocket.nc", tol=0.001)
    mesh = r.mesh()
    # G02 X54 Y50 I-4: a full circle of radius 4 about (50, 50) with a 10 mm tool: disc of radius 9
    for x in (50.0, 47.3):
        ys = _inner(_crossings(_yz_section(mesh, x), -2.0))
        half = math.sqrt(81 - (x - 50) ** 2)
        assert len(ys) == 2
        assert abs(ys[0] - (50 - half)) <= 0.002 and abs(ys[1] - (50 + half)) <= 0.002
    xs = _inner(_crossings(_xz_section(mesh, 50.3), -2.0))
    half = math.sqrt(81 - 0.3 ** 2)
    assert len(xs) == 2
    assert abs(xs[0] - (50 - half)) <= 0.002 and abs(xs[1] - (50 + half)) <= 0.002
    fl = _floor(_yz_section(mesh, 50.0), 41.0, 59.0)
    assert len(fl) and np.all(np.abs(fl + 4.0) <= 0.002)
    vol = math.pi * 81 * 4
    assert abs(r.report["removed_volume"] - vol) <= 5e-4 * vol


# -- ball-end groove -----------------------------------------------------------------------------
def test_ball_groove_section_is_the_ball_circle():
    tol = 0.01
    r = _sim("ball.nc", tol=tol)
    segs = _yz_section(r.mesh(), 50.0)
    pts = segs.reshape(-1, 2)
    groove = pts[(pts[:, 1] < -1e-6) & (pts[:, 1] > -19.0) & (np.abs(pts[:, 0] - 50.0) < 3.5)]  # the groove, not the plate's faces
    assert len(groove) > 10
    # the ball (radius 3) has its centre 3 above the tip: (y, z) = (50, 1)
    d = np.hypot(groove[:, 0] - 50.0, groove[:, 1] - 1.0)
    assert np.all(np.abs(d - 3.0) <= tol + 1e-6)
    assert abs(groove[:, 1].min() + 2.0) <= tol
    # width at the top: chord of the circle 1 above its centre's depth
    ys = _inner(_crossings(segs, -1e-3))
    w = 2 * math.sqrt(9 - (1 + 1e-3) ** 2)
    assert abs((ys[-1] - ys[0]) - w) <= 2 * tol


# -- the CNC8x6 helix (seed 002) ---------------------------------------------------------------
def _helix_trench_volume() -> float:
    """Independent volume of the helical trench: the depth map of the tool's lowest point.

    Tool radius 5 on a circle of radius 100 about (100, 0), clockwise from the angle pi, Z rising
    1.05 per turn from Z0. A point at (rho, phi) of the annulus is first touched when the tool
    centre is within the angle delta(rho) of it; the floor there is the tool's Z at that moment.
    The stock keeps 10 <= x <= 190 (|y| <= 120 holds the whole annulus), plate 0..20."""
    nr, nphi = 400, 6000
    rho = 95 + (np.arange(nr) + 0.5) * (10 / nr)
    total = 0.0
    for rr in rho:
        delta = math.acos((rr * rr + 100 * 100 - 25) / (2 * rr * 100))
        a1, a2 = math.acos(90 / rr), math.acos(-90 / rr)  # 10 <= 100 + rr cos(phi) <= 190
        for lo, hi in ((a1, a2), (-a2, -a1)):
            phi = lo + (np.arange(nphi) + 0.5) * ((hi - lo) / nphi)
            u = (math.pi - phi) % (2 * math.pi)  # clockwise angle from the start
            floor = np.where((u <= delta) | (u >= 2 * math.pi - delta), 0.0, 1.05 * (u - delta) / (2 * math.pi))
            total += float(np.sum(20.0 - floor)) * ((hi - lo) / nphi) * rr * (10 / nr)
    return total


HELIX_TOL = 0.002  # the default tolerance: the helix is swept directly (stock/helix.py), in well under a second


@pytest.fixture(scope="module")
def helix():
    prog = EXAMPLES / "cnc8x6-mill" / "helix.nc"
    return cutsim.simulate(str(prog), str(prog.with_suffix(".toml")), tolerance=HELIX_TOL)


def test_helix_positions(helix):
    arcs = [m for m in helix.program.moves if type(m).__name__ == "Arc"]
    assert len(arcs) == 22  # N50 executed 21 times, then N60
    # 21 full turns and a half turn at 1.05 per turn
    assert arcs[-1].end[2] == pytest.approx(21.5 * 1.05, abs=1e-9)
    assert arcs[-1].end[:2] == pytest.approx((200.0, 0.0), abs=1e-9)
    # N80 then rapids to X100 Y0 Z40: the final position in the report
    assert helix.report["final_position"] == pytest.approx([100.0, 0.0, 40.0])
    # ... while the helix itself ends at X200 Y0 after 21.5 turns: the last cut
    assert helix.report["last_cut_position"] == pytest.approx([200.0, 0.0, 21.5 * 1.05])


def test_helix_trench_volume(helix):
    exact = _helix_trench_volume()
    got = helix.report["removed_volume"]
    assert abs(got - exact) <= 5e-4 * exact, (got, exact)


def test_helix_trench_floor(helix):
    mesh = helix.mesh()
    segs = _yz_section(mesh, 100.0)
    # X100 crosses the annulus at y = +-100 (phi = +-90 degrees), a quarter and three quarters
    # of the first turn after the start; the floor there is the tool's Z when it first arrived
    delta = math.acos((2 * 100 * 100 - 25) / (2 * 100 * 100))
    for y, u in ((100.0, math.pi / 2), (-100.0, 3 * math.pi / 2)):
        expect = 1.05 * (u - delta) / (2 * math.pi)
        pts = segs.reshape(-1, 2)
        near = pts[(np.abs(pts[:, 0] - y) < 0.5) & (pts[:, 1] > 1e-6)]  # not the plate bottom
        assert abs(near[:, 1].min() - expect) <= HELIX_TOL, (y, near[:, 1].min(), expect)
        # the trench walls at radii 95 and 105 about (100, 0), through the plate
        ys = _inner(_crossings(segs, 10.0), -120.0, 120.0)
        side = ys[(ys * np.sign(y)) > 0]
        # within the tolerance (stations and profile chords) plus the section's own sampling
        assert np.allclose(np.sort(np.abs(side)), [95.0, 105.0], atol=2 * HELIX_TOL)


# -- bad helix/jump programs: exit 2 with the line ---------------------------------------------
@pytest.mark.parametrize("name, line, text", [
    ("helix-g98.nc", 3, "G98"),
    ("helix-missing.nc", 2, "N15"),
    ("helix-noq.nc", 2, "Q"),
])
def test_bad_helix_programs_exit_2(tmp_path, name, line, text):
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / name), "--setup", PLATE,
                           "--out", str(out), "-q"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert f"{name}:{line}:" in proc.stderr and text in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (out / "part.stl").exists() and not (out / "report.json").exists()


def test_jump_loop_that_does_not_end():
    # Q99999999 repeats cannot finish: the executed-blocks guard stops it with the G73 line (a
    # small guard here; the CLI's default guard takes a while to reach)
    from cutsim.interp import InterpConfig, interpret

    cfg = InterpConfig(dialect="cnc8x6", machine_kind="mill", start=(0.0, 0.0, 0.0), max_blocks=10000)
    text = (HERE / "helix-endless.nc").read_text()
    with pytest.raises(cutsim.CutsimError) as e:
        interpret("helix-endless.nc", text, cfg)
    assert e.value.line == 3 and "does not end" in str(e.value)


# -- warnings ----------------------------------------------------------------------------------
def test_mill_warnings_with_lines():
    r = _sim("warnings.nc")
    got = {(w["line"], w["message"].split(" ")[0]) for w in r.report["warnings"]}
    assert (1, "rapid") in got  # N10 G00 down into the plate
    assert (4, "plunge") in got  # T3 has no centre cutting edges
    assert (7, "the") in got  # T4's 5 mm flutes, 8 deep
    assert len(r.report["warnings"]) == 3
    # N20 rapid straight up out of its own hole and N50 out of the plunge hole: no false alarms
    assert all(w["line"] not in (2, 5, 8) for w in r.report["warnings"])


def test_center_cutting_key_is_checked(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(Path(PLATE).read_text().replace("center_cutting = false", 'center_cutting = "no"'))
    with pytest.raises(cutsim.CutsimError) as e:
        cutsim.load_setup(str(bad))
    assert "center_cutting" in str(e.value)


# -- mesh stock ----------------------------------------------------------------------------------
def test_slot_in_mesh_stock(tmp_path):
    box = trimesh.creation.box(extents=[100, 100, 20])
    box.apply_translation([50, 50, -10])
    box.export(tmp_path / "blank.stl")
    setup = tmp_path / "mesh.toml"
    text = Path(PLATE).read_text()
    text = text.replace('shape = "box"\nx = [0.0, 100.0]\ny = [0.0, 100.0]\nz = [-20.0, 0.0]', 'shape = "mesh"\npath = "blank.stl"')
    setup.write_text(text)
    r = _sim("slot.nc", setup=str(setup))
    vol = (60 * 10 + math.pi * 25) * 3
    assert abs(r.report["removed_volume"] - vol) <= 5e-4 * vol
    assert r.report["stock_volume"] == pytest.approx(200000.0)


def test_flute_check_same_path_deeper(tmp_path):
    """Flute checks skip a pass whose shank lies inside the shank of an earlier clean pass on the
    same XY path (stock/mill_checks.py ``_shadowed``), but not one that reaches lower into fresh stock. A
    6 mm end mill with 5 mm flutes on a 20 mm plate slots X-30..30 (through the plate, entering and
    leaving outside it) at Z-3 (flutes above the top), Z-6 (shank from Z-1: cleared by the Z-3 pass) and Z-13 (line 12):
    its shank from Z-8 meets the 2 mm from Z-8 to Z-6 that no pass took, over the shank's
    footprint in the plate: X-20..20 x 2 r (r = 3 - 2 tol; straight flanks, exact). The deeper passes at Z-16 .. Z-25 (bottoms below the plate's
    Z-20 or inside the earlier shanks) find nothing more; the slot goes through the plate but for
    the 2 mm no flute reached."""
    tol = 0.01
    setup = tmp_path / "s.toml"
    setup.write_text(f"""\
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [-30.0, 0.0, 10.0]
[stock]
shape = "box"
x = [-20.0, 20.0]
y = [-20.0, 20.0]
z = [-20.0, 0.0]
[[tool]]
number = 1
kind = "endmill"
diameter = 6.0
length = 5.0
[simulation]
tolerance = {tol}
""")
    lines = ["N10 G00 G17 G90 T1 S1000 M03"]
    n = 20
    for z in (-3, -6, -13, -16, -19, -22, -25):
        lines += [f"N{n} G00 X-30. Y0.", f"N{n + 10} G01 Z{z}. F100", f"N{n + 20} G01 X30.", f"N{n + 30} G00 Z2."]
        n += 40
    lines.append(f"N{n} G00 Z20.")
    prog = tmp_path / "p.nc"
    prog.write_text("\n".join(lines) + "\n")
    res = cutsim.simulate(str(prog), str(setup))
    flutes = [(w["line"], w["message"]) for w in res.warnings if "flute length" in w["message"]]
    assert [line for line, _ in flutes] == [12], flutes  # the Z-13 slot (N120)
    assert not [w for w in res.warnings if "flute length" not in w["message"]], res.warnings
    vol = float(flutes[0][1].split("(")[-1].split(" mm^3")[0])
    assert vol == pytest.approx(2.0 * 40.0 * 2 * (3.0 - 2 * tol), abs=2e-3), vol
    # the slot through the plate (X-20..20 x 6 mm) but for Z-8..-6: 18 mm deep
    assert res.report["removed_volume"] == pytest.approx(40.0 * 6.0 * 18.0, abs=1e-3)


def test_tool_far_bigger_than_the_stock(tmp_path):
    """A 2 m flat end mill over a 10 x 10 x 5 mm plate: its sweeps reach far beyond the plate and
    are cut off at the plate's box (stock/cuts.py ``Frame.clip``) without changing what the
    plate loses. Plunge to Z-1 (a 3D move: hulls), ramp to X5 Z-2 (both discs cover the plate, the
    lower bottom is Z-2), then a level pass at Z-3 (a prism): the plate is faced to Z-3 exactly,
    300 mm^3, and no warning."""
    setup = tmp_path / "s.toml"
    setup.write_text("""\
[machine]
kind = "mill"
dialect = "cnc8x6"
start = [0.0, 0.0, 10.0]
[stock]
shape = "box"
x = [0.0, 10.0]
y = [0.0, 10.0]
z = [-5.0, 0.0]
[[tool]]
number = 1
kind = "endmill"
diameter = 2000.0
length = 20.0
[simulation]
tolerance = 0.01
""")
    prog = tmp_path / "p.nc"
    prog.write_text("""\
N10 G00 G17 G90 T1 S1000 M03
N20 G00 X0. Y0. Z5.
N30 G01 Z-1. F100
N40 G01 X5. Z-2.
N50 G01 Z-3.
N60 G01 X10.
N70 G00 Z20.
""")
    res = cutsim.simulate(str(prog), str(setup))
    assert res.warnings == []
    assert res.report["removed_volume"] == pytest.approx(300.0, abs=1e-6)
    lo, hi = res.mesh().bounds
    assert hi[2] == pytest.approx(-3.0, abs=1e-9) and lo[2] == pytest.approx(-5.0, abs=1e-9)
