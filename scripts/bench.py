"""Benchmarks of hapticsim, printed as one JSON object on stdout.

    python scripts/bench.py                  # all sections
    python scripts/bench.py --section fit    # EOF throughput and fit times only

Sections (each a function ``section_<name>(args) -> dict``; add one by writing the function and
listing it in ``SECTIONS``):

- ``sim``: physics steps per second of the hand + object scene (a fingertip pressing) and wall
  and CPU seconds of a 150-contact ``paper`` exploration per body
  (:func:`hapticsim.sim.benchmark.benchmark_sim`; also ``scripts/bench_sim.py``).
- ``env``: steps per second of ``hapticsim/HapticExplore-v0`` with random touches, per backend
  (:func:`hapticsim.envs.benchmark.benchmark_env`; also ``scripts/bench_env.py``).
- ``fit``: EOF evaluations per second for 150 contacts with normals, a population of P vectors
  per call (the genetic algorithm's case) and one vector per call (scipy's least squares), best
  and median of repeated timings; and the median seconds (wall clock and CPU) of a default fit
  per method on the paper's four bodies with ``paper_dataset(truth, noise=0.1, rng=seed)``.

Timings on a shared machine vary with its load; the best of several repeats estimates the speed
of an idle machine, the median what a user sees. CPU seconds of a single-threaded fit do not
depend on the load much.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np


def _rates(call: Callable[[], Any], per_call: int, seconds: float) -> dict[str, float]:
    """Evaluations per second of `call` (which does `per_call` of them).

    ``best`` and ``median`` over the wall-clock times of single calls, and ``cpu``: all calls
    over the process CPU time they took (insensitive to other processes on the machine).
    """
    call()  # warm up (workspace, caches)
    times = []
    start, cpu_start = time.perf_counter(), time.process_time()
    while time.perf_counter() - start < seconds or len(times) < 5:
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    cpu = time.process_time() - cpu_start
    return {
        "best": per_call / min(times),
        "median": per_call / float(np.median(times)),
        "cpu": per_call * len(times) / cpu,
    }


def section_fit(args: argparse.Namespace) -> dict[str, Any]:
    from threadpoolctl import threadpool_limits

    from hapticsim.data.bodies import BODY_NAMES, get_body
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting import DEFAULT_BUDGET, METHODS, fit
    from hapticsim.fitting.objective import Objective
    from hapticsim.geometry import random_rotation

    rng = np.random.default_rng(0)
    data = paper_dataset(get_body("tapered_box"), noise=0.1, rng=0, count=150)
    objective = Objective(data.points, data.normals, lam=0.5, budget=2**62)
    tapered = Objective(data.points, data.normals, lam=0.5, budget=2**62, distance="tapered")
    truth = get_body("tapered_box").to_vector()
    scale = np.r_[[0.005] * 3, [0.1] * 4, [0.3] * 3, [0.005] * 3]
    throughput: dict[str, Any] = {"contacts": 150, "normals": True}
    with threadpool_limits(limits=1, user_api="blas"):
        for count in args.population:
            vectors = objective.bounds.clip(truth + rng.normal(size=(count, 13)) * scale)
            throughput[f"population_{count}"] = _rates(
                lambda v=vectors: objective.eof(v), count, args.seconds
            )
        throughput[f"population_{count}_tapered_distance"] = _rates(
            lambda v=vectors: tapered.eof(v), count, args.seconds
        )
        one = vectors[:1]
        throughput["single_vector"] = _rates(lambda: objective.eof(one), 1, args.seconds)

    fits: dict[str, Any] = {}
    for method in METHODS:
        wall, cpu, evals = [], [], []
        for name in BODY_NAMES:
            for seed in range(args.seeds):
                pose = np.random.default_rng(seed)
                truth_sq = get_body(name).transformed(
                    random_rotation(pose), pose.normal(0.0, 0.1, 3)
                )
                contacts = paper_dataset(truth_sq, noise=0.1, rng=seed)
                t0 = time.process_time()
                result = fit(contacts.points, contacts.normals, method=method, rng=seed)
                cpu.append(time.process_time() - t0)
                wall.append(result.seconds)
                evals.append(result.evaluations)
        fits[method] = {
            "median_seconds": float(np.median(wall)),
            "median_cpu_seconds": float(np.median(cpu)),
            "max_seconds": float(np.max(wall)),
            "median_evaluations": float(np.median(evals)),
            "fits": len(wall),
        }
    return {
        "eof_evaluations_per_second": throughput,
        "default_fit": {
            "budget": DEFAULT_BUDGET,
            "data": f"paper_dataset(noise=0.1), 4 bodies x {args.seeds} seeds, random poses",
            "methods": fits,
        },
    }


def section_env(args: argparse.Namespace) -> dict[str, Any]:
    """Steps per second of hapticsim/HapticExplore-v0 on each backend (random touches)."""
    from hapticsim.envs.benchmark import benchmark_env

    return {b: benchmark_env(b, args.env_episodes) for b in ("analytic", "mujoco")}


def section_sim(args: argparse.Namespace) -> dict[str, Any]:
    """MuJoCo hand: physics steps per second and a 150-contact paper exploration per body."""
    from hapticsim.sim.benchmark import benchmark_sim

    return benchmark_sim(count=150)


SECTIONS: dict[str, Callable[[argparse.Namespace], dict[str, Any]]] = {
    "fit": section_fit,
    "env": section_env,
    "sim": section_sim,
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="hapticsim benchmarks (JSON on stdout)")
    parser.add_argument("--section", choices=(*SECTIONS, "all"), default="all")
    parser.add_argument("--seconds", type=float, default=2.0, help="timing per throughput case")
    parser.add_argument("--population", type=int, nargs="+", default=[100, 200])
    parser.add_argument("--seeds", type=int, default=3, help="fit: seeds per body")
    parser.add_argument("--env-episodes", type=int, default=3, help="env: episodes per backend")
    args = parser.parse_args(argv)
    names = list(SECTIONS) if args.section == "all" else [args.section]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    out: dict[str, Any] = {"load_average_1min": load, "cpus": os.cpu_count()}
    for name in names:
        out[name] = SECTIONS[name](args)
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
