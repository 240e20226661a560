"""The loaded mesh law against the tangent law (docs/drivetrain.md §3d) on the default
scene: accuracy against loaded TCA solves the law's table does not hold, what the law
changes in the dynamics along the propeller law, and what it costs.

    python3 benchmarks/dynamics_mesh_law.py              # about a minute
    python3 benchmarks/dynamics_mesh_law.py --repeats 7

Printed:
1. For each flank and each torque between the table's levels (50, 300, 600, 900 N m):
   the largest gap, as a share of the largest LTE, between the loaded TCA solved at
   that torque and (a) the loaded law's deflection under the torque's mesh force,
   (b) linear interpolation of the table in torque (which neither law takes: both
   take the loaded law's tangent between the levels), (c) the tangent law of the
   operating torque (802 N m) carried to that force. 1b: the cycle mean of the tangent stiffness there, the law's slope
   and the table's linear interpolation in torque, against the loaded TCA's.
2. At 1000, 2000 and 3500 rpm on the propeller law (engine and propeller ripple as in
   the scene): the mesh force's mesh-order amplitude, largest value and dynamic RMS
   over a settled record with each law (fixed-step jax solver).
3. Wall time of the fixed-step run at 3500 rpm, 900 mesh cycles (compiled; median of
   ``--repeats``), each law, and their ratio measured in the same run.
4. With a C compiler: the drivetrain FMU of each law over 0.2 s at 3500 rpm in
   Co-Simulation through fmpy (1 ms communication step; its fixed step and DOPRI5 at
   rtol 1e-8), medians of ``--repeats``, and their ratio.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
MORE = (50.0, 100.0, 150.0, 200.0, 300.0, 450.0, 600.0, 750.0, 900.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()

    from gearbox import load_scene
    from gearbox.drivetrain.model import DrivetrainModel, loaded_law_point, loaded_law_samples
    from gearbox.drivetrain.simulate import mesh_force_metrics, simulate
    from gearbox.pipeline import run_pipeline

    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    with tempfile.TemporaryDirectory() as cache:
        table = run_pipeline(scene, ["tables"], cache=cache)["tables"]
        more = run_pipeline(
            scene.replaced(load={"torques_Nm": list(MORE)}), ["tables"], cache=cache
        )["tables"]

    op = DrivetrainModel.from_scene(scene, table)
    lam = op.drive.lambda1
    print("1. LTE against loaded TCA solves between the levels (largest gap / largest LTE)")
    print(
        f"{'flank':6} {'torque N m':>10} {'loaded law':>11} {'linear in T':>12} {'tangent 802':>12}"
    )
    for flank in ("drive", "coast"):
        rows, forces = loaded_law_samples(table, flank, lam)
        im = more.flank_index(flank)
        kt = table.values_at("tangent_stiffness", flank, op.torque)
        lte_op = table.values_at("lte", flank, op.torque)
        for j, torque in enumerate(MORE):
            if torque in table.torque:
                continue
            ref = more.lte[im, j]
            x, _ = loaded_law_point(rows, forces, torque / lam)
            lin = table.values_at("lte", flank, torque)
            tan = lte_op + (torque - op.torque) / lam / kt
            gaps = [np.abs(v - ref).max() / ref.max() * 100 for v in (x, lin, tan)]
            print(f"{flank:6} {torque:10.0f} {gaps[0]:10.3f}% {gaps[1]:11.3f}% {gaps[2]:11.2f}%")
    print(
        "\n1b. Tangent stiffness there: cycle mean against the loaded TCA's (loaded law / linear in T)"
    )
    for flank in ("drive", "coast"):
        rows, forces = loaded_law_samples(table, flank, lam)
        im = more.flank_index(flank)
        for j, torque in enumerate(MORE):
            if torque in table.torque:
                continue
            ref = more.tangent_stiffness[im, j].mean()
            _, k = loaded_law_point(rows, forces, torque / lam)
            lin = table.values_at("tangent_stiffness", flank, torque).mean()
            print(
                f"{flank:6} {torque:10.0f} N m  {(k.mean() / ref - 1) * 100:+7.2f}%  "
                f"{(lin / ref - 1) * 100:+7.2f}%"
            )

    print(
        "\n2. Mesh force along the propeller law (mesh-order amplitude / largest / dynamic RMS, N)"
    )
    power = scene["drivetrain"]["engine_power_kW"]
    n_op = scene["drivetrain"]["engine_speed_rpm"]
    for rpm in (1000.0, 2000.0, 3500.0):
        line = [f"{rpm:6.0f} rpm"]
        for law in ("tangent", "loaded"):
            s = scene.replaced(
                drivetrain={
                    "mesh_law": law,
                    "engine_speed_rpm": rpm,
                    "engine_power_kW": power * (rpm / n_op) ** 3,
                }
            )
            m = DrivetrainModel.from_scene(s, table)
            met = mesh_force_metrics(simulate(m, mesh_cycles=240), m)
            line.append(
                f"{law}: {met['mesh_force_mesh_order_amplitude_N']:8.2f} / "
                f"{met['mesh_force_max_N']:8.1f} / {met['mesh_force_dynamic_rms_N']:7.2f}"
            )
        print("  ".join(line))

    print(f"\n3. Fixed-step run at {n_op:.0f} rpm, 900 mesh cycles (median of {args.repeats})")
    walls = {}
    for law in ("tangent", "loaded"):
        m = DrivetrainModel.from_scene(scene.replaced(drivetrain={"mesh_law": law}), table)
        simulate(m, mesh_cycles=900)  # compile
        w = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            simulate(m, mesh_cycles=900)
            w.append(time.perf_counter() - t0)
        walls[law] = float(np.median(w))
        print(f"{law:8} {walls[law]:.3f} s  (runs {', '.join(f'{v:.3f}' for v in w)})")
    print(f"loaded / tangent: {walls['loaded'] / walls['tangent']:.2f}")

    from gearbox.fmu.build import find_c_compiler

    if find_c_compiler() is None:
        print("\n4. FMU: no C compiler, skipped")
        return
    from gearbox.fmu import build_fmu, drivetrain_fmu
    from gearbox.fmu.run import simulate_fmu

    stop = 0.2
    print(f"\n4. Drivetrain FMU, Co-Simulation through fmpy, {stop} s at {n_op:.0f} rpm")
    fmu_walls = {}
    with tempfile.TemporaryDirectory() as out:
        for law in ("tangent", "loaded"):
            m = DrivetrainModel.from_scene(scene.replaced(drivetrain={"mesh_law": law}), table)
            path = build_fmu(drivetrain_fmu(m, table), Path(out) / law).fmu
            for method, rtol in (("fixed step", None), ("DOPRI5 rtol 1e-8", 1e-8)):
                w = [
                    simulate_fmu(
                        path, stop_time=stop, step=1e-3, rtol=rtol, outputs=["mesh.force"]
                    )[2]
                    for _ in range(args.repeats)
                ]
                fmu_walls[law, method] = float(np.median(w))
    for method in ("fixed step", "DOPRI5 rtol 1e-8"):
        t, lo = fmu_walls["tangent", method], fmu_walls["loaded", method]
        print(f"{method:17} tangent {t:.3f} s  loaded {lo:.3f} s  ratio {lo / t:.2f}")


if __name__ == "__main__":
    main()
