"""Canonical machine operations: what the interpreter emits and the kinematics consumes.

Every record carries ``src``, the place in the program text that caused it. Positions are absolute
program values of the axes X, Y, Z (``diameter`` says whether X is a diameter); the kinematics turns
them into tool poses.  Nothing here knows about text or meshes.
"""
from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields
from functools import lru_cache

Vec3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Src:
    """Where a record comes from: program name, 1-based line and column, the block label if any.

    ``calls`` lists the call sites (program, line) that led here for subprogram bodies.
    """

    program: str
    line: int
    col: int = 1
    label: str = ""
    calls: tuple[tuple[str, int], ...] = ()


@dataclass(frozen=True, slots=True)
class Ramp:
    """A lead-in or runout: over ``length`` mm of travel along the thread's lead axis the tool
    also moves along ``axis`` by ``length*tan(angle)`` in ``direction`` (+1 or -1)."""

    length: float
    angle: float  # degrees, 0..60
    axis: str  # "X", "Y" or "Z"
    direction: int

    @property
    def displacement(self) -> float:
        """Signed physical displacement along ``axis`` over the whole ramp (mm)."""
        return self.direction * self.length * math.tan(math.radians(self.angle))


@dataclass(frozen=True, slots=True)
class Motion:
    src: Src
    start: Vec3
    end: Vec3
    diameter: bool  # X values are diameters


@dataclass(frozen=True, slots=True)
class Rapid(Motion):
    pass


@dataclass(frozen=True, slots=True)
class Feed(Motion):
    feed: float  # mm/min, or mm/rev when per_rev
    per_rev: bool


@dataclass(frozen=True, slots=True)
class Arc(Motion):
    """Circular (or helical) move in ``plane`` about ``center`` (absolute program values).

    ``clockwise`` is seen from the positive end of the plane normal (G17: +Z, G18: +Y, G19: +X).
    ``full_turn`` means start and end coincide in the plane and the arc is a whole circle; the
    linear axis moves from start to end in proportion to the angle (a helix).
    """

    center: Vec3
    plane: str  # "XY" (G17), "ZX" (G18), "YZ" (G19)
    clockwise: bool
    full_turn: bool
    feed: float
    per_rev: bool


@dataclass(frozen=True, slots=True)
class SyncedFeed(Motion):
    """Spindle-synchronised move (G33): waits for the spindle angle ``start_angle`` (degrees past the
    zero pulse in the direction of rotation), then advances ``lead`` mm per revolution along
    ``lead_axis`` (None: the axis with the larger travel).

    With ramps the tool follows the straight line ``start`` -> ``end`` with each ramp's
    displacement added progressively over its length (the lead-in over the first ``leadin.length``
    mm of lead-axis travel, the runout over the last), so it stops at ``tool_end``. ``end`` is thus
    the programmed end point only where no ramp moves it: the interpreter sets it so that the
    tool reaches what the dialect means (CNC8x6: see its lead-in rule in docs/dialects/cnc8x6.md).

    ``lead_change`` (mm/rev², Sinumerik G34 > 0, G35 < 0): the lead is not constant but linear in
    the revolutions turned since the start, lead(n) = ``lead`` + ``lead_change``·n (no ramps then)."""

    lead: float
    lead_axis: str | None
    start_angle: float
    leadin: Ramp | None = None
    runout: Ramp | None = None
    lead_change: float = 0.0

    @property
    def tool_end(self) -> Vec3:
        """Where the tool stops: ``end`` moved by the ramps' displacements (X twice that in
        diameter mode)."""
        final = list(self.end)
        for r in (self.leadin, self.runout):
            if r is not None:
                i = "XYZ".index(r.axis)
                final[i] += r.displacement * (2.0 if (i == 0 and self.diameter) else 1.0)
        return (final[0], final[1], final[2])


@dataclass(frozen=True, slots=True)
class Spindle:
    """The spindle's direction and speed from here on. ``css`` > 0 (Sinumerik G96 on a lathe): a
    constant cutting speed in m/min instead: the speed follows the tool's radius r as
    1000·css / (2·pi·r) rpm, at most ``limit`` rpm (LIMS; 0: no limit); ``speed`` is then the
    speed at the position where it was set."""
    src: Src
    direction: int  # +1 M03, -1 M04, 0 M05
    speed: float  # rpm, as programmed by S
    css: float = 0.0  # m/min (constant cutting speed), 0: ``speed`` holds
    limit: float = 0.0  # rpm, the speed limit under ``css`` (0: none)


@dataclass(frozen=True, slots=True)
class ToolChange:
    """The tool ``tool`` goes into the spindle; ``tool`` None empties it (Sinumerik ``T0 M6``):
    the moves after it carry no tool and remove nothing until the next change."""

    src: Src
    tool: int | None
    offset: int | None = None


@dataclass(frozen=True, slots=True)
class ProgramEnd:
    src: Src


Record = Rapid | Feed | Arc | SyncedFeed | Spindle | ToolChange | ProgramEnd


