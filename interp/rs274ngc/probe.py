"""G38.2-G38.5 straight probing, simulated without contact (the probe never trips).

The probe move is a feed to the programmed point (it cuts like G1 where it meets stock). Then, as
LinuxCNC's standalone interpreter (``rs274``) goes on: #5061-#5063 hold the programmed point (program
units, the coordinate system in effect, X a radius in G7), #5064-#5069 are 0, #5070 is 0 (no
contact), and the tool stands 0.01 in (0.254 mm) back along the move from that point, without a move
there. G38.2 and G38.4 (which signal an error when the probe does not trip) behave the same way, as
rs274 runs them; a probe move of zero length is refused for G38.2 and G38.4 only (rs274:
"Start point too close to probe point"). The feed is the feed rate rs274 keeps (``canon_feed``):
in G93 the last one an F in G94 or an inverse-time move set; feed per revolution is refused.
"""
from __future__ import annotations

import math

from cutsim.interp.core import MOTION, Step

PROBES = (38.2, 38.3, 38.4, 38.5)
BACKOFF = 0.254  # mm (0.01 in): where rs274 leaves the tool, back along the probe move
FIRST, LAST = 5061, 5070  # the probe's result parameters (#5070: 1 after contact)


def init(m) -> None:
    m.inverse_feed = 0.0  # in G93 the feed rate rs274 keeps (mm/min): a probe's
    m.warned_probe = False


def canon_feed(m) -> float:
    """The feed rate (mm/min) a probe move takes: the one of G1 in G94; in G93 the rate rs274 keeps
    from before (0 after a G94 or G95 left G93)."""
    if m.feed_mode == 93:
        return m.inverse_feed
    return (m.feed_units or 0.0) * m.feed_scale


def leave_mode(m, code: float) -> None:
    """A feed mode code: G93 keeps the last G94 rate as its probe feed; leaving G93 clears it."""
    if code == 93 and m.feed_mode != 93:
        m.inverse_feed = (m.feed_units or 0.0) * m.feed_scale
    elif code != 93:
        m.inverse_feed = 0.0


def run(m, st: Step) -> None:
    line = st.block.line
    w = st.groups.get(MOTION) or next(st.words[a] for a in "XYZ@^" if a in st.words)
    name = f"G{m.motion:g}"
    if m.comp_side:
        raise m.error(line, w.col, f"{name}: cannot probe with cutter radius compensation on (G40 first)")
    feed = canon_feed(m)
    if feed == 0.0:
        raise m.error(line, w.col, f"{name}: cannot probe with a zero feed rate (program F; in G93 the probe "
                      "takes the feed rate in effect before it)")
    if m.feed_mode == 95:
        raise m.error(line, w.col, f"{name}: cannot probe in feed per revolution mode (G95)")
    start = m.start_point()
    end, _ = m.goal(st)
    if end == start and m.motion in (38.2, 38.4):
        raise m.error(line, w.col, f"{name}: the probe move has zero length (start point too close to probe point)")
    if not m.warned_probe:
        m.warn(m.src(st, w.col), f"{name}: probing is simulated without contact (the probe never trips): a feed to "
               "the programmed point, #5070 reads 0 and the tool then stands 0.254 mm (0.01 in) back along the "
               "move without moving there, as LinuxCNC's standalone interpreter goes on")
        m.warned_probe = True
    m.feed = feed
    m.linear(m.src(st), end)
    for i in range(3):
        m.params.numbered[FIRST + i] = (end[i] - m.shift(i)) / m.scale
    for n in range(FIRST + 3, LAST + 1):
        m.params.numbered[n] = 0.0
    length = math.dist(start, end)
    if length > 0.0:
        m.moved(tuple(end[i] - BACKOFF * (end[i] - start[i]) / length for i in range(3)))
