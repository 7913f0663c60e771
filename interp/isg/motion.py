"""ISG motions: the path (G0/G1/G2/G3 through the frame and the compensation), circles by centre
(G161/G162) or radius R, in turned frames, G33 threads with their lead on I/J/K and tapping on a
lathe's spindle axis (G331/G332)."""
from __future__ import annotations

from .reader import IsgBlock
from .tables import LEADS, MIN_LEAD
from ..canon import Src
from ..core import FullCircle, Group, RadiusTooSmall, Step, radius_centre
from ..core.lexer import Word
from ..core.modal import AXES, PLANE_AXES

class Motion:
    """The motions of Isg (a part of it). State: ``lead`` ((mm/rev, axis letter) of G33), ``offset``
    (S.OFFSET, degrees), ``circle_r`` (R, modal) with ``r_col`` (the column of the block's R word,
    1 without one), ``centre_abs`` (G161) and ``tapped`` (where the last G331/G332 left the tap and
    the spindle) with ``tap_pitch`` (G331's signed K)."""

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.lead: tuple[float, str] | None = None
        self.offset = 0.0
        self.circle_r: float | None = None
        self.r_col = 1
        self.centre_abs = False
        self.tapped: tuple | None = None  # the last G331/G332: (end point, signed pitch, direction, end angle)
        self.tap_pitch: float | None = None  # G331's K, signed (modal)

    def convert_motion(self, st: Step) -> None:
        g = st.g.get(Group.RADIUS_COMP)
        if g is not None:
            self.radius_comp(st, g)
        if self.comp_buf is not None and self.plane != self.comp_plane:
            raise self.error(st.block.line, 1, f"plane changed to {self.plane} while tool radius compensation is active "
                             f"in {self.comp_plane}: not modelled by the simulator")
        before = tuple(self.pos)
        self.convert_path(st)
        if self.comp_off and self.comp_buf is not None:
            a, c, _ = PLANE_AXES[self.comp_plane]
            if self.pos[a] != before[a] or self.pos[c] != before[c]:
                self.flush_comp(departure=True)

    def convert_path(self, st: Step) -> None:
        b, src, words, motion = st.block, st.src, st.words, st.motion
        self.extra_axes(st)
        if self.turned and self.rotation is not None and self.rotation[1] != self.plane:
            self.rotation = None  # manual: a change of plane deselects the contour rotation, with a warning
            self.warn(src, "the change of plane deselects the contour rotation (#ROTATION)")
            self.frame_changed(b.line, 1)
        self.r_col = words["R"].col if "R" in words else 1  # errors of a modal R name this block's R, else the block
        if "R" in words:  # circle radius, modal (manual: "Radius programming (R, G163)")
            w = words.pop("R")
            if w.value == 0:
                raise self.error(b.line, w.col, "circle radius R must not be 0")
            self.circle_r = w.value
        axis_words = {AXES.index(a): words.pop(a) for a in AXES if a in words}
        values = {i: w.value for i, w in axis_words.items()}
        cols = {i: w.col for i, w in axis_words.items()}
        centre = {a: words.pop(a) for a in "IJK" if a in words}
        if axis_words and self.motion not in (331, 332):
            self.tapped = None  # another move: the spindle no longer follows the tap
        if self.motion in (331, 332):
            self.tap_block(st, centre, values, cols)
        elif self.motion == 33:
            if self.turned:
                raise self.error(b.line, 1, "G33 in rotated or mirrored coordinates is not modelled by the simulator")
            self.thread_block(b, src, centre, values, cols)
        elif self.motion in (2, 3) and (axis_words or motion in (2, 3)):
            self.circle(b, src, centre, values, cols)
        elif axis_words or motion is not None:  # G00/G01
            if centre:
                self.check_words(b.line, centre, "IJK", self.motion)
            if axis_words:
                end = self.target(values)
                self.check_position(b.line, end, cols)
                (self.rapid if self.motion == 0 else self.linear)(src, end)
        else:
            for a, w in centre.items():
                raise self.error(b.line, w.col, f"address {a} has no meaning in a block without a motion")

    def thread_block(self, b: IsgBlock, src: Src, leads: dict[str, Word], values: dict[int, float],
                     cols: dict[int, int]) -> None:
        if len(leads) > 1:
            a, w = list(leads.items())[1]
            raise self.error(b.line, w.col, f"two leads ({' and '.join(leads)}) in one G33 block: "
                             "program the lead on one of I, J, K")
        for a, w in leads.items():
            if w.raw.lstrip("+").startswith(("-", "\u2212")):
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} is programmed without a sign")
            if w.value == 0:
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} must not be zero when G33 is selected")
            if w.value < MIN_LEAD:
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} is below the programming resolution, "
                                 f"{MIN_LEAD} mm per revolution")
            self.lead = (w.value, LEADS[a])
        if self.lead is None:
            col = b.words[0].col if b.words else 1
            for w in b.words:
                if w.letter == "G" and w.value == 33:
                    col = w.col
            raise self.error(b.line, col, "G33 without a lead: program it without sign on I, J or K "
                             "(mm per revolution along X, Y or Z), e.g. 'G33 Z48 K1.5'")
        if not values:
            return
        end = self.target(values)
        self.check_position(b.line, end, cols)
        lead, axis = self.lead
        self.synced(src, end, lead, axis, self.offset)

    def tap_block(self, st: Step, leads: dict[str, Word], values: dict[int, float], cols: dict[int, int]) -> None:
        """G331 Z.. K.. taps along Z on a lathe: the spindle follows the feed, K > 0 a right-hand thread
        (turning as under M03), K < 0 a left-hand one. G332 Z.. [K..] backs the tap out with the spindle
        reversed, along the helix the G331 before it cut (TwinCAT CNC turning functions, "Tapping
        (G331/G332)"). The first G331 meets the workpiece at the spindle's zero pulse, as a G33 does; a
        G331 or G332 continuing from where the last one stopped keeps its helix."""
        b, code = st.block, self.motion
        gcol = next((w.col for w in b.words if w.letter == "G" and w.value == code), 0)
        if self.cfg.machine_kind != "lathe":
            raise self.error(b.line, gcol or 1, f"G{code} on a mill is not modelled by the simulator (a tap is a lathe tool: "
                             "on a lathe it taps along Z at X0)")
        for c, m in st.m if values or gcol > 1 else ():
            if c in (3, 4, 5, 19):
                raise self.error(b.line, m.col, f"M{m.raw} cannot be programmed with G331/G332: the spindle follows the tap")
        for a, w in leads.items():
            if a != "K":
                raise self.error(b.line, w.col, f"the pitch of G{code} is programmed on K (along Z), not on {a}")
        pitch = leads["K"] if "K" in leads else None
        if pitch is not None and pitch.value == 0:
            raise self.error(b.line, pitch.col, f"the pitch K{pitch.raw} must not be zero")
        for i in (0, 1):
            if i in values and self.target(values)[i] != self.pos[i]:
                raise self.error(b.line, cols[i], f"G{code} taps along Z: {'XY'[i]} must stay where it is")
        if code == 332:
            return self.tap_back(st, gcol, pitch, values)
        if pitch is not None:
            self.tap_pitch = pitch.value
        if self.tap_pitch is None:
            raise self.error(b.line, gcol or 1, "G331 without a pitch: program it on K, signed (K1.5 a right-hand thread, "
                             "K-1.5 a left-hand one)")
        if not values:
            return
        k = self.tap_pitch
        direction = 1 if k > 0 else -1
        t = self.tapped
        start = t[3] if t is not None and t[0] == tuple(self.pos) and t[1] == k and t[2] == direction else 0.0
        self.tap_move(st.src, self.target(values), k, direction, start)

    def tap_back(self, st: Step, gcol: int, pitch: Word | None, values: dict[int, float]) -> None:
        """G332: the reverse of the G331 (or G332) that left the tap here, on its helix; the spindle
        stands when it is done."""
        t, b = self.tapped, st.block
        if t is None or t[0] != tuple(self.pos):
            raise self.error(b.line, gcol or 1, "G332 backs out the tap from where a G331 stopped: program it right after "
                             "the G331, from its end point")
        if pitch is not None and abs(pitch.value) != abs(t[1]):
            raise self.error(b.line, pitch.col, f"G332 with the pitch K{pitch.raw}: it must be the G331's, {abs(t[1]):g}")
        if not values:
            return
        self.tap_move(st.src, self.target(values), t[1], -t[2], (-t[3]) % 360.0)
        self.spindle(st.src, 0, None)

    def tap_move(self, src: Src, end, k: float, direction: int, start: float) -> None:
        """One spindle-synchronised move along Z at pitch |k|, the spindle turning ``direction``,
        starting ``start`` degrees past the zero pulse; remembers where it leaves tap and spindle
        (the angle turned since the zero pulse, in the direction of rotation)."""
        self.check_position(src.line, end)
        z0 = self.pos[2]
        self.spindle(src, direction, None)
        self.synced(src, end, abs(k), "Z", start)
        self.tapped = (tuple(self.pos), k, direction, (start + 360.0 * abs(end[2] - z0) / abs(k)) % 360.0)

    def circle(self, b: IsgBlock, src: Src, words: dict[str, Word], values: dict[int, float],
               cols: dict[int, int]) -> None:
        if self.turned:
            return self.turned_circle(b, src, words, values, cols)
        if self.centre_abs:  # G161: I/J/K are absolute centre coordinates -> relative to the start
            sh = self.shift()
            words = {a: Word(a, w.value + sh["IJK".index(a)] - self.pos["IJK".index(a)], w.raw, w.col)
                     for a, w in words.items()}
            if self.diameter and "I" in words:
                w = words["I"]
                words["I"] = Word("I", w.value / 2.0, w.raw, w.col)
        end = self.target(values)
        self.check_position(b.line, end, cols)
        a, c, _ = PLANE_AXES[self.plane]
        if not words and self.circle_r is not None:
            centre = self.radius_centre(b.line, end, self.motion == 2)
        else:
            centre = self.centre_words(b.line, words, ", relative to the start; or its radius R")
        self.arc(src, end, centre, self.motion == 2)

    def turned_circle(self, b: IsgBlock, src: Src, words: dict[str, Word], values: dict[int, float],
                      cols: dict[int, int]) -> None:
        """A circle in rotated or mirrored coordinates: its centre offsets turn with the frame; a mirrored
        plane reverses its direction (G02 <-> G03). The plane must map onto itself."""
        f = self.program_frame()
        L = f.L
        a, c, n = PLANE_AXES[self.plane]
        if abs(abs(L[n][n]) - 1.0) > 1e-12:
            raise self.error(b.line, 1, f"a circle in the plane {self.plane} under a coordinate system rotated about Z "
                             "lies in a tilted plane: not modelled by the simulator (program it in G17)")
        if self.centre_abs:  # G161: absolute centre coordinates of the program frame -> relative to the start
            p = f.inverse_apply(self.pos)
            words = {k: Word(k, w.value - p["IJK".index(k)], w.raw, w.col) for k, w in words.items()}
        end = self.target(values)
        self.check_position(b.line, end, cols)
        cw = self.motion == 2
        if f.plane_flips(a, c):
            cw = not cw
        if not words and self.circle_r is not None:
            centre = self.radius_centre(b.line, end, cw)
        else:
            prog_centre = self.centre_words(b.line, words, ", relative to the start; or its radius R")
            d = f.linear(tuple(prog_centre[i] - self.pos[i] for i in range(3)))
            centre = (self.pos[0] + d[0], self.pos[1] + d[1], self.pos[2] + d[2])
        self.arc(src, end, centre, cw)

    def radius_centre(self, line: int, end, cw: bool):
        """The centre of a circle given by its radius R (modal): the shorter arc for R > 0, the
        longer one for R < 0 (manual: "Radius programming (R, G163)"); the chord in the plane."""
        r, col = self.circle_r, self.r_col
        try:
            return radius_centre(self.pos, end, r, self.plane, cw, self.diameter)
        except FullCircle:
            raise self.error(line, col, "a full circle cannot be programmed with its radius R (start and end point "
                             "coincide): program its centre with I, J, K") from None
        except RadiusTooSmall as e:
            raise self.error(line, col, f"circle radius R{abs(r):g} is too small for the distance {e.chord:.4f} between "
                             "the start and the end point") from None
