"""The output worker of ``gearbox run`` (:mod:`gearbox.pipeline.overlap`): files and
report sections made in a second process while later stages compute are the same
as those made after the stages in the main process, and what fails there is done
again here."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from gearbox import load_scene
from gearbox.pipeline import run_pipeline
from gearbox.pipeline.outputs import write_run
from gearbox.pipeline.overlap import OutputWorker, available_cores

ROOT = Path(__file__).resolve().parents[1]
SECTIONS = re.compile(r'<section id="(?!provenance)[^"]*">.*?</section>', re.S)


def short_scene():
    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    return scene.replaced(
        simulation={"settled_mesh_cycles": 40, "samples_per_mesh_cycle": 16, "sweep_speeds": 2},
        outputs={"mesh_tables": "analytical"},
    )


def files_of(folder: Path) -> dict[str, bytes]:
    skip = {"run_summary.json", "report.html", "dynamics.json"}  # these hold wall times
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.name not in skip}


@pytest.mark.slow
def test_worker_writes_the_same_files_and_draws_the_same_sections(tmp_path):
    """One run, written twice: by the worker while the stages compute, and after
    them in this process. Every file is byte for byte the same, and so is every
    report section (figures included); the worker's sections say how long they took."""
    scene = short_scene()
    wanted = ("design", "tables", "dynamics", "spectra", "waterfall", "campbell", "report")
    a, b = tmp_path / "worker", tmp_path / "here"
    with OutputWorker(a, None, files=wanted, report=True) as worker:
        run = run_pipeline(
            scene, wanted, cache=False, on_result=lambda n, r, k: worker.submit(scene, n, r, k)
        )
        got = write_run(run, a, worker=worker)
    here = write_run(run, b)
    assert files_of(a) == files_of(b)
    assert {"dynamics.csv", "waterfall.json", "design.json"} <= set(files_of(a))
    html_a, html_b = (f.joinpath("report.html").read_text() for f in (a, b))
    sections_a = SECTIONS.findall(html_a)
    assert len(sections_a) >= 6
    assert sections_a == SECTIONS.findall(html_b)
    # drawn there: a time per stage, as when drawn here
    for name in ("dynamics", "waterfall", "campbell"):
        assert float(got.sections[name]) > 0.0
        assert float(here.sections[name]) > 0.0
    assert got.copied == () and here.copied == ()
    assert set(got.worker) == set(wanted) - {"report"} and here.worker == ()


def test_files_the_worker_has_not_begun_are_claimed_and_written_here(tmp_path):
    """Stages handed over while the worker is still starting: the main process claims
    all their files (once: a second claim gets none), the worker draws their sections
    and leaves the files, write_run writes them here, byte for byte the files of a
    run without the worker. A stage the worker has finished is not claimed."""
    scene = short_scene()
    names = ("design", "tables", "dynamics")
    run = run_pipeline(scene, (*names, "report"), cache=False)
    a, b = tmp_path / "worker", tmp_path / "here"
    with OutputWorker(a, None, files=names, report=True) as worker:
        for n in names:
            worker.submit(scene, n, run.results[n], None)
        # the worker draws a stage's section before it claims the stage's files, and it
        # is still importing matplotlib: it has begun none of them
        assert set(worker.claim_files()) == set(names)
        assert worker.claim_files() == ()
        got = write_run(run, a, worker=worker)
    write_run(run, b)
    assert files_of(a) == files_of(b)
    assert {"dynamics.csv", "design.json", "tables.csv"} <= set(files_of(a))
    assert set(got.worker) == set(names)  # their sections were drawn there
    assert set(got.sections) >= set(names) and float(got.sections["dynamics"]) > 0.0

    with OutputWorker(tmp_path / "late", None, files=["design"], report=False) as worker:
        worker.submit(scene, "design", run.results["design"], None)
        done = worker.take("design")
        assert done is not None and done.files is not None  # the worker wrote them
        assert worker.claim_files() == ()


def test_a_worker_that_dies_leaves_its_work_to_the_main_process(tmp_path):
    """The worker killed (SIGKILL) before it answers: write_run writes every file and
    draws every section here, the same as a run without the worker, and counts none
    as the worker's."""
    import os
    import signal

    scene = short_scene()
    names = ("design", "dynamics")
    run = run_pipeline(scene, (*names, "report"), cache=False)
    a, b = tmp_path / "worker", tmp_path / "here"
    with OutputWorker(a, None, files=names, report=True) as worker:
        for n in names:
            worker.submit(scene, n, run.results[n], None)
        for pid in list(worker._pool._processes):
            os.kill(pid, signal.SIGKILL)
        got = write_run(run, a, worker=worker)
    write_run(run, b)
    assert files_of(a) == files_of(b) and "dynamics.csv" in files_of(a)
    html_a, html_b = (f.joinpath("report.html").read_text() for f in (a, b))
    assert SECTIONS.findall(html_a) == SECTIONS.findall(html_b)
    assert got.worker == ()


def test_what_fails_in_the_worker_is_kept_and_handed_back(tmp_path):
    """A result its writer and renderer cannot handle: both errors come back (the main
    process then writes and draws again, and reports the failure as it would)."""
    scene = short_scene()
    with OutputWorker(tmp_path, None, files=["dynamics"], report=True) as worker:
        worker.submit(scene, "dynamics", {"not": "a dynamics result"}, None)
        p = worker.take("dynamics")
    assert p is not None and p.files is None and p.sections is None
    assert isinstance(p.files_error, Exception) and isinstance(p.section_error, Exception)
    assert list(tmp_path.iterdir()) == []  # nothing half-written


def test_a_result_that_cannot_be_sent_stays_in_the_main_process(tmp_path):
    scene = short_scene()
    with OutputWorker(tmp_path, None, files=["design"], report=True) as worker:
        worker.submit(scene, "design", lambda: None, None)  # not picklable
        assert worker.take("design") is None
        assert worker.take("tables") is None  # never handed over


@pytest.mark.slow
def test_cli_uses_the_worker_only_where_it_can_help(tmp_path, capsys):
    """``gearbox run`` on more than one core computes with the worker; with
    ``--no-output-worker`` the same files come out of the main process."""
    import json

    from gearbox.cli import main

    path = tmp_path / "scene.toml"
    from gearbox.report.build import scene_toml

    path.write_text(scene_toml(short_scene()))
    outs = {}
    for flag in ((), ("--no-output-worker",)):
        out = tmp_path / ("off" if flag else "on")
        rc = main(
            ["run", str(path), "--out", str(out), "--no-cache", "--no-progress", "--json"]
            + ["--only", "design", "dynamics", "spectra", "report", *flag]
        )
        assert rc == 0
        printed = json.loads(capsys.readouterr().out)
        outs[out.name] = printed["outputs"]
    assert set(outs["on"]["report_sections"]) == set(outs["off"]["report_sections"])
    assert [Path(f).name for f in outs["on"]["files"]] == [
        Path(f).name for f in outs["off"]["files"]
    ]
    assert outs["off"]["made_by_output_worker"] == []
    if available_cores() >= 2:
        assert set(outs["on"]["made_by_output_worker"]) == {
            "design",
            "tables",
            "dynamics",
            "spectra",
        }
