"""Beckhoff TwinCAT CNC (ISG kernel) dialect: program structure, control flow, variables,
``#`` commands, global subprograms, work offsets and G33 with I/J/K leads.

A file holds a main program ``%name`` ended by M30 and any number of local subprograms ``%L name``
ended by M29 (or M17), called with ``LL name``; ``L name`` calls a global subprogram file. See
docs/dialects/isg.md for what the simulator assumes where the manual is silent.

- ``lang``         expressions compiled to closures (evaluated when the block runs);
- ``reader``       one line -> a block (IsgBlock) or a control statement (Ctrl);
- ``program``      a file -> sections: declarations, macros, headers, matched control structures;
- ``fast``         the plain-line reader (core.fast) and the plain-block shortcut;
- ``tables``       the G and M code tables and limits;
- ``interpreter``  Isg on the core executor, made of its parts, each with its state:
  ``variables``, ``flow`` (control flow, block counts), ``frames`` (offsets, #CS, rotation,
  mirroring), ``compensation`` (G40/G41/G42; on a lathe the nose radius), ``calls``
  (subprograms), ``motion`` (paths, circles, G33) and ``commands`` (# commands).
"""
from .interpreter import Isg, interpret

__all__ = ["Isg", "interpret"]
