"""The Dask engine: tasks on a ``distributed`` cluster (optional extra ``dask``).

``scheduler`` is either the address of a running scheduler (``tcp://host:8786``; its workers need
the same hapticsim and numpy versions as this process, which is checked) or ``local:N``, which
starts a ``distributed.LocalCluster`` of N single-threaded worker processes for the run.

On a LocalCluster, a worker that dies fails its task at once (``allowed-failures = 0``) and each
worker holds one task at a time (``worker-saturation = 1.0``), so the task named in the error is
the one that was running. A remote scheduler keeps its own settings: Dask retries a task whose
worker died (three times by default) before it gives up and names it.
"""

from __future__ import annotations

import logging
import platform
import re
import threading
import traceback
import uuid
from collections.abc import Callable, Sequence
from typing import Any

import numpy

from hapticsim._version import __version__
from hapticsim.errors import InvalidInputError, SchedulerError, WorkerDiedError
from hapticsim.parallel.base import Executor, R, RemoteTraceback, T, limit_threads

#: Default seconds to wait for a scheduler (and for its first worker).
DEFAULT_TIMEOUT: float = 10.0
#: Protocols of Dask scheduler addresses.
PROTOCOLS: tuple[str, ...] = ("tcp", "tls", "ws", "wss", "ucx", "inproc")
#: What the ``dask`` extra installs.
INSTALL_HINT: str = "pip install 'hapticsim[dask]'"

#: Dask settings of the worker processes of a ``local:N`` cluster. Dask's default
#: ``MALLOC_TRIM_THRESHOLD_=65536`` turns off glibc's adaptive mmap threshold, and every large
#: numpy temporary then costs fresh page faults: measured 1.5x the CPU time per fit-v1 case. The
#: statistical profiler (a thread sampling every 10 ms) costs another ~10 %. For a remote
#: cluster, set the same when starting the workers, e.g.
#: ``DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False`` and no ``MALLOC_TRIM_THRESHOLD_``.
LOCAL_WORKER_SETTINGS: dict[str, object] = {
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
    "distributed.worker.profile.enabled": False,
}

_LOCAL = re.compile(r"local:(\d+)")
_REMOTE = re.compile(r"(?P<proto>[a-z]+)://(?P<host>[^/:]*|\[[^\]]*\]):(?P<port>\d+)/?")

_WORKER_LOCK = threading.Lock()
_WORKER_READY = False


def check_scheduler_address(address: str) -> str:
    """`address` if it is ``local:N`` (N >= 1) or ``PROTOCOL://host:port``.

    Raises:
        InvalidInputError: any other text; the message shows the accepted forms.
    """
    if isinstance(address, str):
        local = _LOCAL.fullmatch(address)
        if local and int(local.group(1)) >= 1:
            return address
        remote = _REMOTE.fullmatch(address)
        if remote and remote.group("proto") in PROTOCOLS:
            return address
    raise InvalidInputError(
        "`scheduler` must be 'local:N' (N >= 1 worker processes) or a Dask scheduler address "
        f"such as tcp://127.0.0.1:8786 (protocols {', '.join(PROTOCOLS)}), got {address!r}"
    )


