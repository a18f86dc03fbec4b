"""Second-order Taylor arithmetic: exact time derivatives through closed-form kinematics.

A :class:`Taylor2` carries a quantity and its first two time derivatives along a trajectory,
``(x, dx/dt, d²x/dt²)``, each an array over samples. Arithmetic and the few elementary functions
used by closed-form inverse kinematics propagate the derivatives exactly (chain rule), so a
closed-form position solver written with them also yields joint velocities and accelerations,
and, seeded with unit directions, its Jacobian. Plain floats and arrays mix freely with it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike


@dataclass(frozen=True)
class Taylor2:
    """Value ``v``, first derivative ``d1`` and second derivative ``d2`` (arrays that broadcast together).

    ``d1`` may have more leading rows than ``d2``: first derivatives along other directions too (a Jacobian's, as
    the closed-form kinematics seed them), whose second derivatives are not carried.
    """

    v: np.ndarray
    d1: np.ndarray
    d2: np.ndarray

    @staticmethod
    def constant(value: ArrayLike) -> Taylor2:
        """A quantity that does not vary: both derivatives are zero."""
        v = np.asarray(value, dtype=float)
        return Taylor2(v, np.zeros_like(v), np.zeros_like(v))

    def __add__(self, other: Taylor2 | ArrayLike) -> Taylor2:
        if not isinstance(other, Taylor2):  # a constant shifts the value only
            return Taylor2(self.v + other, self.d1, self.d2)
        return Taylor2(self.v + other.v, self.d1 + other.d1, self.d2 + other.d2)

    __radd__ = __add__

    def __neg__(self) -> Taylor2:
        return Taylor2(-self.v, -self.d1, -self.d2)

    def __sub__(self, other: Taylor2 | ArrayLike) -> Taylor2:
        if not isinstance(other, Taylor2):  # a constant shifts the value only
            return Taylor2(self.v - other, self.d1, self.d2)
        return Taylor2(self.v - other.v, self.d1 - other.d1, self.d2 - other.d2)

    def __rsub__(self, other: ArrayLike) -> Taylor2:
        return Taylor2(other - self.v, -self.d1, -self.d2)

    def __mul__(self, other: Taylor2 | ArrayLike) -> Taylor2:
        if not isinstance(other, Taylor2):  # a constant scales every term
            return Taylor2(self.v * other, self.d1 * other, self.d2 * other)
        rows = _second_rows(self.d2, other.d2)
        return Taylor2(
            self.v * other.v,
            self.d1 * other.v + self.v * other.d1,
            self.d2 * other.v + 2.0 * _cut(self.d1, rows) * _cut(other.d1, rows) + self.v * other.d2,
        )

    __rmul__ = __mul__

    def __truediv__(self, other: Taylor2 | ArrayLike) -> Taylor2:
        o = _lift(other)
        rows = _second_rows(self.d2, o.d2)
        c0 = self.v / o.v
        c1 = (self.d1 - c0 * o.d1) / o.v
        c2 = (self.d2 - 2.0 * _cut(c1, rows) * _cut(o.d1, rows) - c0 * o.d2) / o.v
        return Taylor2(c0, c1, c2)

    def __rtruediv__(self, other: ArrayLike) -> Taylor2:
        return _lift(other) / self


def _lift(x: Taylor2 | ArrayLike) -> Taylor2:
    return x if isinstance(x, Taylor2) else Taylor2.constant(x)


def _second_rows(*second: np.ndarray) -> int | None:
    """The leading rows that second derivatives of these shapes carry together (None: no rows, all of them)."""
    shape = np.broadcast_shapes(*(np.shape(each) for each in second))
    return shape[0] if len(shape) >= 2 else None


def _cut(first: np.ndarray, rows: int | None) -> np.ndarray:
    """First derivatives restricted to the leading ``rows`` that second derivatives carry (see :class:`Taylor2`)."""
    return first[:rows] if rows is not None and np.ndim(first) >= 2 and len(first) > rows else first


def sqrt(x: Taylor2) -> Taylor2:
    """Square root; the argument must be positive (derivatives are infinite at zero)."""
    x = _lift(x)
    c0 = np.sqrt(x.v)
    c1 = x.d1 / (2.0 * c0)
    rows = _second_rows(x.d2)
    c2 = (x.d2 - 2.0 * _cut(c1, rows) * _cut(c1, rows)) / (2.0 * c0)
    return Taylor2(c0, c1, c2)


def arctan2(y: Taylor2, x: Taylor2) -> Taylor2:
    """Four-quadrant arc tangent of ``y / x`` in rad."""
    y, x = _lift(y), _lift(x)
    rows = _second_rows(x.d2, y.d2)
    r2 = x.v * x.v + y.v * y.v
    c1 = (x.v * y.d1 - y.v * x.d1) / r2
    c2 = ((x.v * y.d2 - y.v * x.d2) / r2
          - 2.0 * _cut(c1, rows) * (x.v * _cut(x.d1, rows) + y.v * _cut(y.d1, rows)) / r2)
    return Taylor2(np.arctan2(y.v, x.v), c1, c2)
