"""Walk the stage graph for one scene: plan, validate, load or compute, summarise."""

from __future__ import annotations

import contextlib
import functools
import logging
import sys
import time
from collections.abc import Callable, Iterable, Mapping
from concurrent.futures import Executor
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from types import MappingProxyType
from typing import Any

from .._pickling import PicklesReadOnly
from ..errors import InputError, Problem
from ..scene import Scene
from .cache import Cache, CacheMiss, stage_key
from .jaxcache import jax_cache
from .stage import Stage, StageContext, StageUnavailable, read_values, restricted_scene
from .summary import RunSummary, StageRecord
from .sweep import blas_limit, map_items

__all__ = ["PipelineRun", "plan", "preview", "run_pipeline"]

_log = logging.getLogger("gearbox.pipeline")

#: Outputs that are not stages: made from whatever the stages produced.
FINAL_OUTPUTS = ("report",)


@dataclass(frozen=True)
class PipelineRun(PicklesReadOnly):
    """The outcome of :func:`run_pipeline`.

    ``results`` maps each stage that produced a result to it; ``keys`` maps every
    planned stage to its cache key; ``summary`` says what was computed or cached;
    ``cache`` is the run's cache (None when caching was off): the report's sections
    and the output files of each stage are kept there too, under the stage's key.
    ``keyed`` holds the results the keys were made for: the same objects as
    ``results``, unless a result was replaced by hand (``dataclasses.replace``);
    sections and files are taken from the cache only for a result found there.
    """

    scene: Scene
    results: Mapping[str, Any]
    keys: Mapping[str, str]
    summary: RunSummary
    cache: Cache | None = None
    keyed: Mapping[str, Any] = field(default_factory=dict, repr=False)

    def cached_key(self, stage: str) -> str | None:
        """The key under which things made from ``stage``'s result may be cached:
        None without a cache or when the result is not the one the key was made for."""
        if self.cache is None or stage not in self.keys or stage not in self.results:
            return None
        return self.keys[stage] if self.keyed.get(stage) is self.results[stage] else None

    def __getitem__(self, stage: str) -> Any:
        return self.results[stage]


def _code(st: Stage) -> tuple[str, ...]:
    """Modules whose source enters the key: the declared ones, the stage function's and
    its checks' (a stage found in the cache is not validated again: its key stands for
    checks passed on the same inputs with the same code)."""
    out = tuple(st.code)
    for fn in (st.compute, st.validate):
        mod = getattr(fn, "__module__", None)
        if mod and mod not in out:
            out += (mod,)
    return out


def plan(
    requested: Iterable[str], stages: Mapping[str, Stage], scene: Scene | None = None
) -> list[str]:
    """The stages needed for ``requested``, upstream first (stable topological order).

    Unknown names raise :class:`InputError`; ``report`` needs no stage of its own.
    With ``scene``, stages that route (:attr:`Stage.route`) take their upstream from it.
    """
    requested = list(requested)
    unknown = [r for r in requested if r not in stages and r not in FINAL_OUTPUTS]
    if unknown:
        valid = ", ".join([*stages, *FINAL_OUTPUTS])
        raise InputError(
            [Problem("outputs.requested", u, f"unknown output; valid: {valid}") for u in unknown],
            "invalid requested outputs",
        )
    order: list[str] = []
    visiting: set[str] = set()

    def visit(name: str) -> None:
        if name in order:
            return
        if name in visiting:
            raise ValueError(f"stage graph has a cycle through {name!r}")
        visiting.add(name)
        req, opt = stages[name].upstream(scene)
        for dep in (*req, *opt):
            visit(dep)
        visiting.discard(name)
        order.append(name)

    for name in stages:  # graph order, so the plan does not depend on request order
        if name in requested:
            visit(name)
    return order


def validate(scene: Scene, names: Iterable[str], stages: Mapping[str, Stage]) -> None:
    """Run every planned stage's ``validate``; raise one InputError with all problems."""
    problems: list[Problem] = []
    for name in names:
        check = stages[name].validate
        if check is None:
            continue
        try:
            check(restricted_scene(scene, stages[name].reads_for(scene)))
        except InputError as exc:
            problems += [p for p in exc.problems if p not in problems]
        except StageUnavailable:
            pass  # reported when the stage runs
    if problems:
        where = f"scene {scene.path}" if scene.path else "scene"
        raise InputError(problems, f"invalid {where}")


