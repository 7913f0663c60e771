"""--images: PNGs of the set size that are not blank, drawn in true workpiece coordinates with the
expected regions coloured, and a report.html that embeds every image and lists every check.

Expected numbers come from the test programs and setups (tests/data/programs/checks/*.toml comments), not from
a run: the multipass blank is Z-30..0 with radius 13.5 and an undercut to radius 12.5 at
Z-12..-8; its thread (lead 1.5, 60 degrees, root diameter 26.177) has a groove at angle 0 at
Z = 3 - 1.5 k. The slot is 8 wide centred on Y20 to X30, floor Z-3 (slot-deep: Z-3.05)."""
import base64
import io
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parents[1] / "data" / "programs" / "checks"
pytest.importorskip("pyvista")
from PIL import Image  # noqa: E402

import cutsim  # noqa: E402
from cutsim.reports import images as I  # noqa: E402
from cutsim.reports import views3d as V  # noqa: E402
from cutsim.reports.images import HEIGHT, WIDTH  # noqa: E402


def _run(nc, toml, out):
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / nc), "--setup", str(HERE / toml),
                           "--out", str(out), "--images", "-q"], capture_output=True, text=True)
    return proc


def _check_png(data, section=False):
    img = np.asarray(Image.open(io.BytesIO(data) if isinstance(data, bytes) else data).convert("RGB"), dtype=float)
    if section or getattr(data, "name", "") == "section.png":  # as high as the part needs, within a range
        assert img.shape[1:] == (WIDTH, 3) and I.SECTION_MIN_HEIGHT <= img.shape[0] <= HEIGHT
    else:
        assert img.shape == (HEIGHT, WIDTH, 3)
    nonwhite = np.mean(np.any(img < 245, axis=2))
    assert 0.05 < nonwhite < 0.95, f"{nonwhite:.3f} of the pixels are drawn"
    assert img.std() > 10
    return img


def _rgb(hexcolor):
    return np.array([int(hexcolor[i:i + 2], 16) for i in (1, 3, 5)], dtype=float)


def _near(img, rc, color, tol=12.0):
    """The pixel at rc (and its 3x3 neighbourhood, all of it) has ``color``."""
    r, c = rc
    patch = img[r - 1:r + 2, c - 1:c + 2].reshape(-1, 3)
    return bool(np.all(np.abs(patch - color).max(axis=1) <= tol))


def _value(text):
    return float(text.replace("\u2212", "-"))


def _tick_labels(view, axis_values, coord):
    """The tick values of one axis as read back from the plotter's text actors: for each value a
    text actor showing it at world ``coord`` (0 = x, 1 = y) equal to the value."""
    found = []
    for text, pos in I.text_actors(view.plotter):
        try:
            v = _value(text)
        except ValueError:
            continue
        if any(abs(v - t) < 1e-9 and abs(pos[coord] - t) < 1e-9 for t in axis_values):
            found.append(v)
    return sorted(set(found))


@pytest.fixture(scope="module")
def multipass():
    return cutsim.simulate(str(HERE / "multipass.nc"), str(HERE / "multipass.toml"))


@pytest.fixture(scope="module")
def slot_deep():
    return cutsim.simulate(str(HERE / "slot-deep.nc"), str(HERE / "slot.checks.toml"), checks=False)


@pytest.mark.parametrize("nc,toml,names", [
    ("multipass.nc", "multipass.toml", ["iso.png", "section.png", "thread-1.png"]),
    ("slot.nc", "slot.checks.toml", ["iso.png", "top.png", "deviation.png"]),
])
def test_images_and_html(tmp_path, nc, toml, names):
    out = tmp_path / "out"
    proc = _run(nc, toml, out)
    assert proc.returncode == 0, proc.stderr
    pngs = {p.name for p in out.glob("*.png")}
    assert pngs == set(names)
    for name in names:
        _check_png(out / name)
    html = (out / "report.html").read_text()
    assert "http://" not in html.replace("http://schemas", "") and "https://" not in html and "<script" not in html
    embedded = re.findall(r'<img alt="([^"]+)"[^>]*src="data:image/png;base64,([^"]+)"', html)
    assert [n for n, _ in embedded] == names  # in the order they were made
    for name, data in embedded:
        assert base64.b64decode(data) == (out / name).read_bytes()
    for c in json.loads((out / "report.json").read_text())["checks"]:
        assert re.search(rf'<td rowspan="\d+">{re.escape(c["name"])}</td>', html)


