"""Order spectra over settled whole periods, with order tracking where the speed varies.

An *order* is a number of cycles per revolution of a reference shaft (here usually
the pinion, which turns at engine speed): the mesh order of the pinion is N_1, the
firing order of a 4-stroke engine with z cylinders is z/2, the blade-pass order of a
propeller behind the gear is blades x N_1 / N_2.

Method (computed order tracking, Fyfe and Munck, "Analysis of computed order
tracking", Mech. Syst. Signal Process. 11(2), 1997):

1. The reference shaft's revolutions rev(t) come from its angle (rad) or from its
   speed (rpm, constant, or sampled and integrated by Simpson's rule).
2. The analysed record is the *last* ``n_periods`` whole periods of
   ``period_revs`` revolutions each (the settled part of a simulation): N samples
   ending on the last input sample, which the DFT treats as N steps of a periodic
   record. An input one step short of a further whole period (samples at k dt,
   k = 1..n, as a simulation writes them; detected within 1.5 steps) counts that
   period too, closed by periodicity: x(rev_0 + record) = x(rev_0).
3. When the speed is constant, the sampling uniform and one period an integer number
   of samples, the samples are used as they are ("fft"). Otherwise the signal is
   resampled at equal angle steps by a cubic spline through (rev_i, x_i)
   ("angle-resampled"), a whole number of samples per period.
4. One real DFT of the windowed record. Scaling: single-sided *peak* amplitude,
   A_k = 2 |X_k| / (N * mean(w)) for 0 < k < N/2 and |X_k| / (N * mean(w)) at k = 0
   (the mean) and at the Nyquist bin; the phase is that of a cosine,
   x(rev) = sum_k A_k cos(2 pi o_k (rev - rev_0) + phase_k), rev_0 the first
   (resampled) sample of the analysed record, at ``start_time``; the record ends on
   the last input sample.

Window: ``rectangular`` for whole periods (every periodic component with a whole
number of cycles in the record falls exactly on a bin: no leakage, exact amplitude);
``flattop`` when the period is not known (``period_revs=None``): a tone between two
bins then keeps its amplitude within about 0.12 % (scipy's 5-term flat top window,
D'Antona and Ferrero, "Digital Signal Processing for Measurement Systems", 2006, p. 70);
the mean is taken out before a tapering window and reported at order 0.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import ClassVar

import numpy as np

from ..errors import InputError, Problems
from ._arrays import (
    WINDOWS,
    ArrayRecord,
    fast_length,
    peak_spectrum,
    real_1d,
    strictly_increasing,
)

__all__ = ["OrderSpectrum", "common_period_revs", "order_spectra", "order_spectrum", "revolutions"]

#: Upper bound on the resampled record length (samples), a guard against a speed
#: that starts near zero making the finest angle step tiny.
MAX_SAMPLES = 2**24


@dataclass(frozen=True, eq=False)
class OrderSpectrum(ArrayRecord):
    """Single-sided order spectrum of one signal.

    Attributes
    ----------
    orders : ndarray, shape (n_bins,)
        Orders (cycles per revolution of the reference shaft), k / ``revs``.
    amplitudes : ndarray, shape (n_bins,)
        Single-sided peak amplitude, in ``unit``; ``amplitudes[0]`` is |mean|.
    phases : ndarray, shape (n_bins,)
        Cosine phase (rad) at the start of the analysed record.
    unit : str
        Unit of the signal (SI), e.g. ``"N"``.
    name : str
        Name of the signal (channel).
    window : str
        Window used: ``rectangular``, ``hann`` or ``flattop``.
    n_periods : int
        Whole periods analysed (1 when ``period_revs`` is None).
    period_revs : float or None
        Period of the signal in reference revolutions; None when unknown.
    revs : float
        Reference revolutions analysed; the order resolution is 1 / revs.
    mean_speed_rpm : float
        Mean reference speed over the record (rpm).
    start_time : float
        Time (s) of the first sample of the analysed record.
    samples : int
        Samples in the DFT.
    method : str
        ``fft`` (samples used as they are) or ``angle-resampled``.
    """

    orders: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray
    unit: str
    name: str
    window: str
    n_periods: int
    period_revs: float | None
    revs: float
    mean_speed_rpm: float
    start_time: float
    samples: int
    method: str

    _arrays: ClassVar[tuple[str, ...]] = ("orders", "amplitudes", "phases")

    @property
    def resolution(self) -> float:
        """Order spacing of the bins, 1 / revs."""
        return 1.0 / self.revs

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Bin frequencies at the mean speed (Hz), shape (n_bins,)."""
        return self.orders * self.mean_speed_rpm / 60.0

    def amplitude_at(self, order: float) -> float:
        """Peak amplitude of the component at ``order`` (cycles/rev), in ``unit``.

        Rectangular window: the bin nearest to ``order``, which must lie within a
        quarter bin of it (a whole-period record puts every periodic component on a
        bin). Other windows: the largest of the nearest bin and its two neighbours
        (a tone between bins has its flat-top maximum on one of them).
        """
        k = float(order) * self.revs
        i = int(round(k))
        if not 0 <= i < self.orders.size:
            raise _order_error(order, self.orders[-1])
        if self.window == "rectangular":
            if abs(k - i) > 0.25:
                raise _off_bin_error(order, self.resolution)
            return float(self.amplitudes[i])
        lo, hi = max(i - 1, 0), min(i + 2, self.orders.size)
        return float(self.amplitudes[lo:hi].max())


