"""Random RS274NGC programs for the differential run against LinuxCNC's rs274.

``program(rng)`` writes one program: motions in the three planes (arcs by centre and radius, full
circles, helices with P turns, G90.1 centres from ``#<_x>``; polar @ ^ in G17), units and distance modes, work
offsets (G10 L1/L2/L10/L11/L20, G54-G59.3, G92 and its resets, G52), G28/G30, G53, tool changes with tool length
offsets, canned cycles with G98/G99 and L (G84/G74 in G17, G74 without L; G87 from its own draws), G96, G33/G33.1, G76
and the lathe cycles G70-G71.2 on a profile (``lathe_cycle``, one program in five; its G70 under cutter radius
compensation in three of ten, ``comp_g70``) M70-M73 (M73 in the subroutine) (G76 never with G7 in
its block, docs/dialects/rs274ngc.md), inverse-time and per-revolution feeds,
parameters and expressions with every operator and function, O-word subroutines and loops, and
a numbered subprogram (O<n> ... M99 after the program's end) called by M98 P<n> [L<k>].
Between the statements, from their own draws (``Comp``), cutter radius compensation sequences, and
(``issue25``) straight probing G38.2-G38.5, the planes G17.1-G19.1 and M19.
Arcs are built to end on their circle (to 4 decimals); everything else is left to chance, so
both interpreters may refuse a program (division by zero, a peck depth of 0 ...): then both must.
"""
from __future__ import annotations

import math
import random

TOOL_TABLE = "".join(f"T{t} P{t} Z{z} X{x} D{d}\n" for t, z, x, d in
                     ((1, 12.5, 0, 6), (2, 30.25, 1.5, 10), (3, -4.75, 0, 3), (4, 0, 0, 8)))
FUNCS = ("abs", "acos", "asin", "cos", "exp", "fix", "fup", "ln", "round", "sin", "sqrt", "tan")
OPS = ("+", "-", "*", "/", "mod", "**", "eq", "ne", "gt", "ge", "lt", "le", "and", "or", "xor")
# Tool length offsets are changed in G21 only (the "G21 " before them): in G20 rs274's position after
# a change differs from cutsim's by amounts not yet explained (docs/dialects/rs274ngc.md).
CYCLE_CODES = ("G81", "G82", "G83", "G73", "G85", "G89", "G86", "G84", "G74")
# rs274 2.9 feeds G84/G74 along permuted axes in G18 (docs/dialects/rs274ngc.md): they tap in G17 only.
# No G88: after it rs274 goes on from the clear level without printing a move, which the comparison
# (following printed moves) cannot see (docs/dialects/rs274ngc.md)
PLANE_LETTERS = {"G17": ("X", "Y", "Z", "I", "J"), "G18": ("Z", "X", "Y", "K", "I"), "G19": ("Y", "Z", "X", "J", "K")}


def num(rng: random.Random, lo: float, hi: float, digits: int = 3) -> str:
    return f"{rng.uniform(lo, hi):.{digits}f}"


def expr(rng: random.Random, depth: int = 0) -> str:
    """A random expression: numbers, parameters #1-#5, functions and binary operators."""
    r = rng.random()
    if depth > 2 or r < 0.3:
        return rng.choice([num(rng, -9, 9, 2), f"#{rng.randint(1, 5)}", str(rng.randint(0, 4))])
    if r < 0.45:
        f = rng.choice(FUNCS)
        inner = expr(rng, depth + 1)
        if rng.random() < 0.9:  # mostly inside the function's domain
            inner = {"acos": f"[{inner}] mod 2 - 1", "asin": f"[{inner}] mod 2 - 1", "ln": f"abs[{inner}] + 0.5",
                     "sqrt": f"abs[{inner}]", "exp": f"[{inner}] mod 5"}.get(f, inner)
        return f"{f}[{inner}]"
    if r < 0.5:
        return f"atan[{expr(rng, depth + 1)}]/[{expr(rng, depth + 1)}]"
    op = rng.choice(OPS)
    right = expr(rng, depth + 1)
    if op in ("/", "mod") and rng.random() < 0.9:
        right = f"[abs[{right}] + 0.25]"
    if op == "**" and rng.random() < 0.9:
        return f"[abs[{expr(rng, depth + 1)}] ** {rng.randint(0, 3)}]"
    return f"[{expr(rng, depth + 1)} {op} {right}]"


