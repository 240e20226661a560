"""Pitch deviations in the dynamics (docs/drivetrain.md §3c).

References: the loaded TCA's own quasi-static answer (gearbox.ltca.pitch, which
solves the contact problem, not the drivetrain), the quasi-static limit (at low orders
the flanks keep their load, so the transmission error follows the deviations), the
energy balance of the undamped model, the nonlinear simulation (which no part of the
harmonic balance uses) and the scipy solver against the fixed-step one.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from _drive import angle_spectrum

from gearbox import load_scene
from gearbox.drivetrain.linear import order_responses, pitch_harmonic_balance
from gearbox.drivetrain.model import (
    DrivetrainModel,
    PitchApproach,
    energy,
    pitch_terms,
    power,
    rhs,
)
from gearbox.errors import InputError
from gearbox.meshtable import TORQUE_ARM, MeshTable, pair_weight_fields
from gearbox.pipeline import run_pipeline

MODELS = Path(__file__).resolve().parents[1] / "models"
QUIET = {"firing_torque_ripple": 0.0, "half_order_ripple": 0.0, "blade_pass_ripple": 0.0}


def scene(**drivetrain):
    s = load_scene(MODELS / "marine_drive.toml").replaced(ltca={"positions": 12})
    return s.replaced(drivetrain={"pitch_deviations": True, **drivetrain})


@pytest.fixture(scope="module")
def ltca(tmp_path_factory):
    """The default scene's loaded TCA (12 positions) and its pitch stage (random single
    pitch deviations within +-4 um, 802 N m)."""
    run = run_pipeline(scene(), ["tables", "pitch"], cache=tmp_path_factory.mktemp("cache"))
    return run["tables"], run["pitch"]


def test_the_table_carries_the_pair_weights_and_torque_arm(ltca, tmp_path):
    table, _ = ltca
    fields = pair_weight_fields(table)
    assert 0 in fields and len(fields) >= 3
    i = table.flank_index("drive")
    total = sum(table.extra[f][i] for f in fields.values())
    np.testing.assert_allclose(total, 1.0, atol=1e-12)
    assert np.all(table.extra[TORQUE_ARM] > 0.05) and np.all(table.extra[TORQUE_ARM] < 0.1)
    assert table.attrs["pinion_reference_pitch_radius_m"] == pytest.approx(0.0925835, rel=1e-5)
    pytest.importorskip("xarray")  # the 'tables' extra, with its netCDF engine
    back = MeshTable.from_netcdf(table.to_netcdf(tmp_path / "t.nc"))
    assert pair_weight_fields(back) == fields
    assert (
        back.attrs["gear_reference_pitch_radius_m"] == table.attrs["gear_reference_pitch_radius_m"]
    )


def test_approach_is_the_loaded_tcas_te_change(ltca):
    """At the samples the approach is minus the loaded TCA's TE change at the model's
    torque (same pair weights, same interpolation in torque): to 1e-12 of its range;
    between them the spline's derivative matches a central difference."""
    table, pr = ltca
    m = DrivetrainModel.from_scene(scene(**QUIET), table)
    assert m.common_period_mesh_cycles() == 29 * 45  # the hunting period
    assert DrivetrainModel.from_scene(scene(), table).common_period_mesh_cycles() == 2 * 29 * 45
    from gearbox.ltca.pitch import hunting_lte

    rec = hunting_lte(_drive(table), pr.deviations, m.torque, teeth=(29, 45))
    a, _ = m.pitch(rec.angle + float(table.angle[0]))
    change = rec.lte - rec.lte_nominal
    assert np.abs(a + change).max() < 1e-12 * np.ptp(change) + 1e-18
    th = float(table.angle[0]) + np.linspace(0.01, 2 * math.pi * 45 - 0.01, 200)
    h = 1e-6
    num = (m.pitch(th + h)[0] - m.pitch(th - h)[0]) / (2 * h)
    np.testing.assert_allclose(m.pitch(th)[1], num, atol=1e-7 * np.abs(num).max())


