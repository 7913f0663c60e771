"""Sinumerik milling cycles: the finished geometry of complete (VARI units 0) cycles against the
analytic shapes of spec/sinumerik.md, measured on the part mesh with plane sections and rays
(tests/support/sinumerik_measure.py), never with cutsim's own geometry."""
from __future__ import annotations

import math

import numpy as np
import pytest

import cutsim
from cutsim import CutsimError
from support.sinumerik_measure import floor_z, hsection, point_segment_distance, ray

TOL = 0.002  # chordal tolerance: the asserted 5 um width needs the tool polygon this fine
SETUP = """
[machine]
kind = "mill"
dialect = "sinumerik"
start = [{sx}, {sy}, 50.0]

[stock]
shape = "box"
x = [{x0}, {x1}]
y = [{y0}, {y1}]
z = [{z0}, {z1}]

[[tool]]
number = 1
kind = "endmill"
diameter = 10.0
length = 40.0

[[tool]]
number = 2
kind = "endmill"
diameter = 20.0
length = 40.0
"""
HEAD = "G17 G90\nT1 D1\nM6\nS2000 M3 F300\n"


def run(tmp_path, body, box=((0, 100), (0, 100), (-20, 0)), start=(50, 50), tol=TOL):
    setup = tmp_path / "setup.toml"
    setup.write_text(SETUP.format(sx=start[0], sy=start[1], x0=box[0][0], x1=box[0][1], y0=box[1][0], y1=box[1][1],
                                  z0=box[2][0], z1=box[2][1]))
    prog = tmp_path / "p.mpf"
    prog.write_text(HEAD + body + "\nM30\n")
    return cutsim.simulate(str(prog), str(setup), tolerance=tol)


def across(segs, c, u):
    """Width of the cavity through c perpendicular to u, and its length along u."""
    n = np.array([-u[1], u[0]])
    return ray(segs, c, n) + ray(segs, c, -n), ray(segs, c, u) + ray(segs, c, -u)


def test_slot1_stadiums(tmp_path):
    # 3 radial slots 12 x 30 from radius 10 about (50, 50), at 20 + k*120 degrees, floor at -6
    r = run(tmp_path, "SLOT1(10, 0, 2, -6, , 3, 30, 12, 50, 50, 10, 20, 120, 100, 300, 6, 0, 0, 0)")
    m = r.mesh()
    hs = hsection(m, -3.0)
    for k in range(3):
        a = math.radians(20 + 120 * k)
        u = np.array([math.cos(a), math.sin(a)])
        c = np.array([50.0, 50.0]) + u * (10 + 15)
        w, length = across(hs, c, u)
        assert w == pytest.approx(12.0, abs=0.005)
        assert length == pytest.approx(30.0, abs=0.005)
        assert floor_z(m, c, 5.0) == pytest.approx(-6.0, abs=0.002)
    area = 12 * 18 + math.pi * 36
    assert r.report["removed_volume"] == pytest.approx(3 * area * 6, rel=5e-4)
    assert r.report["warnings"] == []  # VARI tens 0: G0 only to RFP + SDIS, the infeed itself at FFD


def test_slot2_arc_slots(tmp_path):
    # 3 circular slots of width 12 on radius 30 about (50, 50), 60 degrees long, floor at -5
    r = run(tmp_path, "SLOT2(10, 0, 2, -5, , 3, 60, 12, 50, 50, 30, 10, 120, 100, 300, 5, 0, 0, 10)")
    m = r.mesh()
    hs = hsection(m, -2.5)
    for k in range(3):
        a = math.radians(10 + 120 * k + 30)
        u = np.array([math.cos(a), math.sin(a)])
        c = np.array([50.0, 50.0]) + 30 * u
        w = ray(hs, c, u) + ray(hs, c, -u)
        assert w == pytest.approx(12.0, abs=0.005)
        assert floor_z(m, c, 5.0) == pytest.approx(-5.0, abs=0.002)
        # the round end: its centre lies at angle 10 + 120 k (start), radius 30
        e = np.array([50.0, 50.0]) + 30 * np.array([math.cos(math.radians(10 + 120 * k)), math.sin(math.radians(10 + 120 * k))])
        t = np.array([math.sin(math.radians(10 + 120 * k)), -math.cos(math.radians(10 + 120 * k))])
        assert ray(hs, e, t) == pytest.approx(6.0, abs=0.005)
    area = math.radians(60) * 30 * 12 + math.pi * 36
    assert r.report["removed_volume"] == pytest.approx(3 * area * 5, rel=5e-4)


