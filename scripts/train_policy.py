"""Train an exploration policy on hapticsim/HapticExploreCompact-v0, -Touch-v0 or
-TouchTactile-v0 and export it.

Off-policy (SAC, TQC, CrossQ) or on-policy (PPO) learners from stable-baselines3 / sb3-contrib on
the compact observation of ``HapticExploreCompact-v0`` (``--env compact``, default) or on the
touch history of ``HapticExploreTouch-v0`` (``--env touch``: contacts, normals and past touches
as sets, encoded by :class:`lab.training.sb3.TouchSetExtractor`) or on the same felt
through taxel pads, each touch's pad image in its element (``--env touch-tactile``:
``HapticExploreTouchTactile-v0``, analytic pads, ``ideal`` skin), analytic backend,
``--n-envs`` environments in subprocesses (``--vector subproc``) or in hapticsim's native vector
environment (``--vector native``: one worker process per core), seeded, checkpointed and
resumable. Every ``--val-every`` steps the current deterministic actor
(exported to numpy, exactly what ships) runs on a fixed validation set of objects (environment
seeds 10,000 + i, never used for training or by ``hapticsim policies evaluate --seed 0``) and the
mean epsilon after ``--budget`` touches goes into the learning curve (``curve.csv``,
``curve.png``). Training environments are seeded with 1,000,000 + 10,000 * seed + the step count
at which they start (a resumed run gets fresh objects).

Outputs in ``--out``: ``policy.npz`` (the actor of the best validation point, with the
environment version and settings; ``hapticsim policies evaluate --policy learned:PATH``),
``policy_last.npz`` (the last one), ``curve.csv``/``curve.png``, ``train.log``,
``summary.json``, and ``checkpoint/`` (model, replay buffer and state, to resume; large). Needs
the ``rl`` extra::

    pip install torch==2.13.0            # this machine: the CPU wheel from local disk
    pip install -e ".[rl]"
    nice -n 10 python scripts/train_policy.py --algo sac --timesteps 300000 --out runs/learned
    python scripts/train_policy.py --resume --out runs/learned     # continue after a stop

The shipped ``learned-touch`` actor (docs/policies/learned_touch/)::

    python scripts/train_policy.py --algo ppo --env touch --vector native --n-envs 16 \
        --n-steps 128 --n-epochs 5 --batch-size 256 --timesteps 1000000 --val-every 20000 \
        --checkpoint-every 50000 --max-hours 2.0 --out runs/learned_touch
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import os
import sys
import textwrap
import time
from pathlib import Path
from typing import Any

import numpy as np

ALGOS: tuple[str, ...] = ("sac", "tqc", "crossq", "ppo")
#: Observations: the compact one (HapticExploreCompact-v0), the touch history
#: (HapticExploreTouch-v0) or the touch history with pad images (HapticExploreTouchTactile-v0).
ENVS: tuple[str, ...] = ("compact", "touch", "touch-tactile")
#: Environment seeds of the validation set: VAL_SEED + i.
VAL_SEED: int = 10_000
#: Base of the training environments' seeds.
TRAIN_SEED: int = 1_000_000


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--algo", choices=ALGOS, default="sac")
    p.add_argument(
        "--env", choices=ENVS, default="compact",
        help="observation: 'compact' (HapticExploreCompact-v0, 85 numbers with coverage "
        "features), 'touch' (HapticExploreTouch-v0: contacts, normals and touches as sets, "
        "encoded by a permutation-invariant network) or 'touch-tactile' "
        "(HapticExploreTouchTactile-v0: the same felt through taxel pads, each touch's pad "
        "image in its element)",
    )  # fmt: skip
    p.add_argument(
        "--vector", choices=("subproc", "native"), default="subproc",
        help="SB3's SubprocVecEnv (one process per environment) or hapticsim's native vector "
        "environment (one worker process per core)",
    )  # fmt: skip
    p.add_argument(
        "--torch-threads", type=int, default=1,
        help="torch's threads (1: the environments use the other cores; PPO, which alternates "
        "between stepping and learning, may gain from more)",
    )  # fmt: skip
    p.add_argument("--n-steps", type=int, default=1024, help="PPO: steps per env per rollout")
    p.add_argument("--n-epochs", type=int, default=10, help="PPO: epochs per rollout")
    p.add_argument(
        "--set-net", type=int, nargs="+", default=[64, 64],
        help="--env touch and touch-tactile: widths of the per-element network of each set",
    )  # fmt: skip
    p.add_argument("--timesteps", type=int, default=300_000, help="environment steps in total")
    p.add_argument("--n-envs", type=int, default=2, help="environments (subprocesses)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--objects", default="random", help="object kind of training and validation")
    p.add_argument("--budget", type=int, default=10, help="touches per episode")
    p.add_argument("--noise", type=float, default=0.02, help="sensor noise sigma_N")
    p.add_argument("--reward", default="log_epsilon", choices=("log_epsilon", "epsilon"))
    p.add_argument(
        "--coverage-weight", type=float, default=2.0,
        help="weight of the reward's coverage term (mean gap drop; 0: epsilon only)",
    )  # fmt: skip
    p.add_argument(
        "--chamfer-samples", type=int, default=10,
        help="surface points of the per-step Chamfer distance (unused by the reward; 10 saves "
        "a quarter of a step)",
    )  # fmt: skip
    p.add_argument("--val-episodes", type=int, default=32)
    p.add_argument("--val-every", type=int, default=10_000, help="steps between validations")
    p.add_argument("--checkpoint-every", type=int, default=20_000)
    p.add_argument("--net", type=int, nargs="+", default=[128, 128], help="hidden layer widths")
    p.add_argument(
        "--critic-net", type=int, nargs="+", default=None,
        help="critic/value widths (default: --net; CrossQ's paper uses 1024 1024 or wider)",
    )  # fmt: skip
    p.add_argument("--lr", type=float, default=None, help="learning rate (default per algo)")
    p.add_argument(
        "--batch-size", type=int, default=None,
        help="minibatch size (default 256 for the off-policy learners, 128 for PPO)",
    )  # fmt: skip
    p.add_argument("--buffer-size", type=int, default=400_000)
    p.add_argument("--learning-starts", type=int, default=1_000)
    p.add_argument("--gamma", type=float, default=0.98)
    p.add_argument(
        "--gradient-steps", type=int, default=2,
        help="gradient steps per vector step (off-policy; 2 with 2 envs: one per transition)",
    )  # fmt: skip
    p.add_argument(
        "--max-hours", type=float, default=None,
        help="stop when the run's wall time (summed over resumes) reaches this many hours",
    )  # fmt: skip
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--resume", action="store_true", help="continue the run in --out")
    return p.parse_args(argv)


class Run:
    """The run's files in ``--out``: log, curve, checkpoint and state."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.ckpt = out / "checkpoint"
        self.state_path = self.ckpt / "state.json"
        self.log_path = out / "train.log"

    def log(self, text: str) -> None:
        line = f"{time.strftime('%Y-%m-%d %H:%M:%S')} load={os.getloadavg()[0]:.1f} {text}"
        with self.log_path.open("a") as fh:
            fh.write(line + "\n")
        print(line, file=sys.stderr, flush=True)


