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
    kind: str  # "thread" | "turning" | "grooving" | "profile" | "centredrill" | "tap" | "endmill" | "ballmill" | "drill"
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
    side: str = "outside"  # thread/turning/grooving: "outside" (towards -X) | "inside" (+X) | "face" (-Z)
    hand: str = "R"  # turning insert/grooving: "R" (cuts towards -Z) | "L" (+Z) | "N" (neutral)
    insert: str = ""  # turning: ISO insert shape C D T V W S R ("" = the symmetric V of ``angle``)
    size: float = 12.7  # turning insert: inscribed circle diameter, mm
    approach: float = 0.0  # turning insert: holder approach angle kappa_r, degrees (0 = the default)
    form: str = "partial"  # thread: "partial" (the V) | "full" (ISO metric 60 degree profile of ``pitch``)
    pitch: float = 0.0  # thread, full form: the pitch the insert is ground for, mm
    crest_radius: float = 0.0  # thread, full form: radius of the insert's corners that round the crest's edges, mm
    width: float = 0.0  # grooving: width of the cutting edge, mm (corner radii: ``corner_radius``)
    pilot_length: float = 0.0  # centre drill: from the tip to where the countersink starts, mm
    body_diameter: float = 0.0  # centre drill: the body's diameter (the countersink's widest), mm
    countersink: float = 60.0  # centre drill: included angle of the countersink, 60 or 90 degrees
    chamfer: float = 0.0  # tap: length of the chamfered lead (from the tip), mm
    bar_diameter: float = 0.0  # inside thread/turning/grooving tool: its boring bar's diameter, mm (0: no bar)
    bar_reach: float = 0.0  # inside, with a bar: from the bar's axis to the tool point, mm (0: 0.7 x bar_diameter)
    shank: float = 0.0  # outside/face thread/turning/grooving tool: its holder's square shank, mm (0: no holder)
    name: str = field(default="", compare=False)  # [[tool]] name (T="DRILL 8.5"); not part of the shape
    # where the tool is defined: the setup file and the line/column of its [[tool]] header, for
    # errors about the tool's shape found when it is built (not part of the tool's identity)
    source: str = field(default="", compare=False)
    line: int = field(default=0, compare=False)
    col: int = field(default=0, compare=False)

    @property
    def is_lathe_tool(self) -> bool:
        """A tool only a lathe holds: the turret's tools and the axial tools the spindle axis
        takes only on a lathe (centre drill, tap; a twist drill works on a mill too)."""
        return self.kind in ("thread", "turning", "grooving", "profile") or self.is_axial

    @property
    def is_axial(self) -> bool:
        """A lathe tool on the spindle axis, given as a solid of revolution (centre drill, tap)."""
        return self.kind in ("centredrill", "tap")

    @property
    def tip_direction(self) -> tuple[int, int]:
        """Where the tool's point lies from the centre of its nose, as signs (dx, dz) in the
        workpiece's X-Z plane: what the cutting edge position (``edge_position``) encodes. The
        outside tool of hand R points to -X and -Z, hand L to -X and +Z, a neutral tool to -X;
        an inside tool mirrors X, a face tool swaps X and Z. A profile tool has no direction, nor
        has an axial tool (its point lies on its axis)."""
        if self.kind == "profile" or self.is_axial:
            return (0, 0)
        dz = {"R": -1, "L": 1}.get(self.hand, 0) if self.kind in ("turning", "grooving") and (
            self.kind == "grooving" or self.insert) else 0
        dx = 1 if self.side == "inside" else -1
        return (dz, dx) if self.side == "face" else (dx, dz)

    @property
    def edge_position(self) -> int:
        """The cutting edge position (1-9) a control's nose radius compensation needs, from
        ``tip_direction`` (docs/setup.md has the figure): 3 outside R, 4 outside L, 2 inside R,
        1 inside L, 8 straight to -X, 6 to +X, 7 to -Z, 5 to +Z, 9 a profile tool (centre)."""
        return EDGE_POSITIONS[self.tip_direction]

    @property
    def nose_radius(self) -> float:
        """The radius of the nose that nose radius compensation offsets by: a turning or thread
        tool's ``tip_radius``, a grooving tool's ``corner_radius``; 0 for a profile or axial tool."""
        if self.kind in ("turning", "thread"):
            return self.tip_radius
        return self.corner_radius if self.kind == "grooving" else 0.0


# (dx, dz) signs of the tool's point from its nose centre -> cutting edge position (X up, Z right)
EDGE_POSITIONS = {(1, 1): 1, (1, -1): 2, (-1, -1): 3, (-1, 1): 4, (0, 1): 5, (1, 0): 6, (0, -1): 7,
                  (-1, 0): 8, (0, 0): 9}
