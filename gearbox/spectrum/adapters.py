"""Thin adapters from drivetrain results to the spectrum functions.

Duck-typed: a time series is anything with ``time`` (s, shape (n_t,)), ``channels``
(name -> shape (n_t,)) and ``units`` (name -> unit), as
:class:`gearbox.drivetrain.timeseries.TimeSeries`; nothing here imports the
drivetrain package.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import Problems
from .campbell import ExcitationOrder
from .orders import OrderSpectrum, common_period_revs, order_spectrum

__all__ = ["DEFAULT_CHANNELS", "mode_table", "period_revs_of", "timeseries_spectra"]

#: Channels analysed by default when present: dynamic mesh force, dynamic
#: transmission error and bearing forces along the line of action.
DEFAULT_CHANNELS = (
    "mesh_force_N",
    "dynamic_transmission_error_m",
    "pinion_bearing_force_N",
    "gear_bearing_force_N",
)


def period_revs_of(excitations: Sequence[ExcitationOrder], *, max_denominator: int = 1000) -> float:
    """Common period (pinion revolutions) of all excitation orders, with the mesh
    order's own period 1: see :func:`gearbox.spectrum.common_period_revs`."""
    return common_period_revs(
        [1.0, *(e.order for e in excitations)], max_denominator=max_denominator
    )


def timeseries_spectra(
    ts,
    channels: Sequence[str] | None = None,
    *,
    speed_rpm: float | None = None,
    reference: str = "pinion_angle_rad",
    **options,
) -> dict[str, OrderSpectrum]:
    """Order spectra of a time series' channels.

    Parameters
    ----------
    ts : TimeSeries-like
        ``time``, ``channels``, ``units``.
    channels : sequence of str, optional
        Channel names; default: those of :data:`DEFAULT_CHANNELS` present.
    speed_rpm : float, optional
        Nominal constant pinion speed (rpm): the plain FFT where the samples allow.
        Default: track the angle channel ``reference`` (rad), which holds the
        vibration of the pinion as well.
    options
        Passed to :func:`gearbox.spectrum.order_spectrum` (``period_revs``,
        ``n_periods``, ``window``, ``samples_per_rev``).

    Returns
    -------
    dict name -> OrderSpectrum, in the channels' order.
    """
    p = Problems()
    available = dict(ts.channels)
    names = [c for c in DEFAULT_CHANNELS if c in available] if channels is None else list(channels)
    for c in names:
        p.check(c in available, "channels", c, f"must be one of {sorted(available)}")
    if speed_rpm is None:
        p.check(
            reference in available, "reference", reference, f"must be one of {sorted(available)}"
        )
    p.check(bool(names), "channels", names, "must name at least one channel")
    p.raise_if_any("time-series spectra")
    kw = {"speed_rpm": speed_rpm} if speed_rpm is not None else {"angle": available[reference]}
    units = dict(getattr(ts, "units", {}))
    return {
        c: order_spectrum(ts.time, available[c], name=c, unit=units.get(c, ""), **kw, **options)
        for c in names
    }


def mode_table(
    speeds_rpm,
    frequencies_hz,
    names: Sequence[str] | None = None,
    *,
    min_hz: float | None = None,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Modes for :func:`gearbox.spectrum.campbell` from eigenfrequencies per speed.

    Parameters
    ----------
    speeds_rpm : array, shape (n_speeds,)
        Pinion speeds (rpm), increasing.
    frequencies_hz : array, shape (n_speeds, n_modes)
        Eigenfrequencies (Hz) of the linearised model at each speed, ascending per
        row (modes are tracked by their rank).
    names : sequence of str, optional
        One per mode; default ``mode 1``, ``mode 2``, ...
    min_hz : float, optional
        Modes below this at every speed (rigid-body modes, whose computed
        frequency is round-off) are left out; default 1e-6 x the highest
        frequency in the table.
    """
    s = np.asarray(speeds_rpm, dtype=float)
    f = np.asarray(frequencies_hz, dtype=float)
    if f.ndim == 1:
        f = f[:, None]
    p = Problems()
    p.check(
        s.ndim == 1 and s.size >= 2, "speeds_rpm", f"shape {s.shape}", "must be 1-D, >= 2 speeds"
    )
    p.check(
        f.shape[0] == s.size, "frequencies_hz", f"shape {f.shape}", f"must be ({s.size}, n_modes)"
    )
    if names is not None:
        p.check(len(names) == f.shape[1], "names", list(names), f"must have {f.shape[1]} names")
    p.raise_if_any("mode table")
    names = list(names) if names is not None else [f"mode {j + 1}" for j in range(f.shape[1])]
    if min_hz is None:
        min_hz = 1e-6 * float(np.max(f))
    return {names[j]: (s, f[:, j]) for j in range(f.shape[1]) if np.any(f[:, j] >= min_hz)}
