"""The modal machine every dialect drives: position, modal groups, and emission of canonical records.

A dialect scans its own syntax and calls these methods; the rules that are the same on every
controller (absolute/incremental targets, arcs by centre, diameter values) live here once.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum

from .. import canon
from ..canon import Src, Vec3
from ..errors import CutsimError
from .lexer import COORD_LIMIT, permitted_range

AXES = ("X", "Y", "Z")
PLANES = {17: "XY", 18: "ZX", 19: "YZ"}
# Plane -> (first axis, second axis, normal axis) as indices into (X, Y, Z).
PLANE_AXES = {"XY": (0, 1, 2), "ZX": (2, 0, 1), "YZ": (1, 2, 0)}
MAX_BLOCKS = 1_000_000  # executed blocks before a program is treated as one that does not end (docs/setup.md)


class Group(Enum):
    """The modal groups of G and M codes, one name each on every dialect. Codes of one group exclude
    each other in a block (core.Code); a code that excludes no other has a group of its own. The
    executor applies MOTION, DISTANCE, FEED and PLANE itself; the others are a dialect's."""

    MOTION = "motion"  # G0 G1 G2 G3 G33
    DISTANCE = "distance mode"  # G90 G91
    FEED = "feed mode"  # G94 G95
    PLANE = "plane"  # G17 G18 G19
    RADIUS_COMP = "radius compensation"  # G40 G41 G42
    TRC_TRANSITION = "compensation transition"  # ISG G25 G26
    TRC_SELECTION = "compensation selection"  # ISG G138 G139
    DIAMETER = "diameter mode"  # ISG G51 G52
    ZERO_OFFSET = "zero offset"  # G53..G59
    REFERENCE = "reference point offset"  # ISG G92
    CENTRE = "circle centre mode"  # ISG G161 G162
    UNITS = "units"  # G70 G71
    MIRROR = "mirroring"  # ISG G20..G23
    MIRROR_AXES = "mirroring of axes"  # ISG G351
    ROTATION = "contour rotation"  # ISG G68 G69
    HELIX_ON = "helix on"  # CNC8x6 G09
    HELIX_PITCH = "helix pitch"  # CNC8x6 G10
    HELIX_OFF = "helix off"  # CNC8x6 G98
    JUMP = "jump"  # CNC8x6 G73
    STOP = "stop"  # M0 M1
    END = "end"  # M2 M30 (ISG M17 M29: subprogram end)
    SPINDLE = "spindle"  # M3 M4 M5
    TOOL = "tool"  # ISG M6
    COOLANT = "coolant"  # M7 M8 M9
    GEAR = "gear"  # CNC8x6 M41..M44
    ARC_DISTANCE = "arc distance mode"  # RS274NGC G90.1 G91.1
    NON_MODAL = "non-modal"  # RS274NGC group 0: G4 G10 G28 G30 G53 G92..
    TOOL_LENGTH = "tool length offset"  # RS274NGC G43 G43.1 G43.2 G49
    PATH_CONTROL = "path control"  # RS274NGC G61 G61.1 G64
    RETRACT = "canned cycle return"  # RS274NGC G98 G99
    SPINDLE_MODE = "spindle speed mode"  # RS274NGC G96 G97
    OVERRIDE = "override switches"  # RS274NGC M48..M53
    IO = "digital and analog outputs"  # RS274NGC M62..M68
    CANNED_CYCLE = "canned cycle"  # Sinumerik ISO G73 G74 G80..G89 (apart from the motion group)
    LANGUAGE_MODE = "language mode"  # Sinumerik G290 G291 (Siemens / ISO dialect)
    EXACT_STOP = "exact stop window"  # Sinumerik G601 G602 G603
    CORNER = "compensation corners"  # Sinumerik G450 G451

    __hash__ = object.__hash__  # members are singletons: hashed by identity, without a Python call


