"""Effect of flank modifications on a scene's loaded TCA (one flank, one torque).

    python3 benchmarks/ltca_modifications.py [--scene models/case03.toml]
        [--torque 300] [--flank drive] [--positions 24]

Runs the scene's loaded TCA (fast level) once without modifications and once per row
of ``VARIANTS`` (scene keys of ``[ltca]``, um and mm), and prints per variant the mean
and peak-to-peak mesh stiffness, the mean and peak-to-peak loaded TE, the contact
pattern, the peak amplitudes of the loaded TE's first two mesh-order harmonics, the
largest contact pressure and the largest share of the load on edge points, with the
run time. Every variant is an ordinary scene: the same numbers come
out of ``gearbox ltca`` with those keys set.

``--fe`` also runs the whole-gear FE level (its defaults) on the same contact grids for
the variants of ``FE_VARIANTS`` and prints both levels side by side (mean stiffness, LTE
peak-to-peak, largest contact pressure and the variant's change of each against the
unmodified pair); ``--json FILE`` stores those rows (tests/data/fe_modifications_case03.json
was made with ``--fe --positions 8 --json ...``). The FE runs take minutes.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

FE_GRIDS = {"edge_borders": False}  # the stored FE runs' grids (see bench_fe.py)

#: label -> [ltca] keys; "both" rows set the pinion and the gear alike.
VARIANTS = {
    "unmodified (the paper's flanks)": {},
    "tip relief 8 um / 1.2 mm, both, linear": {
        f"{g}_tip_relief_{k}": v
        for g in ("pinion", "gear")
        for k, v in (("um", 8.0), ("length_mm", 1.2))
    },
    "lead crowning 10 um, pinion": {"pinion_lead_crowning_um": 10.0},
    "lead crowning 5 um, both": {"pinion_lead_crowning_um": 5.0, "gear_lead_crowning_um": 5.0},
    "profile crowning 4 um, both": {
        "pinion_profile_crowning_um": 4.0,
        "gear_profile_crowning_um": 4.0,
    },
    "end relief 10 um / 6 mm, pinion": {
        "pinion_end_relief_um": 10.0,
        "pinion_end_relief_length_mm": 6.0,
    },
    "helix slope +10 um, pinion": {"pinion_helix_slope_um": 10.0},
    "helix slope -10 um, pinion": {"pinion_helix_slope_um": -10.0},
    "profile slope +6 um, pinion": {"pinion_profile_slope_um": 6.0},
    "profile slope -6 um, pinion": {"pinion_profile_slope_um": -6.0},
    "flank twist 10 um, pinion": {"pinion_flank_twist_um": 10.0},
    # the lead crowning of 10 um as a topography (bicubic: exact for it) on a 5 x 9
    # grid over the 40 mm face of the paper's cases: the same row as the crowning's
    "topography = lead crowning 10 um, pinion": {
        "pinion_topography_profile_mm": [-20.0, -10.0, 0.0, 10.0, 20.0],
        "pinion_topography_face_mm": [-20.0 + 5.0 * i for i in range(9)],
        "pinion_topography_um": [[10.0 * ((-20.0 + 5.0 * i) / 20.0) ** 2 for i in range(9)]] * 5,
    },
    "tip relief + lead crowning 5 um, both": {
        **{
            f"{g}_tip_relief_{k}": v
            for g in ("pinion", "gear")
            for k, v in (("um", 8.0), ("length_mm", 1.2))
        },
        "pinion_lead_crowning_um": 5.0,
        "gear_lead_crowning_um": 5.0,
    },
}


#: Variants the ``--fe`` comparison runs (the FE level costs minutes per variant).
FE_VARIANTS = (
    "unmodified (the paper's flanks)",
    "lead crowning 10 um, pinion",
    "helix slope +10 um, pinion",
    "profile crowning 4 um, both",
    "profile slope +6 um, pinion",
    "flank twist 10 um, pinion",
)


def fe_rows(base, flank: str, torque: float, positions: int) -> dict:
    """Fast and FE level on the same grids per variant of FE_VARIANTS: mean stiffness
    (N/m), LTE peak-to-peak (m), largest contact pressure (Pa)."""
    from gearbox.fe import FECompliance
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca import LTCAOptions, ltca_cycle
    from gearbox.ltca.beveloid import scene_grids
    from gearbox.surface import blanks_from_design

    side = {"drive": "R", "coast": "L"}[flank]
    design = design_pair(PairSpec.from_scene(base))
    fe = FECompliance(blanks=blanks_from_design(design))
    out = {}
    for label in FE_VARIANTS:
        scene = base.replaced(ltca=VARIANTS[label])
        grids, _, _ = scene_grids(design, scene, side, positions)
        row = {}
        for name, comp in (("fast", None), ("fe", fe)):
            t0 = time.perf_counter()
            res = ltca_cycle(
                lambda f, grids=grids: grids[int(round(f * positions)) % positions],
                [torque],
                options=LTCAOptions(positions=positions),
                compliance=comp,
            )
            row[name] = {
                "mean_stiffness_N_per_m": float(res.stiffness[0].mean()),
                "lte_peak_to_peak_m": float(np.ptp(res.lte[0])),
                "max_pressure_Pa": float(res.max_pressure[0].max()),
                "seconds": time.perf_counter() - t0,
            }
        out[label] = row
        f, e = row["fast"], row["fe"]
        print(
            f"{label:<42} k {f['mean_stiffness_N_per_m'] / 1e6:6.1f} / "
            f"{e['mean_stiffness_N_per_m'] / 1e6:6.1f} MN/m, LTE p-p "
            f"{f['lte_peak_to_peak_m'] * 1e6:5.2f} / {e['lte_peak_to_peak_m'] * 1e6:5.2f} um, "
            f"p_max {f['max_pressure_Pa'] / 1e6:4.0f} / {e['max_pressure_Pa'] / 1e6:4.0f} MPa "
            f"({e['seconds']:.0f} s FE)",
            flush=True,
        )
    return out


def main() -> None:
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.table import scene_ltca
    from gearbox.scene import load_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "models" / "case03.toml"))
    ap.add_argument("--torque", type=float, default=300.0, help="pinion torque (N m)")
    ap.add_argument("--flank", default="drive", choices=("drive", "coast"))
    ap.add_argument("--positions", type=int, default=24)
    ap.add_argument("--fe", action="store_true", help="also the FE level (FE_VARIANTS)")
    ap.add_argument("--json", metavar="FILE", help="with --fe: store the rows here")
    args = ap.parse_args()
    base = load_scene(args.scene).replaced(ltca=FE_GRIDS)
    print(
        f"scene {args.scene}, {args.flank} flank, {args.torque:g} N m, "
        f"{args.positions} positions per mesh cycle, fast level"
    )
    head = (
        f"{'variant':<42} {'k mean':>8} {'k p-p':>7} {'LTE mean':>8} {'LTE p-p':>8} "
        f"{'pattern':>7} {'h1':>5} {'h2':>5} {'p_max':>6} {'edge':>6} {'time':>6}"
    )
    print(
        f"{'':<42} {'MN/m':>8} {'MN/m':>7} {'um':>8} {'um':>8} {'%':>7} {'nm':>5} {'nm':>5} "
        f"{'MPa':>6} {'%':>6} {'s':>6}"
    )
    print(head)
    print("-" * len(head))
    for label, keys in VARIANTS.items():
        scene = base.replaced(
            ltca={"flanks": [args.flank], "positions": args.positions, **keys},
            load={"torques_Nm": [args.torque]},
        )
        design = design_pair(PairSpec.from_scene(scene))
        t0 = time.perf_counter()
        res = scene_ltca(design, scene)
        dt = time.perf_counter() - t0
        row = res.summary()["flanks"][args.flank][f"{args.torque:g}"]
        h = res.table.summary()[args.flank][f"{args.torque:g}"]["lte_harmonics_m"]
        print(
            f"{label:<42} {row['mean_mesh_stiffness_N_per_m'] / 1e6:8.1f} "
            f"{row['mesh_stiffness_peak_to_peak_N_per_m'] / 1e6:7.1f} "
            f"{row['lte_mean_m'] * 1e6:8.2f} {row['lte_peak_to_peak_m'] * 1e6:8.2f} "
            f"{100 * row['contact_pattern_area_fraction']:7.0f} "
            f"{h[0] * 1e9:5.0f} {h[1] * 1e9:5.0f} "
            f"{row['max_contact_pressure_Pa'] / 1e6:6.0f} "
            f"{100 * row['max_edge_load_fraction']:6.1f} {dt:6.2f}"
        )
    if args.fe:
        print("\nfast / FE level on the same grids (whole gear, FE defaults)")
        base_fe = base.replaced(
            ltca={"flanks": [args.flank], "positions": args.positions},
            load={"torques_Nm": [args.torque]},
        )
        rows = fe_rows(base_fe, args.flank, args.torque, args.positions)
        if args.json:
            cmd = "python3 benchmarks/ltca_modifications.py " + " ".join(sys.argv[1:])
            data = {
                "command": cmd,
                "scene": Path(args.scene).name,
                "flank": args.flank,
                "torque_Nm": args.torque,
                "positions": args.positions,
                "variants": {k: VARIANTS[k] for k in rows},
                "rows": rows,
            }
            Path(args.json).write_text(json.dumps(data, indent=1))


if __name__ == "__main__":
    main()