def _probe(address: str, timeout: float) -> None:
    """Connect to `address` and exchange Dask's handshake, all within `timeout` seconds.

    ``distributed.Client`` waits without limit for the handshake of a server that accepts the
    connection but never answers (any service on the port that waits for its own protocol, such
    as ``python -m http.server``), and fails deep inside with a traceback on one that answers
    otherwise (an HTTP proxy or a Dask dashboard: its ``HTTP/1.0`` read as a frame length of
    3.5e18 bytes is a MemoryError). The probe runs in a thread of its own, so that it works from
    inside a running event loop (a notebook) too.

    Raises:
        SchedulerError: nothing listens, no answer in time, or an answer that is not Dask's.
    """
    import asyncio

    from distributed.comm import connect
    from distributed.security import Security

    outcome: dict[str, BaseException | None] = {}

    async def handshake() -> None:
        args = Security().get_connection_args("client")
        comm = await asyncio.wait_for(connect(address, timeout=timeout, **args), timeout + 1.0)
        comm.abort()

    def attempt() -> None:
        try:
            asyncio.run(handshake())
            outcome["error"] = None
        except BaseException as exc:  # noqa: BLE001 - reported below, in the caller's thread
            outcome["error"] = exc

    thread = threading.Thread(target=attempt, name="hapticsim-dask-probe", daemon=True)
    thread.start()
    thread.join(timeout + 5.0)
    if "error" not in outcome or isinstance(outcome["error"], TimeoutError):
        raise SchedulerError(
            f"cannot reach the Dask scheduler at {address}: no Dask handshake within "
            f"{timeout:g} s (is a Dask scheduler listening there?)"
        )
    error = outcome["error"]
    if isinstance(error, OSError):
        detail = " ".join(str(error).split()) or type(error).__name__
        raise SchedulerError(f"cannot reach the Dask scheduler at {address}: {detail}")
    if error is not None:
        raise SchedulerError(
            f"cannot reach the Dask scheduler at {address}: what answers there is not a Dask "
            f"scheduler ({type(error).__name__} in the handshake; a Dask dashboard or another "
            "service?)"
        )


def _call(func: Callable[[T], R], task: T) -> R:
    """Run one task on a Dask worker: one BLAS thread, one task of ours at a time per process.

    The lock keeps a worker with several threads from running two tasks of ours at once (they
    share per-process caches); give workers one thread (``dask worker ... --nthreads 1``) and
    start more of them instead.
    """
    global _WORKER_READY
    with _WORKER_LOCK:
        if not _WORKER_READY:
            limit_threads()
            _WORKER_READY = True
        return func(task)


def _versions() -> dict[str, str]:
    """What must match between this process and the workers for identical results."""

    import scipy

    return {
        "hapticsim": __version__,
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "python": platform.python_version(),
    }


