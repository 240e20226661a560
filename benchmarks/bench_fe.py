"""Work-precision of the loaded TCA: the fast level against the FE reference level.

For each paper case (models/case01..04.toml) and flank (drive = R, coast = L), a
full table (positions x the scene's torques) at both levels; printed per case and
flank: the fast level's relative error against FE in mean mesh stiffness,
peak-to-peak LTE, maximum contact pressure and maximum root stress (pinion, at the
middle torque), and the wall time of each level with their ratio. The FE level's
memory: the factors' size and the process's peak resident memory.

    python benchmarks/bench_fe.py                     # all four cases, default mesh
    python benchmarks/bench_fe.py --cases 03 --refine 0.5 --positions 8

``--refine`` scales the FE mesh (``MeshOptions().refined(f)``; 1 = default mesh).
``--extent`` also extrapolates the FE segment (loaded teeth, one neighbour each side,
clamped cut faces) to the whole gear on a coarse mesh (``gearbox.fe.extent``; about
8 coarse runs per case and flank) and prints the fast level's error against that, the
reference the fast level is calibrated on (docs/fe.md); its FE runs are of the segment.
``--far-field none`` gives the segment's tables (the default, ``extrapolated``, adds the
FE level's far-field correction: the whole gear).
Timings on a shared machine vary: compare ratios measured in the same run.
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.fe import FECompliance, FEOptions, MeshOptions  # noqa: E402
from gearbox.fe.extent import extent_limit  # noqa: E402
from gearbox.fe.stress import fillet_stress  # noqa: E402
from gearbox.geometry import PairSpec, design_pair  # noqa: E402
from gearbox.ltca import LTCAOptions, ltca_cycle, solve_contact  # noqa: E402
from gearbox.ltca.beveloid import scene_grids  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402
from gearbox.surface import blanks_from_design  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

#: The stored FE runs these comparisons read (tests/data/fe_*.json) were made with the
#: edge points on the last profile samples, before ``ltca.edge_borders`` became the
#: default: both levels run on those grids here. On the default grids, the paper
#: cases against the FE level: ``benchmarks/ltca_edge_borders.py --fidelity fe``.
FE_GRIDS = {"edge_borders": False}


def _rel(a, b):
    return (a - b) / b


def run_case(
    case: str,
    side: str,
    positions: int,
    refine: float,
    neighbours: int = 1,
    cut_faces: str = "clamped",
    far_field: str = "extrapolated",
) -> dict:
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=FE_GRIDS)
    design = design_pair(PairSpec.from_scene(scene))
    grids, _, _ = scene_grids(design, scene, side, positions)
    torques = scene["load"]["torques_Nm"]
    opts = LTCAOptions(positions=positions)

    def grid_at(f):
        return grids[int(round(f * positions)) % positions]

    t0 = time.perf_counter()
    fast = ltca_cycle(grid_at, torques, options=opts)
    t_fast = time.perf_counter() - t0

    fe = FECompliance(
        FEOptions(
            mesh=MeshOptions().refined(refine),
            neighbours=neighbours,
            cut_faces=cut_faces,
            far_field=far_field,
        ),
        blanks=blanks_from_design(design),
    )
    t0 = time.perf_counter()
    fe.reserve(grids)
    ref = ltca_cycle(grid_at, torques, options=opts, compliance=fe)
    t_fe = time.perf_counter() - t0
    # FE root stress at the middle torque: the FE contact loads on the FE fillet
    tm = len(torques) // 2
    t0 = time.perf_counter()
    root_fe = 0.0
    root_profile = []
    for g in grids:
        sol = solve_contact(g, fe, torques[tm])
        fs = fillet_stress(fe, g, sol.load, 0)
        root_fe = max(root_fe, fs.max)
        root_profile.append(
            {
                "teeth": fs.teeth.tolist(),
                "z_m": fs.z.tolist(),
                "root_stress_Pa": fs.root_stress.tolist(),
                "load_N": np.asarray(sol.load).tolist(),
            }
        )
    t_root = time.perf_counter() - t0
    models = list(fe._models.values())
    keep = (
        "torque",
        "stiffness",
        "tangent_stiffness",
        "lte",
        "lte_unloaded",
        "max_pressure",
        "normal_load",
        "pattern_area_fraction",
        "edge_load_fraction",
        "mesh_point",
        "line_of_action",
        "root_stress_pinion",
        "root_stress_gear",
    )
    return {
        "fe_cycle": {k: np.asarray(getattr(ref, k)).tolist() for k in keep},
        "fast_cycle": {k: np.asarray(getattr(fast, k)).tolist() for k in keep},
        "root_fe_profile": root_profile,
        "case": case,
        "flank": "drive" if side == "R" else "coast",
        "k": _rel(fast.stiffness.mean(axis=1), ref.stiffness.mean(axis=1)),
        "k_fe": ref.stiffness.mean(axis=1),
        "lte": _rel(np.ptp(fast.lte, axis=1), np.ptp(ref.lte, axis=1)),
        "p": _rel(fast.max_pressure.max(axis=1), ref.max_pressure.max(axis=1)),
        "root": _rel(float(fast.root_stress_pinion[tm].max()), root_fe),
        "root_fe": root_fe,
        "t_fast": t_fast,
        "t_fe": t_fe,
        "t_root": t_root,
        "dofs": [m.model.n_dofs for m in models],
        "factor_MB": sum(m.model.factor_bytes for m in models) / 1e6,
        "solves": fe.stats["solves"],
        "far_field": far_field,
        "t_far_field": fe.stats["far_field_s"],
        "torques": torques,
        "converged": bool(ref.success and fast.success),
    }


def extent_factor(case: str, side: str, positions: int = 8, refine: float = 0.5):
    """Whole gear over the first clamped segment, per torque, on a coarse mesh
    (``gearbox.fe.extent.extent_limit`` of segments with 1-5 neighbours clamped and
    3-5 free), and the relative uncertainty."""

    def k(nb, bc):
        return run_case(case, side, positions, refine, nb, bc, far_field="none")["k_fe"]

    clamped = [k(nb, "clamped") for nb in range(1, 6)]
    free = [k(nb, "free") for nb in (3, 4, 5)]
    lim, err = extent_limit(np.array(clamped), np.array(free))
    return lim / np.asarray(clamped[0]), err / lim


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["01", "02", "03", "04"])
    ap.add_argument("--flanks", nargs="+", default=["R", "L"])
    ap.add_argument("--positions", type=int, default=24)
    ap.add_argument("--refine", type=float, default=1.0)
    ap.add_argument("--neighbours", type=int, default=1, help="unloaded teeth each side")
    ap.add_argument("--cut-faces", default="clamped", choices=("clamped", "free"))
    ap.add_argument(
        "--far-field",
        default="extrapolated",
        choices=("extrapolated", "none"),
        help="FE far-field correction (whole gear) or the segment alone",
    )
    ap.add_argument(
        "--extent",
        action="store_true",
        help="also extrapolate the segment to the whole gear (coarse-mesh study per case "
        "and flank) and give the fast level's errors against that",
    )
    ap.add_argument("--json", type=Path, help="write every run's numbers to this JSON file")
    a = ap.parse_args(argv)
    print(
        f"fast level against FE (mesh MeshOptions().refined({a.refine})), "
        f"{a.positions} positions; errors = fast / FE - 1"
    )
    head = (
        f"{'case':>4} {'flank':>5} {'torque':>7} {'k_FE N/um':>10} {'d k':>7} "
        f"{'d LTEpp':>8} {'d pmax':>7}"
    )
    rows = []
    for case in a.cases:
        for side in a.flanks:
            # --extent scales the segment itself: the far-field correction stays out
            ff = "none" if a.extent else a.far_field
            r = run_case(case, side, a.positions, a.refine, a.neighbours, a.cut_faces, ff)
            if a.extent:
                t0 = time.perf_counter()
                f, u = extent_factor(case, side)
                k_fast = r["k_fe"] * (1 + r["k"])
                r["k_whole"] = r["k_fe"] * f
                r["k_whole_err"] = u
                r["k_vs_whole"] = k_fast / r["k_whole"] - 1
                r["t_extent"] = time.perf_counter() - t0
            rows.append(r)
            print(head + ("  k_whole N/um   d k (whole)" if a.extent else ""))
            for i, tq in enumerate(r["torques"]):
                extra = ""
                if a.extent:
                    extra = (
                        f"  {r['k_whole'][i] / 1e6:7.1f} +-{r['k_whole_err'][i]:.1%} "
                        f"{r['k_vs_whole'][i]:+7.1%}"
                    )
                print(
                    f"{case:>4} {r['flank']:>5} {tq:7.0f} {r['k_fe'][i] / 1e6:10.1f} "
                    f"{r['k'][i]:+7.1%} {r['lte'][i]:+8.1%} {r['p'][i]:+7.1%}" + extra
                )
            print(
                f"     root stress (pinion, middle torque): FE {r['root_fe'] / 1e6:.0f} MPa, "
                f"fast {r['root']:+.1%}; time fast {r['t_fast']:.2f} s, FE {r['t_fe']:.1f} s "
                f"(x{r['t_fe'] / r['t_fast']:.0f}; far field {r['t_far_field']:.1f} s) "
                f"+ root {r['t_root']:.1f} s; "
                f"{r['solves']} solves, unknowns {r['dofs']}, factors {r['factor_MB']:.0f} MB; "
                f"converged {r['converged']}",
                flush=True,
            )
    if a.json is not None:
        meta = {
            "command": "python benchmarks/bench_fe.py " + " ".join(argv or sys.argv[1:]),
            "mesh": f"MeshOptions().refined({a.refine})",
            "neighbours": a.neighbours,
            "cut_faces": a.cut_faces,
            "far_field": a.far_field,
            "positions": a.positions,
        }
        a.json.write_text(
            json.dumps(
                {
                    "meta": meta,
                    "runs": [
                        {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in r.items()}
                        for r in rows
                    ],
                }
            )
        )
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kerr = np.concatenate([r["k_vs_whole" if a.extent else "k"] for r in rows])
    print(
        f"\nmean-stiffness error of the fast level against the "
        f"{'segment' if a.far_field == 'none' and not a.extent else 'whole-gear'} FE level: "
        f"median {np.median(kerr):+.1%}, "
        f"range {kerr.min():+.1%} .. {kerr.max():+.1%} (target |error| <= 5 %)"
    )
    tfe = [r["t_fe"] for r in rows]
    print(
        f"FE table time per case and flank: median {np.median(tfe):.1f} s, max {max(tfe):.1f} s; "
        f"peak resident memory {peak:.0f} MB"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
