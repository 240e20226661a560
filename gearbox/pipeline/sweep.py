"""Sweeps (speeds, torques, design variants) through a ``concurrent.futures.Executor``.

:func:`map_items` runs ``fn(item)`` for every item and returns the results in the
order of ``items``. It accepts any executor with ``submit``: the default is a
``ProcessPoolExecutor`` on the machine's cores (started with the ``spawn`` method,
since forking a process that has started jax's or BLAS's threads can deadlock); a
cluster takes the sweep through Dask's executor::

    from dask.distributed import Client
    client = Client("scheduler-address:8786")
    map_items(fn, items, executor=client.get_executor())

``fn`` and the items must then be picklable: a module-level function, not a lambda.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterable
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from typing import Any

__all__ = ["default_jobs", "map_items"]


def default_jobs() -> int:
    """Worker processes of the default executor: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def map_items(
    fn: Callable[[Any], Any],
    items: Iterable[Any],
    *,
    executor: Executor | None = None,
    jobs: int | None = None,
    progress: bool = False,
    desc: str = "",
) -> list[Any]:
    """``[fn(x) for x in items]``, in parallel.

    Parameters
    ----------
    executor : concurrent.futures.Executor, optional
        Used as given and not shut down. Default: a new ``ProcessPoolExecutor`` with
        ``jobs`` workers, shut down on return.
    jobs : int, optional
        Workers of the default executor (default :func:`default_jobs`). ``jobs=1``
        without an executor runs in this process, one item after the other.
    progress : bool
        Show a tqdm progress bar on stderr.
    """
    items = list(items)
    from tqdm.auto import tqdm

    bar = tqdm(total=len(items), desc=desc or None, disable=not progress, leave=False)
    try:
        if executor is None and (jobs == 1 or len(items) <= 1):
            out = []
            for x in items:
                out.append(fn(x))
                bar.update()
            return out
        own = executor is None
        if own:
            n = min(jobs or default_jobs(), len(items))
            executor = ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("spawn"))
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
        finally:
            if own:
                executor.shutdown(wait=True, cancel_futures=True)
    finally:
        bar.close()
