"""The parameters LinuxCNC computes on every read: #5400 (tool), #5401-#5403 (tool length offset),
#5420-#5422 (position in the active coordinate system, program units) and the named ones
(``#<_x>``, ``#<_metric>`` ...)."""
from __future__ import annotations


def install(m) -> None:
    def numbered(n: int):
        if n == 5220:
            return float(m.coord)
        if n == 5400:
            return float(m.tool_no)
        if 5401 <= n <= 5403:
            return m.tlo[n - 5401] / m.scale
        if 5420 <= n <= 5422:
            return m.program_value(n - 5420)
        if n == 5410:
            return m.tools.get(m.tool_no, {}).get("D", 0.0) / m.scale
        return 0.0 if n in range(5404, 5410) or n in range(5423, 5429) or n == 5399 else None

    named = {
        "_x": lambda: m.program_value(0), "_y": lambda: m.program_value(1), "_z": lambda: m.program_value(2),
        "_metric": lambda: 1.0 if m.scale == 1.0 else 0.0, "_imperial": lambda: 1.0 if m.scale != 1.0 else 0.0,
        "_absolute": lambda: 1.0 if m.absolute else 0.0, "_incremental": lambda: 0.0 if m.absolute else 1.0,
        "_current_tool": lambda: float(m.tool_no), "_selected_tool": lambda: float(m.selected),
        "_feed": lambda: m.feed_units or 0.0, "_rpm": lambda: float(m.speed),
        "_spindle_on": lambda: 1.0 if m.spindle_dir else 0.0, "_motion_mode": lambda: float(m.motion) * 10.0,
        "_plane": lambda: {"XY": 170.0, "ZX": 180.0, "YZ": 190.0, "UV": 171.0, "WU": 181.0, "VW": 191.0}[m.plane],
        "_coord_system": lambda: 530.0 + 10.0 * m.coord if m.coord <= 6 else 590.0 + m.coord - 6,
        "_call_level": lambda: float(len(m.params.frames) - 1),
        "_value": lambda: 0.0, "_value_returned": lambda: 0.0,
        "_vmajor": lambda: 2.0, "_vminor": lambda: 9.0,
    }

    def lookup(key):
        if isinstance(key, int):
            return numbered(key)
        f = named.get(key)
        return None if f is None else f()

    m.params.predefined = lookup
