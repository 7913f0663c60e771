"""M70-M73: the modal state saved and restored, as LinuxCNC 2.9 does it (move for move the same as
rs274, docs/dialects/rs274ngc.md).

M70 saves the state at the current call level, M72 restores it (the saved copy stays), M71
invalidates it, M73 saves it to be restored when the subroutine returns (endsub or return). The state:
units, plane, distance and arc distance modes, feed mode and F, S and the spindle's direction, G96/G97,
the coordinate system, the retract mode, G7/G8; whether G92 offsets apply (#5210: cleared as by
G92.2, or the stored ones applied again as by G92.3; changed values stay); a saved G49 clears the
tool length offset, a saved G43 over a G49 applies the loaded tool's (G43.1, G43.2 are neither
saved nor undone: measured with rs274).
"""
from __future__ import annotations

from cutsim.interp.errors import CutsimError

from . import offsets

FIELDS = ("scale", "plane", "absolute", "arc_abs", "feed_mode", "per_rev", "feed_units", "retract_old",
          "lathe_diameter", "surface_speed")


def level(m) -> int:
    return len(m.params.frames)


def run_block(m, st) -> None:
    """The block's M70-M73 (collected in m.context_m), then none."""
    for code, w in m.context_m:
        if code in (70, 73):
            save(m, code == 73)
        elif code == 72:
            restore(m, m.src(st, w.col), st.block.line, w.col)
        else:
            invalidate(m)
    m.context_m = []


def save(m, auto: bool) -> None:
    state = {f: getattr(m, f) for f in FIELDS}
    state.update(coord=m.coord, tlo_mode=m.tlo_mode, speed=m.speed, spindle_dir=m.spindle_dir, auto=auto,
                 g92_on=m.params.numbered.get(5210, 0.0) != 0.0)
    m.contexts[level(m)] = state


def restore(m, src, line: int, col: int) -> None:
    state = m.contexts.get(level(m))
    if state is None:
        raise CutsimError(m.name, line, col, "cannot restore the modal state: no M70 or M73 at this call level")
    apply(m, src, state)


def invalidate(m) -> None:
    m.contexts.pop(level(m), None)


def returned(m, src) -> None:
    """A subroutine returns: an M73 state of its level is restored; its level's state goes."""
    state = m.contexts.pop(level(m), None)
    if state is not None and state["auto"]:
        apply(m, src, state)


def apply(m, src, state: dict) -> None:
    feed = m.feed_units
    for f in FIELDS:
        setattr(m, f, state[f])
    # rs274 sets F again only when it changed, to one decimal ("F%.1f"), in the restored units
    if state["feed_units"] != feed:
        m.feed_units = None if state["feed_units"] is None else float(f"{state['feed_units']:.1f}")
        m.feed_scale = m.scale
    if state["coord"] != m.coord:
        offsets.select_system(m, state["coord"])
    speed = m.speed if state["speed"] == m.speed else float(f"{state['speed']:.0f}")  # S to a whole number
    if (state["spindle_dir"], speed) != (m.spindle_dir, m.speed):
        m.spindle(src, state["spindle_dir"], speed)
    on = m.params.numbered.get(5210, 0.0) != 0.0
    if on and not state["g92_on"]:  # G92 applied since: off again (as G92.2)
        m.g92 = [0.0, 0.0, 0.0]
        m.params.numbered[5210] = 0.0
    elif state["g92_on"] and not on:  # G92 taken off since: its stored offsets again (as G92.3)
        m.g92 = [m.params.numbered.get(5211 + i, 0.0) for i in range(3)]
        m.params.numbered[5210] = 1.0
    if state["tlo_mode"] == 49 and m.tlo_mode != 49:
        m.set_tlo([0.0, 0.0, 0.0])
        m.tlo_mode = 49
    elif state["tlo_mode"] == 43 and m.tlo_mode == 49:  # G43.1/G43.2 since are kept (rs274 2.9)
        entry = m.tools.get(m.tool_no, {})
        m.set_tlo([entry.get("X", 0.0), 0.0, entry.get("Z", 0.0)])
        m.tlo_mode = 43