class Gen:
    def __init__(self, rng: random.Random, lathe: bool = False):
        self.rng = rng
        self.out: list[str] = []
        self.plane = "G17"
        self.lathe = lathe
        self.labels = 100
        self.no_do = False
        self.loaded = False  # a T M6 ran: rs274 loads tool 1 on G10 L1 P1 into an empty spindle (rs274.py)
        self.in_do = 0  # open do loops: a while in one holds no break (rs274 would run the do once)
        self.saved = False  # an M70 ran (M72 and M71 may follow)
        self.no_context = False  # an M98 L0 was written: no M70-M72 after it

    def emit(self, s: str) -> None:
        self.out.append(s)

    def axes(self, letters: str = "XYZ", span: float = 30.0) -> str:
        rng = self.rng
        chosen = [a for a in letters if rng.random() < 0.6] or [rng.choice(letters)]
        parts = []
        for a in chosen:
            if rng.random() < 0.15:
                parts.append(f"{a}[#{rng.randint(1, 5)} mod 20]")
            else:
                parts.append(f"{a}{num(rng, -span, span)}")
        return " ".join(parts)

    def move(self) -> None:
        rng = self.rng
        g = rng.choice(["G0", "G1", "G1"])
        dist = rng.choice(["", "", "G90 ", "G91 "])
        if rng.random() < 0.15:  # polar @ ^ (G17 before the block, G8: X words are no diameters)
            self.plane = "G17"
            self.emit("G17 G8")
            words = rng.choice([f"@{num(rng, -20, 20)} ^{num(rng, -360, 360)}", f"@{num(rng, -10, 10)}",
                                f"^{num(rng, -180, 180)}", f"^{num(rng, -90, 90)} Z{num(rng, -10, 10)}"])
            if rng.random() < 0.5:  # mostly G90 with both words: at the XY origin G91 (and G90 without ^) fail
                dist, words = "G90 ", f"@{num(rng, -20, 20)} ^{num(rng, -360, 360)}"
            self.emit(f"{dist}{g} {words}" + (f" F{num(rng, 10, 900, 1)}" if rng.random() < 0.2 else ""))
            return
        self.emit(f"{dist}{g} {self.axes()}" + (f" F{num(rng, 10, 900, 1)}" if rng.random() < 0.2 else ""))

    def arc(self) -> None:
        rng = self.rng
        a, b, n, ia, ib = PLANE_LETTERS[self.plane]
        r = rng.uniform(1, 25)
        phi = rng.uniform(0, 2 * math.pi)
        ci, cj = r * math.cos(phi), r * math.sin(phi)  # centre from the start
        g = rng.choice(["G2", "G3"])
        full = rng.random() < 0.15
        theta = 0.0 if full else math.radians(rng.choice([rng.uniform(15, 160), rng.uniform(200, 345)]))
        sign = -1.0 if g == "G2" else 1.0
        ang = phi + math.pi + sign * theta
        ex, ey = ci + r * math.cos(ang), cj + r * math.sin(ang)
        helix = f" {n}{num(rng, -5, 5)}" if rng.random() < 0.3 else ""
        turns = f" P{rng.randint(2, 3)}" if (helix or full) and rng.random() < 0.4 else ""
        if full:
            ex = ey = 0.0
        if not full and rng.random() < 0.35:
            big = theta > math.pi
            self.emit(f"G91 {g} {a}{ex:.4f} {b}{ey:.4f} R{'-' if big else ''}{r:.4f}{helix}")
        elif rng.random() < 0.25:
            self.emit(f"G90.1 G91 {g} {a}{ex:.4f} {b}{ey:.4f} {ia}[#<_{a.lower()}>+{ci:.4f}] "
                      f"{ib}[#<_{b.lower()}>+{cj:.4f}]{helix}{turns}")
            self.emit("G91.1")
        else:
            self.emit(f"G91 {g} {a}{ex:.4f} {b}{ey:.4f} {ia}{ci:.4f} {ib}{cj:.4f}{helix}{turns}")

    def cycle(self) -> None:
        rng = self.rng
        a, b, n, _, _ = PLANE_LETTERS[self.plane]
        code = rng.choice(CYCLE_CODES)
        if code in ("G84", "G74"):
            self.plane = "G17"
            a, b, n, _, _ = PLANE_LETTERS["G17"]
            self.emit(f"G17 S{rng.randint(100, 2000)} M{4 if code == 'G74' else 3}")
        retract = rng.choice(["G98", "G99", ""])
        extra = ""
        if code in ("G83", "G73"):
            extra += f" Q{num(rng, 0.5, 4, 2)}"
        if code in ("G82", "G89", "G86", "G84", "G74"):
            extra += f" P{num(rng, 0, 1, 1)}"
        if rng.random() < 0.3 and code != "G74":  # rs274 2.9 takes no L with G74
            extra += f" L{rng.randint(1, 3)}"
        if rng.random() < 0.5:
            top = rng.uniform(-5, 10)
            self.emit(f"G90 {retract} {code} {a}{num(rng, -20, 20)} {b}{num(rng, -20, 20)} "
                      f"R{top:.3f} {n}{top - rng.uniform(1, 12):.3f}{extra}")
            for _ in range(rng.randint(0, 2)):
                self.emit(f"{rng.choice(['', 'G98 ', 'G99 '])}{a}{num(rng, -20, 20)}"
                          + (f" R{num(rng, -3, 12)}" if rng.random() < 0.3 else ""))
        elif self.plane == "G17" and rng.random() < 0.2:  # a bolt circle by ^ (the generator writes G8 before)
            self.emit("G8")
            self.emit(f"G91 {retract} {code} ^{num(rng, -120, 120)} R{num(rng, -4, 8)} {n}{-rng.uniform(1, 12):.3f}{extra}")
        else:
            self.emit(f"G91 {retract} {code} {a}{num(rng, -10, 10)} {b}{num(rng, -10, 10)} "
                      f"R{num(rng, -4, 8)} {n}{-rng.uniform(1, 12):.3f}{extra}")
            if rng.random() < 0.5:
                self.emit(f"{a}{num(rng, -10, 10)}")
        self.emit(rng.choice(["G80", "G80", "G0 " + self.axes(span=5), "G90 G80"]))

    def offsets(self) -> None:
        rng = self.rng
        choice = rng.randrange(10)
        if choice == 9:
            self.emit(f"{rng.choice(['', 'G90 ', 'G91 '])}G52 {self.axes(span=10)}")
        elif choice == 0:
            self.emit(f"G10 L2 P{rng.randint(0, 9)} {self.axes(span=40)}")
        elif choice == 1:
            self.emit(rng.choice(["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"]))
        elif choice == 2:
            self.emit(f"G92 {self.axes(span=20)}")
        elif choice == 3:
            self.emit(rng.choice(["G92.1", "G92.2", "G92.3"]))
        elif choice == 4:
            self.emit(f"G10 L20 P{rng.randint(0, 9)} {self.axes(span=20)}")
        elif choice == 5:
            # G21 first: rs274 subtracts a tool length offset in mm from inch coordinates in G28/G30 (rs274.py)
            self.emit("G21 " + rng.choice(["G28.1", "G30.1", "G28", "G30", f"G28 {self.axes(span=10)}",
                                           f"G30 G91 {self.axes(span=5)}"]))
        elif choice == 6:
            # G21 first: rs274 keeps a tool length offset taken in mm when G20 follows (rs274.py)
            self.emit(f"G21 G90 G53 {rng.choice(['G0', 'G1'])} {self.axes(span=50)}")
        elif choice == 7:
            self.emit(f"T{rng.randint(1, 4)} M6")
            self.loaded = True  # G43 in the M6 block: see rs274.py (rs274's stale position)
            self.emit("G21 " + rng.choice(["", "G43", "G43 H2", "G49"]))  # G21: see above CYCLE_CODES
            self.emit("G91 G0 X0 Y0 Z0")  # see rs274.py: an M6 after an offset change reads a stale position
        else:
            self.emit("G21 " + rng.choice(["G43", f"G43 H{rng.randint(1, 4)}", f"G43.1 Z{num(rng, -3, 3)}", "G49",
                                  f"G43.2 H{rng.randint(1, 4)}", f"G10 L1 P{rng.randint(1, 4)} Z{num(rng, -5, 40)}",
                                  f"G10 L{rng.choice([10, 11])} P{rng.randint(1, 4)} Z{num(rng, -20, 20)}"]))
            if not self.loaded and self.out[-1].startswith(("G21 G10 L1 P1 ", "G21 G10 L10 P1 ", "G21 G10 L11 P1 ")):
                self.out[-1] = self.out[-1].replace(" P1 ", " P2 ")
            self.emit("G91 G0 X0 Y0 Z0")

    def modes(self) -> None:
        rng = self.rng
        choice = rng.randrange(8)
        if choice == 7 and self.no_context:
            self.emit("G21")  # after M98 L0 rs274's M72 finds no state (docs/dialects/rs274ngc.md)
        elif choice == 7:  # M70-M72 at the top level, in G21: M72 may change the tool length offset (see G21 above)
            self.emit("G21")
            self.emit("M72" if self.saved and rng.random() < 0.7 else "M71" if self.saved else "M70")
            self.saved = self.out[-1] != "M71"
            # an M72 that restores G43/G49 leaves rs274's program position stale (as after M6, rs274.py):
            # an absolute move to all three axes ends where cutsim's does
            self.emit(f"G90 G0 X{num(rng, -20, 20)} Y{num(rng, -20, 20)} Z{num(rng, 0, 30)}" if self.out[-1] == "M72"
                      else "G91 G0 X0 Y0 Z0")
            self.plane = "G17" if self.out[-2] == "M72" else self.plane  # unknown: set it again below
            if self.out[-2] == "M72":
                self.emit("G17")
        elif choice == 0:
            self.plane = rng.choice(["G17", "G18", "G19"])
            self.emit(self.plane)
        elif choice == 1:
            self.emit(rng.choice(["G20", "G21"]))
        elif choice == 2:
            self.emit(f"G95 F{num(rng, 0.05, 0.5, 3)}" if rng.random() < 0.5 else f"G94 F{num(rng, 20, 800, 1)}")
        elif choice == 3:
            self.emit(f"G93 G1 {self.axes()} F{num(rng, 0.5, 20, 2)}")
            self.emit(f"G94 F{num(rng, 20, 800, 1)}")
        elif choice == 4:
            self.emit(f"G4 P{num(rng, 0, 2, 2)}")
        elif choice == 5:
            self.emit(f"S{rng.randint(100, 3000)} M{rng.choice([3, 4])}")
            if rng.random() < 0.2:
                self.emit(f"G96 S{rng.randint(50, 300)}" + (f" D{rng.randint(500, 4000)}" if rng.random() < 0.5 else ""))
            r = rng.random()
            if r < 0.4:
                self.emit(f"G33 {self.axes('XZ', 10)} K{num(rng, 0.5, 3, 2)}")
            elif r < 0.6:
                self.emit(f"G33.1 Z{num(rng, -20, 0)} K{num(rng, 0.5, 2, 2)}")
            else:
                self.threading()
            self.emit("G97 G1 F300")
        else:
            self.emit(rng.choice(["G7", "G8", "G61", "G64", "G64 P0.01", "M7", "M8", "M9", "M5", "M0", "M1"]))

    def threading(self) -> None:
        """A G76 block: the pitch, end, crest, depths and the optional words in their ranges (J at
        least a tenth of K and R at most 1.5, so at most 31 passes)."""
        rng = self.rng
        k = rng.uniform(0.2, 1.6)
        words = [f"P{num(rng, 0.5, 3)}", f"Z{num(rng, -25, 25)}", f"I{rng.choice(['', '-'])}{num(rng, 0.2, 2)}",
                 f"J{k * rng.uniform(0.1, 0.6):.4f}", f"K{k:.4f}"]
        if rng.random() < 0.3:
            words.append(f"X{num(rng, -10, 10)}")
        for letter, value in (("R", num(rng, 1, 1.5, 2)), ("Q", num(rng, -5, 30, 1)), ("H", str(rng.randint(0, 2))),
                              ("E", num(rng, 0, 3, 2)), ("L", str(rng.randint(0, 3)))):
            if rng.random() < 0.5:
                words.append(f"{letter}{value}")
        rng.shuffle(words)
        mode = rng.choice(["", "G18 ", "G91 ", "G90 "])
        if mode == "G18 ":
            self.plane = "G18"
        self.emit(mode + "G76 " + " ".join(words))

    def params(self) -> None:
        self.emit(f"#{self.rng.randint(1, 5)} = {expr(self.rng)}")

    def statement(self, depth: int = 0) -> None:
        rng = self.rng
        r = rng.random()
        if r < 0.25:
            self.move()
        elif r < 0.4:
            self.arc()
        elif r < 0.5:
            self.cycle()
        elif r < 0.62:
            self.offsets()
        elif r < 0.74:
            self.modes()
        elif r < 0.86:
            self.params()
        elif depth < 2:
            self.control(depth)

    def control(self, depth: int) -> None:
        rng = self.rng
        self.labels += 2
        label = self.labels
        kind = rng.randrange(3 if self.no_do else 4)
        if kind == 0:
            self.emit(f"o{label} repeat [{rng.randint(0, 3)}]")
            for _ in range(rng.randint(1, 3)):
                self.statement(depth + 1)
            self.emit(f"o{label} endrepeat")
        elif kind == 1:
            self.no_do = True  # rs274 runs a do loop after a while loop holding an if once (rs274.py)
            self.emit(f"#<n{depth}> = 0")
            self.emit(f"o{label} while [#<n{depth}> lt {rng.randint(1, 3)}]")
            for _ in range(rng.randint(1, 3)):
                self.statement(depth + 1)
            self.emit(f"#<n{depth}> = [#<n{depth}> + 1]")
            if rng.random() < 0.3 and not self.in_do:
                self.emit(f"o{label + 1000} if [#<n{depth}> gt 1]")
                self.emit(f"o{label} break")
                self.emit(f"o{label + 1000} endif")
            self.emit(f"o{label} endwhile")
        elif kind == 2:
            self.emit(f"o{label} if [{expr(rng)} gt 0]")
            self.statement(depth + 1)
            if rng.random() < 0.5:
                self.emit(f"o{label} elseif [{expr(rng)} lt 0]")
                self.statement(depth + 1)
            if rng.random() < 0.5:
                self.emit(f"o{label} else")
                self.statement(depth + 1)
            self.emit(f"o{label} endif")
        else:
            self.emit(f"o{label} do")
            self.emit(f"#<_d{depth}> = [#<_d{depth}> + 1]")
            self.in_do += 1
            self.statement(depth + 1)
            self.in_do -= 1
            self.emit(f"o{label} while [#<_d{depth}> lt 2]")


