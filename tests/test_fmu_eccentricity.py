"""Eccentricities in the FMUs (docs/drivetrain.md §3b): the drivetrain and gearbox FMUs
of the default scene with the pinion's eccentricity 20 um at 30 deg and the gear's
15 um at -60 deg set here against the Python reference, FMI 2.0 and 3.0.

The reference is the one of tests/test_fmu.py: the scipy solver (DOP853, rtol 1e-10) on
the numpy right-hand side ``gearbox.drivetrain.model.rhs``, which adds the approach
eps_f = A_1f cos theta_1 + B_1f sin theta_1 + A_2f cos theta_2 + B_2f sin theta_2 and
its rate to each flank's gap, an implementation independent of the generated C (which
recomputes the coefficients from the table's samples at instantiation).
"""

from __future__ import annotations

import math
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
    fmu_rows,
    light_load,
    me_derivatives,
    rhs_derivatives,
    scipy_reference,
)

fmpy = pytest.importorskip("fmpy")

from gearbox import load_scene  # noqa: E402
from gearbox.fmu import build_fmu, drivetrain_fmu, gearbox_fmu  # noqa: E402
from gearbox.fmu.build import find_c_compiler  # noqa: E402
from gearbox.fmu.models import model_from_scene  # noqa: E402
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "marine_drive.toml"
STOP = 0.02  # s, as tests/test_fmu.py: 34 mesh cycles at 3500 rpm


def _smooth_start_angles() -> tuple[float, float]:
    """Eccentricity angles (deg) whose approach of the drive flanks is 0 at t = 0: the
    runs start from the static state (q_1s, q_2s: the shafts' static twist), and an
    approach at its peak there (29 um against the 11.8 um static deflection, for 20 and
    15 um at 30 and -60 deg) opens the flanks in the first millisecond. That start is an
    impact, which CVode crosses unlocated (5.9e-5 on the mesh force); contact loss has
    its own test below (the light-load scene)."""
    m, _ = model_from_scene(load_scene(SCENE))
    ys = m.static_state()
    out = []
    for member, theta0 in ((0, ys[1] + m.phase), (1, ys[2])):
        pu, pv = m.drive.transverse[member]
        out.append(math.degrees(math.atan2(-pu, pv) - theta0))
    return out[0], out[1]


_PSI1, _PSI2 = _smooth_start_angles()
#: scene keys (um, deg) and the FMU parameters (m, rad) of the same eccentricities
ECC = {
    "pinion_eccentricity_um": 20.0,
    "pinion_eccentricity_angle_deg": _PSI1,
    "gear_eccentricity_um": 15.0,
    "gear_eccentricity_angle_deg": _PSI2,
}
PARAMS = {  # converted as DrivetrainModel.from_scene does
    f"{member}.eccentricity{part}": conv(ECC[f"{member}_eccentricity{key}"])
    for member in ("pinion", "gear")
    for part, key, conv in (("", "_um", lambda x: x * 1e-6), ("_angle", "_angle_deg", math.radians))
}
ZERO = {"pinion.eccentricity": 0.0, "gear.eccentricity": 0.0}
OUTS = ["mesh.force", "mesh.deflection", "mesh.dte", "input_shaft.torque", "output_shaft.torque"]

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


def _eccentric(model, params):
    """The model with the FMU parameters' eccentricities (SI)."""
    return replace(model, **{k.replace(".", "_"): v for k, v in params.items()})


@pytest.fixture(scope="module")
def model_table():
    model, table = model_from_scene(load_scene(SCENE).replaced(drivetrain=ECC))
    assert model.drive.transverse is not None
    assert {k: getattr(model, k.replace(".", "_")) for k in PARAMS} == PARAMS
    return model, table


@pytest.fixture(scope="module")
def built(model_table, tmp_path_factory):
    model, table = model_table
    out = tmp_path_factory.mktemp("fmu_eccentricity")
    plain = _eccentric(model, ZERO)
    # a model without the flanks' transverse projections: the FMU without the code
    without = replace(
        plain,
        drive=replace(plain.drive, transverse=None),
        coast=replace(plain.coast, transverse=None),
    )
    return {
        "drivetrain": build_fmu(drivetrain_fmu(model, table), out),
        "gearbox": build_fmu(gearbox_fmu(model, table), out),
        "drivetrain3": build_fmu(drivetrain_fmu(model, table), out, fmi_version=3),
        "gearbox3": build_fmu(gearbox_fmu(model, table), out, fmi_version=3),
        # the default scene's FMU: eccentricities 0 as start values
        "plain": build_fmu(drivetrain_fmu(plain, table), out / "plain"),
        "without": build_fmu(drivetrain_fmu(without, table), out / "without"),
    }


