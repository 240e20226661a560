"""Face load factor K_Hbeta of a misaligned spur pair: fast level, independent slices,
ISO 6336-1's elastic-foundation formula and (``--fe``) the whole-gear FE level.

    python3 benchmarks/ltca_misalignment.py [--misalignment-um 10 20] [--fe]
        [--refine 1.0] [--json out.json]

The pair: spur, m 4 mm, z 30/45, alpha 20 deg, b 30 mm (the one of
tests/test_ltca_modifications.py), normal load 6 kN, at two positions of the single-pair
zone (0.8 and 0.9 of a mesh cycle), 40 face slices. The misalignment F_by (um) is the
gap it opens across the face along the line of action; the gear axis is tilted about
the centre line by ``F_by / (b cos alpha_wt)`` (``ParallelPair.misalignment``).
K_Hbeta = largest line load over the mean line load F / b. ISO's formula (method C,
eq. for K_Hbeta with F_by): 1 + F_by c b / (2 F) up to 2, else sqrt(2 F_by c b / F),
with c the aligned pair's stiffness per unit face width of the level in question.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gearbox.ltca import FastCompliance, ParallelPair  # noqa: E402
from gearbox.ltca.compliance import CALIBRATED_BEAM  # noqa: E402
from gearbox.ltca.parallel import parallel_grid  # noqa: E402
from gearbox.ltca.solver import solve_contact  # noqa: E402

SPUR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20.0),
    helix_angle=0.0,
    teeth=(30, 45),
    face_width=30e-3,
)
LOAD_N = 6000.0
POSITIONS = (0.8, 0.9)
N_FACE = 40


def iso_k_hbeta(f_by: float, c: float, b: float, force: float) -> float:
    """ISO 6336-1 method C's K_Hbeta for a misalignment f_by (m), stiffness per unit
    face width c (N/m per m), face width b (m) and normal load ``force`` (N)."""
    x = f_by * c * b / (2.0 * force)
    return 1.0 + x if x <= 1.0 else math.sqrt(4.0 * x)


def k_hbeta(compliance, f_um: float) -> dict:
    """Per position: K_Hbeta, the approach (m) and c (N/m per m) of the aligned pair."""
    b = SPUR.face_width
    g = f_um * 1e-6 / (b * math.cos(SPUR.working_pressure_angle))
    bent = dataclasses.replace(SPUR, misalignment=g)
    rows = []
    for frac in POSITIONS:
        flat = parallel_grid(SPUR, frac, N_FACE)
        arm = float(flat.arm[0])
        aligned = solve_contact(flat, compliance, LOAD_N * arm)
        grid = parallel_grid(bent, frac, N_FACE)
        sol = solve_contact(grid, compliance, LOAD_N * arm)
        q = sol.load / grid.width
        c = LOAD_N / b / (aligned.rotation * arm)
        rows.append(
            {
                "position": frac,
                "k_hbeta": float(q.max() / (LOAD_N / b)),
                "k_hbeta_aligned": float((aligned.load / flat.width).max() / (LOAD_N / b)),
                "c_N_per_m2": float(c),
                "iso_k_hbeta": iso_k_hbeta(f_um * 1e-6, c, b, LOAD_N),
            }
        )
    return {"misalignment_um": f_um, "rows": rows}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--misalignment-um", type=float, nargs="+", default=[10.0, 20.0])
    ap.add_argument("--fe", action="store_true", help="also the whole-gear FE level (minutes)")
    ap.add_argument("--refine", type=float, default=1.0, help="FE mesh refinement factor")
    ap.add_argument("--json", metavar="FILE")
    args = ap.parse_args()
    levels = {
        "fast (default)": FastCompliance(),
        "calibrated beam": CALIBRATED_BEAM,
        # the elastic foundation ISO's formula assumes: nothing shared, no coupling
        "independent slices": FastCompliance(
            coupling_length=0.0, body_compliance=0.0, shared_torsion=False, foundation="normal"
        ),
    }
    if args.fe:
        from gearbox.fe import FECompliance, FEOptions, MeshOptions

        levels["FE (whole gear)"] = FECompliance(FEOptions(mesh=MeshOptions().refined(args.refine)))
    out = {
        "command": "python3 benchmarks/ltca_misalignment.py " + " ".join(sys.argv[1:]),
        "pair": SPUR.to_dict(),
        "load_N": LOAD_N,
        "levels": {},
    }
    print(
        f"spur z {SPUR.teeth[0]}/{SPUR.teeth[1]}, m 4 mm, b 30 mm, {LOAD_N:g} N, positions "
        f"{POSITIONS} (single-pair zone); K_Hbeta = max / mean line load"
    )
    head = f"{'level':<22} {'F_by (um)':>9} {'K_Hbeta':>8} {'ISO, own c':>10} {'c (N/(mm um))':>13} {'time (s)':>8}"
    print(head)
    print("-" * len(head))
    for name, comp in levels.items():
        res = []
        for f in args.misalignment_um:
            t0 = time.perf_counter()
            r = k_hbeta(comp, f)
            dt = time.perf_counter() - t0
            res.append(r)
            k = np.mean([row["k_hbeta"] for row in r["rows"]])
            iso = np.mean([row["iso_k_hbeta"] for row in r["rows"]])
            c = np.mean([row["c_N_per_m2"] for row in r["rows"]])
            print(f"{name:<22} {f:9.1f} {k:8.3f} {iso:10.3f} {c / 1e9:13.2f} {dt:8.1f}")
        out["levels"][name] = res
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