def _order_error(order, max_order) -> InputError:
    p = Problems()
    p.add("order", order, f"must be in [0, {max_order:g}] (the spectrum's order range)")
    return InputError(p.items, "order spectrum")


def _off_bin_error(order, resolution) -> InputError:
    p = Problems()
    p.add(
        "order",
        order,
        f"is not on the order grid (resolution {resolution:g}); analyse whole periods "
        "of this order (see common_period_revs) or use window='flattop'",
    )
    return InputError(p.items, "order spectrum")


def common_period_revs(orders: Iterable[float], *, max_denominator: int = 1000) -> float:
    """Shortest number of reference revolutions holding whole cycles of every order.

    Each order is written as a reduced fraction p/q (q <= ``max_denominator``); the
    period is lcm(q). Example: half orders (q = 2) and the blade-pass order of a
    3-blade propeller behind a 29:45 pair, 3 x 29/45 = 29/15 (q = 15), give 30 pinion
    revolutions.

    Raises :class:`InputError` for an order that is not such a fraction within 1e-9.
    """
    p = Problems()
    period = 1
    for i, o in enumerate(orders):
        o = float(o)
        if not math.isfinite(o) or o < 0:
            p.add(f"orders[{i}]", o, "must be finite and >= 0")
            continue
        f = Fraction(o).limit_denominator(max_denominator)
        if abs(float(f) - o) > 1e-9 * max(1.0, o):
            p.add(
                f"orders[{i}]",
                o,
                f"must be a fraction with denominator <= {max_denominator} "
                "(else the signal has no common period: use period_revs=None)",
            )
            continue
        period = math.lcm(period, f.denominator)
    p.raise_if_any("common period")
    return float(period)


def revolutions(t, *, speed_rpm=None, angle=None) -> np.ndarray:
    """Reference revolutions since ``t[0]``, shape (n,).

    Parameters
    ----------
    t : array, shape (n,)
        Time (s), strictly increasing.
    speed_rpm : float or array, shape (n,)
        Reference speed (rpm), > 0; a sampled speed is integrated by the cumulative
        Simpson rule (``scipy.integrate.cumulative_simpson``, error O(dt^4); exact
        for a speed cubic in time), the trapezoidal rule where scipy is older than
        1.12 or there are only 2 samples.
    angle : array, shape (n,)
        Reference angle (rad), strictly increasing. Give exactly one of the two.
    """
    t = np.asarray(t, dtype=float)
    if angle is not None:
        a = np.asarray(angle, dtype=float)
        return (a - a[0]) / (2.0 * np.pi)
    s = np.asarray(speed_rpm, dtype=float)
    if s.ndim == 0:
        return float(s) / 60.0 * (t - t[0])
    try:
        from scipy.integrate import cumulative_simpson
    except ImportError:  # scipy < 1.12
        cumulative_simpson = None
    if cumulative_simpson is not None and s.size >= 3:
        return cumulative_simpson(s / 60.0, x=t, initial=0.0)
    from scipy.integrate import cumulative_trapezoid

    return cumulative_trapezoid(s / 60.0, t, initial=0.0)


