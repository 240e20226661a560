"""Edge points on the flank borders: the loaded TCA against the profile grid, with the
edge points on their last profile sample (the default) and on the border itself
(``ltca.edge_borders = true``).

    python3 benchmarks/ltca_edge_borders.py [--samples 20 40 80 160] [--torque 300]
        [--scene models/case03.toml] [--fidelity fast|fe] [--flanks drive coast]
        [--edge-points sample border] [--parallel] [--json out.json]

For each number of profile points (``ltca.grid_profile``) and both settings, prints per
flank the mean mesh stiffness, the loaded TE peak-to-peak, the largest contact pressure
and the largest share of the load on edge points over one mesh cycle (24 positions,
the scene's face grid, one torque). A result that needs no finer grid is the same in
every row. ``--parallel`` adds the parallel helical pair of
``tests/data/ltca_parallel_helical.toml`` (12 positions, 20 face points, drive flank),
whose surface path is compared with the closed form of the plane of action (which has
no contact beyond the path of contact: no edge points). ``--json`` writes the rows
(tests/data/fe_edge_borders_paper_cases.json holds the FE level's on the borders).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _row(res) -> str:
    return (
        f"{res.stiffness[0].mean() / 1e6:8.1f} {np.ptp(res.lte[0]) * 1e6:8.3f} "
        f"{res.max_pressure[0].max() / 1e6:7.1f} {100 * res.edge_load_fraction[0].max():6.1f}"
    )


def main(argv=None):
    from gearbox import load_scene
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import beveloid_ltca
    from gearbox.ltca.table import scene_ltca

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "models" / "case03.toml"))
    ap.add_argument("--samples", type=int, nargs="+", default=[20, 40, 80, 160])
    ap.add_argument("--torque", type=float, default=300.0, help="pinion torque (N m)")
    ap.add_argument("--fidelity", choices=("fast", "fe"), default="fast")
    ap.add_argument("--flanks", nargs="+", choices=("drive", "coast"), default=["drive", "coast"])
    ap.add_argument(
        "--edge-points", nargs="+", choices=("sample", "border"), default=["sample", "border"]
    )
    ap.add_argument("--parallel", action="store_true")
    ap.add_argument("--json", type=Path, help="write the rows here")
    args = ap.parse_args(argv)
    rows = []

    scene = load_scene(args.scene).replaced(load={"torques_Nm": [args.torque]})
    design = design_pair(PairSpec.from_scene(scene))
    head = f"{'points':>6} {'edge points':<12} {'flank':<6} {'k MN/m':>8} {'LTE pp um':>9}"
    print(f"{args.scene}, {args.torque:g} N m, 24 positions, {args.fidelity} level")
    print(head + f" {'p_max MPa':>9} {'edge %':>6} {'s':>5}")
    for n in args.samples:
        for where in args.edge_points:
            lt = {"grid_profile": n, "edge_borders": where == "border", "fidelity": args.fidelity}
            s = scene.replaced(ltca=lt | {"flanks": args.flanks})
            t0 = time.perf_counter()
            res = beveloid_ltca(design, s)
            dt = time.perf_counter() - t0
            for flank, r in res.flanks.items():
                print(f"{n:>6} {where:<12} {flank:<6} {_row(r)} {dt:5.1f}")
                rows.append(
                    {
                        "scene": Path(args.scene).name,
                        "fidelity": args.fidelity,
                        "edge_points": where,
                        "grid_profile": n,
                        "flank": flank,
                        "torque_Nm": args.torque,
                        "mean_stiffness_N_per_m": float(r.stiffness[0].mean()),
                        "lte_peak_to_peak_m": float(np.ptp(r.lte[0])),
                        "max_pressure_Pa": float(r.max_pressure[0].max()),
                        "seconds": dt,
                    }
                )
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    if not args.parallel:
        return
    par = load_scene(ROOT / "tests" / "data" / "ltca_parallel_helical.toml")
    print("\nparallel helical pair, drive, surface path / closed form - 1")
    print(f"{'points':>6} {'edge points':<12} {'k mean':>8} {'LTE mean':>9} {'LTE pp um':>9}")
    for n in args.samples:
        for on in (False, True):
            lt = dict(positions=12, grid_profile=n, grid_face=20, flanks=["drive"])
            s = par.replaced(ltca=lt | {"edge_borders": on}, load={"torques_Nm": [args.torque]})
            d = design_pair(PairSpec.from_scene(s))
            b = beveloid_ltca(d, s).flanks["drive"]
            c = scene_ltca(d, s).flanks["drive"]
            k = b.stiffness[0].mean() / c.stiffness[0].mean() - 1
            e = b.lte[0].mean() / c.lte[0].mean() - 1
            pp = f"{np.ptp(b.lte[0]) * 1e6:.3f} / {np.ptp(c.lte[0]) * 1e6:.3f}"
            where = "border" if on else "last sample"
            print(f"{n:>6} {where:<12} {100 * k:+7.2f}% {100 * e:+8.2f}% {pp:>9}")


if __name__ == "__main__":
    main()
