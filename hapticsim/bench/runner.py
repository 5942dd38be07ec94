"""``hapticsim bench run``: a policy on a task's episodes, every metric after every touch.

After each touch an estimate is scored against the truth. The estimators:

- ``env-nH`` (default): the environment's own incremental nH fit, every touch;
- ``env-multi``: the environment's fit schedule with full fits by ``multi`` (a union of
  superquadrics), every touch;
- ``nML``, ``multi``, ``gpis``, ``supertoroid`` and a lab's fitter ``MODULE:ATTR``
  (``fit(points, normals)`` returning a solid or anything holding one, as the suites'
  ``--fitter``): fitted from scratch
  on the contacts the episode has gathered (the environment running ``env-nH``, so the touches
  are the same as ``env-nH``'s for the same policy and seed) at touches
  :data:`SCORED_TOUCHES` and the last only (they are slow); the other touches hold no metrics,
  and the results say which were scored (``scored_touches``).

The metrics, from one :class:`~hapticsim.metrics.episode.TruthScorer` per episode (its random
numbers drawn once, seed 0, so successive estimates are scored with common random numbers):

- ``iou`` and ``epsilon`` (alpha + beta; 1 before the first fit) from
  :data:`VOLUME_SAMPLES` quasi-random points inside each solid (``TruthScorer.score``);
- ``chamfer_mm``, ``f_score`` at 1, 2.5 and 5 mm and ``normal_consistency`` from
  :data:`SURFACE_POINTS` area-weighted points on each surface and exact distances to the other
  (``TruthScorer.surface``);
- ``wall_s`` and ``cpu_s`` of the touch (the policy's choice and the environment's step).

Each touch's estimate is kept in the results (SPEC §6 JSON), so anyone can score it again. The
summary holds, per metric, the mean curve over episodes and the area under each episode's
curve (:func:`hapticsim.metrics.anytime_area`) with its mean and 95 % interval. The file
carries its manifest (SPEC §14) and is written whole or not at all.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim.bench.tasks import PROTOCOL, Task, get_task
from hapticsim.errors import InvalidInputError

#: The environment's own estimators, scored after every touch: name -> its fit schedule's method.
ENV_ESTIMATORS: dict[str, str] = {"env-nH": "nH", "env-multi": "multi"}
#: Estimators fitted from scratch at :data:`SCORED_TOUCHES` (a lab's own comes as
#: ``MODULE:ATTR``).
FIT_ESTIMATORS: tuple[str, ...] = ("nML", "multi", "gpis", "supertoroid")
#: Every built-in estimator.
ESTIMATORS: tuple[str, ...] = (*ENV_ESTIMATORS, *FIT_ESTIMATORS)
#: The touches at which a fitted estimator is scored (and the episode's last).
SCORED_TOUCHES: tuple[int, ...] = (5, 10, 20)
#: Metrics after every touch, in the results' order.
METRICS: tuple[str, ...] = (
    "iou", "epsilon", "chamfer_mm", "f_score_1", "f_score_2.5", "f_score_5",
    "normal_consistency", "wall_s", "cpu_s",
)  # fmt: skip
#: Interior points per solid behind IoU and epsilon (protocol 2; protocol 1 drew 100 000 per
#: solid anew for every estimate, about 20 times the time).
VOLUME_SAMPLES: int = 20_000
#: Surface points per solid behind Chamfer, F-score and normal consistency.
SURFACE_POINTS: int = 2048
#: What an episode's metrics are before the first fit.
_NO_FIT = {"iou": 0.0, "epsilon": 1.0, "chamfer_mm": None, "f_score_1": 0.0, "f_score_2.5": 0.0,
           "f_score_5": 0.0, "normal_consistency": None}  # fmt: skip


@dataclass(frozen=True)
class EpisodeTask:
    """One episode for a worker (picklable)."""

    task: str
    policy: str
    seed: int
    estimator: str = "env-nH"

    @property
    def label(self) -> str:
        """The episode in messages."""
        return f"{self.task} {self.policy} {self.estimator} seed {self.seed}"


def truth_scorer(truth: Any) -> Any:
    """The episode's scorer of `truth` (module docstring)."""
    from hapticsim.metrics.episode import TruthScorer

    return TruthScorer(truth, samples=VOLUME_SAMPLES, chamfer_samples=SURFACE_POINTS, rng=0)


