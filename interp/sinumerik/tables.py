"""The Sinumerik interpreter's tables besides its G and M codes (codes.py): the calls it ignores
or notes, what PROC ... SAVE restores, the limits of arrays, subprogram files and the call stack.
Importing it registers the drilling cycles into the milling cycles' tables (drilling.register).
"""
from __future__ import annotations

import os
import re

from . import drilling as drill, turncycles
from .syntax import KEYWORDS as LANG_KEYWORDS, MACHINE_COMMANDS
from .cycle import _spec, ANGLES, CYCLES, DRILLING, SPECS, TURNING
from .milling import RUNNERS


# calls with no geometric effect (high-speed settings, blank definition for the HMI)
IGNORED_CALLS = {"WORKPIECE", "CYCLE832"}

# language calls that do not change the tool path: one warning per kind (SETAL: an alarm, exit 2)
LANG_CALLS = {"MSG", "SETAL", "FGROUP", "G_GROUP", "SETMS", "GROUP_BEGIN", "GROUP_END", "STOPRE", "WAITM",
              "WAITMC", "WAITE", "SETM", "CLEARM", "CANCEL", "DISPLOF", "DISPLON", "PRESETON", "SPOS", "SPOSA",
              "FA", "WRTPR", "MSG_", "SBLOF", "SBLON", "STOPFIFO", "STARTFIFO", "WAITP", "WAITS", "WAITC",
              "RELEASE", "GET", "GETD", "PRIO"}

NOTES = {"STOPRE": "(preprocessing stop) changes nothing on the tool path",
         "WHENEVER": "(a synchronized action) is not simulated: its condition and action are ignored",
         "ID": "(a synchronized action) is not simulated: its condition and action are ignored",
         "MSG": "(a message on the operator screen) changes nothing on the tool path",
         "FGROUP": "(the axes the feed applies to) is not simulated: F is the path feed of X/Y/Z",
         "H": "(an auxiliary function for the machine's PLC) changes nothing on the tool path",
         "SPOS": "(spindle positioning) changes nothing on the tool path",
         "LIMS": "(the spindle speed limit) changes nothing on the tool path"}

# what PROC ... SAVE puts back on return: the modal G groups, not F, S, T, D, and the machine
# functions' modal state (units, settable and programmable frames: machine.Modal)
SAVED_MODAL = ["absolute", "per_rev", "plane", "motion", "comp", "machine_modal"]

# the drilling cycles and the position patterns join the cycles' tables (CYCLES, SPECS, RUNNERS)
drill.register(SPECS, RUNNERS, CYCLES, ANGLES, _spec, DRILLING)
# the turning cycles (CYCLE93..98) too, run in G18 on a lathe (turncycles.register)
turncycles.register(SPECS, RUNNERS, CYCLES, _spec, TURNING)

# keywords that are never a subprogram file, even with a file of that name beside the program
NOT_FILES = LANG_KEYWORDS | MACHINE_COMMANDS | set(CYCLES) | {"MCALL", "HOLES1", "HOLES2", "LONGHOLE", "CYCLE800",
           "CYCLE801", "CYCLE802", "CYCLE832", "CYCLE840", "CYCLE84", "CYCLE86", "CYCLE87", "CYCLE88", "CYCLE89",
           "CYCLE90", "CYCLE61", "CYCLE76", "CYCLE77", "CYCLE79", "CYCLE899", "CYCLE95", "CYCLE99", "MSG", "SETAL",
           "WORKPIECE"}

# Siemens cycles the simulator knows but does not run yet: the error names what they do and why they are not run
# (docs/dialects/sinumerik-turning.md, "CYCLE99")
NOT_YET = {"CYCLE99": ("ShopTurn thread turning",
                       "the coding of its call (the order of its parameters and the digits of _VARI: machining, "
                       "infeed, inside/outside, longitudinal/taper/face) is not established from Siemens' manuals; "
                       "program the thread with CYCLE97(PIT, MPIT, SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP, "
                       "NRC, NID, VARI, NUMT, _VRT), which cuts the same threads")}

# machine keywords the simulator does not implement, with what they do (the error names it): the
# transformations of a turn-mill centre's driven tools (TRANSMIT, TRACYL: the C axis as a path axis)
UNSUPPORTED_MEANINGS = {"TRANSMIT": "milling on the face with the C axis, a kinematic transformation of driven tools",
                        "TRACYL": "milling on the cylinder's surface with the C axis, a kinematic transformation of "
                                  "driven tools"}

# path words the simulator does not implement: an error naming them, not "unknown variable"
UNSUPPORTED_NAMES = {"ANG": "a contour angle", "AR": "an arc's opening angle",
                     "AP": "a polar angle", "RP": "a polar radius", "TURN": "helix turns", "POS": "a positioning axis",
                     "POSA": "a positioning axis", "OFFN": "a contour offset", "I1": "an intermediate point",
                     "J1": "an intermediate point", "K1": "an intermediate point"}

# a subprogram file's extensions (find_sub) and its archive form _N_NAME_SPF: stripped from the setup's
# [machine] external_subprograms names and from EXTCALL/PCALL paths to give the name a call uses
SUB_EXTENSIONS = (".SPF", ".MPF", ".NC")

ARCHIVE_NAME = re.compile(r"_N_([A-Z0-9_]+)_(?:SPF|MPF)")

MAX_ARRAY = 1_000_000  # elements of one array (DEF REAL A[1000, 1000])

MAX_SUB_BYTES = 10_000_000  # a NAME.spf file beside the program

MAX_STACK = 64  # subprograms (16 of them at most) and REPEAT sections open at once


def call_name(file: str) -> str:
    """The name a call uses for a subprogram file: "subs/L_VENDOR.SPF" and "_N_L_VENDOR_SPF" are
    L_VENDOR (folder, extension and archive form removed; upper case)."""
    name = re.split(r"[/\\]", file.strip())[-1].strip().upper()
    base, ext = os.path.splitext(name)
    if ext in SUB_EXTENSIONS:
        name = base
    m = ARCHIVE_NAME.fullmatch(name)
    return m.group(1) if m else name

def missing_hint(name: str) -> str:
    """What to do about a call the simulator finds no subprogram for (the end of its error)."""
    return (f"; a subprogram the machine has but the simulator does not is declared in the setup: "
            f"[machine] external_subprograms = [\"{name}\"]")

COMPARE = {"==": lambda a, b: a == b, "<>": lambda a, b: a != b, "<": lambda a, b: a < b, ">": lambda a, b: a > b,
           "<=": lambda a, b: a <= b, ">=": lambda a, b: a >= b}
