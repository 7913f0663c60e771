"""The G and M codes the Sinumerik interpreter knows: one ``core.Code`` row each (modal group,
the addresses it restricts, meaning). A code not in the table is an error at its word; a
machine M function the setup declares ([machine] m_functions) passes silently.

``Code.words`` is filled where the manual restricts a block's addresses and the interpreter
checks them: the motion codes (I, J, K and CR belong to circles) and G4 (its dwell time). The
codes of the ISO shell (G73 .. G89, G98/G99, G290/G291) run the Siemens drilling cycles
(interp/sinumerik/drilling.py); path-mode, exact-stop and corner codes only warn (machine.py).
"""
from __future__ import annotations

from ..core import ISO_G_CODES, ISO_M_CODES, Code, Group

_CIRCLE = "X Y Z I J K CR"

G_CODES: dict[int, Code] = {
    **ISO_G_CODES,  # G17/G18/G19, G90/G91, G94/G95
    0: Code(Group.MOTION, "X Y Z", "rapid"),
    1: Code(Group.MOTION, "X Y Z", "line"),
    2: Code(Group.MOTION, _CIRCLE, "arc clockwise"),
    3: Code(Group.MOTION, _CIRCLE, "arc counter-clockwise"),
    4: Code(Group.NON_MODAL, "F S", "dwell"),
    25: Code(Group.NON_MODAL, "S X Y Z", "lower spindle speed limit (S) or working area limitation (axes)"),
    26: Code(Group.NON_MODAL, "S X Y Z", "upper spindle speed limit (S) or working area limitation (axes)"),
    # the lathe's spindle-synchronised moves (interp/sinumerik/turning.py)
    33: Code(Group.MOTION, "X Y Z I J K", "thread cutting with constant lead"),
    34: Code(Group.MOTION, "X Y Z I J K F", "thread cutting with increasing lead"),
    35: Code(Group.MOTION, "X Y Z I J K F", "thread cutting with decreasing lead"),
    331: Code(Group.MOTION, "X Y Z K", "rigid tapping"),
    332: Code(Group.MOTION, "X Y Z K", "rigid tapping, retraction"),
    63: Code(Group.NON_MODAL, "X Y Z F", "tapping with compensating chuck"),
    9: Code(Group.NON_MODAL, "", "exact stop for one block"),
    40: Code(Group.RADIUS_COMP, "", "off"),
    41: Code(Group.RADIUS_COMP, "", "left"),
    42: Code(Group.RADIUS_COMP, "", "right"),
    53: Code(Group.NON_MODAL, "", "machine coordinates for this block"),
    153: Code(Group.NON_MODAL, "", "machine coordinates for this block, base frame suppressed too"),
    500: Code(Group.ZERO_OFFSET, "", "settable zero offset off"),
    **{c: Code(Group.ZERO_OFFSET, "", "settable zero offset") for c in (54, 55, 56, 57, *range(505, 600))},
    60: Code(Group.PATH_CONTROL, "", "exact stop"),
    64: Code(Group.PATH_CONTROL, "", "continuous-path mode"),
    641: Code(Group.PATH_CONTROL, "", "continuous-path mode with rounding"),
    642: Code(Group.PATH_CONTROL, "", "continuous-path mode with axial tolerances"),
    643: Code(Group.PATH_CONTROL, "", "block-internal rounding"),
    644: Code(Group.PATH_CONTROL, "", "rounding with maximum dynamics"),
    645: Code(Group.PATH_CONTROL, "", "rounding with tangential transitions"),
    601: Code(Group.EXACT_STOP, "", "exact stop fine"),
    602: Code(Group.EXACT_STOP, "", "exact stop coarse"),
    603: Code(Group.EXACT_STOP, "", "exact stop at interpolator end"),
    450: Code(Group.CORNER, "", "transition circle at outside corners of radius compensation"),
    451: Code(Group.CORNER, "", "intersection at outside corners of radius compensation; simulated as G450, "
                                "the part is the same"),
    70: Code(Group.UNITS, "", "inch"),
    71: Code(Group.UNITS, "", "metric"),
    700: Code(Group.UNITS, "", "inch, the feed in inch too"),
    710: Code(Group.UNITS, "", "metric, the feed in mm too"),
    # S as a cutting speed (m/min) changes the spindle speed with the tool's diameter, not the path
    96: Code(Group.SPINDLE_MODE, "", "constant cutting speed"),
    961: Code(Group.SPINDLE_MODE, "", "constant cutting speed with the feed per minute"),
    97: Code(Group.SPINDLE_MODE, "", "spindle speed in rpm"),
    971: Code(Group.SPINDLE_MODE, "", "spindle speed in rpm with the feed per minute"),
    # the ISO shell's drilling cycles: modal until G80 or a G0..G3
    73: Code(Group.CANNED_CYCLE, "", "deep-hole drilling with chip breaking"),
    74: Code(Group.CANNED_CYCLE, "", "left-hand tapping"),
    80: Code(Group.CANNED_CYCLE, "", "drilling cycle off"),
    81: Code(Group.CANNED_CYCLE, "", "drilling"),
    82: Code(Group.CANNED_CYCLE, "", "drilling with dwell"),
    83: Code(Group.CANNED_CYCLE, "", "deep-hole drilling"),
    84: Code(Group.CANNED_CYCLE, "", "tapping"),
    85: Code(Group.CANNED_CYCLE, "", "boring, feed out"),
    86: Code(Group.CANNED_CYCLE, "", "boring, spindle stop, rapid out"),
    87: Code(Group.CANNED_CYCLE, "", "back boring"),
    88: Code(Group.CANNED_CYCLE, "", "boring, spindle stop"),
    89: Code(Group.CANNED_CYCLE, "", "boring with dwell, feed out"),
    98: Code(Group.RETRACT, "", "return to the initial level"),
    99: Code(Group.RETRACT, "", "return to the R plane"),
    290: Code(Group.LANGUAGE_MODE, "", "Siemens mode"),
    291: Code(Group.LANGUAGE_MODE, "", "ISO dialect mode"),
}