def test_pocket1_rounded_rectangle(tmp_path):
    # 40 x 24 pocket, corner radius 8, centre (50, 50), long side at 30 degrees, floor -5 in two steps
    r = run(tmp_path, "POCKET1(10, 0, 2, -5, , 40, 24, 8, 50, 50, 30, 100, 300, 5, 0, 0, 10)")
    m = r.mesh()
    hs = hsection(m, -2.5)
    a = math.radians(30)
    u = np.array([math.cos(a), math.sin(a)])
    c = np.array([50.0, 50.0])
    w, length = across(hs, c, u)
    assert w == pytest.approx(24.0, abs=0.005)
    assert length == pytest.approx(40.0, abs=0.005)
    # corner: along the diagonal from the corner circle's centre the wall is 8 away
    v = np.array([-u[1], u[0]])
    cc = c + 12 * u + 4 * v
    assert ray(hs, cc, (u + v) / math.sqrt(2)) == pytest.approx(8.0, abs=0.005)
    for p in (c, c + 15 * u + 7 * v, c - 15 * u - 7 * v):
        assert floor_z(m, p, 5.0) == pytest.approx(-5.0, abs=0.002)
    area = 40 * 24 - (4 - math.pi) * 64
    assert r.report["removed_volume"] == pytest.approx(area * 5, rel=5e-4)


def test_pocket2_disc_with_finishing_allowance(tmp_path):
    # circular pocket radius 14 at (50, 50), floor -4, FAL 0.5: roughing then a finishing pass
    r = run(tmp_path, "POCKET2(10, 0, 2, -4, , 14, 50, 50, 100, 300, 4, 0, 0.5, 10)")
    m = r.mesh()
    hs = hsection(m, -2.0)
    c = np.array([50.0, 50.0])
    for ang in (0, 50, 130, 250):
        u = np.array([math.cos(math.radians(ang)), math.sin(math.radians(ang))])
        assert ray(hs, c, u) == pytest.approx(14.0, abs=0.005)
    for p in (c, c + (9, 0), c + (0, -12.5)):
        assert floor_z(m, p, 5.0) == pytest.approx(-4.0, abs=0.002)
    assert r.report["removed_volume"] == pytest.approx(math.pi * 196 * 4, rel=5e-4)


@pytest.mark.parametrize("body, message", [
    ("T2 D1\nM6\nSLOT1(10, 0, 2, -6, , 3, 30, 12, 50, 50, 10, 20, 120)", "wider than the slot"),
    ("SLOT1(10, 0, 2, -6, , 6, 30, 12, 50, 50, 5, 0, 0)", "overlap"),
    ("SLOT2(10, 0, 2, -5, , 4, 80, 12, 50, 50, 30, 0, 0)", "overlap"),
    ("POCKET1(10, 0, 2, -5, , 40, 24, 3, 50, 50)", "CRAD 3 is smaller than the tool radius"),
    ("POCKET1(10, 0, 2, -5, , 40, 24, 8, 50, 50, 0, 100, 300, 5, 0, 0, 10, 0, 0, 0, 99)", "at most 20 parameters"),
    ("POCKET2(10, 0, 2, \"deep\", , 14, 50, 50)", "must be a number"),
    ("SLOT1(10, 0, 2, -6)", "required"),
    ("CYCLE72(\"NOPE\", 10, 0, 2, -5)", "not found"),
    ("CYCLE72(\"A:B\", 10, 0, 2, -5)", "not both in the program"),
])
def test_cycle_errors_carry_the_line(tmp_path, body, message):
    with pytest.raises(CutsimError) as e:
        run(tmp_path, body)
    assert message in e.value.message
    assert e.value.line == 5 + body.count("\n")


