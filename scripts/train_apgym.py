"""Train a touch policy through the ap_gym interface (``hapticsim/ShapeByTouch-v0``) and export
it for the benchmark.

    pip install torch==2.13.0 && pip install -e ".[rl,apgym]"
    python scripts/train_apgym.py --timesteps 200000 --out runs/apgym
    hapticsim bench run random/exact/analytic/t20 --policy learned:runs/apgym/policy.npz ...

The agent acts through ``ShapeByTouch-v0`` as ap_gym's agents do: each step a touch and a
prediction of the shape, paid minus ap_gym's normalised loss (a blind guess costs 1). The recipe
(ours, simpler than APPLE's, which learns the prediction head too): the prediction is the shape
of the environment's own nH fit before the touch (as ``BaselineAgent`` predicts), and PPO
(stable-baselines3) learns the touch, so that what is learned is where to touch for the fit to
predict well after every touch. ``--n-envs`` environments in subprocesses, seeded
``1 000 000 + step``. Every ``--val-every`` steps the deterministic actor (exported to numpy,
exactly what ships) runs on validation objects (seeds 10 000 + i, never trained on, not the
benchmark's splits) and the mean loss over the episode's steps (the anytime loss) and after its
last step go into ``curve.csv`` and ``curve.png``. Outputs in ``--out``: ``policy.npz`` (the
best validation point's actor, in the learned-policy format: its observation and action are
``HapticExploreCompact-v0``'s), ``curve.csv``, ``curve.png``, ``train.log``, ``summary.json``
with the run's manifest. Progress on stderr.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

VAL_SEED: int = 10_000
TRAIN_SEED: int = 1_000_000
ENV_ID: str = "hapticsim/ShapeByTouch-v0"


class FitPredicts(gym.Wrapper):
    """``ShapeByTouch-v0`` with the prediction filled in by the environment's nH fit (the blind
    guess before the first fit): the agent's action is the touch alone."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self.action_space = env.unwrapped.action_space["action"]

    def step(self, action: Any) -> tuple:
        from hapticsim.envs.shape_by_touch_v0 import shape_target

        base = self.env.unwrapped
        estimate, scale = base.inner.estimate, base.inner.unwrapped.config.obs_scale
        prediction = base.blind_guess if estimate is None else shape_target(estimate, scale)
        touch = np.asarray(action, dtype=np.float32)
        return self.env.step({"action": touch, "prediction": prediction})


def make_env(objects: str, budget: int) -> gym.Env:
    import hapticsim  # noqa: F401 - registers the ids

    env = gym.make(ENV_ID, objects=objects, touch_budget=budget, backend="analytic")
    return FitPredicts(env)


def validate(actor: Any, env: gym.Env, episodes: int) -> dict[str, float]:
    """Mean over the validation episodes of the anytime loss and of the last step's loss."""
    anytime, last = [], []
    for i in range(episodes):
        obs, _ = env.reset(seed=VAL_SEED + i)
        losses, done = [], False
        while not done:
            obs, reward, terminated, truncated, _ = env.step(actor(obs))
            losses.append(-float(reward))
            done = terminated or truncated
        anytime.append(float(np.mean(losses)))
        last.append(losses[-1])
    return {"val_anytime_loss": float(np.mean(anytime)), "val_last_loss": float(np.mean(last))}


