"""Would sharing fits between the workers lift the native vector environment? JSON on stdout.

Measures where each step's time goes for N environments (:func:`lab.benchmarks.env.
step_components`) and estimates, from those times, how busy 2 cores would be under the native
vector environment's static shards, under sharing the fits between the shards, and under an
ideal scheduler of whole steps (:func:`lab.benchmarks.env.schedule_estimates`). The
numbers of ``docs/vector.md``'s "Sharing fits between the workers"::

    python scripts/vector_schedules.py > docs/vector/schedules.json      # ~2 min on 2 cores
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

import numpy as np

from lab.benchmarks.env import schedule_estimates, step_components


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--backends", nargs="+", default=["analytic", "mujoco"])
    p.add_argument("--num-envs", type=int, default=8)
    p.add_argument("--steps", type=int, default=400,
                   help="steps per environment (MuJoCo: a quarter)")  # fmt: skip
    p.add_argument("--job-costs", type=float, nargs="+", default=[0.0, 1e-4, 2e-4],
                   help="seconds of one message between processes")  # fmt: skip
    args = p.parse_args()
    out: dict = {"command": "python " + " ".join(sys.argv), "cpus": os.cpu_count()}
    for backend in args.backends:
        steps = args.steps if backend == "analytic" else args.steps // 4
        print(f"{backend}: {args.num_envs} environments x {steps} steps", file=sys.stderr,
              flush=True)  # fmt: skip
        load = os.getloadavg()[0]
        parts = step_components(backend, args.num_envs, steps)
        step = parts["step"]
        out[backend] = {
            "load_start": load,
            "load_end": os.getloadavg()[0],
            "steps_per_env": steps,
            "step_ms": {"mean": 1e3 * float(step.mean()), "median": 1e3 * float(np.median(step))},
            "touch_ms": 1e3 * float(parts["touch"].mean()),
            "fit_ms": 1e3 * float(parts["fit"].mean()),
            "full_fit_share": float(parts["full"].mean()),
            "full_fit_ms": 1e3 * float(parts["fit"][parts["full"]].mean()),
            "efficiency": {
                f"job_cost_{cost * 1e3:g}ms": schedule_estimates(parts, 2, cost)
                for cost in args.job_costs
            },
        }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
