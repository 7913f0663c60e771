"""Polar coordinates ``@`` (distance) and ``^`` (angle, degrees counter-clockwise from +X) in place
of X and Y, as LinuxCNC 2.9 reads them: from the program's XY zero; in G91 added to the current
point's own distance and angle; a missing one is the current point's. Always X and Y, with G17
in effect before the block (as rs274 2.9 checks it); never with X or Y words.
A canned cycle's L repeats in G91 turn and step again each time (a bolt circle by ``^60 L6``)."""
from __future__ import annotations

import math

from cutsim.interp.core import Step
from cutsim.interp.core.lexer import Word


def present(st: Step) -> bool:
    return "@" in st.words or "^" in st.words


def take(m, st: Step) -> tuple:
    """Pop the block's @ and ^ (checked): (distance word, angle word)."""
    dist, ang = st.words.pop("@", None), st.words.pop("^", None)
    w = dist or ang
    if "X" in st.words or "Y" in st.words:
        raise m.error(st.block.line, w.col, "polar coordinates (@ ^) and X or Y in one block")
    if m.block_plane != "XY":  # rs274 2.9 checks the plane in effect before the block
        raise m.error(st.block.line, w.col, "polar coordinates (@ ^) need G17 in effect before the block")
    return dist, ang


def target(m, line: int, dist, ang) -> tuple[float, float]:
    """The point (program units) the polar words name from where the tool is; at the XY origin (no
    angle to go on from) G91 is refused, and G90 without ^ (rs274 2.9 alike)."""
    x, y = m.program_value(0), m.program_value(1)
    if abs(x) < 1e-9 and abs(y) < 1e-9 and (not m.absolute or ang is None):
        raise m.error(line, (dist or ang).col,
                      "polar coordinates at the XY origin: G91 has no angle to go on from, G90 needs ^")
    r, a = math.hypot(x, y), math.degrees(math.atan2(y, x))
    if m.absolute:
        r = dist.value if dist is not None else r
        a = ang.value if ang is not None else a
    else:
        r += dist.value if dist is not None else 0.0
        if ang is not None and r == 0.0:  # the @ step reached the origin: rs274 then finds no angle to turn
            raise m.error(line, ang.col, "polar coordinates at the XY origin: G91 has no angle to go on from "
                          "(the @ increment reached it)")
        a += ang.value if ang is not None else 0.0
    return r * math.cos(math.radians(a)), r * math.sin(math.radians(a))


def as_xy(m, st: Step, dist, ang) -> None:
    """The block's X and Y words for the polar point (increments in G91)."""
    x, y = target(m, st.block.line, dist, ang)
    if not m.absolute:
        x, y = x - m.program_value(0), y - m.program_value(1)
    col = (dist or ang).col
    st.words["X"] = Word("X", x, f"{x:g}", col)
    st.words["Y"] = Word("Y", y, f"{y:g}", col)