def test_deviation_map_shows_gouge(tmp_path):
    out = tmp_path / "deep"
    proc = _run("slot-deep.nc", "slot.checks.toml", out)
    assert proc.returncode == 1  # the design check fails on the gouge
    _check_png(out / "deviation.png")
    assert "FAIL" in (out / "report.html").read_text()


# ---------------------------------------------------------------------------------------------
# lathe: section and thread detail in true coordinates
# ---------------------------------------------------------------------------------------------
def test_nice_ticks_are_round():
    # steps of 1, 2, 2.5 or 5 x 10^k, about n intervals: never -20, 16, 52, 89
    assert I.nice_ticks(-31.8, 1.8, 7) == [-30.0, -25.0, -20.0, -15.0, -10.0, -5.0, 0.0]
    assert I.nice_ticks(-20.0, 89.0, 6) == [-20.0, 0.0, 20.0, 40.0, 60.0, 80.0]
    assert I.nice_ticks(10.4, 13.6, 7) == [10.5, 11.0, 11.5, 12.0, 12.5, 13.0, 13.5]
    assert I.nice_ticks(-0.06, 0.06, 4) == [-0.05, 0.0, 0.05]


def test_section_in_workpiece_coordinates(multipass):
    view = I.section_view(multipass)
    try:
        z = view.ticks["Z mm"]
        r = view.ticks["radius mm"]
        # the blank is Z-30..0: its ends are round ticks, every tick lies near the part
        assert -30.0 in z and 0.0 in z and min(z) >= -40 and max(z) <= 10
        assert r[0] == 0.0 and max(r) >= 13.5
        assert view.ticks["\u00d8 mm"] == [2 * v for v in r]
        # read back from the plotter's actors: a label "-30" at x = -30, ...
        assert _tick_labels(view, z, 0) == z
        assert _tick_labels(view, r, 1) == r
        rc_part, rc_air, rc_undercut = view.pixel(-20.3, 6.3), view.pixel(-20.3, 16.3), view.pixel(-10.3, 13.1)
        img = _check_png(view.png(), section=True)
    except BaseException:
        view.plotter.close()
        raise
    assert _near(img, rc_part, _rgb(I.PART_COLOR))
    assert _near(img, rc_air, np.array([255.0, 255, 255]))
    assert _near(img, rc_undercut, np.array([255.0, 255, 255]))  # the blank's undercut is not material


def test_thread_detail(multipass):
    spec = [c for c in multipass.setup.checks if c["kind"] == "thread"][0]
    view = I.thread_view(multipass, spec, 1)
    try:
        z, r = view.ticks["Z mm"], view.ticks["radius mm"]
        # two and a half pitches (1.5) around the middle of the checked range Z-6..-1
        assert min(z) <= -3.5 - 1.5 and max(z) >= -3.5 + 1.5 and max(z) - min(z) <= 5 * 1.5
        assert min(r) <= 26.177 / 2 and max(r) >= 13.5 and max(r) - min(r) < 4  # root .. crest, not the bar
        assert _tick_labels(view, z, 0) == z and _tick_labels(view, r, 1) == r
        notes = " ".join(view.notes)
        root = float(re.search(r"root \u00d8 (\d+\.\d+)", notes).group(1))
        assert abs(root - 26.177) <= spec["tolerance"]
        # the bar is a polygon inside the 27 mm circle (chords of the tolerance): its radius at the
        # section angle (clear of the polygon's vertices) reads up to the tolerance small
        crest = float(re.search(r"crest \u00d8 (\d+\.\d+)", notes).group(1))
        assert 27.0 - 2 * multipass.report["tolerance"] - 0.001 <= crest <= 27.0
        assert "P 1.500" in notes
        flanks = [float(a) for a in re.findall(r"(\d+\.\d)\u00b0", notes)]
        assert len(flanks) == 3 and all(abs(a - 30.0) < 0.5 for a in flanks[:2]) and abs(flanks[2] - 60) < 1.0
        texts = [t for t, _ in I.text_actors(view.plotter)]
        assert any(t.startswith("root \u00d8") for t in texts) and any(t.startswith("flanks") for t in texts)
        # a groove at angle 0 at Z-3.0: at radius 13.3 its half width is (13.3 - 13.0885) tan 30 = 0.12
        rc_groove, rc_tooth, rc_core, rc_air = (view.pixel(-3.0, 13.3), view.pixel(-3.75, 13.3),
                                                view.pixel(-3.75, 12.6), view.pixel(-3.75, 13.8))
        img = _check_png(view.png())
    except BaseException:
        view.plotter.close()
        raise
    assert _near(img, rc_groove, _rgb(I.REMOVED_COLOR))
    assert _near(img, rc_tooth, _rgb(I.PART_COLOR))
    assert _near(img, rc_core, _rgb(I.PART_COLOR))
    assert _near(img, rc_air, np.array([255.0, 255, 255]))