@pytest.fixture(scope="module")
def reference(model_table):
    """scipy DOP853, rtol 1e-10, sampled every 1e-4 s, with and without the eccentricities."""
    model, _ = model_table
    runs = {
        name: scipy_reference(m, STOP)
        for name, m in (("ecc", model), ("none", _eccentric(model, ZERO)))
    }
    return runs["ecc"][0], {name: ch for name, (_, ch) in runs.items()}


def _variables(b):
    root = ET.fromstring(zipfile.ZipFile(b.fmu).read("modelDescription.xml"))
    tag = "ScalarVariable" if root.get("fmiVersion") == "2.0" else "Float64"
    return {v.get("name"): v for v in root.iter(tag)}


def test_builds_validate_and_declare_the_eccentricities(built):
    """Warning-free builds that fmpy accepts; the four parameters tunable with the scene's
    values as start (m, rad) and its ranges ([0, 1 mm], [-360, 360] deg); the approach
    as an output. Built from a model without the transverse projections: neither."""
    from fmpy.validation import validate_fmu

    for name, b in built.items():
        assert b.compiler_output == "", (name, b.compiler_output)
        assert validate_fmu(b.fmu) == [], name
    for name in ("drivetrain", "gearbox", "drivetrain3"):
        sv = _variables(built[name])
        for var, start in PARAMS.items():
            v = sv[var]
            real = v.find("Real") if name != "drivetrain3" else v
            assert v.get("causality") == "parameter" and v.get("variability") == "tunable"
            assert (
                float(real.get("start")) == start and "eccentricity" in v.get("description").lower()
            )
            assert real.get("unit") == ("rad" if var.endswith("angle") else "m")
            bounds = (-2 * math.pi, 2 * math.pi) if var.endswith("angle") else (0.0, 1e-3)
            assert (float(real.get("min")), float(real.get("max"))) == bounds
        assert sv["mesh.eccentricity_approach"].get("causality") == "output"
    assert float(_variables(built["plain"])["pinion.eccentricity"].find("Real").get("start")) == 0
    assert not {*PARAMS, "mesh.eccentricity_approach"} & set(_variables(built["without"]))


@pytest.mark.parametrize("kind", ["drivetrain", "gearbox", "drivetrain3", "gearbox3"])
def test_right_hand_side_with_eccentricities_agrees_with_numpy(built, model_table, kind):
    """Derivatives of the Model Exchange FMU (FMI 2.0 and 3.0) at 200 random states about
    the static equilibrium and times in [0, 0.05] s against ``rhs`` (the gearbox FMU:
    its rows, the flanges as inputs from the same state; its gear angle is its own state
    q_2, as the drivetrain's). Max |difference| / std over the samples: measured
    2.7e-12 (pinion, gear), 5.0e-10 (engine) and 1.7e-9 (propeller), the grids'
    interpolation error as in tests/test_fmu.py (bounds 1e-10 and its 2e-8). The
    eccentricities' own share, the derivatives less those of the same FMU with both set
    to 0 at instantiation against rhs's: measured 8.0e-13 of its largest value (the
    grids of the stiffness and of cos and sin), 1e-10 allowed; it reaches 2.8 std of the
    pinion's and the gear's accelerations, so a wrong sign, angle or member would show.
    The initial state is the static one (eps has zero mean)."""
    model, _ = model_table
    p, p0 = model.params(), _eccentric(model, ZERO).params()
    y0, scale = model.static_state(), model.state_scale()
    n = model.n_dof
    rows = fmu_rows(model, kind)
    rng = np.random.default_rng(11)
    times = rng.uniform(0.0, 0.05, 200)
    states = y0 + 0.3 * scale * rng.standard_normal((200, 2 * n))  # in drive contact

    flanges = flange_inputs(model, states) if "gearbox" in kind else None
    got = {}
    for name, start in (("ecc", None), ("zero", ZERO)):
        x0, got[name] = me_derivatives(
            built[kind].fmu, times, states[:, rows], start=start, inputs=flanges, name=kind
        )
        assert np.max(np.abs(x0 - y0[rows])) < 1e-11 * np.abs(y0).max()
    want = {name: rhs_derivatives(q, times, states, rows) for name, q in (("ecc", p), ("zero", p0))}
    rel = np.abs(got["ecc"] - want["ecc"]).max(axis=0) / want["ecc"].std(axis=0)
    acc = [k for k, r in enumerate(rows) if r - n in (1, 2)]  # pinion and gear accelerations
    assert rel[acc].max() < 1e-10, rel
    assert rel.max() < 2e-8, rel
    share, want_share = got["ecc"] - got["zero"], want["ecc"] - want["zero"]
    assert np.abs(share - want_share).max() < 1e-10 * np.abs(want_share).max()
    assert (np.abs(want_share).max(axis=0) / want["ecc"].std(axis=0))[acc].min() > 1.0


