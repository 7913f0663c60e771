"""Siemens' elementary frames (ROT about an axis, SCALE): matrices for core.frames.Affine, which
composes them (TRANS, ROT, SCALE, MIRROR and their additive forms) and inverts them."""
from __future__ import annotations

import math

from ..core.frames import Mat


def _rot(axis: int, deg: float) -> Mat:
    """Right-handed rotation about X/Y/Z: a positive angle turns counter-clockwise seen from the
    positive end of the axis (Siemens' convention)."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    # snap the exact quarter turns so that ROT RPL=90 gives exact coordinates
    c, s = (0.0 if abs(c) < 1e-15 else c), (0.0 if abs(s) < 1e-15 else s)
    i, j = [k for k in range(3) if k != axis] if axis != 1 else (2, 0)
    m = [[1.0 if r == k else 0.0 for k in range(3)] for r in range(3)]
    m[i][i], m[i][j], m[j][i], m[j][j] = c, -s, s, c
    return tuple(tuple(r) for r in m)  # type: ignore


def _diag(x: float, y: float, z: float) -> Mat:
    return ((x, 0.0, 0.0), (0.0, y, 0.0), (0.0, 0.0, z))
