"""Stress test of the design -> loaded TCA chain on random valid beveloid designs.

    python3 benchmarks/ltca_random_designs.py [--seed 1] [--designs 100]
        [--positions 6] [--last-samples] [--json out.json]

Each design draws, uniformly: pinion teeth 12..35, gear teeth 30..60, pinion profile
shift x_t1 -0.3..0.8, pinion helix 5..25 deg, cone angles 0..4 deg, shaft angle
5..20 deg, on case 03's tool, module, face widths and material. The offset is tried
at 13 values from 10 mm below to 20 mm above the sum of the pitch radii, and the first
one whose design passes every design check but undercut (the gear's profile shift
from the backlash-free condition) is kept; a draw without one is skipped. The loaded
TCA (fast level, both flanks, 300 N m) then runs on each design, its edge points on
the flank borders (the default); ``--last-samples`` on the last profile samples
(``ltca.edge_borders = false``).

``--parallel``: parallel-axis helical pairs instead (tests/data/ltca_parallel_helical.toml
with pinion teeth 12..40, gear teeth 20..80, x_1 -0.4..0.8, helix 0..25 deg at the
standard centre distance, x_1 + x_2 = 0; designs that fail a check but undercut or
the total contact ratio are skipped), each through both loaded TCA paths, the surface
path (generated flanks) and the closed form: the ratio of their mean drive stiffness
is printed per design and summarised (median, least, largest).

Prints one row per design whose run is not plain (an error, a refusal, a stiffness
outside 100..2000 MN/m or an unloaded TE above 0.1 um: the flanks are unmodified and
conjugate) and a summary: designs, runs that succeeded, refused (InputError), failed
(any other exception), odd, and the median seconds of a loaded TCA.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: Plausible bounds for the mean mesh stiffness of an unmodified pair (N/m) and the
#: largest unloaded TE p-p of conjugate flanks (m).
STIFFNESS_RANGE = (1e8, 2e9)
UNLOADED_TE_MAX = 1e-7


@dataclass
class Outcome:
    draw: dict
    status: str  # "ok", "odd", "refused", "failed"
    seconds: float = 0.0
    detail: str = ""
    rows: dict = field(default_factory=dict)


def draw_design(rng, base):
    """A random valid design of the ranges above: ``(draw, scene, design)`` or None."""
    from gearbox.geometry import PairSpec, design_pair

    draw = {
        "z1": int(rng.integers(12, 36)),
        "z2": int(rng.integers(30, 61)),
        "xt1": float(rng.uniform(-0.3, 0.8)),
        "beta_deg": float(rng.uniform(5, 25)),
        "cone1_deg": float(rng.uniform(0, 4)),
        "cone2_deg": float(rng.uniform(0, 4)),
        "shaft_deg": float(rng.uniform(5, 20)),
    }
    mn = base["pair"]["normal_module_mm"]
    d0 = mn * draw["z1"] / (2 * math.cos(math.radians(draw["beta_deg"]))) + mn * draw["z2"] / 2
    for off in d0 + np.linspace(-10.0, 20.0, 13):
        scene = base.replaced(
            pinion={
                "teeth": draw["z1"],
                "profile_shift_xt": draw["xt1"],
                "helix_angle_deg": draw["beta_deg"],
                "cone_angle_deg": draw["cone1_deg"],
            },
            gear={"teeth": draw["z2"], "cone_angle_deg": draw["cone2_deg"]},
            pair={"offset_mm": float(off), "shaft_angle_deg": draw["shaft_deg"]},
        )
        try:
            design = design_pair(PairSpec.from_scene(scene))
        except Exception:  # noqa: BLE001 - an offset without a design: try the next
            continue
        bad = [
            k
            for k, c in design.checks.items()
            if not c.ok and "undercut" not in k and k != "gear_helix_angle_given"
        ]
        if not bad:
            return draw | {"offset_mm": float(off)}, scene, design
    return None


def run_one(draw, scene, design) -> Outcome:
    from gearbox.errors import InputError
    from gearbox.ltca.beveloid import beveloid_ltca

    t0 = time.perf_counter()
    try:
        res = beveloid_ltca(design, scene)
    except InputError as exc:
        return Outcome(draw, "refused", time.perf_counter() - t0, str(exc)[:300])
    except Exception as exc:  # noqa: BLE001 - the point of a stress test
        return Outcome(draw, "failed", time.perf_counter() - t0, repr(exc)[:300])
    seconds = time.perf_counter() - t0
    rows, odd = {}, []
    for flank, by_torque in res.summary()["flanks"].items():
        row = by_torque[next(iter(by_torque))]
        k = row["mean_mesh_stiffness_N_per_m"]
        ute = row["unloaded_te_peak_to_peak_m"]
        rows[flank] = {"stiffness_N_per_m": k, "unloaded_te_m": ute}
        if not (STIFFNESS_RANGE[0] < k < STIFFNESS_RANGE[1]) or not ute < UNLOADED_TE_MAX:
            odd.append(f"{flank}: {k / 1e6:.1f} MN/m, unloaded TE {ute * 1e6:.3f} um")
    return Outcome(draw, "odd" if odd else "ok", seconds, "; ".join(odd), rows)


def draw_parallel(rng, base):
    """A random valid parallel helical pair (module doc): ``(draw, scene, design)`` or
    None."""
    from gearbox.geometry import PairSpec, design_pair

    draw = {
        "z1": int(rng.integers(12, 41)),
        "z2": int(rng.integers(20, 81)),
        "x1": float(rng.uniform(-0.4, 0.8)),
        "beta_deg": float(rng.uniform(0, 25)),
    }
    b = math.radians(draw["beta_deg"])
    mn = base["pair"]["normal_module_mm"]
    scene = base.replaced(
        pinion={
            "teeth": draw["z1"],
            "profile_shift_xt": draw["x1"] * math.cos(b),
            "helix_angle_deg": draw["beta_deg"],
        },
        gear={"teeth": draw["z2"]},
        pair={"offset_mm": (draw["z1"] + draw["z2"]) * mn / (2 * math.cos(b))},
    )
    try:
        design = design_pair(PairSpec.from_scene(scene))
    except Exception:  # noqa: BLE001 - a draw without a design: the next one
        return None
    skip = ("undercut", "total_contact_ratio", "gear_helix_angle_given")
    if any(not c.ok and not any(w in k for w in skip) for k, c in design.checks.items()):
        return None
    return draw, scene, design


def both_paths(draw, scene, design) -> Outcome:
    """The surface path and the closed form of one parallel pair: the ratio of their
    mean drive stiffness (closed / surface)."""
    from gearbox.ltca.beveloid import beveloid_ltca
    from gearbox.ltca.table import scene_ltca

    t0 = time.perf_counter()
    try:
        surface, closed = beveloid_ltca(design, scene), scene_ltca(design, scene)
    except Exception as exc:  # noqa: BLE001 - the point of a stress test
        return Outcome(draw, "failed", time.perf_counter() - t0, repr(exc)[:300])
    ks = float(surface.flanks["drive"].stiffness[0].mean())
    kc = float(closed.flanks["drive"].stiffness[0].mean())
    rows = {"surface_N_per_m": ks, "closed_N_per_m": kc, "ratio": kc / ks}
    return Outcome(draw, "ok", time.perf_counter() - t0, f"closed / surface {kc / ks:.4f}", rows)


def _collect(draw, analyse, base, seed: int, designs: int) -> list[Outcome]:
    """``designs`` outcomes of ``analyse(*draw(rng, base))``, skipping empty draws."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < designs:
        got = draw(rng, base)
        if got is not None:
            out.append(analyse(*got))
    return out


