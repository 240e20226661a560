"""Waterfall: spectra against speed, in orders or in frequency.

Two ways to build one:

- :func:`waterfall` stacks order spectra of a speed sweep (one steady-state run per
  speed, each analysed by :func:`gearbox.spectrum.order_spectrum`);
- :func:`runup_waterfall` cuts one run-up record into blocks, each block's
  spectrum at the speed in the block's middle: blocks of equal *revolutions* after angle
  resampling for an order axis (order tracking), blocks of equal *time* for a
  frequency axis. Windowed (flat top by default: the block holds no whole period).

Amplitudes are single-sided peak amplitudes (see :mod:`gearbox.spectrum.orders`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import Problems
from ._arrays import (
    WINDOWS,
    ArrayRecord,
    fast_length,
    peak_spectrum,
    real_1d,
    strictly_increasing,
)
from .orders import OrderSpectrum, revolutions

__all__ = ["Waterfall", "runup_waterfall", "waterfall"]

AXES = ("order", "frequency")


@dataclass(frozen=True, eq=False)
class Waterfall(ArrayRecord):
    """Spectra against speed.

    Attributes
    ----------
    speeds_rpm : ndarray, shape (n_speeds,)
        Reference (pinion) speed of each spectrum (rpm).
    axis : str
        ``order`` (``bins`` in cycles per revolution) or ``frequency`` (Hz).
    bins : ndarray, shape (n_bins,)
        Orders or frequencies (Hz), shared by all spectra.
    amplitudes : ndarray, shape (n_speeds, n_bins)
        Single-sided peak amplitudes, in ``unit``.
    unit, name, window : str
    """

    speeds_rpm: np.ndarray
    axis: str
    bins: np.ndarray
    amplitudes: np.ndarray
    unit: str
    name: str
    window: str

    _arrays: ClassVar[tuple[str, ...]] = ("speeds_rpm", "bins", "amplitudes")

    def frequencies_hz(self) -> np.ndarray:
        """Frequency (Hz) of every cell, shape (n_speeds, n_bins)."""
        if self.axis == "frequency":
            return np.broadcast_to(self.bins, self.amplitudes.shape).copy()
        return np.outer(self.speeds_rpm / 60.0, self.bins)

    def orders(self) -> np.ndarray:
        """Order of every cell, shape (n_speeds, n_bins)."""
        if self.axis == "order":
            return np.broadcast_to(self.bins, self.amplitudes.shape).copy()
        return np.outer(60.0 / self.speeds_rpm, self.bins)

    def order_cut(self, order: float) -> np.ndarray:
        """Amplitude of one order against speed, shape (n_speeds,).

        On an order axis with a rectangular window (whole periods) the order's own
        bin; otherwise, per speed, the largest amplitude among the nearest bin and
        its two neighbours (a tone between bins has its flat-top maximum on one of
        them). NaN where the order lies outside the bins.
        """
        if self.axis == "order":
            target = np.full(self.speeds_rpm.shape, float(order))
        else:
            target = float(order) * self.speeds_rpm / 60.0
        step = float(self.bins[1] - self.bins[0])
        out = np.empty(self.speeds_rpm.shape)
        reach = 0 if (self.axis == "order" and self.window == "rectangular") else 1
        for i, c in enumerate(target):
            k = int(round((c - self.bins[0]) / step))
            lo, hi = max(k - reach, 0), min(k + reach + 1, self.bins.size)
            out[i] = self.amplitudes[i, lo:hi].max() if lo < hi else np.nan
        return out


def waterfall(
    spectra: Sequence[OrderSpectrum], speeds_rpm=None, *, max_order: float | None = None
) -> Waterfall:
    """Stack order spectra of a speed sweep into an order waterfall.

    Parameters
    ----------
    spectra : sequence of OrderSpectrum
        One per speed. With equal ``revs`` the spectra are stacked as they are;
        otherwise each is rebinned onto the coarsest order grid (1 / min revs) by
        peak hold: a target bin takes the largest amplitude of the source bins
        nearest to it, so that line heights survive (records of slightly different
        length, as angle tracking of a vibrating shaft gives, or of different
        numbers of periods).
    speeds_rpm : array, shape (n_speeds,), optional
        Speed of each spectrum (rpm); default: each spectrum's ``mean_speed_rpm``.
    max_order : float, optional
        Keep orders up to this; default: the highest order all spectra share.
    """
    p = Problems()
    if len(spectra) < 1:
        p.add("spectra", [], "must hold at least one OrderSpectrum")
        p.raise_if_any("waterfall")
    for i, s in enumerate(spectra):
        if not isinstance(s, OrderSpectrum):
            p.add(f"spectra[{i}]", type(s).__name__, "must be an OrderSpectrum")
    if speeds_rpm is None:
        speeds = np.array([getattr(s, "mean_speed_rpm", np.nan) for s in spectra], dtype=float)
    else:
        speeds = real_1d(p, "speeds_rpm", speeds_rpm, min_len=1)
        if speeds is not None and speeds.size != len(spectra):
            p.add(
                "speeds_rpm",
                f"{speeds.size} speeds",
                f"must have one speed per spectrum ({len(spectra)})",
            )
    p.raise_if_any("waterfall")
    revs = min(s.revs for s in spectra)
    top = min(float(s.orders[-1]) for s in spectra)
    if max_order is not None:
        top = min(top, float(max_order))
    n = int(math.floor(top * revs + 1e-9)) + 1
    if all(math.isclose(s.revs, revs, rel_tol=1e-9) for s in spectra):
        amps = np.stack([s.amplitudes[:n] for s in spectra])
    else:
        amps = np.zeros((len(spectra), n))
        for i, s in enumerate(spectra):
            k = np.rint(s.orders * revs).astype(int)
            keep = k < n
            np.maximum.at(amps[i], k[keep], s.amplitudes[keep])
    windows = {s.window for s in spectra}
    first = spectra[0]
    return Waterfall(
        speeds_rpm=np.asarray(speeds, dtype=float),
        axis="order",
        bins=np.arange(n) / revs,
        amplitudes=amps,
        unit=first.unit,
        name=first.name,
        window=first.window if len(windows) == 1 else "mixed",
    )


def runup_waterfall(
    t,
    x,
    *,
    speed_rpm,
    axis: str = "order",
    block: float,
    overlap: float = 0.5,
    window: str = "flattop",
    samples_per_rev: float | None = None,
    name: str = "",
    unit: str = "",
) -> Waterfall:
    """Waterfall of one run-up (or run-down) record cut into blocks.

    Parameters
    ----------
    t : array, shape (n,)
        Time (s), strictly increasing (uniform for ``axis='frequency'``).
    x : array, shape (n,)
        Signal, in ``unit``.
    speed_rpm : array, shape (n,)
        Reference (pinion) speed (rpm), > 0.
    axis : str
        ``order``: blocks of ``block`` revolutions after angle resampling (computed
        order tracking; bins in orders, spacing 1 / block). ``frequency``: blocks of
        ``block`` seconds (bins in Hz, spacing 1 / block).
    block : float
        Block length: revolutions (order axis) or seconds (frequency axis).
    overlap : float
        Fraction of a block shared with the next, in [0, 1).
    window : str
        ``flattop`` (default), ``hann`` or ``rectangular``.
    samples_per_rev : float, optional
        Angle resampling density (order axis); default: the finest input spacing.
    """
    p = Problems()
    t = real_1d(p, "t", t)
    x = real_1d(p, "x", x)
    s = real_1d(p, "speed_rpm", speed_rpm)
    strictly_increasing(p, "t", t)
    if t is not None and x is not None and x.shape != t.shape:
        p.add("x", f"shape {x.shape}", f"must have the shape of t, {t.shape}")
    if t is not None and s is not None and s.shape != t.shape:
        p.add("speed_rpm", f"shape {s.shape}", f"must have the shape of t, {t.shape}")
    elif s is not None and np.any(s <= 0):
        p.add("speed_rpm", f"min {s.min():g}", "must be > 0 everywhere")
    p.check(axis in AXES, "axis", axis, f"must be one of {AXES}")
    p.in_range("block", block, 0, None, lo_open=True)
    p.in_range("overlap", overlap, 0, 1, hi_open=True)
    p.check(window in WINDOWS, "window", window, f"must be one of {WINDOWS}")
    p.raise_if_any("run-up waterfall")

    revs = revolutions(t, speed_rpm=s)
    if axis == "order":
        spr = samples_per_rev if samples_per_rev is not None else 1.0 / float(np.diff(revs).min())
        # (1 - 1e-9): round-off in spr; a length with a fast DFT.
        per_block = fast_length(int(math.ceil(spr * block * (1 - 1e-9))))
        from scipy.interpolate import CubicSpline

        n_total = int(math.floor(revs[-1] * per_block / block + 1e-9))
        coord = np.arange(n_total) * (block / per_block)
        y = CubicSpline(revs, x)(coord)
        span = block
    else:
        h = float(np.diff(t).mean())
        if float(np.ptp(np.diff(t))) > 1e-9 * h:
            p.add("t", "non-uniform", "must be uniformly sampled for axis='frequency'")
            p.raise_if_any("run-up waterfall")
        per_block = int(round(block / h))
        y = x
        span = per_block * h
    hop = max(1, int(round(per_block * (1.0 - overlap))))
    starts = np.arange(0, y.size - per_block + 1, hop)
    if starts.size == 0:
        p.add(
            "block", block, f"is longer than the record ({y.size} samples, {per_block} per block)"
        )
        p.raise_if_any("run-up waterfall")
    idx = starts[:, None] + np.arange(per_block)[None, :]
    amps, _ = peak_spectrum(y[idx], window)
    # Speed of a block: the speed at its middle, where the (symmetric) window puts
    # its weight; the middle revolution (order axis) or the middle time (frequency).
    if axis == "order":
        t_mid = np.interp(coord[starts] + 0.5 * block, revs, t)
    else:
        t_mid = t[starts] + 0.5 * span
    speeds = np.interp(t_mid, t, s)
    bins = np.arange(amps.shape[1]) / span
    return Waterfall(speeds, axis, bins, amps, unit, name, window)