def _as_cache(cache: Cache | str | Path | bool | None) -> Cache | None:
    if cache is None or cache is False:
        return None
    if cache is True:
        from .cache import default_cache_dir

        return Cache(default_cache_dir())
    if isinstance(cache, Cache):
        return cache
    return Cache(Path(cache))


def _requested(scene: Scene, requested) -> tuple[str, ...]:
    """The outputs asked for: ``requested`` (one name alone is one output), or the
    scene's ``outputs.requested``."""
    if requested is None:
        return tuple(scene["outputs"]["requested"])
    return (requested,) if isinstance(requested, str) else tuple(requested)


def preview(
    scene: Scene,
    requested: Iterable[str] | None = None,
    *,
    stages: Mapping[str, Stage] | None = None,
    cache: Cache | str | Path | bool | None = True,
) -> list[tuple[str, str, bool]]:
    """What :func:`run_pipeline` would do, without computing: ``(stage, key, cached)``
    per planned stage, upstream first.

    Assumes every upstream stage produces its result (an unavailable optional
    upstream changes the keys below it). Validation runs as in a real run.
    """
    if stages is None:
        from .stages import STAGES as stages
    requested = _requested(scene, requested)
    names = plan(requested, stages, scene)
    validate(scene, names, stages)
    store = _as_cache(cache)
    keys = _planned_keys(scene, names, stages)
    return [(n, keys[n], n in _in_cache(store, keys, stages)) for n in names]


def _planned_keys(scene: Scene, names: list[str], stages: Mapping[str, Stage]) -> dict[str, str]:
    """Each planned stage's cache key, as if every upstream stage produced its result."""
    keys: dict[str, str] = {}
    for name in names:
        st = stages[name]
        req, opt = st.upstream(scene)
        upstream = {d: keys[d] for d in (*req, *opt)}
        keys[name] = stage_key(name, read_values(scene, st.reads_for(scene)), upstream, _code(st))
    return keys


def _in_cache(store: Cache | None, keys: Mapping[str, str], stages) -> set[str]:
    """The stages whose entry under ``keys`` is in ``store`` (not yet loaded)."""
    if store is None:
        return set()
    return {n for n, k in keys.items() if stages[n].cacheable and store.path(n, k).exists()}


