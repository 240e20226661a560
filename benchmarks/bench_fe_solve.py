"""The FE level's solves on one thread against all of the machine's cores.

``ToothModel.solve`` shares the load columns of a block over threads that read one
SuperLU factorisation (its solve releases the GIL); ``GEARBOX_FE_THREADS=1`` keeps them
in the calling thread. Two measurements, each with one thread and with the cores in
the same run, medians of ``--repeats``:

- ``solves``: ``--columns`` lattice unit loads of paper case 03's pinion (default FE
  mesh, drive flank), one block;
- ``cycle``: an FE-level loaded TCA of a spur pair (z 20/40, m_n 4 mm, b 8 mm, default
  mesh, the segment alone), 8 positions x 2 torques: factorisations, lattice solves,
  contact and root stress.

The threaded results must equal the single thread's bit for bit (the same solves in
another order); the script says so or fails.

    python benchmarks/bench_fe_solve.py [--repeats 3] [--columns 64]
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.fe import FECompliance, FEOptions  # noqa: E402
from gearbox.fe.model import solve_threads  # noqa: E402
from gearbox.geometry import PairSpec, design_pair  # noqa: E402
from gearbox.ltca import LTCAOptions, ParallelPair, ltca_cycle, parallel_grid  # noqa: E402
from gearbox.ltca.beveloid import beveloid_grids, separation_field  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402
from gearbox.surface import blanks_from_design  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SPUR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=0.0,
    teeth=(20, 40),
    face_width=8e-3,
)


def _threads(n: int | None):
    if n is None:
        os.environ.pop("GEARBOX_FE_THREADS", None)
    else:
        os.environ["GEARBOX_FE_THREADS"] = str(n)


def _case03_pinion():
    scene = load_scene(ROOT / "models" / "case03.toml")
    design = design_pair(PairSpec.from_scene(scene))
    field = separation_field(design, scene, "R", n_profile=12, n_face=10, positions=4)
    grids, _ = beveloid_grids(design, scene, field, 4)
    fe = FECompliance(FEOptions(far_field="none"), blanks=blanks_from_design(design))
    fe.reserve(grids)
    loads = fe.loads(grids[0], 0)
    gm = fe._model(loads, 0, grids[0].youngs_modulus, grids[0].poisson_ratio)
    F = fe._lattice_unit_loads(gm, loads.side, int(np.unique(loads.tooth)[0]))
    return gm.model, F


def _cycle():
    fe = FECompliance(FEOptions(far_field="none"))
    res = ltca_cycle(
        lambda f: parallel_grid(SPUR, f, n_face=4),
        [150.0, 300.0],
        options=LTCAOptions(positions=8),
        compliance=fe,
    )
    return np.concatenate([res.stiffness.ravel(), res.root_stress_pinion.ravel()])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--columns", type=int, default=64)
    args = ap.parse_args(argv)
    cores = solve_threads()
    print(f"cores: {cores}; load average before: {os.getloadavg()[0]:.2f}")
    model, F = _case03_pinion()
    F = F[:, : args.columns].toarray()
    print(f"case 03 pinion: {model.free.size} free unknowns, factor nnz {model.factor_nnz}")
    rows = []
    for name, run in (("solves", lambda: model.solve(F)), ("cycle", _cycle)):
        times = {1: [], cores: []}
        out = {}
        for _ in range(args.repeats):
            for n in (1, cores):
                _threads(n)
                t0 = time.perf_counter()
                out[n] = run()
                times[n].append(time.perf_counter() - t0)
        _threads(None)
        if not np.array_equal(out[1], out[cores]):
            print(f"{name}: threaded result differs from one thread's", file=sys.stderr)
            return 1
        one, many = statistics.median(times[1]), statistics.median(times[cores])
        rows.append((name, one, many, many / one))
    print(f"\n| what | 1 thread (s) | {cores} threads (s) | ratio |")
    print("|---|---|---|---|")
    for name, one, many, ratio in rows:
        print(f"| {name} | {one:.2f} | {many:.2f} | {ratio:.2f} |")
    print("\nthreaded results equal the single thread's bit for bit")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
