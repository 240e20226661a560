"""The default jax path: fixed-step Runge-Kutta in lax.scan (gearbox/drivetrain/fixed_step.py).

Its right-hand side is a second writing of model.rhs (scalar arithmetic, mesh laws from
a Hermite table): checked here against model.rhs, the table against the Fourier series,
the step rule against the stability polynomial, the order of convergence, batching,
gradients and the failure reports.
"""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from gearbox.drivetrain.linear import periodic_start_state, periodic_start_states
from gearbox.drivetrain.model import (
    DrivetrainModel,
    PitchApproach,
    friction_arms,
    mesh_laws,
    rhs,
)
from gearbox.drivetrain.simulate import mesh_force_metrics, simulate
from gearbox.errors import InputError
from gearbox.mesh_analytical import analytical_table, pair_from_scene
from gearbox.scene import load_scene

pytest.importorskip("diffrax")
import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402

from gearbox.drivetrain import fixed_step as fs  # noqa: E402
from gearbox.drivetrain.diffrax_backend import (  # noqa: E402
    DiffraxSolver,
    integrate_diffrax,
    integrate_speeds,
)

MODELS = Path(__file__).resolve().parents[1] / "models"


def case03(**drivetrain):
    return load_scene(MODELS / "case03.toml").replaced(drivetrain=drivetrain)


@pytest.fixture(scope="module")
def base():
    s = case03()
    table = analytical_table(pair_from_scene(s), [150.0, 300.0, 450.0], positions=24)
    return s, table, DrivetrainModel.from_scene(s, table)


def with_lte(m: DrivetrainModel, seed: int = 0) -> DrivetrainModel:
    """The model with a made-up no-load error e (decaying harmonics, 2 um first) on both
    flanks: the analytical table has e = 0, which would leave e and e' untested."""
    import dataclasses

    rng = np.random.default_rng(seed)
    h = (m.drive.e_coef.size - 1) // 2
    k = np.arange(1, h + 1)
    amp = 2e-6 / k**2
    ec = np.concatenate([[1e-6], amp * rng.normal(size=h), amp * rng.normal(size=h)])
    fl = [dataclasses.replace(f, e_coef=ec) for f in (m.drive, m.coast)]
    return dataclasses.replace(m, drive=fl[0], coast=fl[1])


def exact_laws(p):
    """The mesh-law rows of :func:`fs.mesh_law_table` from the Fourier series, the
    friction arms' rows (phi_1 drive, coast, phi_2 drive, coast) when there are any."""

    def laws_at(phi):
        k, _, e, de = mesh_laws(phi / p["N1"], p, jnp)
        arms = friction_arms(phi / p["N1"], p, jnp)  # (flank, arm) or None
        return jnp.concatenate([k, e, de] + ([] if arms is None else [arms.T.reshape(4)]))

    return laws_at


@pytest.mark.parametrize(
    "variant", ["default", "bearings_governor", "friction", "eccentricity", "pitch"]
)
def test_lean_rhs_equals_model_rhs(base, variant):
    # Same equations in another arrangement: equal to rounding (1e-12 of the largest
    # component) on states that put each flank in and out of contact; with mesh
    # friction (docs/drivetrain.md §3a) the table has four rows more; with eccentricities
    # (§3b) both flanks' gaps move with the pinion's and the gear's angle.
    s, table, m = base
    if variant == "eccentricity":
        sc = case03(
            bearing_dofs=True,
            pinion_eccentricity_um=30.0,
            pinion_eccentricity_angle_deg=70.0,
            gear_eccentricity_um=20.0,
            gear_eccentricity_angle_deg=-120.0,
        )
        m = dataclasses.replace(DrivetrainModel.from_scene(sc, table), phase=0.3)
        assert m.params()["rc"].shape == (2, 4)
    if variant == "pitch":  # docs/drivetrain.md §3c: the drive flank's gap follows a spline
        rng = np.random.default_rng(4)
        pa = PitchApproach(rng.normal(size=24 * 29 * 3) * 3e-6, float(table.angle[0]), 0.009)
        m = dataclasses.replace(m, pitch=pa, phase=0.2)
        assert m.params()["pt"].shape == (24 * 29 * 3, 4)
    if variant == "friction":
        m = DrivetrainModel.from_scene(case03(mesh_friction_coefficient=0.1), table)
        assert fs.mesh_law_table(m.params(), 64, np).shape[0] == 10
    if variant == "bearings_governor":
        sc = case03(
            bearing_dofs=True,
            governor=True,
            governor_kp_Nms_per_rad=50.0,
            governor_ki_Nm_per_rad=2e3,
            half_order_ripple=0.05,
        )
        m = DrivetrainModel.from_scene(sc, table)
    m = with_lte(m)
    p = m.params()
    pj = {k: jnp.asarray(v) for k, v in p.items()}
    laws = exact_laws(pj)
    rng = np.random.default_rng(1)
    n = m.n_dof
    y_s = m.static_state()
    g = m.mesh_vectors()[0]
    for i in range(40):
        t = rng.uniform(0, 0.1)
        y = y_s + rng.normal(size=2 * n) * p["scale"] * 0.5
        if i % 4 == 0:  # drive flank off, coast flank hit: move the pinion back
            y[1] -= (g @ y[:n] + 2 * m.coast.backlash) / g[1]
        z = y / p["scale"]
        te0, rp = fs._time_excitations(pj, jnp.asarray(t), jnp)
        got = np.asarray(fs.lean_rhs(t, jnp.asarray(z), pj, laws, te0, rp))
        want = rhs(t, z, p)
        assert np.allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max()), (i, got, want)


