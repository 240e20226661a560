"""Loaded TCA cost: time per position and per full mesh table (24 positions x 3
torques x 2 flanks) for the paper's four cases at the fast level.

Prints medians over repeats and ratios against a baseline measured in the same run:
the full table of the parallel helical reference pair (closed-form grids, same
torques and positions), so the ratios are comparable between machines.

    python benchmarks/bench_ltca.py            # 3 repeats
    python benchmarks/bench_ltca.py --repeats 1
    python benchmarks/bench_ltca.py --contact matching_depth   # the per-position solve

``--contact`` picks the fast level's contact term for the per-position solve
(``FastCompliance(contact=...)``); the full table runs the scene's default level.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _timed(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def main(argv=None):
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca import FastCompliance, solve_contact
    from gearbox.ltca.analysis import LTCAOptions
    from gearbox.ltca.beveloid import beveloid_grids, separation_field
    from gearbox.ltca.table import scene_ltca
    from gearbox.scene import load_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--contact", default="centre_line", choices=("centre_line", "matching_depth"))
    args = ap.parse_args(argv)
    opts = LTCAOptions(positions=24)

    ref = load_scene(ROOT / "tests" / "data" / "ltca_parallel_helical.toml").replaced(
        ltca={"grid_face": 40}
    )
    ref_design = design_pair(PairSpec.from_scene(ref))
    t_base, _ = _timed(lambda: scene_ltca(ref_design, ref, options=opts), args.repeats)
    print(f"baseline: parallel helical pair, full table (24 x 3 x 2): {t_base:.3f} s (median)")
    print()
    hdr = (
        f"{'case':6s}{'table s':>9s}{'ratio':>8s}{'field s':>9s}{'solve ms/pos':>14s}"
        f"{'k drive MN/m':>14s}{'pattern':>9s}"
    )
    print(hdr)
    print("-" * len(hdr))
    for case in ("01", "02", "03", "04"):
        scene = load_scene(ROOT / "models" / f"case{case}.toml")
        design = design_pair(PairSpec.from_scene(scene))
        lt = scene["ltca"]
        t_table, res = _timed(
            lambda s=scene, d=design: scene_ltca(d, s, options=opts), args.repeats
        )
        t_field, field = _timed(
            lambda s=scene, d=design, lt=lt: separation_field(
                d, s, "R", n_profile=lt["grid_profile"], n_face=lt["grid_face"], positions=24
            ),
            args.repeats,
        )
        grids, _ = beveloid_grids(design, scene, field, 24)
        fc = FastCompliance(contact=args.contact)
        per = []
        for g in grids:
            t = time.perf_counter()
            solve_contact(g, fc, 300.0)
            per.append(time.perf_counter() - t)
        d = res.summary()["flanks"]["drive"]["300"]
        print(
            f"{case:6s}{t_table:9.2f}{t_table / t_base:8.1f}{t_field:9.2f}"
            f"{1e3 * statistics.median(per):14.2f}"
            f"{d['mean_mesh_stiffness_N_per_m'] / 1e6:14.1f}"
            f"{100 * d['contact_pattern_area_fraction']:8.1f}%"
        )
    print()
    print("table s: full table, both flanks (field + grids + 3 solves per cell for the")
    print("tangent stiffness); field s: separation field of one flank; solve ms/pos: one")
    print("contact solve (compliance matrix + active set + Weber fixed point), median.")


if __name__ == "__main__":
    main()