@pytest.mark.parametrize(
    "kind, interface, rtol, tol",
    [
        # tolerances of tests/test_fmu.py (same equations, rtol 1e-8 against 1e-10)
        ("drivetrain", "CoSimulation", 1e-8, 1e-5),
        ("drivetrain", "CoSimulation", None, 1e-5),
        ("drivetrain", "ModelExchange", 1e-8, 5e-5),
        ("drivetrain3", "CoSimulation", None, 1e-5),
        ("drivetrain3", "ModelExchange", 1e-8, 5e-5),
    ],
    ids=["cs_dopri5", "cs_fixed_step", "me_cvode", "fmi3_cs_fixed_step", "fmi3_me_cvode"],
)
def test_run_with_eccentricities_matches_python_reference(
    built, reference, kind, interface, rtol, tol
):
    """The mesh force and the approach eps_drive (``mesh.eccentricity_approach``) as RMS
    error over the reference's AC RMS. Over these 0.02 s (1.2 pinion revolutions, a
    smooth start) the eccentricities move the mesh force by 0.023 of its AC RMS, 2300x
    (CoSimulation) and 470x (ModelExchange) the bounds of tests/test_fmu.py; measured
    5.9e-7 (DOPRI5), 5.9e-7 (fixed step), 1.6e-6 (CVode), FMI 3.0 as FMI 2.0. The
    output eps is cos and sin of the pinion's and the gear's angles, evaluated exactly
    on both sides (the right-hand side reads them from a grid, within 3e-13): its
    error is the integrators' on q_1, q_2 times the eccentricities, measured 7.8e-12
    (DOPRI5), 9.4e-12 (fixed step), 2.4e-11 (CVode); 1e-9 allowed."""
    t_ref, ref = reference
    t, ch, _ = simulate_fmu(
        built[kind].fmu,
        interface=interface,
        stop_time=STOP,
        step=1e-4,
        rtol=rtol,
        outputs=["mesh.force", "mesh.eccentricity_approach"],
    )
    err = ac_relative_error(t, ch["mesh.force"], t_ref, ref["ecc"]["mesh_force_N"])
    assert err < tol, err
    effect = ac_relative_error(
        t_ref, ref["none"]["mesh_force_N"], t_ref, ref["ecc"]["mesh_force_N"]
    )
    assert effect > 100 * tol
    eps = ref["ecc"]["eccentricity_approach_m"]
    assert ac_relative_error(t, ch["mesh.eccentricity_approach"], t_ref, eps) < 1e-9
    assert np.std(eps) > 10e-6  # m: a once-per-revolution wave of each member


def test_parameters_set_at_instantiation_act_as_in_the_python_model(built, model_table, reference):
    """The default scene's FMU (eccentricities 0 as start values) with the eccentricities
    set at instantiation runs as the FMU built with them as start values, bit for bit,
    and so reads the reference (fixed step, measured 5.3e-7 as above). Other values,
    each member alone, set at instantiation: the derivatives at 50 random states follow
    ``rhs`` of the Python model with the same values (pinion and gear rows, measured
    2.0e-12 with the pinion's, 1.1e-12 with the gear's, 1e-10 allowed). The parameters
    are tunable during a run; an eccentricity beyond 1 mm is refused with a message and
    changes nothing."""
    model, _ = model_table
    t_ref, ref = reference
    runs = {
        kind: simulate_fmu(built[kind].fmu, stop_time=STOP, step=1e-4, outputs=OUTS, start_values=s)
        for kind, s in (("drivetrain", None), ("plain", PARAMS))
    }
    t, ch, _ = runs["plain"]
    for var in OUTS:
        assert np.array_equal(ch[var], runs["drivetrain"][1][var]), var
    assert ac_relative_error(t, ch["mesh.force"], t_ref, ref["ecc"]["mesh_force_N"]) < 1e-5

    rows = fmu_rows(model, "drivetrain")
    acc = [1, 2]
    rng = np.random.default_rng(5)
    times = rng.uniform(0.0, 0.05, 50)
    states = model.static_state() + 0.3 * model.state_scale() * rng.standard_normal((50, rows.size))
    for params in (
        {**ZERO, "pinion.eccentricity": 10e-6, "pinion.eccentricity_angle": 2.1},
        {**ZERO, "gear.eccentricity": 25e-6, "gear.eccentricity_angle": -2.8},
    ):
        p = _eccentric(model, params).params()
        _, got = me_derivatives(built["plain"].fmu, times, states, start=params, name="set")
        want = rhs_derivatives(p, times, states)
        rel = np.abs(got - want).max(axis=0) / want.std(axis=0)
        assert rel[[model.n_dof + i for i in acc]].max() < 1e-10, (params, rel)

    log = fmu_log()
    fmu, vr, d = cs_instance(built["plain"].fmu, log, name="tune")
    try:
        fmu.exitInitializationMode()
        fmu.doStep(0.0, 1e-3)
        assert fmu.getReal([vr["mesh.eccentricity_approach"]]) == [0.0]
        fmu.setReal([vr["pinion.eccentricity"]], [50e-6])  # tunable: accepted during the run
        with pytest.raises(Exception, match="fmi2SetReal"):
            fmu.setReal([vr["gear.eccentricity"]], [2e-3])  # beyond the range
        assert "gear.eccentricity = 0.002 is invalid" in log.messages[-1][1], log.messages
        assert fmu.getReal([vr["gear.eccentricity"]]) == [0.0]
        fmu.doStep(1e-3, 1e-3)
        assert abs(fmu.getReal([vr["mesh.eccentricity_approach"]])[0]) > 0.0
        assert np.isfinite(fmu.getReal([vr["mesh.force"]])[0])
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(d, ignore_errors=True)