def lathe_cycle(rng: random.Random, g70_comp: float = 0.3) -> tuple[list[str], list[str]]:
    """A profile o9001 of Z runs and X steps (straight, tapered, convex and concave quarter arcs; fillets
    A and chamfers C between straight moves; at times a pocket), outside or (mirrored in X) a bore, and the lines of a G70-G71.2 block on it with G7 at times,
    its own modes set first (G18 G21 G90 G94 G8, then F). A G70 runs under cutter radius compensation
    in a share ``g70_comp`` of them (``comp_g70``, from its own draws: the rest unchanged)."""
    finishes = random.Random(str(rng.getstate()[1]) + "AC")  # A and C from their own draws: the rest unchanged
    comp = random.Random(str(rng.getstate()[1]) + "G70 comp")
    bore = rng.random() < 0.3

    def r4(lo: float, hi: float) -> float:  # 4 decimals, so an arc's printed end lies on its circle
        return round(rng.uniform(lo, hi), 4)

    x, z = r4(2, 6), 0.0
    pts = [(x, z, "G1", "")]
    for _ in range(rng.randint(2, 4)):
        z = round(z - r4(1.5, 8), 4)
        pts.append((x, z, "G1", ""))
        h, kind = r4(1, 4), rng.randrange(4)
        if kind == 0:
            x = round(x + h, 4)
            pts.append((x, z, "G1", ""))
        elif kind == 1:
            x, z = round(x + h, 4), round(z - r4(0.5, 3), 4)
            pts.append((x, z, "G1", ""))
        elif kind == 2:
            x, z = round(x + h, 4), round(z - h, 4)
            pts.append((x, z, "G3", f" K{-h:.4f}"))
        else:
            x, z = round(x + h, 4), round(z - h, 4)
            pts.append((x, z, "G2", f" I{h:.4f}"))
    z = round(z - r4(1, 5), 4)
    pts.append((x, z, "G1", ""))
    top = round(x + r4(0.5, 3), 4)
    pts = pocket(pts, random.Random(str(rng.getstate()[1]) + "pocket"))

    def xw(v: float) -> float:
        return 30 - v if bore else v

    lines = ["o9001 sub"]
    diameter = rng.random() < 0.3 and all(code == "G1" for _, _, code, _ in pts)
    scale = 2.0 if diameter else 1.0  # G7: every X word a diameter (the profile's too)
    for k, (px, pz, code, centre) in enumerate(pts):
        if bore and code != "G1":
            code, centre = ("G2" if code == "G3" else "G3"), (centre.replace("I", "I-") if "I" in centre else centre)
        # a fillet or chamfer (0.1-0.4: room on sides of 1 mm and more) between two straight moves
        finish = ""
        if 0 < k < len(pts) - 1 and code == "G1" and pts[k + 1][2] == "G1" and finishes.random() < 0.3:
            finish = f" {finishes.choice('AC')}{finishes.uniform(0.1, 0.4):.3f}"
            # not at a slight turn, where rs274 2.9 refuses some as "Not monotonic" (docs/dialects/rs274ngc.md)
            finish = finish if _turn(pts[k - 1], pts[k], pts[k + 1]) >= 0.15 else ""
        lines.append(f"{code} X{xw(px) * scale:.4f} Z{pz:.4f}{centre}{finish}")
    lines.append("o9001 endsub")
    sub, lines = lines, ["G18 G21 G90 G94 G8 G40 G80", "F" + num(rng, 50, 500, 1)]  # F after G21 (rs274: F first)
    lines.append(("G7 " if diameter else "") + f"G0 X{xw(top) * scale:.4f} Z{rng.uniform(-0.5, 3):.4f}")
    code = rng.choice(["G71", "G71.1", "G71.2", "G70"])
    # D and E clear of 0.01: at d sin(turn) = 0.01 rs274's rounding decides a corner's arc (docs)
    words = ["Q9001", f"D{num(rng, 0.02, 0.5)}" if rng.random() < 0.8 else "D0"]
    if code == "G70":
        words += [f"E{num(rng, 0.02, 0.1)}" if rng.random() < 0.7 else "E0", f"P{rng.randint(1, 3)}"]
    else:
        words += [f"I{num(rng, 0.5, 2.5)}", f"R{num(rng, 0.1, 1)}"]
    if any(" A" in line or " C" in line for line in sub):  # no D or E with A or C: rs274 offsets those
        words = [w if w[0] not in "DE" else w[0] + "0" for w in words]  # in steps (docs/dialects/rs274ngc.md)
    with_comp = comp.random() < g70_comp
    if code == "G70" and with_comp:  # a start apart from where the tool stands: the entry goes there;
        # half of them level with the profile's end and its start (as LinuxCNC's sample lathe_g70_71_demo)
        sx, sz = (x, 0.0) if comp.random() < 0.5 else (top + comp.uniform(0.3, 3), comp.uniform(0.5, 4))
        comp_g70(lines, comp, bore, f"G70 {' '.join(words)} X{xw(sx) * scale:.4f} Z{sz:.4f}")
    else:
        lines.append(f"{code} " + " ".join(words))
    if code != "G70" and (rng.random() < 0.5 or with_comp):  # (drawn either way: the rest unchanged)
        g70 = f"G70 Q9001 X{xw(top) * scale:.4f} Z1"
        comp_g70(lines, comp, bore, g70) if with_comp else lines.append(g70)
    lines.append("G8 G0 X40 Z40")
    return sub, lines


