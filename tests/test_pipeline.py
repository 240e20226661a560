"""The stage graph and its cache, on a small graph of test stages.

The test stages mirror the shape of the real graph (design -> ltca -> tables ->
dynamics -> spectra) and count their calls, so every assertion about what was
computed is checked twice: by the run summary and by the calls themselves.
"""

from __future__ import annotations

import dataclasses
import math
import pickle
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import pytest

from gearbox import load_scene
from gearbox.errors import InputError, Problem
from gearbox.pipeline import Cache, Stage, map_items, plan, run_pipeline
from gearbox.pipeline.cache import stage_key

CALLS: Counter = Counter()


@dataclass(frozen=True)
class Value:
    """A tiny result with to_dict/from_dict, like the real stage results."""

    x: float

    def to_dict(self):
        return {"x": self.x}

    @classmethod
    def from_dict(cls, d):
        return cls(d["x"])


def _counted(name, fn):
    def compute(ctx):
        CALLS[name] += 1
        return fn(ctx)

    return compute


def graph(extra: dict | None = None) -> dict[str, Stage]:
    g = {
        "design": Stage(
            "design",
            _counted("design", lambda c: Value(c.scene["pair"]["offset_mm"])),
            reads=("pair",),
        ),
        "ltca": Stage(
            "ltca",
            _counted(
                "ltca", lambda c: Value(c.inputs["design"].x * sum(c.scene["load"]["torques_Nm"]))
            ),
            reads=("load.torques_Nm", "ltca"),
            depends=("design",),
        ),
        "tables": Stage(
            "tables", _counted("tables", lambda c: Value(c.inputs["ltca"].x + 1)), depends=("ltca",)
        ),
        "dynamics": Stage(
            "dynamics",
            _counted(
                "dynamics",
                lambda c: Value(
                    c.inputs["tables"].x * c.scene["drivetrain"]["propeller_inertia_kgm2"]
                ),
            ),
            reads=("drivetrain", "simulation"),
            depends=("tables",),
        ),
        "spectra": Stage(
            "spectra",
            _counted("spectra", lambda c: Value(-c.inputs["dynamics"].x)),
            depends=("dynamics",),
        ),
    }
    g.update(extra or {})
    return g


@pytest.fixture
def scene():
    return load_scene("models/case03.toml")


@pytest.fixture(autouse=True)
def _reset_calls():
    CALLS.clear()


def statuses(run):
    return {r.name: r.status for r in run.summary.records}


def test_plan_takes_only_what_the_outputs_need():
    g = graph()
    assert plan(["design"], g) == ["design"]
    assert plan(["tables"], g) == ["design", "ltca", "tables"]
    # request order does not matter, upstream always first
    assert plan(["spectra", "design"], g) == ["design", "ltca", "tables", "dynamics", "spectra"]
    assert plan(["report"], g) == []


def test_unknown_outputs_are_one_error_naming_each():
    with pytest.raises(InputError) as err:
        plan(["design", "bogus", "nope"], graph())
    paths = [(p.path, p.value) for p in err.value.problems]
    assert paths == [("outputs.requested", "bogus"), ("outputs.requested", "nope")]


def test_only_requested_stages_are_computed(scene, tmp_path):
    run = run_pipeline(scene, ["tables"], stages=graph(), cache=tmp_path)
    assert statuses(run) == {"design": "computed", "ltca": "computed", "tables": "computed"}
    assert set(CALLS) == {"design", "ltca", "tables"}
    # 229 mm offset x (150 + 300 + 450) N m + 1, from the scene values themselves
    assert run["tables"].x == pytest.approx(229.0 * 900.0 + 1.0, rel=1e-15)


def test_second_run_is_all_cached_and_equal(scene, tmp_path):
    first = run_pipeline(scene, ["spectra"], stages=graph(), cache=tmp_path)
    CALLS.clear()
    second = run_pipeline(scene, ["spectra"], stages=graph(), cache=tmp_path)
    assert set(statuses(second).values()) == {"cached"}
    assert not CALLS
    assert second["spectra"] == first["spectra"]
    assert dict(second.keys) == dict(first.keys)
    rec = second.summary.record("ltca")
    assert rec.saved_seconds >= 0.0 and rec.key == first.keys["ltca"]


