"""exudyn backend with eccentricities (runout, docs/drivetrain.md §3b): each flank's gap
gains the approach eps_f(theta_1, theta_2) and its rate in the exudyn user functions,
the runs agree with the scipy reference on the mesh force and on its order lines, and
without eccentricity the backend is left as it was.

The model is the default scene (models/marine_drive.toml, analytical mesh tables) with
a 20 um pinion and a 15 um gear eccentricity, at a pinion phase theta_10 = 0.7 rad (so
the gear's theta_20 = theta_10 N_1 / N_2 is not zero either), with and without the
bearing translations."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

from _exudyn_helpers import force_function_errors, random_cases, rel  # noqa: E402

from gearbox import spectrum  # noqa: E402
from gearbox.drivetrain import exudyn_backend as xb  # noqa: E402
from gearbox.drivetrain.exudyn_backend import ExudynSolver, build_exudyn_system  # noqa: E402
from gearbox.drivetrain.model import DrivetrainModel, mesh_forces, outputs  # noqa: E402
from gearbox.drivetrain.scipy_backend import ScipySolver  # noqa: E402
from gearbox.drivetrain.simulate import (  # noqa: E402
    mesh_force_metrics,
    periodic_start_state,
    record_times,
    simulate,
)
from gearbox.scene import load_scene  # noqa: E402

MODELS = Path(__file__).resolve().parents[1] / "models"
ECCENTRICITY = {
    "pinion_eccentricity_um": 20.0,
    "pinion_eccentricity_angle_deg": 30.0,
    "gear_eccentricity_um": 15.0,
    "gear_eccentricity_angle_deg": -60.0,
}
PHASE = 0.7  # rad
METRICS = ("mesh_force_rms_N", "mesh_force_dynamic_rms_N", "mesh_force_mesh_order_amplitude_N")


@pytest.fixture(scope="module")
def scene():
    return load_scene(MODELS / "marine_drive.toml")


def drive_model(scene, **drivetrain):
    """The default scene with these drivetrain keys, at pinion phase PHASE."""
    m = DrivetrainModel.from_scene(scene.replaced(drivetrain=drivetrain))
    return dataclasses.replace(m, phase=PHASE)


@pytest.fixture(scope="module", params=[False, True], ids=["rotations", "bearings"])
def bearings(request):
    return request.param


@pytest.fixture(scope="module")
def eccentric(scene, bearings):
    m = drive_model(scene, bearing_dofs=bearings, **ECCENTRICITY)
    assert m.params()["rc"].shape == (2, 4)
    return m


@pytest.fixture(scope="module")
def concentric(scene, bearings):
    """The same drive without eccentricity."""
    return drive_model(scene, bearing_dofs=bearings)


def _without_eccentricity(plan):
    """The plan with the eccentricities taken out: what the backend built before it
    knew them (the comparison showing that the tests see the approach)."""
    flanks = tuple(dataclasses.replace(fl, r1=None, r2=None) for fl in plan.flanks)
    return dataclasses.replace(plan, flanks=flanks)


def band_cases(model, rng, count):
    """(t, y): the static state with the drive flank's delta - b placed across the band
    (lo, hi] of :attr:`_Flank.gap_bounds`, where eps_f(t) decides the contact."""
    n = model.n_dof
    fl = xb._plan_from_model(model).flanks[0]
    lo, hi = fl.gap_bounds
    cases = []
    for j in range(count):
        y = model.static_state()
        u = lo + (j + 0.5) / count * (hi - lo)
        y[1] += (u + fl.b - fl.G @ y[:n]) / fl.G[1]
        cases.append((float(rng.uniform(0.0, 0.05)), y))
    return cases


def mesh_coordinates(system):
    """The model coordinates (indices) the mesh object spans."""
    nodes = [int(nd) for nd in system.nodes]
    return [nodes.index(int(nd)) for nd in system.mbs.GetObject(system.mesh_object)["nodeNumbers"]]


# ------------------------------------------------------------------ force functions
def test_eccentricity_force_functions_equal_the_model_right_hand_side(eccentric):
    # Generic layout, symbolic and plain Python user functions, against the model's rhs
    # (gearbox.drivetrain.model.rhs, the eccentricities' eps_f and its rate from
    # eccentricity_terms) at 24 random states (a quarter on the coast flank) and 8
    # states across the drive flank's contact band. Tolerance 1e-12 of the largest
    # term: rounding (measured 7e-14 symbolic, 9e-14 Python; 4e-15 and 6e-15 with the
    # bearings; the amplitude/phase form R cos(theta - phi) against the model's
    # A cos + B sin). Without the eccentricity terms the same comparison is off by 0.49
    # (0.18) of that term (asserted > 1e-4), so the check sees them.
    model = eccentric
    rng = np.random.default_rng(3)
    cases = random_cases(model, rng, 24) + band_cases(model, rng, 8)
    errors, contact, missing = force_function_errors(model, cases, _without_eccentricity)
    for name, err in errors.items():
        assert err < 1e-12, (name, err)
    assert missing > 1e-4, missing
    # each flank in and out of contact; inside the band both outcomes occur
    assert contact.any(axis=0).all() and not contact.all(axis=0).any(), contact
    band = contact[24:, 0]
    assert band.any() and not band.all(), band


def test_eccentricity_mesh_object_reads_the_gear_coordinate(eccentric):
    # Components layout: the mesh object spans the coordinates the flanks' gaps read,
    # the gear's angle theta_2 = Omega_2 t + q_2 + theta_20 among them, and its force
    # (symbolic and Python) is -G^T F of the model's contact forces on those
    # coordinates, to 1e-12 of the largest entry plus the mean mesh force times the
    # largest G entry (for states where no flank is in contact).
    model = eccentric
    p = model.params()
    n = model.n_dof
    sysm = build_exudyn_system(model)
    dofs = mesh_coordinates(sysm)
    assert dofs == ([1, 2, 4, 5] if model.bearing_dofs else [1, 2])
    python = xb._mesh_force(xb._plan_from_model(model), dofs, False)
    symbolic = sysm.keepalive[-2]
    scale = model.mean_mesh_force * np.abs(p["G"]).max()
    for t, y in random_cases(model, np.random.default_rng(5), 16):
        x, v = y[:n], y[n:]
        want = (-(p["G"].T @ mesh_forces(t, x, v, p)[0]))[dofs]
        args = (t, 0, x[dofs].tolist(), v[dofs].tolist())
        for f in (symbolic.Evaluate(sysm.mbs, *args), python(sysm.mbs, *args)):
            big = np.abs(want).max() + scale
            np.testing.assert_allclose(np.array(f), want, rtol=0, atol=1e-12 * big)


# ------------------------------------------------------------------ agreement
def order_lines(ts, model, orders):
    """Single-sided amplitudes (N) of the mesh force at these pinion orders over the
    record (whole pinion revolutions at the nominal speed)."""
    sp = spectrum.order_spectrum(
        ts.time, ts["mesh_force_N"], speed_rpm=model.speed * 30 / np.pi, period_revs=1.0
    )
    return np.array([sp.amplitudes[np.argmin(np.abs(sp.orders - o))] for o in orders])


def test_exudyn_with_eccentricity_agrees_with_scipy(eccentric, concentric):
    # exudyn (RK67, automatic fixed step; symbolic and Python user functions) against
    # scipy DOP853 at rtol 1e-10, one pinion revolution (N_1 = 29 mesh cycles, 32
    # samples each) after the 20 mesh cycles of settling of ``simulate``:
    # - RMS, dynamic RMS and mesh-order amplitude of the mesh force within 1e-5
    #   relative (measured <= 7e-7; the figure for the backends is 1e-4);
    # - the order-1 line (the pinion's eccentricity, 82 N) within 1e-5 (measured
    #   3e-7, 2.5e-8 with the bearings);
    # - the sidebands at the mesh order N_1 -+ 1 (3.6-22 N, 1-2 % of the mesh-order
    #   line) within 1e-4 (measured 8e-6, 2.4e-6 with the bearings): the integrator's
    #   absolute error, about 1e-6 of the dynamic RMS (1557 N), is 1e-4 of a 20 N line.
    # The eccentricities raise the order-1 line about 3x over the same drive without
    # them (82 N against 27 N; the rest is the leakage of the non-integer blade-pass and
    # gear orders out of a one-revolution record): the comparison is about them. Python
    # and symbolic user functions run the same steps: equal to 1e-9 of the spread.
    model = eccentric
    n1 = model.pinion_teeth
    orders = [1, n1 - 1, n1, n1 + 1]
    ref = simulate(model, ScipySolver(rtol=1e-10), mesh_cycles=n1)
    runs = {
        uf: simulate(model, ExudynSolver(user_functions=uf), mesh_cycles=n1)
        for uf in ("symbolic", "python")
    }
    assert ref.success and all(ts.success for ts in runs.values())
    assert "eccentricity_approach_m" in ref.channels
    b, lb = mesh_force_metrics(ref, model), order_lines(ref, model, orders)
    for uf, ts in runs.items():
        np.testing.assert_allclose(ts.time, ref.time, rtol=0, atol=1e-12)
        a = mesh_force_metrics(ts, model)
        for key in METRICS:
            assert rel(a[key], b[key]) < 1e-5, (uf, key, a[key], b[key])
        la = order_lines(ts, model, orders)
        assert rel(la[0], lb[0]) < 1e-5, (uf, la[0], lb[0])
        for k in (1, 3):
            assert rel(la[k], lb[k]) < 1e-4, (uf, orders[k], la[k], lb[k])
        f, f0 = ts["mesh_force_N"], runs["symbolic"]["mesh_force_N"]
        assert np.abs(f - f0).max() < 1e-9 * np.ptp(f0), uf
    plain = simulate(concentric, ExudynSolver(), mesh_cycles=n1)
    assert lb[0] > 2.0 * order_lines(plain, concentric, orders)[0]


# ------------------------------------------------------------------ no eccentricity
def test_without_eccentricity_the_exudyn_system_is_unchanged(scene, concentric, eccentric):
    # Eccentricity keys at zero amplitude (their angles set) build nothing: params' rc
    # has no coefficients, no flank carries an approach, the gap bounds are the error
    # series' own, the mesh object spans the same coordinates, the recorded mesh
    # expression is the same string and the runs (both user-function kinds) and their
    # outputs are bit for bit those of the drive without the keys. (The backend before
    # the eccentricities gave these same runs bit for bit, and the same expression:
    # 8136 characters at phase 0, 8328 here, 8900 with the bearings; measured when
    # written.)
    zero = drive_model(
        scene,
        bearing_dofs=concentric.bearing_dofs,
        **{k: 0.0 if k.endswith("_um") else v for k, v in ECCENTRICITY.items()},
    )
    assert zero.pinion_eccentricity_angle != 0.0
    assert zero.params()["rc"].shape == (2, 0)
    plan = xb._plan_from_model(zero)
    assert not any(fl.eccentric for fl in plan.flanks)
    assert all(fl.gap_bounds == xb._bounds(fl.e, fl.e_harmonics) for fl in plan.flanks)
    a, b = build_exudyn_system(zero), build_exudyn_system(concentric)
    assert str(a.keepalive[-1][2]) == str(b.keepalive[-1][2])
    assert mesh_coordinates(a) == mesh_coordinates(b)
    y0 = periodic_start_state(zero)
    tm = 1.0 / zero.mesh_frequency
    t_eval = np.concatenate([[20 * tm], record_times(zero, 20 * tm, 10, 32)])
    for uf in ("symbolic", "python"):
        solver = ExudynSolver(user_functions=uf)
        ra = xb.integrate_exudyn(zero, y0, t_eval, solver)
        rb = xb.integrate_exudyn(concentric, y0, t_eval, solver)
        assert ra[2]["status"] == rb[2]["status"] == "success"
        np.testing.assert_array_equal(ra[1], rb[1])
        oa, ob = outputs(zero, ra[0], ra[1]), outputs(concentric, rb[0], rb[1])
        assert oa.keys() == ob.keys() and "eccentricity_approach_m" not in oa
        for key in oa:
            np.testing.assert_array_equal(oa[key], ob[key])
    # with the eccentricities the expression grows by their cosines and sines (measured
    # 8328 -> 10179 characters, 8900 -> 10751 with the bearings) and the step limit
    # stays (they do not enter the linearisation)
    c = build_exudyn_system(eccentric)
    assert len(str(c.keepalive[-1][2])) > len(str(a.keepalive[-1][2]))
    assert xb.stability_step_limit(eccentric) == xb.stability_step_limit(zero)
