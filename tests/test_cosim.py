"""Co-simulation of engine, gearbox and propeller FMUs on libcosim (docs/fmu.md).

Reference: the monolithic drivetrain FMU (the same equations without a coupling
split), itself checked against the scipy solver in tests/test_fmu.py. Errors are the
RMS difference over the AC RMS of the reference at the communication points.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fmpy")
pytest.importorskip("libcosimpy")

from gearbox import load_scene  # noqa: E402
from gearbox.cli import main  # noqa: E402
from gearbox.fmu import build_fmu, drivetrain_fmu  # noqa: E402
from gearbox.fmu.build import find_c_compiler  # noqa: E402
from gearbox.fmu.cosim import (  # noqa: E402
    CHANNELS,
    CONNECTIONS,
    RATE_CONNECTIONS,
    CosimResult,
    build_cosim_fmus,
    channels_for,
    cosim_drivetrain,
)
from gearbox.fmu.models import model_from_scene  # noqa: E402
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "marine_drive.toml"
STOP = 0.01  # s: 17 mesh cycles at 3500 rpm

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    model, table = model_from_scene(load_scene(SCENE))
    out = tmp_path_factory.mktemp("cosim")
    builds = build_cosim_fmus(model, table, out)
    mono = build_fmu(drivetrain_fmu(model, table), out)
    t, ch, _ = simulate_fmu(
        mono.fmu,
        stop_time=STOP,
        step=1e-5,
        rtol=1e-10,
        outputs=["mesh.force", "input_shaft.torque", "engine.w"],
    )
    return model, table, out, builds, (t, ch)


def _error(res: CosimResult, ref, channel="mesh_force_N", ref_channel="mesh.force") -> float:
    t, ch = ref
    k = np.abs(t / res.step - np.round(t / res.step)) < 1e-6
    k &= t <= res.time[-1] + 1e-12
    return ac_relative_error(res.time, res[channel], t[k], ch[ref_channel][k])


def test_system_structure_couples_three_fmus(setup):
    model, table, out, builds, _ = setup
    res = cosim_drivetrain(model, table, out, step=5e-5, stop_time=1e-3, builds=builds)
    root = ET.parse(res.system_structure).getroot()
    ns = "{http://opensimulationplatform.com/MSMI/OSPSystemStructure}"
    sims = {s.get("name") for s in root.iter(ns + "Simulator")}
    assert sims == {"engine", "gearbox", "propeller"}
    assert len(list(root.iter(ns + "VariableConnection"))) == len(CONNECTIONS) + len(
        RATE_CONNECTIONS
    )


def test_libcosim_runs_and_agrees_with_the_monolithic_fmu(setup):
    model, table, out, builds, ref = setup
    res = cosim_drivetrain(model, table, out, step=5e-5, stop_time=STOP, builds=builds)
    assert res.success, res.message
    assert res.steps == round(STOP / 5e-5)
    # Measured 3.0e-5 (mesh force) and 7.2e-4 (input shaft torque) at this step over
    # these 0.01 s; zero-order hold gives 1.0e-3 and 1.5e-2. Bounds: 4x and 3x above.
    assert _error(res, ref) < 1.2e-4
    assert _error(res, ref, "input_shaft_torque_Nm", "input_shaft.torque") < 2e-3
    # the mean power flow is the monolithic one
    assert (
        abs(res["mesh_force_N"].mean() - ref[1]["mesh.force"].mean())
        < 1e-3 * ref[1]["mesh.force"].mean()
    )


@pytest.mark.parametrize("extrapolate, order", [(True, 2.0), (False, 1.0)])
def test_coupling_error_converges_with_the_expected_order(setup, extrapolate, order):
    model, table, out, builds, ref = setup
    steps = np.array([4e-5, 2e-5, 1e-5])
    errs = []
    for h in steps:
        res = cosim_drivetrain(
            model, table, out, step=float(h), stop_time=STOP, builds=builds, extrapolate=extrapolate
        )
        assert res.success
        errs.append(_error(res, ref))
    slope = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    # held inputs: first order; inputs extrapolated with their rates: second order.
    # +-0.3 as for fitted convergence orders (scikit-fem's habit is +-0.1 on cleaner data).
    assert abs(slope - order) < 0.3, (slope, errs)


def test_cli_cosim_writes_results(tmp_path):
    out = tmp_path / "cs"
    rc = main(["cosim", str(SCENE), "--out", str(out), "--stop-time", "0.002", "--json"])
    assert rc == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "success" and summary["steps"] == 40
    header = (out / "cosim.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "time_s" and "mesh_force_N" in header
    assert (out / "OspSystemStructure.xml").exists()


def test_cli_invalid_step_exits_2(tmp_path, capsys):
    rc = main(["cosim", str(SCENE), "--out", str(tmp_path), "--step", "-1"])
    assert rc == 2
    assert "step" in capsys.readouterr().err


def test_cli_fmu_build_all(tmp_path, capsys):
    rc = main(["fmu", "build", str(SCENE), "--out", str(tmp_path), "--kind", "all", "--json"])
    assert rc == 0
    builds = json.loads(capsys.readouterr().out)
    assert set(builds) == {"drivetrain", "gearbox", "engine", "propeller"}
    for b in builds.values():
        assert Path(b["fmu"]).exists() and (Path(b["source_dir"]) / "FMI2.xml").exists()


def test_cosim_result_round_trip(setup):
    model, table, out, builds, _ = setup
    res = cosim_drivetrain(model, table, out, step=5e-5, stop_time=5e-4, builds=builds)
    back = CosimResult.from_dict(json.loads(json.dumps(res.to_dict())))
    assert np.array_equal(back.time, res.time)
    assert np.array_equal(back["mesh_force_N"], res["mesh_force_N"])
    assert back.status == res.status and back.step == res.step


def test_libcosim_runs_the_monolithic_fmu_as_an_independent_importer(setup, tmp_path):
    """libcosim (not fmpy) instantiates and steps the drivetrain FMU alone."""
    from gearbox.fmu.cosim import run_system, system_structure

    model, table, out, _, ref = setup
    mono = build_fmu(drivetrain_fmu(model, table), tmp_path)
    path = tmp_path / "OspSystemStructure.xml"
    init = {"drivetrain": {"solver.method": 0.0, "solver.rtol": 1e-10}}
    path.write_text(
        system_structure({"drivetrain": mono.fmu}, 1e-4, initial_values=init, connections=())
    )
    res = run_system(
        path,
        STOP,
        1e-4,
        channels={
            "mesh_force_N": ("drivetrain", "mesh.force"),
            "engine_speed_rad_per_s": ("drivetrain", "engine.w"),
        },
    )
    assert res.success, res.message
    # the same FMU and tolerance as the fmpy reference run: the importers agree to the
    # integrator's tolerance (1e-10) amplified by the stiff mesh, far below 1e-6
    assert _error(res, ref) < 1e-6


def test_a_features_outputs_reach_the_result(tmp_path):
    """With an eccentric pinion the gearbox FMU's ``mesh.eccentricity_approach`` is one
    of the result's channels (gearbox.fmu.cosim.channels_for), equal to the monolithic
    FMU's at the communication points within 1e-4 of its amplitude (the approach is
    kinematic: only the coupling's error in the pinion angle enters)."""
    scene = load_scene(SCENE).replaced(drivetrain={"pinion_eccentricity_um": 20.0})
    model, table = model_from_scene(scene)
    res = cosim_drivetrain(model, table, tmp_path, step=1e-4, stop_time=0.005)
    assert res.status == "success", res.message
    assert set(res.channels) == set(channels_for(model)) > set(CHANNELS)
    mono = build_fmu(drivetrain_fmu(model, table), tmp_path / "mono")
    t, ch, _ = simulate_fmu(
        mono.fmu, stop_time=0.005, step=1e-5, rtol=1e-10, outputs=["mesh.eccentricity_approach"]
    )
    ref = np.interp(res.time, t, ch["mesh.eccentricity_approach"])
    amp = np.abs(ref).max()
    assert amp > 5e-6
    assert np.abs(res.channels["eccentricity_approach_m"] - ref).max() < 1e-4 * amp
