"""Benchmark of hapticsim/HapticExplore-v0: environment steps per second in one process.

Runs random-policy episodes on each backend and prints JSON on stdout (progress on stderr):
steps per second (wall clock and CPU time), and the mean time per step of the touch, the fit and
the metrics, with how many steps did a full fit.

    python scripts/bench_env.py                       # both backends, 3 episodes each
    python scripts/bench_env.py --backend analytic --episodes 10 --out bench_env.json
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402

import hapticsim  # noqa: E402, F401  (registers the environment)
from hapticsim.data.io import write_text_atomic  # noqa: E402
from hapticsim.envs.haptic_explore_v0 import BACKENDS  # noqa: E402
from hapticsim.envs.registration import HAPTIC_EXPLORE_ID  # noqa: E402


def bench(backend: str, episodes: int, seed: int, objects: str) -> dict:
    """Time `episodes` random episodes of the default environment on `backend`."""
    env = gym.make(HAPTIC_EXPLORE_ID, backend=backend, objects=objects)
    env.action_space.seed(seed)
    steps = 0
    parts = {"touch": 0.0, "fit": 0.0, "metrics": 0.0}
    full = 0
    wall0, cpu0 = time.perf_counter(), time.process_time()
    reset_seconds = 0.0
    for ep in range(episodes):
        t = time.perf_counter()
        env.reset(seed=seed + ep)
        reset_seconds += time.perf_counter() - t
        done = False
        while not done:
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            timings = info["timings"]
            for k in parts:
                parts[k] += getattr(timings, k)
            full += info["fit_status"] == "full"
            steps += 1
            done = terminated or truncated
        print(f"{backend}: episode {ep + 1}/{episodes}, {steps} steps", file=sys.stderr)
    wall = time.perf_counter() - wall0
    cpu = time.process_time() - cpu0
    env.close()
    return {
        "backend": backend,
        "objects": objects,
        "episodes": episodes,
        "steps": steps,
        "steps_per_second": steps / (wall - reset_seconds),
        "steps_per_cpu_second": steps / cpu,
        "reset_seconds": reset_seconds / episodes,
        "seconds_per_step": {k: v / steps for k, v in parts.items()},
        "full_fit_fraction": full / steps,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", choices=(*BACKENDS, "all"), default="all")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--objects", default="paper")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=None, help="also write the JSON here")
    args = parser.parse_args(argv)
    backends = BACKENDS if args.backend == "all" else (args.backend,)
    result = {
        "benchmark": "env",
        "machine": {"cpus": os.cpu_count(), "python": sys.version.split()[0]},
        "numpy": np.__version__,
        "results": [bench(b, args.episodes, args.seed, args.objects) for b in backends],
    }
    text = json.dumps(result, indent=2)
    if args.out is not None:
        write_text_atomic(args.out, text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