def test_thread_detail_of_an_inside_thread():
    """The tooth detail of examples/cnc8x6-lathe/nut-m24x1.5 (M24x1.5-6H, its last pass X24.1 with
    a full-profile inside insert from Z4.5 under M03): the root is the nut's major diameter 24.1
    (the insert's flat tip), the crest D1 = 24.1 - 2 x 5H/8 = 22.4762 (its shoulders), a groove at
    angle 0 at Z = 4.5 - 1.5 k (-9.0 among them); the nut's body beyond the root, the bore within
    the crest. The groove at radius 11.7 is P/16 + (12.05 - 11.7) tan 30 = 0.30 half wide. (The body
    is probed at Z-11.25, clear of the pitch's bracket drawn between the roots at -10.5 and -9.0.)"""
    ex = Path(__file__).resolve().parents[2] / "examples" / "cnc8x6-lathe"
    nut = cutsim.simulate(str(ex / "nut-m24x1.5.nc"), str(ex / "nut-m24x1.5.toml"))
    spec = [c for c in nut.setup.checks if c["kind"] == "thread"][0]
    view = I.thread_view(nut, spec, 1)
    try:
        z, r = view.ticks["Z mm"], view.ticks["radius mm"]
        assert min(r) <= 11.238 and max(r) >= 12.05 and max(r) - min(r) < 4  # crest .. root
        notes = " ".join(view.notes)
        root = float(re.search(r"root \u00d8 (\d+\.\d+)", notes).group(1))
        crest = float(re.search(r"crest \u00d8 (\d+\.\d+)", notes).group(1))
        # drawn midway between the sweep's stations: up to 2 x the tolerance inside the helicoid
        tol = nut.report["tolerance"]
        assert 24.1 - 2 * tol - 0.001 <= root <= 24.1 + 0.001, root
        assert abs(crest - (24.1 - 2 * 5.0 / 8.0 * math.sqrt(3.0) / 2.0 * 1.5)) <= 2 * tol + 0.001, crest
        assert "P 1.500" in notes and "M24x1.5-6H" in view.caption
        groove, tooth, body, bore = (view.pixel(-9.0, 11.7), view.pixel(-9.75, 11.7), view.pixel(-11.25, 12.4),
                                     view.pixel(-9.75, 10.9))
        img = _check_png(view.png())
    except BaseException:
        view.plotter.close()
        raise
    assert _near(img, groove, _rgb(I.REMOVED_COLOR))
    assert _near(img, tooth, _rgb(I.PART_COLOR))
    assert _near(img, body, _rgb(I.PART_COLOR))
    assert _near(img, bore, _rgb(I.REMOVED_COLOR))


# ---------------------------------------------------------------------------------------------
# mill: top view by floor, deviation per face
# ---------------------------------------------------------------------------------------------
def test_top_view_colours_floors(slot_deep):
    view = I.top_view(slot_deep)
    try:
        assert view.notes == ["floor Z 0.000", "floor Z \u22123.050"]  # the top and the slot floor
        x, y = view.ticks["X mm"], view.ticks["Y mm"]
        assert 0.0 in x and 60.0 in x and 0.0 in y and 40.0 in y
        assert _tick_labels(view, x, 0) == x and _tick_labels(view, y, 1) == y
        rc_floor, rc_top, rc_out = view.pixel(15.3, 20.3), view.pixel(45.3, 20.3), view.pixel(30.3, -1.5)
        img = _check_png(view.png())
    except BaseException:
        view.plotter.close()
        raise
    floor, top = img[rc_floor], img[rc_top]
    assert np.abs(floor - top).max() > 60  # two floors, two clearly different colours
    for c in (floor, top):
        assert c.max() - c.min() > 40  # coloured, not grey or white
    assert _near(img, rc_out, np.array([255.0, 255, 255]))


