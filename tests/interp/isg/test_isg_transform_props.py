"""Properties of ISG rotation and mirroring on a mill (docs/dialects/isg.md, "Rotation and mirroring"):
a transformed program must give exactly the moves of the same contour transformed by hand.

The hand model here is independent of Isg.program_frame (interp/isg/frames.py): numpy matrices built from the
documented order - contour rotation about its centre (#ROTATION ON [ANGLE CENTER1 CENTER2] or G68 R X Y),
then the mirroring about the program zero (G20..G23, G351), then the #CS stack (each a turn about Z
then a translation; the last one switched on acts first), then G54 and G92. A program P is drawn at
random (lines G00/G01, circles G02/G03 with I/J/K relative or G161 absolute, with R > 0 and R < 0 (the
longer arc), full circles, helices, absolute and G91 incremental words, axes and zero centre words left
out, in G17, G18 and G19, the frame switched in the middle of the contour);
the model turns each block into the machine move it must give (start, end, centre, direction: a
mirrored plane reverses it) and writes the program P' of those moves in plain machine coordinates.
Both P and P' run through the public interpreter and must agree with the model to 1e-6 mm.

The centre of an R circle is computed here from the chord (the one of the two centres whose arc in the
programmed direction turns through at most 180 degrees for R > 0, more for R < 0), not by the code under
test. Tool radius compensation: G41 under a mirrored plane is G42 on the hand-mirrored contour, and a
rotation keeps the side; the inside offset corners of a convex polygon are its offset edges'
intersections, computed here.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as hst

from cutsim.interp import InterpConfig, interpret
from cutsim.interp import canon

TOL = 1e-6
START = (0.0, 0.0, 50.0)
G54 = (12.5, -7.25, 3.0)
SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                     HealthCheck.filter_too_much])


def run(text: str, radius: float = 2.0) -> canon.Program:
    cfg = InterpConfig(dialect="isg", machine_kind="mill", start=START, tool_radii={1: radius},
                       work_offsets={"G54": G54})
    return interpret("t.nc", text, cfg)


PLANES = {"G17": (0, 1, 2), "G18": (2, 0, 1), "G19": (1, 2, 0)}  # the plane's two main axes, its normal
PLANE_NAMES = {"G17": "XY", "G18": "ZX", "G19": "YZ"}


def rot_in(deg: float, a: int, c: int) -> np.ndarray:
    """A turn by deg degrees from axis a towards axis c."""
    r = math.radians(deg)
    m = np.eye(3)
    m[a, a], m[a, c], m[c, a], m[c, c] = math.cos(r), -math.sin(r), math.sin(r), math.cos(r)
    return m


def rot_z(deg: float) -> np.ndarray:
    return rot_in(deg, 0, 1)


class Frame:
    """The hand model of the program -> machine map, in the documented order."""

    def __init__(self, offset=(0.0, 0.0, 0.0)):
        self.rot = None  # (angle, centre 1, centre 2, the plane's axes a, c)
        self.mir = [False, False, False]
        self.cs: list[tuple] = []  # (tx, ty, tz, c), in the order switched on
        self.offset = np.array(offset, dtype=float)

    def affine(self) -> tuple[np.ndarray, np.ndarray]:
        L, t = np.eye(3), np.zeros(3)
        if self.rot is not None:
            deg, c1, c2, a, c = self.rot
            cen = np.zeros(3)
            cen[a], cen[c] = c1, c2
            L, t = rot_in(deg, a, c), cen - rot_in(deg, a, c) @ cen
        M = np.diag([-1.0 if m else 1.0 for m in self.mir])
        L, t = M @ L, M @ t
        for tx, ty, tz, c in reversed(self.cs):
            L, t = rot_z(c) @ L, rot_z(c) @ t + np.array([tx, ty, tz])
        return L, t + self.offset

    def to_machine(self, p) -> np.ndarray:
        L, t = self.affine()
        return L @ np.asarray(p, dtype=float) + t

    def to_program(self, q) -> np.ndarray:
        L, t = self.affine()
        return np.linalg.solve(L, np.asarray(q, dtype=float) - t)

    def mirrored(self, a: int = 0, c: int = 1) -> bool:
        """Whether the plane of axes a, c is mirrored (its orientation reversed)."""
        L, _ = self.affine()
        return np.linalg.det(L[np.ix_([a, c], [a, c])]) < 0


def f3(v: float) -> str:
    return f"{v:.3f}"


def r3(v: float) -> float:
    return float(f3(v))


def sweep(s, e, c, cw: bool) -> float:
    """The angle (radians, in (0, 2 pi]) from s to e about c in the given direction."""
    a0 = math.atan2(s[1] - c[1], s[0] - c[0])
    a1 = math.atan2(e[1] - c[1], e[0] - c[0])
    d = ((a0 - a1) if cw else (a1 - a0)) % (2 * math.pi)
    return d if d > 1e-12 else 2 * math.pi


def r_centre(s, e, r: float, cw: bool, a: int = 0, c: int = 1) -> np.ndarray:
    """The centre of the R circle from s to e (axes a, c of the program frame): of the two centres on
    the chord's bisector, the one whose arc turns through at most 180 degrees for R > 0, more for R < 0."""
    s2, e2 = np.array([s[a], s[c]]), np.array([e[a], e[c]])
    d = e2 - s2
    ch = float(np.hypot(*d))
    h = math.sqrt(max(r * r - ch * ch / 4, 0.0))
    n = np.array([-d[1], d[0]]) / ch
    for cand in ((s2 + e2) / 2 + h * n, (s2 + e2) / 2 - h * n):
        if (sweep(s2, e2, cand, cw) <= math.pi) == (r > 0):
            out = np.array(s, dtype=float)
            out[a], out[c] = cand
            return out
    raise AssertionError("no centre")  # pragma: no cover


