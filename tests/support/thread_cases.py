"""Random lathe programs that turn a bar and cut a thread, with the thread check each one must pass,
derived from the program's words by geometry alone (conventions.md):

- root diameter = the X of the last pass (diameter programming);
- a groove of the start with offset ``a`` lies at ``z = z0 + s * lead * (phi + a) / 360 (mod lead)``,
  z0 the Z where every pass of that start begins, s = +1 right-hand (M03, feeding -Z), -1
  left-hand (M04): the check's ``phase`` is ``s * a`` with ``phase_z = z0``;
- pitch = lead / starts.

``Case.program(variant)`` writes the program correctly (``"ok"``) or deliberately wrong against the
same check: ``"lead"`` cuts every pass with the lead 1 % too long, ``"shift"`` starts one start
10 degrees late, ``"deep"`` puts the last pass of every start 0.05 mm (radially) too deep.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

VARIANTS = ("ok", "lead", "shift", "deep")
TOLERANCE = 0.02  # simulation chordal tolerance: the coarsest that still tells the deep variant apart
ROOT_TOL = 0.05  # on the diameter: chords read up to 2 x TOLERANCE small, the deep variant 0.1 more


def _f(v: float) -> str:
    return f"{v:.4f}".rstrip("0")


@dataclass
class Case:
    seed: int
    dialect: str  # "cnc8x6" or "isg"
    bar: float  # stock diameter
    turned: float  # diameter turned before threading
    turn_tool: tuple[float, float]  # angle, tip radius
    thread_tool: tuple[float, float]
    lead: float
    starts: int
    hand: str
    z0: float  # start Z of every pass
    zend: float  # end Z of every pass
    base: float  # offset of the first start, degrees
    passes: list[float]  # X of each pass, the last is the root diameter
    zrange: tuple[float, float]

    @property
    def offsets(self) -> list[float]:
        return [(self.base + k * 360.0 / self.starts) % 360.0 for k in range(self.starts)]

    def check(self) -> dict:
        s = 1.0 if self.hand == "right" else -1.0
        return dict(kind="thread", name="thread", z=list(self.zrange), lead=self.lead, starts=self.starts,
                    hand=self.hand, root_diameter=self.passes[-1], tolerance=ROOT_TOL,
                    phase=[(s * a) % 360.0 for a in self.offsets], phase_z=self.z0)

    def setup(self) -> str:
        (ta, tr), (ha, hr) = self.turn_tool, self.thread_tool
        lines = ["[machine]", 'kind = "lathe"', f'dialect = "{self.dialect}"']
        if self.dialect == "cnc8x6":
            lines.append("diameter_programming = true")
        lines += [f"start = [{self.bar + 40.0}, 0.0, 30.0]", "", "[stock]", 'shape = "cylinder"',
                  f"diameter = {self.bar}", "z = [-24.0, 0.0]", "",
                  "[[tool]]", "number = 1", 'kind = "turning"', f"angle = {ta}", f"tip_radius = {tr}", "",
                  "[[tool]]", "number = 2", 'kind = "thread"', f"angle = {ha}", f"tip_radius = {hr}", "",
                  "[simulation]", f"tolerance = {TOLERANCE}", ""]
        return "\n".join(lines)

    def program(self, variant: str = "ok") -> str:
        lead = self.lead * (1.01 if variant == "lead" else 1.0)
        offs = list(self.offsets)
        if variant == "shift":
            k = self.seed % self.starts
            offs[k] = (offs[k] + 10.0) % 360.0
        xs = list(self.passes)
        if variant == "deep":
            xs[-1] -= 0.1
        spin = "M03" if self.hand == "right" else "M04"
        w = WORDS[self.dialect]
        blocks = [b.format(spin=spin, turned=_f(self.turned), end=_f(self.zend - 3.0), out=_f(self.bar + 2.0),
                           away=_f(self.bar + 20.0)) for b in w["head"]]
        for a in offs:
            for x in xs:
                blocks += [f"G00 Z{_f(self.z0)}", w["to_x"].format(x=_f(x)),
                           w["g33"].format(z=_f(self.zend), lead=_f(lead), a=_f(a)), f"G00 X{_f(self.bar + 4.0)}"]
        blocks.append("M30")
        return "".join(f"N{w['step'] * (i + 1)} {b}\n" for i, b in enumerate(blocks))


# each dialect's words: turn to a diameter from Z2, then thread passes (G95 mm/rev on CNC8x6, G51
# diameter programming on ISG)
WORDS = {
    "cnc8x6": {"step": 10, "to_x": "X{x}", "g33": "G33 Z{z} F{lead} I{a}",
               "head": ["G95 G00 T1 D1 S1200 M03", "G00 X{turned} Z2.", "G01 Z{end} F0.2", "X{out}",
                        "G00 X{away} Z20.", "T2 D2 S400 {spin}"]},
    "isg": {"step": 5, "to_x": "G00 X{x}", "g33": "G33 Z{z} K{lead} S.OFFSET={a}",
            "head": ["G51", "T1 D1 M03 S1200", "G00 X{turned} Z2", "G01 Z{end} F200", "G01 X{out}",
                     "G00 X{away} Z20", "T2 D2 {spin} S400"]},
}


def make_case(seed: int) -> Case:
    """Case ``seed``: deterministic (numpy's generator seeded with it)."""
    rng = np.random.default_rng(seed)
    dialect = ("cnc8x6", "isg")[seed % 2]
    starts = int(rng.integers(1, 4))
    lead = min(round(float(rng.uniform(1.0, 3.0)) * starts, 3), 6.0)  # pitch 1 to 3, lead at most 6
    pitch = lead / starts
    bar = round(float(rng.uniform(16.0, 30.0)), 2)
    turned = round(bar - float(rng.uniform(0.6, 3.0)), 3)
    ha = float(rng.choice([55.0, 60.0]))
    hr = float(rng.choice([0.0, 0.05, 0.1]))
    # depth: a third to a half of the pitch, and the nose must fit the groove
    depth = round(pitch * float(rng.uniform(0.33, 0.5)) + hr, 3)
    root = round(turned - 2.0 * depth, 3)
    npass = int(rng.integers(1, 4))
    passes = [round(turned - 2.0 * depth * math.sqrt((k + 1) / npass), 3) for k in range(npass)]
    passes[-1] = root
    z0 = round(float(rng.uniform(0.5, 4.0)), 3)
    zend = round(float(rng.uniform(-17.0, -11.0)), 3)
    half = math.tan(math.radians(ha / 2.0))
    width = 2.0 * (depth + hr) * half + 0.2  # the groove at the crest, the end ring as wide
    zrange = (round(zend + width + 0.5, 3), -1.0)
    return Case(seed, dialect, bar, turned, (float(rng.choice([35.0, 55.0, 80.0])),
                                             float(rng.choice([0.0, 0.2, 0.4, 0.8]))),
                (ha, hr), lead, starts, ("right", "left")[int(rng.integers(0, 2))], z0, zend,
                round(float(rng.uniform(0.0, 360.0)), 3), passes, zrange)
