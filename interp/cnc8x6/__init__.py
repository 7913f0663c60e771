"""MEFI CNC8x6 dialect (lathes and mills): seeds 000/001 (G33 threads) and 002 (helix, jumps).
See docs/dialects/cnc8x6.md for what the simulator assumes where the manuals are silent.

- ``language``     code tables (and the codes of other controls it refuses by name), limits, the line scanner and parse;
- ``interpreter``  Cnc8x6 on the core executor: run loops, R parameters, helix, the execute hooks;
- ``plain``        the plain-block and plain-line shortcuts;
- ``threads``      G33 with runout and lead-in;
- ``loops``        G73 loops counted before running.
"""
from .interpreter import Cnc8x6, interpret
from .language import G_CODES, JUMP, LIMITS, M_CODES, decode_angle_code, parse, scan
from .loops import count_executions, crossing_block, crossing_loops, heaviest_loops, static_jumps

__all__ = ["Cnc8x6", "interpret", "G_CODES", "M_CODES", "LIMITS", "JUMP", "decode_angle_code", "parse", "scan",
           "count_executions", "crossing_block", "crossing_loops", "heaviest_loops", "static_jumps"]
