"""exudyn backend with pitch deviations (docs/drivetrain.md §3c, docs/exudyn.md): the
drive flank's gap gains the spline approach a(theta_1) and its rate gains
a'(theta_1) (Omega + v_1) in the symbolic and the Python user functions, the spline is
the model's to the last bit, and a short run agrees with the scipy reference.

The model is the default scene (models/marine_drive.toml, analytical mesh tables, no
loaded TCA) at pinion phase 0.7 rad with a synthetic pitch approach over the hunting
period (N_1 = 29, N_2 = 45: 1305 mesh cycles, 24 samples each, 31,320 samples):
random samples of 2 um standard deviation for the right-hand-side checks, the same
smoothed over one mesh cycle for the runs (a loaded TCA's approach is smooth within a
mesh cycle), with and without the bearing translations.

    PYTHONPATH=. python3 tests/test_drivetrain_exudyn_pitch.py

prints the measurements docs/exudyn.md quotes (agreement with scipy and the cost per
right-hand side; nothing asserted there).
"""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

from _exudyn_helpers import force_function_errors, random_cases, rel  # noqa: E402

from gearbox.drivetrain import exudyn_backend as xb  # noqa: E402
from gearbox.drivetrain.exudyn_backend import ExudynSolver, build_exudyn_system  # noqa: E402
from gearbox.drivetrain.model import (  # noqa: E402
    DrivetrainModel,
    PitchApproach,
    mesh_forces,
    pitch_terms,
)
from gearbox.drivetrain.simulate import default_solver, mesh_force_metrics, simulate  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402

MODELS = Path(__file__).resolve().parents[1] / "models"
PHASE = 0.7  # rad
SAMPLES = 24  # per mesh cycle
ECCENTRICITY = {
    "pinion_eccentricity_um": 20.0,
    "pinion_eccentricity_angle_deg": 30.0,
    "gear_eccentricity_um": 15.0,
    "gear_eccentricity_angle_deg": -60.0,
}
METRICS = ("mesh_force_rms_N", "mesh_force_dynamic_rms_N", "mesh_force_mesh_order_amplitude_N")


def pitch_values(n1, n2, smooth, seed=7):
    """Samples (m) over the hunting period: N(0, (2 um)^2), or the same smoothed by a
    periodic Hann window of one mesh cycle (SAMPLES samples, unit sum) and scaled by 2
    (standard deviation 0.99 um, largest 3.7 um, with seed 7)."""
    n = SAMPLES * n1 * n2 // math.gcd(n1, n2)
    v = np.random.default_rng(seed).normal(size=n) * 2e-6
    if not smooth:
        return v
    w = np.hanning(SAMPLES + 2)[1:-1]
    w = np.r_[w / w.sum(), np.zeros(n - SAMPLES)]
    return 2.0 * np.real(np.fft.ifft(np.fft.fft(v) * np.fft.fft(w)))


def with_pitch(model, smooth=False, angle0=0.0):
    """``model`` with the pitch approach of :func:`pitch_values` from ``angle0`` (rad)."""
    n1, n2 = model.pinion_teeth, model.gear_teeth
    step = 2 * math.pi / (n1 * SAMPLES)
    values = pitch_values(n1, n2, smooth)
    return dataclasses.replace(model, pitch=PitchApproach(values, float(angle0), step))


def drive_model(scene, **drivetrain):
    m = DrivetrainModel.from_scene(scene.replaced(drivetrain=drivetrain))
    return dataclasses.replace(m, phase=PHASE)


@pytest.fixture(scope="module")
def scene():
    return load_scene(MODELS / "marine_drive.toml")


@pytest.fixture(scope="module", params=[False, True], ids=["rotations", "bearings"])
def bearings(request):
    return request.param


@pytest.fixture(scope="module")
def plain(scene, bearings):
    return drive_model(scene, bearing_dofs=bearings)


def _without_pitch(plan):
    """The plan with the pitch approach taken out (the comparison showing that the
    checks see it)."""
    flanks = tuple(dataclasses.replace(fl, pitch=None) for fl in plan.flanks)
    return dataclasses.replace(plan, flanks=flanks)


def band_cases(model, rng, count):
    """(t, y): the static state with the drive flank's delta - b placed across the band
    (lo, hi] of :attr:`_Flank.gap_bounds`, where the approach decides the contact."""
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