def env_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    return {
        "backend": "analytic", "objects": args.objects, "touch_budget": args.budget,
        "noise": args.noise, "reward": args.reward, "chamfer_samples": args.chamfer_samples,
        "coverage_weight": args.coverage_weight,
    }  # fmt: skip


def make_model(args: argparse.Namespace, env: Any) -> Any:
    import torch

    common = {"seed": args.seed, "device": "cpu", "verbose": 0, "gamma": args.gamma}
    arch = list(args.net)
    critic = list(args.critic_net or args.net)
    extractor: dict[str, Any] = {}
    if args.env != "compact":
        from hapticsim.envs.haptic_explore_touch_v0 import SETS, TACTILE_SETS
        from lab.training.sb3 import TouchSetExtractor

        sets = TACTILE_SETS if args.env == "touch-tactile" else SETS
        extractor = {"features_extractor_class": TouchSetExtractor,
                     "features_extractor_kwargs": {"hidden": tuple(args.set_net),
                                                   "sets": sets}}  # fmt: skip
    if args.algo == "ppo":
        from stable_baselines3 import PPO

        return PPO(
            "MlpPolicy", env, learning_rate=args.lr or 3e-4, n_steps=args.n_steps,
            batch_size=args.batch_size or 128, n_epochs=args.n_epochs,
            gae_lambda=0.95, ent_coef=0.0,
            policy_kwargs={"net_arch": {"pi": arch, "vf": critic}, "activation_fn": torch.nn.Tanh,
                           **extractor},
            **common,
        )  # fmt: skip
    off = {
        "buffer_size": args.buffer_size, "batch_size": args.batch_size or 256,
        "learning_starts": args.learning_starts, "train_freq": 1,
        "gradient_steps": args.gradient_steps,
    }  # fmt: skip
    if args.algo == "sac":
        from stable_baselines3 import SAC

        return SAC(
            "MlpPolicy", env, learning_rate=args.lr or 3e-4, tau=0.005,
            policy_kwargs={"net_arch": {"pi": arch, "qf": critic}, **extractor}, **off, **common,
        )  # fmt: skip
    if args.algo == "tqc":
        from sb3_contrib import TQC

        return TQC(
            "MlpPolicy", env, learning_rate=args.lr or 3e-4, tau=0.005,
            top_quantiles_to_drop_per_net=2,
            policy_kwargs={"net_arch": {"pi": arch, "qf": critic}, "n_critics": 2,
                           "n_quantiles": 25}, **off, **common,
        )  # fmt: skip
    from sb3_contrib import CrossQ

    return CrossQ(
        "MlpPolicy", env, learning_rate=args.lr or 1e-3,
        policy_kwargs={"net_arch": {"pi": arch, "qf": critic}}, **off, **common,
    )  # fmt: skip