class Sim:
    """Builds the program P block by block (from hypothesis draws) and the moves it must give."""

    def __init__(self, draw, offset=(0.0, 0.0, 0.0), plane: str = "G17"):
        self.draw = draw
        self.plane, self.axes = plane, PLANES[plane]
        self.centre_abs, self.g161 = False, ""
        self.g92_off = np.zeros(3)  # G92's offset  # G161 / G162, and the word switching it in this block
        self.frame = Frame(offset)
        self.pos = np.array(START)  # machine
        self.lines: list[str] = []
        self.expected: list[tuple] = []  # ("G0"|"G1", s, e) / ("A", s, e, centre, cw, full, r or None)
        self.absolute = True

    def here(self) -> np.ndarray:
        return self.frame.to_program(self.pos)

    def emit_line(self, text: str) -> None:
        self.lines.append(text)

    def mode(self, absolute: bool) -> str:
        word = "" if absolute == self.absolute else ("G90 " if absolute else "G91 ")
        self.absolute = absolute
        return word

    def move(self, g: int, end_prog, words: str, absolute: bool) -> None:
        end = self.frame.to_machine(end_prog)
        self.emit_line(f"{self.mode(absolute)}G0{g} {words}".rstrip())
        self.expected.append((f"G{g}", self.pos.copy(), end))
        self.pos = end

    def line(self, g: int = 1) -> None:
        """A straight move; axes may be left out (they stay where the tool is in the program frame)."""
        draw, p = self.draw, self.here()
        absolute = draw(hst.booleans())
        keep = [draw(hst.booleans()) for _ in range(2)] + [draw(hst.integers(0, 3)) > 0]
        if all(keep):
            keep[0] = False
        end, words = p.copy(), []
        for i, ax in enumerate("XYZ"):
            if keep[i]:
                continue
            lim = 8.0 if i == 2 else 60.0
            v = r3(draw(hst.floats(-lim, lim)))
            end[i] = v if absolute else p[i] + v
            words.append(f"{ax}{f3(v)}")
        self.move(g, end, " ".join(words), absolute)

    def arc(self, kind: str) -> None:
        """A circle in the plane (main axes a, c, normal n): "ij" (centre I/J/K relative to the start,
        or absolute under G161), "r" (R > 0), "rlong" (R < 0, the longer arc) or "full" (the end is the
        start); a quarter of them helical (the normal axis moves too)."""
        draw, p = self.draw, self.here()
        a, c, n = self.axes
        self.g161 = ""
        cw = draw(hst.booleans())
        rad = r3(draw(hst.floats(2.0, 30.0)))
        phi = draw(hst.floats(0.0, 2 * math.pi)) if draw(hst.integers(0, 3)) else math.pi / 2 * draw(hst.integers(0, 3))
        off = (r3(rad * math.cos(phi)), r3(rad * math.sin(phi)))  # centre - start in (a, c)
        turn = {"full": lambda: 0.0, "rlong": lambda: draw(hst.floats(200.0, 340.0)),
                "r": lambda: draw(hst.floats(20.0, 160.0)), "ij": lambda: draw(hst.floats(5.0, 355.0))}[kind]()
        ang = math.radians(-turn if cw else turn)
        co, si = math.cos(ang), math.sin(ang)
        step = (off[0] - co * off[0] + si * off[1], off[1] - si * off[0] - co * off[1])  # end - start
        absolute = draw(hst.booleans()) and kind != "full"
        end, words = p.copy(), {}
        if absolute:
            end[a], end[c] = r3(p[a] + step[0]), r3(p[c] + step[1])
            words = {a: end[a], c: end[c]}
        else:
            inc = (0.0, 0.0) if kind == "full" else (r3(step[0]), r3(step[1]))
            end[a], end[c] = p[a] + inc[0], p[c] + inc[1]
            words = {a: inc[0], c: inc[1]} if kind != "full" or draw(hst.booleans()) else {}
        if draw(hst.integers(0, 3)) == 0:  # a helix
            v = r3(draw(hst.floats(-5.0, 5.0)))
            end[n], words[n] = (v if absolute else p[n] + v), v
        r = None
        if kind in ("r", "rlong"):
            r = r3(math.hypot(*off) * (1 if kind == "r" else -1))
            centre, tail = r_centre(p, end, r, cw, a, c), f"R{f3(r)}"
        else:
            centre, tail = self.centre_words(p, off)
        xyz = " ".join(f"{'XYZ'[i]}{f3(v)}" for i, v in sorted(words.items()))
        self.emit_line(f"{self.mode(absolute)}{self.g161}G0{2 if cw else 3} {xyz} {tail}".replace("  ", " "))
        s, e = self.pos.copy(), self.frame.to_machine(end)
        mcw = cw != self.frame.mirrored(a, c)
        self.expected.append(("A", s, e, self.frame.to_machine(centre), mcw, kind == "full", r))
        self.pos = e

    def centre_words(self, p, off) -> tuple[np.ndarray, str]:
        """The centre (program frame) and its words: I/J/K relative to the start (G162, a zero one may
        be left out) or (G161) absolute coordinates of the program frame."""
        a, c, _ = self.axes
        absolute = self.draw(hst.integers(0, 3)) == 0
        self.g161 = "" if absolute == self.centre_abs else ("G161 " if absolute else "G162 ")
        self.centre_abs = absolute
        centre = p.copy()
        if absolute:
            centre[a], centre[c] = r3(p[a] + off[0]), r3(p[c] + off[1])
            vals = ((a, centre[a]), (c, centre[c]))
        else:
            centre[a], centre[c] = p[a] + off[0], p[c] + off[1]
            vals = tuple((i, v) for i, v in zip((a, c), off) if v != 0.0 or self.draw(hst.booleans()))
        return centre, " ".join(f"{'IJK'[i]}{f3(v)}" for i, v in vals)

    def blocks(self, n: int) -> None:
        for _ in range(n):
            kind = self.draw(hst.sampled_from(["line", "line", "ij", "r", "rlong", "full"]))
            self.line() if kind == "line" else self.arc(kind)

    # -- switching the frame -------------------------------------------------------------------------
    def rotation_on(self) -> None:
        """#ROTATION ON [ANGLE CENTER1 CENTER2] (with or without "=") or G68 R.. with the centre on the
        plane's axes; with no rotation active G68 may leave a centre axis out: the tool's position in
        the program frame."""
        draw, (a, c, _) = self.draw, self.axes
        deg, c1, c2 = (r3(draw(hst.floats(-360.0, 360.0))), r3(draw(hst.floats(-30.0, 30.0))),
                       r3(draw(hst.floats(-30.0, 30.0))))
        form = draw(hst.sampled_from(["rot", "rot-no-eq", "g68", "g68-partial"]))
        if form == "rot":
            self.emit_line(f"#ROTATION ON [ANGLE={f3(deg)} CENTER1={f3(c1)} CENTER2={f3(c2)}]")
        elif form == "rot-no-eq":
            self.emit_line(f"#ROTATION ON [ANGLE {f3(deg)} CENTER1 {f3(c1)} CENTER2 {f3(c2)}]")
        elif form == "g68" or self.frame.rot is not None:
            self.emit_line(f"G68 R{f3(deg)} {'XYZ'[a]}{f3(c1)} {'XYZ'[c]}{f3(c2)}")
        elif draw(hst.booleans()):
            self.emit_line(f"G68 R{f3(deg)} {'XYZ'[c]}{f3(c2)}")
            c1 = self.here()[a]
        else:
            self.emit_line(f"G68 R{f3(deg)} {'XYZ'[a]}{f3(c1)}")
            c2 = self.here()[c]
        self.frame.rot = (deg, c1, c2, a, c)

    def rotation_off(self) -> None:
        self.emit_line(self.draw(hst.sampled_from(["#ROTATION OFF", "G69"])))
        self.frame.rot = None

    def mirror(self) -> None:
        draw, mir = self.draw, self.frame.mir
        if draw(hst.booleans()):
            mx, my = draw(hst.booleans()), draw(hst.booleans())
            self.emit_line(f"G2{[[0, 2], [1, 3]][mx][my]}")
            mir[0], mir[1] = mx, my
            return
        axes = draw(hst.lists(hst.sampled_from([0, 1, 2]), min_size=1, max_size=3, unique=True))
        flags = [draw(hst.booleans()) for _ in axes]
        self.emit_line("G351 " + " ".join(f"{'XYZ'[i]}{'-1' if f else '1'}" for i, f in zip(axes, flags)))
        for i, f in zip(axes, flags):
            mir[i] = f

    def cs_on(self) -> None:
        draw = self.draw
        t = (r3(draw(hst.floats(-50.0, 50.0))), r3(draw(hst.floats(-50.0, 50.0))), r3(draw(hst.floats(-10.0, 10.0))),
             r3(draw(hst.floats(-180.0, 180.0))) if self.plane == "G17" else 180.0 * draw(hst.integers(-1, 2)))
        self.emit_line(f"#CS ON [{f3(t[0])}, {f3(t[1])}, {f3(t[2])}, 0, 0, {f3(t[3])}]")
        self.frame.cs.append(t)

    def cs_off(self) -> None:
        self.emit_line("#CS OFF")
        if self.frame.cs:
            self.frame.cs.pop()

    def g92(self) -> None:
        """G92 X.. Y.. Z.. (an additive zero offset in machine axis directions): set under G90, added
        under G91; the axes not given keep theirs."""
        axes = self.draw(hst.lists(hst.sampled_from([0, 1, 2]), min_size=1, max_size=3, unique=True))
        vals = [r3(self.draw(hst.floats(-20.0, 20.0))) for _ in axes]
        self.emit_line("G92 " + " ".join(f"{'XYZ'[i]}{f3(v)}" for i, v in zip(axes, vals)))
        for i, v in zip(axes, vals):
            self.frame.offset[i] += v - (self.g92_off[i] if self.absolute else 0.0)
            self.g92_off[i] = v if self.absolute else self.g92_off[i] + v

    def switch(self, ops) -> None:
        for op in ops:
            getattr(self, op)()

    def position(self) -> None:
        """The first move: an absolute rapid to a drawn point (all three axes)."""
        p = [r3(self.draw(hst.floats(-40.0, 40.0))) for _ in range(2)] + [r3(self.draw(hst.floats(-5.0, 5.0)))]
        self.emit_line(f"{self.mode(True)}G00 X{f3(p[0])} Y{f3(p[1])} Z{f3(p[2])}")
        self.expected.append(("G0", self.pos.copy(), self.frame.to_machine(p)))
        self.pos = self.expected[-1][2]

    def program(self, head: str = "") -> str:
        return f"%P\n{self.plane} F100 {head}\n".replace(" \n", "\n") + "\n".join(self.lines) + "\nM30\n"


