"""The RS274NGC (LinuxCNC 2.9) code tables: ``{code: Code(modal group, words, meaning)}``.

Codes with a decimal point (G33.1, G59.3) are keyed by their value. A code listed in ``REFUSED``
is valid LinuxCNC G-code the simulator does not model: it is refused at its column naming it,
never silently ignored (docs/dialects/rs274ngc.md).
"""
from __future__ import annotations

from cutsim.interp.core import Code, Group

CYCLES = (73, 74, 81, 82, 83, 84, 85, 86, 87, 88, 89)  # canned cycles simulated
G_CODES: dict[float, Code] = {
    0: Code(Group.MOTION, "XYZ", "rapid"),
    1: Code(Group.MOTION, "XYZF", "linear feed"),
    2: Code(Group.MOTION, "XYZIJKRP", "clockwise arc"),
    3: Code(Group.MOTION, "XYZIJKRP", "counter-clockwise arc"),
    33: Code(Group.MOTION, "XYZK", "spindle-synchronised motion"),
    33.1: Code(Group.MOTION, "XYZK", "rigid tapping"),
    **{c: Code(Group.MOTION, "XYZ", "straight probe") for c in (38.2, 38.3, 38.4, 38.5)},
    73: Code(Group.MOTION, "XYZRQL", "drilling cycle with chip breaking"),
    74: Code(Group.MOTION, "XYZRLP", "left-hand tapping cycle with dwell"),
    84: Code(Group.MOTION, "XYZRLP", "right-hand tapping cycle with dwell"),
    87: Code(Group.MOTION, "XYZRLIJK", "back boring cycle"),
    88: Code(Group.MOTION, "XYZRLP", "boring cycle, spindle stop, manual out"),
    76: Code(Group.MOTION, "XYZPIJKRQHEL", "threading cycle"),
    80: Code(Group.MOTION, "", "cancel canned cycle"),
    81: Code(Group.MOTION, "XYZRL", "drilling cycle"),
    82: Code(Group.MOTION, "XYZRLP", "drilling cycle with dwell"),
    83: Code(Group.MOTION, "XYZRLQ", "peck drilling cycle"),
    85: Code(Group.MOTION, "XYZRL", "boring cycle, feed out"),
    86: Code(Group.MOTION, "XYZRLP", "boring cycle, spindle stop, rapid out"),
    89: Code(Group.MOTION, "XYZRLP", "boring cycle, dwell, feed out"),
    70: Code(Group.MOTION, "XZQDEP", "lathe finishing cycle"),
    **{c: Code(Group.MOTION, "XZQDIR", "lathe roughing cycle") for c in (71, 71.1, 71.2, 72, 72.1, 72.2)},
    4: Code(Group.NON_MODAL, "P", "dwell"),
    10: Code(Group.NON_MODAL, "LPXYZR", "set offsets"),
    28: Code(Group.NON_MODAL, "XYZ", "go to the G28 position"),
    28.1: Code(Group.NON_MODAL, "", "store the G28 position"),
    30: Code(Group.NON_MODAL, "XYZ", "go to the G30 position"),
    30.1: Code(Group.NON_MODAL, "", "store the G30 position"),
    53: Code(Group.NON_MODAL, "XYZ", "move in machine coordinates"),
    92: Code(Group.NON_MODAL, "XYZ", "coordinate system offset"),
    52: Code(Group.NON_MODAL, "XYZ", "local coordinate system offset"),
    92.1: Code(Group.NON_MODAL, "", "reset G92 offsets and parameters"),
    92.2: Code(Group.NON_MODAL, "", "reset G92 offsets"),
    92.3: Code(Group.NON_MODAL, "", "restore G92 offsets"),
    7: Code(Group.DIAMETER, "", "lathe diameter mode"),
    8: Code(Group.DIAMETER, "", "lathe radius mode"),
    17: Code(Group.PLANE, "", "plane XY"),
    18: Code(Group.PLANE, "", "plane ZX"),
    19: Code(Group.PLANE, "", "plane YZ"),
    17.1: Code(Group.PLANE, "", "plane UV"),
    18.1: Code(Group.PLANE, "", "plane WU"),
    19.1: Code(Group.PLANE, "", "plane VW"),
    20: Code(Group.UNITS, "", "inch"),
    21: Code(Group.UNITS, "", "millimetre"),
    40: Code(Group.RADIUS_COMP, "", "cutter compensation off"),
    41: Code(Group.RADIUS_COMP, "DL", "cutter compensation left"),
    42: Code(Group.RADIUS_COMP, "DL", "cutter compensation right"),
    41.1: Code(Group.RADIUS_COMP, "DL", "dynamic cutter compensation left"),
    42.1: Code(Group.RADIUS_COMP, "DL", "dynamic cutter compensation right"),
    43: Code(Group.TOOL_LENGTH, "H", "tool length offset"),
    43.1: Code(Group.TOOL_LENGTH, "XZ", "dynamic tool length offset"),
    43.2: Code(Group.TOOL_LENGTH, "HXZ", "additional tool length offset"),
    49: Code(Group.TOOL_LENGTH, "", "cancel tool length offset"),
    **{n: Code(Group.ZERO_OFFSET, "", f"coordinate system G{n}") for n in range(54, 60)},
    59.1: Code(Group.ZERO_OFFSET, "", "coordinate system G59.1"),
    59.2: Code(Group.ZERO_OFFSET, "", "coordinate system G59.2"),
    59.3: Code(Group.ZERO_OFFSET, "", "coordinate system G59.3"),
    61: Code(Group.PATH_CONTROL, "", "exact path"),
    61.1: Code(Group.PATH_CONTROL, "", "exact stop"),
    64: Code(Group.PATH_CONTROL, "PQ", "blending"),
    90: Code(Group.DISTANCE, "", "absolute"),
    91: Code(Group.DISTANCE, "", "incremental"),
    90.1: Code(Group.ARC_DISTANCE, "", "absolute arc centres"),
    91.1: Code(Group.ARC_DISTANCE, "", "incremental arc centres"),
    93: Code(Group.FEED, "", "inverse time"),
    94: Code(Group.FEED, "", "units per minute"),
    95: Code(Group.FEED, "", "units per revolution"),
    96: Code(Group.SPINDLE_MODE, "DS", "constant surface speed"),
    97: Code(Group.SPINDLE_MODE, "", "constant spindle speed"),
    98: Code(Group.RETRACT, "", "retract to the initial level"),
    99: Code(Group.RETRACT, "", "retract to R"),
}
# Valid LinuxCNC 2.9 codes the simulator refuses (not simulated), with what they are.
REFUSED: dict[float, str] = {
    5: "cubic spline", 5.1: "quadratic spline", 5.2: "NURBS", 5.3: "NURBS end",
}
# The plane each plane code selects; G17.1-G19.1 name planes of the axes U V W, which straight moves
# ignore (LinuxCNC: SELECT_PLANE(CANON_PLANE_UNKNOWN)): what needs their axes is refused (machine.py).
PLANES: dict[float, str] = {17: "XY", 18: "ZX", 19: "YZ", 17.1: "UV", 18.1: "WU", 19.1: "VW"}
UVW_PLANES = {"UV": "G17.1", "WU": "G18.1", "VW": "G19.1"}
M_CODES: dict[int, Code] = {
    0: Code(Group.STOP, "", "program pause"),
    1: Code(Group.STOP, "", "optional pause"),
    2: Code(Group.STOP, "", "program end"),
    30: Code(Group.STOP, "", "program end and rewind"),
    60: Code(Group.STOP, "", "pallet change pause"),
    3: Code(Group.SPINDLE, "S", "spindle clockwise"),
    4: Code(Group.SPINDLE, "S", "spindle counter-clockwise"),
    5: Code(Group.SPINDLE, "", "spindle stop"),
    19: Code(Group.SPINDLE, "RQP", "spindle orientation"),
    6: Code(Group.TOOL, "T", Group.TOOL),
    61: Code(Group.TOOL, "Q", "set the current tool"),
    7: Code(Group.COOLANT, "", "mist coolant"),
    8: Code(Group.COOLANT, "", "flood coolant"),
    9: Code(Group.COOLANT, "", "coolant off"),
    **{m: Code(Group.OVERRIDE, "P", f"override switch M{m}") for m in range(48, 54)},
    **{m: Code(Group.IO, "PEQL", f"digital/analog output M{m}") for m in range(62, 69)},
}
REFUSED_M: dict[int, str] = {}  # M70-M73: machine.check_m, context.py