def _quick_init(cls) -> None:
    """Give a frozen slots dataclass an ``__init__`` that fills the slots through their member
    descriptors: the same signature and defaults as the generated one, about a third faster (a
    program makes one Src and one record per block)."""
    names, params, env = [], [], {}
    for f in fields(cls):
        owner = next(k for k in cls.__mro__ if f.name in k.__dict__)
        env[f"_set_{f.name}"] = owner.__dict__[f.name].__set__
        if f.default is not MISSING:
            env[f"_default_{f.name}"] = f.default
            params.append(f"{f.name}=_default_{f.name}")
        else:
            params.append(f.name)
        names.append(f.name)
    body = "".join(f"    _set_{n}(self, {n})\n" for n in names)
    exec(f"def __init__(self, {', '.join(params)}):\n{body}", env)  # noqa: S102 - fixed text from field names
    init = env["__init__"]
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    cls.__init__ = init


for _cls in (Src, Ramp, Rapid, Feed, Arc, SyncedFeed, Spindle, ToolChange, ProgramEnd):
    _quick_init(_cls)
MOTIONS = (Rapid, Feed, Arc, SyncedFeed)


@dataclass
class Program:
    """The interpreter's result: the canonical records in execution order and the block count."""

    name: str
    dialect: str
    records: list = field(default_factory=list)
    blocks: int = 0
    warnings: list = field(default_factory=list)  # (Src, message)
    final_position: tuple[float, float, float] | None = None  # program values after the last block

    @property
    def moves(self) -> list:
        return [r for r in self.records if isinstance(r, MOTIONS)]

    @property
    def last_cut_position(self) -> Vec3 | None:
        """Where the last cutting (non-rapid) motion leaves the tool, in program values (X a
        diameter when that motion was programmed in diameter mode); None without any."""
        for r in reversed(self.records):
            if isinstance(r, SyncedFeed):
                return r.tool_end
            if isinstance(r, (Feed, Arc)):
                return r.end
        return None


@lru_cache(maxsize=1024)
def _fmt(v: float) -> str:
    s = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


@lru_cache(maxsize=256)
def _vec(v: Vec3) -> str:
    """Cached: a move's start is the previous move's end (equal values print alike; -0 prints 0)."""
    return "(" + " ".join(_fmt(c) for c in v) + ")"


def describe(rec) -> str:
    """One stable text line for a record: the golden-transcript format."""
    where = f"{rec.src.line:>4}"
    if isinstance(rec, Rapid):
        body = f"RAPID {_vec(rec.start)} -> {_vec(rec.end)}"
    elif isinstance(rec, Feed):
        body = f"FEED {_vec(rec.start)} -> {_vec(rec.end)} F{_fmt(rec.feed)}{'/rev' if rec.per_rev else '/min'}"
    elif isinstance(rec, Arc):
        body = (f"ARC {'CW' if rec.clockwise else 'CCW'} {rec.plane} {_vec(rec.start)} -> {_vec(rec.end)} "
                f"C{_vec(rec.center)}{' FULL' if rec.full_turn else ''} F{_fmt(rec.feed)}{'/rev' if rec.per_rev else '/min'}")
    elif isinstance(rec, SyncedFeed):
        body = (f"SYNC {_vec(rec.start)} -> {_vec(rec.end)} LEAD {_fmt(rec.lead)}"
                f"{'' if rec.lead_axis is None else ' ON ' + rec.lead_axis} START {_fmt(rec.start_angle)}")
        for name, r in (("LEADIN", rec.leadin), ("RUNOUT", rec.runout)):
            if r is not None:
                body += f" {name} {_fmt(r.length)}@{_fmt(r.angle)}{'+' if r.direction > 0 else '-'}{r.axis}"
        if rec.lead_change:
            body += f" DLEAD {_fmt(rec.lead_change)}"
    elif isinstance(rec, Spindle):
        body = f"SPINDLE {({1: 'M03', -1: 'M04', 0: 'M05'})[rec.direction]} S{_fmt(rec.speed)}"
        if rec.css:
            body += f" CSS {_fmt(rec.css)}" + (f" LIMS {_fmt(rec.limit)}" if rec.limit else "")
    elif isinstance(rec, ToolChange):
        body = ("TOOL none" if rec.tool is None else f"TOOL T{rec.tool}") + ("" if rec.offset is None else f" D{rec.offset}")
    elif isinstance(rec, ProgramEnd):
        body = "END"
    else:  # pragma: no cover - every record type is listed above
        raise TypeError(rec)
    if isinstance(rec, (Rapid, Feed, Arc, SyncedFeed)) and rec.diameter:
        body += " DIAM"
    return f"{where} {body}"


def transcript_lines(program: Program):
    """The transcript line by line (each ending in a newline), for writing it out without holding
    all of it in memory."""
    for r in program.records:
        yield describe(r) + "\n"


def transcript(program: Program) -> str:
    return "".join(transcript_lines(program))
