"""One episode of a policy in the environment, and the summary of many: epsilon, IoU and
contacts after each touch (``hapticsim policies evaluate``, the comparisons, the suites)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.envs.policies import Observation, Policy

Array = NDArray[np.float64]


@dataclass(frozen=True)
class EpisodeRecord:
    """One episode of a policy.

    Attributes:
        epsilon: (T,) float, epsilon after each touch (1 before the first fit).
        iou: (T,) float, IoU after each touch.
        n_contacts: (T,) int, contacts after each touch.
        step_seconds: (T,) float, wall-clock time of each step [s].
        ret: the episode's return.
    """

    epsilon: Array
    iou: Array
    n_contacts: NDArray[np.int64]
    step_seconds: Array
    ret: float


def run_episode(
    env: Any,
    policy: Policy | Callable[[Observation], np.ndarray],
    seed: int,
    policy_seed: int | None = None,
    options: dict[str, Any] | None = None,
) -> EpisodeRecord:
    """Run one episode to its end and record the metrics after each touch.

    Args:
        env: the environment (compute_metrics on).
        policy: a :class:`Policy` (reset with `policy_seed`) or any callable obs -> action.
        seed: the environment's seed (selects the object, noise and fits).
        policy_seed: seed of the policy's own randomness (default: `seed`).
        options: passed to ``env.reset``.
    """
    obs, _ = env.reset(seed=seed, options=options)
    if isinstance(policy, Policy):
        policy.reset(seed if policy_seed is None else policy_seed)
    eps: list[float] = []
    iou: list[float] = []
    count: list[int] = []
    secs: list[float] = []
    ret = 0.0
    done = False
    while not done:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        ret += float(reward)
        eps.append(info["epsilon"])
        iou.append(info["iou"])
        count.append(info["n_contacts"])
        secs.append(info["timings"].step)
        done = terminated or truncated
    return EpisodeRecord(
        np.asarray(eps), np.asarray(iou), np.asarray(count, dtype=np.int64), np.asarray(secs), ret
    )


def summarize(records: Sequence[EpisodeRecord], budget: int) -> dict[str, Array]:
    """Mean, standard deviation, median and quartiles of epsilon after N = 1..budget touches.

    Episodes that ended early keep their last epsilon.

    Returns:
        dict of (budget,) arrays: ``mean``, ``std``, ``median``, ``q25``, ``q75``.
    """
    table = np.empty((len(records), budget))
    for i, r in enumerate(records):
        e = r.epsilon[:budget]
        table[i, : len(e)] = e
        table[i, len(e) :] = e[-1] if len(e) else 1.0
    return {
        "mean": table.mean(axis=0),
        "std": table.std(axis=0),
        "median": np.median(table, axis=0),
        "q25": np.quantile(table, 0.25, axis=0),
        "q75": np.quantile(table, 0.75, axis=0),
    }


__all__ = ["EpisodeRecord", "run_episode", "summarize"]