# the seed's free contour (seed 003, contour editor output, OCR damage repaired)
SEED_CONTOUR = """KONT_A:
;#7__DlgK contour definition begin - Don't change!;*GP*;*RO*
G17 G90 ;*GP*
G1 X13 Y69.65 ;*GP*
G3 X28 Y54.65 I=AC(28) J=AC(69.65) ;*GP*
G2 X47.741 Y37.856 I=AC(28) J=AC(34.65) ;*GP*
G1 X52.435 Y8.951 ;*GP*
G2 X44.714 Y3.998 I=AC(47.5) J=AC(8.15) ;*GP*
G3 X11.286 I=AC(28) J=AC(-20.915) ;*GP*
G2 X3.565 Y8.951 I=AC(8.5) J=AC(8.15) ;*GP*
G1 X8.259 Y37.856 ;*GP*
G2 X28 Y54.65 I=AC(28) J=AC(34.65) ;*GP*
G3 X43 Y69.65 I=AC(28) J=AC(69.65) ;*GP*
;CON,0,0.000,2,2,MST:2,1,AX:X,Y,1,J;*GP**RO*
;S,EX:13,EY:69.65ATT:G1;*GP*;*RO*
;ACCW,EX:28,EY:54.65,RAD:15;*GP*;*RO*
;#End contour definition end - Don't change!;*GP*;*RO*
KONT_E:
"""
# the same contour the other way round (for G42)
SEED_REVERSED = """KREV_A:
G17 G90
G1 X43 Y69.65
G2 X28 Y54.65 I=AC(28) J=AC(69.65)
G3 X8.259 Y37.856 I=AC(28) J=AC(34.65)
G1 X3.565 Y8.951
G3 X11.286 Y3.998 I=AC(8.5) J=AC(8.15)
G2 X44.714 Y3.998 I=AC(28) J=AC(-20.915)
G3 X52.435 Y8.951 I=AC(47.5) J=AC(8.15)
G1 X47.741 Y37.856
G3 X28 Y54.65 I=AC(28) J=AC(34.65)
G2 X13 Y69.65 I=AC(28) J=AC(69.65)
KREV_E:
"""
# (start, end, centre or None, clockwise) of the seed contour: the analytic wall
SEED_ELEMENTS = [((13, 69.65), (28, 54.65), (28, 69.65), False), ((28, 54.65), (47.741, 37.856), (28, 34.65), True),
                 ((47.741, 37.856), (52.435, 8.951), None, False), ((52.435, 8.951), (44.714, 3.998), (47.5, 8.15), True),
                 ((44.714, 3.998), (11.286, 3.998), (28, -20.915), False), ((11.286, 3.998), (3.565, 8.951), (8.5, 8.15), True),
                 ((3.565, 8.951), (8.259, 37.856), None, False), ((8.259, 37.856), (28, 54.65), (28, 34.65), True),
                 ((28, 54.65), (43, 69.65), (28, 69.65), False)]


def contour_samples(n=7):
    pts = []
    for s, e, c, cw in SEED_ELEMENTS:
        s, e = np.array(s, float), np.array(e, float)
        for t in np.linspace(0.1, 0.9, n):
            if c is None:
                pts.append(s + t * (e - s))
                continue
            c = np.array(c, float)
            r = np.linalg.norm(s - c)
            a0 = math.atan2(*(s - c)[::-1])
            a1 = math.atan2(*(e - c)[::-1])
            d = (a0 - a1) % (2 * math.pi) if cw else (a1 - a0) % (2 * math.pi)
            a = a0 - t * d if cw else a0 + t * d
            pts.append(c + r * np.array([math.cos(a), math.sin(a)]))
    return pts


