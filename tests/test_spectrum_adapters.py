"""Adapters: drivetrain time series -> order spectra; eigenfrequency tables -> Campbell."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.spectrum import (
    ExcitationOrder,
    campbell,
    excitation_orders,
    mode_table,
    period_revs_of,
    timeseries_spectra,
)


def fake_series(n_rpm=1800.0, revs=6.0, spr=29 * 32):
    """A TimeSeries-like record: pinion turning at n_rpm with a small torsional
    vibration, mesh force and DTE as known sums of cosines in pinion revolutions."""
    rev = np.arange(1, int(revs * spr) + 1) / spr
    t = rev * 60.0 / n_rpm
    angle = 2 * np.pi * rev + 1e-4 * np.sin(2 * np.pi * 4 * rev)  # 4th-order wobble
    rev_true = angle / (2 * np.pi)
    force = (
        3600.0 + 100.0 * np.cos(2 * np.pi * 29 * rev_true) + 25.0 * np.cos(2 * np.pi * 4 * rev_true)
    )
    dte = 1.5e-7 * np.cos(2 * np.pi * 29 * rev_true + 0.4)
    return SimpleNamespace(
        time=t,
        channels={
            "pinion_angle_rad": angle,
            "mesh_force_N": force,
            "dynamic_transmission_error_m": dte,
        },
        units={"pinion_angle_rad": "rad", "mesh_force_N": "N", "dynamic_transmission_error_m": "m"},
    )


def test_timeseries_spectra_track_the_pinion_angle():
    # Tracking the (wobbling) pinion angle recovers the amplitudes defined in its
    # revolutions within the 0.5 %; the record starts one sample after
    # t = 0 (as a simulation writes it), and its 6 revolutions all count: the last
    # sample step is closed by periodicity.
    ts = fake_series()
    sp = timeseries_spectra(ts)
    assert list(sp) == ["mesh_force_N", "dynamic_transmission_error_m"]
    f = sp["mesh_force_N"]
    assert f.unit == "N" and f.method == "angle-resampled" and f.n_periods == 6
    assert f.amplitude_at(29) == pytest.approx(100.0, rel=5e-3)
    assert f.amplitude_at(4) == pytest.approx(25.0, rel=5e-3)
    assert f.amplitude_at(0) == pytest.approx(3600.0, rel=1e-9)
    assert sp["dynamic_transmission_error_m"].amplitude_at(29) == pytest.approx(1.5e-7, rel=5e-3)


def test_timeseries_spectra_nominal_speed_plain_fft():
    # At the nominal speed the samples are whole per revolution: the plain FFT.
    # The 1e-4 rad wobble then phase-modulates the mesh order (its sidebands take
    # a share of about (29 * 1e-4 / 2)^2 ~ 2e-6 of the amplitude): bound 1e-4.
    ts = fake_series()
    sp = timeseries_spectra(ts, ["mesh_force_N"], speed_rpm=1800.0)
    f = sp["mesh_force_N"]
    assert f.method == "fft" and f.n_periods == 6
    assert f.amplitude_at(29) == pytest.approx(100.0, rel=1e-4)


def test_timeseries_spectra_bad_names():
    ts = fake_series()
    with pytest.raises(InputError) as err:
        timeseries_spectra(ts, ["nope"], reference="also_nope")
    assert {p.path for p in err.value.problems} == {"channels", "reference"}


def test_period_of_marine_excitations():
    # 29:45, 8 cylinders with half orders, 3 blades: lcm(2, 15) = 30 revolutions.
    ex = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3)
    assert period_revs_of(ex) == 30.0
    assert period_revs_of(excitation_orders(pinion_teeth=29, cylinders=8, half_orders=False)) == 1.0


def test_mode_table_feeds_campbell():
    # Two elastic modes and a rigid-body mode (left out), tabulated at five
    # speeds, linear in speed: crossings equal the closed form a / (o/60 - b).
    speeds = np.linspace(0.0, 4000.0, 5)
    # The rigid-body mode as an eigensolver returns it: round-off, 3.3e-6 Hz.
    freqs = np.column_stack([np.full(5, 3.3e-6), 20.0 + 0.002 * speeds, 1500.0 + 0.05 * speeds])
    modes = mode_table(speeds, freqs, ["rigid", "shaft", "mesh"])
    assert list(modes) == ["shaft", "mesh"]
    cd = campbell(modes, [ExcitationOrder("mesh", 29.0, "mesh")], (100.0, 4000.0))
    got = {c.mode: c.speed_rpm for c in cd.crossings}
    assert got["mesh"] == pytest.approx(1500.0 / (29 / 60 - 0.05), rel=1e-10)
    assert "shaft" not in got  # 29 n / 60 > 20 + 0.002 n above 41.5 rpm: below the range
    with pytest.raises(InputError, match="names"):
        mode_table(speeds, freqs, ["a"])


@pytest.mark.slow
def test_drivetrain_mesh_order_agrees_with_single_frequency_dft():
    # Integration: a real drivetrain run (paper case 03 pair, analytical mesh
    # table, scipy reference solver). The drivetrain's own metric is a DFT at
    # exactly the mesh frequency over the record, independent of this module; on
    # the plain-FFT path both are the same sum, so they agree to round-off (1e-9).
    pytest.importorskip("gearbox.drivetrain.simulate")
    from pathlib import Path

    from gearbox import load_scene
    from gearbox.drivetrain import DrivetrainModel
    from gearbox.drivetrain.simulate import default_solver, mesh_force_metrics, simulate

    scene = load_scene(Path(__file__).resolve().parents[1] / "models" / "case03.toml")
    model = DrivetrainModel.from_scene(scene)
    ts = simulate(model, default_solver("scipy"), mesh_cycles=2 * model.pinion_teeth)
    assert ts.success
    n_rpm = model.speed * 30.0 / np.pi
    f = timeseries_spectra(ts, ["mesh_force_N"], speed_rpm=n_rpm)["mesh_force_N"]
    assert f.method == "fft" and f.n_periods == 2
    ref = mesh_force_metrics(ts, model)["mesh_force_mesh_order_amplitude_N"]
    assert f.amplitude_at(model.pinion_teeth) == pytest.approx(ref, rel=1e-9)
