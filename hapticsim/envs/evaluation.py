"""Policies evaluated over many episodes: epsilon after N touches, paired across policies.

:func:`compare_policies` runs every (policy, object set, episode) through the executor layer
(:mod:`hapticsim.parallel`: local processes or a Dask cluster; seeds depend only on the episode,
so results do not depend on the engine or the worker count, and every policy meets the same
objects, noise and rough positions). :func:`evaluate_policy` is one policy on one object set,
as ``hapticsim policies evaluate`` prints it (SPEC §6). The report writer (tables, plot) is the
lab's (``lab.benchmarks.comparison``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import positive_int
from hapticsim.errors import ChoiceError, InvalidInputError

Array = NDArray[np.float64]

@dataclass(frozen=True)
class ComparisonTask:
    """One episode of the comparison (picklable, for the worker processes).

    Attributes:
        policy: policy name (:data:`hapticsim.envs.policies.POLICY_NAMES` or ``learned:PATH``).
        objects: object distribution kind.
        episode: episode index; the environment's seed is ``seed + episode``.
        seed: root seed.
        env_kwargs: keyword arguments of the environment (backend, budget, ...).
        fresh_env: run the episode in a new environment instead of the worker's cached one
            (then an episode's numbers do not depend on which episodes its worker ran before:
            the environment scores the first episode of an instance with differently drawn
            Monte Carlo samples, about 0.003 in epsilon, than the later ones).
    """

    policy: str
    objects: str
    episode: int
    seed: int
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    fresh_env: bool = False

    @property
    def label(self) -> str:
        """The episode in messages, e.g. ``"episode 3 of policy random on paper objects"``."""
        return f"episode {self.episode} of policy {self.policy} on {self.objects} objects"


_ENVS: dict[tuple, Any] = {}


def run_task(task: ComparisonTask) -> dict[str, Any]:
    """Run one episode; returns epsilon, IoU, contacts and step times after each touch."""
    from hapticsim.envs.episodes import run_episode
    from hapticsim.envs.haptic_explore_tactile_v0 import make_v0
    from hapticsim.envs.policies import make_policy

    key = (task.objects, tuple(sorted(task.env_kwargs.items())))
    env = None if task.fresh_env else _ENVS.get(key)
    if env is None:  # one environment per worker and setting, reused across episodes
        env = make_v0(objects=task.objects, **task.env_kwargs)
        if not task.fresh_env:
            _ENVS[key] = env
    seed = task.seed + task.episode
    policy = make_policy(task.policy, env, rng=seed)
    record = run_episode(env, policy, seed=seed, policy_seed=seed)
    if task.fresh_env:
        env.close()
    return {
        "policy": task.policy,
        "objects": task.objects,
        "episode": task.episode,
        "epsilon": record.epsilon.tolist(),
        "iou": record.iou.tolist(),
        "n_contacts": record.n_contacts.tolist(),
        "step_seconds": record.step_seconds.tolist(),
        "truth": env.unwrapped.truth.to_dict() if env.unwrapped.truth is not None else None,
    }


@dataclass(frozen=True)
class Comparison:
    """Results of :func:`compare_policies`.

    Attributes:
        policies: policy names, in order.
        object_sets: object distribution kinds, in order.
        budget: touches per episode.
        episodes: raw per-episode results (dicts from :func:`run_task`).
        settings: the environment settings and seed, for the record.
    """

    policies: tuple[str, ...]
    object_sets: tuple[str, ...]
    budget: int
    episodes: tuple[dict[str, Any], ...]
    settings: dict[str, Any]

    def epsilon(self, policy: str, objects: str) -> Array:
        """(episodes, budget) float, epsilon after each touch (padded with the last value)."""
        rows = [
            r["epsilon"] for r in self.episodes if r["policy"] == policy and r["objects"] == objects
        ]
        out = np.ones((len(rows), self.budget))
        for i, e in enumerate(rows):
            e = np.asarray(e[: self.budget], dtype=np.float64)
            out[i, : len(e)] = e
            if 0 < len(e) < self.budget:
                out[i, len(e) :] = e[-1]
        return out

    def summary(self, policy: str, objects: str) -> dict[str, Array]:
        """Mean, std, median, quartiles of epsilon per touch count (arrays of length budget)."""
        e = self.epsilon(policy, objects)
        return {
            "mean": e.mean(axis=0),
            "std": e.std(axis=0, ddof=1) if len(e) > 1 else np.zeros(self.budget),
            "median": np.median(e, axis=0),
            "q25": np.quantile(e, 0.25, axis=0),
            "q75": np.quantile(e, 0.75, axis=0),
        }

    def paired_test(self, policy: str, baseline: str, objects: str, touches: int) -> dict:
        """Paired comparison of two policies after `touches` touches on the same objects.

        Returns:
            ``mean_difference`` (policy - baseline; negative: policy better), ``wins`` (episodes
            where the policy's epsilon is lower), ``n``, and the two-sided Wilcoxon signed-rank
            ``p_value``.
        """
        from scipy.stats import wilcoxon

        a = self.epsilon(policy, objects)[:, touches - 1]
        b = self.epsilon(baseline, objects)[:, touches - 1]
        d = a - b
        p = float(wilcoxon(a, b).pvalue) if np.any(d != 0) else 1.0
        return {
            "mean_difference": float(d.mean()),
            "wins": int(np.sum(d < 0)),
            "n": int(len(d)),
            "p_value": p,
        }


def compare_policies(
    policies: Sequence[str],
    object_sets: Sequence[str],
    episodes: int,
    seed: int = 0,
    workers: int | None = 2,
    progress: bool = True,
    scheduler: str | None = None,
    fresh_envs: bool = False,
    **env_kwargs: Any,
) -> Comparison:
    """Run every policy on the same `episodes` objects of each object set.

    Args:
        policies: policy names (:data:`~hapticsim.envs.policies.POLICY_NAMES` or
            ``learned:PATH``; weight files are checked before any episode runs).
        object_sets: object distribution kinds (``"paper"``, ``"random"``, ``"random_tapered"``).
        episodes: episodes per (policy, object set); episode i uses seed ``seed + i``.
        seed: root seed.
        workers: processes (default 2); ignored with `scheduler`.
        progress: show a progress bar on stderr.
        scheduler: run on a Dask cluster instead (``tcp://host:port`` or ``local:N``).
        fresh_envs: a new environment per episode (:class:`ComparisonTask`), so that results do
            not depend on the worker count.
        **env_kwargs: environment settings (``backend``, ``touch_budget``, ``noise``, ...).

    Returns:
        The comparison.
    """
    from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig
    from hapticsim.envs.policies import check_policy_name, learned_path, load_learned
    from hapticsim.parallel import parallel_map

    for p in policies:
        check_policy_name(p)
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise InvalidInputError(f"`episodes` must be an int >= 1, got {episodes!r}")
    config = HapticExploreConfig(**env_kwargs)  # validates the settings up front
    for p in policies:
        if p.startswith("learned"):  # the weight file fits these settings
            load_learned(learned_path(p), config)
    tasks = [
        ComparisonTask(p, o, i, seed, dict(env_kwargs), fresh_envs)
        for o in object_sets
        for i in range(episodes)
        for p in policies
    ]
    results = parallel_map(
        run_task, tasks, workers=None if scheduler else workers, desc="episodes",
        progress=progress, names=lambda t: t.label, unit="episode", scheduler=scheduler,
    )  # fmt: skip
    settings = {k: v for k, v in asdict(config).items() if k not in ("objects", "fit")}
    settings["fit"] = asdict(config.fit)
    settings["seed"] = seed
    settings["episodes"] = episodes
    return Comparison(
        tuple(policies), tuple(object_sets), config.touch_budget, tuple(results), settings
    )


def evaluate_policy(
    policy: str,
    backend: str = "analytic",
    objects: str = "random",
    episodes: int = 50,
    touches: int = 10,
    seed: int = 0,
    workers: int | None = 1,
    progress: bool = True,
    **env_kwargs: Any,
) -> dict[str, Any]:
    """One policy's epsilon after 1..touches touches on `episodes` objects (SPEC §6).

    Episode i runs in a new environment seeded ``seed + i``: every policy evaluated with the same
    seed meets the same objects, rough positions and noise streams, so two results pair episode by
    episode, and the numbers do not depend on `workers`.

    Args:
        policy: a policy name (:data:`~hapticsim.envs.policies.POLICY_NAMES`, ``learned:PATH``).
        backend: ``"analytic"`` or ``"mujoco"``.
        objects: object distribution kind (``"paper"``, ``"random"``, ``"random_tapered"``).
        episodes: number of episodes, >= 1.
        touches: touches per episode (the environment's budget), >= 1.
        seed: root seed, >= 0.
        workers: processes (:mod:`hapticsim.parallel`).
        progress: progress bar on stderr.
        **env_kwargs: further environment settings (noise, fit schedule, ...).

    Returns:
        ``{"policy", "backend", "objects", "episodes", "touches", "seed", "epsilon": {"mean",
        "std", "median"}, "episodes_epsilon"}``; the lists run over touch counts 1..touches
        (std with ddof 1), ``episodes_epsilon[i][n - 1]`` is episode i's epsilon after n touches.
    """
    from hapticsim.data.distributions import OBJECT_KINDS

    if objects not in OBJECT_KINDS:
        raise ChoiceError("objects", objects, OBJECT_KINDS)
    seed = positive_int(seed, "seed", minimum=0)
    touches = positive_int(touches, "touches")
    cmp = compare_policies(
        [policy], [objects], episodes, seed=seed, workers=workers, progress=progress,
        fresh_envs=True, backend=backend, touch_budget=touches, **env_kwargs,
    )  # fmt: skip
    summary = cmp.summary(policy, objects)
    table = cmp.epsilon(policy, objects)
    return {
        "policy": policy, "backend": backend, "objects": objects, "episodes": episodes,
        "touches": touches, "seed": seed,
        "epsilon": {k: [float(v) for v in summary[k]] for k in ("mean", "std", "median")},
        "episodes_epsilon": [[float(v) for v in row] for row in table],
    }  # fmt: skip


__all__ = ["Comparison", "ComparisonTask", "compare_policies", "evaluate_policy", "run_task"]
