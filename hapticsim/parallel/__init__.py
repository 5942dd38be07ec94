"""The one parallel layer of hapticsim: keyed seeds and executors that map a function over tasks.

Every sweep (``hapticsim reproduce``, the policy comparisons, the regression suites) runs its tasks
through an :class:`Executor`:

- :class:`SerialExecutor`: in this process, one task after the other (``workers=1``);
- :class:`ProcessExecutor`: local worker processes (``workers=N``);
- :class:`DaskExecutor`: a Dask distributed cluster (``scheduler="tcp://host:port"``, or
  ``"local:N"`` for a ``distributed.LocalCluster`` of N worker processes; extra ``dask``).

:func:`make_executor` picks one from the command-line options, :func:`parallel_map` is the
one-call form. Results come back in task order; every task draws its random numbers from its own
seed (:func:`seed_sequence`, :func:`key_of`) and runs with one BLAS/OpenMP thread, so results are
the same, bit for bit, whatever the engine and the worker count. A worker that dies (a crash in
native code, the out-of-memory killer, ``kill -9``) stops the run with a
:class:`~hapticsim.errors.WorkerDiedError` naming the task it was running.

This package sits at the bottom of the layout (standard library, numpy and tqdm only): any layer
may use it.
"""

from hapticsim.parallel.base import (
    THREAD_ENV_VARS,
    Executor,
    RemoteTraceback,
    limit_threads,
    resolve_workers,
)
from hapticsim.parallel.cluster import DaskExecutor, check_scheduler_address
from hapticsim.parallel.local import ProcessExecutor, SerialExecutor
from hapticsim.parallel.seeds import key_of, seed_sequence
from hapticsim.parallel.select import make_executor, parallel_map

__all__ = [
    "THREAD_ENV_VARS",
    "DaskExecutor",
    "Executor",
    "ProcessExecutor",
    "RemoteTraceback",
    "SerialExecutor",
    "check_scheduler_address",
    "key_of",
    "limit_threads",
    "make_executor",
    "parallel_map",
    "resolve_workers",
    "seed_sequence",
]
