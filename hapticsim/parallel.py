"""Deterministic seeds and a process-parallel map with a progress bar, for the paper's sweeps.

Every task of a sweep gets its own seed, derived from the root seed and the task's *key* (which
figure, body, noise level, run, method, budget) through :class:`numpy.random.SeedSequence`. The
seed depends on nothing else, so results are the same with 1 worker or 16, in any order of
completion.

Workers are local processes (:class:`concurrent.futures.ProcessPoolExecutor`); each limits BLAS
and OpenMP to one thread, so two workers on two cores do not oversubscribe them.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import TypeVar

import numpy as np

from hapticsim._validate import positive_int

T = TypeVar("T")
R = TypeVar("R")

#: Environment variables that cap the thread pools of BLAS/OpenMP builds.
THREAD_ENV_VARS: tuple[str, ...] = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "BLIS_NUM_THREADS",
    "NUMEXPR_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
)


def seed_sequence(root: int, *key: int) -> np.random.SeedSequence:
    """The seed of one task: ``SeedSequence(root, spawn_key=key)``.

    Two different keys give independent streams; the same (root, key) gives the same stream in
    any process.

    Args:
        root: the user's seed (``--seed``), >= 0.
        *key: non-negative ints naming the task (e.g. figure, body index, run, method index).

    Returns:
        numpy.random.SeedSequence, to pass to :func:`numpy.random.default_rng`.
    """
    return np.random.SeedSequence(int(root), spawn_key=tuple(int(k) for k in key))


def resolve_workers(workers: int | None) -> int:
    """``workers`` checked (>= 1), or ``os.cpu_count()`` when None."""
    if workers is None:
        return max(1, os.cpu_count() or 1)
    return positive_int(workers, "workers")


def limit_threads() -> None:
    """Cap BLAS/OpenMP thread pools of this process at one thread.

    Sets the environment variables (read by libraries loaded later, and by child processes) and
    limits the pools already loaded through threadpoolctl.
    """
    for var in THREAD_ENV_VARS:
        os.environ[var] = "1"
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl is a dependency
        return
    threadpool_limits(limits=1)


def _progress(total: int, desc: str, enabled: bool):  # noqa: ANN202 - tqdm or None
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, file=sys.stderr, unit="fit", dynamic_ncols=True)


def parallel_map(
    func: Callable[[T], R],
    tasks: Sequence[T],
    workers: int | None = None,
    desc: str = "",
    progress: bool = True,
    cost: Callable[[T], float] | None = None,
) -> list[R]:
    """``[func(t) for t in tasks]``, on local processes, with a tqdm bar on stderr.

    The result list is in task order whatever the order of completion. With ``workers == 1`` the
    tasks run in this process (same results, easier to debug).

    Args:
        func: a picklable (module-level) function of one task.
        tasks: the tasks, picklable.
        workers: number of processes, default ``os.cpu_count()``.
        desc: label of the progress bar.
        progress: show the progress bar.
        cost: optional estimate of a task's run time; the most expensive tasks are started first,
            which shortens the tail of the sweep. Does not change any result.

    Returns:
        list of results, ``results[i] = func(tasks[i])``.
    """
    n_workers = min(resolve_workers(workers), max(1, len(tasks)))
    order = list(range(len(tasks)))
    if cost is not None:
        order.sort(key=lambda i: -cost(tasks[i]))
    results: list[R | None] = [None] * len(tasks)
    bar = _progress(len(tasks), desc, progress)
    try:
        if n_workers == 1:
            for i in order:
                results[i] = func(tasks[i])
                if bar is not None:
                    bar.update(1)
        else:
            _run_pool(func, tasks, order, n_workers, results, bar)
    finally:
        if bar is not None:
            bar.close()
    return results  # type: ignore[return-value]


def _run_pool(
    func: Callable[[T], R],
    tasks: Sequence[T],
    order: list[int],
    n_workers: int,
    results: list[R | None],
    bar,  # noqa: ANN001 - tqdm or None
) -> None:
    # Children inherit the environment: set the caps before they start.
    saved = {var: os.environ.get(var) for var in THREAD_ENV_VARS}
    for var in THREAD_ENV_VARS:
        os.environ[var] = "1"
    try:
        with ProcessPoolExecutor(max_workers=n_workers, initializer=limit_threads) as pool:
            # Keep a bounded number of tasks in flight so the expensive-first order holds.
            pending: dict[Future[R], int] = {}
            queue = iter(order)
            for i in queue:
                pending[pool.submit(func, tasks[i])] = i
                if len(pending) >= 2 * n_workers:
                    break
            try:
                while pending:
                    done, _ = wait(pending, return_when=FIRST_COMPLETED)
                    for future in done:
                        results[pending.pop(future)] = future.result()
                        if bar is not None:
                            bar.update(1)
                        nxt = next(queue, None)
                        if nxt is not None:
                            pending[pool.submit(func, tasks[nxt])] = nxt
            except BaseException:
                pool.shutdown(wait=True, cancel_futures=True)
                raise
    finally:
        for var, value in saved.items():
            if value is None:
                os.environ.pop(var, None)
            else:
                os.environ[var] = value
