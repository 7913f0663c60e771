"""Random inside threads for the property test of the thread gauge (tests/reports/
test_inside_thread_props.py): a tube bored below the minor diameter, then an ISO metric inside
thread (full-profile insert) cut through it in CNC8x6, either hand. The check is
derived from the program's words alone: the insert's flat tip (P/8) at the last pass's X is the
major diameter D = X; its shoulders 5H/8 nearer the axis cut the crest, D1 = X - 5 sqrt(3) P / 8;
the groove is P/2 wide (P/8 + 2 tan 30 per mm inwards) at D2 = X - 3 sqrt(3) P / 8."""
from __future__ import annotations

import math
import random
from dataclasses import dataclass

PITCHES = (0.75, 1.0, 1.25, 1.5, 2.0, 2.5)
VARIANTS = ("ok", "shallow", "shift", "hand", "pitch")


@dataclass
class InsideCase:
    seed: int
    pitch: float
    starts: int
    x_last: float
    length: float
    z_start: float
    offset: float
    hand: str

    @property
    def lead(self) -> float:
        return self.pitch * self.starts

    def minor(self) -> float:
        return self.x_last - 5.0 * math.sqrt(3.0) / 8.0 * self.pitch

    def setup(self) -> str:
        rin = self.minor() / 2.0  # bored to D1 first, as a machinist does
        rout = self.x_last / 2.0 + 3.0
        return f"""[machine]
kind = "lathe"
dialect = "cnc8x6"
diameter_programming = true
start = [{2 * rin - 2:.3f}, 0.0, 30.0]

[stock]
shape = "revolve"
profile = [[{rin:.4f}, 0], [{rout:.4f}, 0], [{rout:.4f}, {-self.length}], [{rin:.4f}, {-self.length}]]

[[tool]]
number = 1
kind = "thread"
form = "full"
pitch = {self.pitch}
side = "inside"
height = {2.0 * self.pitch + 1.0}

[simulation]
tolerance = 0.005
"""

    def program(self, variant: str = "ok") -> str:
        spindle = "M03" if (self.hand == "right") != (variant == "hand") else "M04"
        lead = self.lead * (1.01 if variant == "pitch" else 1.0)
        x_last = self.x_last - (0.04 if variant == "shallow" else 0.0)
        clear = self.minor() - 1.0
        depth = x_last - self.minor() + 0.2
        lines = [f"N10 G00 G95 T1 D1 S500 {spindle}", f"G00 X{clear:.4f} Z{self.z_start:.4f}"]
        for k in range(self.starts):
            off = (self.offset + k * 360.0 / self.starts + (10.0 if variant == "shift" and k == self.seed % self.starts
                                                              else 0.0)) % 360.0
            for x in (x_last - 0.5 * depth, x_last - 0.2 * depth, x_last):
                lines += [f"X{x:.4f}", f"G33 Z{-self.length - 2.0:.4f} I{off:.3f} F{lead:.5f}",
                          f"G00 X{clear:.4f}", f"Z{self.z_start:.4f}"]
        lines += ["Z30.", "M05"]
        return "\n".join(lines) + "\n"

    def check(self) -> dict:
        s = math.sqrt(3.0) / 8.0 * self.pitch
        sign = 1.0 if self.hand == "right" else -1.0
        return dict(kind="thread", side="inside", z=[-self.length + 3.0, -3.0], lead=self.lead, starts=self.starts,
                    hand=self.hand, major_diameter=self.x_last, pitch_diameter=self.x_last - 3.0 * s,
                    minor_diameter=self.x_last - 5.0 * s, tolerance=0.004,
                    phase=[(sign * (self.offset + k * 360.0 / self.starts)) % 360.0 for k in range(self.starts)],
                    phase_z=self.z_start)


def make_case(seed: int) -> InsideCase:
    rnd = random.Random(seed)
    pitch = rnd.choice(PITCHES)
    d = rnd.uniform(max(8.0, 8 * pitch), 60.0)
    starts = 1  # two starts: the crest between them is not always recut (see the docs)
    return InsideCase(seed=seed, pitch=pitch, starts=starts, x_last=round(d + rnd.uniform(0.0, 0.2), 3),
                      length=round(rnd.uniform(8.0, 14.0) + 2 * pitch * starts, 2),
                      z_start=round(rnd.uniform(1.0, 4.0) + pitch * starts, 3),
                      offset=round(rnd.uniform(0.0, 360.0), 2), hand=rnd.choice(("right", "left")))