def algo_class(name: str) -> Any:
    if name == "ppo":
        from stable_baselines3 import PPO

        return PPO
    if name == "sac":
        from stable_baselines3 import SAC

        return SAC
    if name == "tqc":
        from sb3_contrib import TQC

        return TQC
    from sb3_contrib import CrossQ

    return CrossQ


def make_vec_env(args: argparse.Namespace, start_step: int) -> Any:
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import SubprocVecEnv

    seed = TRAIN_SEED + 10_000 * args.seed + start_step
    if args.vector == "native":
        from lab.training.sb3 import NativeVecEnv

        vec = NativeVecEnv(env_id(args), args.n_envs, **env_kwargs(args))
        vec.seed(seed)
        return vec
    # "hapticsim:<id>" makes Gymnasium import hapticsim (which registers the id) in the
    # subprocesses, whatever their start method.
    return sb3_make_vec_env(
        "hapticsim:" + env_id(args), n_envs=args.n_envs, seed=seed, env_kwargs=env_kwargs(args),
        vec_env_cls=SubprocVecEnv if args.n_envs > 1 else None,
    )  # fmt: skip


def env_id(args: argparse.Namespace) -> str:
    from hapticsim.envs import registration as reg

    return {
        "compact": reg.HAPTIC_EXPLORE_COMPACT_ID, "touch": reg.HAPTIC_EXPLORE_TOUCH_ID,
        "touch-tactile": reg.HAPTIC_EXPLORE_TOUCH_TACTILE_ID,
    }[args.env]  # fmt: skip


def validate(actor: Any, env: Any, episodes: int) -> dict[str, float]:
    """Mean and median epsilon after the last touch of the validation episodes."""
    final = []
    for i in range(episodes):
        obs, _ = env.reset(seed=VAL_SEED + i)
        done = False
        info: dict[str, Any] = {}
        while not done:
            obs, _, terminated, truncated, info = env.step(actor(obs))
            done = terminated or truncated
        final.append(float(info["epsilon"]))
    return {"val_mean": float(np.mean(final)), "val_median": float(np.median(final))}