def plot_curve(rows: list[dict[str, Any]], path: Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    steps = [r["steps"] for r in rows]
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.plot(steps, [r["val_anytime_loss"] for r in rows], "o-", label="anytime loss", ms=3)
    ax.plot(steps, [r["val_last_loss"] for r in rows], "s--", label="loss after the last touch",
            ms=3)  # fmt: skip
    ax.set_xlabel("environment steps (touches)")
    ax.set_ylabel("normalised shape loss (blind guess 1)")
    ax.set_yscale("log")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timesteps", type=int, default=200_000)
    parser.add_argument("--objects", default="random_tapered")
    parser.add_argument("--budget", type=int, default=20)
    parser.add_argument("--n-envs", type=int, default=2)
    parser.add_argument("--val-every", type=int, default=20_000)
    parser.add_argument("--val-episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import SubprocVecEnv

    from hapticsim.envs.registration import HAPTIC_EXPLORE_COMPACT_ID
    from hapticsim.suites.provenance import manifest
    from lab.training.export import actor_from_sb3, recorded_settings

    args.out.mkdir(parents=True, exist_ok=True)
    command = ["python", "scripts/train_apgym.py", *(argv or sys.argv[1:])]
    log = (args.out / "train.log").open("a")

    def say(text: str) -> None:
        line = f"[{time.strftime('%H:%M:%S')}] {text}"
        print(line, file=sys.stderr, flush=True)
        log.write(line + "\n")
        log.flush()

    vec = make_vec_env(make_env, n_envs=args.n_envs, seed=TRAIN_SEED + args.seed,
                       env_kwargs={"objects": args.objects, "budget": args.budget},
                       vec_env_cls=SubprocVecEnv if args.n_envs > 1 else None)  # fmt: skip
    model = PPO("MlpPolicy", vec, n_steps=256, batch_size=256, n_epochs=5, learning_rate=3e-4,
                gamma=0.99, seed=args.seed, device="cpu", verbose=0,
                policy_kwargs={"net_arch": {"pi": [256, 256], "vf": [256, 256]}})  # fmt: skip
    val_env = make_env(args.objects, args.budget)
    settings = recorded_settings(val_env.unwrapped.inner, objects=args.objects,
                                 reward="shape-by-touch loss")  # fmt: skip
    rows: list[dict[str, Any]] = []
    best: dict[str, Any] = {}
    start = time.perf_counter()

    def evaluate(steps: int) -> None:
        meta = {"env_id": HAPTIC_EXPLORE_COMPACT_ID, "settings": settings,
                "training": {"algo": "ppo", "through": ENV_ID, "steps": steps,
                             "seed": args.seed, "command": command}}  # fmt: skip
        actor = actor_from_sb3(model, meta)
        row = {"steps": steps, **validate(actor, val_env, args.val_episodes),
               "wall_seconds": time.perf_counter() - start}  # fmt: skip
        rows.append(row)
        if not best or row["val_anytime_loss"] < best["val_anytime_loss"]:
            best.clear()
            best.update(row)
            actor.save(args.out / "policy.npz")
        (args.out / "curve.csv").write_text(
            "steps,wall_seconds,val_anytime_loss,val_last_loss\n" + "".join(
                f"{r['steps']},{r['wall_seconds']:.0f},{r['val_anytime_loss']:.5f},"
                f"{r['val_last_loss']:.5f}\n" for r in rows))  # fmt: skip
        plot_curve(rows, args.out / "curve.png",
                   f"PPO through {ENV_ID} ({args.objects}, {args.budget} touches): "
                   f"validation, {args.val_episodes} objects")  # fmt: skip
        say(f"steps {steps}: anytime loss {row['val_anytime_loss']:.4f}, last "
            f"{row['val_last_loss']:.4f} ({row['wall_seconds']:.0f} s)")  # fmt: skip

    class Hooks(BaseCallback):
        def _on_step(self) -> bool:
            if self.num_timesteps // args.val_every > (self.num_timesteps - args.n_envs) // (
                args.val_every
            ):
                evaluate(self.num_timesteps)
            return True

    say(f"started: {' '.join(command)}")
    evaluate(0)
    model.learn(total_timesteps=args.timesteps, callback=Hooks())
    if rows[-1]["steps"] != model.num_timesteps:
        evaluate(model.num_timesteps)
    summary = {"best": best, "curve": rows, "manifest": manifest(command),
               "seconds": time.perf_counter() - start}  # fmt: skip
    (args.out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    vec.close()
    say(f"done: best anytime loss {best['val_anytime_loss']:.4f} at {best['steps']} steps")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
