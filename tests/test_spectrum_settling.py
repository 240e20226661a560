"""Settling check against a decaying transient whose windowed spectrum is analytic."""

from __future__ import annotations

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.spectrum import settling


def windowed_amplitude(order: float, tau: float, a: float, length: float) -> float:
    """Peak amplitude at ``order`` of exp(-r/tau) cos(2 pi order r) over [a, a + L],
    from the continuous Fourier integral: |(1/L) (I(1/tau) + I(1/tau + 4 pi i o))|,
    I(s) = (exp(-a s) - exp(-(a + L) s)) / s."""

    def integral(s):
        return (np.exp(-a * s) - np.exp(-(a + length) * s)) / s

    return abs((integral(1 / tau) + integral(1 / tau + 4j * np.pi * order)) / length)


def test_periodic_record_is_settled():
    rev = np.arange(12 * 512) / 512.0
    x = 2.0 * np.cos(2 * np.pi * 29 * rev) + 0.5 * np.cos(2 * np.pi * 4 * rev + 1.0)
    s = settling(rev / 30.0, x, [4, 29], speed_rpm=1800.0, n_periods=3)
    assert s.settled and s.change < 1e-12
    np.testing.assert_allclose(s.late, [0.5, 2.0], rtol=1e-12)
    assert s.revs == 3.0


def test_decaying_transient_is_measured():
    # Order 4 decays with tau = 3 revolutions under a steady mesh order of 2.
    # Windows [8, 10] and [10, 12] revolutions; expected amplitudes from the
    # continuous integral (the DFT is its rectangle rule at 512 samples per
    # revolution: relative error 6.5e-4 measured; bound 2e-3).
    tau = 3.0
    rev = np.arange(12 * 512) / 512.0
    x = 2.0 * np.cos(2 * np.pi * 29 * rev) + np.exp(-rev / tau) * np.cos(2 * np.pi * 4 * rev)
    s = settling(rev / 30.0, x, [4, 29], speed_rpm=1800.0, n_periods=2)
    early = windowed_amplitude(4, tau, 8.0, 2.0)
    late = windowed_amplitude(4, tau, 10.0, 2.0)
    assert s.early[0] == pytest.approx(early, rel=2e-3)
    assert s.late[0] == pytest.approx(late, rel=2e-3)
    assert s.change == pytest.approx((early - late) / 2.0, rel=2e-3)
    assert not s.settled  # 1.23 % change against the 1 % default
    assert settling(rev / 30.0, x, [4, 29], speed_rpm=1800.0, n_periods=2, tolerance=0.05).settled


def test_tracked_by_angle_matches_constant_speed():
    # The same record tracked by its angle (resampled path) gives the same check
    # within the resampling accuracy (bound 1e-6 on the change).
    rev = np.arange(1, 12 * 512 + 1) / 512.0
    x = 2.0 * np.cos(2 * np.pi * 29 * rev) + np.exp(-rev / 3.0) * np.cos(2 * np.pi * 4 * rev)
    a = settling(rev / 30.0, x, [4, 29], speed_rpm=1800.0, n_periods=2)
    b = settling(rev / 30.0, x, [4, 29], angle=2 * np.pi * rev, n_periods=2)
    assert b.change == pytest.approx(a.change, abs=1e-6)


def test_bad_input():
    t = np.linspace(0, 1, 100)
    with pytest.raises(InputError) as err:
        settling(t, t, [], speed_rpm=60.0, n_periods=0, tolerance=-1)
    assert {p.path for p in err.value.problems} == {"orders", "n_periods", "tolerance"}
