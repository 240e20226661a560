"""exudyn backend with mesh friction (docs/drivetrain.md §3a): the friction torques
-mu phi_1(theta_1) F_f on the pinion and +mu phi_2(theta_1) F_f on the gear in the
exudyn user functions, agreement with the reference backends, the friction's effect on
the power flow, and the mu = 0 path left as it was.

The model is the default scene (models/marine_drive.toml) with its analytical mesh
table, which carries the friction arms, at mu = 0.1 and at mu = 0 (set here, whatever
the scene's own coefficient)."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

from _exudyn_helpers import force_function_errors, random_cases, rel  # noqa: E402

from gearbox.drivetrain import exudyn_backend as xb  # noqa: E402
from gearbox.drivetrain.exudyn_backend import ExudynSolver, build_exudyn_system  # noqa: E402
from gearbox.drivetrain.model import DrivetrainModel, outputs  # noqa: E402
from gearbox.drivetrain.simulate import (  # noqa: E402
    default_solver,
    mesh_force_metrics,
    periodic_start_state,
    record_times,
    simulate,
)
from gearbox.scene import load_scene  # noqa: E402

MODELS = Path(__file__).resolve().parents[1] / "models"
MU = 0.1
METRICS = ("mesh_force_rms_N", "mesh_force_dynamic_rms_N", "mesh_force_mesh_order_amplitude_N")
FRICTION_CHANNELS = (
    "pinion_friction_torque_Nm",
    "gear_friction_torque_Nm",
    "mesh_friction_power_W",
)


def propeller_power(ts):
    """Mean power absorbed by the propeller (W)."""
    return float(np.mean(ts["propeller_torque_Nm"] * ts["propeller_speed_rad_per_s"]))


def engine_power(ts):
    """Mean power delivered by the engine (W)."""
    return float(np.mean(ts["engine_torque_Nm"] * ts["engine_speed_rad_per_s"]))


@pytest.fixture(scope="module")
def scene():
    """The default scene, its own friction coefficient replaced in the models below."""
    return load_scene(MODELS / "marine_drive.toml")


@pytest.fixture(scope="module")
def frictionless(scene):
    """The default scene at mu = 0 (its mesh flanks still carry the friction arms)."""
    m = DrivetrainModel.from_scene(scene.replaced(drivetrain={"mesh_friction_coefficient": 0.0}))
    assert m.mesh_friction_coefficient == 0.0 and m.drive.friction_coef is not None
    return m


@pytest.fixture(scope="module")
def friction(scene):
    """The default scene with mu = 0.1 (both flanks' friction arms in use)."""
    m = DrivetrainModel.from_scene(scene.replaced(drivetrain={"mesh_friction_coefficient": MU}))
    assert m.drive.friction_coef is not None and m.coast.friction_coef is not None
    return m


@pytest.fixture(scope="module")
def runs(frictionless, friction):
    """exudyn and diffrax (the default solvers) at mu = 0 and mu = 0.1, 40 mesh cycles
    after the 20 cycles of settling of ``simulate``."""
    out = {}
    for name in ("exudyn", "diffrax"):
        for mu, model in ((0.0, frictionless), (MU, friction)):
            ts = simulate(model, default_solver(name), mesh_cycles=40)
            assert ts.success, (name, mu, ts.failure)
            out[name, mu] = ts
    return out


def model_outputs(model, t, Y):
    """Mesh force and pinion friction torque of a run, stacked (N, N m)."""
    ch = outputs(model, t, Y)
    return np.concatenate([ch["mesh_force_N"], ch["pinion_friction_torque_Nm"]])


def _without_friction(plan):
    """The plan with the friction series removed: what the backend built before it
    knew friction (the comparison showing the tests see the friction torques)."""
    flanks = tuple(dataclasses.replace(fl, f1=None, f2=None) for fl in plan.flanks)
    return dataclasses.replace(plan, flanks=flanks)


# ------------------------------------------------------------------ force functions
def test_friction_force_functions_equal_the_model_right_hand_side(friction):
    # Generic layout: M a = f_user(t, q, v) - K q - C v must equal M times the model's
    # rhs (which holds the friction torques, gearbox.drivetrain.model.friction_torques)
    # at random states near the operating point, a quarter pushed through the backlash
    # onto the coast flank; symbolic and plain Python user functions. Tolerance 1e-9 of
    # the largest term, as for the frictionless functions in test_drivetrain_exudyn.py
    # (rounding; measured 5e-15 symbolic, 4e-14 Python). Without the friction series
    # the same comparison is off by up to 1.6e-2 of that term (asserted > 1e-4), so the
    # check sees the friction torques.
    model = friction
    assert all(fl.friction for fl in xb._plan_from_model(model).flanks)
    cases = random_cases(model, np.random.default_rng(1), 16)
    errors, contact, missing = force_function_errors(model, cases, _without_friction)
    for name, err in errors.items():
        assert err < 1e-9, (name, err)
    assert contact[:, 1].sum() >= 1  # the coast flank's arms were exercised
    assert missing > 1e-4, missing


def test_friction_layouts_and_user_function_kinds_give_the_same_run(friction):
    # Components and generic layout, symbolic and Python user functions, with friction
    # and with the bearing translations (the mesh object then spans four coordinates,
    # the friction torques act on two of them): the same equations at the same fixed
    # step agree to rounding, 1e-9 of the channels' spread (as without friction in
    # test_drivetrain_exudyn.py; measured 1e-12, 1.7e-12 with the bearings).
    for model in (friction, dataclasses.replace(friction, bearing_dofs=True)):
        y0 = model.static_state()
        t_eval = np.arange(1, 61) * 1e-4
        forces = {}
        for uf in ("symbolic", "python"):
            for layout in ("components", "generic"):
                t, Y, info = xb.integrate_exudyn(
                    model, y0, t_eval, ExudynSolver(user_functions=uf, layout=layout)
                )
                assert info["status"] == "success", info
                forces[uf, layout] = model_outputs(model, t, Y)
        f0 = forces["symbolic", "components"]
        for key, f in forces.items():
            assert np.abs(f - f0).max() < 1e-9 * np.std(f0) + 1e-9, (model.bearing_dofs, key)


# ------------------------------------------------------------------ agreement
def test_exudyn_with_friction_agrees_with_diffrax(friction, runs):
    # exudyn (RK67, automatic fixed step) against diffrax (its default fixed steps) at
    # mu = 0.1 over 40 mesh cycles after 20 of settling.
    # - RMS, dynamic RMS and mesh-order amplitude of the mesh force within 1e-4 relative
    #   (the agreement figure, as test_drivetrain_exudyn.py; measured <= 7e-6,
    #   the same as without friction: diffrax's fixed step sets it, exudyn agrees with
    #   scipy at rtol 1e-10 to 7e-7).
    # - Mean friction torques on pinion and gear and mean friction power within 1e-4
    #   relative (measured 1.3e-6, 1.1e-6, 3e-7).
    # - Sample by sample, the mesh force's RMS error over its dynamic RMS below 1e-3
    #   (measured 1.2e-4; 8e-5 without friction: the diffrax step's phase error).
    # Before the friction torques were in the exudyn functions the run differed by 3e-3
    # (mesh force RMS), 1.2e-2 (mean gear friction torque) and 7e-2 (sample-wise).
    exd, ref = runs["exudyn", MU], runs["diffrax", MU]
    np.testing.assert_allclose(exd.time, ref.time, rtol=0, atol=1e-12)
    a, b = mesh_force_metrics(exd, friction), mesh_force_metrics(ref, friction)
    for key in METRICS:
        assert rel(a[key], b[key]) < 1e-4, (key, a[key], b[key])
    for key in FRICTION_CHANNELS:
        assert key in exd.channels and exd.units[key] == ref.units[key]
        assert rel(np.mean(exd[key]), np.mean(ref[key])) < 1e-4, key
    err = np.sqrt(np.mean((exd["mesh_force_N"] - ref["mesh_force_N"]) ** 2)) / np.std(
        ref["mesh_force_N"]
    )
    assert err < 1e-3, err


def test_friction_takes_its_loss_out_of_the_propeller_power(runs):
    # mu = 0.1 against mu = 0, both exudyn:
    # - the friction dissipates: mesh_friction_power_W > 0 at every sample, its mean
    #   about mu H of the engine power (H the loss factor; measured 3.93 kW of 297.9 kW,
    #   1.32 %, so H = 0.13); asserted between 0.5 % and 3 %.
    # - the mean propeller power drops by about the mean friction power: measured
    #   4.00 kW against 3.93 kW, a ratio of 1.018 (the same to 1e-6 with diffrax and
    #   scipy, so it is the model's, not the integrator's: the propeller coefficient
    #   is set from the arms' cycle means, the dissipation is the mean of the arms times
    #   the varying force); asserted within 5 %.
    # - the engine power is the same to 1e-4 (measured 1.2e-5): the loss comes out of
    #   the propeller side.
    # The same figures from the diffrax runs agree to 1e-4 (measured 1e-6): exudyn's
    # friction is the reference's.
    figures = {}
    for name in ("exudyn", "diffrax"):
        off, on = runs[name, 0.0], runs[name, MU]
        assert not any(key in off.channels for key in FRICTION_CHANNELS)
        loss = on["mesh_friction_power_W"]
        assert np.all(loss > 0)
        pe = engine_power(on)
        assert rel(pe, engine_power(off)) < 1e-4
        assert 0.005 < np.mean(loss) / pe < 0.03, np.mean(loss) / pe
        drop = propeller_power(off) - propeller_power(on)
        assert abs(drop / np.mean(loss) - 1.0) < 0.05, (drop, np.mean(loss))
        figures[name] = (drop, float(np.mean(loss)))
    for got, want in zip(figures["exudyn"], figures["diffrax"], strict=True):
        assert rel(got, want) < 1e-4, figures


# ------------------------------------------------------------------ mu = 0
def test_without_friction_the_exudyn_system_is_unchanged(scene, frictionless):
    # mu = 0 builds no friction: the plan has no friction series, the recorded mesh
    # expression and the run are identical (bit for bit) to those of a model whose mesh
    # table has no friction arms at all, so the mu = 0 path costs nothing extra. The
    # frictionless run's agreement with scipy and diffrax is tested in
    # test_drivetrain_exudyn.py.
    bare = dataclasses.replace(
        frictionless,
        drive=dataclasses.replace(frictionless.drive, friction_coef=None),
        coast=dataclasses.replace(frictionless.coast, friction_coef=None),
    )
    plan = xb._plan_from_model(frictionless)
    assert not any(fl.friction for fl in plan.flanks)
    assert all(fl.W is fl.G for fl in plan.flanks)
    assert xb.stability_step_limit(frictionless) == xb.stability_step_limit(bare)
    a, b = build_exudyn_system(frictionless), build_exudyn_system(bare)
    assert str(a.keepalive[-1][2]) == str(b.keepalive[-1][2])
    assert len(a.mbs.GetObject(a.mesh_object)["nodeNumbers"]) == 2
    y0 = periodic_start_state(frictionless)
    tm = 1.0 / frictionless.mesh_frequency
    t_eval = np.concatenate([[20 * tm], record_times(frictionless, 20 * tm, 10, 32)])
    ra = xb.integrate_exudyn(frictionless, y0, t_eval)
    rb = xb.integrate_exudyn(bare, y0, t_eval)
    assert ra[2]["status"] == rb[2]["status"] == "success"
    np.testing.assert_array_equal(ra[1], rb[1])
    # with friction the expression grows by the arms' series (measured 8136 -> 15711
    # characters) and the stability limit moves a little (the force's mean direction
    # W = G + Phi in the linearisation; measured -0.1 %)
    fric = DrivetrainModel.from_scene(scene.replaced(drivetrain={"mesh_friction_coefficient": MU}))
    c = build_exudyn_system(fric)
    assert len(str(c.keepalive[-1][2])) > len(str(a.keepalive[-1][2]))
    assert rel(xb.stability_step_limit(fric), xb.stability_step_limit(frictionless)) < 1e-2
