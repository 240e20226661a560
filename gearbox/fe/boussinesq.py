"""Elastic half-space (Boussinesq) displacements under a uniform rectangular pressure.

The local part of the contact compliance, which a finite-element mesh of a tooth
cannot resolve, comes from the half-space:

- surface: normal displacement at (x, y) of the surface under a uniform pressure p on
  the rectangle ``|x'| <= a, |y'| <= b``,
  ``w = (1 - nu^2) p / (pi E) * integral dA' / |r - r'|`` (Johnson, *Contact
  Mechanics*, 1985, eq. (3.21) integrated over the rectangle; Love, A.E.H., "Stress
  produced in a semi-infinite solid by pressure on part of the boundary", Phil.
  Trans. R. Soc. A 228 (1929) 377-420). The integral has the closed form
  ``F(x+a, y+b) - F(x+a, y-b) - F(x-a, y+b) + F(x-a, y-b)`` with
  ``F(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|)`` (``d^2 F / dX dY = 1/sqrt(X^2 + Y^2)``);
- below the surface: normal displacement at depth d under a point load P,
  ``u_z = P / (4 pi G) [d^2 / rho^3 + 2 (1 - nu) / rho]``, rho the distance to the
  load (Johnson 1985, eq. (3.22c)), integrated over the rectangle by Gauss-Legendre
  quadrature (smooth for d > 0).
"""

from __future__ import annotations

import numpy as np

__all__ = ["surface_deflection", "depth_deflection"]


def _F(X, Y):
    ax, ay = np.abs(X), np.abs(Y)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(ax > 0, X * np.arcsinh(Y / np.where(ax > 0, ax, 1.0)), 0.0)
        t2 = np.where(ay > 0, Y * np.arcsinh(X / np.where(ay > 0, ay, 1.0)), 0.0)
    return t1 + t2


def surface_deflection(x, y, a, b, youngs_modulus, poisson_ratio):
    """Normal surface displacement (m) per newton on a uniformly loaded rectangle.

    x, y: point on the surface relative to the rectangle centre (m), along its
    half-sides a and b (m). Arrays broadcast. Total load 1 N (p = 1 / (4 a b)).
    """
    x, y, a, b = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, a, b)))
    integral = _F(x + a, y + b) - _F(x + a, y - b) - _F(x - a, y + b) + _F(x - a, y - b)
    return (1 - poisson_ratio**2) / (np.pi * youngs_modulus) * integral / (4 * a * b)


_GX, _GW = np.polynomial.legendre.leggauss(8)


def depth_deflection(x, y, depth, a, b, youngs_modulus, poisson_ratio):
    """Normal displacement (m) at depth ``depth`` below (x, y) per newton on a
    uniformly loaded surface rectangle of half-sides a, b (m).

    8 x 8 Gauss-Legendre points over the rectangle; the integrand is smooth for
    depth > 0 and the rule is exact to 1e-4 relative for depth >= max(a, b) / 2
    (``tests/test_fe_boussinesq.py``). Arrays broadcast.
    """
    x, y, d, a, b = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, depth, a, b)))
    G = youngs_modulus / (2 * (1 + poisson_ratio))
    xs = a[..., None, None] * _GX[:, None]
    ys = b[..., None, None] * _GX[None, :]
    w = 0.25 * _GW[:, None] * _GW[None, :]
    dx = x[..., None, None] - xs
    dy = y[..., None, None] - ys
    dd = d[..., None, None]
    rho = np.sqrt(dx**2 + dy**2 + dd**2)
    uz = (dd**2 / rho**3 + 2 * (1 - poisson_ratio) / rho) / (4 * np.pi * G)
    return np.sum(w * uz, axis=(-2, -1))
