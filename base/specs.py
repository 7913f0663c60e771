"""What the setup says about the machine, the stock and the tools: plain data every stage may use
(the machine model runs in kinematics/, shapes are built in stock/)."""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class MachineSpec:
    """The machine model the kinematics needs (from the setup's [machine] table)."""

    kind: str = "lathe"  # "lathe" | "mill"
    dialect: str = "cnc8x6"
    diameter_programming: bool = True
    m03: str = "positive"  # sense of M03 about +Z: "positive" | "negative"
    start: tuple[float, float, float] | None = None  # program values; None = clear of the stock
    rapid: float = 10000.0  # mm/min, for the cycle time
    feed: float = 100.0  # mm/min assumed when a program feeds without F (cycle time only)


@dataclass(frozen=True)
class StockSpec:
    shape: str  # "cylinder" | "revolve" | "box" | "mesh"
    diameter: float = 0.0
    z: tuple[float, float] = (0.0, 0.0)
    profile: tuple[tuple[float, float], ...] = ()  # revolve: (r, z) outline
    x: tuple[float, float] = (0.0, 0.0)
    y: tuple[float, float] = (0.0, 0.0)
    path: str = ""  # mesh: absolute path

    def bounds(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Axis-aligned bounds (lo, hi) without building the solid (mesh stock: filled in by the loader)."""
        if self.shape == "cylinder":
            r = self.diameter / 2
            return (-r, -r, self.z[0]), (r, r, self.z[1])
        if self.shape == "revolve":
            r = max(p[0] for p in self.profile)
            zs = [p[1] for p in self.profile]
            return (-r, -r, min(zs)), (r, r, max(zs))
        return (self.x[0], self.y[0], self.z[0]), (self.x[1], self.y[1], self.z[1])


@dataclass(frozen=True)
class ToolSpec:
    number: int
    kind: str  # "thread" | "turning" | "profile" | "endmill" | "ballmill" | "drill"
    angle: float = 60.0  # thread/turning: included angle of the V, degrees
    tip_radius: float = 0.0  # thread/turning: nose radius
    height: float = 10.0  # lathe tools: how far the profile reaches out from the tip, mm
    thickness: float = 5.0  # lathe tools: insert thickness along Y (cuts with the spindle stopped)
    points: tuple[tuple[float, float], ...] = ()  # profile: (x, z) polygon, control point at (0, 0)
    diameter: float = 0.0  # mills
    length: float = 0.0  # mills: flute length
    corner_radius: float = 0.0  # mills: bull-nose corner radius (ballmill: diameter / 2)
    center_cutting: bool = True  # mills: can plunge (an end mill without centre cutting edges cannot)
    point_angle: float = 118.0  # drill: included angle of the point, degrees (180 = flat)
    name: str = field(default="", compare=False)  # [[tool]] name (T="DRILL 8.5"); not part of the shape
    # where the tool is defined: the setup file and the line/column of its [[tool]] header, for
    # errors about the tool's shape found when it is built (not part of the tool's identity)
    source: str = field(default="", compare=False)
    line: int = field(default=0, compare=False)
    col: int = field(default=0, compare=False)

    @property
    def is_lathe_tool(self) -> bool:
        return self.kind in ("thread", "turning", "profile")
