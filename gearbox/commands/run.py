"""``gearbox run SCENE``: the whole job, stage by stage, cached, with a report."""

HELP = (
    "Run a scene: compute (or load from the cache) every stage its outputs.requested "
    "needs, write the report and a run summary."
)
EXAMPLES = """\
  gearbox run models/marine_drive.toml                  report in out/marine_drive/
  gearbox run models/marine_drive.toml --out results/   another output folder
  gearbox run models/case03.toml --only design report   other outputs than the scene's
  gearbox run models/marine_drive.toml --cache /tmp/gb  cache elsewhere (default ~/.cache/gearbox)
  gearbox run models/marine_drive.toml --no-cache --jobs 2 --json
  gearbox run models/marine_drive.toml --dry-run        what would be computed or cached
"""


def add_arguments(parser):
    from ._common import add_cache_arguments, add_scene_argument

    add_scene_argument(parser)
    parser.add_argument("--out", metavar="DIR", help="output folder (default out/<scene name>)")
    add_cache_arguments(parser, "the stages' results")
    parser.add_argument(
        "--only",
        nargs="+",
        metavar="OUTPUT",
        help="outputs to produce instead of the scene's outputs.requested",
    )
    parser.add_argument(
        "--jobs",
        type=int,
        metavar="N",
        help="workers for sweeps: threads for diffrax sweeps, processes for the others; "
        "1: none, and no output worker either (default: diffrax sweeps on one thread per "
        "core; other sweeps on a pool of processes when timing the first item says it "
        "pays)",
    )
    parser.add_argument(
        "--no-output-worker",
        action="store_true",
        help="write the files and draw the report in this process after the stages "
        "(default on a machine with more than one core: a second process does it for "
        "each computed stage while the later stages compute)",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bars")
    parser.add_argument(
        "--dry-run",
        action="store_true",
        help="validate and list the stages with their cache state; compute nothing",
    )
    parser.add_argument("--json", action="store_true", help="print the run summary as JSON")
    parser.add_argument(
        "--strict",
        action="store_true",
        help="exit 1 when a requested output could not be produced (stage unavailable)",
    )


def _outputs_line(written) -> str:
    """One line: time spent writing files and the report, and what came from the cache."""
    sec = written.seconds
    files = sum(v for k, v in sec.items() if k != "report")
    line = f"files {files:.2f} s"
    if written.copied:
        line += f" (copied from the cache: {', '.join(written.copied)})"
    if "report" in sec:
        cached = [n for n, d in written.sections.items() if d == "cached"]
        line += f"; report {sec['report']:.2f} s"
        line += f" (sections from the cache: {', '.join(cached)})" if cached else ""
    return line


def _output_worker(scene, only, cache, out, jobs, off: bool):
    """An :class:`~gearbox.pipeline.overlap.OutputWorker` when it can help: more than
    one core, ``--jobs`` not 1, not ``--no-output-worker``, and a requested stage (or,
    with a report, any stage) to compute; else a context that gives None."""
    import contextlib

    from ..pipeline import preview
    from ..pipeline.overlap import OutputWorker, available_cores
    from ..pipeline.runner import _as_cache

    if off or jobs == 1 or available_cores() < 2:
        return contextlib.nullcontext()
    requested = tuple(scene["outputs"]["requested"] if only is None else only)
    report = "report" in requested
    todo = [n for n, _, cached in preview(scene, requested, cache=cache) if not cached]
    if not any(report or n in requested for n in todo):
        return contextlib.nullcontext()
    try:
        return OutputWorker(out, _as_cache(cache), files=requested, report=report)
    except (OSError, NotImplementedError):  # no process pool here (e.g. no semaphores)
        return contextlib.nullcontext()


def run(args) -> int:
    import functools
    import os
    import sys
    from pathlib import Path

    from ..errors import Problem
    from ..pipeline import run_pipeline
    from ..pipeline.outputs import write_run
    from ..pipeline.runner import FINAL_OUTPUTS
    from ..pipeline.stages import STAGES
    from ._common import cache_of, dumps_json, output_folder, scene_and_options, usable_cache

    options = []
    if args.jobs is not None and args.jobs < 1:
        options.append(Problem("--jobs", args.jobs, "must be >= 1"))
    valid = (*STAGES, *FINAL_OUTPUTS)
    for name in args.only or ():
        if name not in valid:
            options.append(Problem("--only", name, f"unknown output; valid: {', '.join(valid)}"))
    # The pipeline's simulations are single small runs: on the CPU they beat a GPU
    # (a 900-mesh-cycle run took 15 s on an H200 machine's GPU, about 5 s on a
    # 2-core CPU). JAX_PLATFORMS=cuda (or any value) in the environment overrides.
    os.environ.setdefault("JAX_PLATFORMS", "cpu")
    scene = scene_and_options(args.scene, options)
    out = Path(args.out) if args.out else Path("out") / scene.name
    cache = cache_of(args)
    progress = not args.no_progress and sys.stderr.isatty()
    if args.dry_run:
        from ..pipeline import preview

        rows = preview(scene, args.only, cache=cache)
        if args.json:
            print(dumps_json([{"stage": n, "key": k, "cached": c} for n, k, c in rows]))
        else:
            for n, k, c in rows:
                print(f"{n:<10} {'cached' if c else 'compute':<8} {k[:12]}")
        return 0

    output_folder(out)  # before any stage computes: a folder that cannot be written fails now
    requested = args.only if args.only is not None else scene["outputs"]["requested"]
    if set(requested) == {"report"}:
        print(
            "gearbox run: the report alone holds no stage's results (only the run's "
            "provenance); name the stages beside it, e.g. --only design tca report, or "
            "leave out --only for the scene's outputs.requested",
            file=sys.stderr,
        )
    cache = usable_cache(cache, "run")

    def note(rec):  # one line per stage when there are no progress bars (logs, pipes)
        print(f"gearbox run: {rec.name} {rec.status} ({rec.seconds:.2f} s)", file=sys.stderr)

    quiet = progress or args.no_progress
    with _output_worker(scene, args.only, cache, out, args.jobs, args.no_output_worker) as worker:
        result = run_pipeline(
            scene,
            args.only,
            cache=cache,
            jobs=args.jobs,
            progress=progress,
            on_stage=None if quiet else note,
            on_result=None if worker is None else functools.partial(worker.submit, scene),
        )
        written = write_run(result, out, worker=worker)
    files = written.files
    s = result.summary
    if args.json:
        print(
            dumps_json(
                {
                    "summary": s.to_dict(),
                    "files": [str(f) for f in files],
                    "outputs": written.to_dict(),
                }
            )
        )
    else:
        print(s.table())
        for f in files:
            print(f"wrote {f}")
        print(_outputs_line(written))
    bad = [r for r in s.records if r.bad_input]
    for r in bad:  # the problems a stage found in its inputs: exit 2, as for the scene's
        print(f"gearbox run: {r.name}: {r.detail}", file=sys.stderr)
    if bad:
        return 2
    if not s.ok:
        return 1
    if args.strict and any(
        s.record(n).status != "computed" and s.record(n).status != "cached"
        for n in s.requested
        if n != "report"
    ):
        return 1
    return 0
