"""Ranges of a setup's numbers and names (docs/setup.md), and the checks of a single TOML value.
Coordinates and sizes in mm."""
from __future__ import annotations

import math

COORD_MAX = 100_000.0  # |coordinate| of the stock, the start position, profile points
MIN_SIZE = 0.001  # smallest stock size (diameter, extent along an axis)
RATE_MAX = 1_000_000.0  # mm/min: rapid and default feed
ACCELERATION_MAX = 1_000_000.0  # mm/s^2: [machine] thread_acceleration (about 100 g)
VALUE_MAX = 1e12  # |R parameter| and |machine constant|
# The finest chordal tolerance: 0.1 um. The written mesh is snapped to a grid of at least 2^-16 mm
# (1.5e-5 mm; docs/setup.md, reports/mesh.py), so a finer tolerance could not survive the export, and
# circles at 1e-5 mm have thousands of segments whose booleans run for minutes.
MIN_TOLERANCE = 1e-4
MAX_BLOCKS_LIMIT = 10_000_000  # every executed move is held until the run ends (~0.65 KB each): 6.5 GB at the ceiling
MAX_TRIANGLES_RANGE = (1_000, 2_000_000_000)
MAX_SETUP_BYTES = 16 * 1024 * 1024
FUNCTION_MAX = 99_999  # [machine] m_functions / h_functions: numbers 0 to this
STRING_MAX = 200  # characters of a string value in [variables] (a Sinumerik STRING holds at most 200)
AXIS_KINDS = ("rotary", "linear")
EXTERNAL_NAME_MAX = 64  # characters of an [machine] external_subprograms name (its folder removed)
TRANSFORMATIONS = ("TRAFO",)  # [machine] transformations the dialects know (ISG #TRAFO ON)


def is_number(v) -> bool:
    """A TOML number that is a finite float: not a bool, not nan/inf, not an integer too big for a float."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return False
    try:
        return math.isfinite(float(v))
    except OverflowError:  # a 400-digit integer
        return False


def is_coord(v) -> bool:
    return is_number(v) and abs(v) <= COORD_MAX


def show(v) -> str:
    """A value for a message, cut short (a hostile setup can hold huge arrays)."""
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."
