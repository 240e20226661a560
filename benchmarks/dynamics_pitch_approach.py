"""The dynamics' approach of the tooth deviations (docs/drivetrain.md §3c) on the
default scene: the linear method's (the mesh table's weights, or the traces' turns)
against the exact method's (exact hunting records at the loaded TCA's torque levels and
the operating torque, interpolated in torque), both measured against exact hunting
records solved at the model's operating torque and at a torque between the levels
(``--between-Nm``, 700 N m), with the time of the ``pitch`` stage that makes each.

    python3 benchmarks/dynamics_pitch_approach.py                 # 24 positions, 3 cases
    python3 benchmarks/dynamics_pitch_approach.py --positions 12 --cases crownings

Cases (``[pitch]`` of the default scene, ``drivetrain.pitch_deviations = true``):
``pitch`` the scene's random single pitch deviations (+-4 um on both members);
``crownings`` random profile and helix crownings within +-4 um on both members, no
pitch deviations; ``all`` the pitch deviations with random slopes and crownings within
+-4 um. Printed per case and method: the pitch stage's time (the exact one solves the
record at the operating torque and at each of the four levels), and at each of the two
torques the approach's largest and RMS gap to minus the exact record's TE change (share
of the change's range) and the largest gap among the change's ten largest order lines
(share of the line).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

CASES = {
    "pitch": {},
    "crownings": {
        "random_single_um": 0.0,
        "random_profile_crowning_um": 4.0,
        "random_helix_crowning_um": 4.0,
    },
    "all": {
        "random_profile_slope_um": 4.0,
        "random_helix_slope_um": 4.0,
        "random_profile_crowning_um": 4.0,
        "random_helix_crowning_um": 4.0,
    },
}


def _gaps(approach, table, rec) -> tuple[float, float, float]:
    """Largest and RMS gap of an approach to minus the record's TE change (share of
    its range), and the largest gap among its ten largest lines (share of the line)."""
    change = rec.lte - rec.lte_nominal
    a, _ = approach(rec.angle + float(table.angle[0]))
    gap = a + change
    span = float(np.ptp(change))
    want = np.abs(np.fft.rfft(change))
    got = np.abs(np.fft.rfft(-a))
    top = np.argsort(want[1:])[::-1][:10] + 1
    lines = float(np.max(np.abs(got[top] / want[top] - 1.0)))
    return float(np.abs(gap).max()) / span, float(np.sqrt(np.mean(gap**2))) / span, lines


def main(argv=None) -> None:
    from gearbox import load_scene
    from gearbox.drivetrain.model import DrivetrainModel, PitchApproach
    from gearbox.pipeline import run_pipeline

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, default=24)
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--between-Nm", type=float, default=700.0, help="a torque between levels")
    args = ap.parse_args(argv)

    base = load_scene(ROOT / "models" / "marine_drive.toml").replaced(
        ltca={"positions": args.positions}, drivetrain={"pitch_deviations": True}
    )
    cache = Path(tempfile.mkdtemp(prefix="gearbox-approach-"))
    run_pipeline(base, ["tables"], cache=cache)  # the loaded TCA once
    between = args.between_Nm
    print(
        f"default scene, {args.positions} positions; gaps against the exact record at the "
        f"model's torque (operating) and at {between:g} N m (between levels)"
    )
    head = f"{'case':10s} {'method':7s} {'pitch stage (s)':>16s}"
    for where in ("operating", "between"):
        head += f" | {where + ': largest':>18s} {'RMS':>7s} {'lines':>7s}"
    print(head)
    for case in args.cases:
        runs = {}
        for method in ("exact", "linear"):
            s = base.replaced(pitch={**CASES[case], "method": method})
            t0 = time.perf_counter()
            run = run_pipeline(s, ["tables", "pitch", "approach"], cache=cache)
            wall = time.perf_counter() - t0
            ap = run["approach"]
            model = DrivetrainModel.from_scene(
                s, run["tables"], trace_turns=ap.turns, level_records=ap.levels
            )
            runs[method] = (model, run, wall)
        table = runs["exact"][1]["tables"]
        op = runs["exact"][1]["pitch"]
        mid = run_pipeline(  # the exact record between the levels alone
            base.replaced(
                pitch={**CASES[case], "method": "exact", "torque_Nm": between},
                drivetrain={"pitch_deviations": False},
            ),
            ["pitch"],
            cache=cache,
        )["pitch"].record
        for method, (model, run, wall) in runs.items():
            if method == "exact":
                at = PitchApproach.from_levels(table, run["approach"].levels, between)
            else:
                dev = run["pitch"].deviations
                at = PitchApproach.from_table(table, dev.pinion, dev.gear, between, dev.form)
            row = f"{case:10s} {method:7s} {wall:16.1f}"
            for approach, rec in ((model.pitch, op.record), (at, mid)):
                big, rms, lines = _gaps(approach, table, rec)
                row += f" | {100 * big:17.2f}% {100 * rms:6.2f}% {100 * lines:6.2f}%"
            print(row)


if __name__ == "__main__":
    main()
