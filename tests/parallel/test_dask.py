"""The Dask engine on a real ``distributed.LocalCluster`` with worker processes (extra ``dask``)."""

from __future__ import annotations

import socket
import sys
import threading
import time
from collections.abc import Iterator

import pytest

from hapticsim.errors import InvalidInputError, SchedulerError, WorkerDiedError
from hapticsim.parallel import DaskExecutor, RemoteTraceback, SerialExecutor
from tests.parallel.test_executors import _blas_threads, _die_on, _draw, _raise_on


def test_without_distributed_the_message_says_what_to_install(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import fails as if not installed
    with pytest.raises(SchedulerError, match=r"pip install 'hapticsim\[dask\]'"):
        DaskExecutor("local:1").map(_draw, [1], progress=False)


pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster() -> Iterator[DaskExecutor]:
    with DaskExecutor("local:2") as engine:  # ~1 s to start two worker processes
        yield engine


def test_local_cluster_gives_the_serial_results(cluster: DaskExecutor) -> None:
    tasks = list(range(10))
    serial = SerialExecutor().map(_draw, tasks, progress=False)
    remote = cluster.map(_draw, tasks, progress=False, cost=lambda k: k % 3)
    assert [r[:2] for r in remote] == [r[:2] for r in serial]
    assert {r[2] for r in remote} == {"1"}
    assert cluster.map(_blas_threads, [0, 1], progress=False) == [1, 1]
    assert cluster.workers == 2
    assert cluster.describe() == {"engine": "dask", "scheduler": "local:2", "workers": 2}


def test_a_task_error_arrives_with_its_type(cluster: DaskExecutor) -> None:
    with pytest.raises(InvalidInputError, match="must not be 2") as info:
        cluster.map(_raise_on, [1, 2, 3], names=["a", "b", "c"], progress=False)
    assert isinstance(info.value.__cause__, RemoteTraceback)
    assert "running b" in str(info.value.__cause__)


def test_connecting_by_address_to_a_running_scheduler(cluster: DaskExecutor) -> None:
    address = cluster._cluster.scheduler_address  # a real tcp:// scheduler on loopback
    with DaskExecutor(address) as engine:
        assert [r[:2] for r in engine.map(_draw, [4, 5], progress=False)] == [
            r[:2] for r in SerialExecutor().map(_draw, [4, 5], progress=False)
        ]


def test_a_worker_that_dies_is_named_with_its_task() -> None:
    names = [f"case c{k}" for k in range(8)]
    with DaskExecutor("local:2") as engine:
        with pytest.raises(WorkerDiedError) as info:
            engine.map(_die_on, list(range(8)), names=names, progress=False)
    assert info.value.task == "case c3"
    assert "died while running case c3" in str(info.value)


def test_an_unreachable_scheduler_is_one_clear_error() -> None:
    start = time.perf_counter()
    with pytest.raises(SchedulerError, match=r"cannot reach the Dask scheduler at tcp://127\.0"):
        DaskExecutor("tcp://127.0.0.1:9", timeout=1.0).map(_draw, [1], progress=False)
    assert time.perf_counter() - start < 15.0


@pytest.fixture
def impostor(request: pytest.FixtureRequest) -> Iterator[str]:
    """A loopback server that is not a Dask scheduler: it keeps silent, or answers like HTTP."""
    server = socket.create_server(("127.0.0.1", 0))
    held: list[socket.socket] = []

    def serve() -> None:
        try:
            conn, _ = server.accept()
        except OSError:  # closed before anyone came
            return
        held.append(conn)
        conn.recv(1024)  # Dask's handshake
        if request.param == "http":  # what a dashboard port or an HTTP proxy says
            conn.sendall(b"HTTP/1.0 400 Bad Request\r\nContent-Length: 0\r\n\r\n")

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    server.close()
    for conn in held:
        conn.close()


@pytest.mark.parametrize(
    ("impostor", "message"),
    [
        # distributed.Client alone waits for this one's handshake without end
        ("silent", "no Dask handshake within 1 s"),
        # ... and ends with a MemoryError traceback on this one (b"HTTP/1.0" read as a length)
        ("http", "is not a Dask scheduler (MemoryError in the handshake"),
    ],
    indirect=["impostor"],
)
def test_a_server_that_is_not_a_scheduler_is_one_clear_error(impostor: str, message: str) -> None:
    with pytest.raises(
        SchedulerError, match=rf"cannot reach the Dask scheduler at {impostor}: "
    ) as info:
        DaskExecutor(impostor, timeout=1.0).map(_draw, [1], progress=False)
    assert message in str(info.value)


def test_reproduce_and_policy_comparisons_give_the_same_results_on_dask(
    cluster: DaskExecutor,
) -> None:
    from hapticsim.envs.estimator import FitSchedule
    from hapticsim.envs.evaluation import compare_policies
    from hapticsim.experiments.fig4 import Fig4Config
    from hapticsim.experiments.trial import run_trial
    from hapticsim.parallel import parallel_map

    trials = Fig4Config(bodies=("cube",), methods=("LS", "nH"), runs=2, budget=600).trials()
    serial = parallel_map(run_trial, trials, workers=1, progress=False)
    remote = parallel_map(run_trial, trials, executor=cluster, progress=False)
    assert [(r.estimate, r.epsilon, r.theta) for r in remote] == [
        (r.estimate, r.epsilon, r.theta) for r in serial
    ]
    # compare_policies through a scheduler address (the LocalCluster's tcp:// scheduler)
    settings = {
        "episodes": 2, "progress": False, "backend": "analytic", "touch_budget": 3,
        "fit": FitSchedule(full_budget=1500, refine_budget=200, full_every=10),
    }  # fmt: skip
    here = compare_policies(["random", "uncertainty"], ["paper"], workers=1, **settings)
    address = cluster._cluster.scheduler_address
    there = compare_policies(["random", "uncertainty"], ["paper"], scheduler=address, **settings)

    def stable(episodes: tuple[dict, ...]) -> list[dict]:
        return [{k: v for k, v in e.items() if k != "step_seconds"} for e in episodes]

    assert stable(there.episodes) == stable(here.episodes)