def comp_g70(lines: list, rng: random.Random, bore: bool, g70: str) -> None:
    """A G70 block under cutter radius compensation (rs274 2.9 runs it; G71/G72 it refuses): G41.1/G42.1
    with a diameter of 0-0.8 and at times an orientation L, or G41/G42 with a tool's D; outside mostly G42
    (G41 gouges at the first corner there), in a bore either; at times after a compensated rapid; then G40."""
    side = rng.choice(["G41", "G42"]) if bore else ("G42" if rng.random() < 0.8 else "G41")
    if rng.random() < 0.85:
        word = f"{side}.1 D{num(rng, 0, 0.8, 2)}" + (f" L{rng.randint(0, 9)}" if rng.random() < 0.6 else "")
    else:
        word = f"{side} D{rng.randint(1, 4)}"
    lines.append(word)
    if rng.random() < 0.3:  # compensation on before the cycle: its move to the start is no entry
        lines.append(f"G0 X{num(rng, 45, 60, 3) if not bore else num(rng, 2, 10, 3)} Z{num(rng, 5, 15, 3)}")
    lines.append(g70)
    lines.append("G40")


def _turn(a, b, c) -> float:
    """The angle (radians, 0 to pi) the profile turns at b on its way a -> b -> c (points (x, z, ...))."""
    t = math.atan2(c[0] - b[0], c[1] - b[1]) - math.atan2(b[0] - a[0], b[1] - a[1])
    return abs(math.remainder(t, 2 * math.pi))


