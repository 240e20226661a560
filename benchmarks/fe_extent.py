"""How the FE level's mesh stiffness depends on the extent of the modelled segment.

The FE level models the loaded teeth, ``neighbours`` unloaded teeth on each side and
their rim; the bore is clamped and the segment's two radial cut faces are either
clamped (too stiff: the cut faces hold the rim) or free (too soft). Both converge to
the full gear's value as the segment grows; this script runs both sequences for one
case and flank on a coarse mesh and extrapolates each geometrically (Aitken's delta^2
on the last three values), so that the two estimates bracket and check each other.

    python benchmarks/fe_extent.py --case 03 --flank R            # prints a table
    python benchmarks/fe_extent.py --case 03 --flank R --jsonl out.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_fe import run_case  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gearbox.fe.extent import extent_limit  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="03")
    ap.add_argument("--flank", default="R", choices=("R", "L"))
    ap.add_argument("--positions", type=int, default=8)
    ap.add_argument("--refine", type=float, default=0.5)
    ap.add_argument("--clamped", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    ap.add_argument("--free", type=int, nargs="+", default=[3, 4, 5])
    ap.add_argument("--jsonl", type=Path, help="append one JSON line per run")
    a = ap.parse_args(argv)
    out = {"clamped": [], "free": []}
    for bc in ("clamped", "free"):
        for nb in getattr(a, bc):
            r = run_case(a.case, a.flank, a.positions, a.refine, nb, bc, far_field="none")
            k = np.asarray(r["k_fe"], dtype=float)
            out[bc].append(k)
            line = {
                "case": a.case,
                "flank": a.flank,
                "refine": a.refine,
                "positions": a.positions,
                "cut_faces": bc,
                "neighbours": nb,
                "torques": r["torques"],
                "k_fe": k.tolist(),
                "dofs": r["dofs"],
                "t_fe": r["t_fe"],
            }
            print(json.dumps(line), flush=True)
            if a.jsonl is not None:
                with a.jsonl.open("a") as fh:
                    fh.write(json.dumps(line) + "\n")
    if len(out["clamped"]) >= 3 and len(out["free"]) >= 3:
        lim, err = extent_limit(np.array(out["clamped"]), np.array(out["free"]))
        print(
            f"whole gear: {np.round(lim / 1e6, 1)} +- {np.round(err / 1e6, 1)} N/um; "
            f"over the first clamped segment: {np.round(lim / out['clamped'][0], 3)}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