@dataclass
class InterpConfig:
    """What the interpreter needs from the setup: nothing geometric beyond the start position."""

    dialect: str
    machine_kind: str = "lathe"  # "lathe" | "mill"
    diameter_programming: bool = False
    start: Vec3 = (0.0, 0.0, 0.0)  # program values
    parameters: dict[int, float] = field(default_factory=dict)
    constants: dict[int, float] = field(default_factory=dict)
    max_blocks: int = MAX_BLOCKS  # [simulation] max_blocks
    tool_radii: dict[int, float] = field(default_factory=dict)  # tool number -> radius (mills; first = active at start)
    # lathe tools: tool number -> (nose radius, cutting edge position 1-9) for nose radius compensation
    tool_noses: dict[int, tuple[float, int]] = field(default_factory=dict)
    tool_widths: dict[int, float] = field(default_factory=dict)  # grooving tools: number -> width (Sinumerik CYCLE93)
    tool_faces: frozenset[int] = frozenset()  # lathe tools with side = "face" (Sinumerik CYCLE93 face grooves)
    # What only the setup can say about the machine (docs/setup.md). Every name is
    # upper case as the dialect normalises it; the interpreter names the setup key in its errors.
    axes: dict[str, str] = field(default_factory=dict)  # [machine] axes: extra axis -> "rotary" | "linear"
    m_functions: frozenset[int] = frozenset()  # [machine] m_functions: machine M codes that pass silently
    h_functions: frozenset[int] = frozenset()  # [machine] h_functions (ISG H words)
    transformations: frozenset[str] = frozenset()  # [machine] transformations: Cartesian ones ("TRAFO")
    variables: dict[str, float | str] = field(default_factory=dict)  # [variables]: "$P_X", "$A_DBB[5]", "V.G.X"
    work_offsets: dict[str, Vec3] = field(default_factory=dict)  # [work_offsets] "G54" = [x, y, z] (mm, machine frame)
    subprogram_path: tuple[str, ...] = ()  # [machine] subprogram_path: absolute dirs, searched after the program's
    tool_names: dict[str, int] = field(default_factory=dict)  # [[tool]] name -> number (T="DRILL 8.5")
    # [machine] external_subprograms: subprograms / cycle files / implicit-call G codes the machine has but
    # the simulator does not ("0_INICIO_PROG.NC", "G803", "L_VENDOR"): upper case, file names without
    # their folder. A call to one is accepted with one warning naming it; its motion is not simulated
    # and the position after the call is the position before it.
    external_subprograms: frozenset[str] = frozenset()
    # RS274NGC: the setup's LinuxCNC tool table (.tbl) and parameter file (.var), absolute paths or ""
    tool_table: str = ""
    parameter_file: str = ""
    # Sinumerik lathe: [machine] thread_acceleration, the thread axis' acceleration in mm/s^2 (0: not
    # given), the ramp DITS/DITE = -1 cut over (docs/dialects/sinumerik-turning.md "DITS / DITE")
    thread_acceleration: float = 0.0


