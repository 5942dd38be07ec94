"""The executor interface, thread caps and the progress bar shared by every engine."""

from __future__ import annotations

import contextlib
import os
import signal
import sys
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Generic, TypeVar

from hapticsim._validate import positive_int
from hapticsim.errors import InvalidInputError

T = TypeVar("T")
R = TypeVar("R")

#: Environment variables that cap the thread pools of BLAS/OpenMP/numba builds.
THREAD_ENV_VARS: tuple[str, ...] = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "BLIS_NUM_THREADS",
    "NUMEXPR_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
    "NUMBA_NUM_THREADS",
)

#: How a task is named in messages: a sequence (one name per task) or a function of the task.
Names = Sequence[str] | Callable[[Any], str] | None


class RemoteTraceback(Exception):
    """The traceback of an exception raised in a worker, attached as its ``__cause__``."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text

    def __str__(self) -> str:
        return self.text


def resolve_workers(workers: int | None) -> int:
    """``workers`` checked (>= 1), or ``os.cpu_count()`` when None."""
    if workers is None:
        return max(1, os.cpu_count() or 1)
    return positive_int(workers, "workers")


def limit_threads() -> None:
    """Cap the BLAS/OpenMP/numba thread pools of this process at one thread.

    Sets the environment variables (read by libraries loaded later, and by child processes) and
    limits the pools already loaded through threadpoolctl. (numba's own pool is left alone: the
    kernels are not ``parallel=True``, and starting that pool would load an OpenMP runtime.)
    """
    for var in THREAD_ENV_VARS:
        os.environ[var] = "1"
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1)


@contextlib.contextmanager
def capped_thread_env() -> Iterator[None]:
    """Within the block, the thread-cap variables are "1" (for child processes started in it)."""
    saved = {var: os.environ.get(var) for var in THREAD_ENV_VARS}
    for var in THREAD_ENV_VARS:
        os.environ[var] = "1"
    try:
        yield
    finally:
        for var, value in saved.items():
            if value is None:
                os.environ.pop(var, None)
            else:
                os.environ[var] = value


def progress_bar(total: int, desc: str, unit: str, enabled: bool) -> Any:
    """A tqdm bar on stderr, or None when disabled."""
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc or None, file=sys.stderr, unit=unit, dynamic_ncols=True)


def namer(names: Names, tasks: Sequence[Any], desc: str) -> Callable[[int], str]:
    """A function from task index to the task's name in messages.

    Raises:
        InvalidInputError: a sequence of names whose length is not the number of tasks.
    """

    if names is None:
        label = f" of {desc}" if desc else ""
        return lambda i: f"task {i}{label}"
    if callable(names):
        func = names
        return lambda i: str(func(tasks[i]))
    listed = [str(n) for n in names]
    if len(listed) != len(tasks):
        raise InvalidInputError(
            f"`names` must have one entry per task ({len(tasks)}), got {len(listed)}"
        )
    return lambda i: listed[i]


def describe_exit(exitcode: int | None) -> str:
    """How a process ended, in words: "killed by signal SIGKILL", "exit status 1", ..."""

    if exitcode is None:
        return "it stopped answering"
    if exitcode < 0:
        try:
            return f"killed by signal {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"killed by signal {-exitcode}"
    return f"exit status {exitcode}"


class Executor(ABC, Generic[T, R]):
    """Maps a function over tasks; results in task order (the interface of every engine).

    An executor may hold resources (worker processes, a cluster connection): use it as a context
    manager, or call :meth:`close`. Every task runs with one BLAS/OpenMP thread.
    """

    #: Short name of the engine (``"serial"``, ``"processes"``, ``"dask"``).
    kind: str = "executor"

    @property
    @abstractmethod
    def workers(self) -> int:
        """How many tasks run at once."""

    def describe(self) -> dict[str, Any]:
        """The engine as JSON-ready data (for provenance records)."""
        return {"engine": self.kind, "workers": self.workers}

    def map(
        self,
        func: Callable[[T], R],
        tasks: Sequence[T],
        *,
        names: Names = None,
        desc: str = "",
        unit: str = "task",
        progress: bool = True,
        cost: Callable[[T], float] | None = None,
    ) -> list[R]:
        """``[func(t) for t in tasks]`` on this engine, with a tqdm bar on stderr.

        Args:
            func: a module-level (picklable) function of one task.
            tasks: the tasks, picklable.
            names: the tasks' names in messages (a worker that died names its task); one per
                task, or a function of the task. Default ``"task i of DESC"``.
            desc: label of the progress bar.
            unit: unit of the progress bar.
            progress: show the progress bar.
            cost: optional estimate of a task's run time; the most expensive tasks start first,
                which shortens the tail of the sweep. Changes no result.

        Returns:
            list of results, ``results[i] = func(tasks[i])``.

        Raises:
            WorkerDiedError: a worker died while running a task (the message names it).
            SchedulerError: the cluster was lost during the run.
            Exception: whatever a task raised, re-raised here with the worker's traceback as
                its ``__cause__``; the remaining tasks are cancelled.
        """
        tasks = list(tasks)
        name_of = namer(names, tasks, desc)
        order = list(range(len(tasks)))
        if cost is not None:
            order.sort(key=lambda i: -cost(tasks[i]))
        results: list[Any] = [None] * len(tasks)
        if not tasks:
            return results
        bar = None

        def done(index: int, result: R) -> None:
            results[index] = result
            if bar is not None:
                bar.update(1)

        def started() -> None:
            nonlocal bar
            bar = progress_bar(len(tasks), desc, unit, progress)

        try:
            self._run(func, tasks, order, name_of, started, done)
        except BaseException:
            if bar is not None:  # a failed run's bar disappears: its error is the one line
                bar.leave = False
            raise
        finally:
            if bar is not None:
                bar.close()
        return results

    @abstractmethod
    def _run(
        self,
        func: Callable[[T], R],
        tasks: Sequence[T],
        order: Sequence[int],
        name_of: Callable[[int], str],
        started: Callable[[], None],
        done: Callable[[int, R], None],
    ) -> None:
        """Run ``func(tasks[i])`` for i in `order` (start order); call `started` once the
        workers are up (the progress bar appears then) and ``done(i, result)`` per result."""

    def close(self) -> None:
        """Free the engine's resources (idempotent)."""

    def __enter__(self) -> Executor[T, R]:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
