"""Stress test of the whole chain on random scenes: design -> loaded TCA -> mesh tables
-> dynamics, spectra, waterfall, Campbell diagram -> report.

    python3 benchmarks/pipeline_random_scenes.py [--seed 1] [--scenes 20]
        [--positions 12] [--cache DIR] [--keep DIR] [--last-samples] [--json out.json]

Each scene starts from models/marine_drive.toml and draws, uniformly:

- a valid beveloid design as ``benchmarks/ltca_random_designs.py`` draws one (pinion
  teeth 12..35, gear teeth 30..60, x_t1 -0.3..0.8, helix 5..25 deg, cones 0..4 deg,
  shaft angle 5..20 deg, the offset that passes every check but undercut);
- flank modifications, each present with probability 1/2: lead and profile crowning
  0..20 um, tip relief 0..30 um over 0..3 mm (linear or parabolic), end relief 0..20 um
  over 0..8 mm, helix slope and flank twist -15..15 um, on either member;
- assembly errors with probability 1/3: offset -0.1..0.1 mm, shaft angle -0.05..0.05 deg;
- the drive: engine speed 1500..4000 rpm at a mean torque 150..850 N m (the tables'
  torques are 50..900 N m), inertias 0.5..2 x, shaft stiffnesses 0.3..3 x and damping
  ratios 0.01..0.1, mesh damping 0.02..0.1, backlash 0.02..0.3 mm, mesh friction 0 or
  0.02..0.08, bearing translations on or off, the mesh law (tangent, loaded, auto),
  random pitch deviations 0..6 um carried into the dynamics or not;
- a short simulation (diffrax, scipy or exudyn with probabilities 0.6, 0.2, 0.2;
  60..120 settled mesh cycles, 16..32 samples per cycle) and a
  waterfall of 3..5 speeds from 0.3..0.6 x the engine speed (higher where the
  propeller law would take the torque below 55 N m) to the engine speed.

Every scene runs through :func:`gearbox.pipeline.run_pipeline` with all its outputs and
a report (:func:`gearbox.pipeline.outputs.write_run`), one process, a cache shared by
the scenes (jax's compiled programs are reused; each scene's own stages are new).

A scene counts as

- ``ok``: every stage computed, the report written, and the operating point's metrics
  finite;
- ``refused``: the scene's validation or a stage found its inputs wrong (an
  ``InputError``, e.g. the drive's torque outside the tables), with its message;
- ``odd``: all computed, but a metric is not finite or the run did not succeed;
- ``failed``: a stage raised anything else (its traceback is printed).

Prints one row per scene that is not ``ok`` and a summary with the median seconds per
scene.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import statistics
import sys
import tempfile
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from ltca_random_designs import Outcome, draw_design  # noqa: E402

OUTPUTS = [
    "design", "tca", "ltca", "pitch", "tables", "dynamics", "spectra", "waterfall",
    "campbell", "report",
]  # fmt: skip


def _maybe(rng, p=0.5) -> bool:
    return bool(rng.random() < p)


def draw_modifications(rng) -> dict:
    """Random flank modifications of the ``[ltca]`` section (module doc)."""
    out: dict = {}
    for g in ("pinion", "gear"):
        if _maybe(rng):
            out[f"{g}_lead_crowning_um"] = float(rng.uniform(0, 20))
        if _maybe(rng):
            out[f"{g}_profile_crowning_um"] = float(rng.uniform(0, 20))
        if _maybe(rng):
            out[f"{g}_tip_relief_um"] = float(rng.uniform(0, 30))
            out[f"{g}_tip_relief_length_mm"] = float(rng.uniform(0, 3))
            out[f"{g}_tip_relief_shape"] = str(rng.choice(["linear", "parabolic"]))
        if _maybe(rng):
            out[f"{g}_end_relief_um"] = float(rng.uniform(0, 20))
            out[f"{g}_end_relief_length_mm"] = float(rng.uniform(0, 8))
        if _maybe(rng, 0.3):
            out[f"{g}_helix_slope_um"] = float(rng.uniform(-15, 15))
        if _maybe(rng, 0.3):
            out[f"{g}_flank_twist_um"] = float(rng.uniform(-15, 15))
    return out


def draw_drive(rng, base) -> dict:
    """Random drivetrain values around the default scene's (module doc)."""
    d = base["drivetrain"]
    speed = float(rng.uniform(1500, 4000))
    torque = float(rng.uniform(150, 850))
    out = {
        "engine_speed_rpm": speed,
        "engine_power_kW": torque * speed * math.pi / 30 / 1e3,
        "mesh_damping_ratio": float(rng.uniform(0.02, 0.1)),
        "backlash_mm": float(rng.uniform(0.02, 0.3)),
        "mesh_friction_coefficient": float(rng.uniform(0.02, 0.08)) if _maybe(rng) else 0.0,
        "bearing_dofs": _maybe(rng),
        "mesh_law": str(rng.choice(["tangent", "loaded", "auto"])),
        "pitch_deviations": _maybe(rng),
    }
    for k in (
        "engine_inertia_kgm2",
        "pinion_inertia_kgm2",
        "gear_inertia_kgm2",
        "propeller_inertia_kgm2",
    ):
        out[k] = float(d[k] * rng.uniform(0.5, 2.0))
    for k in ("input_shaft_stiffness_Nm_per_rad", "output_shaft_stiffness_Nm_per_rad"):
        out[k] = float(d[k] * rng.uniform(0.3, 3.0))
    for k in ("input_shaft_damping_ratio", "output_shaft_damping_ratio"):
        out[k] = float(rng.uniform(0.01, 0.1))
    return out