def hand_program(expected, plane: str = "G17") -> str:
    """P': the expected moves in machine coordinates, no frame (G90, I/J/K relative, R circles by R)."""
    out = [f"%P\n{plane} G90 F100"]
    a, c, _ = PLANES[plane]
    for rec in expected:
        e = rec[2]
        xyz = f"X{e[0]:.12f} Y{e[1]:.12f} Z{e[2]:.12f}"
        if rec[0] in ("G0", "G1"):
            out.append(f"G0{rec[0][1]} {xyz} F100")
            continue
        _, s, e, cen, cw, full, r = rec
        tail = f"R{r:.12f}" if r is not None else f"{'IJK'[a]}{cen[a] - s[a]:.12f} {'IJK'[c]}{cen[c] - s[c]:.12f}"
        out.append(f"G0{2 if cw else 3} {xyz} {tail}")
    return "\n".join(out) + "\nM30\n"


def canonical(prog, plane: str = "G17") -> list[tuple]:
    out = []
    for m in prog.moves:
        if isinstance(m, canon.Arc):
            assert m.plane == PLANE_NAMES[plane]
            out.append(("A", m.start, m.end, m.center, m.clockwise, m.full_turn))
        else:
            out.append(("G0" if isinstance(m, canon.Rapid) else "G1", m.start, m.end))
    return out


