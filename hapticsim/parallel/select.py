"""Choosing an engine from the command-line options (``--workers N | --scheduler ADDRESS``)."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from hapticsim.errors import InvalidInputError
from hapticsim.parallel.base import Executor, Names, R, T, resolve_workers
from hapticsim.parallel.cluster import DEFAULT_TIMEOUT, DaskExecutor
from hapticsim.parallel.local import ProcessExecutor, SerialExecutor


def make_executor(
    workers: int | None = None,
    scheduler: str | None = None,
    timeout: float = DEFAULT_TIMEOUT,
) -> Executor:
    """The engine for ``--workers N`` or ``--scheduler ADDRESS`` (not both).

    Args:
        workers: local processes (1: in this process); default ``os.cpu_count()``.
        scheduler: a Dask address, ``tcp://host:port`` or ``local:N``
            (:class:`~hapticsim.parallel.DaskExecutor`).
        timeout: seconds to wait for a Dask scheduler.

    Returns:
        a :class:`~hapticsim.parallel.SerialExecutor`, :class:`~hapticsim.parallel.ProcessExecutor`
        or :class:`~hapticsim.parallel.DaskExecutor` (not yet connected).

    Raises:
        InvalidInputError: both given, workers < 1, or a malformed scheduler address.
    """
    if scheduler is not None:
        if workers is not None:
            raise InvalidInputError(
                "give either `workers` (local processes) or `scheduler` (a Dask cluster), not "
                f"both: got workers={workers!r} and scheduler={scheduler!r}"
            )
        return DaskExecutor(scheduler, timeout=timeout)
    n = resolve_workers(workers)
    return SerialExecutor() if n == 1 else ProcessExecutor(n)


def parallel_map(
    func: Callable[[T], R],
    tasks: Sequence[T],
    workers: int | None = None,
    desc: str = "",
    progress: bool = True,
    cost: Callable[[T], float] | None = None,
    *,
    names: Names = None,
    unit: str = "task",
    scheduler: str | None = None,
    executor: Executor | None = None,
) -> list[R]:
    """``[func(t) for t in tasks]`` on the chosen engine, with a tqdm bar on stderr.

    Args:
        func: a module-level (picklable) function of one task.
        tasks: the tasks, picklable.
        workers: local processes (1: in this process), default ``os.cpu_count()``.
        desc: label of the progress bar.
        progress: show the progress bar.
        cost: optional run-time estimate; expensive tasks start first (no effect on results).
        names: the tasks' names in messages (see :meth:`Executor.map`).
        unit: unit of the progress bar.
        scheduler: run on a Dask cluster instead (``tcp://host:port`` or ``local:N``).
        executor: an engine to use (and leave open) instead of `workers`/`scheduler`.

    Returns:
        list of results, ``results[i] = func(tasks[i])``, whatever the engine.
    """
    kwargs = {"names": names, "desc": desc, "unit": unit, "progress": progress, "cost": cost}
    if executor is not None:
        return executor.map(func, tasks, **kwargs)
    with make_executor(workers, scheduler) as engine:
        return engine.map(func, tasks, **kwargs)