def draw_scene(rng, base):
    """``(draw, scene)``: a random scene of the ranges above, or None."""
    got = draw_design(rng, base)
    if got is None:
        return None
    draw, scene, _ = got
    ltca = draw_modifications(rng)
    drive = draw_drive(rng, base)
    speed = drive["engine_speed_rpm"]
    torque = drive["engine_power_kW"] * 1e3 / (speed * math.pi / 30)
    # the sweep follows the propeller law T (n / n_op)^2: its slowest speed keeps the
    # torque above the tables' 50 N m (with a margin)
    lo = max(0.3, math.sqrt(55.0 / torque))
    sim = {
        "solver": str(rng.choice(["diffrax", "scipy", "exudyn"], p=[0.6, 0.2, 0.2])),
        "settled_mesh_cycles": int(rng.integers(60, 121)),
        "samples_per_mesh_cycle": int(rng.integers(16, 33)),
        "speed_sweep_rpm": [float(rng.uniform(lo, max(lo, 0.6)) * speed), speed],
        "sweep_speeds": int(rng.integers(3, 6)),
    }
    assembly = {}
    if _maybe(rng, 1 / 3):
        assembly = {
            "offset_error_mm": float(rng.uniform(-0.1, 0.1)),
            "shaft_angle_error_deg": float(rng.uniform(-0.05, 0.05)),
        }
    pitch = {"random_single_um": float(rng.uniform(0, 6))}
    scene = scene.replaced(
        ltca=ltca,
        drivetrain=drive,
        simulation=sim,
        pitch=pitch,
        outputs={"requested": OUTPUTS},
        **({"assembly": assembly} if assembly else {}),
    )
    draw = draw | {"ltca": ltca, "drivetrain": drive, "simulation": sim, "assembly": assembly}
    return draw, scene


class _Tracebacks(logging.Handler):
    """Collects the tracebacks the pipeline logs for failed stages."""

    def __init__(self):
        super().__init__(logging.ERROR)
        self.texts: list[str] = []

    def emit(self, record):
        self.texts.append(self.format(record))


