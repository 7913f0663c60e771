"""Program frames: the one affine map type for every rotation, mirroring, scaling and offset a
program switches on (``q = L p + t``: program coordinates p -> machine coordinates q)."""
from __future__ import annotations

import math
from dataclasses import dataclass

Mat = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
IDENTITY: Mat = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
ZERO = (0.0, 0.0, 0.0)


def mat_vec(L, v) -> tuple:
    """``L v``."""
    return tuple(L[i][0] * v[0] + L[i][1] * v[1] + L[i][2] * v[2] for i in range(3))


def mat_mul(A, B) -> tuple:
    """``A B``."""
    return tuple(tuple(sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def det(a: Mat) -> float:
    """The determinant of ``a``."""
    return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))


def cofactor(a: Mat) -> Mat:
    """The cofactor matrix: maps a plane's normal to the normal of its image, orientation kept
    (det(A) A^-T)."""
    def c(i, j):
        r = [k for k in range(3) if k != i]
        s = [k for k in range(3) if k != j]
        return (-1) ** (i + j) * (a[r[0]][s[0]] * a[r[1]][s[1]] - a[r[0]][s[1]] * a[r[1]][s[0]])
    return tuple(tuple(c(i, j) for j in range(3)) for i in range(3))  # type: ignore


def inverse(a: Mat) -> Mat:
    """``a^-1`` of any invertible matrix (scaling frames included), by cofactors."""
    d = det(a)
    c = cofactor(a)
    return tuple(tuple(c[j][i] / d for j in range(3)) for i in range(3))  # type: ignore


def turn(deg: float, a: int, c: int) -> Mat:
    """The rotation by ``deg`` degrees in the plane of axes ``a`` -> ``c`` (positive from a towards c:
    counter-clockwise in G17 seen from +Z); whole quarter turns are exact."""
    r = math.radians(deg % 360.0)
    co, si = math.cos(r), math.sin(r)
    if deg % 90.0 == 0.0:
        co, si = round(co), round(si)
    rows = [list(row) for row in IDENTITY]
    rows[a][a], rows[a][c], rows[c][a], rows[c][c] = co, -si, si, co
    return tuple(tuple(row) for row in rows)


@dataclass(frozen=True)
class Affine:
    """``q = L p + t``. Frames compose with ``then``; ``Affine()`` is the identity."""

    L: Mat = IDENTITY
    t: tuple[float, float, float] = ZERO

    @staticmethod
    def rotation(deg: float, a: int, c: int, centre=ZERO) -> Affine:
        """A rotation by ``deg`` in the plane a -> c (see turn) about the point ``centre``."""
        R = turn(deg, a, c)
        rc = mat_vec(R, centre)
        return Affine(R, tuple(centre[i] - rc[i] for i in range(3)))

    @staticmethod
    def mirror(axes) -> Affine:
        """Mirroring of the axes whose flag in ``axes`` (X, Y, Z) is true."""
        return Affine(tuple(tuple((-1.0 if axes[i] else 1.0) if i == j else 0.0 for j in range(3)) for i in range(3)))

    def then(self, inner: Affine) -> Affine:
        """This frame applied after ``inner``: p -> self(inner(p))."""
        lt = mat_vec(self.L, inner.t)
        return Affine(mat_mul(self.L, inner.L), tuple(lt[i] + self.t[i] for i in range(3)))

    def shifted(self, d) -> Affine:
        """The frame followed by the translation ``d``."""
        return Affine(self.L, tuple(self.t[i] + d[i] for i in range(3)))

    def apply(self, p) -> tuple:
        """Machine coordinates of the program point ``p``."""
        q = mat_vec(self.L, p)
        return (q[0] + self.t[0], q[1] + self.t[1], q[2] + self.t[2])

    def linear(self, v) -> tuple:
        """The direction ``v`` mapped (no translation)."""
        return mat_vec(self.L, v)

    def identity(self) -> bool:
        """Whether the frame changes nothing."""
        return self.L == IDENTITY and self.t == ZERO

    def inverse_linear(self, v) -> tuple:
        """The direction ``v`` mapped back (any invertible L, scaling included)."""
        return v if self.L == IDENTITY else mat_vec(inverse(self.L), v)

    def inverse_apply(self, q) -> list:
        """Program coordinates of the machine point ``q`` (L orthogonal: rotations and mirrorings)."""
        L, t = self.L, self.t
        d = (q[0] - t[0], q[1] - t[1], q[2] - t[2])
        return [L[0][i] * d[0] + L[1][i] * d[1] + L[2][i] * d[2] for i in range(3)]

    def plane_flips(self, a: int, c: int) -> bool:
        """Whether the frame reverses the turning sense in the plane of axes a, c (a mirrored plane)."""
        L = self.L
        return L[a][a] * L[c][c] - L[a][c] * L[c][a] < 0