def test_changing_the_propeller_recomputes_only_downstream(scene, tmp_path):
    run_pipeline(scene, ["spectra"], stages=graph(), cache=tmp_path)
    CALLS.clear()
    heavier = scene.replaced(drivetrain={"propeller_inertia_kgm2": 7.5})
    run = run_pipeline(heavier, ["spectra"], stages=graph(), cache=tmp_path)
    assert statuses(run) == {
        "design": "cached",
        "ltca": "cached",
        "tables": "cached",
        "dynamics": "computed",
        "spectra": "computed",
    }
    assert set(CALLS) == {"dynamics", "spectra"}
    assert run["dynamics"].x == pytest.approx((229.0 * 900.0 + 1.0) * 7.5, rel=1e-15)


def test_a_key_not_read_does_not_invalidate_but_an_upstream_change_does(scene, tmp_path):
    run_pipeline(scene, ["spectra"], stages=graph(), cache=tmp_path)
    # ltca reads load.torques_Nm only: the operating torque does not enter its key
    run = run_pipeline(
        scene.replaced(load={"operating_torque_Nm": 333.0}),
        ["spectra"],
        stages=graph(),
        cache=tmp_path,
    )
    assert set(statuses(run).values()) == {"cached"}
    # the offset changes the design, hence every key downstream of it
    run = run_pipeline(
        scene.replaced(pair={"offset_mm": 230.0}), ["spectra"], stages=graph(), cache=tmp_path
    )
    assert set(statuses(run).values()) == {"computed"}


def test_key_depends_on_version_code_scene_and_upstream():
    base = stage_key("s", {"pair": {"a": 1.0}}, {"up": "k"})
    assert base == stage_key("s", {"pair": {"a": 1.0}}, {"up": "k"})
    assert base != stage_key("s", {"pair": {"a": 1.0 + 1e-12}}, {"up": "k"})
    assert base != stage_key("s", {"pair": {"a": 1.0}}, {"up": "k2"})
    assert base != stage_key("t", {"pair": {"a": 1.0}}, {"up": "k"})
    assert base != stage_key("s", {"pair": {"a": 1.0}}, {"up": "k"}, code=("gearbox.errors",))
    import gearbox.pipeline.cache as cache_mod

    old = cache_mod.__version__
    try:
        cache_mod.__version__ = "999"
        assert base != stage_key("s", {"pair": {"a": 1.0}}, {"up": "k"})
    finally:
        cache_mod.__version__ = old


