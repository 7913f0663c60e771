"""ISG motions: the path (G0/G1/G2/G3 through the frame and the compensation), circles by centre
(G161/G162) or radius R, in turned frames, and G33 threads with their lead on I/J/K."""
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
    1 without one) and ``centre_abs`` (G161)."""

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.lead: tuple[float, str] | None = None
        self.offset = 0.0
        self.circle_r: float | None = None
        self.r_col = 1
        self.centre_abs = False

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
        if self.motion == 33:
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
