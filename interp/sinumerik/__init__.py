"""Siemens Sinumerik 840D (docs/dialects/sinumerik.md), one package by concern:

- language: ``syntax`` (limits, messages, the syntax tree), ``expressions`` and ``reader`` (a block's
  text into it), ``lowering`` (structured control flow into jumps), ``fast`` (the plain-line shortcut);
- the run: ``interpreter`` (``Sinumerik``, a ``core.Interpreter``: blocks through the core executor's
  hooks, moves) with its parts ``values`` (expressions and variables), ``flow`` (jumps, CASE, REPEAT,
  the loop guard), ``calls`` (subprograms), ``words`` (a block's words and G code groups); ``codes``
  (the G and M tables) and ``tables`` (notes and limits);
- the machine side as an owned object: ``machine`` (units, frames, extra axes, tools, spindles) on
  ``frames``; ``axes`` (AXNAME, AXSTRING, SPI, AXTOSPI, AX[..]);
- cycles: ``cycle`` (parameters, ``Cycle``, the contour offset), ``milling`` (SLOT1/2, POCKET1-4,
  CYCLE71, run_cycle), ``contour`` (CYCLE72), ``drilling`` (CYCLE81..89, patterns, MCALL, ISO G81..G89),
  ``corners`` (CHF, CHR, RND, RNDM, FRC, FRCM); the turning cycles: ``turncycles`` (CYCLE93..98 in the
  interpreter, CYCLE84 on a lathe) on the planners ``threading`` (CYCLE97, 98), ``grooving`` (CYCLE93,
  94, 96) and ``stockremoval`` (CYCLE95).

``interpret(name, text, cfg)`` is the registry's entry point (interp/__init__.py).
"""
from .interpreter import Sinumerik, interpret

__all__ = ["Sinumerik", "interpret"]