def touch_metrics(estimate: Any, scorer: Any) -> dict[str, Any]:
    """The quality measures of one estimate against the truth of `scorer` (:func:`truth_scorer`;
    module docstring; `estimate` None: before the first fit)."""
    if estimate is None:
        return dict(_NO_FIT) | {"chamfer": None, "f_score": {"1": 0.0, "2.5": 0.0, "5": 0.0}}
    q = scorer.score(estimate)
    s = scorer.surface(estimate)
    f = dict(zip(("f_score_1", "f_score_2.5", "f_score_5"), s.f_score, strict=True))
    # SPEC §13's keys (chamfer [m], f_score by threshold [mm]) and the flat ones the summary uses
    return {"iou": q.iou, "epsilon": q.epsilon, "chamfer": s.chamfer,
            "chamfer_mm": 1000.0 * s.chamfer, "f_score": s.to_dict()["f_score"], **f,
            "normal_consistency": s.normal_consistency}  # fmt: skip


def make_bench_policy(name: str, env: Any, seed: int) -> Any:
    """A built-in policy by name, or a lab's class ``MODULE:ATTR`` (the baselines' interface)."""
    from hapticsim.envs.policies import LEARNED_PREFIX, make_policy
    from hapticsim.suites.plugins import make_plugin_policy

    if ":" in name and not name.startswith(LEARNED_PREFIX):
        return make_plugin_policy(name, env, seed)
    return make_policy(name, env, rng=seed)


