"""Mesh friction in the FMUs (docs/drivetrain.md §3a): the drivetrain and gearbox FMUs of
the default scene with mu = 0.1 set here (``drivetrain.mesh_friction_coefficient``; the
analytical mesh table carries the friction arms) against the Python reference, FMI 2.0
and 3.0.

The reference is the one of tests/test_fmu.py: the scipy solver (DOP853, rtol 1e-10) on
the numpy right-hand side ``gearbox.drivetrain.model.rhs``, which applies the friction
torques -mu phi_1 F on the pinion and +mu phi_2 F on the gear, an implementation
independent of the generated C.
"""

from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from _fmu_helpers import (
    cosim_against_drivetrain,
    cs_instance,
    flange_inputs,
    fmu_log,
    me_derivatives,
    rhs_derivatives,
)

fmpy = pytest.importorskip("fmpy")

from gearbox import load_scene  # noqa: E402
from gearbox.drivetrain.model import outputs  # noqa: E402
from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy  # noqa: E402
from gearbox.errors import InputError  # noqa: E402
from gearbox.fmu import build_fmu, drivetrain_fmu, gearbox_fmu  # noqa: E402
from gearbox.fmu.build import find_c_compiler  # noqa: E402
from gearbox.fmu.models import FRICTION_ARMS, model_from_scene  # noqa: E402
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "marine_drive.toml"
MU = 0.1
STOP = 0.02  # s, as tests/test_fmu.py: 34 mesh cycles at 3500 rpm
FRICTION_OUTPUTS = {
    "mesh.pinion_friction_torque": "pinion_friction_torque_Nm",
    "mesh.gear_friction_torque": "gear_friction_torque_Nm",
    "mesh.friction_power": "mesh_friction_power_W",
}

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


def _without_arms(table):
    return replace(table, extra={k: v for k, v in table.extra.items() if k not in FRICTION_ARMS})


@pytest.fixture(scope="module")
def model_table():
    scene = load_scene(SCENE).replaced(drivetrain={"mesh_friction_coefficient": MU})
    model, table = model_from_scene(scene)
    assert model.mesh_friction_coefficient == MU and model.drive.friction_coef is not None
    return model, table


@pytest.fixture(scope="module")
def built(model_table, tmp_path_factory):
    model, table = model_table
    out = tmp_path_factory.mktemp("fmu_friction")
    return {
        "drivetrain": build_fmu(drivetrain_fmu(model, table), out),
        "gearbox": build_fmu(gearbox_fmu(model, table), out),
        "drivetrain3": build_fmu(drivetrain_fmu(model, table), out, fmi_version=3),
        # the same model from the table without the arms: the FMU without friction code
        "frictionless": build_fmu(
            drivetrain_fmu(replace(model, mesh_friction_coefficient=0.0), _without_arms(table)),
            out / "frictionless",
        ),
    }


@pytest.fixture(scope="module")
def reference(model_table):
    """scipy DOP853, rtol 1e-10, sampled every 1e-4 s (with the friction channels)."""
    model, _ = model_table
    t = np.linspace(0.0, STOP, int(round(STOP / 1e-4)) + 1)
    tt, y, info = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=1e-10))
    assert info["status"] == "success"
    ch = outputs(model, tt, y)
    assert set(FRICTION_OUTPUTS.values()) <= set(ch)
    return tt, ch


def test_builds_validate_and_declare_the_friction(built, model_table):
    """Warning-free builds that fmpy accepts; mesh.friction_coefficient a tunable
    parameter with the model's start value, the scene's range [0, 0.3], unit and
    description; the friction torques as outputs; the arms as two more columns of the
    mesh samples. Without arms in the table: neither, and 8 columns as before."""
    from fmpy.validation import validate_fmu

    _, table = model_table
    for name, b in built.items():
        assert b.compiler_output == "", (name, b.compiler_output)
        assert validate_fmu(b.fmu) == [], name
    zf = zipfile.ZipFile(built["drivetrain"].fmu)
    root = ET.fromstring(zf.read("modelDescription.xml"))
    sv = {v.get("name"): v for v in root.iter("ScalarVariable")}
    mu = sv["mesh.friction_coefficient"]
    real = mu.find("Real")
    assert mu.get("causality") == "parameter" and mu.get("variability") == "tunable"
    assert float(real.get("start")) == MU and real.get("unit") == "1"
    assert (float(real.get("min")), float(real.get("max"))) == (0.0, 0.3)
    assert "friction" in mu.get("description")
    for name in FRICTION_OUTPUTS:
        assert sv[name].get("causality") == "output" and sv[name].get("description")
    samples = zf.read("resources/mesh_samples.txt").decode().splitlines()
    assert samples[0] == f"gearbox-table 1 {table.angle.size * table.torque.size * 2} 10"
    names = {
        v.get("name")
        for v in ET.fromstring(
            zipfile.ZipFile(built["gearbox"].fmu).read("modelDescription.xml")
        ).iter("ScalarVariable")
    }
    assert {"mesh.friction_coefficient", *FRICTION_OUTPUTS} <= names
    zf = zipfile.ZipFile(built["frictionless"].fmu)
    names = {
        v.get("name") for v in ET.fromstring(zf.read("modelDescription.xml")).iter("ScalarVariable")
    }
    assert not {"mesh.friction_coefficient", *FRICTION_OUTPUTS} & names
    assert zf.read("resources/mesh_samples.txt").decode().splitlines()[0].endswith(" 8")