M_CODES: dict[int, Code] = {
    **ISO_M_CODES,  # M0 M1 stop, M2 end, M3 M4 spindle
    5: Code(Group.SPINDLE, "", "spindle stop"),
    6: Code(Group.TOOL, "", "tool change"),
    7: Code(Group.COOLANT, "", "mist coolant"),
    8: Code(Group.COOLANT, "", "flood coolant"),
    9: Code(Group.COOLANT, "", "coolant off"),
    17: Code(Group.END, "", "subprogram end"),
    19: Code(Group.SPINDLE, "", "spindle positioning"),
    30: Code(Group.END, "", "program end"),
    40: Code(Group.GEAR, "", "automatic gear stage"),
    **{c: Code(Group.GEAR, "", f"gear stage {c - 40}") for c in range(41, 46)},
}

# the groups the language checks for two different codes in one block (Words.check_groups)
LANGUAGE_GROUPS = frozenset((Group.MOTION, Group.PLANE, Group.DISTANCE, Group.FEED, Group.RADIUS_COMP))
# codes that only change how the path is run, not where: accepted with one warning each
PATH_ONLY = frozenset(c for c, row in G_CODES.items() if c == 9 or row.group in (Group.PATH_CONTROL,
                      Group.EXACT_STOP, Group.CORNER))
# the ISO shell's codes by group, in the order drilling.iso_codes checks them
ISO_GROUPS = (Group.CANNED_CYCLE, Group.RETRACT, Group.LANGUAGE_MODE)


def takes(code: int, address: str) -> bool:
    """Whether a block of G code ``code`` may carry ``address`` (its row's ``Code.words``)."""
    return address in G_CODES[code].words.split()
