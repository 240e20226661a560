"""Is the record settled? Order amplitudes of the last periods against the ones before.

A spectrum over "settled whole periods" assumes the response repeats. This check
makes the assumption measurable: the record's last ``n_periods`` periods and the
``n_periods`` periods before them each give an order spectrum (rectangular window,
:func:`gearbox.spectrum.order_spectrum`); the change of the amplitudes at the
orders of interest, relative to the largest of them, says how far the response
still drifts (a decaying start transient, a slow beat).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import Problems
from .orders import order_spectrum

__all__ = ["Settling", "settling"]


@dataclass(frozen=True, eq=False)
class Settling:
    """Amplitudes at ``orders`` in two consecutive windows of whole periods.

    Attributes
    ----------
    orders : ndarray, shape (n_orders,)
        Orders checked (cycles per reference revolution).
    early, late : ndarray, shape (n_orders,)
        Peak amplitudes (signal unit) in the earlier and in the last window.
    change : float
        max |late - early| / max(late): relative drift between the windows.
    tolerance : float
        ``settled`` is ``change <= tolerance``.
    revs : float
        Revolutions in each window.
    """

    orders: np.ndarray
    early: np.ndarray
    late: np.ndarray
    change: float
    tolerance: float
    revs: float

    @property
    def settled(self) -> bool:
        """True when the amplitudes changed by no more than ``tolerance``."""
        return bool(self.change <= self.tolerance)


def settling(
    t,
    x,
    orders: Sequence[float],
    *,
    speed_rpm=None,
    angle=None,
    period_revs: float = 1.0,
    n_periods: int = 1,
    tolerance: float = 0.01,
) -> Settling:
    """Compare the order amplitudes of the last two windows of ``n_periods`` periods.

    Parameters
    ----------
    t, x : arrays, shape (n,)
        Time (s) and signal, as for :func:`gearbox.spectrum.order_spectrum`.
    orders : sequence of float
        Orders to compare (each must lie on the grid of ``n_periods * period_revs``
        revolutions: whole cycles per window).
    speed_rpm, angle, period_revs
        The reference, as for :func:`gearbox.spectrum.order_spectrum`.
    n_periods : int
        Periods per window; the record needs 2 n_periods periods.
    tolerance : float
        Relative change accepted as settled (default 1 %).
    """
    p = Problems()
    o = np.asarray(orders, dtype=float)
    p.check(o.ndim == 1 and o.size >= 1, "orders", list(np.atleast_1d(o)), "must list >= 1 order")
    p.check(
        isinstance(n_periods, int) and n_periods >= 1, "n_periods", n_periods, "must be int >= 1"
    )
    p.in_range("tolerance", tolerance, 0, None)
    p.raise_if_any("settling check")
    opts = {"period_revs": period_revs, "n_periods": n_periods}
    late = order_spectrum(t, x, speed_rpm=speed_rpm, angle=angle, **opts)
    # The earlier record ends just before the last window starts; its last
    # n_periods whole periods are the window before (the plain FFT path takes
    # exactly the samples before; whole periods make the start phase irrelevant
    # to the amplitudes).
    t = np.asarray(t, dtype=float)
    h = float(np.median(np.diff(t)))
    i = int(np.searchsorted(t, late.start_time - 1e-6 * h, side="left"))  # round-off
    if angle is not None:
        ref = {"angle": np.asarray(angle, dtype=float)[:i]}
    elif np.ndim(speed_rpm) == 0:
        ref = {"speed_rpm": speed_rpm}
    else:
        ref = {"speed_rpm": np.asarray(speed_rpm, dtype=float)[:i]}
    early = order_spectrum(t[:i], np.asarray(x, dtype=float)[:i], **ref, **opts)
    a_late = np.array([late.amplitude_at(v) for v in o])
    a_early = np.array([early.amplitude_at(v) for v in o])
    scale = float(np.max(a_late)) or 1.0
    change = float(np.max(np.abs(a_late - a_early)) / scale)
    return Settling(o, a_early, a_late, change, float(tolerance), float(late.revs))
