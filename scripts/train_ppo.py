"""Train stable-baselines3 PPO on hapticsim/HapticExplore-v0 for a few thousand steps.

An example that the environment works with the ecosystem's tools, not a tuned agent: PPO with
the ``MultiInputPolicy`` (the observation is a Dict) on the fast analytic backend, several
environments in subprocesses, then a short evaluation of the trained policy (its mean action,
and sampled actions) against random touches on the same objects (epsilon after the last touch).
A few thousand steps teach PPO little: its mean action repeats nearly the same touch. Needs the
``rl`` extra:

    pip install torch==2.13.0            # this machine: the CPU wheel from local disk
    pip install -e ".[rl]"
    python scripts/train_ppo.py --timesteps 4096 --out runs/ppo
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timesteps", type=int, default=4096)
    parser.add_argument("--n-envs", type=int, default=2)
    parser.add_argument("--budget", type=int, default=10, help="touches per episode")
    parser.add_argument("--objects", default="paper")
    parser.add_argument("--eval-episodes", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/ppo"))
    args = parser.parse_args(argv)

    try:
        from stable_baselines3 import PPO
        from stable_baselines3.common.env_util import make_vec_env
        from stable_baselines3.common.vec_env import SubprocVecEnv
    except ImportError:
        print("train_ppo.py needs stable-baselines3: pip install -e '.[rl]'", file=sys.stderr)
        return 2

    import gymnasium as gym

    import hapticsim  # noqa: F401  (registers the environment)
    from hapticsim.envs.episodes import run_episode
    from hapticsim.envs.policies import RandomPolicy
    from hapticsim.envs.registration import HAPTIC_EXPLORE_ID

    env_kwargs = {"backend": "analytic", "objects": args.objects, "touch_budget": args.budget}
    # "hapticsim:<id>" makes Gymnasium import hapticsim (which registers the id) in the
    # subprocesses too, whatever their start method.
    vec_env = make_vec_env(
        "hapticsim:" + HAPTIC_EXPLORE_ID, n_envs=args.n_envs, seed=args.seed, env_kwargs=env_kwargs,
        vec_env_cls=SubprocVecEnv if args.n_envs > 1 else None,
    )  # fmt: skip
    model = PPO(
        "MultiInputPolicy", vec_env, n_steps=256, batch_size=64, n_epochs=4, learning_rate=3e-4,
        gamma=0.99, seed=args.seed, verbose=1, device="cpu",
    )  # fmt: skip
    start = time.perf_counter()
    model.learn(total_timesteps=args.timesteps, progress_bar=False)
    train_seconds = time.perf_counter() - start
    vec_env.close()
    args.out.mkdir(parents=True, exist_ok=True)
    model.save(args.out / "ppo_haptic_explore")

    env = gym.make(HAPTIC_EXPLORE_ID, **env_kwargs)

    def ppo_policy(deterministic: bool):  # noqa: ANN202
        def act(obs: dict) -> np.ndarray:
            action, _ = model.predict(obs, deterministic=deterministic)
            return action

        return act

    seeds = [10_000 + i for i in range(args.eval_episodes)]  # objects not seen in training
    final = {
        "ppo_deterministic": [
            float(run_episode(env, ppo_policy(True), seed=s).epsilon[-1]) for s in seeds
        ],
        "ppo_stochastic": [
            float(run_episode(env, ppo_policy(False), seed=s).epsilon[-1]) for s in seeds
        ],
        "random": [
            float(run_episode(env, RandomPolicy(env, rng=s), seed=s).epsilon[-1]) for s in seeds
        ],
    }
    env.close()
    report = {
        "timesteps": args.timesteps,
        "train_seconds": train_seconds,
        "steps_per_second": args.timesteps / train_seconds,
        "eval_episodes": args.eval_episodes,
        "final_epsilon_mean": {k: float(np.mean(v)) for k, v in final.items()},
        "final_epsilon": final,
        "env_kwargs": env_kwargs,
    }
    (args.out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    print(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