def pocket(pts: list, rng: random.Random) -> list:
    """At times (from its own generator: the rest of the profile unchanged) a V pocket in a run along Z
    of 2 mm or more: down 0.3-1.5 (never below X 0.5) to a point 30-70 % along it and back up."""
    runs = [k for k in range(1, len(pts)) if pts[k][0] == pts[k - 1][0] and pts[k - 1][1] - pts[k][1] >= 2
            and pts[k][2] == "G1" and pts[k][0] > 1]
    if not runs or rng.random() < 0.6:
        return pts
    k = rng.choice(runs)
    (x, z0), z1 = pts[k - 1][:2], pts[k][1]
    depth = round(rng.uniform(0.3, min(1.5, x - 0.5)), 4)
    zm = round(z0 + (z1 - z0) * rng.uniform(0.3, 0.7), 4)
    return pts[:k] + [(round(x - depth, 4), zm, "G1", "")] + pts[k:]


def back_bore(g: Gen, rng: random.Random) -> None:
    """A G87 series in the current plane (the spindle started first): the offset I J K of the plane's
    axes, the top by the hole axis's letter (absolute in G90, from the bottom in G91), G98/G99, L."""
    a, b, n, _, _ = PLANE_LETTERS[g.plane]
    ijk = {"X": "I", "Y": "J", "Z": "K"}
    g.emit(f"S{rng.randint(100, 2000)} M{rng.choice([3, 4])}")
    retract = rng.choice(["G98", "G99", ""])
    repeat = f" L{rng.randint(1, 3)}" if rng.random() < 0.3 else ""
    off = f"{ijk[a]}{num(rng, -3, 3)} {ijk[b]}{num(rng, -3, 3)}"
    if rng.random() < 0.5:
        top = rng.uniform(-5, 10)
        bottom = top - rng.uniform(2, 12)
        g.emit(f"G90 {retract} G87 {a}{num(rng, -20, 20)} {b}{num(rng, -20, 20)} R{top:.3f} {n}{bottom:.3f} "
               f"{off} {ijk[n]}{bottom + rng.uniform(0.5, 2):.3f}{repeat}")
        if rng.random() < 0.5:
            g.emit(f"{rng.choice(['', 'G98 ', 'G99 '])}{a}{num(rng, -20, 20)}"
                   + (f" {ijk[a]}{num(rng, -3, 3)}" if rng.random() < 0.3 else ""))
    else:
        g.emit(f"G91 {retract} G87 {a}{num(rng, -10, 10)} {b}{num(rng, -10, 10)} R{num(rng, -4, 8)} "
               f"{n}{-rng.uniform(2, 12):.3f} {off} {ijk[n]}{num(rng, 0.5, 2)}{repeat}")
    g.emit(rng.choice(["G80", "G90 G80", f"G0 {n}{num(rng, -5, 5)}"]))


