"""Benchmark: one pair design and a 10,000-point design sweep.

Prints medians over repeats and the ratio of the batched sweep against the same
designs solved one at a time (the baseline, measured in the same run).

    python3 benchmarks/bench_design.py
"""

from __future__ import annotations

import math
import statistics
import time
from pathlib import Path

import numpy as np

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair, solve_pair_arrays

SCENE = Path(__file__).parents[1] / "models" / "case03.toml"


def timed(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    spec = PairSpec.from_scene(load_scene(SCENE))
    n = 10_000
    # 100 pinion cone angles x 100 shaft angles, the rest of case 03
    g1 = np.linspace(0.0, math.radians(5.0), 100)[None, :]
    delta = np.linspace(math.radians(9.0), math.radians(17.0), 100)[:, None]

    def batched():
        return solve_pair_arrays(
            spec.normal_module,
            spec.normal_pressure_angle,
            delta,
            spec.offset,
            spec.pinion.teeth,
            spec.gear.teeth,
            spec.pinion.helix_angle,
            g1,
            spec.gear.cone_angle,
        )

    flat_g1 = np.broadcast_to(g1, (100, 100)).ravel()
    flat_d = np.broadcast_to(delta, (100, 100)).ravel()
    n_loop = 500  # the scalar loop is timed on a subset and scaled to n

    def looped():
        for i in range(n_loop):
            solve_pair_arrays(
                spec.normal_module,
                spec.normal_pressure_angle,
                flat_d[i],
                spec.offset,
                spec.pinion.teeth,
                spec.gear.teeth,
                spec.pinion.helix_angle,
                flat_g1[i],
                spec.gear.cone_angle,
            )

    t_one = timed(lambda: design_pair(spec), 50)
    t_one_nochk = timed(lambda: design_pair(spec, with_checks=False), 50)
    t_batch = timed(batched, 7)
    t_loop = timed(looped, 3) * n / n_loop
    ok = int(batched()["ok"].sum())
    print(f"{'case':46}{'median':>12}{'per design':>14}")
    print(f"{'design_pair (case 03, with checks)':46}{t_one * 1e3:10.2f} ms{t_one * 1e6:11.0f} us")
    print(
        f"{'design_pair (case 03, no checks)':46}{t_one_nochk * 1e3:10.2f} ms{t_one_nochk * 1e6:11.0f} us"
    )
    print(
        f"{f'sweep {n} designs, batched ({ok} solved)':46}{t_batch * 1e3:10.2f} ms{t_batch / n * 1e6:11.2f} us"
    )
    print(
        f"{f'sweep {n} designs, scalar loop (baseline)':46}{t_loop * 1e3:10.2f} ms{t_loop / n * 1e6:11.2f} us"
    )
    print(f"\nbatched / loop speed-up: {t_loop / t_batch:.0f}x")


if __name__ == "__main__":
    main()
