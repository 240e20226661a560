"""exudyn backend with eccentricities (docs/exudyn.md, docs/drivetrain.md §3b): agreement
with the scipy reference and the cost per right-hand side with and without them.

    python benchmarks/bench_exudyn_eccentricity.py [--repeat 5] [--cycles 200]

Scene: models/marine_drive.toml with a 20 um pinion (30 deg) and a 15 um gear (-60 deg)
eccentricity at pinion phase 0.7 rad, without and with the bearing translations (the
drive of tests/test_drivetrain_exudyn_eccentricity.py).

- Agreement: ``simulate`` with exudyn (default step; symbolic and Python user
  functions) against scipy DOP853 at rtol 1e-10, 20 settling mesh cycles and one pinion
  revolution (N_1 mesh cycles at 32 samples each): relative differences of the mesh
  force's RMS, dynamic RMS and mesh-order amplitude, and of its order lines 1 and
  N_1 -+ 1 (single-sided amplitudes over the revolution).
- Cost: ``integrate_exudyn`` from the operating point, 20 settling and ``--cycles``
  recorded mesh cycles at 8 samples each: median wall time over ``--repeat`` runs per
  right-hand side, each user-function kind, with and without the eccentricities; and
  the length of the recorded mesh expression.

Nothing here is asserted; wall times scatter with the machine's load.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
from pathlib import Path

import numpy as np

from gearbox import spectrum
from gearbox.drivetrain import exudyn_backend as xb
from gearbox.drivetrain.linear import periodic_start_state
from gearbox.drivetrain.model import DrivetrainModel
from gearbox.drivetrain.scipy_backend import ScipySolver
from gearbox.drivetrain.simulate import mesh_force_metrics, record_times, simulate
from gearbox.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
ECCENTRICITY = {
    "pinion_eccentricity_um": 20.0,
    "pinion_eccentricity_angle_deg": 30.0,
    "gear_eccentricity_um": 15.0,
    "gear_eccentricity_angle_deg": -60.0,
}
PHASE = 0.7
METRICS = ("mesh_force_rms_N", "mesh_force_dynamic_rms_N", "mesh_force_mesh_order_amplitude_N")


def drive(bearings: bool, eccentric: bool) -> DrivetrainModel:
    keys = {"bearing_dofs": bearings, **(ECCENTRICITY if eccentric else {})}
    scene = load_scene(ROOT / "models" / "marine_drive.toml").replaced(drivetrain=keys)
    return dataclasses.replace(DrivetrainModel.from_scene(scene), phase=PHASE)


def figures(ts, model) -> np.ndarray:
    """The compared quantities: the mesh-force metrics, then the order lines 1,
    N_1 - 1, N_1 + 1 (N)."""
    m = mesh_force_metrics(ts, model)
    rpm = model.speed * 30 / np.pi
    sp = spectrum.order_spectrum(ts.time, ts["mesh_force_N"], speed_rpm=rpm, period_revs=1.0)
    n1 = model.pinion_teeth
    lines = np.interp([1, n1 - 1, n1 + 1], sp.orders, sp.amplitudes)
    return np.r_[[m[k] for k in METRICS], lines]


def agreement(bearings: bool) -> None:
    model = drive(bearings, True)
    kw = {"mesh_cycles": model.pinion_teeth}
    ref = figures(simulate(model, ScipySolver(rtol=1e-10), **kw), model)
    names = ("RMS", "dyn RMS", "mesh order", "order 1", "N1-1", "N1+1")
    print(
        f"bearings {bearings}: scipy "
        + "  ".join(f"{a} {b:.3f} N" for a, b in zip(names, ref, strict=True))
    )
    for uf in ("symbolic", "python"):
        got = figures(simulate(model, xb.ExudynSolver(user_functions=uf), **kw), model)
        d = np.abs(got - ref) / np.abs(ref)
        print(
            f"  exudyn {uf:8s} rel. diff "
            + "  ".join(f"{a} {b:.1e}" for a, b in zip(names, d, strict=True))
        )
    plain = drive(bearings, False)
    line = figures(simulate(plain, xb.ExudynSolver(), **kw), plain)[3]
    print(f"  order-1 line without the eccentricities {line:.2f} N (with: {ref[3]:.2f} N)")


def cost(bearings: bool, cycles: int, repeat: int) -> None:
    for eccentric in (False, True):
        model = drive(bearings, eccentric)
        tm = 1.0 / model.mesh_frequency
        t_eval = np.concatenate([[20 * tm], record_times(model, 20 * tm, cycles, 8)])
        y0 = periodic_start_state(model)
        size = len(str(xb.build_exudyn_system(model).keepalive[-1][2]))
        row = []
        for uf in ("symbolic", "python"):
            walls = []
            for _ in range(repeat if uf == "symbolic" else 1):
                _, _, info = xb.integrate_exudyn(
                    model, y0, t_eval, xb.ExudynSolver(user_functions=uf)
                )
                walls.append(info["wall_time"])
            row.append(f"{uf} {statistics.median(walls) / info['nfev'] * 1e6:.2f} us")
        print(
            f"bearings {bearings}, eccentricity {eccentric}: per right-hand side "
            f"{', '.join(row)} (nfev {info['nfev']}); mesh expression {size} characters"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=200, help="recorded mesh cycles (cost)")
    ap.add_argument("--repeat", type=int, default=5, help="runs per setting (median wall)")
    args = ap.parse_args()
    for bearings in (False, True):
        agreement(bearings)
    print()
    for bearings in (False, True):
        cost(bearings, args.cycles, args.repeat)


if __name__ == "__main__":
    main()