def _check(t, x, speed_rpm, angle, period_revs, n_periods, window_name, samples_per_rev):
    p = Problems()
    t = real_1d(p, "t", t)
    x = real_1d(p, "x", x)
    strictly_increasing(p, "t", t)
    if t is not None and x is not None and t.shape != x.shape:
        p.add("x", f"shape {x.shape}", f"must have the shape of t, {t.shape}")
    if (speed_rpm is None) == (angle is None):
        p.add("speed_rpm / angle", "both" if angle is not None else "neither", "give exactly one")
    if speed_rpm is not None:
        s = np.asarray(speed_rpm, dtype=float)
        if s.ndim == 0:
            p.in_range("speed_rpm", float(s), 0, None, lo_open=True)
        else:
            s = real_1d(p, "speed_rpm", s)
            if s is not None and t is not None and s.shape != t.shape:
                p.add(
                    "speed_rpm",
                    f"shape {s.shape}",
                    f"must be a scalar or have the shape of t, {t.shape}",
                )
            elif s is not None and np.any(s <= 0):
                p.add("speed_rpm", f"min {s.min():g}", "must be > 0 everywhere (order tracking)")
    if angle is not None:
        a = real_1d(p, "angle", angle)
        if a is not None and t is not None and a.shape != t.shape:
            p.add("angle", f"shape {a.shape}", f"must have the shape of t, {t.shape}")
        elif a is not None:
            strictly_increasing(p, "angle", a)
    if period_revs is not None:
        if not isinstance(period_revs, int | float) or not math.isfinite(period_revs):
            p.add("period_revs", period_revs, "must be a positive number or None")
        else:
            p.in_range("period_revs", period_revs, 0, None, lo_open=True)
    if n_periods is not None:
        if period_revs is None:
            p.add("n_periods", n_periods, "needs period_revs (a known period)")
        elif not isinstance(n_periods, int | np.integer) or n_periods < 1:
            p.add("n_periods", n_periods, "must be an integer >= 1 or None (all whole periods)")
    if window_name not in ("auto", *WINDOWS):
        p.add("window", window_name, f"must be one of {('auto', *WINDOWS)}")
    if samples_per_rev is not None and not (
        isinstance(samples_per_rev, int | float) and samples_per_rev >= 4
    ):
        p.add("samples_per_rev", samples_per_rev, "must be a number >= 4 or None")
    p.raise_if_any("order spectrum")
    return t, x


