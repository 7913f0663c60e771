"""The setup file (TOML): machine, parameters, stock, tools, checks, simulation. See docs/setup.md.

Every problem is a CutsimError naming the setup file, the line of the offending key, the table and
the key. ``load_setup(path)`` reads a file; the modules, one job each: ``loader`` (the file, the
TOML, the order of the tables), ``positions`` (where each key is written), ``reader`` (typed,
located access to a table), ``limits`` (ranges), and one per table: ``machine`` (with
[parameters], [variables], [work_offsets]), ``stock``, ``tools``, ``checks``, ``simulation``.
What belongs to a dialect (its default diameter programming, its settable work offsets) is in its
registry entry (cutsim.interp.DIALECTS).
"""
from __future__ import annotations

from .checks import CHECK_KEYS, LATHE_CHECKS, MILL_CHECKS, check_spec
from .limits import (AXIS_KINDS, COORD_MAX, EXTERNAL_NAME_MAX, FUNCTION_MAX, MAX_BLOCKS_LIMIT, MAX_SETUP_BYTES,
                     MAX_TRIANGLES_RANGE, MIN_SIZE, MIN_TOLERANCE, RATE_MAX, STRING_MAX, TRANSFORMATIONS, VALUE_MAX)
from .loader import huge_number_at, load_setup
from .machine import KINDS
from .model import Setup
from .positions import key_positions
from .simulation import DEFAULT_TOLERANCE
from .tools import DRILL_LENGTH_FACTOR, TOOL_COMMON, TOOL_KEYS, TOOL_NAME_MAX

__all__ = ["AXIS_KINDS", "CHECK_KEYS", "COORD_MAX", "DEFAULT_TOLERANCE", "DRILL_LENGTH_FACTOR", "EXTERNAL_NAME_MAX",
           "FUNCTION_MAX", "KINDS", "LATHE_CHECKS", "MAX_BLOCKS_LIMIT", "MAX_SETUP_BYTES", "MAX_TRIANGLES_RANGE",
           "MILL_CHECKS", "MIN_SIZE", "MIN_TOLERANCE", "RATE_MAX", "STRING_MAX", "Setup", "TOOL_COMMON", "TOOL_KEYS",
           "TOOL_NAME_MAX", "TRANSFORMATIONS", "VALUE_MAX", "check_spec", "huge_number_at", "key_positions",
           "load_setup"]
