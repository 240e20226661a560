"""The FMU folders committed under fmus/ (Reference-FMUs shape): each builds from its
own sources with gcc, passes fmpy's validation, and reproduces its reference CSV.

Regenerate the folders and CSVs with ``python3 -m gearbox.fmu.reference``.
BeveloidDrivetrain_ref.csv comes from the scipy solver (independent of the C code);
the other three come from the libcosim co-simulation (golden masters).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fmpy")

from gearbox.fmu.build import (
    build_folder,  # noqa: E402
    find_c_compiler,  # noqa: E402
)
from gearbox.fmu.run import ac_relative_error, simulate_fmu  # noqa: E402

FMUS = Path(__file__).resolve().parents[1] / "fmus"
FOLDERS = sorted(p.parent.name for p in FMUS.glob("*/FMI2.xml"))

pytestmark = pytest.mark.skipif(find_c_compiler() is None, reason="needs a C compiler (gcc or $CC)")


def _ref(name: str) -> dict[str, np.ndarray]:
    data = np.genfromtxt(FMUS / name / f"{name}_ref.csv", delimiter=",", names=True, deletechars="")
    return {k: data[k] for k in data.dtype.names}


@pytest.fixture(scope="module")
def builds(tmp_path_factory):
    out = tmp_path_factory.mktemp("fmus")
    return {name: build_folder(FMUS / name, out) for name in FOLDERS}


def test_the_four_folders_are_there():
    assert set(FOLDERS) == {"BeveloidDrivetrain", "BeveloidGearbox", "MarineEngine", "Propeller"}
    for name in FOLDERS:
        for f in ("config.h", "model.c", "FMI2.xml", "FMI3.xml", "readme.md", f"{name}_ref.csv"):
            assert (FMUS / name / f).exists(), f"{name}/{f}"


@pytest.mark.parametrize("name", FOLDERS)
def test_folder_builds_and_validates(builds, name):
    from fmpy.validation import validate_fmu

    assert builds[name].compiler_output == ""
    assert validate_fmu(builds[name].fmu) == []


def test_folder_builds_as_fmi3_and_reproduces_the_reference(tmp_path):
    from fmpy.validation import validate_fmu

    b = build_folder(FMUS / "BeveloidDrivetrain", tmp_path, fmi_version=3)
    assert validate_fmu(b.fmu) == []
    ref = _ref("BeveloidDrivetrain")
    t, ch, _ = simulate_fmu(
        b.fmu, stop_time=float(ref["time"][-1]), step=1e-4, rtol=1e-8, outputs=["mesh.force"]
    )
    assert ac_relative_error(t, ch["mesh.force"], ref["time"], ref["mesh.force"]) < 1e-5


@pytest.mark.parametrize("interface, tol", [("CoSimulation", 1e-5), ("ModelExchange", 5e-5)])
def test_drivetrain_reproduces_the_scipy_reference(builds, interface, tol):
    ref = _ref("BeveloidDrivetrain")
    stop = float(ref["time"][-1])
    t, ch, _ = simulate_fmu(
        builds["BeveloidDrivetrain"].fmu,
        interface=interface,
        stop_time=stop,
        step=1e-4,
        rtol=1e-8,
        outputs=["mesh.force", "input_shaft.torque"],
    )
    # tolerances as in tests/test_fmu.py (same equations, rtol 1e-8 against 1e-10)
    assert ac_relative_error(t, ch["mesh.force"], ref["time"], ref["mesh.force"]) < tol
    assert (
        ac_relative_error(t, ch["input_shaft.torque"], ref["time"], ref["input_shaft.torque"]) < tol
    )


def test_cosimulation_reproduces_its_golden_master(builds, tmp_path):
    pytest.importorskip("libcosimpy")
    from gearbox.fmu.cosim import CHANNELS, run_system, system_structure

    fmus = {
        "engine": builds["MarineEngine"].fmu,
        "gearbox": builds["BeveloidGearbox"].fmu,
        "propeller": builds["Propeller"].fmu,
    }
    init = {k: {"solver.method": 0.0, "solver.rtol": 1e-8, "solver.max_step": 1e-5} for k in fmus}
    path = tmp_path / "OspSystemStructure.xml"
    path.write_text(system_structure(fmus, 1e-5, initial_values=init))
    stop = 0.02  # as gearbox.fmu.reference.STOP
    res = run_system(path, stop, 1e-5)
    assert res.success, res.message
    names = {"BeveloidGearbox": "gearbox", "MarineEngine": "engine", "Propeller": "propeller"}
    for name, sim in names.items():
        ref = _ref(name)
        for channel, (s, var) in CHANNELS.items():
            if s != sim:
                continue
            k = ref["time"] <= res.time[-1] + 1e-12  # libcosim samples up to the last step
            got = np.interp(ref["time"][k], res.time, res[channel])
            # same code, same compiler flags: equal to round-off of the CSV's 12 digits
            scale = max(np.abs(ref[var]).max(), 1e-300)
            assert np.max(np.abs(got - ref[var][k])) < 1e-9 * scale, (name, var)
