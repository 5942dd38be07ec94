"""Train an exploration policy with Ray RLlib (PPO or SAC) on hapticsim/HapticExploreCompact-v0.

The environments run in RLlib's EnvRunners on a Ray cluster (``--address auto`` joins the one
``ray start --head`` began on this machine; ``--address HOST:6379`` another; none starts one in
this process). Same objects, touches, noise and reward as ``scripts/train_policy.py`` (SB3);
validation on its objects (seeds 10,000 + i) against random touches. Needs the ``ray`` extra::

    pip install torch==2.13.0 && pip install -e ".[ray]"
    ray start --head --num-cpus 2
    python scripts/train_rllib.py --address auto --algo ppo --timesteps 140000 --out runs/rllib-ppo
    ray stop

Outputs in ``--out``: ``curve.csv``, ``summary.json`` (with ``learns``: the best validation
epsilon below random's) and ``best/`` (the RLlib module of the best validation point).
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import sys

from hapticsim.errors import HapticsimError
from lab.training.rllib import ALGOS, PPO_LR, VECTORIZE, build_config, train


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--algo", choices=ALGOS, default="ppo")
    p.add_argument("--address", default=None, help="Ray cluster ('auto': the local ray start)")
    p.add_argument("--timesteps", type=int, default=140_000, help="environment steps in all")
    p.add_argument("--runners", type=int, default=2, help="EnvRunner actors")
    p.add_argument("--envs-per-runner", type=int, default=1)
    p.add_argument("--vectorize", choices=VECTORIZE, default="sync")
    p.add_argument("--eval-every", type=int, default=10_000, help="steps between validations")
    p.add_argument("--val-episodes", type=int, default=32)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--lr-end", type=float, default=None,
                   help=f"PPO: the learning rate falls linearly from {PPO_LR:g} to this by "
                   "--timesteps")  # fmt: skip
    p.add_argument("--max-hours", type=float, default=None)
    p.add_argument("--out", required=True)
    args = p.parse_args()
    if args.lr_end is not None and (args.algo != "ppo" or not args.lr_end > 0):
        p.error(f"--lr-end must be > 0 and goes with --algo ppo, got {args.lr_end} with "
                f"--algo {args.algo}")  # fmt: skip
    try:
        summary = _run(args)
    except HapticsimError as exc:
        sys.exit(f"train_rllib.py: {exc}")
    print(json.dumps(summary, default=str))


def _run(args: argparse.Namespace) -> dict:
    training = {}
    if args.lr_end is not None:
        training["lr"] = [[0, PPO_LR], [args.timesteps, args.lr_end]]
    config = build_config(
        args.algo, num_env_runners=args.runners, num_envs_per_env_runner=args.envs_per_runner,
        vectorize=args.vectorize, seed=args.seed, **training,
    )  # fmt: skip
    return train(config, args.timesteps, args.out, args.eval_every, args.val_episodes,
                 args.address, args.max_hours)  # fmt: skip


if __name__ == "__main__":
    main()
