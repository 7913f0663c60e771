"""The RS274NGC machine on the shared executor (core.Interpreter): modes, offsets and motion.

Positions (``self.pos``, the records) are the tool tip in the machine frame in mm, X a radius:
program value x (mm) + G54..G59.3 offset + G92 offset + tool length offset in effect - the loaded
tool's length from the tool table (so G43 with the loaded tool puts the tip where the program
says). Parameters that hold offsets (#5161-#5389) are in mm: the machine is metric.
"""
from __future__ import annotations

import math

from cutsim.interp.canon import Src
from cutsim.interp.core import MOTION, Group, Interpreter, Step
from cutsim.interp.core.lexer import COORD_LIMIT, Word
from cutsim.interp.core.modal import PLANE_AXES, InterpConfig

from . import compensation, context, cycles, exact, lathe, offsets, orient, polar, probe, threading
from .tables import G_CODES, M_CODES, PLANES, REFUSED, REFUSED_M, UVW_PLANES
from .values import Parameters, Unreadable

INCH = 25.4
AXIS_INDEX = {"X": 0, "Y": 1, "Z": 2}


class Ngc(Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig, params: Parameters, tools: dict):
        super().__init__(name, cfg)
        self.params = params
        self.tools = tools  # tool number -> {"Z": mm, "X": mm, "D": mm}
        self.motion = 80
        self.plane = "XY"
        self.scale = 1.0  # mm per program unit (G21 1, G20 25.4)
        self.arc_abs = False
        self.feed_mode = 94
        self.retract_old = False  # G98 (LinuxCNC starts in G99)
        self.lathe_diameter = False  # G7
        self.g5x = [0.0, 0.0, 0.0]
        self.g92 = [0.0, 0.0, 0.0]
        self.tlo = [0.0, 0.0, 0.0]
        self.tool_len = [0.0, 0.0, 0.0]
        self.tool_no = 0
        self.selected = 0
        self.coord = 1
        self.cycle = cycles.CycleState()
        self.feed_units = None  # F as programmed (program units), converted when used
        self.feed_scale = self.block_scale = 1.0  # mm per unit of F (the units when F was read); of the block's start
        self.surface_speed = self.warned_css = False  # G96 in effect; its warning given
        self.tlo_mode = 49  # the tool length offset's code (G43, G43.1, G43.2, G49)
        self.contexts: dict = {}  # call level -> the state M70/M73 saved there (context.py)
        self.context_m: list = []  # the block's M70-M73
        self.profile: list | None = None  # collecting a G70-G72 profile: its moves (lathe.capture)
        self.run_profile = None  # runs a profile subroutine (set by flow.Runner)
        probe.init(self)
        self.orient_words: tuple = ()  # the block's words M19 read (orient.py)
        compensation.init(self)
        offsets.load(self)
        exact.start(self)

    def emit(self, rec) -> None:
        if (self.comp is None and self.comp_exit is None) or not compensation.route(self, rec):
            self.program.records.append(rec)

    # -- program coordinates -----------------------------------------------------------------------
    def shift(self, i: int) -> float:
        return self.g5x[i] + self.g92[i] + self.tlo[i] - self.tool_len[i]

    def unit(self, i: int) -> float:
        """mm per program unit on axis ``i`` (X in G7 is a diameter)."""
        return self.scale / 2.0 if (i == 0 and self.lathe_diameter) else self.scale

    def program_value(self, i: int) -> float:
        """The position in program units (#5420-#5422, #<_x>...): X a radius in G7 too, as
        LinuxCNC 2.9 reads it (G7 halves X words, not the position it reports). Not while cutter
        radius compensation is on (rs274 refuses it)."""
        if self.comp_side:
            raise Unreadable("cannot read the current position with cutter radius compensation on")
        return (self.base()[i] - self.shift(i)) / self.scale

    def goal(self, st: Step, letters=("X", "Y", "Z"), machine: bool = False) -> tuple[tuple, dict]:
        """The end point (mm, machine frame) of the block's axis words under G90/G91; with
        ``machine`` (G53) absolute machine coordinates. Returns (end, {axis index: word})."""
        words = {AXIS_INDEX[a]: st.words.pop(a) for a in letters if a in st.words}
        end = self.base()
        for i, w in words.items():
            if machine:
                end[i] = w.value * self.unit(i) - self.tool_len[i]
            elif self.absolute:
                end[i] = w.value * self.unit(i) + self.shift(i)
            else:
                end[i] = end[i] + w.value * self.unit(i)
            exact.goal(self, i, w, end[i]) if not machine else exact.note(self, i, None, end[i])
        self.check_position(st.block.line, end, {i: w.col for i, w in words.items()})
        return (end[0], end[1], end[2]), words

    def base(self) -> list:
        """The tip position as a list (a move's unprogrammed axes stay where they are)."""
        return list(self.pos)

    def set_tlo(self, tlo: list) -> None:
        """A new tool length offset: the machine does not move, the program position changes (as
        LinuxCNC shows it)."""
        self.tlo = tlo

    def src(self, st: Step, col: int = 1) -> Src:
        return Src(self.name, st.src.line, col, "", st.src.calls)

    # -- G codes -----------------------------------------------------------------------------------
    def check_g(self, st: Step, gs: list[Word]) -> None:
        line = st.block.line
        self.block_scale = self.scale  # F counts in the units before the block's G20/G21 (LinuxCNC's order)
        self.block_plane = self.plane  # polar words need G17 before the block (polar.py)
        codes = []
        for g in gs:
            code = round(g.value, 4)
            if code in REFUSED:
                raise self.error(line, g.col, f"G{g.raw} ({REFUSED[code]}) is not simulated")
            row = self.G_CODES.get(code)
            if row is None:
                raise self.error(line, g.col, f"unknown G code G{g.raw}")
            if row.group in st.groups and not (row.group == MOTION and 80 in (code, round(st.groups[MOTION].value, 4))):
                raise self.error(line, g.col, f"G{g.raw} conflicts with G{st.groups[row.group].raw} in the same block "
                                 "(two codes of one modal group)")
            st.groups[row.group] = g
            codes.append((code, row, g))
        for code, row, g in codes:
            if row.group == MOTION:
                st.motion = code if st.motion in (None, 80) else st.motion
            elif row.group == Group.PLANE and self.comp_side and row.meaning != f"plane {self.plane}":
                raise self.error(line, g.col, f"G{g.raw}: cannot change the plane with cutter radius compensation on")
            elif row.group == Group.PLANE:
                self.plane = PLANES[code]
            elif row.group == Group.DISTANCE:
                self.common_g(int(code))
            else:
                self.g_code(st, code, row, g)

    def g_code(self, st: Step, code, row, g: Word) -> None:
        group = row.group
        if group == Group.UNITS:
            self.scale = INCH if code == 20 else 1.0
        elif group == Group.ARC_DISTANCE:
            self.arc_abs = code == 90.1
        elif group == Group.FEED:
            probe.leave_mode(self, code)
            self.feed_mode = int(code)
            self.per_rev = code == 95
            if code == 93:
                self.feed_units = None
        elif group == Group.DIAMETER:
            self.lathe_diameter = code == 7
        elif group == Group.RETRACT:
            compensation.refuse(self, st, g, f"G{g.raw}: cannot change the retract mode")
            self.retract_old = code == 98
        elif group == Group.ZERO_OFFSET:
            compensation.refuse(self, st, g, f"G{g.raw}: cannot change the coordinate system")
            offsets.select(self, code)
        elif group == Group.SPINDLE_MODE:
            self.surface_speed = code == 96
            if self.surface_speed and not self.warned_css:
                self.warn(self.src(st, g.col), "G96: S is a surface speed (m/min, ft/min in G20), D the spindle's "
                          "limit; the tool path is unchanged, the spindle speed is recorded as written (not in rpm)")
                self.warned_css = True
        else:
            st.g[group] = g

    # -- settings before the motion (LinuxCNC's order of execution) --------------------------------
    def convert_settings(self, st: Step) -> None:
        words, line = st.words, st.block.line
        if "F" in words:
            f = words.pop("F")
            if st.motion in (33, 33.1) or (st.motion is None and self.motion in (33, 33.1)):
                raise self.error(line, f.col, "F cannot be used with G33/G33.1 (the pitch is K)")
            if f.value < 0:
                raise self.error(line, f.col, "negative feed rate F")
            self.feed_units = f.value
            self.feed_scale = self.block_scale
        if Group.SPINDLE_MODE in st.groups and self.surface_speed and "D" in words:
            d = words.pop("D")  # G96's speed limit (rpm): no effect on the path
            if d.value < 0:
                raise self.error(line, d.col, "negative spindle speed limit D")
        if "S" in words:
            s = words.pop("S")
            if s.value < 0:
                raise self.error(line, s.col, "negative spindle speed S")
            self.speed = s.value
            if st.direction is None:
                self.spindle(self.src(st, s.col), None, s.value)
        if "T" in words:
            self.selected = self.whole(line, words.pop("T"), "tool number")
        self.tool_m(st)
        if st.direction is not None:
            self.spindle(self.src(st), st.direction, None)
        orient.run(self, st)
        context.run_block(self, st)  # M70-M73 after the spindle, before the modes (LinuxCNC's order)
        compensation.select(self, st)
        offsets.tool_length(self, st)
        if Group.PATH_CONTROL in st.g:
            compensation.refuse(self, st, st.g[Group.PATH_CONTROL], f"G{st.g[Group.PATH_CONTROL].raw}: cannot change "
                                "the path control mode")
            for letter in "PQ":
                w = st.words.pop(letter, None)
                if w is not None and w.value < 0:
                    raise self.error(line, w.col, f"G64 {letter} must not be negative")
        for code, m in self.m_group(st, Group.OVERRIDE) + self.m_group(st, Group.IO):
            for letter in self.M_CODES[code].words:
                st.words.pop(letter, None)
        if Group.NON_MODAL in st.g and round(st.g[Group.NON_MODAL].value, 4) == 4:
            g = st.g.pop(Group.NON_MODAL)
            p = words.pop("P", None)
            if p is None or p.value < 0:
                raise self.error(line, g.col, "G4 needs a dwell time P of 0 or more (seconds)")

    def check_m(self, st: Step, ms: list[Word]) -> None:
        keep = []
        for m in ms:
            code = int(m.value) if m.value == int(m.value) else None
            if code in REFUSED_M:
                raise self.error(st.block.line, m.col, f"M{m.raw} ({REFUSED_M[code]}) is not simulated")
            if code in (70, 71, 72, 73):
                if self.context_m:
                    raise self.error(st.block.line, m.col, f"M{m.raw} and M{self.context_m[0][0]}: two M codes of "
                                     "one modal group in a block")
                self.context_m.append((code, m))
                continue
            if code is not None and 100 <= code <= 199 and code in self.cfg.m_functions:
                continue
            keep.append(m)
        groups: dict[Group, Word] = {}
        for m in keep:
            row = self.M_CODES.get(int(m.value)) if m.value == int(m.value) else None
            if row is not None and row.group in groups:
                raise self.error(st.block.line, m.col, f"M{m.raw} and M{groups[row.group].raw}: two M codes of one "
                                 "modal group in a block")
            if row is not None:
                groups[row.group] = m
        super().check_m(st, keep)

    def tool_m(self, st: Step) -> None:
        for code, m in self.m_group(st, Group.TOOL):
            if code == 61:
                q = st.words.pop("Q", None)
                if q is None:
                    raise self.error(st.block.line, m.col, "M61 needs the tool number Q")
                self.selected = self.whole(st.block.line, q, "tool number")
            if code == 6:
                compensation.tool_change(self, st, m)
            if code == 6 and self.spindle_dir != 0:  # LinuxCNC stops the spindle for a tool change
                self.spindle(self.src(st, m.col), 0, None)
            self.known_tool(st, self.selected, m)
            self.tool_no = self.selected
            entry = self.tools.get(self.tool_no, {})
            length = [entry.get("X", 0.0), 0.0, entry.get("Z", 0.0)]
            self.moved(tuple(self.pos[i] - length[i] + self.tool_len[i] for i in range(3)))  # the new tip
            self.tool_len = length
            self.tool(self.src(st, m.col), self.tool_no, None)

    def known_tool(self, st: Step, number: int, w: Word) -> None:
        """A tool loaded (M6, M61) must be in the tool table (the setup's .tbl, else its [[tool]]s),
        as LinuxCNC refuses a tool it does not know; tool 0 is the empty spindle."""
        if number != 0 and number not in self.tools and number not in self.cfg.tool_radii:
            raise self.error(st.block.line, w.col, f"requested tool {number} not found in the tool table")

    def convert_nonmodal(self, st: Step) -> None:
        g = st.g.get(Group.NON_MODAL)
        if g is not None and round(g.value, 4) != 53:
            offsets.nonmodal(self, st, round(g.value, 4), g)

    def convert_feed(self, st: Step) -> None:
        pass

    # -- motion ------------------------------------------------------------------------------------
    def feed_for(self, st: Step, length: float) -> float:
        """The feed (mm/min or mm/rev) of a cutting move ``length`` mm long; refused without F. In G93
        F over the move's time: length x F, and at least 0.1 program units per minute as in LinuxCNC."""
        if self.feed_mode == 93:
            if self.feed_units is None or self.feed_units == 0.0:
                raise self.error(st.block.line, 1, "inverse time feed (G93): every feed move needs its own F")
            f, self.feed_units = self.feed_units, None
            self.inverse_feed = max(0.1 * self.scale, length * f)  # LinuxCNC: at least 0.1 program units per minute
            return self.inverse_feed
        if self.feed_units is None or self.feed_units == 0.0:
            raise self.error(st.block.line, 1, "cannot feed with a zero feed rate (program F)")
        return self.feed_units * self.feed_scale

    def convert_motion(self, st: Step) -> None:
        line = st.block.line
        g53 = st.g.get(Group.NON_MODAL)
        if g53 is not None and round(g53.value, 4) == 53:
            if self.motion not in (0, 1) or not self.absolute:
                raise self.error(line, g53.col, "G53 needs G0 or G1 and G90")
            compensation.refuse(self, st, g53, "G53: cannot move in machine coordinates")
        if polar.present(st) and self.motion not in cycles.CYCLE_CODES:
            polar.as_xy(self, st, *polar.take(self, st))
        has_axes = (any(a in st.words for a in "XYZ@^")
                    or (self.motion in (2, 3) and any(a in st.words for a in "IJK")))
        if self.profile is not None:
            lathe.check_profile(self, st, has_axes)
        if any(a in st.words for a in "ABCUVW"):
            a = next(st.words[a] for a in "ABCUVW" if a in st.words)
            raise self.error(line, a.col, f"axis {a.letter} is not simulated (the simulator has X, Y and Z)")
        m = self.motion
        if self.plane in UVW_PLANES and has_axes and (m in (2, 3) or m in cycles.CYCLE_CODES):
            cycles.refuse_uvw(self, st, m)
        if m not in cycles.CYCLE_CODES:
            self.cycle.initial = self.cycle.code = None
        if self.comp_side and ((has_axes and m not in (0, 1, 2, 3, 80, *probe.PROBES)) or (m in lathe.LATHE_CYCLES and st.motion == m)):
            compensation.refuse_motion(self, st, m)
        if m in lathe.LATHE_CYCLES and st.motion == m:
            lathe.cycle(self, st)
        elif m in cycles.CYCLE_CODES and has_axes:
            cycles.run(self, st)
        elif not has_axes:
            if st.motion not in (None, 0, 1, 80) and Group.NON_MODAL not in st.g:
                raise self.error(line, st.groups[MOTION].col, f"G{st.groups[MOTION].raw}: all axes missing")
            self.check_left(st)
            return
        elif m in probe.PROBES:
            probe.run(self, st)
        elif m == 80:
            w = next(st.words[a] for a in "XYZ" if a in st.words)
            raise self.error(line, w.col, "axis words without a motion mode (G80 is active)")
        elif m in (0, 1):
            end, _ = self.goal(st, machine=g53 is not None and round(g53.value, 4) == 53)
            if m == 0:
                self.rapid(self.src(st), end)
            else:
                self.linear_to(st, end)
        elif m in (2, 3):
            self.arc_block(st, m == 2)
        elif m == 33:
            threading.g33(self, st)
        elif m == 76:
            threading.g76(self, st)
        elif m == 33.1:
            threading.g33_1(self, st)
        self.check_left(st)

    # -- a profile collects its moves instead of cutting them (lathe.capture) -----------------------
    def rapid(self, src: Src, end) -> None:
        _ = super().rapid(src, end) if self.profile is None else self.collect(end, None, False)

    def linear(self, src: Src, end) -> None:
        _ = super().linear(src, end) if self.profile is None else self.collect(end, None, False)

    def arc(self, src: Src, end, center, clockwise: bool) -> None:
        _ = super().arc(src, end, center, clockwise) if self.profile is None else self.collect(end, center, clockwise)

    def collect(self, end, center, clockwise: bool) -> None:
        self.profile.append((self.start_point(), tuple(end), None if center is None else tuple(center), clockwise))
        self.moved(end)

    def check_left(self, st: Step) -> None:
        """A word the block did not use is refused at its column (LinuxCNC: "... word with no G code
        that uses it"), so no value is silently ignored."""
        for letter, w in st.words.items():
            if letter in "NO" or orient.used(self, w):
                continue
            raise self.error(st.block.line, w.col, f"{letter} word with nothing that uses it in this block")

    def linear_to(self, st: Step, end) -> None:
        if self.profile is None:
            self.feed = self.feed_for(st, math.dist(self.pos, end))
        self.linear(self.src(st), end)

    def arc_block(self, st: Step, clockwise: bool) -> None:
        line = st.block.line
        a, b, n = PLANE_AXES[self.plane]
        start = self.start_point()
        end, words = self.goal(st)
        letters = {0: "I", 1: "J", 2: "K"}
        p = st.words.pop("P", None)
        turns = 1 if p is None else self.whole(line, p, "arc turns P")
        if turns < 1:
            raise self.error(line, p.col, "P (turns) must be 1 or more")
        if letters[n] in st.words:
            w = st.words[letters[n]]
            raise self.error(line, w.col, f"{w.letter} is not in the plane {self.plane} of the arc")
        r = st.words.pop("R", None)
        if r is not None:
            if letters[a] in st.words or letters[b] in st.words:
                raise self.error(line, r.col, "an arc takes either R or I/J/K, not both")
            centre = cycles.radius_centre(self, st, start, end, r.value * self.scale, clockwise, r.col)
        else:
            if letters[a] not in st.words and letters[b] not in st.words:
                raise self.error(line, st.groups.get(MOTION, Word("G", 2, "2", 1)).col,
                                 f"arc needs its centre ({letters[a]}/{letters[b]}) or its radius R")
            centre = list(start)
            for i in (a, b):
                w = st.words.pop(letters[i], None)
                if self.arc_abs:
                    centre[i] = (w.value * self.scale + self.shift(i)) if w is not None else self.shift(i)
                elif w is not None:
                    centre[i] = start[i] + w.value * self.scale
            cycles.check_radii(self, line, start, end, centre, a, b)
        if self.profile is not None and turns != 1:
            raise self.error(line, p.col, "an arc of more than one turn in a G70-G72 profile is not simulated")
        if self.profile is None:
            self.feed = self.feed_for(st, cycles.arc_length(self, start, end, centre, clockwise, turns))
        if self.profile is not None or not compensation.arc_taken(self, st, start, end, centre, clockwise, turns):
            cycles.arc_turns(self, self.src(st), start, end, centre, clockwise, turns)

    def convert_end(self, st: Step) -> None:
        st.result = any(code in (2, 30, 60) and code != 60 for code, _ in self.m_group(st, Group.STOP))
        if st.result:
            compensation.finish(self, st)
            self.comp_side, self.comp_exit = 0, None
            self.end(self.src(st))
