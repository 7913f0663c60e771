"""The ISG code tables and limits: G and M codes, the G codes accepted with a warning or refused,
implicit subroutine calls, leads, call depth and subprogram files."""
from __future__ import annotations

import re

from ..core import ISO_G_CODES, ISO_M_CODES, Code, Group

# V.G.NP[i].V.X (zero offset i = 1..6, G54..G59) and V.G.NP_AKT.V.X (the active one), X/Y/Z only
# V.G.@P[i].VALID: in a cycle, 1 when its call programmed @Pi (manual, error ID 21544)
VALID_VAR = re.compile(r"V\.G\.@P\[(\d+)\]\.VALID")
ZERO_VAR = re.compile(r"V\.G\.NP(?:\[(\d+)\]|_AKT)\.V\.([XYZ])")

G_CODES = {
    0: Code(Group.MOTION, "XYZ", "rapid"),
    1: Code(Group.MOTION, "XYZF", "linear feed"),
    2: Code(Group.MOTION, "XYZIJKF", "clockwise arc, centre I/J/K from the start"),
    3: Code(Group.MOTION, "XYZIJKF", "counter-clockwise arc, centre I/J/K from the start"),
    33: Code(Group.MOTION, "XYZIJK", "thread, lead on I/J/K (mm/rev)"),
    331: Code(Group.MOTION, "XYZK", "tapping on a lathe's spindle axis, signed pitch on K (mm/rev)"),
    332: Code(Group.MOTION, "XYZK", "retracting the tap along its helix, the spindle reversed"),
    40: Code(Group.RADIUS_COMP, "", "tool radius compensation off"),
    41: Code(Group.RADIUS_COMP, "", "tool radius compensation left"),
    42: Code(Group.RADIUS_COMP, "", "tool radius compensation right"),
    51: Code(Group.DIAMETER, "", "diameter programming on (lathe)"),
    52: Code(Group.DIAMETER, "", "diameter programming off"),
    53: Code(Group.ZERO_OFFSET, "", "zero offset off"),
    **{n: Code(Group.ZERO_OFFSET, "", f"zero offset G{n}") for n in range(54, 60)},
    92: Code(Group.REFERENCE, "XYZ", "reference point offset"),
    161: Code(Group.CENTRE, "", "circle centre absolute"),
    162: Code(Group.CENTRE, "", "circle centre relative to the start"),
    71: Code(Group.UNITS, "", "millimetres"),
    70: Code(Group.UNITS, "", "inches"),
    25: Code(Group.TRC_TRANSITION, "", "linear transitions at outside corners with tool radius compensation"),
    26: Code(Group.TRC_TRANSITION, "", "circular transitions at outside corners with tool radius compensation"),
    138: Code(Group.TRC_SELECTION, "", "direct selection/deselection of tool radius compensation"),
    139: Code(Group.TRC_SELECTION, "", "indirect selection/deselection of tool radius compensation"),
    20: Code(Group.MIRROR, "", "mirroring off"),
    21: Code(Group.MIRROR, "", "mirroring of X (on the Y axis)"),
    22: Code(Group.MIRROR, "", "mirroring of Y (on the X axis)"),
    23: Code(Group.MIRROR, "", "mirroring of X and Y"),
    351: Code(Group.MIRROR_AXES, "XYZ", "mirroring of the axes given (-1 on, 1 off)"),
    68: Code(Group.ROTATION, "XYZR", "contour rotation by R about X/Y in the plane"),
    69: Code(Group.ROTATION, "", "contour rotation off"),
    **ISO_G_CODES,
}
MIRRORS = {20: (False, False), 21: (True, False), 22: (False, True), 23: (True, True)}
# G codes that do not change the tool path (TwinCAT CNC programming manual, "G functions"):
# accepted with one warning each. Those in G_AXIS_PARAMS take axis words as percentages or limits.
G_HARMLESS = {
    4: "dwell time", 8: "acceleration at block start", 9: "deceleration at block end",
    10: "constant feed with tool radius compensation", 11: "adapted feed with tool radius compensation",
    12: "corner deceleration off", 13: "corner deceleration on",
    60: "exact stop", 61: "polynomial contouring (blends corners within the contour tolerance)",
    63: "tapping without compensating chuck", 66: "synchronise cycle at block end",
    96: "constant cutting speed", 97: "constant spindle speed", 98: "negative software limit switches",
    99: "positive software limit switches", 129: "G00 velocity weighting", 130: "axis acceleration weighting",
    131: "acceleration weighting", 132: "axis ramp time weighting", 133: "ramp time weighting",
    134: "geometric ramp time weighting", 164: "circle centre correction", 193: "time-related feed interpolation",
    293: "path-related feed interpolation", 230: "axis G00 acceleration weighting",
    231: "G00 acceleration weighting", 233: "G00 ramp time weighting", 333: "axis feedhold acceleration weighting",
    334: "feedhold acceleration weighting", 900: "acceleration on block transitions", 901: "acceleration on block transitions",
    359: "exact stop mode", 360: "exact stop mode",
    260: "polynomial contouring mode", 261: "polynomial contouring mode", 93: "feed as machining time",
}

G_AXIS_PARAMS = {4, 98, 99, 130, 132, 230, 333}
# selection/deselection methods of tool radius compensation the simulator does not model: they only
# act when G41/G42 is selected or deselected, which is then refused (G138 direct and G139 indirect are)
TRC_METHODS = {5: "tangential selection/deselection", 236: "direct selection/deselection on the path",
               237: "perpendicular selection/deselection", 238: "inside corner selection",
               239: "direct selection/deselection without a block"}
# G codes that change the tool path in a way the simulator does not model: exit 2 naming them
G_NOT_MODELLED = {
    101: "measuring offsets into the zero offsets", 102: "measuring offsets out of the zero offsets",
    74: "homing (a move to the reference point)", 100: "measuring", 106: "measuring", 310: "measuring",
    303: "circle in space", 150: "spline", 151: "spline",
}
# G codes harmless on a mill that change the part on a lathe, where the workpiece spindle turns with
# the path: exit 2 there
G_LATHE_NOT_MODELLED = {
    63: "tapping with the spindle following the path: its start angle, where the spindle stood after "
        "M05 or M19, is not known to the simulator; tap with G33 Z.. K.. at X0",
}
# implicit subroutine calls (manual: "Implicit subroutine calls (G80-G89/G800..)"): each runs the global
# subprogram the machine maker configures for it once, at the end of its block ("no modal effect")
IMPLICIT_CALLS = set(range(80, 90)) | set(range(800, 820))
M_CODES = {
    **ISO_M_CODES,
    5: Code(Group.SPINDLE, "", "spindle stop (after the motion)"),
    6: Code(Group.TOOL, "TD", "tool change"),
    7: Code(Group.COOLANT, "", "coolant"),
    8: Code(Group.COOLANT, "", "coolant"),
    9: Code(Group.COOLANT, "", "coolant off"),
    17: Code(Group.END, "", "subprogram end"),
    29: Code(Group.END, "", "subprogram end"),
    30: Code(Group.END, "", "program end"),
}
LEADS = {"I": "X", "J": "Y", "K": "Z"}
MIN_LEAD = 0.0001  # mm/rev: the programming resolution
MAX_CALL_DEPTH = 20  # subprograms (local and global) open at once
MAX_SUB_BYTES = 10_000_000
SUB_EXTENSIONS = ("", ".nc", ".NC", ".Nc", ".ISG", ".isg")