@pytest.mark.parametrize("call", [
    'CYCLE72("KONT_A:KONT_E", 10, 0, 2, -5, 5, 0, 0, 300, 100, 0, 41, 1, 10, 0, 1, 10)',
    'CYCLE72("KREV_A:KREV_E", 10, 0, 2, -5, 5, 0, 0, 300, 100, 0, 42, 1, 10, 0, 1, 10)',
], ids=["G41", "G42-reversed"])
def test_cycle72_wall_on_the_seed_contour(tmp_path, call):
    r = run(tmp_path, call + "\nM30\n" + SEED_CONTOUR + SEED_REVERSED, box=((-20, 76), (-35, 69.65), (-10, 0)),
            start=(28, 90))
    m = r.mesh()
    hs = hsection(m, -2.5)
    # At the neck the fillets (r 15) touch the big circle (r 20 about (28, 34.65)): where a fillet
    # comes closer than the tool diameter to that circle, the pass along the circle necessarily cuts
    # into it (the contour itself is a bottleneck there), so those samples cannot lie on the wall.
    pts = [p for p in contour_samples() if abs(math.dist(p, (28, 34.65)) - 20) >= 10 or math.dist(p, (28, 69.65)) > 15.01]
    assert len(pts) == 53
    dist = [point_segment_distance(hs, p) for p in pts]
    assert max(dist) < 0.005
    # the tool ran outside the body: 1 mm beyond the wall there is no material at mid-depth,
    # 1 mm inside there is (a ray from there outwards meets the wall after 1 mm)
    for s, e, c, cw in SEED_ELEMENTS[2:3]:
        mid = (np.array(s) + np.array(e)) / 2
        out = np.array([e[1] - s[1], -(e[0] - s[0])]) / math.dist(s, e)  # right of travel = body side
        assert ray(hs, mid - out, out) == pytest.approx(1.0, abs=0.005)
    assert floor_z(m, (58.0, 20.0), 5.0) == pytest.approx(-5.0, abs=0.002)


def test_cycle71_face(tmp_path):
    # face the whole 60 x 40 block from Z 0 to -1.5 in two infeeds, zig-zag along X
    r = run(tmp_path, "CYCLE71(10, 0, 2, -1.5, 0, 0, 60, 40, 0, 1, 6, 5, 0, 500, 31, 2)",
            box=((0, 60), (0, 40), (-10, 0)), start=(-20, -20))
    m = r.mesh()
    assert m.bounds[1][2] == pytest.approx(-1.5, abs=0.002)  # no material left above the face
    for p in ((0.5, 0.5), (30, 20), (59.5, 39.5), (12.3, 33.3)):
        assert floor_z(m, p, 5.0) == pytest.approx(-1.5, abs=0.002)
    assert r.report["part_volume"] == pytest.approx(60 * 40 * 8.5, rel=5e-4)


def test_pocket3_helix_floor_allowance(tmp_path):
    # 36 x 22 pocket, corner radius 6, centre (50, 50), 15 degrees, floor -4, helix plunge,
    # floor allowance 0.3 and wall allowance 0.4 (complete: roughed, floor cleared, wall finished)
    r = run(tmp_path, "POCKET3(10, 0, 2, -4, 36, 22, 6, 50, 50, 15, 4, 0.4, 0.3, 300, 100, 0, 20, 5, , , , 3, 2)")
    m = r.mesh()
    hs = hsection(m, -2.0)
    a = math.radians(15)
    u = np.array([math.cos(a), math.sin(a)])
    c = np.array([50.0, 50.0])
    w, length = across(hs, c, u)
    assert w == pytest.approx(22.0, abs=0.005)
    assert length == pytest.approx(36.0, abs=0.005)
    for p in (c, c + 12 * u, c - 14 * u + 2 * np.array([-u[1], u[0]])):
        assert floor_z(m, p, 5.0) == pytest.approx(-4.0, abs=0.002)
    area = 36 * 22 - (4 - math.pi) * 36
    assert r.report["removed_volume"] == pytest.approx(area * 4, rel=5e-4)


def test_pocket4_disc(tmp_path):
    # circular pocket radius 13 centred (40, 60), floor -3, vertical G1 plunge
    r = run(tmp_path, "POCKET4(10, 0, 2, -3, 13, 40, 60, 3, 0, 0, 300, 100, 0, 10)")
    m = r.mesh()
    hs = hsection(m, -1.5)
    c = np.array([40.0, 60.0])
    for ang in (10, 100, 200, 300):
        u = np.array([math.cos(math.radians(ang)), math.sin(math.radians(ang))])
        assert ray(hs, c, u) == pytest.approx(13.0, abs=0.005)
    assert floor_z(m, c + (4, 4), 5.0) == pytest.approx(-3.0, abs=0.002)
    assert r.report["removed_volume"] == pytest.approx(math.pi * 169 * 3, rel=5e-4)