class ModalMachine:
    def __init__(self, name: str, cfg: InterpConfig):
        self.name = name
        self.cfg = cfg
        self.pos: list[float] = list(cfg.start)
        self._pos_t: Vec3 | None = None  # ``pos`` as the tuple the last move ended at (start_point)
        self.diameter = cfg.diameter_programming if cfg.machine_kind == "lathe" else False
        self.absolute = True
        self.per_rev = False
        self.feed: float | None = None
        self.spindle_dir = 0
        self.speed = 0.0
        self.plane = "ZX" if cfg.machine_kind == "lathe" else "XY"
        self.program = canon.Program(name=name, dialect=cfg.dialect)
        self._warned_feed = False
        self.executed = 0  # blocks executed (count_block)

    # -- helpers ---------------------------------------------------------------------------------
    def count_block(self, b) -> None:
        """Count one executed block (anything with a ``line``); past ``cfg.max_blocks`` the error
        ``block_limit`` builds is raised: the one guard against programs that do not end."""
        self.executed += 1
        if self.executed > self.cfg.max_blocks:
            raise self.block_limit(b)

    def block_limit(self, b) -> CutsimError:
        """The error for the block that passes ``cfg.max_blocks``; dialects name their loops."""
        return self.error(b.line, 1, f"more than {self.cfg.max_blocks:,} blocks executed "
                          "(the limit is [simulation] max_blocks)")

    def error(self, line: int, col: int, message: str) -> CutsimError:
        return CutsimError(self.name, line, col, message)

    def emit(self, rec) -> None:
        self.program.records.append(rec)

    def warn(self, src: Src, message: str) -> None:
        self.program.warnings.append((src, message))

    def whole(self, line: int, w, what: str) -> int:
        """The value of word ``w`` as a whole number of 0 or more (a tool or offset number); an
        error at its column otherwise. The value is finite (the lexer checked its range)."""
        if w.value != int(w.value) or w.value < 0:
            raise self.error(line, w.col, f"{what} {w.letter}{w.raw} must be a whole number, 0 or more")
        return int(w.value)

    def check_position(self, line: int, end, cols: dict[int, int] | None = None, limit: float = COORD_LIMIT) -> None:
        """Every axis of ``end`` (program values) within +-``limit`` (docs/dialects/*.md, "Limits");
        incremental moves, ramps and helices can pass it with words that are each in range. The
        error is at the column of the axis word (``cols``: axis index -> column), else at 1."""
        for i, v in enumerate(end):
            if not (math.isfinite(v) and abs(v) <= limit):
                col = (cols or {}).get(i, 1)
                raise self.error(line, col, f"the {AXES[i]} position {v:.4f} {permitted_range(-limit, limit, 'mm')}")

    def set_diameter(self, on: bool) -> None:
        """Switch X between diameter and radius values; the tool does not move."""
        if on != self.diameter:
            self.pos[0] = self.pos[0] * 2.0 if on else self.pos[0] / 2.0  # (start_point sees the new value)
            self.diameter = on

    def target(self, values: dict[int, float], absolute: dict[int, bool] | None = None) -> Vec3:
        """End point from axis values (index -> value), honouring G90/G91 or a per-axis override."""
        end = list(self.pos)
        for i, v in values.items():
            ab = self.absolute if absolute is None or i not in absolute else absolute[i]
            end[i] = v if ab else self.pos[i] + v
        return (end[0], end[1], end[2])

    @staticmethod
    def split_words(words) -> tuple[list, list, dict]:
        """A block's words: the G words, the M words and the others by letter."""
        gs, ms, rest = [], [], {}
        for w in words:
            if w.letter == "G":
                gs.append(w)
            elif w.letter == "M":
                ms.append(w)
            else:
                rest[w.letter] = w
        return gs, ms, rest

    def spindle_code(self, line: int, codes: list[tuple[int, int]]) -> int | None:
        """The spindle direction the block's M3/M4/M5 set (+1, -1, 0; None without one) from
        (code, column) pairs; two of them in one block are an error at the second."""
        direction = None
        for code, col in codes:
            if code in (3, 4, 5):
                if direction is not None:
                    raise self.error(line, col, "two spindle M codes in one block")
                direction = {3: 1, 4: -1, 5: 0}[code]
        return direction

    def common_g(self, code: int) -> bool:
        """Apply a G code every dialect means the same way: G90/G91 distance mode, G94/G95 feed
        mode, G17/G18/G19 plane. False when ``code`` is none of them."""
        if code in (90, 91):
            self.absolute = code == 90
        elif code in (94, 95):
            self.per_rev = code == 95
        elif code in PLANES:
            self.plane = PLANES[code]
        else:
            return False
        return True

    # -- motions ---------------------------------------------------------------------------------
    def start_point(self) -> Vec3:
        """``pos`` as a tuple: the very tuple the previous move ended at while ``pos`` still holds
        its values (the same float objects), so consecutive records share it (half the memory of
        a move's points); a new tuple when ``pos`` was changed since."""
        p, t = self.pos, self._pos_t
        if t is None or len(p) != 3 or t[0] is not p[0] or t[1] is not p[1] or t[2] is not p[2]:
            t = self._pos_t = tuple(p)
        return t

    def moved(self, end) -> None:
        """The tool is at ``end`` now."""
        self.pos = list(end)
        self._pos_t = end if type(end) is tuple else None

    def rapid(self, src: Src, end: Vec3) -> None:
        self.emit(canon.Rapid(src, self.start_point(), end, self.diameter))
        self.moved(end)

    def need_feed(self, src: Src) -> float:
        """The modal feed; 0.0 (with one warning) when none was programmed: the feed only changes
        the cycle time, so a fragment without F still simulates."""
        if self.feed is None:
            if not self._warned_feed:
                self.warn(src, "feed motion with no feed rate programmed (F); the cycle time assumes the machine's default feed")
                self._warned_feed = True
            return 0.0
        return self.feed

    def linear(self, src: Src, end: Vec3) -> None:
        feed = self.need_feed(src)
        self.emit(canon.Feed(src, self.start_point(), end, self.diameter, feed, self.per_rev))
        self.moved(end)

    def arc(self, src: Src, end: Vec3, center: Vec3, clockwise: bool) -> None:
        """Arc about an absolute centre in the current plane; start = end in the plane is a full
        circle. The end must lie on the circle through the start."""
        feed = self.need_feed(src)
        a, b, _ = PLANE_AXES[self.plane]
        start = self.start_point()

        def rad(p, i):  # physical coordinate (X as radius in diameter mode)
            return p[i] / 2.0 if (i == 0 and self.diameter) else p[i]

        r0 = math.hypot(rad(start, a) - rad(center, a), rad(start, b) - rad(center, b))
        r1 = math.hypot(rad(end, a) - rad(center, a), rad(end, b) - rad(center, b))
        if r0 < 1e-9:
            raise self.error(src.line, src.col, "arc centre coincides with its start point")
        if abs(r1 - r0) > max(0.005, 1e-4 * r0):
            raise self.error(src.line, src.col,
                             f"arc end point is not on the circle (radius {r0:.4f} at the start, {r1:.4f} at the end)")
        full = abs(rad(end, a) - rad(start, a)) < 1e-9 and abs(rad(end, b) - rad(start, b)) < 1e-9
        self.emit(canon.Arc(src, start, end, self.diameter, center, self.plane, clockwise, full, feed, self.per_rev))
        self.moved(end)

    def synced(self, src: Src, end: Vec3, lead: float, lead_axis: str | None, start_angle: float,
               leadin: canon.Ramp | None = None, runout: canon.Ramp | None = None) -> None:
        """G33. The tool ends at the programmed end point moved by the ramps' displacements."""
        rec = canon.SyncedFeed(src, self.start_point(), end, self.diameter, lead, lead_axis, start_angle, leadin, runout)
        self.emit(rec)
        self.moved(rec.tool_end)

    def spindle(self, src: Src, direction: int | None, speed: float | None) -> None:
        if direction is not None:
            self.spindle_dir = direction
        if speed is not None:
            self.speed = speed
        self.emit(canon.Spindle(src, self.spindle_dir, self.speed))

    def tool(self, src: Src, number: int, offset: int | None) -> None:
        self.emit(canon.ToolChange(src, number, offset))

    def end(self, src: Src) -> None:
        self.emit(canon.ProgramEnd(src))