@pytest.mark.parametrize(
    "interface, rtol", [("CoSimulation", None), ("CoSimulation", 1e-8), ("ModelExchange", 1e-8)]
)
def test_zero_eccentricity_is_bit_identical_to_the_fmu_without(built, interface, rtol):
    """Both eccentricities set to 0: every output equal to the last bit to that of the
    FMU built without the eccentricities' code (GBX_ECCENTRICITY 0), whose results are
    those of the FMUs before it (docs/fmu.md); the approach is 0 throughout."""
    kw = {"interface": interface, "stop_time": STOP, "step": 1e-4, "rtol": rtol}
    _, zero, _ = simulate_fmu(
        built["drivetrain"].fmu,
        outputs=[*OUTS, "mesh.eccentricity_approach"],
        start_values=ZERO,
        **kw,
    )
    _, without, _ = simulate_fmu(built["without"].fmu, outputs=OUTS, **kw)
    for var in OUTS:
        assert np.array_equal(zero[var], without[var]), var
    assert np.all(zero["mesh.eccentricity_approach"] == 0.0)


def test_fixed_step_contact_test_includes_the_eccentricities(tmp_path):
    """The light-load scene of tests/test_fmu.py (separation, coast contact at zero
    backlash) with the eccentricities: the fixed steps that end out of the nominal
    contact, with the gap s_f + eps_f (gearbox.drivetrain.fixed_step: lost), are redone
    with adaptive steps. Measured 657 intervals handed over, mesh force 6.4e-7 of the AC
    RMS off the scipy reference over 0.02 s. 1e-5 allowed (tests/test_fmu.py's). With
    the contact test left without eps the run read the reference 5.6e-4 off (measured
    once by hand on a modified build, at 60 N m, before the analytical table's radial
    sign was turned, at 668 intervals and 2.5e-6 with eps)."""
    light = {**ECC, "pinion_eccentricity_angle_deg": 30.0, "gear_eccentricity_angle_deg": -60.0}
    scene = load_scene(SCENE).replaced(drivetrain={**light_load(0.0), **light})
    model, table = model_from_scene(scene)
    fmu = build_fmu(drivetrain_fmu(model, table), tmp_path).fmu
    tt, ref = scipy_reference(model, STOP)
    assert ref["mesh_force_N"].min() < 0.0 and np.any(ref["mesh_force_N"] == 0.0)
    t, ch, _ = simulate_fmu(
        fmu, stop_time=STOP, step=1e-4, outputs=["mesh.force", "solver.handed_over"]
    )
    assert ch["solver.handed_over"][-1] > 10
    assert ac_relative_error(t, ch["mesh.force"], tt, ref["mesh_force_N"]) < 1e-5


def test_co_simulated_gearbox_with_eccentricities_agrees_with_the_monolithic_fmu(
    built, model_table, tmp_path
):
    """Engine, gearbox (with the eccentricities) and propeller FMUs on libcosim against
    the drivetrain FMU, as tests/test_cosim.py: the gearbox FMU turns its gear by its
    own state with the coupling's output flange as input. Over 0.01 s at a 5e-5 s
    communication step, mesh force measured 2.0e-5 of the AC RMS (the bound of
    tests/test_cosim.py, 6x above), its mean 4.2e-7 relative (1e-5 allowed)."""
    pytest.importorskip("libcosimpy")
    model, table = model_table
    force, _, mean = cosim_against_drivetrain(
        model, table, built["gearbox"], built["drivetrain"].fmu, tmp_path
    )
    assert force < 1.2e-4
    assert mean < 1e-5
