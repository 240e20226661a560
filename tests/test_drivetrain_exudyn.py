"""exudyn backend of the drivetrain dynamics: agreement with the scipy reference, the
exudyn system's structure, the step limit, failure reports and bad input."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

from _exudyn_helpers import random_states, rel  # noqa: E402

from gearbox.drivetrain import exudyn_backend as xb  # noqa: E402
from gearbox.drivetrain.exudyn_backend import (  # noqa: E402
    ExudynSolver,
    build_exudyn_system,
    integrate_exudyn,
    simulate_exudyn,
    stability_step_limit,
)
from gearbox.drivetrain.model import DrivetrainModel, mesh_forces, outputs, rhs  # noqa: E402
from gearbox.drivetrain.scipy_backend import ScipySolver  # noqa: E402
from gearbox.drivetrain.simulate import mesh_force_metrics, simulate  # noqa: E402
from gearbox.errors import InputError  # noqa: E402
from gearbox.mesh_analytical import analytical_table, pair_from_scene  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402

MODELS = Path(__file__).resolve().parents[1] / "models"


def case03(**drivetrain):
    """Paper case 03 (models/case03.toml, Tables 1-2 of the paper) with drivetrain keys."""
    return load_scene(MODELS / "case03.toml").replaced(drivetrain=drivetrain)


@pytest.fixture(scope="module")
def marine():
    """The default scene (models/marine_drive.toml) with its analytical mesh tables."""
    return DrivetrainModel.from_scene(load_scene(MODELS / "marine_drive.toml"))


@pytest.fixture(scope="module")
def marine_ref(marine):
    """scipy reference on the default scene: DOP853, rtol 1e-10, 40 recorded mesh cycles."""
    return simulate(marine, ScipySolver(rtol=1e-10), mesh_cycles=40)


@pytest.fixture(scope="module")
def small():
    """Case 03 with the default drivetrain and a governor (every load path in use)."""
    s = case03(governor=True, half_order_ripple=0.05, engine_harmonics=2)
    table = analytical_table(pair_from_scene(s), [150.0, 300.0, 450.0], positions=24)
    return DrivetrainModel.from_scene(s, table)


# ------------------------------------------------------------------ agreement
def test_exudyn_agrees_with_scipy_on_the_default_scene(marine, marine_ref):
    # Issue 6: RMS and mesh-order amplitude of the dynamic mesh force within 1e-4
    # relative of the scipy reference (DOP853, rtol 1e-10 on the scaled state; it differs
    # from rtol 1e-12 by 4e-11 in these quantities), over 40 whole mesh cycles after 20
    # cycles of settling. Measured when written: about 1e-6 for the default RK67 step.
    ref = marine_ref
    exd = simulate(marine, ExudynSolver(), mesh_cycles=40)
    assert ref.success and exd.success, (ref.failure, exd.failure)
    np.testing.assert_allclose(exd.time, ref.time, rtol=0, atol=1e-12)
    a, b = mesh_force_metrics(exd, marine), mesh_force_metrics(ref, marine)
    for key in (
        "mesh_force_rms_N",
        "mesh_force_dynamic_rms_N",
        "mesh_force_mesh_order_amplitude_N",
    ):
        assert rel(a[key], b[key]) < 1e-4, (key, a[key], b[key])
    # Sample by sample: the error of the mesh force over its dynamic RMS, the stricter
    # measure the benchmark reports.
    err = np.sqrt(np.mean((exd["mesh_force_N"] - ref["mesh_force_N"]) ** 2)) / np.std(
        ref["mesh_force_N"]
    )
    assert err < 1e-4, err
    # Work: the fixed step puts every sample on its grid; the step count is known in
    # advance (settling steps + samples x steps per sample), a guard against regressions.
    assert exd.steps <= 2000, exd.steps  # 1836 when written
    assert exd.nfev == 7 * exd.steps


def test_exudyn_diffrax_and_scipy_agree_three_ways(marine, marine_ref):
    # Issue 6: "exudyn, diffrax and scipy give the same dynamic mesh force (RMS and the
    # mesh-order amplitude) within 1e-4 relative on the default scene". diffrax with its
    # default settings (fixed steps since; with adaptive rtol 1e-6 the largest pairwise
    # difference measured 6e-6 when written).
    pytest.importorskip("diffrax")
    from gearbox.drivetrain.diffrax_backend import DiffraxSolver

    runs = [simulate(marine, s, mesh_cycles=40) for s in (ExudynSolver(), DiffraxSolver())]
    runs.append(marine_ref)
    assert all(ts.success for ts in runs), [ts.failure for ts in runs]
    metrics = [mesh_force_metrics(ts, marine) for ts in runs]
    for key in (
        "mesh_force_rms_N",
        "mesh_force_dynamic_rms_N",
        "mesh_force_mesh_order_amplitude_N",
    ):
        values = [m[key] for m in metrics]
        assert (max(values) - min(values)) / values[-1] < 1e-4, (key, values)


def test_generic_layout_and_python_user_functions_give_the_same_run(small):
    # The four variants integrate the same equations with the same fixed step, so they
    # agree to rounding (1e-9 of the dynamic force; the amplitude/phase form of the
    # Fourier series differs from the model's a/b form only in the last bits).
    y0 = small.static_state()
    t_eval = np.arange(1, 101) * 1e-4
    runs = {}
    for uf in ("symbolic", "python"):
        for layout in ("components", "generic"):
            t, Y, info = integrate_exudyn(
                small, y0, t_eval, ExudynSolver(user_functions=uf, layout=layout)
            )
            assert info["status"] == "success", info
            runs[(uf, layout)] = outputs(small, t, Y)["mesh_force_N"]
    f0 = runs[("symbolic", "components")]
    for key, f in runs.items():
        assert np.abs(f - f0).max() < 1e-9 * np.std(f0) + 1e-9, key


# ------------------------------------------------------------------ the exudyn system
@pytest.fixture(scope="module")
def with_error(small):
    """``small`` with a non-zero no-load error on both flanks (2 and 0.5 um harmonics)."""
    e = np.zeros_like(small.drive.e_coef)
    h = (e.size - 1) // 2
    e[0], e[1], e[2], e[1 + h] = 0.3e-6, 2e-6, 0.5e-6, -1e-6
    return dataclasses.replace(
        small,
        drive=dataclasses.replace(small.drive, e_coef=e),
        coast=dataclasses.replace(small.coast, e_coef=-e),
    )


@pytest.mark.parametrize("name", ["small", "marine", "with_error"])
def test_symbolic_force_functions_equal_the_model_right_hand_side(name, request):
    # Generic layout: M a = f_user(t, q, v) - K q - C v must equal M times the model's
    # own rhs (docs/drivetrain.md §7) at random states: 1e-9 of the largest term. With a
    # non-zero error series e(theta) the contact test also runs through the band
    # e_lo < delta - b <= e_hi where the gap s itself decides (states placed there).
    model = request.getfixturevalue(name)
    sysm = build_exudyn_system(model, ExudynSolver(layout="generic"))
    uf = sysm.keepalive[0]
    plan = xb._plan_from_model(model)
    K, C = xb._structural(plan)
    p = model.params()
    n = model.n_dof
    rng = np.random.default_rng(1)
    states = random_states(model, rng, 12)
    fl = plan.flanks[0]
    e_lo, e_hi = xb._bounds(fl.e, fl.e_harmonics)
    if e_hi - e_lo > 1e-12:  # states inside the band of the drive flank
        for j in range(8):
            y = model.static_state().copy()
            u = e_lo + (j + 0.5) / 8 * (e_hi - e_lo)
            y[1] += (u - fl.G @ y[:n]) / fl.G[1]
            states.append(y)
    coast_hits = 0
    band = []
    for i, y in enumerate(states):
        t = float(rng.uniform(0.0, 0.05))
        x, v = y[:n], y[n:]
        f = np.array(uf.Evaluate(sysm.mbs, t, 0, x.tolist(), v.tolist()))
        got = (f - K @ x - C @ v) / plan.inertia
        want = (rhs(t, y / p["scale"], p) * p["scale"])[n:]
        big = np.abs(want).max() + np.abs(K @ x).max() / plan.inertia.min()
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * big)
        forces = mesh_forces(t, x, v, p)[0]
        coast_hits += forces[1] > 0
        if i >= 12:
            band.append(forces[0] > 0)
    assert coast_hits >= 1  # the coast flank's law was exercised
    if name == "with_error":  # inside the band, both outcomes of the gap test occur
        assert any(band) and not all(band)


def test_components_layout_is_a_real_exudyn_system(small):
    sysm = build_exudyn_system(small)
    mbs = sysm.mbs
    types = [mbs.GetObject(i)["objectType"] for i in range(mbs.systemData.NumberOfObjects())]
    assert types.count("RotationalMass1D") == 4
    assert types.count("ConnectorCoordinateSpringDamper") == 4  # 2 shafts, governor, propeller
    assert types.count("GenericODE2") == 1
    assert set(sysm.connectors) == {"input_shaft", "output_shaft", "governor", "propeller_load"}
    assert mbs.GetLoad(sysm.loads[0])["loadType"] == "Coordinate"
    assert [mbs.GetNode(nd)["nodeType"] for nd in sysm.nodes] == ["1D"] * 4
    # With bearing translations: two point masses, two bearing connectors, and the mesh
    # object spans pinion, gear and both translations.
    bear = dataclasses.replace(small, bearing_dofs=True)
    sb = build_exudyn_system(bear)
    types = [sb.mbs.GetObject(i)["objectType"] for i in range(sb.mbs.systemData.NumberOfObjects())]
    assert types.count("Mass1D") == 2
    assert {"pinion_bearing", "gear_bearing"} <= set(sb.connectors)
    assert len(sb.mbs.GetObject(sb.mesh_object)["nodeNumbers"]) == 4


def test_constant_stiffness_without_excitation_stays_at_the_static_solution(small):
    # No mesh ripple, no error, no engine or propeller ripple, no governor offset: the
    # static state is an equilibrium and the run must stay on it (rounding only).
    flat = dataclasses.replace(
        small.drive,
        k_coef=np.r_[small.drive.k_coef[0], np.zeros(small.drive.k_coef.size - 1)],
        e_coef=np.zeros_like(small.drive.e_coef),
    )
    m = dataclasses.replace(
        small, drive=flat, firing_ripple=0.0, half_order_ripple=0.0, blade_pass_ripple=0.0
    )
    ts = simulate_exudyn(m, 0.02, output_step=1e-3)
    assert ts.success
    f0 = m.torque / m.drive.lambda1  # static mesh force (N)
    assert np.abs(ts["mesh_force_N"] - f0).max() < 1e-9 * f0


# ------------------------------------------------------------------ step limit
def _one_step(method, k, c, y0, h):
    """exudyn's one-step map of x'' = -k x - c x' (unit mass) from y0 = [x, v]."""
    import exudyn.itemInterface as ii

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    nd = mbs.AddNode(ii.Node1D(initialCoordinates=[y0[0]], initialVelocities=[y0[1]]))
    mbs.AddObject(ii.ObjectMass1D(nodeNumber=nd, mass=1.0))
    g = mbs.AddNode(ii.NodePointGround())
    mg = mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=g, coordinate=0))
    mn = mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=nd, coordinate=0))
    mbs.AddObject(
        ii.ObjectConnectorCoordinateSpringDamper(markerNumbers=[mg, mn], stiffness=k, damping=c)
    )
    mbs.Assemble()
    s = xb._settings(0.0, h, 1, h)
    ok, err, _ = xb._solve(mbs, s, method)
    assert ok, err
    ov = exu.OutputVariableType
    return np.array(
        [mbs.GetNodeOutput(nd, ov.Coordinates), mbs.GetNodeOutput(nd, ov.Coordinates_t)]
    )


@pytest.mark.parametrize("method", ["RK44", "RK67"])
def test_stability_polynomial_matches_exudyns_one_step_map(method):
    # One step of a linear system y' = A y is R(hA) y: the polynomial the step limit
    # uses must reproduce exudyn's step to rounding (1e-12), for damped and undamped A.
    c = np.array(xb._STABILITY[method])
    for k, d, h in [(1.0, 0.0, 0.7), (4.0, 0.3, 0.4), (0.5, 1.2, 1.1)]:
        A = np.array([[0.0, 1.0], [-k, -d]])
        R = sum(ck * np.linalg.matrix_power(h * A, i) for i, ck in enumerate(c))
        got = np.column_stack(
            [_one_step(method, k, d, [1.0, 0.0], h), _one_step(method, k, d, [0.0, 1.0], h)]
        )
        np.testing.assert_allclose(got, R, rtol=0, atol=1e-12)


def test_step_beyond_the_stability_limit_is_refused_and_divergence_is_located(small, monkeypatch):
    lim = stability_step_limit(small, "RK67")
    # The limit sits near the mesh mode: h omega_max of order 1 (ISO 6336-1 mesh
    # resonance about 2.5 kHz here, so h about 1e-4 s).
    assert 2e-5 < lim < 5e-4
    y0 = small.static_state()
    t_eval = np.arange(1, 201) * 5 * lim
    with pytest.raises(InputError, match="step"):
        integrate_exudyn(small, y0, t_eval, ExudynSolver(step=1.5 * lim))
    # Bypass the guard: the run blows up, and the report says when and where.
    monkeypatch.setattr(xb, "_step_limit", lambda plan, method: 1.0)
    t, Y, info = integrate_exudyn(small, y0, t_eval, ExudynSolver(step=2.0 * lim))
    assert info["status"] in ("divergence", "nan")
    f = info["failure"]
    assert 0.0 < f.time <= t_eval[-1]
    assert len(f.state) == 2 * small.n_dof and np.all(np.isfinite(f.state))
    monkeypatch.undo()
    # Below the limit the same run is fine.
    t, Y, info = integrate_exudyn(small, y0, t_eval[:20], ExudynSolver(step=0.5 * lim))
    assert info["status"] == "success"


# ------------------------------------------------------------------ stress
@pytest.mark.slow
def test_light_load_with_backlash_agrees_with_scipy_through_impacts():
    # Light torque (150 N m), firing ripple 2x mean at 600 rpm, 0.1 mm backlash: the
    # flanks separate and the coast flank is hit (as in test_drivetrain.py). The fixed
    # step crosses the contact kinks without locating them, so agreement is looser:
    # RMS within 1e-3 of scipy at rtol 1e-10 (measured 1e-5 when written; the mesh-order
    # amplitude, a small line under the impacts, differed by 2e-2, so it is not asserted).
    s = case03(firing_torque_ripple=2.0).replaced(load={"operating_torque_Nm": 150.0})
    table = analytical_table(pair_from_scene(s), [150.0, 300.0, 450.0], positions=24)
    m = DrivetrainModel.from_scene(s, table, speed_rpm=600.0)
    ref = simulate(m, ScipySolver(rtol=1e-10), mesh_cycles=60, samples_per_cycle=16)
    exd = simulate(m, ExudynSolver(), mesh_cycles=60, samples_per_cycle=16)
    assert ref.success and exd.success
    f = exd["mesh_force_N"]
    assert (f == 0).any() and (f < 0).any(), "no contact loss or no coast impact"
    a, b = mesh_force_metrics(exd, m), mesh_force_metrics(ref, m)
    assert rel(a["mesh_force_rms_N"], b["mesh_force_rms_N"]) < 1e-3


def test_stiffness_times_100_gets_a_smaller_automatic_step(small):
    # x100 stiffness moves the mesh mode up 10x: the automatic step and the limit
    # follow (both scale with 1/omega_max), and the run stays finite.
    stiff = dataclasses.replace(
        small,
        drive=dataclasses.replace(
            small.drive, k_coef=small.drive.k_coef * 100, damping=small.drive.damping * 10
        ),
    )
    ratio = stability_step_limit(small) / stability_step_limit(stiff)
    assert 7 < ratio < 11
    ts = simulate_exudyn(stiff, 0.01, output_step=2e-4)
    assert ts.success and np.all(np.isfinite(ts["mesh_force_N"]))
    assert ts.attrs["step_s"] < stability_step_limit(stiff)


# ------------------------------------------------------------------ interface
def test_simulate_exudyn_returns_a_timeseries_with_work_counters(small):
    ts = simulate_exudyn(small, 0.01, output_step=5e-4, t_record=0.005)
    assert ts.success and ts.status == "success"
    np.testing.assert_allclose(ts.time, 0.005 + 5e-4 * np.arange(11), atol=1e-12)
    assert ts.units["mesh_force_N"] == "N" and ts.units["pinion_speed_rad_per_s"] == "rad/s"
    assert ts.steps > 0 and ts.nfev == 7 * ts.steps and ts.wall_time > 0
    assert ts.attrs["solver"] == "exudyn"
    assert ExudynSolver.from_dict(ExudynSolver(method="RK44").to_dict()) == ExudynSolver(
        method="RK44"
    )


def test_bad_settings_and_requests_are_reported_together(small):
    with pytest.raises(InputError) as e:
        ExudynSolver(method="RK5", step=-1.0, layout="tree", user_functions="C").validate()
    msg = str(e.value)
    assert len(e.value.problems) == 4
    for word in ("method", "step", "layout", "user_functions"):
        assert word in msg
    y0 = small.static_state()
    with pytest.raises(InputError, match="uniformly spaced"):
        integrate_exudyn(small, y0, np.array([1e-3, 2e-3, 4e-3]))
    bad = y0.copy()
    bad[2] = math.nan
    with pytest.raises(InputError, match="y0"):
        integrate_exudyn(small, bad, np.array([1e-3, 2e-3]))
    with pytest.raises(InputError, match="t_end"):
        simulate_exudyn(small, -1.0)
    # a very fine step meets the step cap before anything runs
    with pytest.raises(InputError, match="max_steps"):
        integrate_exudyn(small, y0, np.array([1e-3, 2e-3]), ExudynSolver(step=1e-9, max_steps=1000))


def _resonant(small):
    from gearbox.drivetrain.linear import modes

    rpm = modes(small).frequencies[-1] / small.pinion_teeth * 60
    return small.with_speed(rpm * math.pi / 30)


def _jump(small):
    # a 1.5x step in stiffness over half the mesh cycle (as test_drivetrain.py), fitted
    # by all 24 harmonics: Gibbs ripple, but a smooth right-hand side
    s = case03(governor=True, half_order_ripple=0.05, engine_harmonics=2)
    table = analytical_table(pair_from_scene(s), [150.0, 300.0, 450.0], positions=24)
    k = table.stiffness.copy()
    k[:, :, 12:] *= 1.5
    lam1 = table.rotation_radii("drive", 300.0)[0]
    lte = (table.torque / lam1)[None, :, None] / k
    return DrivetrainModel.from_scene(
        s, dataclasses.replace(table, stiffness=k, tangent_stiffness=k, lte=lte)
    )


def _bearings(small):
    return dataclasses.replace(small, bearing_dofs=True)


@pytest.mark.slow
@pytest.mark.parametrize("variant", [_resonant, _jump, _bearings])
def test_stress_cases_agree_with_scipy(small, variant):
    # Operation at the mesh resonance, a table with a stiffness jump, and the 6-DOF
    # model with bearing translations: the default exudyn run against scipy at rtol
    # 1e-10 over 30 mesh cycles, RMS and mesh-order amplitude within 1e-4 (the issue's
    # agreement figure). Measured when written (amplitude): 7.4e-5 at the resonance
    # (the lightly damped mesh mode, Q about 10, magnifies the integrator's phase
    # error; the fixed-step run is deterministic), 4e-9 with the jump, 2e-8 with bearings.
    m = variant(small)
    ref = simulate(m, ScipySolver(rtol=1e-10), mesh_cycles=30)
    exd = simulate(m, ExudynSolver(), mesh_cycles=30)
    assert ref.success and exd.success, (ref.failure, exd.failure)
    a, b = mesh_force_metrics(exd, m), mesh_force_metrics(ref, m)
    for key in ("mesh_force_rms_N", "mesh_force_mesh_order_amplitude_N"):
        assert rel(a[key], b[key]) < 1e-4, (variant.__name__, key, a[key], b[key])
