"""Seeds and the process-parallel map: results independent of the worker count."""

from __future__ import annotations

import os

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.parallel import parallel_map, resolve_workers, seed_sequence


def _draw(key: int) -> tuple[int, float, str | None]:
    """A task: a random number from the task's own seed, and the BLAS thread cap it saw."""
    value = float(np.random.default_rng(seed_sequence(7, key)).normal())
    return key, value, os.environ.get("OPENBLAS_NUM_THREADS")


def test_seed_sequence_depends_on_root_and_key_only() -> None:
    a = np.random.default_rng(seed_sequence(3, 1, 2)).random(4)
    b = np.random.default_rng(seed_sequence(3, 1, 2)).random(4)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, np.random.default_rng(seed_sequence(3, 2, 1)).random(4))
    assert not np.array_equal(a, np.random.default_rng(seed_sequence(4, 1, 2)).random(4))


def test_parallel_map_same_result_for_any_worker_count() -> None:
    tasks = list(range(12))
    serial = parallel_map(_draw, tasks, workers=1, progress=False)
    pooled = parallel_map(_draw, tasks, workers=2, progress=False, cost=lambda k: k % 5)
    assert [r[:2] for r in serial] == [r[:2] for r in pooled]
    assert [r[0] for r in pooled] == tasks  # task order, whatever the completion order
    assert {r[2] for r in pooled} == {"1"}  # workers run with one BLAS thread


def test_parallel_map_propagates_errors() -> None:
    with pytest.raises(InvalidInputError):
        parallel_map(resolve_workers, [1, 0, 2], workers=2, progress=False)


def test_resolve_workers() -> None:
    assert resolve_workers(None) == (os.cpu_count() or 1)
    assert resolve_workers(3) == 3
    with pytest.raises(InvalidInputError, match="workers"):
        resolve_workers(0)
