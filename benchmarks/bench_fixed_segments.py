"""The fixed-step runs in segments of one compiled program against one scan per run.

    python3 benchmarks/bench_fixed_segments.py [--scene models/marine_drive.toml]
        [--speeds 3500 1000] [--repeats 5]

For each speed (engine power scaled on the propeller law, as the waterfall does) the
default scene's settled record (20 settling and 900 recorded mesh cycles, 32 samples
each) is integrated twice with the default fixed-step Tsit5:

- baseline: one ``jax.lax.scan`` over the whole step plan, padded to its length bucket
  (``fixed_step.bucket``), compiled per bucket (the backend's path before the segments);
- segments: ``diffrax_backend._integrate_fixed``, the chunked program in segments of
  ``SEGMENT`` steps, one compilation for every length.

Prints per speed the steps, compile time of each (the first call in this process) and
the median integration wall time, their ratio, and the largest difference of the
states (0: the same steps, the same numbers). Compile times are per process: the
second speed's segments reuse the first's program.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None) -> None:
    import jax

    from gearbox.drivetrain import diffrax_backend as db
    from gearbox.drivetrain.diffrax_backend import DiffraxSolver, _fixed_plan
    from gearbox.drivetrain.fixed_step import bucket, excitation_terms, fixed_solve_fn
    from gearbox.drivetrain.linear import periodic_start_state
    from gearbox.drivetrain.model import DrivetrainModel
    from gearbox.drivetrain.simulate import record_times
    from gearbox.scene import load_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "models" / "marine_drive.toml"))
    ap.add_argument("--speeds", type=float, nargs="+", default=[3500.0, 1000.0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)

    scene = load_scene(args.scene)
    rated = scene["drivetrain"]["engine_speed_rpm"]
    power = scene["drivetrain"]["engine_power_kW"]
    solver = DiffraxSolver()
    print(f"scene {args.scene}; segment {db.SEGMENT} steps; medians of {args.repeats} runs (s)")
    head = "speed rpm   steps   compile one scan / segments   run one scan / segments   ratio   max |diff|"
    print(head)
    print("-" * len(head))
    for rpm in args.speeds:
        sc = scene.replaced(drivetrain={"engine_power_kW": power * (rpm / rated) ** 3})
        m = DrivetrainModel.from_scene(sc, speed_rpm=rpm)
        p = m.params()
        y0 = periodic_start_state(m)
        ts = np.concatenate([[0.0], record_times(m, 20 / m.mesh_frequency, 900, 32)])
        plan, _ = _fixed_plan(m, ts, solver)
        steps = plan.n_steps
        padded = plan.padded(bucket(steps))
        fn = fixed_solve_fn(solver.solver, solver.table_cells, terms=excitation_terms(p))
        params = {k: np.asarray(v) for k, v in p.items()}
        one = (params, y0 / p["scale"], padded.t, padded.h, padded.out)
        t0 = time.perf_counter()
        compiled = fn.lower(*one).compile()
        c_one = time.perf_counter() - t0
        walls, zs = [], None
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            zs, _ = jax.block_until_ready(compiled(*one))
            walls.append(time.perf_counter() - t0)
        w_one = statistics.median(walls)
        Y_one = np.asarray(zs) * p["scale"]
        _, Y, info = db._integrate_fixed(m, y0, ts[1:], solver)
        c_seg, walls = info["compile_time"], [info["wall_time"]]
        for _ in range(args.repeats - 1):
            walls.append(db._integrate_fixed(m, y0, ts[1:], solver)[2]["wall_time"])
        w_seg = statistics.median(walls)
        diff = float(np.max(np.abs(Y - Y_one)))
        print(
            f"{rpm:9.0f} {steps:7d}   {c_one:8.2f} / {c_seg:8.2f}"
            f"              {w_one:7.3f} / {w_seg:7.3f}        {w_seg / w_one:5.2f}   {diff:.3g}"
        )
    print("(the segments' compile time of the first speed includes its first call only;")
    print(" a later speed finds the program compiled: one compilation for all lengths)")


if __name__ == "__main__":
    main()