def run_parallel(seed: int, designs: int, positions: int) -> list[Outcome]:
    from gearbox import load_scene

    base = load_scene(ROOT / "tests" / "data" / "ltca_parallel_helical.toml").replaced(
        ltca={"positions": positions, "flanks": ["drive"]}, load={"torques_Nm": [300.0]}
    )
    return _collect(draw_parallel, both_paths, base, seed, designs)


def run(seed: int, designs: int, positions: int, edge_borders: bool = True) -> list[Outcome]:
    from gearbox import load_scene

    base = load_scene(ROOT / "models" / "case03.toml").replaced(
        ltca={"positions": positions, "edge_borders": edge_borders}, load={"torques_Nm": [300.0]}
    )
    return _collect(draw_design, run_one, base, seed, designs)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--designs", type=int, default=100)
    ap.add_argument("--positions", type=int, default=6)
    ap.add_argument("--parallel", action="store_true", help="parallel pairs, both paths")
    ap.add_argument(
        "--last-samples", action="store_true", help="ltca.edge_borders = false (crossed pairs)"
    )
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    if args.parallel:
        outcomes = run_parallel(args.seed, args.designs, args.positions)
        for o in outcomes:
            d = o.draw
            print(
                f"{o.status:8s} z {d['z1']}/{d['z2']} x_1 {d['x1']:.3f} beta {d['beta_deg']:.2f}: "
                f"{o.detail}"
            )
        r = [o.rows["ratio"] for o in outcomes if o.status == "ok"]
        failed = sum(o.status == "failed" for o in outcomes)
        print(
            f"seed {args.seed}: {len(outcomes)} parallel pairs, failed {failed}; closed form / "
            f"surface path, mean drive stiffness: median {statistics.median(r):.4f}, "
            f"least {min(r):.4f}, largest {max(r):.4f}; {time.perf_counter() - t0:.0f} s in all"
        )
        if args.json:
            args.json.write_text(json.dumps([asdict(o) for o in outcomes], indent=1))
        return
    outcomes = run(args.seed, args.designs, args.positions, not args.last_samples)
    for o in outcomes:
        if o.status != "ok":
            d = o.draw
            print(
                f"{o.status:8s} z {d['z1']}/{d['z2']} x_t1 {d['xt1']:.3f} beta {d['beta_deg']:.2f}"
                f" cones {d['cone1_deg']:.2f}/{d['cone2_deg']:.2f} shaft {d['shaft_deg']:.2f}"
                f" E {d['offset_mm']:.3f}: {o.detail}"
            )
    count = {s: sum(o.status == s for o in outcomes) for s in ("ok", "odd", "refused", "failed")}
    secs = [o.seconds for o in outcomes if o.status in ("ok", "odd")]
    print(
        f"seed {args.seed}: {len(outcomes)} designs, ok {count['ok']}, odd {count['odd']}, "
        f"refused {count['refused']}, failed {count['failed']}; loaded TCA median "
        f"{statistics.median(secs) if secs else math.nan:.2f} s ({args.positions} positions, "
        f"both flanks, 300 N m); {time.perf_counter() - t0:.0f} s in all"
    )
    if args.json:
        args.json.write_text(json.dumps([asdict(o) for o in outcomes], indent=1))


if __name__ == "__main__":
    sys.exit(main())