class Comp:
    """Cutter radius compensation sequences (G41/G42 with a tool's D, G41.1/G42.1 with a diameter and, in
    G18, an orientation L): a contour of lines, rapids, arcs (by centre and radius, full circles,
    helices) and moves along the plane's normal, each element starting at a chosen turn from the last
    one's direction (0, or 0.1 to 2.4 rad either way: clear of rs274's 0.05 rad corner threshold and of
    reversals), then G40 and a straight departure. Drawn from their own generator, seeded from the
    program's without drawing from it, so the rest of a program is what it was without them. Kept out:
    G33/G93/canned cycles and position reads under compensation (docs/dialects/rs274ngc.md)."""

    def __init__(self, rng: random.Random):
        self.rng = rng
        self.heading = 0.0

    def sequence(self, g: Gen) -> None:
        rng = self.rng
        plane = rng.choice(["G17", "G17", "G18"])
        g.plane = plane
        a, b, n, ia, ib = PLANE_LETTERS[plane]
        g.emit(f"{plane} G8 G90 G94 F{num(rng, 50, 900, 1)}")
        side = rng.choice(["G41", "G42"])
        r = rng.random()
        if r < 0.5:
            word = f"{side} D{rng.randint(1, 4)}"
        elif r < 0.6:
            word = side  # the loaded tool's diameter (T0: none)
        else:
            word = f"{side}.1 D{num(rng, -0.5, 10, 2)}"
            if plane == "G18" and rng.random() < 0.7:
                word += f" L{rng.randint(0, 9)}"
        self.heading = rng.uniform(-math.pi, math.pi)
        entry = self.line(a, b, rng.uniform(12, 30), rng.choice(["G0", "G1"]))
        if rng.random() < 0.3:
            g.emit(f"{word} {entry}")
        else:
            g.emit(word)
            g.emit(entry)
        for _ in range(rng.randint(2, 6)):
            self.element(g, a, b, n, ia, ib)
        if rng.random() < 0.5:
            g.emit("G40")
            g.emit(f"G91 {rng.choice(['G0', 'G1'])} " + (f"{n}{num(rng, 1, 5)}" if rng.random() < 0.2 else
                                                          f"{a}{num(rng, -20, 20)} {b}{num(rng, -20, 20)}"))
        else:
            g.emit(f"G40 G91 G0 {a}{num(rng, -20, 20)} {b}{num(rng, -20, 20)}")
        g.emit("G90")

    def turn(self) -> None:
        rng = self.rng
        t = 0.0 if rng.random() < 0.25 else rng.choice([-1, 1]) * rng.uniform(0.1, 2.4)
        self.heading += t

    def line(self, a: str, b: str, length: float, g: str) -> str:
        da, db = length * math.cos(self.heading), length * math.sin(self.heading)
        return f"G91 {g} {a}{da:.4f} {b}{db:.4f}"

    def element(self, g: Gen, a: str, b: str, n: str, ia: str, ib: str) -> None:
        rng = self.rng
        r = rng.random()
        if r < 0.12:
            g.emit(f"G91 {rng.choice(['G0', 'G1'])} {n}{num(rng, -3, 3)}")
            return
        self.turn()
        if r < 0.55:
            g.emit(self.line(a, b, rng.uniform(4, 30), "G0" if rng.random() < 0.15 else "G1")
                   + (f" F{num(rng, 50, 900, 1)}" if rng.random() < 0.1 else ""))
            return
        radius = rng.uniform(4, 30)
        ccw = rng.random() < 0.5
        sweep = 2 * math.pi if rng.random() < 0.08 else rng.uniform(0.3, 5.5)
        side = math.pi / 2 if ccw else -math.pi / 2
        ci, cj = radius * math.cos(self.heading + side), radius * math.sin(self.heading + side)
        phi = math.atan2(-cj, -ci) + (sweep if ccw else -sweep)  # the end seen from the centre
        ea, eb = ci + radius * math.cos(phi), cj + radius * math.sin(phi)
        self.heading += sweep if ccw else -sweep
        helix = f" {n}{num(rng, -4, 4)}" if rng.random() < 0.2 else ""
        code = "G3" if ccw else "G2"
        if sweep < 2 * math.pi and rng.random() < 0.3:
            rr = f"-{radius:.4f}" if sweep > math.pi else f"{radius:.4f}"
            g.emit(f"G91 {code} {a}{ea:.4f} {b}{eb:.4f} R{rr}{helix}")
        else:
            turns = f" P{rng.randint(2, 3)}" if helix and rng.random() < 0.3 else ""
            g.emit(f"G91 {code} {a}{ea:.4f} {b}{eb:.4f} {ia}{ci:.4f} {ib}{cj:.4f}{helix}{turns}")


