"""Vector environments against one environment, in turn in the same run: JSON on stdout.

Per backend: one environment; hapticsim's vector environment with one worker per core
(``native``), without drawing episodes ahead and batch scheduling (``native_plain``) and with
more workers than cores (``native:W``); Gymnasium's ``AsyncVectorEnv``;
the N environments stepped by a thread pool in one process (``threads``); two free-running
processes; and the shard estimate (:func:`lab.benchmarks.env.shard_estimate`). The
numbers of ``docs/vector.md``::

    python scripts/bench_vector.py > docs/vector/bench.json      # ~10 min on 2 cores
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

from lab.benchmarks.env import benchmark_vector_env


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--backends", nargs="+", default=["analytic", "mujoco"])
    p.add_argument("--num-envs", type=int, default=8)
    p.add_argument("--steps", type=int, default=1600,
                   help="analytic steps per variant (MuJoCo: a quarter)")  # fmt: skip
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--variants", nargs="+", default=["native", "native_plain", "native:4", "async",
                                                    "threads"])
    args = p.parse_args()
    out = {"command": "python " + " ".join(sys.argv), "cpus": os.cpu_count()}
    for backend in args.backends:
        steps = args.steps if backend == "analytic" else args.steps // 4
        print(f"{backend}: {len(args.variants) + 1} variants x {args.repeats} rounds of {steps} "
              "steps", file=sys.stderr, flush=True)  # fmt: skip
        out[backend] = benchmark_vector_env(
            backend, args.num_envs, steps, variants=tuple(args.variants), repeats=args.repeats,
        ) | {"load_end": os.getloadavg()[0]}  # fmt: skip
    print(json.dumps(out))


if __name__ == "__main__":
    main()
