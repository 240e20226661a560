"""Write a stage's files and draw its report section in a second process, while
the stages after it compute.

``gearbox run`` hands each stage it computes to an :class:`OutputWorker` as soon as
the stage is done: one worker process (started with ``spawn``, so nothing of the
main process's threads is copied) writes the stage's files into the output folder
and draws its report section(s), keeping both in the run's cache exactly as
:func:`gearbox.pipeline.outputs.write_run` would. Drawing is pure Python and
matplotlib and holds the interpreter lock; in a second process it runs beside the
main process's simulations instead of after them. :func:`write_run` then takes the
files and sections from the worker and only assembles the report.

A stage whose files or section fail in the worker, or a worker that dies, is done
again in the main process, so a failure there reads exactly as without the worker.
The worker ignores Ctrl-C: the main process handles it, cancels what is queued and
lets the worker finish the file it is writing (every file is written atomically).
"""

from __future__ import annotations

import atexit
import os
import pickle
import signal
import time
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ["OutputWorker", "Prepared", "available_cores"]


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the system has one)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # macOS, Windows
        return os.cpu_count() or 1


@dataclass(frozen=True)
class Prepared:
    """What the worker made of one stage. ``files``: ``(paths, from_cache, seconds)``
    or None when the stage's files were not asked for; ``sections``: ``(sections,
    drawn)`` as :func:`gearbox.report.sections.draw` returns them, or None; an
    exception raised while making either is kept in ``files_error`` /
    ``section_error`` (the main process then does that part again)."""

    files: tuple[list[Path], bool, float] | None = None
    sections: tuple[tuple, str] | None = None
    files_error: BaseException | None = field(default=None, repr=False)
    section_error: BaseException | None = field(default=None, repr=False)


def _leave_at_once() -> None:
    """The worker's exit, once the pool has told it to stop: its files are written and
    closed and its answers sent, so the process ends without the interpreter's
    teardown of matplotlib and the rest (the pool's shutdown, and with it the command,
    waits for the process to end)."""
    from ..commands._common import exit_now

    exit_now(0)


#: In the worker: the claims on the stages' files it shares with the main process.
_claims = None


def _claim(claims, slot: int) -> bool:
    """Take file slot ``slot`` for this process: True when no one had it (the one who
    takes it writes those files; the other leaves them). False as well when the flags'
    lock cannot be had within seconds (a worker killed while it held it): the main
    process then waits for the worker's answer, and writes the files when none comes."""
    lock = claims.get_lock()
    if not lock.acquire(timeout=5.0):
        return False
    try:
        if claims[slot]:
            return False
        claims[slot] = 1
        return True
    finally:
        lock.release()


def _init_worker(claims=None) -> None:
    global _claims
    _claims = claims
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the main process's
    atexit.register(_leave_at_once)
    # import what every stage needs now, while the main process starts its stages
    import matplotlib.figure  # noqa: F401

    from ..report import build

    build._renderers()  # imports the renderers' modules


def _ready() -> None:
    """The first task: makes the pool start its process at once."""


def _prepare(payload: bytes) -> Prepared:
    """In the worker: the section(s) of one stage, then its files unless the main
    process has claimed them (it writes the files of the stages the worker has not
    reached once its own stages are done, while the worker draws)."""
    from ..report import build, sections
    from .cache import Cache
    from .outputs import stage_files

    name, result, key, scene, folder, cache_root, files, section, slot = pickle.loads(payload)
    cache = Cache(Path(cache_root)) if cache_root is not None else None
    out: dict[str, Any] = {}
    if section:
        try:
            render = build.default_renderer(name)
            out["sections"] = sections.draw(name, render, scene, result, key or "", cache)
        except Exception as exc:
            out["section_error"] = exc
    if files and _claim(_claims, slot):
        t0 = time.perf_counter()
        try:
            paths, hit = stage_files(name, result, Path(folder), key, cache)
            out["files"] = (paths, hit, time.perf_counter() - t0)
        except Exception as exc:
            out["files_error"] = exc
    return Prepared(**out)


class OutputWorker:
    """One worker process that writes stages' files and draws their sections.

    Parameters
    ----------
    folder : path
        The run's output folder.
    cache : Cache or None
        The run's cache; files and sections are kept there as by :func:`write_run`.
    files : iterable of str
        Stages whose files are wanted (the requested ones).
    report : bool
        Whether sections are wanted (``report`` requested).

    Use as a context manager: leaving it on an exception cancels what is queued.
    """

    def __init__(self, folder, cache, *, files, report: bool) -> None:
        import multiprocessing

        self.folder = Path(folder)
        self.cache = cache
        self._files = frozenset(files)
        self._report = bool(report)
        self._futures: dict[str, Future] = {}
        ctx = multiprocessing.get_context("spawn")
        # one flag per stage whose files are wanted: set by whichever process writes them
        self._slots = {name: i for i, name in enumerate(sorted(self._files))}
        self._claims = ctx.Array("b", max(len(self._slots), 1))
        self._pool = ProcessPoolExecutor(
            1, mp_context=ctx, initializer=_init_worker, initargs=(self._claims,)
        )
        # start the process now (the pool starts it at the first task): its imports
        # then run while the main process imports and starts its first stage
        self._pool.submit(_ready)

    def submit(self, scene, name: str, result: Any, key: str | None) -> None:
        """Queue stage ``name``'s files (when wanted) and section(s) (when the report
        is); ``key``: the stage's cache key, None when the run has no cache."""
        from .._pickling import dumps

        files, section = name in self._files, self._report
        if not (files or section) or result is None:
            return
        root = str(self.cache.root) if self.cache is not None and key is not None else None
        slot = self._slots.get(name)
        try:
            job = (name, result, key, scene, str(self.folder), root, files, section, slot)
            self._futures[name] = self._pool.submit(_prepare, dumps(job))
        except Exception:  # unpicklable result or a pool that died: done in the main process
            self._futures.pop(name, None)

    def claim_files(self) -> tuple[str, ...]:
        """The stages whose files the worker has not begun: claimed for the main
        process, which then writes them (:func:`gearbox.pipeline.outputs.write_run`,
        once the stages are done) while the worker draws their sections; the worker
        leaves them."""
        mine = []
        for name, slot in self._slots.items():
            fut = self._futures.get(name)
            if fut is not None and not fut.done():
                if _claim(self._claims, slot):
                    mine.append(name)
        return tuple(mine)

    def take(self, name: str) -> Prepared | None:
        """What the worker made of stage ``name`` (waiting for it), or None when it was
        not handed over or the worker failed."""
        fut = self._futures.pop(name, None)
        if fut is None:
            return None
        try:
            return fut.result()
        except Exception:  # the worker died or its answer did not unpickle
            return None

    def close(self, *, cancel: bool = False) -> None:
        self._pool.shutdown(wait=not cancel, cancel_futures=cancel)

    def __enter__(self) -> OutputWorker:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close(cancel=exc_type is not None)
