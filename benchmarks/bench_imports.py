"""What importing the modules of a ``gearbox run`` costs, each in a new process.

    python3 benchmarks/bench_imports.py [--repeats 7]

Every process that simulates, draws or reads a stage back from the cache pays its
imports before it does anything; a second run of a scene with only the propeller
changed (``benchmarks/bench_pipeline.py``) spends a large share of its time there.
For each module the script starts ``python -c "import numpy; <timer>; import M"``
``--repeats`` times and prints the median seconds of the import alone (numpy, which
everything here needs first, is outside the timer), with the installed version of
the module's distribution, and the median of a bare interpreter start as the
baseline the ratios are taken against.

``ml_dtypes`` is listed on its own: jax imports it, and its 0.7.0 release took 0.43 s
to import beside numpy 2.4 (0.6.0: 5 ms; measured with this script's method), which is
why the ``dynamics`` extra asks for ``ml_dtypes<0.7``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from importlib import metadata

#: module -> distribution whose version is printed beside it
MODULES = {
    "ml_dtypes": "ml_dtypes",
    "jax": "jax",
    "scipy.linalg": "scipy",
    "scipy.interpolate": "scipy",
    "scipy.optimize": "scipy",
    "matplotlib.figure": "matplotlib",
    "xarray": "xarray",
    "exudyn": "exudyn",
    "gearbox.pipeline": "gearbox",
}

TIMED = "import time, numpy; t = time.perf_counter(); import {m}; print(time.perf_counter() - t)"


def timed_import(module: str, repeats: int) -> list[float]:
    out = []
    for _ in range(repeats):
        proc = subprocess.run(
            [sys.executable, "-c", TIMED.format(m=module)], capture_output=True, text=True
        )
        if proc.returncode != 0:
            raise SystemExit(f"import {module} failed:\n{proc.stderr[-2000:]}")
        out.append(float(proc.stdout.split()[-1]))
    return out


def interpreter_start(repeats: int) -> list[float]:
    import time

    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], check=True)
        out.append(time.perf_counter() - t0)
    return out


def version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    if args.repeats < 1:
        raise SystemExit(f"--repeats = {args.repeats}: must be >= 1")
    base = statistics.median(interpreter_start(args.repeats))
    print(f"interpreter start (python -c pass): {base:.3f} s, median of {args.repeats}\n")
    head = f"{'module':<20} {'version':<14} {'import (s)':>10} {'/ start':>8}"
    print(head)
    print("-" * len(head))
    for module, dist in MODULES.items():
        v = version(dist)
        if v == "not installed":
            print(f"{module:<20} {v:<14}")
            continue
        t = statistics.median(timed_import(module, args.repeats))
        print(f"{module:<20} {v:<14} {t:10.3f} {t / base:8.2f}")


if __name__ == "__main__":
    main()