def test_hermite_table_against_the_fourier_series(base):
    # Cubic Hermite interpolation: error h^4 |f''''| / 384 per harmonic; measured on the
    # default scene's stiffness 8.5e-11 of the mean at 2048 cells, 16x less per doubling.
    _, _, m = base
    m = with_lte(m)
    p = m.params()
    rng = np.random.default_rng(2)
    th = rng.uniform(0, 2 * math.pi / m.pinion_teeth, 400)
    k, _, e, de = mesh_laws(th, p)
    want = np.concatenate([k, e, de], axis=1)
    errs = []
    for cells in (1024, 2048):
        tab = jnp.asarray(fs.mesh_law_table(p, cells, np))
        got = np.stack([fs._hermite(tab, m.pinion_teeth * t, cells, jnp, jax.lax) for t in th])
        errs.append(np.abs(got - want).max(axis=0))
    kbar = m.drive.mean_stiffness
    assert errs[1][0] < 2e-10 * kbar and errs[1][1] < 2e-10 * kbar
    assert errs[1][2] < 1e-9 * 2e-6 and errs[1][4] < 1e-7 * 2e-6 * m.pinion_teeth
    ratio = errs[0] / errs[1]
    assert np.all(ratio[[0, 2, 4]] > 12), ratio  # fourth order: 16


def test_stability_polynomial_and_step_limit(base):
    # Tsit5 is 5th order: R(z) matches exp(z) through z^5; its 6th coefficient is not
    # 1/720. A step beyond the linearised model's stability limit is refused with the
    # parameter named; the default step sits well inside it.
    A, b, _ = fs.explicit_tableau("Tsit5")
    c = fs.stability_polynomial(A, b)
    assert np.allclose(c[:6], [1 / math.factorial(k) for k in range(6)], rtol=1e-12)
    assert abs(c[6] - 1 / 720) > 1e-6
    _, _, m = base
    lim = fs.stability_limit(m)
    tg, lim_b, f_max = fs.step_targets(m, DiffraxSolver())
    assert lim_b[0] == pytest.approx(lim) and tg[0] < 0.5 * lim
    assert tg[0] == pytest.approx(1 / (12 * f_max[0]))
    y0 = periodic_start_state(m)
    with pytest.raises(InputError, match="step"):
        integrate_diffrax(m, y0, np.array([1e-3]), DiffraxSolver(step=1.1 * lim))
    with pytest.raises(InputError, match="atol"):
        DiffraxSolver(atol=1e-9).validate()
    with pytest.raises(InputError, match="step"):
        DiffraxSolver(rtol=1e-6, step=1e-5).validate()


def test_unstable_step_blows_up_and_is_reported_with_time_and_state(base, monkeypatch):
    # With the stability check bypassed, a step 3x beyond the limit must not fail
    # silently: the run is reported as NaN or divergence, with a time and a state.
    _, _, m = base
    lim = fs.stability_limit(m)
    monkeypatch.setattr(fs, "stability_limit", lambda *a, **k: 1.0)
    real = fs.step_targets

    def targets(model, solver, speeds=None):
        t, _, f = real(model, solver, speeds)
        return t, np.ones_like(t), f

    monkeypatch.setattr(fs, "step_targets", targets)
    t_eval = np.arange(1, 201) * 3 * lim
    # contact_rtol None: keep the fixed-step run (the blow-up also opens the mesh, which
    # would otherwise hand the run to adaptive steps)
    solver = DiffraxSolver(step=3 * lim, contact_rtol=None)
    _, _, info = integrate_diffrax(m, periodic_start_state(m), t_eval, solver)
    assert info["status"] in ("nan", "divergence"), info["status"]
    f = info["failure"]
    assert 0 < f.time <= t_eval[-1] and len(f.state) == 8