class DaskExecutor(Executor[T, R]):
    """Runs the tasks on a Dask distributed cluster.

    The connection is made on entering the context (or at the first :meth:`map`) and closed by
    :meth:`close`; a ``local:N`` cluster lives as long as the executor.

    Args:
        scheduler: ``local:N`` or a scheduler address (:func:`check_scheduler_address`).
        timeout: seconds to wait for the scheduler and for its first worker.

    Raises:
        InvalidInputError: a malformed address.
    """

    kind = "dask"

    def __init__(self, scheduler: str, timeout: float = DEFAULT_TIMEOUT) -> None:
        self.scheduler = check_scheduler_address(scheduler)
        if not timeout > 0:
            raise InvalidInputError(f"`timeout` must be > 0 [s], got {timeout!r}")
        self.timeout = float(timeout)
        self._client: Any = None
        self._cluster: Any = None

    # ------------------------------------------------------------------ connection
    def _connect(self) -> Any:
        if self._client is not None:
            return self._client
        try:
            import dask
            from distributed import Client, LocalCluster
        except ImportError:
            raise SchedulerError(
                f"--scheduler {self.scheduler} needs the Dask `distributed` package: {INSTALL_HINT}"
            ) from None
        local = _LOCAL.fullmatch(self.scheduler)
        try:
            if local:
                settings = {
                    "distributed.scheduler.allowed-failures": 0,
                    "distributed.scheduler.worker-saturation": 1.0,
                    **LOCAL_WORKER_SETTINGS,
                }
                with dask.config.set(settings):
                    self._cluster = LocalCluster(
                        n_workers=int(local.group(1)), threads_per_worker=1, processes=True,
                        dashboard_address=":0", silence_logs=logging.CRITICAL,
                    )  # fmt: skip
                self._client = Client(self._cluster, set_as_default=False)
            else:
                if not self.scheduler.startswith("inproc://"):  # in-process: nothing to probe
                    _probe(self.scheduler, self.timeout)
                self._client = Client(self.scheduler, timeout=self.timeout, set_as_default=False)
                self._client.wait_for_workers(1, timeout=self.timeout)
        except (OSError, TimeoutError) as exc:
            self.close()
            what = "start a LocalCluster" if local else "reach the Dask scheduler at"
            where = "" if local else f" {self.scheduler}"
            detail = " ".join(str(exc).split()) or type(exc).__name__
            raise SchedulerError(f"cannot {what}{where}: {detail}") from None
        self._check_versions()
        return self._client

    def _check_versions(self) -> None:
        mine = _versions()
        theirs = self._client.run(_versions)
        for address, versions in theirs.items():
            if versions != mine:
                differ = ", ".join(
                    f"{k} {versions.get(k)} (here {v})" for k, v in mine.items()
                    if versions.get(k) != v
                )  # fmt: skip
                self.close()
                raise SchedulerError(
                    f"the Dask worker {address} runs {differ}: install the same versions on "
                    "every worker, or results would differ"
                )

    @property
    def workers(self) -> int:  # noqa: D102
        if self._client is None:
            local = _LOCAL.fullmatch(self.scheduler)
            return int(local.group(1)) if local else 0
        info = self._client.scheduler_info(n_workers=-1)
        return int(sum(w.get("nthreads", 1) for w in info["workers"].values()))

    def describe(self) -> dict[str, Any]:  # noqa: D102
        return {"engine": self.kind, "scheduler": self.scheduler, "workers": self.workers}

    def __enter__(self) -> DaskExecutor[T, R]:
        self._connect()
        return self

    def close(self) -> None:  # noqa: D102
        client, cluster = self._client, self._cluster
        self._client = self._cluster = None
        for thing in (client, cluster):
            if thing is not None:
                try:
                    thing.close()
                except Exception:  # noqa: BLE001 - closing is best effort
                    pass

    # ------------------------------------------------------------------ mapping
    def _run(
        self,
        func: Callable[[T], R],
        tasks: Sequence[T],
        order: Sequence[int],
        name_of: Callable[[int], str],
        started: Callable[[], None],
        done: Callable[[int, R], None],
    ) -> None:
        client = self._connect()
        from distributed import as_completed
        from distributed.scheduler import KilledWorker

        token = uuid.uuid4().hex[:12]
        index_of: dict[str, int] = {}
        queue = iter(enumerate(order))
        futures: list[Any] = []

        def submit() -> Any:
            item = next(queue, None)
            if item is None:
                return None
            rank, i = item
            key = f"hapticsim-{token}-{i}"
            index_of[key] = i
            future = client.submit(_call, func, tasks[i], key=key, pure=False, priority=-rank)
            futures.append(future)
            return future

        # One task in flight per worker thread: a worker that dies was running exactly one of
        # ours, so the error names the right task (and the expensive-first order holds).
        pending = as_completed([], loop=client.loop)
        for _ in range(max(1, self.workers)):
            future = submit()
            if future is not None:
                pending.add(future)
        started()
        try:
            for future in pending:
                i = index_of[future.key]
                if future.status == "error":
                    exc = future.exception()
                    if isinstance(exc, KilledWorker):
                        raise WorkerDiedError(
                            f"a Dask worker ({exc.last_worker.address}) died while running "
                            f"{name_of(i)}",
                            task=name_of(i),
                        ) from None
                    text = "".join(_format_traceback(future.traceback()))
                    raise exc from RemoteTraceback(f"\n(on Dask, running {name_of(i)})\n{text}")
                if future.status != "finished":
                    raise SchedulerError(
                        f"the Dask scheduler at {self.scheduler} dropped {name_of(i)} "
                        f"({future.status}): the connection was lost"
                    )
                done(i, future.result())
                future.release()
                following = submit()
                if following is not None:
                    pending.add(following)
        finally:
            unfinished = [f for f in futures if f.status not in ("finished", "lost")]
            if unfinished:
                try:
                    client.cancel(unfinished)
                except Exception:  # noqa: BLE001 - the run already failed
                    pass


def _format_traceback(tb: Any) -> list[str]:
    return traceback.format_tb(tb) if tb is not None else []