def test_deviation_per_face(slot_deep):
    from cutsim.reports.measure import load_solid

    spec = [c for c in slot_deep.setup.checks if c["kind"] == "design"][0]
    view = I.deviation_view(slot_deep, load_solid(spec["path"]), spec)
    try:
        mesh = view.mesh
        d = np.asarray(mesh.cell_data["deviation (unclipped) mm"])
        assert len(d) == mesh.n_cells and "deviation mm" in mesh.cell_data  # cell data: one value per face
        nrm = np.asarray(mesh.compute_normals(cell_normals=True, point_normals=False).cell_data["Normals"])
        cen = np.asarray(mesh.cell_centers().points)
        floor = (nrm[:, 2] > 0.99) & (np.abs(cen[:, 2] + 3.05) < 1e-6)
        assert np.count_nonzero(floor) >= 2
        # a uniform gouge: one value, no gradient. A floor face by the slot's round end may meet the
        # design's coarser end arc diagonally: sqrt(0.05^2 + tol^2) - 0.05 <= tol^2 / 0.1 = 1e-3 at tol 0.01
        assert np.allclose(d[floor], -0.05, atol=1e-3)
        assert np.median(d[floor]) == pytest.approx(-0.05, abs=1e-6)
        walls = (np.abs(nrm[:, 2]) < 0.01) & (np.abs(cen[:, 1] - 16.0) < 1e-6) & (cen[:, 2] > -2.9)
        assert np.count_nonzero(walls) >= 1
        assert np.all(np.abs(d[walls]) < 1e-6)  # the slot's wall is on the design: zero
        lim = I.DEV_K * spec["max_deviation"]
        assert view.ticks["deviation mm"][0] == pytest.approx(-lim) and view.ticks["deviation mm"][-1] == pytest.approx(lim)
        assert any(n.startswith("worst gouge \u22120.050 mm") and "OUT OF TOL" in n for n in view.notes)
        img = _check_png(view.png())
    except BaseException:
        view.plotter.close()
        raise
    del img


def test_render_images_reports_progress(multipass):
    calls = []
    captions = {}
    out = I.render_images(multipass, lambda s, i, n: calls.append((s, i, n)), captions)
    assert list(out) == ["iso.png", "section.png", "thread-1.png"] == list(captions)
    assert calls == [("images", 0, 3), ("images", 1, 3), ("images", 2, 3), ("images", 3, 3)]
    assert all(captions.values())


# ---------------------------------------------------------------------------------------------
# progress: plain lines when stderr is not a terminal
# ---------------------------------------------------------------------------------------------
def test_progress_lines_without_a_terminal(monkeypatch):
    import cutsim.cli as cli

    clock = [100.0]
    monkeypatch.setattr(cli.time, "monotonic", lambda: clock[0])
    buf = io.StringIO()
    prog = cli._Progress(True, stream=buf, tty=False)
    prog("sweeps", 0, 120)
    clock[0] += 0.5
    prog("sweeps", 10, 120)  # under a second: nothing yet
    clock[0] += 0.6
    prog("sweeps", 40, 120)  # 1.1 s: the first line
    for k in range(41, 60):  # 19 calls within 1.9 s: no line (at most one every 5 s)
        clock[0] += 0.1
        prog("sweeps", k, 120)
    clock[0] += 3.2
    prog("sweeps", 90, 120)  # 5.1 s after the first line
    prog("sweeps", 120, 120)
    prog("checks", 0, 2)  # a short stage prints nothing
    prog("checks", 2, 2)
    prog("images", 0, 1)  # a long stage of one step: its time when done
    clock[0] += 2.5
    prog("images", 1, 1)
    assert buf.getvalue().splitlines() == ["cutsim: sweeps 40/120", "cutsim: sweeps 90/120",
                                           "cutsim: sweeps 120/120 done (6.2 s)", "cutsim: images 1/1 done (2.5 s)"]


