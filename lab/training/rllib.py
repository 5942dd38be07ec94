"""Training exploration policies with Ray RLlib (PPO, SAC), on one machine or a Ray cluster.

The environment (``hapticsim/HapticExploreCompact-v0`` by default, analytic backend) runs in
RLlib's EnvRunners, one Ray actor each, anywhere on the cluster; every EnvRunner steps
``num_envs_per_env_runner`` environments, vectorised by Gymnasium (``"sync"``) or by hapticsim's
own vector environment (``"native"``: :class:`~hapticsim.envs.vector.HapticVectorEnv`, its
``workers`` processes inside the EnvRunner's node). The learner sits in the driver.

    ray start --head --num-cpus 2          # here; or any cluster: ray start --address HEAD:6379
    python scripts/train_rllib.py --address auto --algo ppo --timesteps 200000 --out runs/ppo

Every ``eval_every`` environment steps the deterministic policy (the distribution's mode) runs
on the validation objects of ``scripts/train_policy.py`` (environment seeds 10,000 + i, never
trained on) and the mean epsilon after the last touch goes into the curve, beside random
touches' on the same objects. Needs the ``ray`` extra (``pip install -e ".[ray]"``, with torch's
CPU build installed first where there is no GPU).
"""

from __future__ import annotations

import csv
import json
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from hapticsim.envs.registration import HAPTIC_EXPLORE_COMPACT_ID
from hapticsim.errors import ChoiceError, ExecutionError, InvalidInputError

#: Algorithms :func:`build_config` knows.
ALGOS: tuple[str, ...] = ("ppo", "sac")
#: How an EnvRunner vectorises its environments.
VECTORIZE: tuple[str, ...] = ("sync", "native")
#: PPO's learning rate (a schedule, ``[[step, lr], ...]``, may replace it: ``lr=`` of
#: :func:`build_config`, ``--lr-end`` of ``scripts/train_rllib.py``).
PPO_LR: float = 3e-4
#: Environment seeds of the validation objects: VAL_SEED + i (as ``scripts/train_policy.py``).
VAL_SEED: int = 10_000
#: The SB3 recipe's environment settings (``scripts/train_policy.py`` defaults).
DEFAULT_ENV_CONFIG: dict[str, Any] = {
    "backend": "analytic", "objects": "random", "touch_budget": 10, "noise": 0.02,
    "reward": "log_epsilon", "coverage_weight": 2.0, "chamfer_samples": 10,
}  # fmt: skip


def make_env(config: dict[str, Any]) -> gym.Env | gym.vector.VectorEnv:
    """RLlib's environment creator: one environment, or with ``num_envs`` a native vector one.

    Args:
        config: the environment's settings, with ``env_id`` (default the compact id) and, when
            RLlib asks for a vector environment, ``num_envs`` (and optionally ``workers`` and
            ``context``, default ``"spawn"``: a Ray actor has threads, which a fork would copy
            in whatever state they are).
    """
    from hapticsim.envs.vector import HapticVectorEnv

    settings = dict(config)
    env_id = settings.pop("env_id", HAPTIC_EXPLORE_COMPACT_ID)
    num_envs = settings.pop("num_envs", None)
    workers = settings.pop("workers", None)
    # a Ray actor has threads of its own (gRPC): its workers start fresh, not by fork
    context = settings.pop("context", "spawn")
    if num_envs is None:
        return gym.make(env_id, **settings)
    return HapticVectorEnv(env_id, num_envs=int(num_envs), workers=workers, context=context,
                           **settings)  # fmt: skip


