"""The involute function and its inverse, accurate for small angles.

``inv(a) = tan(a) - a`` loses every digit for small ``a`` when written that way
(both terms are nearly equal); below 0.05 rad a Taylor series is used instead.
The inverse is a bounded Newton iteration that raises when it does not converge.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, Problem

__all__ = ["inv", "inv_inverse"]

# tan(a) - a = a^3/3 + 2a^5/15 + 17a^7/315 + 62a^9/2835 + 1382a^11/155925 + ...
_SERIES = (1 / 3, 2 / 15, 17 / 315, 62 / 2835, 1382 / 155925, 21844 / 6081075)


def inv(a):
    """Involute function inv(a) = tan(a) - a (rad), vectorised.

    Uses the Taylor series for |a| < 0.05 (truncation error below 1e-22 there), so
    relative accuracy is kept near 0.
    """
    a = np.asarray(a, dtype=float)
    a2 = a * a
    series = (
        a
        * a2
        * (
            _SERIES[0]
            + a2
            * (
                _SERIES[1]
                + a2 * (_SERIES[2] + a2 * (_SERIES[3] + a2 * (_SERIES[4] + a2 * _SERIES[5])))
            )
        )
    )
    out = np.where(np.abs(a) < 0.05, series, np.tan(a) - a)
    return out if out.ndim else float(out)


def inv_inverse(y, *, tol: float = 1e-15, max_iter: int = 30):
    """Angle a in [0, pi/2) with inv(a) = y (y >= 0), by bounded Newton iteration.

    Converged when the step is below ``tol`` (relative) or the residual reaches the
    rounding floor of ``tan(a) - a``. Raises :class:`InputError` for negative ``y`` or
    when neither happens within ``max_iter`` steps.
    """
    y = np.asarray(y, dtype=float)
    if np.any(y < 0) or not np.all(np.isfinite(y)):
        raise InputError(Problem("inv_inverse.y", y.tolist(), "must be finite and >= 0"))
    # starting value: cube-root series inversion, good for small y, fine for large
    a = np.minimum(np.cbrt(3.0 * y) * (1.0 - 0.2 * np.cbrt(3.0 * y) ** 2 / 1.0), 1.5)
    a = np.where(y > 0.3, np.arctan(y + 1.0), np.maximum(a, 0.0))
    for _ in range(max_iter):
        t = np.tan(a)
        f = inv(a) - y
        with np.errstate(invalid="ignore", divide="ignore"):
            step = f / (t * t)  # d inv / da = tan^2 a
        step = np.where(t == 0, 0.0, step)
        a_new = np.clip(a - step, 0.5 * a, 0.5 * (a + np.pi / 2))
        a_new = np.where(y == 0, 0.0, a_new)
        # converged: a small step, or a residual at the rounding floor of tan(a) - a
        # (one ulp of tan(a) bounds a to ~ulp/tan^2, which can exceed tol * a)
        floor = 4.0 * np.finfo(float).eps * (np.abs(t) + np.abs(a))
        done = (np.abs(a_new - a) <= tol * np.maximum(np.abs(a_new), 1e-300)) | (np.abs(f) <= floor)
        a = a_new
        if np.all(done):
            return a if a.ndim else float(a)
    raise InputError(
        Problem(
            "inv_inverse.y", y.tolist(), f"Newton iteration did not converge in {max_iter} steps"
        )
    )