def test_cli_progress_in_a_log(tmp_path):
    """stderr to a pipe: single plain lines for the image stage (several seconds), no \\r or ESC."""
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / "multipass.nc"), "--setup",
                           str(HERE / "multipass.toml"), "--out", str(tmp_path / "o"), "--images"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "\r" not in proc.stderr and "\x1b" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert re.fullmatch(r"cutsim: images 3/3 done \(\d+\.\d s\)", [ln for ln in lines if "images" in ln][-1])
    assert all(re.fullmatch(r"cutsim: \w[\w ]* \d+/\d+( done \(\d+\.\d s\))?", ln) for ln in lines), lines
    assert proc.stdout.startswith("multipass.nc: ") and proc.stdout.count("\n") == 1  # the summary: stdout


def test_nearest_on_triangles_is_exact():
    """The deviation map's pruned nearest-triangle search finds the same distances as trying every
    triangle (small sizes: cutsim.reports.measure's brute force), for a mix of large and small
    triangles and points on, near and far from them."""
    from cutsim.reports.measure import _point_triangle_distance

    rng = np.random.default_rng(7)
    small = rng.uniform(0, 50, (600, 1, 3)) + rng.normal(0, 0.8, (600, 3, 3))
    big = rng.uniform(-20, 70, (20, 3, 3))
    tri = np.concatenate([small, big])
    on = tri[rng.integers(0, len(tri), 300)].mean(axis=1)  # centroids: distance 0
    pts = np.concatenate([on, on + rng.normal(0, 0.01, on.shape), rng.uniform(-30, 80, (200, 3))])
    ref = _point_triangle_distance(pts, tri)[0]
    assert len(pts) * len(tri) <= 500_000  # the reference tries every triangle
    got = V._nearest_on_triangles(pts, tri)[0]
    assert np.allclose(got, ref, rtol=0, atol=1e-12)
    assert np.all(got[:300] < 1e-12)


def test_top_view_many_levels_is_continuous():
    """More flat levels than MAX_FLOORS (16 steps 0.5 + 0.7 k deep): one continuous scale over the
    cut depth, each face's Z as cell data."""
    import types

    from manifold3d import Manifold

    stock = Manifold.cube((100, 20, 20)).translate((0, 0, -20))
    part = stock
    depths = [0.5 + 0.7 * k for k in range(16)]
    for k, dz in enumerate(depths):
        part = part - Manifold.cube((6, 10, dz)).translate((2 + 6 * k, 5, -dz))
    setup = cutsim.load_setup(str(HERE / "slot.toml"))
    res = types.SimpleNamespace(setup=setup, part=part, stock=stock, report={"program": "stairs", "tolerance": 0.01})
    view = I.top_view(res)
    try:
        z = np.asarray(view.mesh.cell_data["Z mm"])
        nrm = np.asarray(view.mesh.compute_normals(cell_normals=True, point_normals=False).cell_data["Normals"])
        levels = sorted({round(float(v), 6) for v in z[nrm[:, 2] > 0.99]})
        assert levels == sorted([round(-d, 6) for d in depths] + [0.0])
        rc_deep, rc_shallow = view.pixel(2 + 6 * 15 + 3, 10), view.pixel(2 + 3, 10)
        img = _check_png(view.png())
    except BaseException:
        view.plotter.close()
        raise
    assert np.abs(img[rc_deep] - img[rc_shallow]).max() > 60


# ---------------------------------------------------------------------------------------------
# one camera convention: the same feature on the same side in every view; axes span the stock
# ---------------------------------------------------------------------------------------------
def _plate_result(pocket_depth=4.0):
    """A 100 x 60 x 10 plate (top Z0) with a 25 x 20 pocket at its back left (X10..35, Y35..55)."""
    import types

    from manifold3d import Manifold

    stock = Manifold.cube((100, 60, 10)).translate((0, 0, -10))
    part = stock - Manifold.cube((25, 20, pocket_depth + 1)).translate((10, 35, -pocket_depth))
    setup = cutsim.load_setup(str(HERE / "slot.toml"))
    return types.SimpleNamespace(setup=setup, part=part, stock=stock, report={"program": "plate", "tolerance": 0.01})