def test_friction_without_arms_in_the_table_is_a_build_error(model_table):
    model, table = model_table
    for make in (drivetrain_fmu, gearbox_fmu):
        with pytest.raises(
            InputError,
            match="mesh_friction_coefficient = 0.1: needs the mesh table's friction arms",
        ):
            make(model, _without_arms(table))


@pytest.mark.parametrize(
    "kind, interface, rtol, tol",
    [
        # tolerances of tests/test_fmu.py (same equations, rtol 1e-8 against 1e-10):
        # measured, mesh force / friction torques / friction power / shaft torques,
        # DOPRI5 4.7e-7 / 1.6e-7 / 1.1e-6 / 2e-8, fixed-step Tsit5 5.8e-7 / 1.9e-7 /
        # 1.3e-6 / 5e-8, CVode 3.4e-6 / 1.1e-6 / 7.9e-6 / 1.2e-7, FMI 3.0 DOPRI5 as
        # FMI 2.0 to the last digit; bounds 6-20x above (the loss, the product of
        # torque and speed, is the closest), room for other compilers and libm
        ("drivetrain", "CoSimulation", 1e-8, 1e-5),
        ("drivetrain", "CoSimulation", None, 1e-5),
        ("drivetrain", "ModelExchange", 1e-8, 5e-5),
        ("drivetrain3", "CoSimulation", 1e-8, 1e-5),
    ],
    ids=["cs_dopri5", "cs_fixed_step", "me_cvode", "fmi3_cs"],
)
def test_friction_matches_python_reference(
    built, reference, model_table, kind, interface, rtol, tol
):
    """Every channel the friction touches: the mesh force, the shaft torques, the friction
    torques and the friction loss, as RMS error over the reference's AC RMS; the means of
    the friction torques and loss to 1e-6 relative (measured at most 3.6e-8, CVode).
    The propeller torque at t = 0 is kappa Omega_2^2 with the friction's torque ratio
    (DrivetrainModel.propeller_coefficient, 1.4 % below the frictionless one): measured
    equal to 6e-16, 1e-12 allowed (round-off)."""
    model, _ = model_table
    t_ref, ref = reference
    pairs = {
        "mesh.force": "mesh_force_N",
        "input_shaft.torque": "input_shaft_torque_Nm",
        "output_shaft.torque": "output_shaft_torque_Nm",
        **FRICTION_OUTPUTS,
    }
    t, ch, _ = simulate_fmu(
        built[kind].fmu,
        interface=interface,
        stop_time=STOP,
        step=1e-4,
        rtol=rtol,
        outputs=[*pairs, "propeller.torque"],
    )
    for var, channel in pairs.items():
        assert ac_relative_error(t, ch[var], t_ref, ref[channel]) < tol, var
    for var in FRICTION_OUTPUTS:
        mean = ref[FRICTION_OUTPUTS[var]].mean()
        assert abs(ch[var].mean() - mean) < 1e-6 * abs(mean), var
    tp0 = model.propeller_coefficient * model.gear_speed**2
    assert ch["propeller.torque"][0] == pytest.approx(tp0, rel=1e-12)
    assert (
        model.propeller_coefficient
        < replace(model, mesh_friction_coefficient=0.0).propeller_coefficient
    )


@pytest.mark.parametrize("kind", ["drivetrain", "gearbox"])
def test_right_hand_side_with_friction_agrees_with_numpy(built, model_table, kind):
    """Derivatives of the Model Exchange FMU at 200 random states about the static
    equilibrium and times in [0, 0.05] s against ``rhs`` (the gearbox FMU: pinion, gear
    and bearing rows, the flanges as inputs from the same state). Measured max
    |difference| / std over the samples 2.7e-12 (pinion, gear), 5.2e-10 (engine),
    1.8e-9 (propeller): the grids' interpolation error, as without friction in
    tests/test_fmu.py, whose 2e-8 bound stands; leaving the friction out would show as
    5-8 % (pinion, gear) and 42 % (propeller, kappa). The initial state is the model's
    static state with friction (which the friction moves by 1 % of its largest
    deviation): measured 1.3e-13 of that deviation, 1e-11 allowed (round-off of two
    linear solvers)."""
    model, _ = model_table
    p = model.params()
    y0, scale = model.static_state(), model.state_scale()
    n = model.n_dof
    dofs = list(range(n)) if kind == "drivetrain" else [i for i in range(n) if i not in (0, 3)]
    rows = np.array(dofs + [n + i for i in dofs])
    rng = np.random.default_rng(11)
    times = rng.uniform(0.0, 0.05, 200)
    states = y0 + 0.3 * scale * rng.standard_normal((200, 2 * n))  # in drive contact

    flanges = flange_inputs(model, states) if kind == "gearbox" else None
    x0, got = me_derivatives(
        built[kind].fmu, times, states[:, rows], inputs=flanges, name="friction"
    )
    assert np.max(np.abs(x0 - y0[rows])) < 1e-11 * np.abs(y0).max()
    got, want = np.array(got), rhs_derivatives(p, times, states, rows)
    rel = np.abs(got - want).max(axis=0) / want.std(axis=0)
    assert rel.max() < 2e-8, rel