def test_approach_carries_the_form_deviations(ltca):
    """With profile and helix slopes and crownings on every tooth the approach is still
    minus the loaded TCA's TE change (its form weights through the table): to 1e-12 of
    its range; the table's form weights are the loaded TCA's, its contact middles the
    crownings' vertices."""
    from gearbox.ltca.pitch import PitchDeviations, form_from_section, hunting_lte
    from gearbox.meshtable import CONTACT_CENTRES, CONTACT_LENGTHS, form_weight_fields

    table, pr = ltca
    m = DrivetrainModel.from_scene(scene(**QUIET), table)
    L = [table.attrs[k] for k in CONTACT_LENGTHS]
    c = [table.attrs[k] for k in CONTACT_CENTRES]
    given = {
        "random_profile_slope_um": 3.0,
        "random_helix_slope_um": 3.0,
        "random_profile_crowning_um": 2.0,
        "random_helix_crowning_um": 2.0,
    }
    sec = dict(scene()["pitch"], **given)
    slopes = form_from_section(
        sec, (29, 45), ((L[0], L[1]), (L[2], L[3])), ((c[0], c[1]), (c[2], c[3]))
    )
    assert slopes.crowned
    dev = PitchDeviations(
        pr.deviations.pinion,
        pr.deviations.gear,
        pr.deviations.pinion_radius,
        pr.deviations.gear_radius,
        slopes,
    )
    approach = PitchApproach.from_table(table, dev.pinion, dev.gear, m.torque, slopes)
    view = _drive(table)
    form = form_weight_fields(table)
    i = table.flank_index("drive")
    view.pair_form_weight = np.stack(
        [np.stack([table.extra[n][i] for n in form[k]], axis=-1) for k in view.pair_index],
        axis=-2,
    )
    rec = hunting_lte(view, dev, m.torque, teeth=(29, 45))
    change = rec.lte - rec.lte_nominal
    without = hunting_lte(_drive(table), pr.deviations, m.torque, teeth=(29, 45))
    assert np.ptp(change - (without.lte - without.lte_nominal)) > 0.2e-6  # the form's part
    a, _ = approach(rec.angle + float(table.angle[0]))
    assert np.abs(a + change).max() < 1e-12 * np.ptp(change) + 1e-18
    sc = scene(**QUIET).replaced(pitch=given)
    a2, _ = DrivetrainModel.from_scene(sc, table).pitch(rec.angle + float(table.angle[0]))
    np.testing.assert_array_equal(a2, a)
    with pytest.raises(InputError, match="form weights"):
        bare = dataclasses.replace(
            table, extra={k: v for k, v in table.extra.items() if not k.startswith("form_")}
        )
        PitchApproach.from_table(bare, dev.pinion, dev.gear, m.torque, slopes)


def _drive(table):
    """A CycleResult-like view of the table's drive flank for hunting_lte (weights,
    arm, TE per torque and position)."""
    fields = pair_weight_fields(table)
    i = table.flank_index("drive")
    ks = np.array(sorted(fields))

    class View:
        torque = table.torque
        fraction = np.arange(table.angle.size) / table.angle.size
        pair_index = ks
        pair_weight = np.stack([table.extra[fields[k]][i] for k in ks], axis=-1)
        normal_load = table.torque[:, None] / table.extra[TORQUE_ARM][i]
        lte = table.lte[i]
        pair_share = np.zeros(pair_weight.shape)  # no loads in the table: none asked for
        pair_root_stress = np.zeros(pair_weight.shape + (2,))
        pair_load_sensitivity = None

    return View()


def test_analytical_tables_and_other_backends_say_what_is_missing(ltca):
    with pytest.raises(InputError, match="pair weights"):
        DrivetrainModel.from_scene(scene())  # analytical table
    table, _ = ltca
    m = DrivetrainModel.from_scene(scene(), table)
    from gearbox.fmu import FmuModel, drivetrain_fmu

    # the FMUs model them (tests/test_fmu_pitch.py)
    assert isinstance(drivetrain_fmu(m, table), FmuModel)
    pytest.importorskip("exudyn")
    from gearbox.drivetrain.exudyn_backend import build_exudyn_system

    # the exudyn backend models them (tests/test_drivetrain_exudyn_pitch.py)
    build_exudyn_system(m).release()


def test_undamped_power_balance_with_pitch_deviations(ltca):
    """dE/dt along the flow equals :func:`power`, whose term F a' is the work of the
    deviating teeth: central differences of E (step 1e-7 s), tolerance 1e-5 of the
    largest power term, on the loaded-TCA table with rotation radii in the tooth
    ratio."""
    table, _ = ltca
    undamped = {
        "input_shaft_damping_ratio": 0.0,
        "output_shaft_damping_ratio": 0.0,
        "mesh_damping_ratio": 0.0,
        "bearing_damping_ratio": 0.0,
    }
    m = DrivetrainModel.from_scene(scene(**undamped), table)
    # power() is exact where the rotation radii keep the tooth ratio; the loaded TCA's
    # radii miss it by 1.3e-4 (dE/dt off by 0.1 % with or without the deviations)
    fl = [dataclasses.replace(f, lambda2=f.lambda1 * 45 / 29) for f in (m.drive, m.coast)]
    m = dataclasses.replace(m, drive=fl[0], coast=fl[1])
    p = m.params()
    n = m.n_dof
    y0 = m.static_state()
    rng = np.random.default_rng(0)
    h = 1e-7
    for _ in range(6):
        t = rng.uniform(0, 0.05)
        y = y0 + rng.normal(size=2 * n) * p["scale"] * 0.3
        dy = rhs(t, y / p["scale"], p) * p["scale"]
        de = (energy(t + h, y + h * dy, p) - energy(t - h, y - h * dy, p)) / (2 * h)
        assert abs(pitch_terms(t, y[1], y[n + 1], p)[1]) > 0  # the term is exercised
        assert de == pytest.approx(power(t, y, p), abs=1e-5 * abs(p["T"] * m.speed))


