"""Regenerate the FMU source folders of the default scene under ``fmus/``.

    python3 -m gearbox.fmu.reference [SCENE] [--out fmus]

Writes one Reference-FMUs-shaped folder per FMU (``config.h``, ``model.c``,
``FMI2.xml``, ``readme.md``, ``resources/``) and its reference output
``<id>_ref.csv`` (time first, SI):

- ``BeveloidDrivetrain_ref.csv``: the scipy solver (DOP853, rtol 1e-10) on the numpy
  right-hand side, an implementation independent of the generated C;
- ``BeveloidGearbox_ref.csv``, ``MarineEngine_ref.csv``, ``Propeller_ref.csv``: the
  libcosim co-simulation of the three at a 1e-5 s communication step.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from ..commands._common import write_atomic
from ..scene import load_scene
from .build import write_sources
from .cosim import CHANNELS, build_cosim_fmus, cosim_drivetrain
from .models import drivetrain_fmu, engine_fmu, gearbox_fmu, model_from_scene, propeller_fmu

STOP = 0.02  # s
DT = 1e-4  # s, reference sample step

#: drivetrain FMU variable -> channel of gearbox.drivetrain.model.outputs
DRIVETRAIN_COLUMNS = {
    "engine.w": "engine_speed_rad_per_s",
    "pinion.w": "pinion_speed_rad_per_s",
    "gear.w": "gear_speed_rad_per_s",
    "propeller.w": "propeller_speed_rad_per_s",
    "input_shaft.torque": "input_shaft_torque_Nm",
    "output_shaft.torque": "output_shaft_torque_Nm",
    "mesh.force": "mesh_force_N",
    "mesh.deflection": "mesh_deflection_m",
    "mesh.dte": "dynamic_transmission_error_m",
    # with mesh friction (mu > 0) only
    "mesh.pinion_friction_torque": "pinion_friction_torque_Nm",
    "mesh.gear_friction_torque": "gear_friction_torque_Nm",
    "mesh.friction_power": "mesh_friction_power_W",
    # with an eccentricity (pinion or gear) only
    "mesh.eccentricity_approach": "eccentricity_approach_m",
    # with pitch deviations only
    "mesh.pitch_approach": "pitch_approach_m",
}


def _csv(time: np.ndarray, columns: dict[str, np.ndarray]) -> str:
    lines = [",".join(["time", *columns])]
    for i, t in enumerate(time):
        lines.append(",".join([f"{t:.10g}", *(f"{v[i]:.12g}" for v in columns.values())]))
    return "\n".join(lines) + "\n"


def regenerate(scene_path: str | Path, out: str | Path) -> list[Path]:
    """Write the four folders and reference CSVs; return the folders."""
    from ..drivetrain.model import outputs
    from ..drivetrain.scipy_backend import ScipySolver, integrate_scipy

    out = Path(out)
    model, table = model_from_scene(load_scene(scene_path))
    fmus = {
        "drivetrain": drivetrain_fmu(model, table),
        "gearbox": gearbox_fmu(model, table),
        "engine": engine_fmu(model),
        "propeller": propeller_fmu(model),
    }
    folders = {k: write_sources(m, out / m.identifier) for k, m in fmus.items()}
    t = np.linspace(0.0, STOP, int(round(STOP / DT)) + 1)
    tt, y, info = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=1e-10))
    if info["status"] != "success":
        raise RuntimeError(f"reference run failed: {info}")
    ch = outputs(model, tt, y)
    ident = fmus["drivetrain"].identifier
    write_atomic(
        folders["drivetrain"] / f"{ident}_ref.csv",
        _csv(tt, {k: ch[v] for k, v in DRIVETRAIN_COLUMNS.items() if v in ch}),
    )
    with tempfile.TemporaryDirectory() as tmp:
        builds = build_cosim_fmus(model, table, tmp)
        res = cosim_drivetrain(model, table, tmp, step=1e-5, stop_time=STOP, builds=builds)
    keep = np.abs(res.time / DT - np.round(res.time / DT)) < 1e-6
    for kind in ("gearbox", "engine", "propeller"):
        cols = {var: res[name][keep] for name, (sim, var) in CHANNELS.items() if sim == kind}
        ident = fmus[kind].identifier
        write_atomic(folders[kind] / f"{ident}_ref.csv", _csv(res.time[keep], cols))
    return list(folders.values())


def main(argv: list[str] | None = None) -> int:
    root = Path(__file__).resolve().parents[2]
    ap = argparse.ArgumentParser(
        prog="python3 -m gearbox.fmu.reference",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("scene", nargs="?", default=str(root / "models" / "marine_drive.toml"))
    ap.add_argument("--out", default=str(root / "fmus"))
    args = ap.parse_args(argv)
    for f in regenerate(args.scene, args.out):
        print(f)
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