def run_scene(draw, scene, cache: Path, out: Path) -> Outcome:
    from gearbox.pipeline import run_pipeline
    from gearbox.pipeline.outputs import write_run

    handler = _Tracebacks()
    handler.setFormatter(logging.Formatter("%(message)s"))
    log = logging.getLogger("gearbox.pipeline")
    log.addHandler(handler)
    from gearbox.errors import InputError

    t0 = time.perf_counter()
    try:
        run = run_pipeline(scene, cache=cache, jobs=1)
        write_run(run, out)
    except InputError as exc:  # the scene's own problems, found before any stage
        return Outcome(draw, "refused", time.perf_counter() - t0, str(exc)[:600])
    except Exception:  # noqa: BLE001 - the point of a stress test
        import traceback

        return Outcome(draw, "failed", time.perf_counter() - t0, traceback.format_exc()[-3000:])
    finally:
        log.removeHandler(handler)
    seconds = time.perf_counter() - t0
    bad = [r for r in run.summary.records if r.status not in ("computed", "cached")]
    if bad:
        refused = all(r.bad_input or r.status == "skipped" for r in bad)
        detail = "; ".join(f"{r.name} {r.status}: {r.detail[:400]}" for r in bad)
        if not refused:
            detail += "\n" + "\n".join(t[-3000:] for t in handler.texts)
        return Outcome(draw, "refused" if refused else "failed", seconds, detail)
    op = run.results["dynamics"]
    metrics = {k: float(v) for k, v in op.metrics.items() if isinstance(v, (int, float))}
    odd = [k for k, v in metrics.items() if not math.isfinite(v)]
    odd += [f"sweep {p.speed_rpm:.0f} rpm {p.status}" for p in run.results["waterfall"].points
            if p.status != "success"]  # fmt: skip
    if op.series.status != "success":
        odd.append(f"operating point {op.series.status}")
    if not (out / "report.html").is_file():
        odd.append("no report")
    return Outcome(draw, "odd" if odd else "ok", seconds, "; ".join(odd), rows=metrics)


def run(
    seed: int,
    scenes: int,
    positions: int,
    cache: Path,
    keep: Path | None,
    edge_borders: bool = True,
):
    from gearbox import load_scene

    base = load_scene(ROOT / "models" / "marine_drive.toml")
    base = base.replaced(ltca={"positions": positions, "edge_borders": edge_borders})
    rng = np.random.default_rng(seed)
    outcomes = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = keep or Path(tmp)
        while len(outcomes) < scenes:
            got = draw_scene(rng, base)
            if got is None:
                continue
            i = len(outcomes)
            o = run_scene(*got, cache, folder / f"scene{i:03d}")
            outcomes.append(o)
            d = o.draw
            print(
                f"{i:3d} {o.status:8s} {o.seconds:6.1f} s  z {d['z1']}/{d['z2']} "
                f"beta {d['beta_deg']:.1f} law {d['drivetrain']['mesh_law']} "
                f"solver {d['simulation']['solver']}"
                + (f"\n    {o.detail}" if o.status != "ok" else ""),
                flush=True,
            )
    return outcomes


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--positions", type=int, default=12)
    ap.add_argument("--cache", type=Path, help="cache folder (default: a new temporary one)")
    ap.add_argument("--keep", type=Path, help="keep each scene's outputs under this folder")
    ap.add_argument(
        "--last-samples", action="store_true", help="every scene with ltca.edge_borders = false"
    )
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        cache = args.cache or Path(tmp)
        outcomes = run(
            args.seed, args.scenes, args.positions, cache, args.keep, not args.last_samples
        )
    count = {s: sum(o.status == s for o in outcomes) for s in ("ok", "odd", "refused", "failed")}
    secs = [o.seconds for o in outcomes if o.status in ("ok", "odd")]
    print(
        f"seed {args.seed}: {len(outcomes)} scenes, ok {count['ok']}, odd {count['odd']}, "
        f"refused {count['refused']}, failed {count['failed']}; median "
        f"{statistics.median(secs) if secs else math.nan:.1f} s per scene; "
        f"{time.perf_counter() - t0:.0f} s in all"
    )
    if args.json:
        args.json.write_text(json.dumps([asdict(o) for o in outcomes], indent=1, default=str))


if __name__ == "__main__":
    sys.exit(main())
