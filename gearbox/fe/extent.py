"""Extent of the FE level's segment model: extrapolation to the whole gear.

The FE level (:class:`~gearbox.fe.compliance.FECompliance`) models the loaded teeth,
``neighbours`` unloaded teeth on each side and their rim, with the bore clamped and
the segment's two radial cut faces either clamped (too stiff: the cut faces hold the
rim) or free (too soft). The mesh stiffness of both sequences converges to that of
the whole gear as the segment grows, roughly geometrically (measured ratios 0.57-0.72
per added tooth on each side; ``benchmarks/fe_extent.py``), from above and from below.
:func:`extent_limit` extrapolates each sequence with Aitken's delta-squared process and
returns their mean and half their difference (within 1.2 % of the mean on the
paper's cases and 1.3 % on three parallel pairs, measured: the two estimates bracket
and check each other).
"""

from __future__ import annotations

import numpy as np

from ..errors import Problems

__all__ = ["aitken_limit", "extent_limit"]


def aitken_limit(values) -> np.ndarray:
    """Limit of geometrically converging sequences from their last three terms.

    values: shape (m, ...) with m >= 3 (the sequence along axis 0). Raises an
    :class:`~gearbox.errors.InputError` where the last three terms do not converge
    monotonically (ratio of successive differences outside (0, 1)).
    """
    a = np.asarray(values, dtype=float)
    p = Problems()
    p.check(a.ndim >= 1 and a.shape[0] >= 3, "values", a.shape, "needs at least 3 terms")
    p.raise_if_any("cannot extrapolate")
    d1 = a[-2] - a[-3]
    d2 = a[-1] - a[-2]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = d2 / d1
    bad = ~((r > 0) & (r < 1))
    if np.any(bad):
        p.add(
            "values",
            np.asarray(r)[bad].ravel()[:3].tolist(),
            "ratio of successive "
            "differences must lie in (0, 1) (a monotonically converging sequence)",
        )
        p.raise_if_any("cannot extrapolate")
    return a[-1] + d2 * r / (1 - r)


def extent_limit(clamped, free) -> tuple[np.ndarray, np.ndarray]:
    """Whole-gear estimate from a clamped-cut and a free-cut sequence of mesh stiffness
    (each shape (m, ...), growing segments): the mean of their Aitken limits and half
    their difference (an uncertainty)."""
    lc = aitken_limit(clamped)
    lf = aitken_limit(free)
    return 0.5 * (lc + lf), 0.5 * np.abs(lc - lf)
