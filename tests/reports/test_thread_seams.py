"""A thread cut from the zero pulse on a turned bar: its helix stations and the revolved solids'
outlines lie in the half-plane at C0. The thread check and the lathe images section the part
clear of such construction seams (measure.seam_free_angles) and must read the program's thread
from any start Z. Expected values come from the program words: root diameter = X of the G33 pass,
lead = F, a groove at angle phi lies at z = z0 + lead * phi / 360 (mod lead), I0 from Z = z0."""
import re

import numpy as np
import pytest

import cutsim
from cutsim.reports import images as I
from cutsim.reports import measure as M

SETUP = """
[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [80.0, 0.0, 50.0]

[stock]
shape = "cylinder"
diameter = 40.0
z = [-60.0, 0.0]

[[tool]]
number = 1
kind = "turning"
angle = 55.0
tip_radius = 0.4

[[tool]]
number = 2
kind = "thread"
angle = 60.0
tip_radius = 0.0

[simulation]
tolerance = 0.005

[[check]]
kind = "thread"
z = [-16.0, -4.0]
lead = 2.0
starts = 1
hand = "right"
root_diameter = {root}
phase = [0.0]
phase_z = {z0}
"""

PROGRAM = """N10 G95 G00 T1 D1 S1200 M03
N20 G00 X{turned} Z2.
N30 G01 Z-25. F0.2
N40 X42.
N50 G00 X80. Z50.
N60 T2 D2 S400 M03
N70 G00 X{root} Z{z0}.
N80 G33 Z-20. F2.
N90 G00 X34.
N100 X80. Z50.
N110 M30
"""

# (turned diameter, root diameter = X of the G33 pass, start Z)
CASES = [(30.0, 27.546, 4), (30.0, 27.546, 3), (26.0, 23.546, 4), (26.0, 23.546, 3)]


def _run(tmp_path, turned, root, z0):
    setup = tmp_path / "seam.toml"
    setup.write_text(SETUP.format(root=root, z0=float(z0)))
    return cutsim.simulate("seam.nc", str(setup), text=PROGRAM.format(turned=turned, root=root, z0=z0))


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"D{c[0]:g}-Z{c[2]}")
def seam_part(request, tmp_path_factory):
    turned, root, z0 = request.param
    return _run(tmp_path_factory.mktemp("seam"), turned, root, z0), root, z0


def test_the_check_passes_and_reads_the_program(seam_part):
    result, root, _z0 = seam_part
    rec = result.checks[0]
    assert rec["passed"], rec
    items = {i["quantity"]: i["measured"] for i in rec["items"]}
    assert abs(items["lead"] - 2.0) <= 0.002
    assert items["starts"] == 1 and items["hand"] == "right"
    assert root - 2 * 0.005 - 1e-6 <= items["root_diameter"] <= root  # chords lie inside


def test_no_measuring_plane_holds_a_vertex(seam_part):
    result = seam_part[0]
    phis = M.thread_angles(result.part, 36)
    assert np.all(np.abs(phis - np.arange(36) * 10.0) <= 1.0)
    verts = np.asarray(result.part.to_mesh().vert_properties, dtype=float)
    off = np.hypot(verts[:, 0], verts[:, 1]) > 1e-3
    ang = np.degrees(np.arctan2(verts[off, 1], verts[off, 0]))
    for phi in phis:  # the whole plane: phi and phi + 180
        d = np.abs((ang - phi + 90.0) % 180.0 - 90.0)
        assert d.min() > 0.01, (phi, d.min())


def test_every_section_has_the_programs_grooves(seam_part):
    """At every measuring angle the roots lie where the program put them (no seam section)."""
    result, root, z0 = seam_part
    m = M.measure_thread(result.part, -16.0, -4.0)
    assert len(m["angles"]) == 36
    for phi in m["angles"]:
        rts = np.array([(z, r) for p, z, r in m["roots"] if p == phi])
        assert len(rts) >= 5, phi  # a groove every 2 mm over 12 mm, the two at the ends cut off
        want = z0 + 2.0 * phi / 360.0
        err = (rts[:, 0] - want + 1.0) % 2.0 - 1.0
        assert np.all(np.abs(err) <= 0.002), (phi, err)
        assert np.all(np.abs(rts[:, 1] - root / 2) <= 0.005 + 1e-6), (phi, rts[:, 1])


def test_thread_image_shows_one_groove_per_pitch(seam_part):
    result, root, _z0 = seam_part
    spec = result.setup.checks[0]
    view = I.thread_view(result, spec, 1)
    try:
        notes = " ".join(view.notes)
        texts = [a.GetInput() for a in view.plotter.renderer.actors.values() if hasattr(a, "GetInput")]
    finally:
        view.plotter.close()
    assert "P 2.000 here, 2.000 median  (lead 2.000)" in notes
    flanks = [float(a) for a in re.findall(r"(\d+\.\d)\u00b0", notes)]
    assert len(flanks) == 3 and all(abs(a - 30.0) <= 0.2 for a in flanks[:2]), flanks
    d = float(re.search(r"root \u00d8 (\d+\.\d+)", notes).group(1))
    assert root - 0.011 <= d <= root
    title = next(t for t in texts if t and "tooth detail" in t)
    assert "1 start(s), right hand" in title and "C0 " not in title


def test_section_angle_is_near_c0_and_clear_of_both_solids(seam_part):
    result = seam_part[0]
    phi = I.section_angle(result)
    assert 0.0 < abs(phi) <= 1.0
    _, clear = M.seam_free_angles([result.part, result.stock], [phi], window=0.0)
    assert clear[0] > 0.01