def order_spectrum(
    t,
    x,
    *,
    speed_rpm=None,
    angle=None,
    period_revs: float | None = 1.0,
    n_periods: int | None = None,
    window: str = "auto",
    samples_per_rev: float | None = None,
    name: str = "",
    unit: str = "",
) -> OrderSpectrum:
    """Order spectrum of ``x(t)`` over the last whole periods of the record.

    Parameters
    ----------
    t : array, shape (n,)
        Time (s), strictly increasing.
    x : array, shape (n,)
        Signal, in ``unit``.
    speed_rpm : float or array, shape (n,)
        Reference shaft speed (rpm), > 0. A float means constant speed.
    angle : array, shape (n,)
        Reference shaft angle (rad), strictly increasing; instead of ``speed_rpm``.
    period_revs : float or None
        Period of the signal in reference revolutions (1 when all orders are whole
        numbers; see :func:`common_period_revs` for half orders and blade-pass
        orders). None: unknown; the whole record is analysed with a flat-top window.
    n_periods : int or None
        Whole periods to analyse, taken from the end of the record (the settled
        part); None: as many as the record holds.
    window : str
        ``auto`` (rectangular for whole periods, flattop when ``period_revs`` is
        None), ``rectangular``, ``hann`` or ``flattop``.
    samples_per_rev : float or None
        Samples per revolution after angle resampling; None: the finest spacing
        of the input over the analysed record. The highest order resolved is
        ``samples_per_rev / 2``. Accuracy of the cubic-spline resampling, measured
        on sums of cosines (tests/test_spectrum_orders.py): about 1.8e-3 relative
        amplitude error at 6 input samples per cycle, 3.5e-5 at 15.
    name, unit : str
        Channel name and its unit, carried into the result.

    Returns
    -------
    OrderSpectrum
    """
    t, x = _check(t, x, speed_rpm, angle, period_revs, n_periods, window, samples_per_rev)
    revs = revolutions(t, speed_rpm=speed_rpm, angle=angle)
    total = float(revs[-1])
    win = window if window != "auto" else ("flattop" if period_revs is None else "rectangular")

    # Plain FFT: constant speed, uniform sampling, whole samples per period. The n
    # samples x[-n:] then stand for n sample intervals (the DFT's periodic record).
    dt = np.diff(t)
    h = float(dt.mean())
    constant = speed_rpm is not None and np.ndim(speed_rpm) == 0
    plain = constant and float(np.ptp(dt)) <= 1e-9 * h
    if plain and period_revs is not None:
        m = period_revs * 60.0 / float(speed_rpm) / h
        plain = abs(m - round(m)) <= 1e-9 * m
        if plain:
            total = x.size * h * float(speed_rpm) / 60.0

    if period_revs is None:
        n_use = 1
        record = x.size * h * float(speed_rpm) / 60.0 if plain else total
    else:
        # An input that ends less than 1.5 sample steps short of a further whole
        # period (as a simulation records k dt for k = 1..n) counts it, closed
        # periodically below: x(rev_0 + record) = x(rev_0).
        reach = total if plain else total + 1.5 * float(revs[-1] - revs[-2])
        available = int(math.floor(reach / period_revs + 1e-9))
        n_use = available if n_periods is None else int(n_periods)
        if available < 1 or n_use > available:
            p = Problems()
            p.add(
                "n_periods" if n_periods is not None else "period_revs",
                n_periods if n_periods is not None else period_revs,
                f"the record covers {total:.6g} revolutions: at most {available} whole "
                f"periods of {period_revs:g} revolutions",
            )
            p.raise_if_any("order spectrum")
        record = n_use * float(period_revs)
    if plain:
        n = x.size if period_revs is None else n_use * int(round(m))
        xs = x[-n:]
        start_time = float(t[-n])
        duration = n * h
        method = "fft"
    else:
        start = total - record
        if samples_per_rev is None:
            i0 = max(int(np.searchsorted(revs, start)) - 1, 0)
            spr = 1.0 / float(np.diff(revs[i0:]).min())
        else:
            spr = float(samples_per_rev)
        # At least spr samples per revolution, a length with a fast DFT.
        per_period = fast_length(
            int(math.ceil(spr * (period_revs if period_revs is not None else record) * (1 - 1e-9)))
        )
        n = per_period * n_use
        if n > MAX_SAMPLES:
            p = Problems()
            p.add("samples_per_rev", samples_per_rev, f"gives {n} samples, more than {MAX_SAMPLES}")
            p.raise_if_any("order spectrum")
        from scipy.interpolate import CubicSpline

        if start >= -1e-12 * record:
            # N equal steps ending on the last input sample, like the plain path.
            grid = start + (np.arange(n) + 1) * (record / n)
            xs = CubicSpline(revs, x)(grid)
            start_time = float(np.interp(grid[0], revs, t))
            duration = float(t[-1]) - float(np.interp(start, revs, t))
        else:
            # Periodic closure: the whole record is one stretch of whole periods
            # whose last sample lies less than 1.5 steps before the end; a
            # periodic spline through (rev_i, x_i) and (record, x_0) bridges it.
            gap = record - total
            grid = np.arange(n) * (record / n)
            xs = CubicSpline(np.r_[revs, record], np.r_[x, x[0]], bc_type="periodic")(grid)
            start_time = float(t[0])
            duration = float(t[-1] - t[0]) + gap * float(t[-1] - t[-2]) / float(revs[-1] - revs[-2])
        method = "angle-resampled"

    amps, phases = peak_spectrum(xs, win)
    return OrderSpectrum(
        orders=np.arange(amps.size) / record,
        amplitudes=amps,
        phases=phases,
        unit=unit,
        name=name,
        window=win,
        n_periods=n_use,
        period_revs=None if period_revs is None else float(period_revs),
        revs=float(record),
        mean_speed_rpm=float(record / duration * 60.0),
        start_time=start_time,
        samples=int(n),
        method=method,
    )


def order_spectra(
    t, channels: Mapping[str, object], *, units: Mapping[str, str] | None = None, **options
):
    """:func:`order_spectrum` of several channels sampled at the same times.

    ``channels`` maps name -> array, shape (n,); ``units`` maps name -> unit;
    ``options`` are passed on. Returns dict name -> :class:`OrderSpectrum`.
    """
    units = units or {}
    return {
        k: order_spectrum(t, v, name=k, unit=units.get(k, ""), **options)
        for k, v in channels.items()
    }