def build_config(
    algo: str = "ppo",
    env_config: dict[str, Any] | None = None,
    num_env_runners: int = 2,
    num_envs_per_env_runner: int = 1,
    vectorize: str = "sync",
    seed: int = 0,
    hidden: tuple[int, ...] = (256, 256),
    **training: Any,
) -> Any:
    """An RLlib ``AlgorithmConfig`` (new API stack) for hapticsim exploration.

    Args:
        algo: ``"ppo"`` or ``"sac"``.
        env_config: environment settings (default :data:`DEFAULT_ENV_CONFIG`; ``env_id``
            chooses another hapticsim id; ``workers`` the native vector environment's
            processes).
        num_env_runners: EnvRunner actors (0: sample in the driver).
        num_envs_per_env_runner: environments per EnvRunner.
        vectorize: ``"sync"`` (Gymnasium's SyncVectorEnv) or ``"native"``
            (:class:`~hapticsim.envs.vector.HapticVectorEnv`).
        seed: seed of RLlib and of the environments.
        hidden: hidden layer sizes of the policy and value/Q networks.
        **training: further ``config.training(...)`` arguments (e.g. ``lr``,
            ``train_batch_size_per_learner``).

    Returns:
        the config; ``config.build_algo()`` makes the algorithm.
    """
    if algo not in ALGOS:
        raise ChoiceError("algo", algo, ALGOS)
    if vectorize not in VECTORIZE:
        raise ChoiceError("vectorize", vectorize, VECTORIZE)
    try:
        from ray.rllib.algorithms.ppo import PPOConfig
        from ray.rllib.algorithms.sac import SACConfig
        from ray.rllib.core.rl_module.rl_module import RLModuleSpec
        from ray.tune.registry import register_env
    except ImportError as exc:
        raise InvalidInputError(
            "RLlib training needs the ray extra: pip install torch==2.13.0 && pip install -e "
            '".[ray]"'
        ) from exc
    register_env("hapticsim-rllib", make_env)
    env_config = {**DEFAULT_ENV_CONFIG, **(env_config or {})}
    mode = "vector_entry_point" if vectorize == "native" else "sync"
    layers = list(hidden)
    if algo == "ppo":
        config = PPOConfig().training(
            **{"lr": PPO_LR, "gamma": 0.99, "lambda_": 0.95, "num_epochs": 10,
               "minibatch_size": 128, "train_batch_size_per_learner": 1024, **training}
        ).rl_module(model_config={"fcnet_hiddens": layers, "fcnet_activation": "tanh",
                                  "vf_share_layers": False})  # fmt: skip
    else:
        config = SACConfig().training(
            **{"actor_lr": 3e-4, "critic_lr": 3e-4, "alpha_lr": 3e-4, "gamma": 0.99,
               "tau": 0.005, "train_batch_size_per_learner": 256,
               "num_steps_sampled_before_learning_starts": 1000,
               "replay_buffer_config": {"type": "PrioritizedEpisodeReplayBuffer",
                                        "capacity": 300_000}, **training}
        ).rl_module(rl_module_spec=RLModuleSpec(model_config={
            "fcnet_hiddens": layers, "head_fcnet_hiddens": [], "fcnet_activation": "relu",
        }))  # fmt: skip
    return (
        config.environment("hapticsim-rllib", env_config=env_config)
        .env_runners(num_env_runners=num_env_runners,
                     num_envs_per_env_runner=num_envs_per_env_runner,
                     gym_env_vectorize_mode=mode, num_cpus_per_env_runner=1)
        .framework("torch")
        .debugging(seed=seed)
    )  # fmt: skip


def deterministic_policy(module: Any) -> Callable[[np.ndarray], np.ndarray]:
    """The mode of an RLlib module's action distribution, as a numpy function of one
    observation (actions clipped to [-1, 1])."""
    import torch

    dist_cls = module.get_inference_action_dist_cls()

    def act(obs: np.ndarray) -> np.ndarray:
        with torch.no_grad():
            out = module.forward_inference({"obs": torch.as_tensor(obs[None], dtype=torch.float32)})
            dist = dist_cls.from_logits(out["action_dist_inputs"])
            action = dist.to_deterministic().sample()
        return np.clip(action.numpy()[0], -1.0, 1.0).astype(np.float32)

    return act


def final_epsilons(
    policy: Callable[[np.ndarray], np.ndarray] | None,
    env_config: dict[str, Any] | None = None,
    episodes: int = 32,
    seed: int = VAL_SEED,
) -> list[float]:
    """Epsilon after the last touch of each episode (seeds ``seed + i``).

    Args:
        policy: a function of one observation (None: uniform random actions, seeded).
        env_config: environment settings (default :data:`DEFAULT_ENV_CONFIG`).
        episodes: episodes, seeds ``seed + i``.
        seed: first seed.
    """
    settings = {**DEFAULT_ENV_CONFIG, **(env_config or {})}
    for key in ("workers", "context", "num_envs"):  # one environment, in this process
        settings.pop(key, None)
    env = make_env(settings)
    env.action_space.seed(seed)
    final = []
    for i in range(episodes):
        obs, _ = env.reset(seed=seed + i)
        done, info = False, {}
        while not done:
            action = env.action_space.sample() if policy is None else policy(obs)
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
        final.append(float(info["epsilon"]))
    env.close()
    return final


def validate(
    policy: Callable[[np.ndarray], np.ndarray] | None,
    env_config: dict[str, Any] | None = None,
    episodes: int = 32,
    seed: int = VAL_SEED,
) -> dict[str, float]:
    """Mean and median epsilon after the last touch of the validation episodes
    (:func:`final_epsilons`)."""
    final = final_epsilons(policy, env_config, episodes, seed)
    return {"mean": float(np.mean(final)), "median": float(np.median(final))}


def _sampled(result: dict[str, Any]) -> int:
    """Environment steps sampled so far, from an RLlib result."""
    runners = result.get("env_runners", {})
    for key in ("num_env_steps_sampled_lifetime", "num_env_steps_sampled"):
        if key in runners:
            return int(runners[key])
    return int(result.get("num_env_steps_sampled_lifetime", 0))


def _token_available(environ: Any = None, home: Path | None = None) -> bool:
    """Whether this process has a Ray authentication token (where Ray looks for one)."""
    environ = os.environ if environ is None else environ
    if environ.get("RAY_AUTH_TOKEN"):
        return True
    path = environ.get("RAY_AUTH_TOKEN_PATH")
    token = Path(path) if path else (Path.home() if home is None else home) / ".ray" / "auth_token"
    return token.is_file()