def _lathe_result(thin_end=-20.0):
    """A Ø40 bar Z-60..0 turned to Ø20 over 20 mm from Z ``thin_end`` (-20: the face end)."""
    import types

    from manifold3d import Manifold

    stock = Manifold.cylinder(60, 20, 20, 96).translate((0, 0, -60))
    ring = Manifold.cylinder(20, 25, 25, 96) - Manifold.cylinder(20, 10, 10, 96)
    part = stock - ring.translate((0, 0, thin_end))
    setup = cutsim.load_setup(str(HERE / "multipass.toml"))
    return types.SimpleNamespace(setup=setup, part=part, stock=stock, report={"program": "bar", "tolerance": 0.01})


def _render(view):
    try:
        return np.asarray(Image.open(io.BytesIO(view.png())).convert("RGB"), dtype=float)
    except BaseException:
        view.plotter.close()
        raise


def _centroid(mask):
    rows, cols = np.nonzero(mask)
    assert len(rows) > 200, len(rows)
    return rows.mean(), cols.mean()


def test_pocket_on_the_same_side_in_top_iso_and_deviation():
    """Found by colour alone: the pocket's floor (dark viridis blue, or the deviation map's gouge
    blue) lies left of and above the plate's top face (yellow-green, or pale green) in all three
    views, as it does on the plate (X10..35 of 0..100, Y35..55 of 0..60)."""
    res = _plate_result()
    top = _render(I.top_view(res))
    iso = _render(I.iso_view(res))
    design = _plate_result(3.0).part  # the pocket 1 mm shallower on the design: its floor a gouge
    dev = _render(I.deviation_view(res, design, {"name": "d", "max_deviation": 0.01}))
    for img in (top, iso):
        r, g, b = (img[..., k] for k in range(3))
        floor = _centroid((b - g > 30) & (r < 120))  # viridis' dark end
        face = _centroid((g - b > 60) & (g > 150))  # viridis' yellow-green end
        assert floor[1] < face[1] - 40, (floor, face)  # left
        if img is top:
            assert floor[0] < face[0] - 10  # and behind: up in the top view
    r, g, b = (dev[..., k] for k in range(3))
    gouge = _centroid((b - r > 60) & (b > 60))
    within = _centroid((g > 150) & (g - b > 12) & (g - r > 5))  # the pale green band, lit
    assert gouge[1] < within[1] - 40, (gouge, within)


def test_lathe_face_end_on_the_right_in_iso_and_section():
    """+Z is to the right in both lathe views: the part's pixels (its greys, lit or flat) lie
    further left when the thin end is at the face (Z-20..0) than when it is at the chuck
    (Z-60..-40); the same bar otherwise."""
    def centre(view):
        img = _render(view)
        grey = (np.ptp(img, axis=2) < 40) & (img.mean(axis=2) > 90) & (img.mean(axis=2) < 235)
        return _centroid(grey)[1]

    for make in (I.iso_view, I.section_view):
        at_face, at_chuck = centre(make(_lathe_result(-20.0))), centre(make(_lathe_result(-60.0)))
        assert at_face < at_chuck - 40, (make.__name__, at_face, at_chuck)


def _labels(plotter):
    """(value, world position) of every numeric world-anchored label."""
    out = []
    for text, pos in I.text_actors(plotter):
        try:
            out.append((_value(text), np.array(pos)))
        except ValueError:
            pass
    return out


def _axis_labels(labels, k, fixed):
    """The labels of the axis along coordinate k: placed at their own value on that axis and
    outside the stock box next to the edge at ``fixed`` ({coordinate: value})."""
    return sorted(v for v, pos in labels if abs(pos[k] - v) < 1e-9
                  and all(abs(pos[j] - c) > 1e-6 for j, c in fixed.items()))


