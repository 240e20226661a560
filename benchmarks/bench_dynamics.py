"""Work-precision of the drivetrain solvers on the default scene (paper case 03).

Prints tables, not pass/fail:

1. work-precision: wall time against the relative error of the RMS and of the
   mesh-order amplitude of the mesh force, for scipy solve_ivp (LSODA, DOP853, Radau)
   and diffrax (Tsit5, Dopri8) at several tolerances, against a tight reference
   (scipy DOP853, rtol 1e-11) on the same record; the ratio of the fastest scipy
   setting reaching 1e-4 to the fastest diffrax setting reaching it;
2. one second of simulated time at 2000 rpm with the default solver (after compile);
3. a batched (vmap) sweep of N speeds with its time per speed.

Walls are medians of repeated runs (the machine is shared); ratios are measured in the
same run. Usage:

    python benchmarks/bench_dynamics.py            # full (several minutes on 2 cores)
    python benchmarks/bench_dynamics.py --quick    # shorter record, fewer settings
    python benchmarks/bench_dynamics.py --sweep-only --speeds 4096   # e.g. on a GPU
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from pathlib import Path

import numpy as np

from gearbox.drivetrain.diffrax_backend import DiffraxSolver
from gearbox.drivetrain.model import DrivetrainModel
from gearbox.drivetrain.scipy_backend import ScipySolver
from gearbox.drivetrain.simulate import mesh_force_metrics, simulate
from gearbox.drivetrain.sweep import speed_sweep
from gearbox.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def model_at(rpm: float | None = None) -> DrivetrainModel:
    return DrivetrainModel.from_scene(load_scene(ROOT / "models" / "case03.toml"), speed_rpm=rpm)


def timed(fn, repeats: int):
    walls, out = [], None
    for _ in range(repeats):
        out = fn()
        walls.append(out.wall_time)
    return statistics.median(walls), out


def work_precision(m, cycles: int, quick: bool) -> None:
    print(
        f"\n## 1. Work-precision: {cycles} mesh cycles ({cycles / m.mesh_frequency:.3f} s) at "
        f"{m.speed * 30 / math.pi:.0f} rpm, after 20 settling cycles"
    )
    t0 = time.perf_counter()
    ref = simulate(m, ScipySolver(method="DOP853", rtol=1e-11), mesh_cycles=cycles)
    print(
        f"reference scipy DOP853 rtol 1e-11: {time.perf_counter() - t0:.2f} s wall, "
        f"status {ref.status}, nfev {ref.nfev}"
    )
    r = mesh_force_metrics(ref, m)
    rows = []
    settings = [
        ("scipy", "DOP853", [1e-5, 1e-6, 1e-7, 1e-8]),
        ("scipy", "LSODA", [1e-5, 1e-6, 1e-7, 1e-8]),
        ("scipy", "Radau", [1e-5, 1e-6] if quick else [1e-5, 1e-6, 1e-7]),
        ("diffrax", "Tsit5", [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]),
        ("diffrax", "Dopri8", [1e-6, 1e-8, 1e-10]),
    ]
    for backend, method, rtols in settings:
        for rtol in rtols:
            if backend == "scipy":
                solver = ScipySolver(method=method, rtol=rtol)
                reps = 1
            else:
                solver = DiffraxSolver(solver=method, rtol=rtol)
                simulate(m, solver, mesh_cycles=cycles)  # compile
                reps = 5
            wall, ts = timed(lambda s=solver: simulate(m, s, mesh_cycles=cycles), reps)
            a = mesh_force_metrics(ts, m)
            e_rms = abs(a["mesh_force_rms_N"] / r["mesh_force_rms_N"] - 1)
            e_dyn = abs(a["mesh_force_dynamic_rms_N"] / r["mesh_force_dynamic_rms_N"] - 1)
            e_amp = abs(
                a["mesh_force_mesh_order_amplitude_N"] / r["mesh_force_mesh_order_amplitude_N"] - 1
            )
            rows.append((backend, method, rtol, wall, e_rms, e_dyn, e_amp, ts.nfev, ts.status))
    print(
        "| solver | method | rtol | wall (s, median) | err RMS | err dynamic RMS | err mesh-order amp | nfev | status |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for b, mth, rtol, wall, e1, e2, e3, nfev, st in rows:
        print(
            f"| {b} | {mth} | {rtol:.0e} | {wall:.4f} | {e1:.1e} | {e2:.1e} | {e3:.1e} | {nfev} | {st} |"
        )

    def best(backend):
        ok = [
            w
            for b, _, _, w, e1, e2, e3, _, st in rows
            if b == backend and st == "success" and max(e1, e3) <= 1e-4
        ]
        return min(ok) if ok else math.nan

    bs, bd = best("scipy"), best("diffrax")
    print(
        f"\nfastest to 1e-4 (RMS and mesh-order amplitude): scipy {bs:.4f} s, diffrax {bd:.4f} s, "
        f"ratio {bs / bd:.1f}x"
    )


def one_second(m) -> None:
    print(
        "\n## 2. One second of simulated time at 2000 rpm, default solver (diffrax Tsit5 rtol 1e-6)"
    )
    cycles = int(round(1.0 * m.mesh_frequency))
    solver = DiffraxSolver()
    first = simulate(m, solver, mesh_cycles=cycles, settle_time=0.0)
    walls = [simulate(m, solver, mesh_cycles=cycles, settle_time=0.0).wall_time for _ in range(5)]
    print(
        f"compile {first.attrs['compile_time_s']:.2f} s; run median {statistics.median(walls):.4f} s "
        f"(min {min(walls):.4f}, max {max(walls):.4f}) over 5; steps {first.steps}, status {first.status}"
    )


def sweep(n_speeds: int, cycles: int) -> None:
    import jax

    print(
        f"\n## 3. Batched sweep: {n_speeds} speeds 500-3000 rpm, {cycles} mesh cycles each, "
        f"device {jax.devices()[0].platform}"
    )
    rpms = np.linspace(500.0, 3000.0, n_speeds)
    base = model_at()
    t0 = time.perf_counter()
    sw = speed_sweep(base, rpms, DiffraxSolver(), settle_cycles=0, mesh_cycles=cycles, batch="vmap")
    total = time.perf_counter() - t0
    wall = sw.wall_time
    ok = sum(st == "success" for st in sw.status)
    print(
        f"compile {sw.compile_time:.2f} s; batch run {wall:.3f} s = {1e3 * wall / n_speeds:.2f} ms "
        f"per speed; total incl. setup {total:.2f} s; {ok}/{n_speeds} succeeded"
    )
    t0 = time.perf_counter()
    sl = speed_sweep(base, rpms, DiffraxSolver(), settle_cycles=0, mesh_cycles=cycles, batch="loop")
    total = time.perf_counter() - t0
    print(
        f"loop of compiled single runs: {sl.wall_time:.3f} s = {1e3 * sl.time_per_speed:.2f} ms per "
        f"speed (integration); total incl. setup and compile {total:.2f} s"
    )
    ms = [base.with_speed(r * math.pi / 30) for r in rpms]
    # single-speed baseline measured in the same run (the first call compiles)
    for _ in range(2):
        one = simulate(
            ms[n_speeds // 2],
            DiffraxSolver(),
            mesh_cycles=cycles,
            settle_time=0.0,
            samples_per_cycle=16,
        )
    print(
        f"one speed alone: {one.wall_time:.4f} s; batched/single time per speed ratio "
        f"{(wall / n_speeds) / one.wall_time:.4f}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sweep-only", action="store_true")
    ap.add_argument("--speeds", type=int, default=200)
    ap.add_argument("--sweep-cycles", type=int, default=100)
    a = ap.parse_args()
    m = model_at()
    if not a.sweep_only:
        work_precision(m, 50 if a.quick else 200, a.quick)
        one_second(m)
    sweep(a.speeds, a.sweep_cycles)


if __name__ == "__main__":
    main()
