"""Profile and helix slope and crowning deviations per tooth on the default scene
(docs/ltca.md "Form deviations"): the linear method against the exact re-solve, and
what they add to the pitch deviations' loaded TE, tooth loads and root stress.

    python3 benchmarks/ltca_form_deviations.py            # both parts (about 12 min)
    python3 benchmarks/ltca_form_deviations.py --sweep    # linear vs exact, by amplitude
    python3 benchmarks/ltca_form_deviations.py --table    # the default scene, five cases

--sweep: random slopes on all four shapes (seed 7) within +-0.5 / 1 / 2 / 5 um, then
random crownings alone (seed 7) within the same, every 29th mesh cycle of the hunting
period, 802 N m, at 12 and 24 positions: the linear method's largest and RMS error as
a share of the largest TE change of the exact.

--table: the default scene (24 positions, its pitch deviations) with and without
random slopes within +-4 um (`pitch.random_profile_slope_um`, `random_helix_slope_um`),
the slopes alone, the crownings alone (`random_profile_crowning_um`,
`random_helix_crowning_um` 4 um) and all three: TE peak-to-peak, the linear method's
largest sample error, tooth load factor and largest root stress (linear scaled, linear
from first-order point loads, exact), and the exact method's wall time (the positions
over the machine's cores).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def sweep() -> None:
    from gearbox import load_scene
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca import LTCAOptions, compliance_for, ltca_cycle
    from gearbox.ltca.beveloid import scene_grids
    from gearbox.ltca.pitch import (
        FormDeviations,
        PitchDeviations,
        covered_centres,
        covered_lengths,
        exact_solutions,
        hunting_lte,
        pair_coefficients,
    )

    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    design = design_pair(PairSpec.from_scene(scene))
    z1, z2 = design.pinion.teeth, design.gear.teeth
    r = (design.pinion.reference_pitch_radius, design.gear.reference_pitch_radius)
    comp = compliance_for("fast")
    print("positions  shapes     within (um)  largest change (um)  largest error  RMS error")
    for P in (12, 24):
        grids, _, _ = scene_grids(design, scene, "R", P)
        res = ltca_cycle(
            lambda f, grids=grids, P=P: grids[round(f * P)],
            [600.0, 802.0, 900.0],
            options=LTCAOptions(positions=P),
            compliance=comp,
        )
        lengths = covered_lengths(res.flank_range)
        centres = covered_centres(res.flank_range)
        zero = [np.zeros(z) for z in (z1, z1, z2, z2)]
        for kind, scale in [
            (k, s) for k in ("slopes", "crownings") for s in (0.5e-6, 1e-6, 2e-6, 5e-6)
        ]:
            rng = np.random.default_rng(7)
            drawn = [rng.uniform(-scale, scale, z) for z in (z1, z1, z2, z2)]
            if kind == "slopes":
                sl = FormDeviations(*drawn, *lengths)
            else:
                sl = FormDeviations(*zero, *lengths, *drawn, *centres)
            dev = PitchDeviations(np.zeros(z1), np.zeros(z2), *r, sl)
            lin = hunting_lte(res, dev, 802.0, teeth=(z1, z2))
            cyc = np.arange(0, dev.hunting_cycles, 29)
            coef = pair_coefficients(dev, res.pair_index, cyc)
            ex = np.column_stack(
                [
                    np.prod(exact_solutions(g, comp, 802.0, coef, res.pair_index)[:2], axis=0)
                    for g in grids
                ]
            )
            nom = lin.lte_nominal.reshape(-1, P)[cyc]
            dl, de = lin.lte.reshape(-1, P)[cyc] - nom, ex - nom
            big = np.abs(de).max()
            print(
                f"{P:9d}  {kind:9s}  +-{scale * 1e6:<9g}  {big * 1e6:19.3f}  "
                f"{np.abs(dl - de).max() / big * 100:12.2f} %  "
                f"{np.sqrt(np.mean((dl - de) ** 2)) / big * 100:8.2f} %"
            )


def table() -> None:
    from gearbox import load_scene
    from gearbox.pipeline import run_pipeline

    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    slopes = {"random_profile_slope_um": 4.0, "random_helix_slope_um": 4.0}
    crownings = {"random_profile_crowning_um": 4.0, "random_helix_crowning_um": 4.0}
    cases = {
        "pitch only": {},
        "pitch and slopes": slopes,
        "slopes only": {"random_single_um": 0.0, **slopes},
        "crownings only": {"random_single_um": 0.0, **crownings},
        "pitch, slopes and crownings": {**slopes, **crownings},
    }
    for name, extra in cases.items():
        got = {}
        for method in ("linear", "exact"):
            t = time.perf_counter()
            run = run_pipeline(scene.replaced(pitch={**extra, "method": method}), ["pitch"])
            got[method] = (run["pitch"].record, time.perf_counter() - t)
        lin, ex = got["linear"][0], got["exact"][0]
        scaled = replace(lin, pair_root_stress=None)  # each pair's nominal stress scaled
        change = np.abs(ex.lte - ex.lte_nominal).max()
        print(f"\n{name}: exact method {got['exact'][1]:.1f} s")
        print(
            f"  TE peak-to-peak (um): nominal {np.ptp(lin.lte_nominal) * 1e6:.2f}, "
            f"linear {np.ptp(lin.lte) * 1e6:.2f}, exact {np.ptp(ex.lte) * 1e6:.2f}"
        )
        print(
            f"  linear's largest sample error {np.abs(lin.lte - ex.lte).max() * 1e6:.3f} um "
            f"of {change * 1e6:.3f} um"
        )
        for rec, label in ((lin, "linear"), (ex, "exact")):
            f = max(t.max() for t in rec.tooth_loads()) / rec.tooth_load_nominal
            print(f"  tooth load factor, {label}: {f:.3f}")
        for i, member in enumerate(("pinion", "gear")):
            vals = [rec.root_stress()[i] / 1e6 for rec in (scaled, lin, ex)]
            print(
                f"  largest root stress, {member} (MPa): scaled {vals[0]:.1f}, point loads "
                f"{vals[1]:.1f}, exact {vals[2]:.1f} (nominal {ex.root_stress_nominal()[i] / 1e6:.1f})"
            )
        lines = sorted(
            ((a, o) for o, a in zip(*ex.order_spectrum(), strict=True) if o > 0), reverse=True
        )[:6]
        lo, la = lin.order_spectrum()
        print("  largest lines, exact / linear (um):")
        for a, o in lines:
            i = int(np.argmin(np.abs(lo - o)))
            print(f"    order {o:8.3f}: {a * 1e6:.3f} / {la[i] * 1e6:.3f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweep", action="store_true", help="linear against exact by amplitude")
    ap.add_argument("--table", action="store_true", help="the default scene, five cases")
    args = ap.parse_args()
    both = not (args.sweep or args.table)
    if args.sweep or both:
        sweep()
    if args.table or both:
        table()


if __name__ == "__main__":
    main()
