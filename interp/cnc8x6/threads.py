"""CNC8x6 G33 threads: the lead, start angle, runout J and lead-in E with their angle from machine
constant 8 or the R parameter it names, and the rule on the blocks after a ramped thread."""
from __future__ import annotations

import math

from ..canon import Ramp, Src
from ..core.lexer import Block, Word
from ..core.modal import AXES
from .language import MAX_DIRECT_LEAD, MIN_LEAD, RESERVED_PARAMS, decode_angle_code


class Threads:
    """G33 of Cnc8x6 (a part of it). State: ``lead`` (the modal lead, mm/rev) and ``after_ramp``
    ((G33 src, 1 = expect an empty block, 2 = expect every axis) after a ramped thread)."""

    lead: float | None
    after_ramp: tuple[Src, int] | None

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.lead = None
        self.after_ramp = None

    def ramp_unfinished(self) -> None:
        """At the end of the file: a ramped thread must have been followed by an empty block."""
        if self.after_ramp is not None and self.after_ramp[1] == 1:
            src = self.after_ramp[0]
            raise self.error(src.line, src.col, "a thread with runout or lead-in must be followed by an empty block")

    def ramp_rule(self, b: Block) -> bool:
        """After a thread with runout or lead-in: an empty block, then one with every axis. True
        for the empty block (nothing else to do)."""
        if self.after_ramp is None:
            return False
        g33src, stage = self.after_ramp
        if stage == 1:
            if not b.empty:
                raise self.error(b.line, 1, f"line {g33src.line} cuts a thread with runout or lead-in: "
                                 "the next block must be empty")
            self.after_ramp = (g33src, 2)
            return True
        missing = [a for a in self.machine_axes() if not b.find(a)]
        if missing:
            raise self.error(b.line, 1, f"after the empty block that follows the thread at line {g33src.line}, "
                             f"this block must program every axis (missing {', '.join(missing)})")
        self.after_ramp = None
        return False

    # -- G33 -------------------------------------------------------------------------------------
    def thread(self, b: Block, src: Src, words: dict[str, Word], axis_words: dict[int, Word]) -> None:
        if "F" in words:
            f = words.pop("F")
            if f.param is None and f.value > MAX_DIRECT_LEAD:
                raise self.error(b.line, f.col, f"lead F{f.raw} exceeds {MAX_DIRECT_LEAD} mm/rev; "
                                 "program a larger lead through a parameter (FR10)")
            if f.value <= 0:
                raise self.error(b.line, f.col, "the lead F of G33 must be greater than zero")
            if f.value < MIN_LEAD:
                raise self.error(b.line, f.col, f"the lead F{f.raw} of G33 is below the smallest lead, {MIN_LEAD} mm/rev")
            self.lead = f.value
        if self.lead is None:
            raise self.error(b.line, 1, "G33 without a lead: program F (mm/rev)")
        if not axis_words:
            raise self.error(b.line, 1, "G33 needs an end point")
        angle = 0.0
        if "I" in words:
            iw = words.pop("I")
            if not 0.0 <= iw.value <= 360.0:
                raise self.error(b.line, iw.col, f"start angle I{iw.raw} is outside 0..360 degrees")
            angle = iw.value
        end = self.target({i: w.value for i, w in axis_words.items()})
        self.check_position(b.line, end, {i: w.col for i, w in axis_words.items()})
        runout = leadin = None
        if "J" in words:
            jw = words.pop("J")
            if jw.value < 0:
                raise self.error(b.line, jw.col, "runout length J is always positive")
            if jw.value > 0:
                runout = self.ramp(b, jw, "runout", jw.value)
        if "E" in words:
            ew = words.pop("E")
            if ew.param is None and "." not in ew.raw:
                raise self.error(b.line, ew.col, f"lead-in E{ew.raw} must be written with a decimal point "
                                 f"(E{ew.raw}. or E{ew.raw}.0)")
            if ew.value < 0:
                raise self.error(b.line, ew.col, "lead-in length E must be positive")
            if ew.value > 0:
                leadin = self.ramp(b, ew, "lead-in", ew.value)
        self.check_words(b.line, words, "KLQ", 33)
        if leadin or runout:
            travel = self.thread_travel(end)
            total = (leadin.length if leadin else 0.0) + (runout.length if runout else 0.0)
            if total > travel + 1e-9:
                raise self.error(b.line, 1, f"lead-in and runout ({total:g} mm) are longer than the thread ({travel:g} mm)")
            self.after_ramp = (src, 1)
        if leadin is not None:
            end = self.leadin_end(b, src, end, axis_words, ew, leadin)
        self.synced(src, end, self.lead, None, angle, leadin, runout)
        self.check_position(b.line, self.pos)

    def leadin_end(self, b: Block, src: Src, end, axis_words: dict[int, Word], ew: Word, leadin: Ramp):
        """The record's end for a thread with a lead-in (canon.SyncedFeed: the tool follows the line
        start -> end with the ramps added, so it stops at end + ramp displacements).

        The lead-in ramps from the start point over the first E mm (seed 000, 5.3: the tool starts
        outside, at the value from which the lead-in reaches the thread). The lead-in axis left
        out of the block keeps that value: a straight thread at start + ramp (the manual's
        example). Programmed, it is where the thread ends, like every G33 end point; the thread
        then tapers from where the lead-in would have put a straight one, which is warned about
        unless the value is that straight thread's.
        """
        i = "XYZ".index(leadin.axis)
        scale = 2.0 if (i == 0 and self.diameter) else 1.0
        shift = leadin.displacement * scale  # program units
        if i not in axis_words:
            return end
        straight = self.pos[i] + shift
        if abs(end[i] - straight) > 1e-6:
            w = axis_words[i]
            on = " on the diameter" if scale == 2.0 else ""
            self.warn(src, f"G33 with lead-in E{ew.raw} and {leadin.axis}{w.raw} programmed: the thread ends at "
                           f"{leadin.axis}{end[i]:g} and the lead-in comes in from the start {leadin.axis}{self.pos[i]:g} "
                           f"by {abs(shift):.4g}{on} ({leadin.length:g}*tan {leadin.angle:g} deg) relative to the thread, "
                           f"so the thread tapers; leave {leadin.axis} out (or program {leadin.axis}{straight:.4f}) "
                           "for the manual's straight thread after the lead-in")
        out = list(end)
        out[i] -= shift
        return (out[0], out[1], out[2])

    def thread_travel(self, end) -> float:
        dx = abs(end[0] - self.pos[0]) / (2.0 if self.diameter else 1.0)
        return max(dx, abs(end[1] - self.pos[1]), abs(end[2] - self.pos[2]))

    def ramp(self, b: Block, w: Word, what: str, length: float) -> Ramp:
        """Angle and axis of a runout or lead-in from machine constant 8 or the parameter it names."""
        const = self.cfg.constants.get(8)
        if const is None:
            raise self.error(b.line, w.col, f"{what} needs its angle: set machine constant 8 ([machine.constants] 8 = ...)")
        if not (math.isfinite(const) and abs(const) < 1e8):
            raise self.error(b.line, w.col, f"machine constant 8 = {const} has more than eight decades")
        code = f"{abs(int(const)):08d}"
        if len(code) > 8:
            raise self.error(b.line, w.col, f"machine constant 8 = {const} has more than eight decades")
        if code[:2] == "00":  # angle mode: one angle and axis for runout and lead-in
            sign = -1 if const < 0 else 1
            axis, angle = int(code[2]), int(code[3:]) / 1000.0
            origin = f"machine constant 8 = {int(const)}"
        else:
            pnum = int(code[:2]) if what == "runout" else int(code[2:4])
            if pnum == 0:
                raise self.error(b.line, w.col, f"machine constant 8 = {int(const)} names no {what} parameter")
            if pnum in RESERVED_PARAMS:
                raise self.error(b.line, w.col, f"machine constant 8 names the reserved parameter R{pnum:02d}")
            if pnum not in self.params:
                raise self.error(b.line, w.col, f"the {what} angle parameter R{pnum:02d} (machine constant 8) is not set")
            try:
                sign, axis, angle = decode_angle_code(self.params[pnum])
            except ValueError:
                raise self.error(b.line, w.col, f"R{pnum:02d} = {self.params[pnum]} is not an angle code") from None
            origin = f"R{pnum:02d} = {self.params[pnum]:g}"
        if axis not in (1, 2, 3):
            raise self.error(b.line, w.col, f"{what} axis {axis} from {origin} is not 1 (X), 2 (Y) or 3 (Z)")
        if not 0.0 <= angle <= 60.0:
            raise self.error(b.line, w.col, f"{what} angle {angle:.3f} degrees from {origin} is outside 0..60")
        # + means the runout moves towards + on its axis; the lead-in comes from that side
        direction = sign if what == "runout" else -sign
        return Ramp(length, angle, AXES[axis - 1], direction)