def assert_moves(got: list, expected: list, text: str) -> None:
    assert len(got) == len(expected), text
    for k, (g, e) in enumerate(zip(got, expected)):
        assert g[0] == e[0], (k, g, e, text)
        for a, b in zip(g[1:4 if e[0] == "A" else 3], e[1:4 if e[0] == "A" else 3]):
            assert np.allclose(a, b, rtol=0, atol=TOL), (k, g, e, text)
        if e[0] == "A":
            assert (g[4], g[5]) == (e[4], e[5]), (k, g, e, text)


def check(sim: Sim, head: str = "") -> None:
    text = sim.program(head)
    assert_moves(canonical(run(text), sim.plane), sim.expected, text)
    hand = hand_program(sim.expected, sim.plane)
    assert_moves(canonical(run(hand), sim.plane), sim.expected, hand)


# -- 1: one frame switched on before the contour ------------------------------------------------------
FRAMES = {
    "rotation": ["rotation_on"],
    "cs": ["cs_on"],
    "cs2": ["cs_on", "cs_on"],
    "mirror": ["mirror"],
    "all": ["rotation_on", "mirror", "cs_on", "cs_on"],
}


@pytest.mark.parametrize("kind", list(FRAMES))
@settings(max_examples=40, **SETTINGS)
@given(data=hst.data())
def test_transformed_contour_is_the_hand_transformed_contour(kind, data):
    offsets = data.draw(hst.sampled_from(["", "G54", "G54 G92"]), "offsets")
    g92 = (r3(data.draw(hst.floats(-20, 20))), r3(data.draw(hst.floats(-20, 20))), 0.0)
    offset = np.zeros(3)
    head = ""
    if offsets:
        offset += np.array(G54)
        head = "G54"
    sim = Sim(data.draw, tuple(offset))
    if offsets == "G54 G92":
        sim.emit_line(f"G92 X{f3(g92[0])} Y{f3(g92[1])}")
        sim.frame.offset = sim.frame.offset + np.array(g92)
        sim.g92_off = np.array(g92)
    ops = FRAMES[kind]
    if kind == "all":  # the documented order holds whatever order the program switches them on in
        ops = data.draw(hst.permutations(ops), "order")
    sim.switch(ops)
    sim.position()
    sim.blocks(data.draw(hst.integers(1, 6), "blocks"))
    check(sim, head)