def join_cluster(address: str | None) -> None:
    """Start Ray in this process (`address` None) or join the cluster at `address`.

    Ray (2.5x) turns token authentication on for ``ray start`` and ``ray.init(address="auto")``
    whenever a token is at hand (``~/.ray/auth_token``, ``RAY_AUTH_TOKEN_PATH``,
    ``RAY_AUTH_TOKEN``), but not for a driver given an explicit address, which then cannot join
    a cluster started on the same machine. The same rule is applied here to every address:
    with ``RAY_AUTH_MODE`` unset and a token at hand, this process authenticates with it (a
    cluster without authentication accepts such a driver too). ``RAY_AUTH_MODE=disabled``
    opts out.

    Raises:
        ExecutionError: the cluster cannot be joined; the message says what to check.
    """
    import ray

    if address is not None and "RAY_AUTH_MODE" not in os.environ and _token_available():
        os.environ["RAY_AUTH_MODE"] = "token"
        try:  # Ray reads its configuration once; its own CLI refreshes it the same way
            from ray._raylet import Config

            Config.initialize("")
        except (ImportError, AttributeError):  # pragma: no cover - other Ray versions
            pass
    # the lab is not installed: ship it to the workers, which unpickle its environment creator
    lab = str(Path(__file__).resolve().parents[1])
    try:
        ray.init(address=address, include_dashboard=False, log_to_driver=False,
                 runtime_env={"py_modules": [lab]})  # fmt: skip
    except ConnectionError as exc:
        raise ExecutionError(
            f"could not join the Ray cluster at {address!r} ({exc}). Check that it runs "
            "(`ray status --address ADDRESS`); if it uses token authentication, give this "
            "process its token (RAY_AUTH_TOKEN_PATH=FILE, from `ray get-auth-token` on the "
            "head) and set RAY_AUTH_MODE=token"
        ) from exc


def train(
    config: Any,
    timesteps: int,
    out: Path | str,
    eval_every: int = 10_000,
    val_episodes: int = 32,
    address: str | None = None,
    max_hours: float | None = None,
    progress: bool = True,
) -> dict[str, Any]:
    """Train until `timesteps` environment steps, validating every `eval_every`.

    Writes ``curve.csv`` (steps, seconds, validation mean and median, return), ``summary.json``
    and the module of the best validation point (``best/``, RLlib's checkpoint format) in
    `out`.

    Args:
        config: from :func:`build_config`.
        timesteps: environment steps to sample in all.
        out: output folder.
        eval_every: environment steps between validations.
        val_episodes: validation episodes.
        address: Ray cluster to join (``"auto"``: the one ``ray start`` began here; None: start
            one in this process); see :func:`join_cluster` for token authentication.
        max_hours: stop after this much wall time.
        progress: a line per iteration on stderr.

    Returns:
        the summary.
    """
    import ray

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if not ray.is_initialized():
        join_cluster(address)
    env_config = dict(config.env_config)
    random_val = validate(None, env_config, val_episodes)
    algo = config.build_algo()
    start = time.perf_counter()
    rows: list[dict[str, Any]] = []
    best: dict[str, Any] | None = None
    next_eval = 0
    steps = 0
    try:
        while steps < timesteps:
            result = algo.train()
            steps = _sampled(result)
            seconds = time.perf_counter() - start
            ret = result.get("env_runners", {}).get("episode_return_mean", float("nan"))
            if progress:
                print(f"{steps:,} steps, {seconds:.0f} s, return {ret:.3f}", file=sys.stderr,
                      flush=True)  # fmt: skip
            if steps >= next_eval or steps >= timesteps:
                next_eval = steps + eval_every
                val = validate(deterministic_policy(algo.get_module()), env_config, val_episodes)
                row = {"steps": steps, "seconds": seconds, "val_mean": val["mean"],
                       "val_median": val["median"], "return_mean": float(ret)}  # fmt: skip
                rows.append(row)
                if progress:
                    print(f"  validation: epsilon {val['mean']:.4f} (random "
                          f"{random_val['mean']:.4f})", file=sys.stderr, flush=True)  # fmt: skip
                if best is None or val["mean"] < best["val_mean"]:
                    best = row
                    algo.get_module().save_to_path(str((out / "best").resolve()))
                _write_curve(rows, out / "curve.csv")
            if max_hours is not None and seconds > 3600 * max_hours:
                break
    finally:
        algo.stop()
    summary = {
        "algo": type(config).__name__,
        "env_config": env_config,
        "num_env_runners": config.num_env_runners,
        "num_envs_per_env_runner": config.num_envs_per_env_runner,
        "vectorize": config.gym_env_vectorize_mode,
        "seed": config.seed,
        "lr": config.lr,
        "steps": steps,
        "seconds": time.perf_counter() - start,
        "random_validation": random_val,
        "best": best,
        "last": rows[-1] if rows else None,
        "learns": bool(best is not None and best["val_mean"] < random_val["mean"]),
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=1, default=str) + "\n")
    return summary


def _write_curve(rows: list[dict[str, Any]], path: Path) -> None:
    tmp = path.with_suffix(".tmp")
    with tmp.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    tmp.replace(path)
