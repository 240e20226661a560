"""FMI 3.0 export (``build_fmu(..., fmi_version=3)``): fmpy validation, both
interfaces against the scipy reference, errors through the FMI 3.0 API."""

from __future__ import annotations

import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fmpy")

from gearbox import load_scene  # noqa: E402
from gearbox.drivetrain.model import outputs  # noqa: E402
from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy  # noqa: E402
from gearbox.fmu import build_fmu, drivetrain_fmu, engine_fmu, gearbox_fmu, propeller_fmu  # noqa: E402
from gearbox.fmu.build import find_c_compiler  # noqa: E402
from gearbox.fmu.models import model_from_scene  # noqa: E402
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "models" / "marine_drive.toml"
STOP = 0.01  # s

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    model, table = model_from_scene(load_scene(SCENE))
    out = tmp_path_factory.mktemp("fmi3")
    builds = {
        "drivetrain": build_fmu(drivetrain_fmu(model, table), out, fmi_version=3),
        "gearbox": build_fmu(gearbox_fmu(model, table), out, fmi_version=3),
        "engine": build_fmu(engine_fmu(model), out, fmi_version=3),
        "propeller": build_fmu(propeller_fmu(model), out, fmi_version=3),
    }
    t = np.linspace(0.0, STOP, int(round(STOP / 1e-4)) + 1)
    tt, y, info = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=1e-10))
    assert info["status"] == "success"
    return builds, (tt, outputs(model, tt, y))


@pytest.mark.parametrize("kind", ["drivetrain", "gearbox", "engine", "propeller"])
def test_fmi3_validates_and_exports_only_fmi3_functions(setup, kind):
    from fmpy.validation import validate_fmu

    b = setup[0][kind]
    assert b.fmu.endswith("_fmi3.fmu") and b.compiler_output == ""
    assert validate_fmu(b.fmu) == []
    names = zipfile.ZipFile(b.fmu).namelist()
    assert f"binaries/x86_64-linux/{b.identifier}.so" in names
    assert "sources/fmi3_runtime.c" in names


@pytest.mark.parametrize("interface, tol", [("CoSimulation", 1e-5), ("ModelExchange", 5e-5)])
def test_fmi3_matches_python_reference(setup, interface, tol):
    builds, (t_ref, ref) = setup
    t, ch, _ = simulate_fmu(
        builds["drivetrain"].fmu,
        interface=interface,
        stop_time=STOP,
        step=1e-4,
        rtol=1e-8,
        outputs=["mesh.force", "input_shaft.torque"],
    )
    # as the FMI 2.0 tests in tests/test_fmu.py: the same C code behind another API
    assert ac_relative_error(t, ch["mesh.force"], t_ref, ref["mesh_force_N"]) < tol
    assert ac_relative_error(t, ch["input_shaft.torque"], t_ref, ref["input_shaft_torque_Nm"]) < tol


def test_fmi3_invalid_parameter_is_an_error_with_a_message(setup):
    from fmpy import extract, read_model_description
    from fmpy.fmi3 import FMU3Slave

    path = setup[0]["drivetrain"].fmu
    md = read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(path)
    messages = []

    def log(env, status, category, message):
        messages.append((status, message.decode()))

    try:
        fmu = FMU3Slave(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="fmi3",
        )
        fmu.instantiate(logMessage=log)
        fmu.enterInitializationMode(startTime=0.0)
        old = fmu.getFloat64([vr["gear.inertia"]])[0]
        with pytest.raises(Exception, match="fmi3SetFloat64"):
            fmu.setFloat64([vr["gear.inertia"]], [-1.0])
        assert any("gear.inertia = -1 is invalid" in m for s, m in messages), messages
        assert fmu.getFloat64([vr["gear.inertia"]])[0] == old
        fmu.exitInitializationMode()
        fmu.doStep(0.0, 1e-3)
        assert fmu.getFloat64([vr["time"]])[0] == pytest.approx(1e-3)
        assert np.isfinite(fmu.getFloat64([vr["mesh.force"]])[0])
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(d, ignore_errors=True)


def test_fmi3_missing_resource_fails_at_instantiation(setup):
    from fmpy import extract, read_model_description
    from fmpy.fmi3 import FMU3Slave

    path = setup[0]["drivetrain"].fmu
    md = read_model_description(path)
    d = extract(path)
    messages = []

    def log(env, status, category, message):
        messages.append(message.decode())

    try:
        (Path(d) / "resources" / "mesh_torque.txt").unlink()
        fmu = FMU3Slave(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="fmi3",
        )
        with pytest.raises(Exception, match="Failed to instantiate"):
            fmu.instantiate(logMessage=log)
        assert any("cannot open resource table" in m for m in messages), messages
    finally:
        shutil.rmtree(d, ignore_errors=True)