def checked_action(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    """A policy's action as float32 of `shape`, finite (else one line naming the policy)."""
    action = np.asarray(value, dtype=np.float32)
    if action.shape != shape or not np.all(np.isfinite(action)):
        raise InvalidInputError(
            f"the policy {name} returned {action.shape} action with non-finite or missing values "
            f"(expected {shape}, finite)"
        )
    return action


def check_estimator(name: Any) -> str:
    """`name` if it is a built-in estimator or a loadable ``MODULE:ATTR`` fitter, else one line
    naming the problem."""
    from hapticsim.errors import ChoiceError
    from hapticsim.suites.plugins import load_fitter

    if isinstance(name, str) and ":" in name:
        load_fitter(name)  # imports it, or says why not
        return name
    if name not in ESTIMATORS:
        raise ChoiceError("estimator", name, (*ESTIMATORS, "MODULE:ATTR"))
    if name == "gpis":  # a missing extra is said once, not scored as "cannot fit yet"
        from hapticsim.fitting.gpis import require_marching_cubes

        require_marching_cubes()
    return name


def _fitted(estimator: str, points: np.ndarray, normals: np.ndarray, seed: int) -> Any:
    """A fitted estimator's solid from the contacts so far (None where it cannot fit them)."""
    from hapticsim.errors import HapticsimError
    from hapticsim.fitting import fit
    from hapticsim.suites.plugins import as_solid, load_fitter

    if ":" in estimator:  # a lab's fitter: what goes wrong is said in one line
        try:
            value = load_fitter(estimator)(points.copy(), normals.copy())
        except Exception as exc:  # noqa: BLE001 - any failure of the lab's code
            detail = " ".join(str(exc).split())
            raise InvalidInputError(
                f"the estimator {estimator} failed on {len(points)} contacts: "
                f"{type(exc).__name__}: {detail}"
            ) from None
        return as_solid(value)
    try:
        return fit(points, normals, method=estimator, rng=seed).solid
    except HapticsimError:
        return None  # too few contacts or no closed level set yet: scored as no fit


def _stored(estimate: Any) -> dict[str, Any] | None:
    """An estimate as the results keep it: its JSON, but a mesh (GPIS's) only by its size (its
    vertices would make a results file of hundreds of megabytes)."""
    if estimate is None:
        return None
    if estimate.kind == "mesh":
        return {"mesh_faces": int(len(estimate.faces)), "volume": float(estimate.volume)}
    return estimate.to_dict()


def run_episode(job: EpisodeTask) -> dict[str, Any]:
    """One episode of a task (module-level: the executor maps it)."""
    from dataclasses import replace

    from hapticsim.envs.estimator import FitSchedule
    from hapticsim.envs.haptic_explore_tactile_v0 import make_v0
    from hapticsim.envs.policies import Policy

    task = get_task(job.task)
    kwargs = task.env_kwargs()
    live = job.estimator in ENV_ESTIMATORS
    if job.estimator == "env-multi":
        kwargs["fit"] = replace(FitSchedule(), method=ENV_ESTIMATORS["env-multi"])
    env = make_v0(**kwargs)
    core = env.unwrapped  # the truth, the estimate and the contacts
    try:
        policy = make_bench_policy(job.policy, env, job.seed)
        obs, _ = env.reset(seed=job.seed)
        scorer = truth_scorer(core.truth)
        if isinstance(policy, Policy):
            policy.reset(job.seed)
        touches, done = [], False
        while not done:
            wall, cpu = time.perf_counter(), time.process_time()
            action = checked_action(job.policy, policy(obs), env.action_space.shape)
            obs, _, terminated, truncated, info = env.step(action)
            row = {"wall_s": time.perf_counter() - wall, "cpu_s": time.process_time() - cpu}
            done = terminated or truncated
            touch = len(touches) + 1
            if live:
                estimate = core.solid
            elif touch in SCORED_TOUCHES or done:
                c = core.contacts
                start, cpu = time.perf_counter(), time.process_time()
                estimate = _fitted(job.estimator, c.points, c.normals, job.seed)
                row["fit_wall_s"] = time.perf_counter() - start
                row["fit_cpu_s"] = time.process_time() - cpu
            else:
                row |= dict.fromkeys(_NO_FIT)  # the quality measures: not scored here
                row["contacts"] = int(info["n_contacts"])
                touches.append(row)
                continue
            row |= touch_metrics(estimate, scorer)
            row["contacts"] = int(info["n_contacts"])
            row["estimate"] = _stored(estimate)
            touches.append(row)
        truth = core.truth.to_dict() if core.truth.kind != "mesh" else None
    finally:
        env.close()
    return {"seed": job.seed, "truth": truth, "touches": touches}


def _summary(episodes: list[dict[str, Any]]) -> dict[str, Any]:
    """Per metric: the mean curve over episodes, each episode's area under its curve, and the
    areas' mean with a 95 % interval (t distribution)."""
    from scipy import stats

    from hapticsim.metrics import anytime_area

    out: dict[str, Any] = {}
    for metric in METRICS:
        curves = []
        for e in episodes:
            values = [t[metric] for t in e["touches"]]
            if any(v is None for v in values):  # before the first fit: no distance yet
                values = [np.nan if v is None else v for v in values]
            curves.append(values)
        arr = np.asarray(curves, dtype=float)
        areas = [anytime_area(c[~np.isnan(c)]) if np.any(~np.isnan(c)) else None for c in arr]
        valid = np.array([a for a in areas if a is not None], dtype=float)
        mean = float(valid.mean()) if len(valid) else None
        half = (float(stats.t.ppf(0.975, len(valid) - 1) * valid.std(ddof=1) / np.sqrt(len(valid)))
                if len(valid) > 1 else None)  # fmt: skip
        out[metric] = {
            "mean_curve": [None if np.all(np.isnan(col)) else float(np.nanmean(col))
                           for col in arr.T],  # fmt: skip
            "area": areas, "area_mean": mean,
            "area_ci95": None if half is None else [mean - half, mean + half],
        }  # fmt: skip
    return out


def scored_touches(estimator: str, touches: int) -> list[int]:
    """The touches (1-based) at which `estimator` is scored in an episode of `touches` touches
    (module docstring; an episode that ends early is scored at its last touch too)."""
    if estimator in ENV_ESTIMATORS:
        return list(range(1, touches + 1))
    return sorted({t for t in SCORED_TOUCHES if t <= touches} | {touches})


def run_bench(
    task: str, policy: str, episodes: int, estimator: str = "env-nH", split: str = "test",
    workers: int | None = 1, scheduler: str | None = None, progress: bool = True,
    command: list[str] | None = None,
) -> dict[str, Any]:  # fmt: skip
    """Run `policy` on `episodes` episodes of `task`'s split; the results (module docstring).

    Raises:
        InvalidInputError: an unknown task, estimator or split, a policy that cannot be made
            (an unknown name, a plug-in that does not import), or one that returns a bad
            action (all checked before a file is written).
    """
    from hapticsim.parallel import parallel_map

    jobs = bench_jobs(task, policy, episodes, estimator, split)
    start = time.perf_counter()
    rows = parallel_map(run_episode, jobs, workers=None if scheduler else workers,
                        desc=f"bench {task}", progress=progress, names=lambda j: j.label,
                        unit="episode", scheduler=scheduler)  # fmt: skip
    return bench_results(jobs, rows, split, time.perf_counter() - start, command)


def bench_jobs(
    task: str, policy: str, episodes: int, estimator: str = "env-nH", split: str = "test"
) -> list[EpisodeTask]:
    """The episodes of one run (:func:`run_bench`), checked: an unknown task, estimator or split,
    or a policy that cannot be made, raise InvalidInputError here."""
    spec: Task = get_task(task)
    check_estimator(estimator)
    seeds = spec.seeds(split, episodes)
    _check_policy(policy, spec)
    return [EpisodeTask(task, policy, s, estimator) for s in seeds]


def bench_results(
    jobs: list[EpisodeTask], rows: list[dict[str, Any]], split: str, seconds: float,
    command: list[str] | None = None,
) -> dict[str, Any]:  # fmt: skip
    """One run's results (SPEC §13) from its jobs (:func:`bench_jobs`) and their episodes."""
    from hapticsim.suites.provenance import manifest

    first = jobs[0]
    spec = get_task(first.task)
    return {
        "protocol": PROTOCOL, "task": spec.to_dict(), "policy": first.policy,
        "estimator": first.estimator, "split": split, "seeds": [j.seed for j in jobs],
        "metrics": list(METRICS), "scored_touches": scored_touches(first.estimator, spec.touches),
        "f_score_thresholds_mm": [1.0, 2.5, 5.0], "episodes": rows,
        "summary": _summary(rows), "seconds": seconds, "manifest": manifest(command),
    }  # fmt: skip


def _check_policy(policy: str, task: Task) -> None:
    """Make the policy once on the task's environment, reset (bad names and plug-ins, and an
    object family whose extra is missing, fail here, before any worker starts)."""
    from hapticsim.envs.haptic_explore_tactile_v0 import make_v0

    kwargs = task.env_kwargs() | {"backend": "analytic"}
    env = make_v0(**kwargs)
    try:
        make_bench_policy(policy, env, 0)
        env.reset(seed=0)
    finally:
        env.close()


def write_results(results: dict[str, Any], path: str | Path) -> Path:
    """Write results as compact JSON (a file holds every touch's estimate) through a temporary
    file and a rename."""
    import json

    from hapticsim._files import write_text_atomic

    return write_text_atomic(path, json.dumps(results, separators=(",", ":")) + "\n")


__all__ = ["ENV_ESTIMATORS", "ESTIMATORS", "FIT_ESTIMATORS", "METRICS", "SCORED_TOUCHES",
           "SURFACE_POINTS", "VOLUME_SAMPLES", "bench_jobs", "bench_results", "check_estimator",
           "run_bench", "run_episode", "scored_touches", "touch_metrics", "truth_scorer",
           "write_results"]  # fmt: skip