# -- 3: the frame switched in the middle of a contour (no compensation active) -------------------------
OPS = ["rotation_on", "rotation_off", "mirror", "cs_on", "cs_off", "g92"]


@pytest.mark.parametrize("plane", list(PLANES))
@settings(max_examples=60, **SETTINGS)
@given(data=hst.data())
def test_frame_switched_in_the_middle_of_a_contour(plane, data):
    """Rotation, mirroring and #CS switched on and off between the blocks of one contour: the tool
    starts each block where the last one left it; absolute words are program coordinates of the
    frame now active, incremental ones (G91, also right after #ROTATION OFF or G69) steps in it, and
    an axis left out stays where the tool is. In G18 and G19 the rotation turns the plane's axes (Z
    towards X, Y towards Z) and a #CS turns by a multiple of 180 degrees (else a circle would be tilted)."""
    sim = Sim(data.draw, plane=plane)
    sim.position()
    for _ in range(data.draw(hst.integers(2, 4), "segments")):
        sim.switch(data.draw(hst.lists(hst.sampled_from(OPS), min_size=1, max_size=2), "ops"))
        sim.blocks(data.draw(hst.integers(1, 3), "blocks"))
    check(sim)


def test_incremental_moves_after_the_rotation_is_switched_off():
    """#ROTATION ON [ANGLE=90]: X10 Y0 is machine (0, 10); G91 X5 turns too: (0, 15). After
    #ROTATION OFF, G91 X5 is a step along machine X: (5, 15); G69 after G68 likewise."""
    for on, off in (("#ROTATION ON [ANGLE=90]", "#ROTATION OFF"), ("G68 R90 X0 Y0", "G69")):
        prog = run(f"%P\nG17 F100\n{on}\nG01 X10 Y0\nG91 X5\n{off}\nX5\nY-3\nM30\n")
        ends = [tuple(round(v, 9) + 0.0 for v in m.end[:2]) for m in prog.moves]
        assert ends == [(0.0, 10.0), (0.0, 15.0), (5.0, 15.0), (5.0, 12.0)]