def issue25(g: Gen, rng: random.Random) -> None:
    """Straight probing (G38.2-G38.5, after a G0 so rs274's canonical layer knows where the tool is:
    docs/dialects/rs274ngc.md), a plane of U V W with straight moves and a probe in it, or M19."""
    def _axes(rng: random.Random) -> str:  # as Gen.axes, from these draws
        chosen = [a for a in "XYZ" if rng.random() < 0.6] or [rng.choice("XYZ")]
        return " ".join(f"{a}[#{rng.randint(1, 5)} mod 20]" if rng.random() < 0.15 else f"{a}{num(rng, -30, 30)}"
                        for a in chosen)

    kind = rng.randrange(3)
    if kind == 0:
        g.emit(f"G0 {_axes(rng)}")
        dist = rng.choice(["", "G90 ", "G91 "])
        code = rng.choice(["G38.2", "G38.3", "G38.4", "G38.5"])
        feed = f" F{num(rng, 20, 500, 1)}" if rng.random() < 0.3 else ""
        g.emit(f"{dist}{code} {_axes(rng)}{feed}" if rng.random() < 0.95 else f"G91 {code} X0{feed}")
        r = rng.random()
        if r < 0.3:
            g.emit(f"G90 G1 X#5061 Y[#5062 + {num(rng, -3, 3)}] Z#5063")
        elif r < 0.5:
            g.emit(f"#{rng.randint(1, 5)} = [#5061 + #5062 * #5070 - #5063]")
        elif r < 0.6:
            g.emit(f"G91 G1 {_axes(rng)}")  # from where rs274 leaves the tool
    elif kind == 1:
        g.emit(rng.choice(["G17.1", "G18.1", "G19.1"]))
        for _ in range(rng.randint(1, 3)):
            if rng.random() < 0.2:
                g.emit(f"G0 {_axes(rng)}")
                g.emit(f"G38.3 {_axes(rng)}")
            else:
                g.emit(f"{rng.choice(['G0', 'G1'])} {_axes(rng)}")
        g.emit(g.plane)
    else:
        words = [f"R{num(rng, 0, 360, 2)}" if rng.random() < 0.8 else ""]
        words += [f"Q{num(rng, 0.1, 5, 2)}" if rng.random() < 0.3 else "", f"P{rng.randint(0, 2)}" if rng.random() < 0.3 else ""]
        g.emit(" ".join(["M19", *[w for w in words if w]]))
        if rng.random() < 0.6:
            g.emit("M3")