def run_pipeline(
    scene: Scene,
    requested: Iterable[str] | None = None,
    *,
    stages: Mapping[str, Stage] | None = None,
    cache: Cache | str | Path | bool | None = True,
    executor: Executor | None = None,
    jobs: int | None = None,
    progress: bool = False,
    on_stage: Callable[[StageRecord], None] | None = None,
    on_result: Callable[[str, Any, str | None], None] | None = None,
) -> PipelineRun:
    """Compute, or load from the cache, every stage that ``requested`` needs.

    Parameters
    ----------
    scene : Scene
        A validated scene (:func:`gearbox.load_scene`).
    requested : iterable of str, or str, optional
        Outputs to produce (one name alone is one output); default
        ``scene["outputs"]["requested"]``.
    stages : mapping, optional
        The stage graph; default :data:`gearbox.pipeline.STAGES`.
    cache : Cache, path, bool or None
        ``True``: the default cache directory; a path or :class:`Cache`: that one;
        ``False`` / ``None``: no cache. While the run lasts, jax's compiled programs
        are kept there too (:mod:`gearbox.pipeline.jaxcache`).
    executor : concurrent.futures.Executor, optional
        Runs the sweeps (see :mod:`gearbox.pipeline.sweep`); not shut down here.
    jobs : int, optional
        Workers of the default process pool when no executor is given.
    progress : bool
        tqdm progress bars on stderr.
    on_stage : callable, optional
        Called with each stage's :class:`StageRecord` as soon as the stage is done.
    on_result : callable, optional
        Called as ``on_result(stage, result, key)`` for each stage computed in this
        run, as soon as it is done (``key`` is None without a cache); ``gearbox run``
        hands the result to a worker process that writes its files and draws its
        report section (:mod:`gearbox.pipeline.overlap`).

    A stage that raises is recorded as ``failed`` (its message in the summary, its
    traceback logged to the ``gearbox.pipeline`` logger) and the stages downstream of
    it as ``skipped``; :class:`InputError` from validation
    is raised before anything is computed, with every problem of every stage.
    """
    if stages is None:
        from .stages import STAGES as stages
    requested = _requested(scene, requested)
    names = plan(requested, stages, scene)
    store = _as_cache(cache)
    # A stage found in the cache passed its checks on these inputs (its key holds the
    # scene values it reads and its code): only the others are validated.
    cached = _in_cache(store, _planned_keys(scene, names, stages), stages)
    validate(scene, [n for n in names if n not in cached], stages)
    started = datetime.now(UTC).isoformat(timespec="seconds")
    t_run = time.perf_counter()
    keys: dict[str, str] = {}
    results: dict[str, Any] = {}
    from tqdm.auto import tqdm

    bar = tqdm(names, desc="gearbox run", disable=not progress, leave=False, file=sys.stderr)

    records: list[StageRecord] = []

    def record(rec: StageRecord) -> None:
        records.append(rec)
        if on_stage is not None:
            on_stage(rec)

    jit_cache = contextlib.ExitStack()
    if store is not None:  # jax's compiled executables too, under <cache>/jax
        jit_cache.enter_context(jax_cache(store.root))
    with jit_cache:
        for name in bar:
            st = stages[name]
            bar.set_postfix_str(name)
            req, opt = st.upstream(scene)
            used = (*req, *(d for d in opt if d in results))
            upstream = {d: keys[d] for d in used} | {d: "absent" for d in opt if d not in results}
            keys[name] = stage_key(
                name, read_values(scene, st.reads_for(scene)), upstream, _code(st)
            )
            missing = [d for d in req if d not in results]
            if missing:
                record(
                    StageRecord(
                        name, "skipped", key=keys[name], detail=f"needs {', '.join(missing)}"
                    )
                )
                continue
            t0 = time.perf_counter()
            detail = ""
            if store is not None and st.cacheable:
                try:
                    results[name], meta = store.load(name, keys[name])
                except CacheMiss as miss:
                    if miss.corrupt:
                        detail = miss.reason
                else:
                    dt = time.perf_counter() - t0
                    record(
                        StageRecord(name, "cached", dt, keys[name], "", meta.get("seconds", 0.0))
                    )
                    continue
            ctx = StageContext(
                name=name,
                scene=restricted_scene(scene, st.reads_for(scene)),
                inputs=MappingProxyType({d: results[d] for d in used}),
                map=functools.partial(
                    map_items, executor=executor, jobs=jobs, progress=progress, desc=name
                ),
                progress=progress,
            )
            try:
                if name in cached:  # not validated up front: its planned key was cached
                    validate(scene, [name], stages)
                with blas_limit(st.blas_threads):
                    result = st.compute(ctx)
            except StageUnavailable as exc:
                record(
                    StageRecord(name, "unavailable", time.perf_counter() - t0, keys[name], str(exc))
                )
                continue
            except InputError as exc:  # its checks, or found mid-run: recorded; run goes on
                dt = time.perf_counter() - t0
                record(StageRecord(name, "failed", dt, keys[name], str(exc), bad_input=True))
                continue
            except Exception as exc:  # a fault: recorded with its traceback; run goes on
                msg = f"{type(exc).__name__}: {exc}"
                _log.error("stage %s failed", name, exc_info=True)  # the traceback, on stderr
                record(StageRecord(name, "failed", time.perf_counter() - t0, keys[name], msg))
                continue
            dt = time.perf_counter() - t0
            results[name] = result
            if store is not None and st.cacheable:
                try:
                    store.store(name, keys[name], result, dt)
                except Exception as exc:  # a full disk or an unpicklable result: run on
                    detail = (
                        detail + "; " if detail else ""
                    ) + f"not cached ({type(exc).__name__}: {exc})"
            record(StageRecord(name, "computed", time.perf_counter() - t0, keys[name], detail))
            if on_result is not None:
                on_result(name, result, keys[name] if store is not None else None)
    bar.close()
    summary = RunSummary(
        records=tuple(records),
        requested=requested,
        seconds=time.perf_counter() - t_run,
        cache_dir=str(store.root) if store is not None else "",
        started=started,
    )
    results = MappingProxyType(results)
    return PipelineRun(scene, results, MappingProxyType(keys), summary, store, results)
