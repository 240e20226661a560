"""Second-order forward differentiation in two variables ("jets"), numpy-vectorised.

A :class:`Jet` carries a value and its exact first and second partial derivatives
with respect to two surface parameters (here the axial position ``z`` and the rack
profile arc length ``u``)::

    data[0] = f, data[1] = f_z, data[2] = f_u, data[3] = f_zz, data[4] = f_zu, data[5] = f_uu

Arithmetic and ``sin``/``cos``/``sqrt`` follow the chain rule, so a closed-form
surface written with jets yields r, r_z, r_u, r_zz, r_zu, r_uu to rounding, which the
fundamental forms (curvatures) and the contact solver's Jacobian need.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Jet", "jet_variable", "jet_constant"]


class Jet:
    """Value with first and second derivatives in two variables; shape ``(6, ...)``."""

    __slots__ = ("d",)
    __array_priority__ = 1000

    def __init__(self, d):
        self.d = d

    # --- construction -------------------------------------------------------------
    @staticmethod
    def _lift(x) -> Jet:
        if isinstance(x, Jet):
            return x
        x = np.asarray(x, dtype=float)
        d = np.zeros((6,) + x.shape)
        d[0] = x
        return Jet(d)

    @property
    def val(self) -> np.ndarray:
        return self.d[0]

    # --- arithmetic ---------------------------------------------------------------
    def __add__(self, o):
        if isinstance(o, Jet):
            return Jet(self.d + o.d)
        d = self.d.copy()
        d[0] = d[0] + o
        return Jet(d)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.d)

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if not isinstance(o, Jet):
            return Jet(self.d * np.asarray(o, dtype=float))
        a, b = self.d, o.d
        return Jet(
            np.stack(
                [
                    a[0] * b[0],
                    a[1] * b[0] + a[0] * b[1],
                    a[2] * b[0] + a[0] * b[2],
                    a[3] * b[0] + 2 * a[1] * b[1] + a[0] * b[3],
                    a[4] * b[0] + a[1] * b[2] + a[2] * b[1] + a[0] * b[4],
                    a[5] * b[0] + 2 * a[2] * b[2] + a[0] * b[5],
                ]
            )
        )

    __rmul__ = __mul__

    def reciprocal(self) -> Jet:
        g = self.d
        i = 1.0 / g[0]
        i2, i3 = i * i, i * i * i
        return Jet(
            np.stack(
                [
                    i,
                    -g[1] * i2,
                    -g[2] * i2,
                    -g[3] * i2 + 2 * g[1] * g[1] * i3,
                    -g[4] * i2 + 2 * g[1] * g[2] * i3,
                    -g[5] * i2 + 2 * g[2] * g[2] * i3,
                ]
            )
        )

    def __truediv__(self, o):
        if not isinstance(o, Jet):
            return Jet(self.d / np.asarray(o, dtype=float))
        return self * o.reciprocal()

    def __rtruediv__(self, o):
        return self.reciprocal() * o

    def _unary(self, f0, f1, f2) -> Jet:
        """Chain rule for a scalar function with value f0, derivatives f1, f2."""
        g = self.d
        return Jet(
            np.stack(
                [
                    f0,
                    f1 * g[1],
                    f1 * g[2],
                    f2 * g[1] * g[1] + f1 * g[3],
                    f2 * g[1] * g[2] + f1 * g[4],
                    f2 * g[2] * g[2] + f1 * g[5],
                ]
            )
        )

    def sin(self) -> Jet:
        s, c = np.sin(self.d[0]), np.cos(self.d[0])
        return self._unary(s, c, -s)

    def cos(self) -> Jet:
        s, c = np.sin(self.d[0]), np.cos(self.d[0])
        return self._unary(c, -s, -c)

    def sqrt(self) -> Jet:
        r = np.sqrt(self.d[0])
        return self._unary(r, 0.5 / r, -0.25 / (r * r * r))


def jet_variable(x, which: int) -> Jet:
    """The independent variable ``which`` (0: z, 1: u) with value ``x``."""
    x = np.asarray(x, dtype=float)
    d = np.zeros((6,) + x.shape)
    d[0] = x
    d[1 + which] = 1.0
    return Jet(d)


def jet_constant(x) -> Jet:
    return Jet._lift(x)


def where(mask, a: Jet, b: Jet) -> Jet:
    """Elementwise choice between two jets (all derivatives follow the choice)."""
    return Jet(np.where(mask, a.d, b.d))
