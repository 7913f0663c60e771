"""The programmable frame's algebra (TRANS, ROT, SCALE, MIRROR and their additive forms): 3x3 matrices
as tuples and ``Affine`` (parent = A @ child + t).
"""
from __future__ import annotations

import math
from dataclasses import dataclass


Mat = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
IDENT: Mat = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
ZERO = (0.0, 0.0, 0.0)


# -- small affine algebra (parent = A @ child + t) ----------------------------------------------------
def _mul(a: Mat, b: Mat) -> Mat:
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))  # type: ignore


def _apply(a: Mat, v) -> tuple[float, float, float]:
    return tuple(a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2] for i in range(3))  # type: ignore


def _det(a: Mat) -> float:
    return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))


def _cof(a: Mat) -> Mat:
    """The cofactor matrix: maps a plane's normal to the normal of its image, orientation kept
    (det(A) A^-T)."""
    def c(i, j):
        r = [k for k in range(3) if k != i]
        s = [k for k in range(3) if k != j]
        return (-1) ** (i + j) * (a[r[0]][s[0]] * a[r[1]][s[1]] - a[r[0]][s[1]] * a[r[1]][s[0]])
    return tuple(tuple(c(i, j) for j in range(3)) for i in range(3))  # type: ignore


def _inv(a: Mat) -> Mat:
    d = _det(a)
    c = _cof(a)
    return tuple(tuple(c[j][i] / d for j in range(3)) for i in range(3))  # type: ignore


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


@dataclass
class Affine:
    a: Mat = IDENT
    t: tuple[float, float, float] = ZERO

    def then(self, other: Affine) -> Affine:
        """This frame followed by ``other`` given in this frame's coordinates (the additive A...
        instructions): parent = A (A' p + t') + t."""
        t2 = _apply(self.a, other.t)
        return Affine(_mul(self.a, other.a), (self.t[0] + t2[0], self.t[1] + t2[1], self.t[2] + t2[2]))

    def identity(self) -> bool:
        return self.a == IDENT and self.t == ZERO