# -- 2: tool radius compensation on a convex polygon ---------------------------------------------------
def offset_corners(pts, r: float) -> list[np.ndarray]:
    """The corners of a counter-clockwise convex polygon's edges moved r to their left (inside):
    corner k is where the offset edges k-1 -> k and k -> k+1 meet."""
    out = []
    n = len(pts)
    for k in range(n):
        a, b, c = pts[k - 1], pts[k], pts[(k + 1) % n]
        u, v = (b - a) / np.linalg.norm(b - a), (c - b) / np.linalg.norm(c - b)
        nu, nv = np.array([-u[1], u[0]]), np.array([-v[1], v[0]])
        # b + r nu + s u = b + r nv + w v
        s, _ = np.linalg.solve(np.column_stack([u, -v]), r * (nv - nu))
        out.append(b + r * nu + s * u)
    return out


@settings(max_examples=80, **SETTINGS)
@given(data=hst.data())
def test_compensated_polygon_under_a_frame_is_the_hand_transformed_one(data):
    """A convex polygon run counter-clockwise with G41 (tool inside) or G42 (outside), approached
    and left radially from outside, under a drawn rotation / mirroring / #CS: the moves are those of
    the hand-transformed polygon with the side swapped exactly when the plane is mirrored (manual:
    under mirroring G41 computes the path right of the mirrored contour), kept under rotation. With
    G41 the inside corners (but the first, where the approach and the departure are) are the
    offset edges' intersections, mapped. Some edges may be arcs bulging outwards (G03 R, the shorter
    arc): then P and the hand program are compared alone."""
    draw = data.draw
    weights = draw(hst.lists(hst.floats(1.0, 2.0), min_size=3, max_size=6), "gaps")
    gaps = [2 * math.pi * w / sum(weights) for w in weights]
    first = draw(hst.floats(0.0, 2 * math.pi), "first")
    angles = [first + sum(gaps[:k]) for k in range(len(gaps))]
    r = r3(draw(hst.floats(0.5, 2.0), "r"))
    pts = [np.array([r3(30 * math.cos(a)), r3(30 * math.sin(a))]) for a in angles]
    edges = [np.linalg.norm(pts[(k + 1) % len(pts)] - pts[k]) for k in range(len(pts))]
    assume(max(gaps) < math.pi - 0.1 and min(edges) > 8 * r)
    side = draw(hst.sampled_from([41, 42]), "side")
    sim = Sim(draw)
    sim.switch(draw(hst.lists(hst.sampled_from(["rotation_on", "mirror", "cs_on"]), min_size=1, max_size=3), "ops"))
    L, t = sim.frame.affine()
    approach = np.array([r3(v) for v in pts[0] * 1.5])
    body = [f"G00 X{f3(approach[0])} Y{f3(approach[1])} Z-1", f"G{side} G01 X{f3(pts[0][0])} Y{f3(pts[0][1])}"]
    bulge = [r3(e * draw(hst.floats(0.6, 2.0))) if draw(hst.integers(0, 2)) == 0 else None for e in edges]
    body += [f"G0{1 if b is None else 3} X{f3(p[0])} Y{f3(p[1])}{'' if b is None else f' R{f3(b)}'}"
             for p, b in zip(pts[1:] + [pts[0]], bulge)] + [f"G40 G01 X{f3(approach[0])} Y{f3(approach[1])}"]
    prog = run("%P\nG17 F100\n" + "\n".join(sim.lines + body) + "\nM30\n", radius=r)

    def m(p, z=-1.0):
        q = L @ np.array([p[0], p[1], z]) + t
        return f"X{q[0]:.12f} Y{q[1]:.12f} Z{q[2]:.12f}"
    hand_side = side if not sim.frame.mirrored() else 83 - side
    hand = [f"G00 {m(approach)}", f"G{hand_side} G01 {m(pts[0])}"]
    hand += [f"G01 {m(p)}" if b is None else f"G0{2 if sim.frame.mirrored() else 3} {m(p)} R{f3(b)}"
             for p, b in zip(pts[1:] + [pts[0]], bulge)]
    hand_prog = run("%P\nG17 F100\n" + "\n".join(hand + [f"G40 G01 {m(approach)}"]) + "\nM30\n", radius=r)
    got, want = canonical(prog), canonical(hand_prog)
    assert_moves(got, want, str(prog))
    if side == 41 and bulge == [None] * len(pts):
        ends = [np.array(g[2]) for g in got]
        for c in offset_corners(pts, r)[1:]:
            q = L @ np.array([c[0], c[1], -1.0]) + t
            assert min(np.linalg.norm(e - q) for e in ends) < TOL, (c, q)


def test_modal_radius_under_mirroring_keeps_the_shorter_arc():
    """R is modal: G02 X10 Y0 R10 from (0, 0) runs clockwise over the top about (5, -sqrt(75)); the next
    G03 X20 Y0 (R10 still) counter-clockwise below, about (15, sqrt(75)). Under G21 (x -> -x) both
    centres mirror, (-5, -sqrt(75)) and (-15, sqrt(75)), and the directions reverse."""
    prog = run("%P\nG17 F100\nG21\nG01 X0 Y0\nG02 X10 Y0 R10\nG03 X20 Y0\nM30\n")
    arcs = [m for m in prog.moves if isinstance(m, canon.Arc)]
    h = math.sqrt(75.0)
    assert [(a.end[:2], a.clockwise) for a in arcs] == [((-10.0, 0.0), False), ((-20.0, 0.0), True)]
    assert np.allclose([a.center[:2] for a in arcs], [(-5.0, -h), (-15.0, h)], rtol=0, atol=TOL)
