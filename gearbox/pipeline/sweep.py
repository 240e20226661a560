"""Sweeps (speeds, torques, design variants) through a ``concurrent.futures.Executor``.

:func:`map_items` runs ``fn(item)`` for every item and returns the results in the
order of ``items``. It accepts any executor with ``submit``; a cluster takes the
sweep through Dask's executor::

    from dask.distributed import Client
    client = Client("scheduler-address:8786")
    map_items(fn, items, executor=client.get_executor())

``fn`` and the items must then be picklable: a module-level function, not a lambda.

Without an executor, ``jobs`` workers of a ``ProcessPoolExecutor`` run the items
(started with the ``spawn`` method, since forking a process that has started jax's
or BLAS's threads can deadlock, and with jax kept on the CPU in the workers unless
``JAX_PLATFORMS`` is set); ``jobs=1`` runs them in this process. With neither
given, the first item runs here and is timed, and the rest go to a pool on all cores
only when that is expected to be faster (:func:`use_pool`): starting workers that
import gearbox and jax cost 2.3-3.4 s on the 2-core development machine, more than a
short sweep takes in one process. A sweep whose items run compiled code that releases
the GIL (``threads=True``: the diffrax runs of the speed sweep) goes to a thread pool
of this process instead (``jobs`` threads, or one per core): no start, the solver
compiled once.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import time
from collections.abc import Callable, Iterable
from concurrent.futures import Executor, ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from typing import Any

__all__ = [
    "POOL_START_S",
    "POOL_WARMUP_S",
    "blas_limit",
    "default_jobs",
    "map_items",
    "use_pool",
]

#: Assumed cost (s) of starting the worker processes of the default pool, importing
#: gearbox and jax in them: 2.3-3.4 s measured for 2 workers on the development
#: machine (spawn, 3 repetitions).
POOL_START_S = 3.0

#: Assumed least cost (s) of a worker's first item beyond its work: compiling the
#: drivetrain solver in a new process took 1.6-1.9 s (``compile_time_s`` of the
#: default scene's runs on the development machine). The first item here may not
#: show it: an earlier stage of the run (the operating point) compiled already.
POOL_WARMUP_S = 2.0


def default_jobs() -> int:
    """Worker processes of the default executor: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def use_pool(
    n_rest: int,
    first_s: float,
    workers: int,
    start_s: float = POOL_START_S,
    warmup_s: float = POOL_WARMUP_S,
) -> bool:
    """Whether ``n_rest`` items like the first (``first_s`` seconds each) finish sooner
    on ``workers`` new processes than here.

    Each worker pays the start ``start_s`` and, once, what the first item paid here
    beyond the work itself (compilation): estimated as ``first_s`` again, and at
    least ``warmup_s`` (the first item here may have found everything compiled).
    """
    if workers < 2 or n_rest < 2:
        return False
    here = n_rest * first_s
    pooled = start_s + max(first_s, warmup_s) + n_rest * first_s / workers
    return pooled < here


def blas_limit(threads: int | None):
    """A context in which the BLAS libraries loaded in this process (OpenBLAS, MKL,
    BLIS) run on at most ``threads`` threads, set back on leaving
    (``threadpoolctl.threadpool_limits``); None: a context that changes nothing. The
    limit is the process's: threads started inside it share it."""
    if threads is None:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=int(threads), user_api="blas")


def _worker_init() -> None:
    """Keep jax in each worker on the CPU unless ``JAX_PLATFORMS`` says otherwise:
    several processes each claiming a GPU's memory fail (seen on a 16-core GPU
    machine: every worker's CUDA start ran out of memory), and single small runs
    gain nothing from a GPU. And one BLAS thread per worker: the pool has a worker per
    core already."""
    os.environ.setdefault("JAX_PLATFORMS", "cpu")
    blas_limit(1)  # applies at once; never lifted in the worker


def _pool(jobs: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(
        jobs, mp_context=multiprocessing.get_context("spawn"), initializer=_worker_init
    )


def _submit_all(fn, items, executor, bar) -> list[Any]:
    futures: dict = {}
    try:
        futures = {executor.submit(fn, x): i for i, x in enumerate(items)}
        results: list[Any] = [None] * len(items)
        for fut in as_completed(futures):
            results[futures[fut]] = fut.result()
            bar.update()
        return results
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise


def map_items(
    fn: Callable[[Any], Any],
    items: Iterable[Any],
    *,
    executor: Executor | None = None,
    jobs: int | None = None,
    progress: bool = False,
    desc: str = "",
    threads: bool = False,
) -> list[Any]:
    """``[fn(x) for x in items]``, in parallel where that pays.

    Parameters
    ----------
    executor : concurrent.futures.Executor, optional
        Used as given for every item and not shut down.
    jobs : int, optional
        Without an executor: ``1`` runs here, one item after the other; ``N > 1``
        runs on a new ``ProcessPoolExecutor`` of ``N`` workers (with ``threads``: the
        first item here, the rest on ``N`` threads), shut down on return; None decides
        after timing the first item (module doc).
    progress : bool
        Show a tqdm progress bar on stderr.
    threads : bool
        ``fn`` spends its time in compiled code that releases the GIL and may run in
        several threads at once (a compiled jax run): without an executor, the first
        item runs here and the rest on a thread pool in this process (nothing to
        start, nothing compiled again), of ``jobs`` threads or, with ``jobs`` None,
        one per core.
    """
    items = list(items)
    from tqdm.auto import tqdm

    bar = tqdm(total=len(items), desc=desc or None, disable=not progress, leave=False)
    try:
        if executor is not None:
            return _submit_all(fn, items, executor, bar)
        done: list[Any] = []
        pool_type = "thread" if threads else "process"
        if (jobs is None or (threads and jobs > 1)) and items:
            t0 = time.perf_counter()
            done.append(fn(items[0]))  # here: it compiles, if anything
            bar.update()
            first_s = time.perf_counter() - t0
            workers = min(default_jobs() if jobs is None else jobs, len(items) - 1)
            pays = threads or use_pool(len(items) - 1, first_s, workers)
            jobs = workers if pays else 1
        rest = items[len(done) :]
        if jobs == 1 or len(rest) <= 1:
            for x in rest:
                done.append(fn(x))
                bar.update()
            return done
        n = min(jobs, len(rest))
        pool = (
            ThreadPoolExecutor(n, thread_name_prefix="gearbox-sweep")
            if pool_type == "thread"
            else _pool(n)
        )
        with pool:
            return done + _submit_all(fn, rest, pool, bar)
    finally:
        bar.close()
