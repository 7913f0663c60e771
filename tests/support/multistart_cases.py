"""Random multi-start ISO metric threads for the pitch-diameter property test
(tests/reports/test_thread_multistart_props.py): 2, 3 or 4 starts cut with a sharp 60 degree V
(``kind = "thread"``, tip_radius 0) in CNC8x6, one start after the other (offsets I = phase +
k 360 / starts), either hand, outside on a bar of d (odd seeds) or inside a tube bored to D1
(even seeds). The expected diameters come from the program's words alone (H = sqrt(3)/2 P, P =
lead / starts): a sharp V's groove is 2 (depth) tan 30 wide, so it is P/2 wide H/2 above (outside)
or below (inside) its tip:
- outside: last pass at X = d - 2 x 7H/8 (the ISO 68-1 fundamental triangle's apex), so
  d2 = X + H = d - 0.649519 P (ISO 724), the tip forms d1' = X;
- inside: last pass at X = D + 2 x H/8 (the apex beyond the major diameter), D2 = X - H =
  D - 0.649519 P, the bore D1 = D - 1.082532 P stays the crest.
The wrong variants: one start 10 degrees late (its phase fails), the last pass 0.01 mm shallow
(radially: the pitch diameter 2 x 0.01 / ... fails: a V 0.01 shallower is 0.02 smaller or larger
in d2, ten times the check's tolerance).
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass

PITCHES = (0.75, 1.0, 1.25, 1.5, 2.0)
VARIANTS = ("ok", "shallow", "shift")
S3 = math.sqrt(3.0)
SHALLOW = 0.01  # mm, radial
SHIFT = 10.0  # degrees


@dataclass
class MultiCase:
    seed: int
    side: str
    pitch: float
    starts: int
    d: float  # nominal (major) diameter
    length: float
    z_start: float
    offset: float
    hand: str
    tol: float = 0.002

    @property
    def lead(self) -> float:
        return self.pitch * self.starts

    @property
    def x_last(self) -> float:
        h = S3 / 2.0 * self.pitch
        return self.d - 2.0 * 7.0 * h / 8.0 if self.side == "outside" else self.d + 2.0 * h / 8.0

    @property
    def pitch_diameter(self) -> float:
        return self.d - 0.649519 * self.pitch  # = x_last +- H (module docstring), ISO 724's d - 0.649519 P

    def setup(self) -> str:
        if self.side == "inside":
            d1 = self.d - 1.082532 * self.pitch
            rout = self.d / 2.0 + 3.0
            stock = (f'shape = "revolve"\nprofile = [[{d1 / 2:.6f}, 0], [{rout:.4f}, 0], [{rout:.4f}, {-self.length}], '
                     f'[{d1 / 2:.6f}, {-self.length}]]')
            start = d1 - 2.0
        else:
            stock = f'shape = "cylinder"\ndiameter = {self.d:.4f}\nz = [{-self.length}, 0.0]'
            start = self.d + 6.0
        return f"""[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [{start:.3f}, 0.0, 30.0]

[stock]
{stock}

[[tool]]
number = 1
kind = "thread"
angle = 60.0
side = "{self.side}"
height = {2.0 * self.pitch:.4f}

[simulation]
tolerance = {self.tol}
"""

    def program(self, variant: str = "ok") -> str:
        spindle = "M03" if self.hand == "right" else "M04"
        inward = -1.0 if self.side == "inside" else 1.0  # X of a shallower pass
        x_last = self.x_last + (2.0 * SHALLOW * inward if variant == "shallow" else 0.0)
        clear = self.d - 1.082532 * self.pitch - 1.0 if self.side == "inside" else self.d + 2.0
        late = self.seed % self.starts
        lines = [f"N10 G00 G95 T1 D1 S500 {spindle}", f"G00 X{clear:.4f} Z{self.z_start:.4f}"]
        for k in range(self.starts):
            off = (self.offset + k * 360.0 / self.starts + (SHIFT if variant == "shift" and k == late else 0.0)) % 360.0
            for x in (x_last + inward * 0.3 * self.pitch, x_last):
                lines += [f"X{x:.4f}", f"G33 Z{-self.length - 2.0:.4f} I{off:.4f} F{self.lead:.5f}",
                          f"G00 X{clear:.4f}", f"Z{self.z_start:.4f}"]
        lines += ["Z30.", "M05"]
        return "\n".join(lines) + "\n"

    def check(self) -> dict:
        sign = 1.0 if self.hand == "right" else -1.0
        return dict(kind="thread", side=self.side, z=[-self.length + 3.0, -3.0], lead=self.lead, starts=self.starts,
                    hand=self.hand, pitch_diameter=self.pitch_diameter, tolerance=0.002, phase_z=self.z_start,
                    phase=[(sign * (self.offset + k * 360.0 / self.starts)) % 360.0 for k in range(self.starts)])

    def wrong_items(self, variant: str) -> set[str]:
        if variant == "shallow":
            return {"pitch_diameter", "pitch_diameter_wires"}
        return {f"phase[{self.seed % self.starts + 1}]"}


def make_case(seed: int) -> MultiCase:
    rnd = random.Random(7919 * seed + 1)
    pitch = rnd.choice(PITCHES)
    starts = (2, 3, 4)[seed % 3]
    d = round(rnd.uniform(max(10.0, 8 * pitch), 50.0), 3)
    return MultiCase(seed=seed, side=("inside", "outside")[seed % 2], pitch=pitch, starts=starts, d=d,
                     length=round(rnd.uniform(6.0, 9.0) + 2 * pitch * starts, 2),
                     z_start=round(rnd.uniform(1.0, 3.0) + pitch * starts, 3),
                     offset=round(rnd.uniform(0.0, 360.0), 2), hand=rnd.choice(("right", "left")))
