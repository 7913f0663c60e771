"""Random ISO metric threads for the property test of the thread gauge (tests/reports/
test_thread_gauge_props.py): outside, a bar; inside, a tube bored to the minor diameter; either way
a single-start thread cut with a full-profile insert (pitch 0.75 to 2.5, diameter 8 P to 60 mm,
either hand, random start Z and angle) in CNC8x6 (G33 Z.. I<angle> F<lead>) and ISG (G51 diameter
programming, G33 Z.. K<lead> S.OFFSET=<angle>): seeds 0, 1 CNC8x6 inside and outside, 2, 3 ISG, and so
on. The check is derived from the program's words
alone (H = sqrt(3)/2 P, last pass at X):
- inside: the insert's flat tip (P/8) forms the root, D = X; its shoulders 5H/8 nearer the axis
  recut the crest (the tube is bored 0.1 below it) at D1 = X - 5 sqrt(3) P / 8; the groove, P/8 at the tip and widening by 2 tan 30 per
  mm inwards, is P/2 wide at D2 = X - 3 sqrt(3) P / 8;
- outside: the flat tip (P/4) forms the root, d1 = X; the shoulders 5H/8 further out cut the crest,
  d = X + 5 sqrt(3) P / 8 (the bar is 0.1 over it); the groove is P/2 wide at d2 = X + sqrt(3) P / 4.
The crest is checked on both hands (the full-profile insert's shoulders overlap the next turn's,
stock/inserts.py: a left-hand thread's crest once kept a sliver of the blank).
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass

PITCHES = (0.75, 1.0, 1.25, 1.5, 2.0, 2.5)
VARIANTS = ("ok", "shallow", "shift", "hand", "pitch")
S3 = math.sqrt(3.0)


@dataclass
class GaugeCase:
    seed: int
    side: str
    pitch: float
    x_last: float
    length: float
    z_start: float
    offset: float
    hand: str
    starts: int = 1
    dialect: str = "cnc8x6"

    @property
    def lead(self) -> float:
        return self.pitch * self.starts

    def diameters(self) -> tuple[float, float, float]:
        """(major, pitch, minor) from the last pass's X."""
        x, p = self.x_last, self.pitch
        if self.side == "inside":
            return x, x - 3.0 * S3 / 8.0 * p, x - 5.0 * S3 / 8.0 * p
        return x + 5.0 * S3 / 8.0 * p, x + S3 / 4.0 * p, x

    def setup(self) -> str:
        major, _, minor = self.diameters()
        if self.side == "inside":
            rin, rout = minor / 2.0 - 0.05, major / 2.0 + 3.0
            stock = f'shape = "revolve"\nprofile = [[{rin:.6f}, 0], [{rout:.4f}, 0], [{rout:.4f}, {-self.length}], ' \
                    f'[{rin:.6f}, {-self.length}]]'
            start = 2 * rin - 2
        else:
            stock = f'shape = "cylinder"\ndiameter = {major + 0.1:.4f}\nz = [{-self.length}, 0.0]'
            start = major + 6
        return f"""[machine]
kind = "lathe"
dialect = "{self.dialect}"
{"diameter_programming = true" if self.dialect == "cnc8x6" else ""}
start = [{start:.3f}, 0.0, 30.0]

[stock]
{stock}

[[tool]]
number = 1
kind = "thread"
form = "full"
pitch = {self.pitch}
side = "{self.side}"
height = {2.0 * self.pitch + 1.0}

[simulation]
tolerance = 0.005
"""

    def program(self, variant: str = "ok") -> str:
        spindle = "M03" if (self.hand == "right") != (variant == "hand") else "M04"
        lead = self.lead * (1.01 if variant == "pitch" else 1.0)
        major, _, minor = self.diameters()
        inward = -1.0 if self.side == "inside" else 1.0  # X of a shallower pass: inside smaller, outside larger
        x_last = self.x_last + (0.04 * inward if variant == "shallow" else 0.0)
        clear = minor - 1.0 if self.side == "inside" else major + 2.0
        depth = 5.0 * S3 / 8.0 * self.pitch
        isg = self.dialect == "isg"
        lines = ["G51", f"T1 D1 {spindle} S500"] if isg else [f"N10 G00 G95 T1 D1 S500 {spindle}"]
        lines.append(f"G00 X{clear:.4f} Z{self.z_start:.4f}")
        for k in range(self.starts):
            off = (self.offset + k * 360.0 / self.starts + (10.0 if variant == "shift" and k == self.seed % self.starts
                                                              else 0.0)) % 360.0
            for f in (0.5, 0.2, 0.0):
                g33 = (f"G33 Z{-self.length - 2.0:.4f} K{lead:.5f} S.OFFSET={off:.3f}" if isg
                       else f"G33 Z{-self.length - 2.0:.4f} I{off:.3f} F{lead:.5f}")
                lines += [f"G00 X{x_last + inward * f * depth:.4f}", g33, f"G00 X{clear:.4f}", f"Z{self.z_start:.4f}"]
        lines += ["Z30.", "M05"] + (["M30"] if isg else [])
        return "\n".join(lines) + "\n"

    def check(self) -> dict:
        major, pitch_d, minor = self.diameters()
        sign = 1.0 if self.hand == "right" else -1.0
        out = dict(kind="thread", side=self.side, z=[-self.length + 3.0, -3.0], lead=self.lead, starts=self.starts,
                   hand=self.hand, major_diameter=major, pitch_diameter=pitch_d, minor_diameter=minor,
                   tolerance=0.004, phase_z=self.z_start,
                   phase=[(sign * (self.offset + k * 360.0 / self.starts)) % 360.0 for k in range(self.starts)])
        return out

    def wrong_items(self, variant: str) -> set[str]:
        """The items a wrong variant must fail."""
        if variant == "shallow":
            return {"pitch_diameter", "pitch_diameter_wires", "major_diameter" if self.side == "inside" else "minor_diameter"}
        return {"hand": {"hand"}, "pitch": {"lead"}}.get(variant, {f"phase[{self.seed % self.starts + 1}]"})


def make_case(seed: int) -> GaugeCase:
    rnd = random.Random(seed)
    pitch = rnd.choice(PITCHES)
    d = rnd.uniform(max(8.0, 8 * pitch), 60.0)
    side = ("inside", "outside")[seed % 2]
    x_last = d if side == "inside" else d - 5.0 * S3 / 8.0 * pitch
    return GaugeCase(seed=seed, side=side, pitch=pitch, x_last=round(x_last + rnd.uniform(0.0, 0.2), 3),
                     length=round(rnd.uniform(8.0, 14.0) + 2 * pitch, 2), z_start=round(rnd.uniform(1.0, 4.0) + pitch, 3),
                     offset=round(rnd.uniform(0.0, 360.0), 2), hand=rnd.choice(("right", "left")),
                     dialect=("cnc8x6", "isg")[(seed // 2) % 2])