@pytest.mark.parametrize("damage", ["truncate", "flip", "garbage", "empty"])
def test_corrupt_entry_is_recomputed(scene, tmp_path, damage):
    first = run_pipeline(scene, ["ltca"], stages=graph(), cache=tmp_path)
    entry = Cache(tmp_path).path("ltca", first.keys["ltca"])
    raw = entry.read_bytes()
    entry.write_bytes(
        {
            "truncate": raw[: len(raw) // 2],
            "flip": raw[:-1] + bytes([raw[-1] ^ 0xFF]),
            "garbage": b"not a cache entry",
            "empty": b"",
        }[damage]
    )
    CALLS.clear()
    run = run_pipeline(scene, ["ltca"], stages=graph(), cache=tmp_path)
    assert statuses(run) == {"design": "cached", "ltca": "computed"}
    assert "corrupt entry" in run.summary.record("ltca").detail
    assert CALLS == Counter({"ltca": 1})
    assert run["ltca"] == first["ltca"]
    # the fresh entry is good again
    again = run_pipeline(scene, ["ltca"], stages=graph(), cache=tmp_path)
    assert statuses(again) == {"design": "cached", "ltca": "cached"}


def test_interrupted_cache_write_leaves_no_entry(scene, tmp_path, monkeypatch):
    import gearbox.commands._common as common

    def boom(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(common.os, "replace", boom)
    with pytest.raises(KeyboardInterrupt):
        run_pipeline(scene, ["design"], stages=graph(), cache=tmp_path)
    assert [p for p in tmp_path.rglob("*") if p.is_file()] == []


def test_no_cache_means_nothing_on_disk(scene, tmp_path, monkeypatch):
    monkeypatch.setenv("GEARBOX_CACHE", str(tmp_path / "default"))
    run = run_pipeline(scene, ["tables"], stages=graph(), cache=False)
    assert run.summary.cache_dir == ""
    assert not (tmp_path / "default").exists()
    run = run_pipeline(scene, ["design"], stages=graph(), cache=True)
    assert run.summary.cache_dir == str(tmp_path / "default")
    assert any((tmp_path / "default").rglob("*.gbx"))


def test_a_stage_reading_an_undeclared_section_fails_loudly(scene, tmp_path):
    sneaky = Stage(
        "design", lambda c: Value(c.scene["drivetrain"]["engine_speed_rpm"]), reads=("pair",)
    )
    run = run_pipeline(scene, ["tables"], stages=graph({"design": sneaky}), cache=tmp_path)
    rec = run.summary.record("design")
    assert rec.status == "failed" and "drivetrain" in rec.detail
    assert statuses(run) == {"design": "failed", "ltca": "skipped", "tables": "skipped"}
    assert not run.summary.ok


def test_a_single_key_declaration_hides_the_rest_of_its_section(scene, tmp_path):
    sneaky = Stage(
        "design",
        lambda c: Value(c.scene["load"]["operating_torque_Nm"]),
        reads=("load.torques_Nm",),
    )
    run = run_pipeline(scene, ["design"], stages={"design": sneaky}, cache=tmp_path)
    assert run.summary.record("design").status == "failed"


def test_unavailable_stage_is_reported_not_replaced(scene, tmp_path):
    from gearbox.pipeline import StageUnavailable
    from gearbox.pipeline.stages import require

    def missing(ctx):
        require("gearbox.no_such_module")

    run = run_pipeline(
        scene,
        ["spectra"],
        stages=graph({"ltca": Stage("ltca", missing, depends=("design",))}),
        cache=tmp_path,
    )
    assert statuses(run) == {
        "design": "computed",
        "ltca": "unavailable",
        "tables": "skipped",
        "dynamics": "skipped",
        "spectra": "skipped",
    }
    assert "gearbox.no_such_module" in run.summary.record("ltca").detail
    assert "ltca" not in run.results and "spectra" not in run.results
    assert run.summary.ok  # nothing failed; the summary says what is missing
    with pytest.raises(StageUnavailable, match="has no nothing_here"):
        require("gearbox.errors", "nothing_here")


def test_validation_collects_every_problem_of_every_stage_before_computing(scene, tmp_path):
    def bad_pair(s):
        raise InputError(
            [Problem("pair.offset_mm", 229.0, "too small"), Problem("pair.x", 1, "bad")]
        )

    def bad_drive(s):
        raise InputError(Problem("drivetrain.propeller_blades", 3, "odd"))

    g = graph()
    g["design"] = Stage("design", g["design"].compute, reads=("pair",), validate=bad_pair)
    g["dynamics"] = Stage(
        "dynamics",
        g["dynamics"].compute,
        reads=("drivetrain",),
        depends=("tables",),
        validate=bad_drive,
    )
    with pytest.raises(InputError) as err:
        run_pipeline(scene, ["spectra"], stages=g, cache=tmp_path)
    assert [p.path for p in err.value.problems] == [
        "pair.offset_mm",
        "pair.x",
        "drivetrain.propeller_blades",
    ]
    assert "3 problems" in str(err.value)
    assert not CALLS  # nothing was computed


def test_unpicklable_result_runs_on_uncached(scene, tmp_path):
    odd = Stage("design", lambda c: lambda: 1, reads=("pair",))
    run = run_pipeline(scene, ["design"], stages={"design": odd}, cache=tmp_path)
    rec = run.summary.record("design")
    assert rec.status == "computed" and "not cached" in rec.detail
    assert run["design"]() == 1


def test_result_without_to_dict_round_trips_through_pickle(tmp_path):
    c = Cache(tmp_path)
    c.store("s", "k", {"a": [1.0, 2.0]}, seconds=1.25)
    value, meta = c.load("s", "k")
    assert value == {"a": [1.0, 2.0]} and meta["seconds"] == 1.25
    c.store("s", "k2", Value(3.0), seconds=0.0)
    assert c.load("s", "k2")[0] == Value(3.0)
    # stored through to_dict: the payload names the type and holds the dict
    raw = c.path("s", "k2").read_bytes().split(b"\n", 2)[2]
    _meta, blob = pickle.loads(raw)
    assert pickle.loads(blob)["form"] == "dict"


def test_summary_round_trip_and_table(scene, tmp_path):
    from gearbox.pipeline import RunSummary

    run = run_pipeline(scene, ["tables"], stages=graph(), cache=tmp_path)
    s = run.summary
    assert RunSummary.from_dict(s.to_dict()) == s
    text = s.table()
    for name in ("design", "ltca", "tables", "computed", "total"):
        assert name in text


def _square(x):
    return x * x


def test_map_items_keeps_order_with_any_executor():
    items = list(range(23))
    expect = [x * x for x in items]
    assert map_items(_square, items, jobs=1) == expect
    with ThreadPoolExecutor(3) as ex:
        assert map_items(_square, items, executor=ex) == expect
        # the executor given is not shut down
        assert ex.submit(_square, 4).result() == 16


def test_map_items_process_pool():
    # math.sqrt pickles by reference, so the spawned workers need nothing from tests/
    got = map_items(math.sqrt, [0.0, 4.0, 9.0, 2.0], jobs=2)
    assert got == [0.0, 2.0, 3.0, math.sqrt(2.0)]


def _pid(_):
    import os

    return os.getpid()


def test_map_items_keeps_cheap_sweeps_in_this_process():
    import os

    # microseconds per item: starting workers can never pay off
    assert map_items(_pid, range(6)) == [os.getpid()] * 6


def test_pool_decision():
    from gearbox.pipeline.sweep import use_pool

    # 9 more items of 0.4 s on 2 workers: 3.6 s here against 3 + 2 + 1.8 s pooled
    assert not use_pool(9, 0.4, 2, start_s=3.0, warmup_s=2.0)
    # 9 more items of 3 s: 27 s here against 3 + 3 + 13.5 s pooled
    assert use_pool(9, 3.0, 2, start_s=3.0, warmup_s=2.0)
    # 8 more items of 1.2 s, the first found the solver compiled: 9.6 s here against
    # 3 + 2 (each worker compiles) + 4.8 s pooled
    assert not use_pool(8, 1.2, 2, start_s=3.0, warmup_s=2.0)
    assert use_pool(8, 1.2, 2, start_s=3.0, warmup_s=0.0)
    assert not use_pool(9, 3.0, 1, start_s=3.0)  # one core: nothing to gain
    assert not use_pool(1, 100.0, 8, start_s=3.0)  # one item left


def _blas_threads(_=None) -> int:
    from threadpoolctl import threadpool_info

    counts = [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]
    return max(counts) if counts else -1


def test_a_stage_runs_on_the_blas_threads_it_declares(scene, tmp_path):
    """``Stage.blas_threads``: 1 inside the stage and in the threads it starts (the
    speed sweep's), the library's own count again after it and in a stage that
    declares none. The drivetrain stages declare 1."""
    from threadpoolctl import threadpool_limits

    from gearbox.pipeline.stages import STAGES

    def sweep(c):
        with ThreadPoolExecutor(2) as ex:
            return (_blas_threads(), *ex.map(_blas_threads, range(2)))

    with threadpool_limits(limits=2, user_api="blas"):  # as on a 2-core machine
        assert _blas_threads() == 2, "numpy's BLAS is not one threadpoolctl can limit"
        stages = {
            "design": Stage("design", sweep, reads=(), blas_threads=1),
            "ltca": Stage("ltca", lambda c: _blas_threads(), reads=(), depends=("design",)),
        }
        run = run_pipeline(scene, ["ltca"], stages=stages, cache=False)
        assert run["design"] == (1, 1, 1)
        assert run["ltca"] == 2
        assert _blas_threads() == 2
    for name in ("dynamics", "spectra", "waterfall", "campbell", "fmu"):
        assert STAGES[name].blas_threads == 1, name
    assert STAGES["ltca"].blas_threads is None


def test_pool_workers_run_on_one_blas_thread():
    """Each process of the default pool has a core of its own: one BLAS thread."""
    assert map_items(_blas_threads, [0, 1], jobs=2) == [1, 1]


def test_sweep_from_inside_a_stage_uses_the_run_executor(scene, tmp_path):
    seen = []

    class Recording(ThreadPoolExecutor):
        def submit(self, fn, *a, **k):
            seen.append(a)
            return super().submit(fn, *a, **k)

    sweep = Stage("design", lambda c: tuple(c.map(_square, [1, 2, 3])), reads=())
    with Recording(2) as ex:
        run = run_pipeline(scene, ["design"], stages={"design": sweep}, cache=False, executor=ex)
    assert run["design"] == (1, 4, 9)
    assert sorted(seen) == [(1,), (2,), (3,)]


def test_preview_predicts_the_next_run(scene, tmp_path):
    from gearbox.pipeline import preview

    before = preview(scene, ["spectra"], stages=graph(), cache=tmp_path)
    assert [c for _, _, c in before] == [False] * 5
    run = run_pipeline(scene, ["spectra"], stages=graph(), cache=tmp_path)
    assert [(n, k) for n, k, _ in before] == list(run.keys.items())
    heavier = scene.replaced(drivetrain={"propeller_inertia_kgm2": 7.5})
    predicted = {n: c for n, _, c in preview(heavier, ["spectra"], stages=graph(), cache=tmp_path)}
    CALLS.clear()
    actual = statuses(run_pipeline(heavier, ["spectra"], stages=graph(), cache=tmp_path))
    assert predicted == {n: s == "cached" for n, s in actual.items()}
    assert not CALLS["design"] and CALLS["dynamics"] == 1


def test_the_stage_functions_own_module_enters_the_key():
    from gearbox.pipeline.runner import _code
    from gearbox.pipeline.stages import STAGES

    st = STAGES["dynamics"]
    assert _code(st)[-1] == "gearbox.pipeline.adapters.dynamics"
    assert set(st.code) < set(_code(st))


def test_on_stage_reports_each_stage_as_it_ends(scene, tmp_path):
    seen = []
    run = run_pipeline(scene, ["tables"], stages=graph(), cache=tmp_path, on_stage=seen.append)
    assert seen == list(run.summary.records)
    assert [r.name for r in seen] == ["design", "ltca", "tables"]


def test_files_of_a_cached_stage_are_copied_from_the_cache(scene, tmp_path, monkeypatch):
    from gearbox.pipeline import outputs

    # "response": a stage without a writer of its own (a <stage>.json of its to_dict)
    g = graph({"response": dataclasses.replace(graph()["dynamics"], name="response")})
    heavier = scene.replaced(drivetrain={"propeller_inertia_kgm2": 0.12})
    first = run_pipeline(scene, ["response"], stages=g, cache=tmp_path / "c")
    w1 = outputs.write_run(first, tmp_path / "a")
    assert w1.copied == ()
    # a second run: the files of cached stages are copied, not written by the writer
    written = []
    real = outputs._write_stage
    monkeypatch.setattr(outputs, "_write_stage", lambda n, r, f: written.append(n) or real(n, r, f))
    second = run_pipeline(heavier, ["response"], stages=g, cache=tmp_path / "c")
    w2 = outputs.write_run(second, tmp_path / "b")
    assert written == ["response"]
    assert w2.copied == ()  # only requested stages write files: response, computed anew
    again = outputs.write_run(second, tmp_path / "b2")
    assert again.copied == ("response",) and written == ["response"]
    a, b = (tmp_path / "b" / "response.json"), (tmp_path / "b2" / "response.json")
    assert a.read_bytes() == b.read_bytes()
    assert (tmp_path / "a" / "response.json").read_text() != a.read_text()  # new propeller
    summary = (tmp_path / "b2" / "run_summary.json").read_text()
    assert '"copied_from_cache": [\n      "response"\n    ]' in summary
    # a result replaced by hand is written by its writer again
    other = dataclasses.replace(second, results={"response": Value(1.0)})
    assert outputs.write_run(other, tmp_path / "c2").copied == ()
    assert written == ["response", "response"]


def _thread_name(_):
    import threading

    return threading.current_thread().name


def test_map_items_on_threads_for_compiled_runs():
    import os

    got = map_items(_thread_name, range(5), threads=True)
    assert got[0] == "MainThread"  # the first item runs here (it compiles, if anything)
    if len(os.sched_getaffinity(0)) > 1:
        assert all(n.startswith("gearbox-sweep") for n in got[1:]), got
    assert map_items(_pid, range(4), threads=True) == [os.getpid()] * 4  # no processes
    assert map_items(_thread_name, range(3), threads=True, jobs=1) == ["MainThread"] * 3
    # --jobs N: N threads after the first item, here, whatever the cores
    got = map_items(_thread_name, range(6), threads=True, jobs=3)
    assert got[0] == "MainThread" and all(n.startswith("gearbox-sweep") for n in got[1:])
    assert len(set(got[1:])) <= 3
    assert map_items(_pid, range(4), threads=True, jobs=2) == [os.getpid()] * 4


def test_json_files_take_numpy_values_and_write_non_finite_numbers_as_null(tmp_path):
    """The output files' JSON: numpy arrays, scalars and read-only mappings go to the
    encoder as they are; a NaN or infinity anywhere (or a key JSON has no word for)
    makes the whole object go through ``jsonable`` first, which writes null."""
    import json
    from types import MappingProxyType

    import numpy as np

    from gearbox.pipeline.outputs import _json, jsonable

    plain = {
        "a": np.linspace(0.0, 1.0, 7),
        "n": np.int64(3),
        "f": np.float32(0.5),
        "m": MappingProxyType({"k": np.arange(3), "b": np.array([True, False])}),
        "t": (1, 2.5, "x"),
    }
    (path,) = _json(tmp_path / "a.json", plain, compact=True)
    assert json.loads(path.read_text()) == jsonable(plain)
    assert json.loads(path.read_text())["a"] == np.linspace(0.0, 1.0, 7).tolist()
    odd = {"x": np.array([1.0, np.nan, np.inf]), "y": {(1, 2): -np.inf}, "z": [float("nan")]}
    (path,) = _json(tmp_path / "b.json", odd)
    got = json.loads(path.read_text())
    assert got == {"x": [1.0, None, None], "y": {"(1, 2)": None}, "z": [None]}


def test_the_loaded_tca_stage_shows_its_progress(capsys):
    """``progress=True`` (``gearbox run`` on a terminal): the loaded TCA, the longest
    stage, shows a bar over its contact solves; without it, none."""
    import pathlib

    case = load_scene(pathlib.Path(__file__).parents[1] / "models" / "case03.toml").replaced(
        ltca={"positions": 4, "flanks": ["drive"]}, load={"torques_Nm": [300.0]}
    )
    run_pipeline(case, ["ltca"], cache=False, progress=True)
    assert "loaded TCA" in capsys.readouterr().err
    run_pipeline(case, ["ltca"], cache=False, progress=False)
    assert "loaded TCA" not in capsys.readouterr().err


def test_a_stage_found_in_the_cache_is_not_validated_again(scene, tmp_path):
    """Checks run for the stages that will compute; a stage whose entry is in the
    cache passed them on the same inputs (its key holds what it reads and its checks'
    code). A changed input makes a new key: checked again."""
    checked: Counter = Counter()

    def checking(name):
        def check(s):
            checked[name] += 1

        return check

    g = graph()
    g["design"] = Stage("design", g["design"].compute, reads=("pair",), validate=checking("design"))
    g["dynamics"] = Stage(
        "dynamics",
        g["dynamics"].compute,
        reads=("drivetrain", "simulation"),
        depends=("tables",),
        validate=checking("dynamics"),
    )
    run_pipeline(scene, ["spectra"], stages=g, cache=tmp_path)
    assert checked == {"design": 1, "dynamics": 1}
    run_pipeline(scene, ["spectra"], stages=g, cache=tmp_path)  # all from the cache
    assert checked == {"design": 1, "dynamics": 1}
    heavier = scene.replaced(drivetrain={"propeller_inertia_kgm2": 0.5})
    run_pipeline(heavier, ["spectra"], stages=g, cache=tmp_path)
    assert checked == {"design": 1, "dynamics": 2}
    # without a cache every stage is checked
    run_pipeline(scene, ["spectra"], stages=g, cache=False)
    assert checked == {"design": 2, "dynamics": 3}


def test_a_stage_whose_planned_key_was_cached_is_checked_before_it_computes(scene, tmp_path):
    """The up-front look into the cache assumes every optional upstream produces. When
    one does not, the stage's real key differs, it computes, and its checks run first:
    a problem they find is the stage's failure, and it does not compute."""
    from gearbox.pipeline import StageUnavailable

    present = {"extra": True}
    calls: Counter = Counter()

    def extra(ctx):
        if not present["extra"]:
            raise StageUnavailable("extra: switched off")
        return Value(1.0)

    def check(s):
        if s["drivetrain"]["propeller_inertia_kgm2"] > 1.0:
            raise InputError([Problem("drivetrain.propeller_inertia_kgm2", 2.0, "must be <= 1")])

    def downstream(ctx):
        calls["down"] += 1
        return Value(ctx.inputs["extra"].x if "extra" in ctx.inputs else 0.0)

    g = {
        "extra": Stage("extra", extra, cacheable=False),
        "down": Stage(
            "down", downstream, reads=("drivetrain",), optional=("extra",), validate=check
        ),
    }
    heavy = scene.replaced(drivetrain={"propeller_inertia_kgm2": 2.0})
    with pytest.raises(InputError, match="propeller_inertia_kgm2"):
        run_pipeline(heavy, ["down"], stages=g, cache=tmp_path)
    # put an entry under the key planned with "extra" present, as a run with an older,
    # laxer check would have left it
    lax = dict(g, down=dataclasses.replace(g["down"], validate=None))
    run_pipeline(heavy, ["down"], stages=lax, cache=tmp_path)
    assert calls["down"] == 1
    present["extra"] = False  # now the optional upstream gives nothing: another key
    run = run_pipeline(heavy, ["down"], stages=g, cache=tmp_path)
    rec = run.summary.record("down")
    assert rec.status == "failed" and "propeller_inertia_kgm2" in rec.detail
    assert calls["down"] == 1  # not computed unchecked


def test_a_stage_key_holds_its_checks_module():
    """The checks' module enters the key (a stage in the cache is not checked again)."""
    from gearbox.pipeline.runner import _code
    from gearbox.pipeline.stages import STAGES

    for st in STAGES.values():
        if st.validate is not None:
            assert st.validate.__module__ in _code(st), st.name


def test_the_scene_takes_every_output_the_pipeline_makes():
    """outputs.requested's choices are the stages and the final outputs, no more, no
    less (`--only approach` ran while the scene refused "approach")."""
    from gearbox.pipeline.runner import FINAL_OUTPUTS
    from gearbox.pipeline.stages import STAGES
    from gearbox.scene import SCHEMA

    choices = SCHEMA["outputs"]["requested"].choices
    assert set(choices) == set(STAGES) | set(FINAL_OUTPUTS)


@pytest.mark.slow
def test_worker_processes_solve_the_loaded_tca_as_this_one_does():
    """The exact pitch method on a beveloid pair (case 03's drive flank, no
    deviations: one contact solve per position) with its positions on two worker
    processes, against the loaded TCA's TE solved in this process: equal to 1e-9
    (measured 5.6e-16). Each worker solves its own plane-strain tooth tables; when a
    table was solved for the first section met in its cell, a worker's first
    sections set its values and the two disagreed by up to 9.1e-6 (and CI's run of
    the parallel pair beside other tests by 3.1e-5)."""
    import pathlib

    import numpy as np

    scene = load_scene(pathlib.Path(__file__).parents[1] / "models" / "case03.toml").replaced(
        ltca={"flanks": ["drive"], "positions": 6}, pitch={"method": "exact"}
    )
    run = run_pipeline(scene, ["pitch"], cache=False, jobs=2)
    lt = run["ltca"].flanks["drive"]
    t = int(np.flatnonzero(lt.torque == 300.0)[0])
    np.testing.assert_allclose(run["pitch"].record.lte_nominal[:6], lt.lte[t], rtol=1e-9)
