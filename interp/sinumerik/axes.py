"""Sinumerik axis identifiers as values (Job Planning, "axis functions"): ``AXNAME("X")`` (a string
into an axis), ``AXSTRING(X)`` (an axis into its name), ``SPI(n)`` (spindle n as an axis) and
``AXTOSPI(axis)`` (back to the spindle number), and ``AX[<axis expression>]=value``.

An AXIS value is held as its name in upper case: X, Y, Z, an axis the setup declares in
``[machine] axes`` (A, B1, SP1, ...), or ``S<n>`` for spindle n (what AXSTRING(SPI(n)) gives, as on
the controller). Every AXIS value that comes from a string is checked against the machine: a name
the machine does not have is an error at the column of the word that uses it.
"""
from __future__ import annotations

import re

from .syntax import R_NAME, FuncCall, Var
from .machine import AXES, axis_message

AXIS_FUNCS = {"AXNAME", "AXSTRING", "SPI", "AXTOSPI"}
SPINDLE = re.compile(r"S([1-9][0-9]?)")  # SPI(n): spindles 1 to 99
NAME = re.compile(r"[A-Z][A-Z0-9_]*")


def spindle_number(name: str) -> int | None:
    """n for the spindle identifier S<n>, None for any other axis."""
    m = SPINDLE.fullmatch(name)
    return int(m.group(1)) if m else None


def checked(m, name, line: int, col: int) -> str:
    """``name`` (a value the program computed) as an axis of this machine, in upper case; an error
    at ``col`` when it is no string or names no axis the machine has."""
    if not isinstance(name, str):
        raise m.error(line, col, f"an axis name is expected here, not the number {name:.10g}")
    up = name.strip().upper()
    if up in AXES or up in m.cfg.axes or spindle_number(up) is not None:
        return up
    if not NAME.fullmatch(up):
        raise m.error(line, col, f"\"{name}\" is no axis name")
    raise m.error(line, col, axis_message(up))


def axis_of(m, node, line: int, col: int) -> str:
    """The axis an AXIS expression names: a bare name that is no variable is the axis itself
    (``AX[X]``, ``AXSTRING(B)``), anything else is evaluated (an AXIS variable, ``AXNAME(..)``,
    ``SPI(..)``, ``$P_AXN1``, a GUD holding a name)."""
    if isinstance(node, Var) and not node.name.startswith("$") and not R_NAME.fullmatch(node.name) \
            and node.name not in m.vars and node.name not in m.cfg_names:
        return checked(m, node.name, line, col)
    return checked(m, m.ev(node, line, col), line, col)


def function(m, node: FuncCall, line: int, col: int):
    """The value of AXNAME, AXSTRING, SPI or AXTOSPI (``col``: the word's column, where a name the
    machine does not have is reported)."""
    arg = node.args[0]
    if node.name == "AXNAME":
        v = m.ev(arg, line, col)
        if not isinstance(v, str):
            raise m.error(line, node.col, f"AXNAME takes a string, not the number {v:.10g}")
        return checked(m, v, line, col)
    if node.name == "SPI":
        n = m.num(m.ev(arg, line, col), line, node.col)
        if n != int(n) or not 1 <= n <= 99:
            raise m.error(line, node.col, f"SPI({n:.10g}): a spindle number is a whole number from 1 to 99")
        return f"S{int(n)}"
    axis = axis_of(m, arg, line, col)
    if node.name == "AXSTRING":
        return axis
    n = spindle_number(axis)  # AXTOSPI
    if n is None:
        raise m.error(line, node.col, f"AXTOSPI({axis}): axis {axis} is no spindle (a spindle is SPI(n))")
    return float(n)
