"""Boundary checks and window helpers shared by the spectrum modules (no plotting)."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from ..errors import Problems

#: Windows offered by the spectrum functions. ``rectangular`` is exact for a record of
#: whole periods; ``flattop`` keeps the amplitude error of a tone between two bins
#: below about 0.12 % (scalloping, measured in ``tests/test_spectrum_orders.py``);
#: ``hann`` resolves close tones better but loses up to about 15 % between bins.
WINDOWS = ("rectangular", "hann", "flattop")


def window(name: str, n: int) -> np.ndarray:
    """Periodic (DFT-even) window of ``n`` samples, shape (n,)."""
    if name == "rectangular":
        return np.ones(n)
    from scipy.signal import windows

    return getattr(windows, name)(n, sym=False)


def fast_length(n: int, max_prime: int = 31) -> int:
    """``n`` if its prime factors are all <= ``max_prime`` (pocketfft is fast for
    those; a large prime factor costs about 15x), else the next 5-smooth length.
    Keeping ``n`` keeps a resampling grid on the input samples where they allow."""
    m, f = n, 2
    while f * f <= m:
        while m % f == 0:
            m //= f
        f += 1
    largest = max(m, f - 1) if m > 1 else f - 1
    if largest <= max_prime:
        return n
    from scipy.fft import next_fast_len

    return next_fast_len(n, real=True)


def peak_spectrum(y: np.ndarray, window_name: str) -> tuple[np.ndarray, np.ndarray]:
    """Single-sided peak amplitudes and cosine phases of records along the last axis.

    ``y``: shape (..., n). Returns (amplitudes, phases), shape (..., n // 2 + 1):
    A_k = 2 |X_k| / (n mean(w)) for 0 < k < n/2, |X_k| / (n mean(w)) at k = 0 and at
    the Nyquist bin (n even); phase = arg X_k. With a window other than
    ``rectangular`` the order-0 bin is the record's mean.
    """
    n = y.shape[-1]
    w = window(window_name, n)
    # With a tapering window the mean is taken out first and reported at order 0
    # as it is: its leakage would otherwise cover the lowest orders (a flat top's
    # main lobe spans +-5 bins), where a mesh force's large mean swamps them.
    mean = y.mean(axis=-1, keepdims=True) if window_name != "rectangular" else 0.0
    spec = np.fft.rfft((y - mean) * w, axis=-1) / (n * float(w.mean()))
    if window_name != "rectangular":
        spec[..., :1] = mean
    amps = 2.0 * np.abs(spec)
    amps[..., 0] *= 0.5
    if n % 2 == 0:
        amps[..., -1] *= 0.5
    return amps, np.angle(spec)


class ArrayRecord:
    """Mixin for frozen dataclasses with ndarray fields named in ``_arrays``:
    ``to_dict()`` (plain JSON: arrays as lists) and ``from_dict()``."""

    _arrays: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """Plain-JSON form (lists and numbers)."""
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        for k in self._arrays:
            d[k] = d[k].tolist()
        return d

    @classmethod
    def from_dict(cls, data):
        """Inverse of :meth:`to_dict`."""
        d = dict(data)
        for k in cls._arrays:
            d[k] = np.asarray(d[k], dtype=float)
        return cls(**d)


def real_1d(problems: Problems, path: str, value, *, min_len: int = 2) -> np.ndarray | None:
    """``value`` as a finite float array of shape (n,), n >= ``min_len``; else a problem."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        problems.add(path, _short(value), "must be a 1-D array of real numbers")
        return None
    if arr.ndim != 1 or arr.size < min_len:
        problems.add(path, f"array of shape {arr.shape}", f"must be 1-D with >= {min_len} samples")
        return None
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        problems.add(path, f"{bad} non-finite values", "must be finite (no NaN or inf)")
        return None
    return arr


def strictly_increasing(problems: Problems, path: str, arr: np.ndarray | None) -> bool:
    """Record a problem unless ``arr`` increases strictly."""
    if arr is None:
        return False
    d = np.diff(arr)
    if np.any(d <= 0):
        i = int(np.argmax(d <= 0))
        problems.add(
            path,
            f"[{i}] = {arr[i]:g}, [{i + 1}] = {arr[i + 1]:g}",
            "must increase strictly (time, or angle at positive speed)",
        )
        return False
    return True


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
