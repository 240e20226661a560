"""Tip reliefs on case 03: the loaded TCA's table per relief, drive and coast flank.

    python benchmarks/ltca_tip_relief.py [--scene models/case03.toml] [--json out.json]

Runs the loaded TCA of the scene (its grid, positions and fast level) with equal tip
relief on pinion and gear, for the reliefs of docs/ltca.md ("Tip relief"): none, 8 um
over 1.2 mm linear, 20 um over 1.8 mm parabolic, 30 um over 3.0 mm linear, and prints
per flank and torque the largest edge load, the mean, tangent and peak-to-peak mesh
stiffness, the LTE's mean and peak-to-peak, the unloaded TE's peak-to-peak, the
contact pattern's area fraction and the largest contact pressure, each with the wall
time of the relief's run.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.geometry import PairSpec, design_pair  # noqa: E402
from gearbox.ltca.table import scene_ltca  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

#: (label, relief um, length mm, shape)
RELIEFS = (
    ("none", 0.0, 0.0, "linear"),
    ("8 um, 1.2 mm, linear", 8.0, 1.2, "linear"),
    ("20 um, 1.8 mm, parabolic", 20.0, 1.8, "parabolic"),
    ("30 um, 3.0 mm, linear", 30.0, 3.0, "linear"),
)


def run(scene, um: float, mm: float, shape: str) -> tuple[dict, float]:
    keys = {}
    for gear in ("pinion", "gear"):
        keys[f"{gear}_tip_relief_um"] = um
        keys[f"{gear}_tip_relief_length_mm"] = mm
        keys[f"{gear}_tip_relief_shape"] = shape
    s = scene.replaced(ltca=keys)
    t0 = time.perf_counter()
    res = scene_ltca(design_pair(PairSpec.from_scene(s)), s)
    return res.summary()["flanks"], time.perf_counter() - t0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "models" / "case03.toml"))
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    scene = load_scene(a.scene)
    out = {}
    head = (
        f"{'relief (both gears)':<26} {'flank':<5} {'T (N m)':>7} {'edge':>6} {'k mean':>7} "
        f"{'k tan':>6} {'k p-p':>6} {'LTE mean':>8} {'LTE p-p':>7} {'TE0 p-p':>7} "
        f"{'pattern':>7} {'p_max':>5}"
    )
    print(f"scene {a.scene}; k in MN/m, LTE in um, unloaded TE in nm, p_max in MPa")
    print(head)
    print("-" * len(head))
    for label, um, mm, shape in RELIEFS:
        flanks, wall = run(scene, um, mm, shape)
        out[label] = {"flanks": flanks, "wall_s": wall}
        for flank, rows in flanks.items():
            for tq, r in rows.items():
                print(
                    f"{label:<26} {flank:<5} {float(tq):7.0f} "
                    f"{100 * r['max_edge_load_fraction']:5.1f}% "
                    f"{r['mean_mesh_stiffness_N_per_m'] / 1e6:7.1f} "
                    f"{r['mean_tangent_stiffness_N_per_m'] / 1e6:6.1f} "
                    f"{r['mesh_stiffness_peak_to_peak_N_per_m'] / 1e6:6.1f} "
                    f"{r['lte_mean_m'] * 1e6:8.2f} {r['lte_peak_to_peak_m'] * 1e6:7.2f} "
                    f"{r['unloaded_te_peak_to_peak_m'] * 1e9:7.1f} "
                    f"{100 * r['contact_pattern_area_fraction']:6.0f}% "
                    f"{r['max_contact_pressure_Pa'] / 1e6:5.0f}"
                )
        print(f"{'':<26} (run: {wall:.1f} s)")
    if a.json:
        a.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
