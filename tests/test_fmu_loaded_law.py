"""The loaded mesh law in the FMUs (docs/drivetrain.md §3d): the drivetrain and gearbox
FMUs of the default scene's loaded-TCA model with ``mesh_law = "loaded"``, against the
Python reference (``gearbox.drivetrain.model.rhs`` and scipy's DOP853 on it, which the
generated C shares no code with: the C builds the law from the table samples in
``resources/`` at instantiation), FMI 2.0 and 3.0.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest
from _fmu_helpers import flange_inputs, fmu_rows, me_derivatives, rhs_derivatives

fmpy = pytest.importorskip("fmpy")

from gearbox import load_scene  # noqa: E402
from gearbox.drivetrain.model import DrivetrainModel, outputs  # noqa: E402
from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy  # noqa: E402
from gearbox.fmu import build_fmu, drivetrain_fmu, gearbox_fmu  # noqa: E402
from gearbox.fmu.build import find_c_compiler  # noqa: E402
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402
from gearbox.pipeline import run_pipeline  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "marine_drive.toml"
STOP = 0.02  # s: 34 mesh cycles at 3500 rpm, as tests/test_fmu.py

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


@pytest.fixture(scope="module")
def model_table(tmp_path_factory):
    """The default scene's loaded-TCA table (levels 50, 300, 600, 900 N m) and its model
    with the loaded law at 3500 rpm, 802 N m."""
    scene = load_scene(SCENE)
    table = run_pipeline(scene, ["tables"], cache=tmp_path_factory.mktemp("cache"))["tables"]
    model = DrivetrainModel.from_scene(scene.replaced(drivetrain={"mesh_law": "loaded"}), table)
    return model, table


@pytest.fixture(scope="module")
def built(model_table, tmp_path_factory):
    model, table = model_table
    out = tmp_path_factory.mktemp("fmu_loaded")
    return {
        "drivetrain": build_fmu(drivetrain_fmu(model, table), out),
        "gearbox": build_fmu(gearbox_fmu(model, table), out),
        "drivetrain3": build_fmu(drivetrain_fmu(model, table), out, fmi_version=3),
    }


def _tangent(model, table):
    return DrivetrainModel.from_scene(load_scene(SCENE), table)


def test_builds_validate_and_ship_the_secant_stiffnesses(built, model_table):
    from fmpy.validation import validate_fmu

    model, table = model_table
    for name, b in built.items():
        assert b.compiler_output == "", (name, b.compiler_output)
        assert validate_fmu(b.fmu) == [], name
        assert "resources/mesh_secant.txt" in zipfile.ZipFile(b.fmu).namelist()
    text = zipfile.ZipFile(built["drivetrain"].fmu).read("resources/mesh_secant.txt").decode()
    assert text.startswith(f"gearbox-table 1 {2 * table.angle.size} 1\n")
    plain = drivetrain_fmu(_tangent(model, table), table)
    assert "#define GBX_LOADED 0" in plain.c_code
    assert "mesh_secant.txt" not in plain.resources


@pytest.mark.parametrize("kind", ["drivetrain", "gearbox", "drivetrain3"])
def test_right_hand_side_with_the_loaded_law_agrees_with_numpy(built, model_table, kind):
    """Derivatives of the Model Exchange FMU at 200 random states about the static
    equilibrium (mesh deflection swung by 0.6 of the static one either way: from 40 to
    over 1300 N m of load, the law's every piece) against ``rhs``. Max |difference| /
    std over the samples: pinion and gear rows measured 6.6e-12, bound 1e-10 (the
    grids' interpolation error, tests/test_fmu.py's bound; the law's 2 J + 1 = 9 rows
    are gridded like k_f); engine 1.6e-10 and propeller 1.7e-9, every row within 2e-8.
    The law's own share (rhs less the tangent law's rhs) reaches 0.076 of the std, and
    the difference stays below 1e-6 of it, so a wrong piece or sign would show."""
    model, table = model_table
    p, pt = model.params(), _tangent(model, table).params()
    y0, scale = model.static_state(), model.state_scale()
    n = model.n_dof
    rows = fmu_rows(model, kind)
    rng = np.random.default_rng(5)
    times = rng.uniform(0.0, 0.05, 200)
    states = y0 + 0.3 * scale * rng.standard_normal((200, 2 * n))
    states[:, 1] = y0[1] * (1.0 + rng.uniform(-0.95, 0.6, 200))
    flanges = flange_inputs(model, states) if "gearbox" in kind else None
    _, got = me_derivatives(built[kind].fmu, times, states[:, rows], inputs=flanges, name=kind)
    want, want_t = (rhs_derivatives(q, times, states, rows) for q in (p, pt))
    rel = np.abs(got - want).max(axis=0) / want.std(axis=0)
    acc = [k for k, r in enumerate(rows) if r - n in (1, 2)]
    assert rel[acc].max() < 1e-10, rel
    assert rel.max() < 2e-8, rel
    share = np.abs(want - want_t)[:, acc].max(axis=0) / want.std(axis=0)[acc]
    assert share.min() > 0.05, share
    assert rel[acc].max() < 1e-6 * share.min()


def _reference(model, stop=STOP):
    t = np.linspace(0.0, stop, int(round(stop / 1e-4)) + 1)
    tt, y, info = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=1e-10))
    assert info["status"] == "success", info
    return tt, outputs(model, tt, y)


@pytest.mark.parametrize(
    ("kind", "interface", "rtol", "tol"),
    [
        ("drivetrain", "CoSimulation", 1e-8, 3e-6),
        ("drivetrain", "CoSimulation", None, 3e-6),
        ("drivetrain3", "CoSimulation", 1e-8, 3e-6),
        ("drivetrain", "ModelExchange", 1e-8, 1e-5),
    ],
    ids=["cs_dopri5", "cs_fixed_step", "fmi3_cs_dopri5", "me_cvode"],
)
def test_run_with_the_loaded_law_matches_python_reference(
    built, model_table, kind, interface, rtol, tol
):
    """The mesh force over 0.02 s from the static state as RMS error over the
    reference's AC RMS (scipy DOP853 at rtol 1e-10). Measured: 3.4e-7 (DOPRI5 at rtol
    1e-8, FMI 2.0 and 3.0 alike), 2.4e-7 (the default fixed step), 1.7e-6 (CVode rtol
    1e-8); bounds about 10x. The loaded law moves the mesh force by 0.016 of its AC RMS
    against the tangent law from the same start (bound 0.005)."""
    model, table = model_table
    t_ref, ref = _reference(model)
    t, ch, _ = simulate_fmu(
        built[kind].fmu,
        interface=interface,
        stop_time=STOP,
        step=1e-4,
        rtol=rtol,
        outputs=["mesh.force"],
    )
    err = ac_relative_error(t, ch["mesh.force"], t_ref, ref["mesh_force_N"])
    assert err < tol, err
    _, tangent = _reference(_tangent(model, table))
    effect = ac_relative_error(t_ref, tangent["mesh_force_N"], t_ref, ref["mesh_force_N"])
    assert effect > 5e-3, effect


def test_tangent_law_fmu_takes_the_laws_tangent_at_another_mean_torque(
    model_table, tmp_path, monkeypatch
):
    """The tangent-law drivetrain FMU of the 802 N m model with ``engine.mean_torque`` set
    to 150 N m at instantiation (between the levels 50 and 300 N m, where the law bends
    most): its derivatives at 200 random states against ``rhs`` of the model built at
    150 N m (``tangent_at``: the loaded law's tangent), within the grids' 1e-10 of the
    std (tests/test_fmu.py's bound) on the pinion and gear rows (measured 1.0e-11). The
    model built with the table linear in torque differs by 0.41 of the std there
    (measured; asserted above 0.1), so C code that interpolated linearly would fail."""
    from gearbox.drivetrain import model as dm

    model, table = model_table
    power = 150.0 * 3500 * np.pi / 30 / 1e3
    low_scene = load_scene(SCENE).replaced(drivetrain={"engine_power_kW": power})
    low = DrivetrainModel.from_scene(low_scene, table)
    assert low.torque == pytest.approx(150.0, rel=1e-12) and low.mesh_law == "tangent"
    fmu = build_fmu(drivetrain_fmu(_tangent(model, table), table), tmp_path).fmu
    n = low.n_dof
    rows = fmu_rows(low, "drivetrain")
    rng = np.random.default_rng(7)
    times = rng.uniform(0.0, 0.05, 200)
    y0, scale = low.static_state(), low.state_scale()
    states = y0 + 0.3 * scale * rng.standard_normal((200, 2 * n))
    start = {"engine.mean_torque": low.torque}
    _, got = me_derivatives(fmu, times, states[:, rows], start=start, name="tangent 150")
    want = rhs_derivatives(low.params(), times, states, rows)
    rel = np.abs(got - want).max(axis=0) / want.std(axis=0)
    acc = [k for k, r in enumerate(rows) if r - n in (1, 2)]
    assert rel[acc].max() < 1e-10, rel

    def linear(tab, flank, lam1, torque):
        k = tab.values_at("tangent_stiffness", flank, torque)
        return (k, tab.values_at("lte", flank, torque)), "linear"

    monkeypatch.setattr(dm, "tangent_at", linear)
    other = rhs_derivatives(
        DrivetrainModel.from_scene(low_scene, table).params(), times, states, rows
    )
    gap = np.abs(other - want)[:, acc].max(axis=0) / want.std(axis=0)[acc]
    assert gap.min() > 0.1, gap