def plot_curve(rows: list[dict[str, Any]], path: Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    steps = [r["steps"] for r in rows]
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.plot(steps, [r["val_mean"] for r in rows], "o-", label="validation mean", markersize=3)
    ax.plot(steps, [r["val_median"] for r in rows], "s--", label="validation median", markersize=3)
    ax.set_xlabel("environment steps (touches)")
    ax.set_ylabel("epsilon after the last touch")
    ax.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)
    ax.set_yscale("log")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        import torch
        from stable_baselines3.common.callbacks import BaseCallback
        from stable_baselines3.common.vec_env import VecMonitor
    except ImportError:
        print("train_policy.py needs the rl extra: pip install -e '.[rl]'", file=sys.stderr)
        return 2
    if args.algo in ("tqc", "crossq"):
        try:
            import sb3_contrib  # noqa: F401
        except ImportError:
            print(f"--algo {args.algo} needs sb3-contrib: pip install -e '.[rl]'", file=sys.stderr)
            return 2

    import gymnasium as gym

    from lab.training.export import actor_from_sb3, recorded_settings

    torch.set_num_threads(args.torch_threads)  # 1: the environments use the other cores
    run = Run(args.out)
    command = "python scripts/train_policy.py " + " ".join(sys.argv[1:] if argv is None else argv)
    state: dict[str, Any] = {"steps": 0, "wall_seconds": 0.0, "curve": [], "best": None}
    if args.resume:
        if not run.state_path.is_file():
            print(f"--resume: no checkpoint in {run.ckpt}", file=sys.stderr)
            return 2
        state = json.loads(run.state_path.read_text())
        saved = state["args"]
        keep = {"out", "resume", "timesteps", "max_hours"}
        for k, v in saved.items():  # the run's settings come from the checkpoint
            if k not in keep:
                setattr(args, k, Path(v) if k == "out" else v)
    elif run.state_path.exists():
        print(f"{args.out} holds a run: pass --resume, or another --out", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    run.ckpt.mkdir(exist_ok=True)
    saved_args = {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()}

    vec = VecMonitor(make_vec_env(args, state["steps"]))
    cls = algo_class(args.algo)
    if args.resume:
        model = cls.load(run.ckpt / "model.zip", env=vec, device="cpu")
        buffer = run.ckpt / "replay_buffer.pkl"
        if buffer.is_file() and hasattr(model, "load_replay_buffer"):
            model.load_replay_buffer(buffer)
        run.log(f"resumed {args.algo} at {model.num_timesteps} steps: {command}")
    else:
        model = make_model(args, vec)
        run.log(f"started {args.algo}: {command}")
    trained_id = env_id(args)
    val_env = gym.make(trained_id, **env_kwargs(args))  # the variant: a wrapper of the core
    settings = recorded_settings(
        val_env, objects=args.objects, reward=args.reward, coverage_weight=args.coverage_weight
    )
    start_wall = time.perf_counter()
    base_wall = float(state["wall_seconds"])

    def meta(steps: int) -> dict[str, Any]:
        wall = base_wall + time.perf_counter() - start_wall
        return {
            "env_id": trained_id, "settings": settings,
            "training": {
                "algo": args.algo, "steps": steps, "seed": args.seed, "wall_seconds": wall,
                "command": command, "hyperparameters": saved_args,
                "validation": {"seeds": f"{VAL_SEED}..{VAL_SEED + args.val_episodes - 1}",
                               "objects": args.objects},
            },
        }  # fmt: skip

    def save_checkpoint(steps: int) -> None:
        model.save(run.ckpt / "model.tmp.zip")
        os.replace(run.ckpt / "model.tmp.zip", run.ckpt / "model.zip")
        if hasattr(model, "save_replay_buffer"):
            model.save_replay_buffer(run.ckpt / "replay_buffer.tmp.pkl")
            os.replace(run.ckpt / "replay_buffer.tmp.pkl", run.ckpt / "replay_buffer.pkl")
        state.update(steps=steps, wall_seconds=base_wall + time.perf_counter() - start_wall)
        state["args"] = saved_args
        tmp = run.state_path.with_suffix(".tmp")
        tmp.write_text(json.dumps(state, indent=1) + "\n")
        os.replace(tmp, run.state_path)
        run.log(f"checkpoint at {steps} steps")

    def evaluate(steps: int) -> None:
        actor = actor_from_sb3(model, meta(steps))
        t0 = time.perf_counter()
        row = {"steps": steps, **validate(actor, val_env, args.val_episodes)}
        row["wall_seconds"] = base_wall + time.perf_counter() - start_wall
        row["val_seconds"] = time.perf_counter() - t0
        row["train_final_epsilon"] = (
            float(np.mean(recent_eps[-200:])) if recent_eps else float("nan")
        )
        state["curve"].append(row)
        actor.save(args.out / "policy_last.npz")
        if state["best"] is None or row["val_mean"] < state["best"]["val_mean"]:
            state["best"] = row
            actor.save(args.out / "policy.npz")
        lines = ["steps,wall_seconds,val_mean,val_median,train_final_epsilon"]
        lines += [
            f"{r['steps']},{r['wall_seconds']:.1f},{r['val_mean']:.5f},{r['val_median']:.5f},"
            f"{r['train_final_epsilon']:.5f}"
            for r in state["curve"]
        ]
        (args.out / "curve.csv").write_text("\n".join(lines) + "\n")
        plot_curve(
            state["curve"], args.out / "curve.png",
            f"{args.algo.upper()} on {trained_id}, {args.objects} objects: validation "
            f"({args.val_episodes} objects, {args.budget} touches)",
        )  # fmt: skip
        run.log(
            f"steps {steps}: validation epsilon mean {row['val_mean']:.4f} median "
            f"{row['val_median']:.4f}; training episodes {row['train_final_epsilon']:.4f} "
            f"({row['val_seconds']:.0f} s validation, {row['wall_seconds']:.0f} s total)"
        )

    recent_eps: list[float] = []

    class Hooks(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.next_val = (model.num_timesteps // args.val_every + 1) * args.val_every
            self.next_ckpt = (model.num_timesteps // args.checkpoint_every + 1) * (
                args.checkpoint_every
            )
            self.bar = None

        def _on_training_start(self) -> None:
            from tqdm import tqdm

            self.bar = tqdm(
                total=args.timesteps, initial=model.num_timesteps, desc=args.algo,
                unit="step", file=sys.stderr, dynamic_ncols=True, mininterval=5.0,
            )  # fmt: skip

        def _on_step(self) -> bool:
            for done, info in zip(self.locals["dones"], self.locals["infos"], strict=True):
                if done:
                    recent_eps.append(float(info["epsilon"]))
            if self.bar is not None:
                self.bar.update(self.num_timesteps - self.bar.n)
            if self.num_timesteps >= self.next_val:
                evaluate(self.num_timesteps)
                self.next_val += args.val_every
            if self.num_timesteps >= self.next_ckpt:
                save_checkpoint(self.num_timesteps)
                self.next_ckpt += args.checkpoint_every
            wall = base_wall + time.perf_counter() - start_wall
            if args.max_hours is not None and wall >= 3600.0 * args.max_hours:
                run.log(f"stopping at {self.num_timesteps} steps: {wall:.0f} s of wall time")
                return False
            return True

        def _on_training_end(self) -> None:
            if self.bar is not None:
                self.bar.close()

    if not state["curve"]:
        evaluate(model.num_timesteps)  # the untrained actor: the curve's first point
    remaining = args.timesteps - model.num_timesteps
    if remaining > 0:
        model.learn(total_timesteps=remaining, callback=Hooks(), reset_num_timesteps=False)
    steps = int(model.num_timesteps)
    if not state["curve"] or state["curve"][-1]["steps"] != steps:
        evaluate(steps)
    save_checkpoint(steps)
    vec.close()
    summary = {
        "algo": args.algo, "steps": steps, "wall_seconds": state["wall_seconds"],
        "steps_per_second": steps / max(state["wall_seconds"], 1e-9), "best": state["best"],
        "last": state["curve"][-1], "command": command, "hyperparameters": saved_args,
        "load_average": os.getloadavg(),
    }  # fmt: skip
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    run.log(f"done: {json.dumps(summary['best'])}")
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