def test_fixed_step_converges_at_fifth_order(base):
    # Halving the step must cut the sample-wise mesh-force error about 32x (5th order);
    # reference: adaptive Dopri8 at rtol 1e-12. Allowed: observed order >= 4.
    _, _, m = base
    ref = simulate(m, DiffraxSolver(solver="Dopri8", rtol=1e-12), mesh_cycles=10)
    errs = []
    for spp in (12.0, 24.0, 48.0):
        ts = simulate(m, DiffraxSolver(steps_per_period=spp), mesh_cycles=10)
        assert ts.success
        d = ts["mesh_force_N"] - ref["mesh_force_N"]
        errs.append(np.sqrt(np.mean(d**2)) / np.std(ref["mesh_force_N"]))
    order = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(order > 4), (errs, order)
    assert errs[0] < 1e-4


def test_batched_set_up_equals_one_model_per_speed(base):
    _, _, m = base
    w = np.array([700.0, 1900.0, 2900.0]) * math.pi / 30
    Y = periodic_start_states(m, w)
    P = m.speed_params(w)
    for i, wi in enumerate(w):
        mi = m.with_speed(wi)
        assert np.allclose(Y[i], periodic_start_state(mi), rtol=1e-12, atol=1e-14)
        for k, v in mi.params().items():
            assert np.allclose(P[k][i], v, rtol=1e-13, atol=0), k


def test_speed_batch_equals_single_fixed_runs(base):
    # Same step plans (the batch only appends h = 0 steps): the same numbers to rounding.
    _, _, m = base
    w = np.array([1200.0, 2400.0]) * math.pi / 30
    y0s = periodic_start_states(m, w)
    tm = 2 * math.pi / (m.pinion_teeth * w)
    tev = (5 + np.arange(1, 8 * 16 + 1)[None, :] / 16) * tm[:, None]
    res = integrate_speeds(m, w, y0s, tev, DiffraxSolver(), keep_states=True)
    assert res["status"] == ("success", "success")
    for i, wi in enumerate(w):
        mi = m.with_speed(wi)
        _, Yi, info = integrate_diffrax(mi, y0s[i], tev[i], DiffraxSolver())
        assert info["steps"] == res["steps"][i]
        assert np.allclose(res["states"][i], Yi, rtol=1e-10, atol=1e-12 * np.abs(Yi).max())
        one = simulate(
            mi, DiffraxSolver(), settle_time=5 * tm[i], mesh_cycles=8, samples_per_cycle=16
        )
        amp = mesh_force_metrics(one, mi)["mesh_force_mesh_order_amplitude_N"]
        f = res["mesh_force"][i]
        a_b = 2 * abs(np.mean(f * np.exp(-1j * m.pinion_teeth * wi * tev[i])))
        # simulate() also samples t = settle, so its first interval is split elsewhere:
        # another step grid, the same answer within the method's error (measured 7e-9
        # at 1200 rpm, 4e-7 at 2400 rpm)
        assert a_b == pytest.approx(amp, rel=1e-5)


def test_gradient_through_the_fixed_step_scan(base):
    # jax.grad of the final mesh deflection with respect to the mesh damping, against a
    # central difference (1e-4: the fixed step makes the map smooth in the parameter).
    _, _, m = base
    p = {k: jnp.asarray(v) for k, v in m.params().items()}
    ts = np.concatenate([[0.0], np.arange(1, 97) / (32 * m.mesh_frequency)])
    plan = fs.plan_steps(m, ts, DiffraxSolver())
    fn = fs.fixed_solve_fn("Tsit5", 2048)
    z0 = jnp.asarray(m.static_state() / m.params()["scale"])
    g = jnp.asarray(m.mesh_vectors()[0])
    sc = p["scale"]
    args = (jnp.asarray(plan.t), jnp.asarray(plan.h), jnp.asarray(plan.out))

    def out(cm):
        zs, lost = fn(dict(p, cm=p["cm"].at[0].set(cm)), z0, *args)
        return g @ (zs[-1, :4] * sc[:4])

    c0 = float(p["cm"][0])
    gr = float(jax.grad(out)(c0))
    h = 0.01 * c0
    fd = (float(out(c0 + h)) - float(out(c0 - h))) / (2 * h)
    assert gr == pytest.approx(fd, rel=1e-4) and gr != 0


