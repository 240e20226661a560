"""Waterfalls against signals with known, speed-dependent amplitudes."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.spectrum import Waterfall, order_spectrum, runup_waterfall, waterfall


def mesh_amplitude(n_rpm):
    """A resonance-like amplitude curve of the mesh order (the known truth)."""
    return 1.0 + 2.0 / (1.0 + ((np.asarray(n_rpm) - 1500.0) / 200.0) ** 2)


def test_sweep_waterfall_order_cut_follows_the_amplitude_curve():
    # One steady run per speed, 12 revolutions at 2**9 samples per revolution
    # (plain FFT path): each spectrum is exact, so the order cut equals the
    # amplitude curve to round-off (bound 1e-9; the issue asks 0.5 %).
    speeds = np.linspace(600.0, 2600.0, 11)
    spectra = []
    for n in speeds:
        rev = np.arange(12 * 512) / 512.0
        t = rev * 60.0 / n
        x = mesh_amplitude(n) * np.cos(2 * np.pi * 29 * rev) + 0.3 * np.cos(2 * np.pi * 4 * rev)
        spectra.append(order_spectrum(t, x, speed_rpm=n, name="F_mesh", unit="N"))
    wf = waterfall(spectra, max_order=100.0)
    assert wf.axis == "order" and wf.amplitudes.shape == (11, wf.bins.size)
    assert wf.bins[-1] <= 100.0
    np.testing.assert_allclose(wf.speeds_rpm, speeds, rtol=1e-12)
    np.testing.assert_allclose(wf.order_cut(29), mesh_amplitude(speeds), rtol=1e-9)
    np.testing.assert_allclose(wf.order_cut(4), 0.3, rtol=1e-9)
    # Whole periods: the cut reads the order's own bin, not a neighbour's
    # (order 4 + 1/12 is empty, next to order 4).
    np.testing.assert_allclose(wf.order_cut(4 + 1 / 12), 0.0, atol=1e-9)
    assert np.all(np.isnan(wf.order_cut(500.0)))
    # Frequency of each cell: order times speed.
    f = wf.frequencies_hz()
    k = int(round(29 * 12))
    np.testing.assert_allclose(f[:, k], 29 * speeds / 60.0, rtol=1e-12)
    back = Waterfall.from_dict(json.loads(json.dumps(wf.to_dict())))
    np.testing.assert_array_equal(back.amplitudes, wf.amplitudes)


def test_sweep_waterfall_rebins_different_resolutions():
    # Spectra over 6 and 7 revolutions (whole periods, exact lines at orders 4
    # and 29) and one over 6 revolutions plus 1e-7 (as angle tracking of a
    # vibrating shaft gives): rebinned by peak hold onto the 1/6 grid, every line
    # keeps its height (the third record is 1e-7 revolutions off whole periods:
    # its lines move by 1.6e-8 and leak 7e-8 into order 4, measured; bound 2e-7).
    spectra = []
    for revs in (6.0, 7.0, 6.0 + 1e-7):
        rev = np.arange(int(round(revs * 512))) / 512.0 * (revs / round(revs))
        x = 2.0 * np.cos(2 * np.pi * 29 * rev) + 0.3 * np.cos(2 * np.pi * 4 * rev)
        spectra.append(
            order_spectrum(rev / 20.0, x, speed_rpm=1200.0, period_revs=None, window="rectangular")
        )
    assert spectra[1].revs == pytest.approx(7.0) and spectra[2].revs != spectra[0].revs
    wf = waterfall(spectra, max_order=60.0)
    assert wf.bins[1] == pytest.approx(1.0 / 6.0) and wf.bins[-1] <= 60.0
    np.testing.assert_allclose(wf.order_cut(29), 2.0, rtol=0, atol=2e-7)
    np.testing.assert_allclose(wf.order_cut(4), 0.3, rtol=0, atol=2e-7)
    t = np.arange(2048) / 2048.0
    a = order_spectrum(t, np.cos(2 * np.pi * 3 * t), speed_rpm=60.0)
    b = order_spectrum(t, np.cos(2 * np.pi * 3 * t), speed_rpm=60.0, window="hann")
    assert waterfall([a, b]).window == "mixed"
    with pytest.raises(InputError, match="speeds_rpm"):
        waterfall([a, a], speeds_rpm=[1.0])


def test_runup_order_waterfall_tracks_orders_through_a_ramp():
    # Run-up 600 -> 2600 rpm in 4 s with the mesh amplitude following the curve
    # above. Order-tracked blocks of 8 revolutions with a flat-top window: the order
    # cut equals the curve at each block's middle speed within the 0.5 %
    # (orders 29 and 4 sit on bins; what remains is the change of the amplitude
    # over a block, weighted by the window: 9.5e-5 worst measured).
    t = np.arange(0.0, 4.0, 1.0 / 16384.0)
    speed = 600.0 + 500.0 * t
    rev = (600.0 * t + 250.0 * t**2) / 60.0
    x = mesh_amplitude(speed) * np.cos(2 * np.pi * 29 * rev) + 0.5 * np.cos(2 * np.pi * 4 * rev)
    wf = runup_waterfall(t, x, speed_rpm=speed, axis="order", block=8.0, samples_per_rev=256)
    assert wf.axis == "order" and wf.window == "flattop"
    assert wf.bins[1] == pytest.approx(1.0 / 8.0)
    # Block speeds: 8 revolutions over the analytic time they take.
    assert np.all(np.diff(wf.speeds_rpm) > 0)
    assert 600.0 < wf.speeds_rpm[0] < wf.speeds_rpm[-1] < 2600.0
    np.testing.assert_allclose(wf.order_cut(29), mesh_amplitude(wf.speeds_rpm), rtol=5e-3)
    np.testing.assert_allclose(wf.order_cut(4), 0.5, rtol=5e-3)


def test_runup_frequency_waterfall_shows_a_fixed_resonance():
    # A structural resonance at a fixed 310 Hz, amplitude 0.8, under a run-up:
    # in the frequency waterfall it stays on one frequency (0.25 s blocks, 4 Hz
    # bins; flat top keeps the amplitude within the 0.5 %).
    fs = 8192.0
    t = np.arange(0.0, 3.0, 1.0 / fs)
    speed = 900.0 + 300.0 * t
    x = 0.8 * np.sin(2 * np.pi * 310.0 * t)
    wf = runup_waterfall(t, x, speed_rpm=speed, axis="frequency", block=0.25, overlap=0.0)
    assert wf.axis == "frequency" and wf.bins[1] == pytest.approx(4.0)
    k = int(np.argmin(np.abs(wf.bins - 310.0)))
    peak = wf.amplitudes[:, k - 1 : k + 2].max(axis=1)
    np.testing.assert_allclose(peak, 0.8, rtol=5e-3)
    # Block speeds: the ramp's mean over each block (linear: its mid value, within
    # half a sample step of 300 rpm/s / 8192 Hz).
    mids = 0.25 * (np.arange(wf.speeds_rpm.size) + 0.5)
    np.testing.assert_allclose(wf.speeds_rpm, 900.0 + 300.0 * mids, atol=0.05)
    # Orders of the fixed frequency fall as speed rises.
    o = wf.orders()[:, k]
    assert np.all(np.diff(o) < 0)


def test_runup_bad_input():
    t = np.linspace(0, 1, 100)
    with pytest.raises(InputError) as err:
        runup_waterfall(t, t[:50], speed_rpm=-t, axis="time", block=-1.0, overlap=1.0, window="x")
    paths = {p.path for p in err.value.problems}
    assert {"x", "speed_rpm", "axis", "block", "overlap", "window"} <= paths
    with pytest.raises(InputError, match="longer than the record"):
        runup_waterfall(t, np.sin(t), speed_rpm=np.full(100, 600.0), axis="order", block=50.0)
