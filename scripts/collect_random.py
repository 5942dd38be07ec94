"""Collect environment steps with random actions on the native vector environment, timed.

Issue 25's yardstick: one million analytic steps with random actions within an hour on a
2-core machine. Steps ``gym.make_vec(ENV_ID, num_envs=N)`` (hapticsim's vector environment, one
worker process per core) with uniform random actions, keeps every step's reward, epsilon and
contact count (float32, in memory) and every finished episode's final epsilon, and writes a
JSON summary (and optionally the per-step arrays as ``.npz``). Progress on stderr every 30 s.

    python scripts/collect_random.py --steps 1000000 --out docs/vector/random_1m.json
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import hapticsim  # noqa: F401  (registers the environments)
from hapticsim.envs.registration import HAPTIC_EXPLORE_ID


def _cpu_seconds() -> float:
    """CPU seconds of this process and its finished children."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=1_000_000, help="environment steps")
    parser.add_argument("--num-envs", type=int, default=16, help="environments of the batch")
    parser.add_argument("--workers", type=int, default=None, help="worker processes (cores)")
    parser.add_argument("--backend", default="analytic", choices=("analytic", "mujoco"))
    parser.add_argument("--env-id", default=HAPTIC_EXPLORE_ID)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, required=True, help="JSON summary")
    parser.add_argument("--npz", type=Path, default=None, help="per-step arrays (optional)")
    args = parser.parse_args()
    if args.steps < args.num_envs:
        parser.error(f"--steps must be >= --num-envs ({args.num_envs}), got {args.steps}")

    load_start = os.getloadavg()
    start_cpu = _cpu_seconds()
    start = time.perf_counter()
    envs = gym.make_vec(args.env_id, num_envs=args.num_envs, backend=args.backend,
                        workers=args.workers)  # fmt: skip
    envs.action_space.seed(args.seed)
    envs.reset(seed=args.seed)
    made = time.perf_counter() - start
    rounds = args.steps // args.num_envs
    n = rounds * args.num_envs
    reward = np.zeros(n, np.float32)
    epsilon = np.zeros(n, np.float32)
    contacts = np.zeros(n, np.float32)
    finals: list[float] = []
    last = time.perf_counter()
    for k in range(rounds):
        _, r, terminated, truncated, info = envs.step(envs.action_space.sample())
        rows = slice(k * args.num_envs, (k + 1) * args.num_envs)
        reward[rows], epsilon[rows], contacts[rows] = r, info["epsilon"], info["n_contacts"]
        done = terminated | truncated
        finals += [float(e) for e in info["epsilon"][done]]
        if time.perf_counter() - last >= 30.0:
            last = time.perf_counter()
            done_steps = (k + 1) * args.num_envs
            rate = done_steps / (last - start)
            print(f"{done_steps:,} steps, {rate:.0f} steps/s, {len(finals):,} episodes, "
                  f"about {(n - done_steps) / rate / 60:.1f} min left, load "
                  f"{os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)  # fmt: skip
    envs.close()
    seconds = time.perf_counter() - start
    summary = {
        "command": "python " + " ".join(sys.argv),
        "env_id": args.env_id,
        "backend": args.backend,
        "num_envs": args.num_envs,
        "workers": args.workers,
        "steps": n,
        "seconds": seconds,
        "make_and_reset_seconds": made,
        "cpu_seconds": _cpu_seconds() - start_cpu,
        "steps_per_second": n / seconds,
        "episodes": len(finals),
        "final_epsilon_mean": float(np.mean(finals)) if finals else None,
        "final_epsilon_median": float(np.median(finals)) if finals else None,
        "reward_mean": float(reward.mean()),
        "contacts_per_step_mean": float(contacts.mean()),
        "cpus": os.cpu_count(),
        "load_average_start": list(load_start),
        "load_average_end": list(os.getloadavg()),
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_suffix(".tmp")
    tmp.write_text(json.dumps(summary, indent=1) + "\n")
    tmp.replace(args.out)
    if args.npz is not None:
        np.savez_compressed(args.npz, reward=reward, epsilon=epsilon, n_contacts=contacts)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