def program(rng: random.Random, statements: int = 25, lathe: bool = True, lathe_share: float = 0.2,
            g70_comp: float = 0.3) -> str:
    """One random program; ``lathe_share`` of them get a lathe cycle (drawn last), whose G70 runs under
    cutter radius compensation in a share ``g70_comp`` (both from draws of their own: changing them
    changes nothing else)."""
    g = Gen(rng)
    g.emit("(random program)")
    g.emit(rng.choice(["G21", "G20"]) + " G17 G90 G94 G40 G49 G54 G80 G91.1 G8")
    g.emit(f"F{num(rng, 50, 900, 1)} S{rng.randint(200, 2000)} M3")
    for i in range(1, 6):
        g.emit(f"#{i} = {num(rng, -5, 5, 3)}")
    g.emit("#<_d0> = 0")
    g.emit("#<_d1> = 0")
    subs = []
    if rng.random() < 0.5:
        subs = ["o<shape> sub", "M73", f"G91 G1 X[#1] Y{num(rng, -5, 5)}", "G91 G2 X0 Y0 I[#2] J0",
                "o<shape> endsub [#1 * 2]"]
        g.out[1:1] = subs
    numbered = rng.randint(1, 9999) if rng.random() < 0.3 else None  # an O<n> ... M99 subprogram
    comp = Comp(random.Random(str(rng.getstate()[1])))  # its own draws (Comp's docstring)
    bore = random.Random(str(rng.getstate()[1]) + "G87")  # G87's own draws too: the rest stays as it was
    probe = random.Random(str(rng.getstate()[1]) + "G38")  # G38, G17.1-G19.1, M19: their own draws
    for _ in range(statements):
        g.statement()
        if comp.rng.random() < 0.12:
            comp.sequence(g)
        if bore.random() < 0.04:
            back_bore(g, bore)
        if probe.random() < 0.06:
            issue25(g, probe)
        if subs and rng.random() < 0.1:
            g.emit("G17")
            g.plane = "G17"
            g.emit(f"o<shape> call [{num(rng, -8, 8)}] [{num(rng, 1, 6)}]")
            g.emit("#3 = #<_value>")
        if numbered is not None and rng.random() < 0.1:
            g.emit(f"M98 P{numbered}" + (f" L{rng.randint(0, 3)}" if rng.random() < 0.5 else ""))
            g.no_context = g.no_context or g.out[-1].endswith(" L0")
    g.emit("M2")
    if numbered is not None:  # after the end, as Fanuc-style programs keep them; #1-#5 are shared
        g.emit(f"O{numbered}")
        g.emit("#<k> = [#1 * 0.5]")
        g.emit(f"G91 G1 X#<k> Y{num(rng, -5, 5)}")
        g.emit("#2 = [#2 + 0.5]")
        g.emit("M99")
    if lathe and rng.random() < lathe_share:  # drawn last: the rest of each program is what it was without it
        sub, block = lathe_cycle(random.Random(rng.random()), g70_comp)
        end = g.out.index("M2")
        g.out[end:end] = block
        g.out[1:1] = sub  # defined at the top, as the shape subroutine (rs274 refuses a sub met after M98's O<n>)
    return "\n".join(g.out) + "\n"
