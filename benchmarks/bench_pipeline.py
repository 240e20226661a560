"""A scene's first run against a second run with only the propeller changed.

    python3 benchmarks/bench_pipeline.py [--scene models/marine_drive.toml]
        [--repeats 3] [--set ltca.fidelity=fe ...] [--output-worker on|off|both]
        [--json out.json]

Each repeat runs ``gearbox run`` twice in new processes (``python -m gearbox``), with
a fresh, empty cache folder: first the scene as it is, then the same scene with
``drivetrain.propeller_inertia_kgm2`` times 1.5 (every other value unchanged). Both
scenes are written by this script from the validated scene, with any ``--set``
overrides applied to both. Times are wall clock of the whole command (interpreter
start, imports, stages, result files, report, exit), and the per-stage times each
run records in its ``run_summary.json``.

Prints per stage the median over the repeats of the seconds spent and the status
(computed / cached), the time spent writing each stage's files and drawing the
report, the median wall time of both runs and the median of the per-repeat ratios
second / first. It also prints the CPU seconds of each command with its output
worker, and the second run's CPU seconds over the cores over the first run's wall
time: the ratio no schedule of the second run's work could beat on this machine.
``--output-worker both`` runs every repeat with and without the
output worker of ``gearbox run`` (:mod:`gearbox.pipeline.overlap`: files and report
sections made in a second process while later stages compute), each with its own
fresh cache, and adds the ratios with / without for both runs.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def parse_set(items: list[str]) -> dict[str, dict]:
    """``["ltca.fidelity=fe"]`` -> ``{"ltca": {"fidelity": "fe"}}`` (TOML values)."""
    import tomllib

    out: dict[str, dict] = {}
    for item in items:
        path, sep, text = item.partition("=")
        section, dot, key = path.partition(".")
        if not sep or not dot:
            raise SystemExit(f"--set {item!r}: must be section.key=value")
        out.setdefault(section, {})[key] = tomllib.loads(f"v = {text}")["v"]
    return out


def write_scenes(scene_path: Path, overrides: dict, folder: Path) -> tuple[Path, Path, str]:
    """The scene with ``overrides``, and the same with a 1.5 x propeller inertia."""
    from gearbox import load_scene
    from gearbox.report.build import scene_toml

    scene = load_scene(scene_path)
    if overrides:
        scene = scene.replaced(**overrides)
    j = scene["drivetrain"]["propeller_inertia_kgm2"]
    changed = scene.replaced(drivetrain={"propeller_inertia_kgm2": 1.5 * j})
    first, second = folder / "first.toml", folder / "second.toml"
    first.write_text(scene_toml(scene))
    second.write_text(scene_toml(changed))
    return first, second, f"propeller_inertia_kgm2 {j:g} -> {1.5 * j:g} kg m^2"


def run_once(scene: Path, out: Path, cache: Path, extra: tuple[str, ...] = ()) -> dict:
    """One ``gearbox run`` in a new process; its run_summary.json plus the wall time."""
    cmd = [sys.executable, "-m", "gearbox", "run", str(scene), "--out", str(out)]
    cmd += ["--cache", str(cache), "--no-progress", *extra]
    env = os.environ | {"PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    cpu0 = _children_cpu()
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, env=env)
    wall = time.perf_counter() - t0
    cpu = _children_cpu() - cpu0
    if proc.returncode != 0:
        raise SystemExit(f"gearbox run failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    summary = json.loads((out / "run_summary.json").read_text())
    summary["wall_s"] = wall
    summary["cpu_s"] = cpu
    return summary


def _children_cpu() -> float:
    """User + system seconds of this process's ended children and theirs (the command
    and its output worker, which it waits for), or NaN where the system keeps none."""
    try:
        import resource
    except ImportError:  # Windows
        return math.nan
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def stage_rows(runs: list[dict]) -> dict[str, tuple[float, str]]:
    """stage -> (median seconds, status or 'mixed') over the repeats of one run."""
    names = [r["name"] for r in runs[0]["records"]]
    rows = {}
    for name in names:
        recs = [next(r for r in run["records"] if r["name"] == name) for run in runs]
        status = {r["status"] for r in recs}
        rows[name] = (
            statistics.median(r["seconds"] for r in recs),
            status.pop() if len(status) == 1 else "mixed",
        )
    return rows


def output_rows(runs: list[dict]) -> dict[str, tuple[float, str]]:
    """What writing took per stage (its files) and for the report, medians."""
    names = list(runs[0]["outputs"]["seconds"])
    rows = {}
    for name in names:
        secs = [run["outputs"]["seconds"].get(name, 0.0) for run in runs]
        if name == "report":
            how = [
                sum(d == "cached" for d in run["outputs"]["report_sections"].values())
                for run in runs
            ]
            n = len(runs[0]["outputs"]["report_sections"])
            note = f"{statistics.median(how):g} of {n} sections cached"
        else:
            copied = sum(name in run["outputs"]["copied_from_cache"] for run in runs)
            note = "copied" if copied == len(runs) else ("written" if copied == 0 else "mixed")
        rows[name] = (statistics.median(secs), note)
    return rows


def print_table(firsts: list[dict], seconds: list[dict]) -> list[float]:
    """Per stage, files and report: medians of both runs; returns the ratios."""
    a, b = stage_rows(firsts), stage_rows(seconds)
    head = f"{'stage':<22} {'first run':>9} {'':<9} {'second run':>10} {'':<9}"
    print(head)
    print("-" * len(head))
    for name, (t, st) in a.items():
        t2, st2 = b.get(name, (0.0, "-"))
        print(f"{name:<22} {t:9.2f} {st:<9} {t2:10.2f} {st2:<9}")
    tot = [statistics.median(r["seconds"] for r in runs) for runs in (firsts, seconds)]
    print(f"{'all stages':<22} {tot[0]:9.2f} {'':<9} {tot[1]:10.2f}")
    oa, ob = output_rows(firsts), output_rows(seconds)
    for name, (t, note) in oa.items():
        t2, note2 = ob.get(name, (0.0, "-"))
        label = "report" if name == "report" else f"files: {name}"
        print(f"{label:<22} {t:9.2f} {note:<9} {t2:10.2f} {note2}")
    walls = [statistics.median(r["wall_s"] for r in runs) for runs in (firsts, seconds)]
    rest = [w - t for w, t in zip(walls, tot, strict=True)]
    print(f"{'outside the stages':<22} {rest[0]:9.2f} {'':<9} {rest[1]:10.2f}")
    print(f"{'whole command (wall)':<22} {walls[0]:9.2f} {'':<9} {walls[1]:10.2f}")
    cpus = [statistics.median(r["cpu_s"] for r in runs) for runs in (firsts, seconds)]
    print(f"{'CPU, all processes':<22} {cpus[0]:9.2f} {'':<9} {cpus[1]:10.2f}")
    from gearbox.pipeline.overlap import available_cores

    cores = available_cores()
    floors = [c / cores for c in cpus]
    print(f"{f'CPU / {cores} cores':<22} {floors[0]:9.2f} {'':<9} {floors[1]:10.2f}")
    ratios = [s["wall_s"] / f["wall_s"] for f, s in zip(firsts, seconds, strict=True)]
    print(
        f"\nsecond / first: median {statistics.median(ratios):.3f} "
        f"(repeats: {', '.join(f'{r:.3f}' for r in ratios)})"
    )
    # no schedule of the second run's work on these cores ends before its CPU seconds
    # over the cores: the ratio it could reach with every core busy all the time
    bound = [s["cpu_s"] / cores / f["wall_s"] for f, s in zip(firsts, seconds, strict=True)]
    print(
        f"second run's CPU / {cores} cores / first run's wall: median "
        f"{statistics.median(bound):.3f} (repeats: {', '.join(f'{r:.3f}' for r in bound)})"
    )
    return ratios


#: ``--output-worker`` choices -> the variants run, each with its extra CLI options.
VARIANTS = {
    "on": {"output worker": ()},
    "off": {"no output worker": ("--no-output-worker",)},
    "both": {"output worker": (), "no output worker": ("--no-output-worker",)},
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "models" / "marine_drive.toml"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE")
    ap.add_argument(
        "--output-worker",
        choices=list(VARIANTS),
        default="on",
        help="run with the CLI's output worker (on, the default), without it "
        "(--no-output-worker), or both, interleaved in every repeat",
    )
    ap.add_argument("--json", metavar="FILE", help="write every run's summary here")
    args = ap.parse_args()
    if args.repeats < 1:
        raise SystemExit(f"--repeats = {args.repeats}: must be >= 1")

    variants = VARIANTS[args.output_worker]
    runs: dict[str, tuple[list[dict], list[dict]]] = {v: ([], []) for v in variants}
    with tempfile.TemporaryDirectory(prefix="bench_pipeline.") as tmp:
        folder = Path(tmp)
        s1, s2, change = write_scenes(Path(args.scene), parse_set(args.set), folder)
        for i in range(args.repeats):
            for j, (label, extra) in enumerate(variants.items()):
                cache = folder / f"cache{i}_{j}"  # fresh for every repeat and variant
                firsts, seconds = runs[label]
                firsts.append(run_once(s1, folder / f"out{i}_{j}a", cache, extra))
                seconds.append(run_once(s2, folder / f"out{i}_{j}b", cache, extra))
                r = seconds[-1]["wall_s"] / firsts[-1]["wall_s"]
                print(
                    f"repeat {i + 1}, {label}: first {firsts[-1]['wall_s']:.2f} s, "
                    f"second {seconds[-1]['wall_s']:.2f} s, ratio {r:.3f}",
                    file=sys.stderr,
                )

    print(f"scene {args.scene} {' '.join(args.set)}; second run: {change}")
    out: dict[str, dict] = {}
    for label, (firsts, seconds) in runs.items():
        print(f"\n{label}: medians of {args.repeats} repeats, each with a fresh cache (s)\n")
        ratios = print_table(firsts, seconds)
        out[label] = {"first": firsts, "second": seconds, "ratios": ratios}
    if len(runs) == 2:
        (la, (fa, sa)), (lb, (fb, sb)) = runs.items()
        for what, xa, xb in (("first", fa, fb), ("second", sa, sb)):
            r = [x["wall_s"] / y["wall_s"] for x, y in zip(xa, xb, strict=True)]
            print(
                f"{what} run, {la} / {lb}: median {statistics.median(r):.3f} "
                f"(repeats: {', '.join(f'{v:.3f}' for v in r)})"
            )
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
