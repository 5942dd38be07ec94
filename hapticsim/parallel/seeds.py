"""Seeds of tasks, keyed by what a task is rather than by where it sits in a sweep.

A task's seed is ``SeedSequence(root, spawn_key=key)``; the key names the task (which figure,
body, noise level, run, method; or a suite case's parameters through :func:`key_of`). It depends
on nothing else, so results are the same with 1 worker or 16, in any order of completion, and a
task keeps its seed when other tasks are added to or removed from the sweep.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

import numpy as np

#: 32-bit words of a :func:`key_of` key (128 bits of SHA-256: collisions are out of reach).
KEY_WORDS: int = 4


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


def key_of(params: Mapping[str, Any]) -> tuple[int, ...]:
    """A seed key from named parameters: SHA-256 of their canonical JSON, as 32-bit words.

    The key depends on the names and values only (not on their order, the Python version or
    ``PYTHONHASHSEED``): ``{"body": "cube", "run": 3}`` gives the same key in every process.

    Args:
        params: JSON-serialisable parameters (str, int, float, bool, None, lists of them).

    Returns:
        :data:`KEY_WORDS` non-negative ints, for :func:`seed_sequence`.
    """
    text = json.dumps(dict(params), sort_keys=True, separators=(",", ":"))
    digest = hashlib.sha256(text.encode()).digest()
    return tuple(int.from_bytes(digest[4 * i : 4 * i + 4], "little") for i in range(KEY_WORDS))