def test_fixed_step_rule_follows_the_friction(built, model_table):
    """solver.stability_limit is the Python rule's (gearbox.drivetrain.fixed_step, whose
    linearisation carries the mean friction direction W = G + Phi): measured 8.7e-12
    relative, 1e-9 allowed as in tests/test_fmu.py; the friction moves the limit by
    8.4e-4, so a frictionless linearisation would fail. The parameter is tunable: a new
    mu during the run moves the limit; one beyond the scene's range (0.3) is refused with
    a message and changes nothing."""
    from gearbox.drivetrain.diffrax_backend import DiffraxSolver
    from gearbox.drivetrain.fixed_step import step_targets

    model, _ = model_table
    limit = float(step_targets(model, DiffraxSolver())[1][0])
    log = fmu_log()
    fmu, vr, d = cs_instance(built["drivetrain"].fmu, log, name="rule")
    try:
        fmu.exitInitializationMode()
        lim = vr["solver.stability_limit"]
        assert fmu.getReal([lim])[0] == pytest.approx(limit, rel=1e-9)
        fmu.doStep(0.0, 1e-3)
        fmu.setReal([vr["mesh.friction_coefficient"]], [0.2])
        assert abs(fmu.getReal([lim])[0] / limit - 1) > 1e-4
        with pytest.raises(Exception, match="fmi2SetReal"):
            fmu.setReal([vr["mesh.friction_coefficient"]], [0.5])  # beyond the range
        assert "mesh.friction_coefficient = 0.5 is invalid" in log.messages[-1][1], log.messages
        assert fmu.getReal([vr["mesh.friction_coefficient"]]) == [0.2]
        fmu.doStep(1e-3, 1e-3)
        assert np.isfinite(fmu.getReal([vr["mesh.force"]])[0])
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(d, ignore_errors=True)


def test_friction_lowers_the_propeller_torque_by_the_friction_loss(built, model_table):
    """The same FMU with mesh.friction_coefficient = 0 gives the result of the FMU built
    without friction code (measured: equal to the last bit; 1e-12 allowed), and its mean
    propeller torque over 0.02 s is higher than with mu = 0.1 by the mean friction loss
    over the gear speed, P_f / Omega_2 = 16.8 N m (1.3 % of the propeller torque), and
    so is the output shaft torque: measured drop over loss 1.022 (propeller), 1.018
    (shaft). kappa takes the friction with the arms' cycle means, the loss with their
    products with the varying mesh force (1.1 % apart here); 5 % allowed."""
    model, _ = model_table
    outs = ["propeller.torque", "output_shaft.torque", "mesh.force", "mesh.friction_power"]
    runs = {}
    for name, kind, start in [
        ("mu", "drivetrain", {}),
        ("zero", "drivetrain", {"mesh.friction_coefficient": 0.0}),
        ("none", "frictionless", {}),
    ]:
        _, ch, _ = simulate_fmu(
            built[kind].fmu,
            stop_time=STOP,
            step=1e-4,
            outputs=outs if kind == "drivetrain" else outs[:3],
            start_values=start,
        )
        runs[name] = ch
    for var in outs[:3]:
        scale = np.abs(runs["none"][var]).max()
        assert np.max(np.abs(runs["zero"][var] - runs["none"][var])) <= 1e-12 * scale, var
    assert np.all(runs["zero"]["mesh.friction_power"] == 0.0)
    loss = runs["mu"]["mesh.friction_power"].mean() / model.gear_speed
    assert loss > 0.01 * runs["zero"]["propeller.torque"].mean()
    for var in ("propeller.torque", "output_shaft.torque"):
        drop = runs["zero"][var].mean() - runs["mu"][var].mean()
        assert drop == pytest.approx(loss, rel=0.05), var


def test_co_simulated_gearbox_with_friction_agrees_with_the_monolithic_fmu(
    built, model_table, tmp_path
):
    """Engine, gearbox (with friction) and propeller FMUs on libcosim against the
    drivetrain FMU with friction, as tests/test_cosim.py: the propeller FMU's nominal
    torque and the engine's initial deviation carry the friction (kappa, static state),
    so the split system starts in the same equilibrium. Measured over 0.01 s at a 5e-5 s
    communication step 3.0e-5 (mesh force), 7.3e-4 (input shaft torque), the figures of
    the frictionless model; bounds of tests/test_cosim.py (4x, 3x above). The mean mesh
    force at the communication points: measured 8e-7 relative (as without friction),
    1e-5 allowed."""
    pytest.importorskip("libcosimpy")
    model, table = model_table
    force, torque, mean = cosim_against_drivetrain(
        model, table, built["gearbox"], built["drivetrain"].fmu, tmp_path
    )
    assert force < 1.2e-4
    assert torque < 2e-3
    assert mean < 1e-5