@pytest.mark.parametrize("make,edges", [  # {axis title: (its coordinate, the edge's other coordinates)}
    (_plate_result, {"X mm": (0, {1: 0.0, 2: -10.0}), "Y mm": (1, {0: 0.0, 2: -10.0}),
                     "Z mm": (2, {0: 100.0, 1: 0.0})}),
    (_lathe_result, {"Z mm": (2, {0: -20.0, 1: 20.0}), "X mm": (0, {1: 20.0, 2: -60.0}),
                     "Y mm": (1, {0: -20.0, 2: 0.0})}),
])
def test_iso_axes_span_the_stock(make, edges):
    """Read back from the plotter: each axis line runs exactly along a stock box edge from the
    stock's minimum to its maximum (the plate's X ends at 100, not at a rounder 125), its labels sit
    at their values, all inside the stock's range and at most one step from its ends; no two text
    labels overlap on screen."""
    from vtkmodules.vtkRenderingCore import vtkTextActor

    res = make()
    b = res.stock.bounding_box()
    lo, hi = np.array(b[:3]), np.array(b[3:])
    view = I.iso_view(res)
    try:
        p = view.plotter
        labels = _labels(p)
        for title, (k, fixed) in edges.items():
            lb = p.renderer.actors[f"axis-{title}"].GetBounds()
            assert lb[2 * k] == pytest.approx(lo[k], abs=1e-9) and lb[2 * k + 1] == pytest.approx(hi[k], abs=1e-9)
            for j, c in fixed.items():
                assert lb[2 * j] <= c <= lb[2 * j + 1]
            vals = _axis_labels(labels, k, fixed)
            assert len(vals) >= 2, title
            step = vals[1] - vals[0]
            assert lo[k] - 1e-9 <= vals[0] <= lo[k] + step and hi[k] - step <= vals[-1] <= hi[k] + 1e-9, (title, vals)
            assert vals == view.ticks[title]
        p.render()
        boxes = []
        for a in p.renderer.actors.values():
            if isinstance(a, vtkTextActor) and a.GetInput().strip():
                bb = [0.0] * 4
                a.GetBoundingBox(p.renderer, bb)
                x, y = a.GetPositionCoordinate().GetComputedDoubleDisplayValue(p.renderer)
                boxes.append((a.GetInput(), x + bb[0], x + bb[1], y + bb[2], y + bb[3]))
        for i, (ta, a0, a1, b0, b1) in enumerate(boxes):
            assert 0 <= a0 and a1 <= WIDTH and 0 <= b0 and b1 <= HEIGHT, ta
            for tb, c0, c1, d0, d1 in boxes[i + 1:]:
                assert a1 <= c0 or c1 <= a0 or b1 <= d0 or d1 <= b0, (ta, tb)
    finally:
        view.plotter.close()


def test_top_view_ticks_span_the_stock():
    res = _plate_result()
    view = I.top_view(res)
    try:
        x, y = view.ticks["X mm"], view.ticks["Y mm"]
        assert _tick_labels(view, x, 0) == x and _tick_labels(view, y, 1) == y
        assert x[0] == 0.0 and x[-1] == 100.0 and y[0] == 0.0 and y[-1] == 60.0
    finally:
        view.plotter.close()


def test_section_fills_its_image(multipass):
    """A slender part (30 long, radius 13.5): the image is lower than HEIGHT and drawn over most of
    its height."""
    view = I.section_view(multipass)
    img = _render(view)
    assert I.SECTION_MIN_HEIGHT <= img.shape[0] < HEIGHT and img.shape[1] == WIDTH
    rows = np.flatnonzero(np.any(img < 200, axis=2).sum(axis=1) > 3)
    assert (rows.max() - rows.min()) / img.shape[0] > 0.8


def test_3d_views_are_deterministic():
    res = _plate_result()
    assert I.iso_view(res).png() == I.iso_view(res).png()


def test_a_sliver_is_no_floor():
    """A flat level of 0.05 x 0.05 mm (0.0025 mm^2, under MIN_FLOOR_AREA) left at Z-2 beside a
    Z-4 pocket is not listed as a floor; the pocket's floor (100 mm^2) is."""
    import types

    from manifold3d import Manifold

    stock = Manifold.cube((40, 30, 10)).translate((0, 0, -10))
    part = stock - Manifold.cube((10, 10, 5)).translate((10, 10, -4)) - \
        Manifold.cube((0.05, 0.05, 3)).translate((20, 10, -2))
    res = types.SimpleNamespace(setup=cutsim.load_setup(str(HERE / "slot.toml")), part=part, stock=stock,
                                report={"program": "sliver", "tolerance": 0.01})
    view = I.top_view(res)
    view.plotter.close()
    assert view.notes == ["floor Z 0.000", "floor Z \u22124.000"]
