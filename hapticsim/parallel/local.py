"""Engines on this machine: in this process, or on local worker processes.

:class:`ProcessExecutor` hands one task at a time to each worker process over a pipe and watches
the processes' sentinels, so it always knows which task a worker was running when it died.
(``concurrent.futures.ProcessPoolExecutor`` cannot tell: when one worker dies it fails every
pending task with the same ``BrokenProcessPool`` and terminates the other workers.)
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
import signal
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any

from hapticsim.errors import WorkerDiedError
from hapticsim.parallel.base import (
    Executor,
    R,
    RemoteTraceback,
    T,
    capped_thread_env,
    describe_exit,
    limit_threads,
    resolve_workers,
)

#: Seconds a worker gets to exit after being asked to, before it is terminated.
STOP_TIMEOUT: float = 2.0
#: Seconds between an idle worker's checks that its parent is still alive.
ORPHAN_CHECK: float = 1.0


class SerialExecutor(Executor[T, R]):
    """Runs the tasks in this process, one after the other (same results, easiest to debug).

    BLAS/OpenMP pools are capped at one thread while the tasks run, as in the worker processes
    of the other engines, so that results do not depend on the engine.
    """

    kind = "serial"

    @property
    def workers(self) -> int:  # noqa: D102
        return 1

    def _run(
        self,
        func: Callable[[T], R],
        tasks: Sequence[T],
        order: Sequence[int],
        name_of: Callable[[int], str],
        started: Callable[[], None],
        done: Callable[[int, R], None],
    ) -> None:
        from threadpoolctl import threadpool_limits

        started()
        with threadpool_limits(limits=1):
            for i in order:
                done(i, func(tasks[i]))


@dataclass
class _Worker:
    process: Any  # multiprocessing process
    conn: Connection
    task: int | None = None


def _portable(exc: BaseException) -> BaseException:
    """`exc` if it survives pickling, else a RuntimeError carrying its type and message."""
    try:
        pickle.loads(pickle.dumps(exc))
    except Exception:
        return RuntimeError(f"{type(exc).__name__}: {exc}")
    return exc


def _worker_main(conn: Connection) -> None:
    """Loop of a worker process: receive ``(index, func, task)``, send ``(index, ok, payload)``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    limit_threads()
    parent = os.getppid()
    while True:
        try:
            # A parent killed outright (SIGKILL, the out-of-memory killer) closes no pipe that
            # a forked sibling still holds a copy of, so recv() alone would wait for ever: an
            # idle worker whose parent is gone (it was re-parented) exits.
            while not conn.poll(ORPHAN_CHECK):
                if os.getppid() != parent:
                    return
            message = conn.recv()
        except (EOFError, OSError):
            return
        if message is None:
            return
        index, func, task = message
        try:
            reply: tuple[int, bool, Any] = (index, True, func(task))
        except BaseException as exc:  # noqa: BLE001 - everything goes back to the parent
            reply = (index, False, (_portable(exc), traceback.format_exc()))
        try:
            conn.send(reply)
        except Exception as exc:  # an unpicklable result: report it instead
            conn.send((index, False, (_portable(exc), traceback.format_exc())))


class ProcessExecutor(Executor[T, R]):
    """Runs the tasks on local worker processes, one task per worker at a time.

    Workers start for each :meth:`map` and stop at its end; each runs with one BLAS/OpenMP
    thread. With a single task (or ``workers == 1``) the work still goes to one worker process.

    Args:
        workers: number of worker processes, default ``os.cpu_count()``.
        start_method: ``multiprocessing`` start method (``"fork"``, ``"spawn"``,
            ``"forkserver"``); default the platform's.
    """

    kind = "processes"

    def __init__(self, workers: int | None = None, start_method: str | None = None) -> None:
        self._workers = resolve_workers(workers)
        self._context = multiprocessing.get_context(start_method)

    @property
    def workers(self) -> int:  # noqa: D102
        return self._workers

    def _run(
        self,
        func: Callable[[T], R],
        tasks: Sequence[T],
        order: Sequence[int],
        name_of: Callable[[int], str],
        started: Callable[[], None],
        done: Callable[[int, R], None],
    ) -> None:
        pool: list[_Worker] = []
        finished = False
        try:
            with capped_thread_env():  # children inherit the caps before loading BLAS
                for _ in range(min(self._workers, len(order))):
                    parent, child = self._context.Pipe()
                    process = self._context.Process(
                        target=_worker_main, args=(child,), daemon=True, name="hapticsim-worker"
                    )
                    process.start()
                    child.close()
                    pool.append(_Worker(process, parent))
            started()
            queue = iter(order)
            for worker in pool:
                self._feed(worker, queue, func, tasks, name_of)
            while True:
                busy = [w for w in pool if w.task is not None]
                if not busy:
                    break
                ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
                for worker in busy:
                    if worker.conn in ready or worker.process.sentinel in ready:
                        self._collect(worker, name_of, done)
                        self._feed(worker, queue, func, tasks, name_of)
            finished = True
        finally:
            _stop(pool, graceful=finished)

    @staticmethod
    def _feed(
        worker: _Worker,
        queue: Any,
        func: Callable[[T], R],
        tasks: Sequence[T],
        name_of: Callable[[int], str],
    ) -> None:
        """Give `worker` the next task of `queue`, if any."""
        if worker.task is not None:
            return
        index = next(queue, None)
        if index is None:
            return
        worker.task = index
        try:
            worker.conn.send((index, func, tasks[index]))
        except (BrokenPipeError, ConnectionResetError, EOFError):
            _died(worker, name_of)

    @staticmethod
    def _collect(
        worker: _Worker, name_of: Callable[[int], str], done: Callable[[int, R], None]
    ) -> None:
        """Read the reply of `worker` (or find it dead); re-raise a task's exception."""
        if not worker.conn.poll():
            if worker.process.is_alive():  # spurious wake-up
                return
            _died(worker, name_of)
        try:
            index, ok, payload = worker.conn.recv()
        except (EOFError, OSError):
            _died(worker, name_of)
        worker.task = None
        if ok:
            done(index, payload)
            return
        exc, text = payload
        raise exc from RemoteTraceback(f"\n(in the worker running {name_of(index)})\n{text}")


def _died(worker: _Worker, name_of: Callable[[int], str]) -> None:
    """Raise :class:`WorkerDiedError` for the task `worker` was running."""
    worker.process.join(STOP_TIMEOUT)
    how = describe_exit(worker.process.exitcode)
    name = name_of(worker.task) if worker.task is not None else "no task"
    raise WorkerDiedError(
        f"a worker process (pid {worker.process.pid}) died ({how}) while running {name}",
        task=name,
    )


def _stop(pool: list[_Worker], graceful: bool) -> None:
    """Stop the workers: ask them to exit (graceful) or terminate them at once."""
    for worker in pool:
        if graceful and worker.process.is_alive():
            try:
                worker.conn.send(None)
            except (BrokenPipeError, ConnectionResetError, EOFError, OSError):
                pass
    for worker in pool:
        if graceful:
            worker.process.join(STOP_TIMEOUT)
        if worker.process.is_alive():
            worker.process.terminate()
            worker.process.join(STOP_TIMEOUT)
        if worker.process.is_alive():  # pragma: no cover - ignored SIGTERM
            worker.process.kill()
            worker.process.join(STOP_TIMEOUT)
        worker.conn.close()