# ------------------------------------------------------------------ the spline
def test_the_spline_is_the_models_bit_for_bit(scene):
    # _Pitch.terms (Python) and _Pitch.terms_symbolic (the IfThenElse tree, evaluated
    # by exudyn) against model.pitch_terms at 400 pinion angles between about -6 and +3
    # hunting periods (negative angles: the interval index's floor and mod), exact: the
    # same floating-point operations in the same order. The bounds hold the spline
    # (sampled 16 times per interval) and are its range to 1e-8 of it (the intervals at
    # the extremes sampled 1e5 times; measured 5.3e-10, the bounds' 1e-9 pad).
    model = with_pitch(drive_model(scene), angle0=0.25)
    p = model.params()
    pitch = xb._plan_from_model(model).flanks[0].pitch
    assert pitch is not None and pitch.n == p["pt"].shape[0] == 24 * 29 * 45
    assert xb._plan_from_model(model).flanks[1].pitch is None  # the coast keeps its teeth
    rng = np.random.default_rng(11)
    period = model.pitch.period
    t = rng.uniform(0.0, 3 * period / model.speed, 400)
    q1 = rng.uniform(-6 * period, 0.0, 400)
    v1 = rng.normal(0.0, 5.0, 400)
    want_a, want_rate = pitch_terms(t, q1, v1, p)
    theta = p["Omega"] * t + q1 + p["phase"]  # the model's angle, as the backend forms it
    speed = p["Omega"] + v1
    assert theta.min() < -2 * period and theta.max() > 2 * period
    esym = exu.symbolic
    was = esym.GetRecording()
    esym.SetRecording(True)
    try:
        th, w = esym.Real("theta", 0.0), esym.Real("w", 0.0)
        sym_a, sym_rate = pitch.terms_symbolic(th, w)
        for j in range(theta.size):
            got = pitch.terms(float(theta[j]), float(speed[j]))
            th.SetValue(float(theta[j]))
            w.SetValue(float(speed[j]))
            assert got == (want_a[j], want_rate[j]), j
            assert (sym_a.Evaluate(), sym_rate.Evaluate()) == got, j
    finally:
        esym.SetRecording(was)
    dense = model.pitch(0.25 + model.pitch.step * np.arange(pitch.n * 16) / 16.0)[0]
    lo, hi = pitch.bounds
    assert lo <= dense.min() and dense.max() <= hi
    d = np.linspace(0.0, 1.0, 100_001)  # the extremes' intervals and those before, finely
    fine = []
    for k in (np.argmin(dense) // 16, np.argmax(dense) // 16):
        c = p["pt"][[k - 1, k]]
        fine.append(c[:, :1] + d * (c[:, 1:2] + d * (c[:, 2:3] + d * c[:, 3:4])))
    span = np.ptp(dense)
    assert fine[0].min() - lo < 1e-8 * span and hi - fine[1].max() < 1e-8 * span


# ------------------------------------------------------------------ force functions
@pytest.mark.parametrize("extra", ["pitch", "pitch+eccentricity+friction"])
def test_pitch_force_functions_equal_the_model_right_hand_side(scene, bearings, extra):
    # Generic layout, symbolic and plain Python user functions, against the model's rhs
    # (gearbox.drivetrain.model.rhs, the approach from approach_terms) at 24 random
    # states (a quarter on the coast flank) and 8 states across the drive flank's
    # contact band, raw random samples (the spline's every interval alike), angle0
    # 0.25 rad. Tolerance 1e-12 of the largest term (measured at most 7.9e-14 symbolic,
    # 9.2e-14 Python; 4.0e-15 to 1.9e-14 with the bearings: rounding, the backend sums
    # the gap in another order than the model). Without the pitch terms the same
    # comparison is off by 0.014-0.13 of that term (asserted > 1e-4).
    # With eccentricity and friction the approaches add (model.approach_terms) and the
    # friction torques take the force.
    keys = {"bearing_dofs": bearings}
    if extra != "pitch":
        keys.update(ECCENTRICITY, mesh_friction_coefficient=0.05)
    model = with_pitch(drive_model(scene, **keys), angle0=0.25)
    rng = np.random.default_rng(3)
    cases = random_cases(model, rng, 24) + band_cases(model, rng, 8)
    errors, contact, missing = force_function_errors(model, cases, _without_pitch)
    for name, err in errors.items():
        assert err < 1e-12, (name, err)
    assert missing > 1e-4, missing
    assert contact.any(axis=0).all() and not contact.all(axis=0).any(), contact
    band = contact[24:, 0]
    assert band.any() and not band.all(), band


def test_pitch_mesh_object_force_is_the_models(plain):
    # Components layout: the mesh object spans the pinion (whose angle the spline
    # reads) and the gear (and the bearings), and its force, symbolic and Python, is
    # -G^T F of the model's contact forces on those coordinates, to 1e-12 of the
    # largest entry plus the mean mesh force times the largest G entry.
    model = with_pitch(plain)
    p = model.params()
    n = model.n_dof
    sysm = build_exudyn_system(model)
    nodes = [int(nd) for nd in sysm.nodes]
    dofs = [nodes.index(int(nd)) for nd in sysm.mbs.GetObject(sysm.mesh_object)["nodeNumbers"]]
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
    sysm.release()
    assert sysm.keepalive == [] and sysm.mbs.systemData.NumberOfObjects() == 0


# ------------------------------------------------------------------ agreement
def test_exudyn_with_pitch_agrees_with_scipy(plain):
    # exudyn (RK67, automatic fixed step; symbolic and Python user functions) against
    # scipy DOP853 at rtol 1e-9, one pinion revolution (N_1 = 29 mesh cycles, 32 samples
    # each) after the 20 mesh cycles of settling of ``simulate``, smoothed samples:
    # - the mesh force sample by sample within 1e-5 of its range (measured 1.3e-6,
    #   8.9e-7 with the bearings);
    # - RMS, dynamic RMS and mesh-order amplitude within 1e-5 relative (measured
    #   <= 7.1e-7);
    # - Python and symbolic user functions run the same steps: equal to 1e-9 of the
    #   range.
    # The pitch approach moves the mesh force by 0.32 (0.42) of its range against the
    # same run without it (asserted > 0.1), so the comparison is about it.
    model = with_pitch(plain, smooth=True)
    n1 = model.pinion_teeth
    ref = simulate(model, default_solver("scipy", 1e-9), mesh_cycles=n1)
    assert ref.success and "pitch_approach_m" in ref.channels
    f0 = ref["mesh_force_N"]
    span = np.ptp(f0)
    b = mesh_force_metrics(ref, model)
    runs = {
        uf: simulate(model, ExudynSolver(user_functions=uf), mesh_cycles=n1)
        for uf in ("symbolic", "python")
    }
    for uf, ts in runs.items():
        assert ts.success, (uf, ts.status)
        np.testing.assert_allclose(ts.time, ref.time, rtol=0, atol=1e-12)
        f = ts["mesh_force_N"]
        assert np.abs(f - f0).max() < 1e-5 * span, (uf, np.abs(f - f0).max() / span)
        a = mesh_force_metrics(ts, model)
        for key in METRICS:
            assert rel(a[key], b[key]) < 1e-5, (uf, key, a[key], b[key])
    f, fs = runs["python"]["mesh_force_N"], runs["symbolic"]["mesh_force_N"]
    assert np.abs(f - fs).max() < 1e-9 * span
    bare = simulate(plain, ExudynSolver(), mesh_cycles=n1)["mesh_force_N"]
    assert np.abs(fs - bare).max() > 0.1 * span


# ------------------------------------------------------------------ measurements
def _measure(repeat=5, cycles=200):  # pragma: no cover - run by hand
    """Agreement with scipy (as the test above, also the raw samples) and the cost per
    right-hand side (``integrate_exudyn`` from the static state, 20 settling and
    ``cycles`` recorded mesh cycles at 8 samples each, median of ``repeat`` runs), the
    build time, with and without the pitch approach; then one run over the common
    period of the excitations (``simulate``, 32 samples per mesh cycle, smoothed
    samples) per user-function kind."""
    import statistics
    import time

    from gearbox.drivetrain.simulate import record_times

    sc = load_scene(MODELS / "marine_drive.toml")
    for bear in (False, True):
        base = drive_model(sc, bearing_dofs=bear)
        n1 = base.pinion_teeth
        for smooth in (True, False):
            model = with_pitch(base, smooth=smooth)
            ref = simulate(model, default_solver("scipy", 1e-9), mesh_cycles=n1)
            f0 = ref["mesh_force_N"]
            b = mesh_force_metrics(ref, model)
            bare = simulate(base, default_solver("scipy", 1e-9), mesh_cycles=n1)
            shift = np.abs(f0 - bare["mesh_force_N"]).max() / np.ptp(f0)
            print(
                f"bearings {bear}, {'smoothed' if smooth else 'raw'} samples: mesh force "
                f"range {np.ptp(f0):.1f} N, moved by {shift:.3f} of it by the pitch approach"
            )
            _print_exudyn_against(model, f0, b, n1)
    for bear in (False, True):
        base = drive_model(sc, bearing_dofs=bear)
        for label, model in (("without", base), ("with", with_pitch(base))):
            tm = 1.0 / model.mesh_frequency
            t_eval = np.concatenate([[20 * tm], record_times(model, 20 * tm, cycles, 8)])
            y0 = model.static_state()
            row = []
            for uf in ("symbolic", "python"):
                solver = ExudynSolver(user_functions=uf)
                walls, builds = [], []
                for _ in range(repeat):
                    t1 = time.perf_counter()
                    build_exudyn_system(model, solver).release()
                    builds.append(time.perf_counter() - t1)
                    _, _, info = xb.integrate_exudyn(model, y0, t_eval, solver)
                    walls.append(info["wall_time"])
                us = statistics.median(walls) / info["nfev"] * 1e6
                row.append(f"{uf} {us:.2f} us, build {statistics.median(builds):.3f} s")
            print(
                f"bearings {bear}, pitch {label}: per right-hand side "
                f"{'; '.join(row)} (nfev {info['nfev']})"
            )
    _measure_raw_steps(sc)
    _measure_loaded_tca(sc)
    model = with_pitch(drive_model(sc, bearing_dofs=False), smooth=True)
    common = model.common_period_mesh_cycles()
    for uf in ("symbolic", "python"):
        t1 = time.perf_counter()
        ts = simulate(model, ExudynSolver(user_functions=uf), mesh_cycles=common)
        print(
            f"common period ({common} mesh cycles), {uf}: {ts.status}, integration "
            f"{ts.wall_time:.2f} s, {ts.steps} steps, simulate {time.perf_counter() - t1:.2f} s"
        )


def _measure_raw_steps(sc):  # pragma: no cover - run by hand
    """The raw samples (rotations only) against scipy at rtol 1e-11, at the default
    step and at 40 and 160 steps per period, and scipy at rtol 1e-9 against it."""
    model = with_pitch(drive_model(sc, bearing_dofs=False), smooth=False)
    n1 = model.pinion_teeth
    ref = simulate(model, default_solver("scipy", 1e-11), mesh_cycles=n1)["mesh_force_N"]
    span = np.ptp(ref)
    r9 = simulate(model, default_solver("scipy", 1e-9), mesh_cycles=n1)["mesh_force_N"]
    print(
        f"raw samples against scipy rtol 1e-11: scipy rtol 1e-9 {np.abs(r9 - ref).max() / span:.2e}"
    )
    for spp in (None, 40, 160):
        ts = simulate(model, ExudynSolver(steps_per_period=spp), mesh_cycles=n1)
        d = np.abs(ts["mesh_force_N"] - ref).max() / span
        print(f"  exudyn steps_per_period {spp}: max |dF| / range {d:.2e} ({ts.steps} steps)")


def _measure_loaded_tca(sc):  # pragma: no cover - run by hand
    """Agreement with scipy on the default scene with ``drivetrain.pitch_deviations``:
    the loaded TCA's table (12 positions) and the scene's random single pitch
    deviations (the model of tests/test_drivetrain_pitch.py), as above."""
    import tempfile

    from gearbox.pipeline import run_pipeline

    sc = sc.replaced(ltca={"positions": 12}, drivetrain={"pitch_deviations": True})
    with tempfile.TemporaryDirectory() as cache:
        table = run_pipeline(sc, ["tables", "pitch"], cache=Path(cache))["tables"]
    for bear in (False, True):
        model = DrivetrainModel.from_scene(sc.replaced(drivetrain={"bearing_dofs": bear}), table)
        n1 = model.pinion_teeth
        ref = simulate(model, default_solver("scipy", 1e-9), mesh_cycles=n1)
        f0 = ref["mesh_force_N"]
        b = mesh_force_metrics(ref, model)
        bare = dataclasses.replace(model, pitch=None)
        bare = simulate(bare, default_solver("scipy", 1e-9), mesh_cycles=n1)["mesh_force_N"]
        print(
            f"loaded TCA, bearings {bear}: {model.pitch.values.size} samples, approach range "
            f"{np.ptp(model.pitch.values):.3g} m; mesh force range {np.ptp(f0):.1f} N, moved "
            f"by {np.abs(f0 - bare).max() / np.ptp(f0):.3f} of it by the pitch approach"
        )
        _print_exudyn_against(model, f0, b, n1)


def _print_exudyn_against(model, f0, b, n1):
    """Both exudyn user-function kinds against the scipy reference's mesh force f0 and
    its metrics b, printed (the measurement script's lines)."""
    for uf in ("symbolic", "python"):
        ts = simulate(model, ExudynSolver(user_functions=uf), mesh_cycles=n1)
        a = mesh_force_metrics(ts, model)
        d = np.abs(ts["mesh_force_N"] - f0).max() / np.ptp(f0)
        figs = "  ".join(f"{k[11:-2]} {rel(a[k], b[k]):.1e}" for k in METRICS)
        print(f"  exudyn {uf:8s} max |dF| / range {d:.2e}  {figs}")


if __name__ == "__main__":  # pragma: no cover
    _measure()
