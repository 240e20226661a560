"""Cost of the spectrum functions against a bare FFT of the same record.

    python3 benchmarks/bench_spectrum.py [--repeats 7]

Prints the median wall time of each case and its ratio to the baseline measured in
the same run (numpy rfft of the record), so the numbers compare across machines.
Record: 7 revolutions (203 mesh cycles) of a 29-tooth pinion at 32 samples per
mesh cycle (the scene's default sampling), 6496 samples, as a drivetrain run
produces; the ramp cases use the same number of samples.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from gearbox.spectrum import (
    campbell,
    excitation_orders,
    order_spectrum,
    runup_waterfall,
)


def median_time(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()

    n1, spc, cycles = 29, 32, 29 * 7  # 7 whole revolutions
    spr = n1 * spc
    rev = np.arange(1, cycles * spc + 1) / spr
    n_rpm = 2000.0
    t = rev * 60.0 / n_rpm
    x = 3600 + 100 * np.cos(2 * np.pi * 29 * rev) + 25 * np.cos(2 * np.pi * 4 * rev)
    # A ramp 1500 -> 2500 rpm over the same number of samples.
    t_r = np.linspace(0.0, 0.25, x.size)
    speed_r = 1500.0 + 4000.0 * t_r
    rev_r = (1500.0 * t_r + 2000.0 * t_r**2) / 60.0
    x_r = np.cos(2 * np.pi * 29 * rev_r) + 0.2 * np.cos(2 * np.pi * 4 * rev_r)
    ex = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3)
    modes = {f"m{k}": (lambda n, k=k: 20.0 * k + 1e-3 * n) for k in range(1, 11)}

    cases = {
        "numpy rfft (baseline)": lambda: np.fft.rfft(x),
        "order_spectrum, plain FFT": lambda: order_spectrum(t, x, speed_rpm=n_rpm),
        "order_spectrum, resampled (const.)": lambda: order_spectrum(
            t * 1.0000001, x, speed_rpm=n_rpm
        ),
        "order_spectrum, tracked ramp": lambda: order_spectrum(t_r, x_r, speed_rpm=speed_r),
        "order_spectrum, flat top": lambda: order_spectrum(
            t_r, x_r, speed_rpm=speed_r, period_revs=None
        ),
        "runup_waterfall, order, 1-rev blocks": lambda: runup_waterfall(
            t_r, x_r, speed_rpm=speed_r, block=1.0
        ),
        f"campbell, {len(modes)} modes x {len(ex)} orders": lambda: campbell(
            modes, ex, (300.0, 3500.0), operating_range_rpm=(600.0, 3000.0)
        ),
    }
    print(f"record: {x.size} samples; median of {args.repeats} runs")
    print(f"| {'case':40s} | {'median (ms)':>11s} | {'ratio':>8s} |")
    print(f"|{'-' * 42}|{'-' * 13}|{'-' * 10}|")
    base = None
    for name, fn in cases.items():
        fn()  # warm-up (imports, caches)
        m = median_time(fn, args.repeats)
        base = base if base is not None else m
        print(f"| {name:40s} | {1e3 * m:11.3f} | {m / base:8.1f} |")


if __name__ == "__main__":
    main()
