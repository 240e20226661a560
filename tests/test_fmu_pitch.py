"""Pitch deviations in the FMUs (docs/drivetrain.md §3c): the drivetrain and gearbox FMUs
of the default scene's analytical-table model with a pitch approach set here, against
the Python reference, FMI 2.0 and 3.0.

The approach is a random series over a hunting period (lcm(29, 45) = 1305 mesh cycles
of 24 samples, n = 31320, step 2 pi / (29 x 24)): sines at the pinion orders k / 45,
k = 1..29, with random phases and amplitudes of standard deviation 1 um / k (5.7 um
peak to peak), plus white noise of 0.1 um on every sample (``ROUGH``, which puts
energy up to the samples' Nyquist order, 12 x mesh, and bends the spline at every
knot) or without it (``SMOOTH``). The reference is
``gearbox.drivetrain.model.rhs`` (its ``pitch_terms``: scipy's periodic CubicSpline)
and the scipy solver on it, an implementation independent of the generated C (which
fits the spline from the samples in ``resources/`` at instantiation).
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
    flange_inputs,
    fmu_log,
    fmu_rows,
    light_load,
    me_derivatives,
    rhs_derivatives,
)

fmpy = pytest.importorskip("fmpy")

from gearbox import load_scene  # noqa: E402
from gearbox.drivetrain.model import PitchApproach, outputs  # noqa: E402
from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy  # noqa: E402
from gearbox.fmu import build_fmu, drivetrain_fmu, gearbox_fmu  # noqa: E402
from gearbox.fmu.build import find_c_compiler  # noqa: E402
from gearbox.fmu.models import model_from_scene  # noqa: E402
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "marine_drive.toml"
STOP = 0.02  # s, as tests/test_fmu.py: 34 mesh cycles at 3500 rpm
N1, N2, PER_MESH = 29, 45, 24
N_SAMPLES = PER_MESH * N1 * N2  # 31320: a hunting period, 1305 mesh cycles
STEP = 2 * math.pi / (N1 * PER_MESH)  # rad of pinion angle per sample

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


def _series(noise: float) -> np.ndarray:
    """The approach samples (m): sines at the pinion orders k / 45 with random phases
    and amplitudes (standard deviation 1 um / k), plus white noise of ``noise`` (m) on
    every sample."""
    rng = np.random.default_rng(3)
    theta = np.arange(N_SAMPLES) * STEP
    v = np.zeros(N_SAMPLES)
    for k in range(1, 30):
        v += rng.normal() * 1e-6 / k * np.cos(k / N2 * theta + rng.uniform(0.0, 2 * math.pi))
    return v + noise * rng.standard_normal(N_SAMPLES)


ROUGH, SMOOTH = 0.1e-6, 0.0


def _with_pitch(model, table, noise: float):
    return replace(model, pitch=PitchApproach(_series(noise), float(table.angle[0]), STEP))


@pytest.fixture(scope="module")
def model_table():
    """The default scene's model on its analytical table (no loaded TCA) with the rough
    approach."""
    model, table = model_from_scene(load_scene(SCENE))
    assert model.pitch is None and (table.pinion_teeth, table.gear_teeth) == (N1, N2)
    return _with_pitch(model, table, ROUGH), table


@pytest.fixture(scope="module")
def built(model_table, tmp_path_factory):
    model, table = model_table
    out = tmp_path_factory.mktemp("fmu_pitch")
    smooth = _with_pitch(model, table, SMOOTH)
    return {
        "drivetrain": build_fmu(drivetrain_fmu(model, table), out),
        "gearbox": build_fmu(gearbox_fmu(model, table), out),
        "drivetrain3": build_fmu(drivetrain_fmu(model, table), out, fmi_version=3),
        "gearbox3": build_fmu(gearbox_fmu(model, table), out, fmi_version=3),
        "smooth": build_fmu(drivetrain_fmu(smooth, table), out / "smooth"),
    }


def _reference(model, stop=STOP, rtol=1e-12):
    """scipy DOP853 from the static state, sampled every 1e-4 s: (time, channels). At
    rtol 1e-10 (tests/test_fmu.py's) the rough approach's knots leave 9.5e-6 of the
    mesh force's AC RMS against rtol 1e-12, which the FMU's DOPRI5 at rtol 1e-12 reads
    within 2.1e-8 (measured), so the reference runs at 1e-12."""
    t = np.linspace(0.0, stop, int(round(stop / 1e-4)) + 1)
    tt, y, info = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=rtol))
    assert info["status"] == "success", info
    return tt, outputs(model, tt, y)


@pytest.fixture(scope="module")
def reference(model_table):
    """The rough and the smooth approach, and none."""
    model, table = model_table
    return {
        "rough": _reference(model),
        "smooth": _reference(_with_pitch(model, table, SMOOTH)),
        "none": _reference(replace(model, pitch=None)),
    }


def _variables(b):
    root = ET.fromstring(zipfile.ZipFile(b.fmu).read("modelDescription.xml"))
    tag = "ScalarVariable" if root.get("fmiVersion") == "2.0" else "Float64"
    return {v.get("name"): v for v in root.iter(tag)}


def test_builds_validate_and_ship_the_samples(built, model_table):
    """Warning-free builds that fmpy accepts, with ``mesh.pitch_approach`` as an output
    and the samples in ``resources/`` (31320 values, 0.73 MB of text; the FMU 0.40 MB,
    measured), no parameter of it; the model without pitch deviations: neither."""
    from fmpy.validation import validate_fmu

    model, table = model_table
    for name, b in built.items():
        assert b.compiler_output == "", (name, b.compiler_output)
        assert validate_fmu(b.fmu) == [], name
        sv = _variables(b)
        assert sv["mesh.pitch_approach"].get("causality") == "output", name
        assert [k for k in sv if "pitch" in k] == ["mesh.pitch_approach"], name
        files = set(zipfile.ZipFile(b.fmu).namelist())
        assert {"resources/pitch_meta.txt", "resources/pitch_samples.txt"} <= files
    text = zipfile.ZipFile(built["drivetrain"].fmu).read("resources/pitch_samples.txt").decode()
    assert text.startswith(f"gearbox-table 1 {N_SAMPLES} 1\n")
    assert Path(built["drivetrain"].fmu).stat().st_size < 1e6
    plain = drivetrain_fmu(replace(model, pitch=None), table)
    assert not any("pitch" in v.name for v in plain.variables)
    assert not any("pitch" in name for name in plain.resources)
    assert "#define GBX_PITCH 0" in plain.c_code


def _me_outputs(path, times, states, names):
    """Outputs ``names`` of the Model Exchange FMU at ``path`` at each (t, x)."""
    from ctypes import c_double

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model

    md = read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(path)
    m = states.shape[1]
    out = np.empty((len(times), len(names)))
    try:
        fmu = FMU2Model(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.modelExchange.modelIdentifier,
            instanceName="outputs",
        )
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmu.enterContinuousTimeMode()
        for i, (t, x) in enumerate(zip(times, states, strict=True)):
            fmu.setTime(float(t))
            fmu.setContinuousStates((c_double * m)(*x), m)
            out[i] = fmu.getReal([vr[k] for k in names])
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(d, ignore_errors=True)
    return out


def test_spline_fitted_in_c_is_the_python_one(built, model_table):
    """``mesh.pitch_approach`` at 500 random pinion angles over the hunting period and
    beyond it either way (t over a period, q_1 in [-20, 20] rad: negative intervals
    wrap around) against ``PitchApproach`` (scipy's periodic CubicSpline): measured
    7.3e-17 of the largest |a|, 1e-14 allowed. At 200 sample angles (j in [-2 n, 3 n))
    the samples themselves, measured 1.0e-12 of it (the angle's round-off at up to 850
    rad times the slope), 1e-11 allowed."""
    model, _ = model_table
    pa = model.pitch
    n = model.n_dof
    rng = np.random.default_rng(7)
    times = rng.uniform(0.0, pa.period / model.speed, 500)
    states = np.tile(model.static_state(), (500, 1))
    states[:, 1] = rng.uniform(-20.0, 20.0, 500)
    states[:, n + 1] = rng.normal(0.0, 1.0, 500)
    got = _me_outputs(built["drivetrain"].fmu, times, states, ["mesh.pitch_approach"])[:, 0]
    want, _ = pa(model.speed * times + states[:, 1])
    scale = np.abs(pa.values).max()
    assert np.abs(got - want).max() < 1e-14 * scale, np.abs(got - want).max() / scale
    j = rng.integers(-2 * N_SAMPLES, 3 * N_SAMPLES, 200)
    states = np.tile(model.static_state(), (200, 1))
    states[:, 1] = pa.angle0 + j * pa.step
    got = _me_outputs(built["drivetrain"].fmu, np.zeros(200), states, ["mesh.pitch_approach"])
    err = np.abs(got[:, 0] - pa.values[j % N_SAMPLES]).max() / scale
    assert err < 1e-11, err


@pytest.mark.parametrize("kind", ["drivetrain", "gearbox", "drivetrain3", "gearbox3"])
def test_right_hand_side_with_pitch_agrees_with_numpy(built, model_table, kind):
    """Derivatives of the Model Exchange FMU (FMI 2.0 and 3.0) at 200 random states about
    the static equilibrium and times in [0, 0.05] s against ``rhs`` (the gearbox FMU:
    its rows, the flanges as inputs from the same state). Max |difference| / std over
    the samples: measured 2.4e-12 (pinion, gear), 5.0e-10 (engine), 1.7e-9
    (propeller), the grids' interpolation error as in tests/test_fmu.py (bounds 1e-10
    and 2e-8). The approach's own share of the pinion's and the gear's accelerations
    (rhs with less rhs without it) reaches 0.17 std: the difference is measured 1.4e-11
    of it, so a wrong sign, interval or rate would show."""
    model, _ = model_table
    p, p0 = model.params(), replace(model, pitch=None).params()
    y0, scale = model.static_state(), model.state_scale()
    n = model.n_dof
    rows = fmu_rows(model, kind)
    rng = np.random.default_rng(11)
    times = rng.uniform(0.0, 0.05, 200)
    states = y0 + 0.3 * scale * rng.standard_normal((200, 2 * n))  # in drive contact
    flanges = flange_inputs(model, states) if "gearbox" in kind else None
    x0, got = me_derivatives(built[kind].fmu, times, states[:, rows], inputs=flanges, name=kind)
    assert np.max(np.abs(x0 - y0[rows])) < 1e-11 * np.abs(y0).max()
    want, want0 = (rhs_derivatives(q, times, states, rows) for q in (p, p0))
    rel = np.abs(got - want).max(axis=0) / want.std(axis=0)
    acc = [k for k, r in enumerate(rows) if r - n in (1, 2)]  # pinion and gear accelerations
    assert rel[acc].max() < 1e-10, rel
    assert rel.max() < 2e-8, rel
    share = np.abs(want - want0)[:, acc].max(axis=0)
    assert (share / want.std(axis=0)[acc]).min() > 0.1
    assert (np.abs(got - want)[:, acc].max(axis=0) / share).max() < 1e-9


def test_right_hand_side_with_pitch_and_eccentricities(built, model_table):
    """Both approaches at once (eccentricities of tests/test_fmu_eccentricity.py's
    magnitude set at instantiation): derivatives at 100 random states against ``rhs``
    of the model with the same values; pinion and gear rows measured 2.9e-12 of their
    std, 1e-10 allowed."""
    model, _ = model_table
    params = {
        "pinion.eccentricity": 20e-6,
        "pinion.eccentricity_angle": 0.5,
        "gear.eccentricity": 15e-6,
        "gear.eccentricity_angle": -1.0,
    }
    p = replace(model, **{k.replace(".", "_"): v for k, v in params.items()}).params()
    n = model.n_dof
    rng = np.random.default_rng(5)
    times = rng.uniform(0.0, 0.05, 100)
    states = model.static_state() + 0.3 * model.state_scale() * rng.standard_normal((100, 2 * n))
    _, got = me_derivatives(built["drivetrain"].fmu, times, states, start=params, name="both")
    want = rhs_derivatives(p, times, states)
    rel = np.abs(got - want).max(axis=0) / want.std(axis=0)
    assert rel[[n + 1, n + 2]].max() < 1e-10, rel


@pytest.mark.parametrize(
    "series, kind, interface, rtol, start, tol",
    [
        ("rough", "drivetrain", "CoSimulation", 1e-8, None, 3e-5),
        ("rough", "drivetrain", "CoSimulation", None, None, 3e-4),
        ("rough", "drivetrain", "CoSimulation", None, {"solver.steps_per_mesh_period": 128}, 5e-6),
        ("rough", "drivetrain", "ModelExchange", 1e-8, None, 1.5e-5),
        ("rough", "drivetrain3", "CoSimulation", None, None, 3e-4),
        ("rough", "drivetrain3", "ModelExchange", 1e-8, None, 1.5e-5),
        ("smooth", "smooth", "CoSimulation", 1e-8, None, 1e-5),
        ("smooth", "smooth", "CoSimulation", None, None, 1e-5),
        ("smooth", "smooth", "ModelExchange", 1e-8, None, 5e-5),
    ],
    ids=[
        "cs_dopri5",
        "cs_fixed_step",
        "cs_fixed_step_128",
        "me_cvode",
        "fmi3_cs_fixed_step",
        "fmi3_me_cvode",
        "smooth_cs_dopri5",
        "smooth_cs_fixed_step",
        "smooth_me_cvode",
    ],
)
def test_run_with_pitch_matches_python_reference(
    built, reference, series, kind, interface, rtol, start, tol
):
    """The mesh force and ``mesh.pitch_approach`` over 0.02 s from the static state as
    RMS error over the reference's AC RMS (scipy DOP853 at rtol 1e-12). The approach
    moves the mesh force by 0.081 (rough) and 0.025 (smooth) of its AC RMS. Measured,
    rough: 9.9e-6 (DOPRI5 rtol 1e-8), 1.05e-4 (default fixed step), 1.5e-6 (fixed step
    at 128 per mesh period), 4.0e-6 (CVode rtol 1e-8), FMI 3.0 as FMI 2.0; smooth:
    4.9e-7, 5.9e-7, 2.7e-6, as the eccentricities' (tests/test_fmu_eccentricity.py);
    bounds about 3x the rough figures, tests/test_fmu.py's for the smooth. The rough
    approach's spline bends at every knot, 24 per mesh period (its third derivative
    jumps): the fixed step (32 per mesh period by default) does not resolve that, 128
    per mesh period do. The output a itself is the spline at the integrated q_1:
    measured 2.1e-7 (rough, default fixed step) and at most 2.0e-8 elsewhere of its AC
    RMS over the run (0.12 um rough, 0.074 um smooth); 1e-6 allowed."""
    t_ref, ref = reference[series]
    t, ch, _ = simulate_fmu(
        built[kind].fmu,
        interface=interface,
        stop_time=STOP,
        step=1e-4,
        rtol=rtol,
        outputs=["mesh.force", "mesh.pitch_approach"],
        start_values=start,
    )
    err = ac_relative_error(t, ch["mesh.force"], t_ref, ref["mesh_force_N"])
    assert err < tol, err
    effect = ac_relative_error(
        t_ref, reference["none"][1]["mesh_force_N"], t_ref, ref["mesh_force_N"]
    )
    assert effect > 100 * tol if series == "smooth" else effect > 0.05
    a = ref["pitch_approach_m"]
    assert ac_relative_error(t, ch["mesh.pitch_approach"], t_ref, a) < 1e-6
    assert np.std(a) > 0.05e-6


def test_fixed_step_contact_test_includes_the_pitch_approach(tmp_path):
    """The light-load scene of tests/test_fmu.py (separation, coast contact at zero
    backlash) with the smooth approach: the fixed steps that end out of the nominal
    contact, with the gap s_drive + a, are redone with adaptive steps. Measured 229
    intervals handed over, mesh force 8.3e-6 of the AC RMS off the scipy reference
    (rtol 1e-10) over 0.02 s; 2e-5 allowed (the kinks at contact change limit the
    adaptive DOPRI5 of tests/test_fmu.py's light-load case to 1.0e-5 as well). With the
    contact test left without a (measured once by hand on a modified build, when the
    case ran at 60 N m): 82 intervals, 4.6e-3 off."""
    scene = load_scene(SCENE).replaced(drivetrain=light_load(0.0))
    model, table = model_from_scene(scene)
    model = _with_pitch(model, table, SMOOTH)
    fmu = build_fmu(drivetrain_fmu(model, table), tmp_path).fmu
    tt, ref = _reference(model, rtol=1e-10)
    assert ref["mesh_force_N"].min() < 0.0 and np.any(ref["mesh_force_N"] == 0.0)
    t, ch, _ = simulate_fmu(
        fmu, stop_time=STOP, step=1e-4, outputs=["mesh.force", "solver.handed_over"]
    )
    assert ch["solver.handed_over"][-1] > 10
    assert ac_relative_error(t, ch["mesh.force"], tt, ref["mesh_force_N"]) < 2e-5


@pytest.mark.parametrize(
    "damage, expect",
    [
        ("delete", "cannot open resource table"),
        ("count", "pitch_samples.txt must hold the n samples"),
        ("step", "the step must be > 0"),
    ],
)
def test_missing_or_corrupt_pitch_samples_fail_at_instantiation(built, damage, expect):
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    path = built["drivetrain"].fmu
    md = read_model_description(path)
    d = extract(path)
    log = fmu_log()
    try:
        res = Path(d) / "resources"
        if damage == "delete":
            (res / "pitch_samples.txt").unlink()
        elif damage == "count":
            f = res / "pitch_samples.txt"
            lines = f.read_text().splitlines()
            lines[0] = f"gearbox-table 1 {N_SAMPLES - 1} 1"
            f.write_text("\n".join(lines[:-1]) + "\n")
        else:
            f = res / "pitch_meta.txt"
            lines = f.read_text().splitlines()
            lines[-1] = f"{N_SAMPLES} 0 0"
            f.write_text("\n".join(lines) + "\n")
        fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="corrupt",
        )
        with pytest.raises(Exception, match="instantiate"):
            fmu.instantiate(callbacks=log.callbacks)
        assert any(expect in m for _, m in log.messages), log.messages
    finally:
        shutil.rmtree(d, ignore_errors=True)


def test_long_series_are_written_in_rows_the_reader_takes():
    """gbx_read_table reads at most 100000 rows of up to 1000 values: one sample per row
    up to 100000 samples, then the fewest columns that divide them into as many rows;
    a count with no such divisor is refused by name."""
    from gearbox.errors import InputError
    from gearbox.fmu.models import _pitch_layout

    assert _pitch_layout(N_SAMPLES) == (N_SAMPLES, 1)
    assert _pitch_layout(100_000) == (100_000, 1)
    assert _pitch_layout(2 * 29 * 45 * 96) == (83_520, 3)
    with pytest.raises(InputError, match="pitch.values"):
        _pitch_layout(100_003)  # prime
