"""The core every word-address dialect runs on (docs/architecture.md):

- ``lexer``         numbers, words, blocks, line splitting and the limits every number keeps;
- ``modal``         the modal machine (position, modal groups, canonical records) and InterpConfig;
- ``executor``      the block executor read -> check -> convert driven by a dialect's code tables;
- ``geometry``      arc centres (I/J/K or a radius) and sweep angles;
- ``compensation``  cutter radius compensation of a chain of records.

The executor's names are re-exported here: a dialect writes ``from ..core import Interpreter``.
"""
from .executor import CENTRE_WORDS, COMMON_GROUPS, ISO_G_CODES, ISO_M_CODES, MOTION, Code, Interpreter, Step
from .geometry import FullCircle, RadiusTooSmall, arc_centre, radius_centre, sweep_degrees
from .modal import Group

__all__ = ["CENTRE_WORDS", "COMMON_GROUPS", "ISO_G_CODES", "ISO_M_CODES", "MOTION", "Code", "Group", "Interpreter", "Step", "arc_centre", "sweep_degrees",
           "radius_centre", "FullCircle", "RadiusTooSmall"]
