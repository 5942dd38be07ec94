"""The executor layer: same results on every local engine, errors and dead workers reported."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError, WorkerDiedError
from hapticsim.parallel import (
    DaskExecutor,
    ProcessExecutor,
    RemoteTraceback,
    SerialExecutor,
    check_scheduler_address,
    key_of,
    make_executor,
    parallel_map,
    resolve_workers,
    seed_sequence,
)


def _draw(key: int) -> tuple[int, float, str | None]:
    """A task: a random number from the task's own seed, and the BLAS thread cap it saw."""
    value = float(np.random.default_rng(seed_sequence(7, key)).normal())
    return key, value, os.environ.get("OPENBLAS_NUM_THREADS")


def _blas_threads(_: int) -> int:
    from threadpoolctl import threadpool_info

    return max((p["num_threads"] for p in threadpool_info()), default=1)


def _die_on(key: int) -> int:
    """A task whose worker dies on key 3 (as a crash in native code would kill it)."""
    if key == 3:
        os.kill(os.getpid(), signal.SIGKILL)
    time.sleep(0.05)
    return key


def _raise_on(key: int) -> int:
    if key == 2:
        raise InvalidInputError("`key` must not be 2")
    return key


class _Unpicklable(Exception):
    def __init__(self, a: int, b: int) -> None:
        super().__init__(f"{a}/{b}")
        self.lock = threading.Lock()  # locks do not pickle


def _raise_unpicklable(key: int) -> int:
    raise _Unpicklable(key, 1)


def test_seed_sequence_depends_on_root_and_key_only() -> None:
    a = np.random.default_rng(seed_sequence(3, 1, 2)).random(4)
    b = np.random.default_rng(seed_sequence(3, 1, 2)).random(4)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, np.random.default_rng(seed_sequence(3, 2, 1)).random(4))
    assert not np.array_equal(a, np.random.default_rng(seed_sequence(4, 1, 2)).random(4))


def test_key_of_is_canonical() -> None:
    assert key_of({"body": "cube", "run": 3}) == key_of({"run": 3, "body": "cube"})
    assert key_of({"body": "cube", "run": 3}) != key_of({"body": "cube", "run": 4})
    # Fixed value: the key must not depend on the Python process (hash seed, version).
    assert key_of({"a": 1}) == (2143115777, 763020636, 2423606233, 148392688)


def test_parallel_map_same_result_for_any_worker_count() -> None:
    tasks = list(range(12))
    serial = parallel_map(_draw, tasks, workers=1, progress=False)
    pooled = parallel_map(_draw, tasks, workers=2, progress=False, cost=lambda k: k % 5)
    assert [r[:2] for r in serial] == [r[:2] for r in pooled]
    assert [r[0] for r in pooled] == tasks  # task order, whatever the completion order
    assert {r[2] for r in pooled} == {"1"}  # workers run with one BLAS thread


def test_every_local_engine_caps_blas_threads() -> None:
    from hapticsim.data.bodies import get_body
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting import fit

    contacts = paper_dataset(get_body("cube"), rng=0)
    fit(contacts.points, contacts.normals, budget=300, rng=0)  # BLAS and numba loaded and used
    assert SerialExecutor().map(_blas_threads, [0], progress=False) == [1]
    assert ProcessExecutor(2).map(_blas_threads, [0, 1], progress=False) == [1, 1]


def test_parallel_map_propagates_errors_with_the_workers_traceback() -> None:
    with pytest.raises(InvalidInputError, match="must not be 2") as info:
        parallel_map(_raise_on, [1, 2, 3, 4], workers=2, progress=False)
    cause = info.value.__cause__
    assert isinstance(cause, RemoteTraceback)
    assert "task 1" in str(cause) and "_raise_on" in str(cause)
    with pytest.raises(InvalidInputError, match="must not be 2"):
        parallel_map(_raise_on, [1, 2, 3], workers=1, progress=False)


def test_an_exception_that_cannot_be_pickled_still_arrives() -> None:
    # both tasks fail: whichever reply reaches the parent first is raised
    with pytest.raises(RuntimeError, match="_Unpicklable: [01]/1"):
        ProcessExecutor(2).map(_raise_unpicklable, [0, 1], progress=False)


def test_a_worker_that_dies_is_named_with_its_task() -> None:
    names = [f"case c{k}" for k in range(8)]
    start = time.perf_counter()
    with pytest.raises(WorkerDiedError) as info:
        ProcessExecutor(2).map(_die_on, list(range(8)), names=names, progress=False)
    message = str(info.value)
    assert info.value.task == "case c3"
    assert "while running case c3" in message and "SIGKILL" in message
    assert time.perf_counter() - start < 20.0  # the other worker is stopped, nothing hangs


def test_a_worker_death_is_reported_with_the_default_name() -> None:
    with pytest.raises(WorkerDiedError, match="task 3 of sweep"):
        parallel_map(_die_on, list(range(6)), workers=2, progress=False, desc="sweep")


def test_a_pool_after_a_death_works_again() -> None:
    with pytest.raises(WorkerDiedError):
        parallel_map(_die_on, [3], workers=2, progress=False)
    assert parallel_map(_draw, [1, 2], workers=2, progress=False)[1][0] == 2


def test_names_must_match_the_tasks() -> None:
    with pytest.raises(InvalidInputError, match="one entry per task"):
        SerialExecutor().map(_draw, [1, 2], names=["a"], progress=False)


def test_empty_task_list() -> None:
    assert parallel_map(_draw, [], workers=2, progress=False) == []


def test_make_executor_picks_the_engine() -> None:
    assert isinstance(make_executor(1), SerialExecutor)
    assert isinstance(make_executor(2), ProcessExecutor)
    assert isinstance(make_executor(scheduler="local:2"), DaskExecutor)  # not connected yet
    with pytest.raises(InvalidInputError, match="not both"):
        make_executor(2, "local:2")
    with pytest.raises(InvalidInputError, match="workers"):
        make_executor(0)


@pytest.mark.parametrize("address", ["local:2", "tcp://127.0.0.1:8786", "tls://[::1]:8786"])
def test_scheduler_addresses_accepted(address: str) -> None:
    assert check_scheduler_address(address) == address


@pytest.mark.parametrize("address", ["local:0", "local", "127.0.0.1:8786", "http://h:1", "x"])
def test_scheduler_addresses_refused_with_the_accepted_forms(address: str) -> None:
    with pytest.raises(InvalidInputError, match="local:N"):
        check_scheduler_address(address)


def test_resolve_workers() -> None:
    assert resolve_workers(None) == (os.cpu_count() or 1)
    assert resolve_workers(3) == 3
    with pytest.raises(InvalidInputError, match="workers"):
        resolve_workers(0)