@pytest.fixture(scope="module")
def pitch_run(ltca):
    """The default drive on the loaded-TCA table with the pitch deviations, 3500 rpm,
    engine and propeller ripple off: one hunting period (1305 mesh cycles) after 0.5 s."""
    pytest.importorskip("diffrax")
    from gearbox.drivetrain.simulate import default_solver, simulate

    table, pr = ltca
    m = DrivetrainModel.from_scene(scene(**QUIET), table)
    ts = simulate(m, default_solver(), settle_time=0.5, mesh_cycles=1305, samples_per_cycle=24)
    assert ts.success
    return m, ts, pr


def test_quasi_static_te_is_the_loaded_tcas(pitch_run):
    """Against the pinion's angle, the transmission error's pitch lines at low orders
    are the loaded TCA's (which solves the contact, not the drivetrain): pinion orders
    1 and 2 and gear orders 1 and 2 within 1 % (measured 0.01-0.31 % on 24 positions);
    at pinion order 5 (290 Hz) the drive begins to respond dynamically (+2.4 %)."""
    m, ts, pr = pitch_run
    dte = angle_spectrum(ts, "dynamic_transmission_error_m")
    _, want = pr.record.order_spectrum()
    for order in (1.0, 2.0, 29 / 45, 58 / 45):
        i = int(round(order * 45))
        assert dte[i] == pytest.approx(want[i], rel=0.01), order


def test_harmonic_balance_reads_the_nonlinear_run(pitch_run):
    """The mesh force's pitch lines from the harmonic balance against the nonlinear
    run's constant-speed spectrum over the hunting period: low pinion and gear orders
    and the sidebands about 1x and 2x mesh within 1 % (measured 0.00-0.39 % on 24
    positions)."""
    m, ts, _ = pitch_run
    F = ts.channels["mesh_force_N"]
    amp = np.abs(np.fft.rfft(F)) / F.size * 2  # bins of 1/45 pinion order
    orders, _, f = pitch_harmonic_balance(m)
    for o in (1.0, 3.0, 5.0, 29 / 45, 58 / 45, 28.0, 30.0, 29 - 29 / 45, 29 + 29 / 45, 57.0, 59.0):
        line = abs(f[0, np.argmin(np.abs(orders - o))])
        assert line == pytest.approx(amp[int(round(o * 45))], rel=0.01), o


def test_scipy_agrees_with_the_fixed_step_run(ltca):
    """Fixed-step Tsit5 against scipy's adaptive DOP853 (rtol 1e-9) over 40 mesh cycles
    with the pitch deviations: mesh force within 1e-4 of its range."""
    pytest.importorskip("diffrax")
    from gearbox.drivetrain.simulate import default_solver, simulate

    table, _ = ltca
    m = DrivetrainModel.from_scene(scene(), table)
    a = simulate(m, default_solver("diffrax"), settle_time=0.0, mesh_cycles=40)
    b = simulate(m, default_solver("scipy", 1e-9), settle_time=0.0, mesh_cycles=40)
    fa, fb = a.channels["mesh_force_N"], b.channels["mesh_force_N"]
    assert np.abs(fa - fb).max() < 1e-4 * np.ptp(fb)
    assert "pitch_approach_m" in a.channels


def test_order_responses_list_the_pitch_lines(ltca):
    table, _ = ltca
    m = DrivetrainModel.from_scene(scene(**QUIET), table)
    r = order_responses(m)
    assert "pitch deviations" in r.sources
    i = int(np.argmin(np.abs(r.orders - 1.0)))
    assert r.sources[i] == "pitch deviations" and abs(r.mesh_force[0, i]) > 1.0


def test_spline_passes_through_its_samples():
    rng = np.random.default_rng(2)
    v = rng.normal(size=64) * 1e-6
    pa = PitchApproach(v, 0.3, 0.01)
    a, _ = pa(0.3 + 0.01 * np.arange(64))
    np.testing.assert_allclose(a, v, atol=1e-18)
    a2, _ = pa(0.3 + 0.01 * (np.arange(64) + 64))  # periodic
    np.testing.assert_allclose(a2, v, atol=1e-18)
    with pytest.raises(InputError, match="pitch.step"):
        PitchApproach(v, 0.0, 0.0)
    assert dataclasses.replace(pa).period == pytest.approx(0.64)
