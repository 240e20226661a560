"""A flank topography from a CSV file in the loaded TCA: a script to copy.

A grinding machine's k-chart, or a flank measured on the gear checker less its design,
is a removal over a grid of roll length and face position. This script writes such a
grid for the pinion of a scene (default: the paper's case 03 pair) as a CSV file, sets
the scene's topography keys to it, runs the loaded TCA, and compares the result with
the unmodified flanks and with the lead crowning the grid was made from. It saves the
map of the removal (``gearbox.ltca.plot.plot_modification_map``).

What it does, step by step:

1. load the scene and design the pair;
2. sample a lead crowning of ``--crowning-um`` (``C (2 w / b)^2``) on a grid of
   ``--profile-mm`` roll lengths from the reference circle and ``--face-mm`` axial
   positions from the face middle, plus, if ``--waviness-um`` is set, a waviness of
   that amplitude along the face (as a measured flank might show), and write it as a
   CSV file: one line per profile position, one value (um) per face position;
3. run the loaded TCA (``gearbox.ltca.table.scene_ltca``) three times: unmodified,
   with the lead crowning as the scene key ``pinion_lead_crowning_um``, and with the
   CSV file as ``pinion_topography_um`` (the positions in
   ``pinion_topography_profile_mm`` and ``pinion_topography_face_mm``);
4. print mean stiffness, LTE peak-to-peak and first mesh harmonic, contact pattern and
   largest pressure of each, and save the map.

Run it from the repository root::

    python models/example_topography.py                       # case 03, 300 N m
    python models/example_topography.py --waviness-um 1 --out topography.png
    python models/example_topography.py --csv my_k_chart.csv --profile-mm -15 -5 5 15 \\
        --face-mm -20 -10 0 10 20

Without waviness the topography's row equals the crowning's (the bicubic spline is
exact for a parabola): on case 03, 24 positions, both read 418.5 MN/m and 2.78 um LTE
peak-to-peak at 300 N m (docs/ltca.md, "Flank topography").
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca.table import scene_ltca

HERE = Path(__file__).resolve().parent


def write_topography(path, profile_mm, face_mm, face_width_mm, crowning_um, waviness_um):
    """The CSV file of a lead crowning plus a waviness along the face (um); returns
    the rows it wrote."""
    w = np.asarray(face_mm, dtype=float)
    crown = crowning_um * (2.0 * w / face_width_mm) ** 2
    wave = waviness_um * np.sin(2.0 * np.pi * w / (0.5 * face_width_mm))
    rows = [crown + wave for _ in profile_mm]
    lines = ["# pinion flank topography: removal (um) normal to the flank"]
    lines.append(f"# rows: roll length from the reference circle {list(profile_mm)} mm")
    lines.append(f"# columns: axial position from the face middle {list(face_mm)} mm")
    lines += [",".join(f"{v:.6g}" for v in row) for row in rows]
    Path(path).write_text("\n".join(lines) + "\n")
    return rows


def summary_row(res, flank: str, torque: float) -> dict:
    row = res.summary()["flanks"][flank][f"{torque:g}"]
    h = res.table.summary()[flank][f"{torque:g}"]["lte_harmonics_m"]
    return {
        "stiffness_MN_per_m": row["mean_mesh_stiffness_N_per_m"] / 1e6,
        "lte_pp_um": row["lte_peak_to_peak_m"] * 1e6,
        "h1_um": h[0] * 1e6,
        "pattern_pct": 100 * row["contact_pattern_area_fraction"],
        "p_max_MPa": row["max_contact_pressure_Pa"] / 1e6,
    }


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(HERE / "case03.toml"))
    ap.add_argument("--flank", default="drive", choices=("drive", "coast"))
    ap.add_argument("--torque-Nm", type=float, default=300.0)
    ap.add_argument("--positions", type=int, default=24)
    ap.add_argument("--crowning-um", type=float, default=10.0)
    ap.add_argument("--waviness-um", type=float, default=0.0)
    ap.add_argument("--profile-mm", type=float, nargs="+", default=[-20.0, -10.0, 0.0, 10.0, 20.0])
    ap.add_argument("--face-mm", type=float, nargs="+", default=None, help="default: 9 across")
    ap.add_argument("--csv", help="use this topography file instead of writing one")
    ap.add_argument("--out", default="topography.png", help="the map (PNG)")
    args = ap.parse_args(argv)

    base = load_scene(args.scene).replaced(
        ltca={"flanks": [args.flank], "positions": args.positions},
        load={"torques_Nm": [args.torque_Nm]},
    )
    b = base["pinion"]["face_width_mm"]
    face = args.face_mm or list(np.linspace(-0.5 * b, 0.5 * b, 9))
    csv = Path(args.csv) if args.csv else Path(args.out).with_suffix(".csv")
    if not args.csv:
        csv.parent.mkdir(parents=True, exist_ok=True)
        write_topography(csv, args.profile_mm, face, b, args.crowning_um, args.waviness_um)
    topo = {
        "pinion_topography_profile_mm": list(args.profile_mm),
        "pinion_topography_face_mm": [float(v) for v in face],
        "pinion_topography_um": str(csv.resolve()),  # a file name: read when validated
    }
    variants = {
        "unmodified": base,
        f"lead crowning {args.crowning_um:g} um": base.replaced(
            ltca={"pinion_lead_crowning_um": args.crowning_um}
        ),
        f"topography {csv.name}": base.replaced(ltca=topo),
    }
    design = design_pair(PairSpec.from_scene(base))
    rows, results = {}, {}
    for label, scene in variants.items():
        results[label] = scene_ltca(design, scene)
        rows[label] = summary_row(results[label], args.flank, args.torque_Nm)
    print(f"{args.flank} flank, {args.torque_Nm:g} N m, {args.positions} positions")
    print(f"{'variant':<34} {'k MN/m':>8} {'LTE p-p':>8} {'h1 um':>7} {'pattern':>8} {'p_max':>6}")
    for label, r in rows.items():
        print(
            f"{label:<34} {r['stiffness_MN_per_m']:8.1f} {r['lte_pp_um']:8.2f} "
            f"{r['h1_um']:7.3f} {r['pattern_pct']:7.0f}% {r['p_max_MPa']:6.0f}"
        )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gearbox.ltca.plot import plot_modification_map

    fig, ax = plt.subplots(figsize=(6.5, 4))
    plot_modification_map(
        results[f"topography {csv.name}"].modification_maps["pinion, drive flank"],
        ax,
        title=f"pinion, drive flank: {csv.name}",
    )
    fig.tight_layout()
    out = Path(args.out)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(f"wrote {out} and {csv}")
    return {"rows": rows, "csv": csv, "map": out}


if __name__ == "__main__":
    main()
