"""Load along the contact lines: the fast level against the FE level, position by position.

Both levels solve the same contact grids (a paper case's scene grids, one flank, one
torque) at a few positions; printed per position and tooth pair: the load share, the
loaded slices and the line load along the line (N/mm), and per level the pinion's
rotation (the loaded TE over the base radius), the largest line load and the largest
Hertz pressure. Where the two levels' contact zones differ (its length, its peak), the
fast level's compliance splits differently between each slice and the face-wise
coupling; the rotation tells the overall stiffness.

    python benchmarks/ltca_load_distribution.py                        # runs the FE level
    python benchmarks/ltca_load_distribution.py --json tests/data/fe_load_distribution_case03.json
    python benchmarks/ltca_load_distribution.py --stored tests/data/fe_load_distribution_case03.json
    python benchmarks/ltca_load_distribution.py --stored FILE --coupling-length 1.0

The FE level (default mesh, far field included) takes about 2.5 minutes for its
influence coefficients on case 03 and 3-4 GB; ``--stored`` reads its loads from an
earlier ``--json`` run and solves the fast level only (seconds). ``--coupling-length``,
``--body`` and ``--contact`` change the fast level's (``FastCompliance``) for
experiments.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.ltca import FastCompliance, solve_contact  # noqa: E402
from gearbox.ltca.slice_model import hertz_pressure  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltca_ripple import case_grids  # noqa: E402


def zone(grid, load) -> dict:
    """Per tooth pair (sorted along the face): share of the load, loaded slices, line
    loads (N/m); and the largest line load and Hertz pressure of the position."""
    q = load / grid.line_length
    p = hertz_pressure(q, grid.curvature_radius, grid.youngs_modulus, grid.poisson_ratio)
    pairs = {}
    for k in grid.pairs():
        on = np.flatnonzero(grid.pair == k)
        on = on[np.argsort(grid.slot[on])]
        pairs[int(k)] = {
            "share": float(load[on].sum() / load.sum()),
            "loaded": int(np.sum(load[on] > 0)),
            "line_load_N_per_m": q[on].tolist(),
        }
    return {
        "pairs": pairs,
        "max_line_load_N_per_m": float(q.max()),
        "max_pressure_Pa": float(p.max()),
    }


def compare(grid, fe: dict, fast, torque: float) -> dict:
    """The fast level's solution at ``grid`` beside the FE's stored one."""
    sol = solve_contact(grid, fast, torque)
    out = zone(grid, sol.load) | {"rotation_rad": float(sol.rotation)}
    print(
        f"  rotation FE {fe['rotation_rad']:.4e} fast {out['rotation_rad']:.4e} "
        f"({out['rotation_rad'] / fe['rotation_rad'] - 1:+.1%}); largest line load FE "
        f"{fe['max_line_load_N_per_m'] / 1e3:.1f} fast {out['max_line_load_N_per_m'] / 1e3:.1f} "
        f"N/mm; largest pressure FE {fe['max_pressure_Pa'] / 1e6:.0f} fast "
        f"{out['max_pressure_Pa'] / 1e6:.0f} MPa"
    )
    for k, row in fe["pairs"].items():
        mine = out["pairs"][int(k)]
        for name, r in (("FE", row), ("fast", mine)):
            q = np.round(np.asarray(r["line_load_N_per_m"]) / 1e3).astype(int)
            print(
                f"    pair {int(k):+d} {name:>4}: share {r['share']:.3f}, {r['loaded']:2d} slices "
                f"loaded, q (N/mm) {' '.join(str(v) for v in q)}"
            )
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="03")
    ap.add_argument("--flank", default="drive", choices=("drive", "coast"))
    ap.add_argument("--torque", type=float, default=300.0, help="pinion torque (N m)")
    ap.add_argument("--positions", type=int, nargs="+", default=[8, 21], help="of 24")
    ap.add_argument("--json", type=Path, help="store the FE level's solutions here")
    ap.add_argument("--stored", type=Path, help="FE solutions of an earlier --json run")
    ap.add_argument("--coupling-length", type=float, help="the fast level's (tooth depths)")
    ap.add_argument("--body", type=float, help="the fast level's body coefficient")
    ap.add_argument(
        "--contact",
        choices=("centre_line", "matching_depth"),
        help="the fast level's contact reference (with the plane-strain tooth read there)",
    )
    a = ap.parse_args(argv)
    opts = {}
    if a.coupling_length is not None:
        opts["coupling_length"] = a.coupling_length
    if a.body is not None:
        opts["body_compliance"] = a.body
    if a.contact is not None:
        opts["contact"] = a.contact
    fast = FastCompliance(**opts)
    if a.stored is not None:
        stored = json.loads(a.stored.read_text())
        case, flank, torque = stored["case"], stored["flank"], stored["torque_Nm"]
        positions = [int(p) for p in stored["positions"]]
    else:
        stored = None
        case, flank, torque, positions = a.case, a.flank, a.torque, a.positions
    _, design, grids = case_grids(case, flank)
    print(f"case {case}, {flank} flank, {torque:g} N m; fast level: {fast.describe()}")
    out = {
        "command": "python benchmarks/ltca_load_distribution.py " + " ".join(argv or sys.argv[1:]),
        "case": case,
        "flank": flank,
        "torque_Nm": torque,
        "positions": positions,
        "fe": {},
    }
    fe_level = None
    if stored is None:
        from gearbox.fe.compliance import FECompliance
        from gearbox.surface import blanks_from_design

        fe_level = FECompliance(blanks=blanks_from_design(design))
    for p in positions:
        g = grids[p]
        if stored is not None:
            fe = stored["fe"][str(p)]
        else:
            t0 = time.perf_counter()
            sol = solve_contact(g, fe_level, torque)
            fe = zone(g, sol.load) | {
                "rotation_rad": float(sol.rotation),
                "seconds": time.perf_counter() - t0,
            }
        out["fe"][str(p)] = fe
        print(f"position {p} of 24")
        compare(g, fe, fast, torque)
    if a.json is not None:
        a.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