def test_sweep_loop_and_vmap_give_the_same_numbers(base):
    # The loop runs each speed's own steps through one chunked compilation; the batch
    # pads all speeds to one length with h = 0 steps after the last output: the same
    # step grids, so the same metrics to rounding.
    from gearbox.drivetrain.sweep import speed_sweep

    _, _, m = base
    rpms = [700.0, 1500.0, 2900.0]
    a = speed_sweep(m, rpms, DiffraxSolver(), settle_cycles=3, mesh_cycles=6, batch="loop")
    b = speed_sweep(m, rpms, DiffraxSolver(), settle_cycles=3, mesh_cycles=6, batch="vmap")
    assert a.status == b.status == ("success",) * 3
    for k, v in a.metrics.items():
        assert np.allclose(v, b.metrics[k], rtol=1e-10, atol=0), k
    assert a.compile_time > 0 and a.to_dict()["setup_time_s"] >= 0


def test_contact_loss_hands_the_run_to_adaptive_steps(base):
    # At 663 rpm the mesh frequency (321 Hz) sits on the 308 Hz shaft mode: the flanks
    # separate and the coast flank is hit. A fixed step crosses those kinks unlocated
    # (measured on 100 mesh cycles: mesh-order amplitude 28 % off); the default repeats
    # the run with adaptive steps (rtol 1e-9), which agrees with rtol 1e-11 within 1e-4.
    _, _, m = base
    mr = m.with_speed(663.3 * math.pi / 30)
    kw = dict(settle_time=0.0, mesh_cycles=40, samples_per_cycle=16)
    ts = simulate(mr, DiffraxSolver(), **kw)
    assert ts.success and ts.attrs["stepping"] == "adaptive (contact loss)"
    assert ts.attrs["contact_loss_steps"] > 0 and (ts["mesh_force_N"] < 0).any()
    ref = simulate(mr, DiffraxSolver(rtol=1e-11), **kw)
    a, b = mesh_force_metrics(ts, mr), mesh_force_metrics(ref, mr)
    for k in ("mesh_force_rms_N", "mesh_force_mesh_order_amplitude_N"):
        assert abs(a[k] / b[k] - 1) < 1e-4, k
    kept = simulate(mr, DiffraxSolver(contact_rtol=None), **kw)
    assert kept.attrs["stepping"] == "fixed" and kept.attrs["contact_loss_steps"] > 0
    # at 2000 rpm the mesh stays in contact: fixed steps throughout
    two = simulate(m, DiffraxSolver(), mesh_cycles=10)
    assert two.attrs["stepping"] == "fixed" and two.attrs["contact_loss_steps"] == 0
    # a sweep re-runs only the speeds with contact loss, with the same adaptive settings
    from gearbox.drivetrain.sweep import speed_sweep

    sw = speed_sweep(m, [663.3, 2000.0], DiffraxSolver(), settle_cycles=0, mesh_cycles=40)
    assert sw.status == ("success", "success")
    assert sw.contact_loss_steps[0] > 0 and sw.contact_loss_steps[1] == 0
    # the same adaptive settings: equal to the single run's within rounding, which the
    # step control at the contact kinks amplifies (the sweep's batched program and the
    # single run's differ in the order of floating-point operations; measured 1.7e-6
    # on one machine, 0 on another), far below the 28 % of fixed steps
    k = "mesh_force_mesh_order_amplitude_N"
    assert sw.metrics[k][0] == pytest.approx(a[k], rel=1e-4)


def test_a_run_in_segments_is_the_one_scan_and_shares_its_compilation(base, monkeypatch):
    # The backend runs every fixed-step run through one chunked program in segments of
    # SEGMENT steps (the state carried over): the same steps as one scan over the whole
    # plan, so the same states to the bit; and a run of another length adds no
    # compilation. SEGMENT taken small here so that the run spans several segments.
    import gearbox.drivetrain.diffrax_backend as db

    monkeypatch.setattr(db, "SEGMENT", 4 * fs.CHUNK)
    _, _, m = base
    p = m.params()
    solver = DiffraxSolver()
    ts = np.concatenate([[0.0], np.arange(1, 641) / (32 * m.mesh_frequency)])
    plan = fs.plan_steps(m, ts, solver)
    assert plan.n_steps > 2 * db.SEGMENT and plan.n_steps % db.SEGMENT  # a partial last one
    fn = fs.fixed_solve_fn(solver.solver, solver.table_cells, terms=fs.excitation_terms(p))
    y0 = periodic_start_state(m)
    zs, lost = fn(p, y0 / p["scale"], plan.t, plan.h, plan.out)
    _, Y, info = db._integrate_fixed(m, y0, ts[1:], solver)
    assert np.array_equal(Y, np.asarray(zs) * p["scale"])
    assert info["steps"] == plan.n_steps and info["contact_loss_steps"] == int(lost) == 0
    n = len(db._COMPILED)
    _, Y2, _ = db._integrate_fixed(m, y0, ts[1:400], solver)  # another number of steps
    assert len(db._COMPILED) == n
    assert np.array_equal(Y2, Y[:399])
