"""Siemens Sinumerik 840D (docs/dialects/sinumerik.md), one package by concern:

- ``lang``        the language: syntax tree, the block reader and the lowering of structured control
                  flow to jumps (``split_units``);
- ``fast``        the plain-line shortcut of the reader and of the block evaluation;
- ``interpreter`` the run: values and variables, subprogram calls, control flow, moves (``Sinumerik``);
- ``machine``     the machine side as an owned object (units, frames, extra axes, tools, spindles);
- ``axes``        the axis functions (AXNAME, AXSTRING, SPI, AXTOSPI, AX[..]);
- ``milling``     the milling cycles (SLOT1/2, POCKET1-4, CYCLE71/72) on ``Cycle``;
- ``drilling``    the drilling cycles, hole patterns, MCALL and the ISO G81..G89 cycles;
- ``corners``     chamfers and roundings (CHF, CHR, RND, RNDM, FRC, FRCM).

``interpret(name, text, cfg)`` is the registry's entry point (interp/__init__.py).
"""
from .interpreter import Sinumerik, interpret

__all__ = ["Sinumerik", "interpret"]
