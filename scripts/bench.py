"""Benchmarks of hapticsim, printed as one JSON object on stdout (progress on stderr).

    python scripts/bench.py                  # all sections
    python scripts/bench.py --section fit    # EOF throughput and fit times only

Sections (each a function ``section_<name>(args) -> dict``; add one by writing the function and
listing it in ``SECTIONS``):

- ``fit``: EOF evaluations per second for 150 contacts with normals (a population of P vectors per
  call, the genetic algorithm's case; one vector per call; a Jacobian), and the median wall and CPU
  seconds of a default fit per method over the paper's four bodies x ``--poses`` random poses x
  sigma_N in {0, 0.02, 0.05, 0.1} (``paper_dataset``; the fast-loop issue's grid).
- ``startup``: the first fit of a fresh Python process, with numba's cache cold (an empty cache
  directory: everything compiles) and warm (the cache that the cold run wrote).
- ``score``: one step's scoring in the environment (:class:`hapticsim.metrics.episode.
  TruthScorer`: alpha, beta, epsilon, IoU, Chamfer) and one ``hapticsim score`` (100 000 samples).
- ``env``: steps per second of ``hapticsim/HapticExplore-v0`` with random touches, per backend,
  one process (resets counted and not), and ``make_vec(..., num_envs=8)`` (hapticsim's vector
  environment, one worker per core) and Gymnasium's ``AsyncVectorEnv`` of 8 against one process,
  in turn in the same run (:func:`lab.benchmarks.env.benchmark_vector_env`).
- ``sim``: physics steps per second of the hand + object scene and a 150-contact ``paper``
  exploration per body (:func:`lab.benchmarks.sim.benchmark_sim`).
- ``multi``: the median wall and CPU seconds of a ``method="multi"`` fit of 300 contacts against
  nH's on the same contacts: area samples of the L-block and of 10 random composites (seeds
  200-209), and the paper's patterns on the four bodies (one part), with the parts it chose.
- ``tactile``: exact against tactile sensing in the same run: the environment's steps per
  second with random touches per backend (ideal skin; ``--tactile-mujoco-episodes`` MuJoCo
  episodes, 20 by default: an episode's cost depends on its chaotic path, and over 5 the MuJoCo
  ratio fell anywhere in 0.44-0.54 between runs), and ``explore``'s whole work (simulation, fit,
  score, files, report picture) on the paper's four bodies, the two alternating.

The machine is shared: every section records the 1-minute load average beside its timings;
medians are quoted, and CPU seconds (which other processes change less) beside wall seconds.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

NOISES = (0.0, 0.02, 0.05, 0.1)


def _load() -> float:
    return os.getloadavg()[0]


def _rates(call: Callable[[], Any], per_call: int, seconds: float) -> dict[str, float]:
    """Evaluations per second of `call` (which does `per_call` of them): ``best`` and ``median``
    of single calls' wall times, ``cpu`` over the process CPU time of all calls."""
    call()  # warm up
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
    from hapticsim.data.bodies import BODY_NAMES, get_body
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting import DEFAULT_BUDGET, METHODS, fit
    from hapticsim.fitting.objective import Objective
    from hapticsim.geometry import random_rotation

    rng = np.random.default_rng(0)
    data = paper_dataset(get_body("tapered_box"), noise=0.1, rng=0, count=150)
    objective = Objective(data.points, data.normals, lam=0.5, budget=2**62, distance="tapered")
    truth = get_body("tapered_box").to_vector()
    scale = np.r_[[0.005] * 3, [0.1] * 4, [0.3] * 3, [0.005] * 3]
    throughput: dict[str, Any] = {"contacts": 150, "normals": True, "load": _load()}
    vectors = truth
    for count in args.population:
        vectors = objective.bounds.clip(truth + rng.normal(size=(count, 13)) * scale)
        throughput[f"population_{count}"] = _rates(
            lambda v=vectors: objective.eof(v), count, args.seconds
        )
    one = vectors[:1]
    throughput["single_vector"] = _rates(lambda: objective.eof(one), 1, args.seconds)
    contacts = objective.contacts
    throughput["jacobian_per_second"] = _rates(
        lambda: contacts.jacobian(one[0], 0.5, True), 1, args.seconds
    )

    fits: dict[str, Any] = {}
    methods = METHODS if args.methods is None else tuple(args.methods)
    for method in methods:
        wall, cpu, evals = [], [], []
        for noise in NOISES:
            for name in BODY_NAMES:
                for seed in range(args.poses):
                    pose = np.random.default_rng(seed)
                    truth_sq = get_body(name).transformed(
                        random_rotation(pose), pose.normal(0.0, 0.1, 3)
                    )
                    contacts_ = paper_dataset(truth_sq, noise=noise, rng=seed)
                    t0 = time.process_time()
                    result = fit(contacts_.points, contacts_.normals, method=method, rng=seed)
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
        print(f"bench fit: {method} done", file=sys.stderr)
    return {
        "eof_evaluations_per_second": throughput,
        "default_fit": {
            "budget": DEFAULT_BUDGET,
            "data": f"paper_dataset, 4 bodies x {args.poses} poses x sigma_N {list(NOISES)}",
            "load": _load(),
            "methods": fits,
        },
    }


_FIRST_FIT = """
import time
t0 = time.perf_counter()
from hapticsim.data.bodies import get_body
from hapticsim.data.synthetic import paper_dataset
from hapticsim.fitting import fit
t1 = time.perf_counter()
c = paper_dataset(get_body("cube"), noise=0.1, rng=0)
fit(c.points, c.normals, method="nH", rng=0)
t2 = time.perf_counter()
fit(c.points, c.normals, method="nH", rng=1)
t3 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2)
"""


#: A warm process's set-up, step by step: numba's own start (its compiler's registries, which
#: it loads before any cached function, scipy.linalg among them), then the kernels nH uses.
_WARM_PARTS = """
import time
t0 = time.perf_counter()
import hapticsim.fitting
from hapticsim.fitting import kernels
from numba.core.registry import cpu_target
t1 = time.perf_counter()
cpu_target.target_context.refresh()
t2 = time.perf_counter()
kernels.prepare("nH")
t3 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2)
"""


def _cli_fit(path: str, out: str, env: dict[str, str], runs: int = 5) -> dict[str, Any]:
    """`hapticsim fit FILE` in fresh processes (the console script's code path): median wall,
    and the fit's own `seconds` and `setup_seconds` from its JSON."""
    walls, seconds, setup = [], [], []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "hapticsim.cli", "fit", path, "--out", out],
                       env=env, capture_output=True, check=True)  # fmt: skip
        walls.append(time.perf_counter() - start)
        data = json.loads(Path(out).read_text())
        seconds.append(data["seconds"])
        setup.append(data["setup_seconds"])
    return {"runs": runs, "wall_median": float(np.median(walls)),
            "seconds_median": float(np.median(seconds)),
            "setup_seconds_median": float(np.median(setup))}  # fmt: skip


def section_startup(args: argparse.Namespace) -> dict[str, Any]:
    """First-fit time of fresh processes with numba's cache cold and warm; a warm process's
    set-up step by step; and `hapticsim fit FILE` (150 contacts) from start to exit."""
    from hapticsim.data.bodies import get_body
    from hapticsim.data.io import Contacts, write_contacts
    from hapticsim.data.synthetic import paper_dataset

    out: dict[str, Any] = {"load": _load()}
    with tempfile.TemporaryDirectory() as cache:
        env = os.environ | {"NUMBA_CACHE_DIR": cache}
        for label in ("cold", "warm"):
            proc = subprocess.run(
                [sys.executable, "-c", _FIRST_FIT], env=env, capture_output=True, text=True,
                check=True,
            )  # fmt: skip
            imp, first, second = (float(v) for v in proc.stdout.split())
            out[label] = {"import_seconds": imp, "first_fit_seconds": first,
                          "second_fit_seconds": second}  # fmt: skip
        parts = []
        for _ in range(5):
            proc = subprocess.run([sys.executable, "-c", _WARM_PARTS], env=env,
                                  capture_output=True, text=True, check=True)  # fmt: skip
            parts.append([float(v) for v in proc.stdout.split()])
        imp, numba_start, kernels = np.median(np.array(parts), axis=0)
        out["warm_setup"] = {"import_fitting_seconds": float(imp),
                             "numba_start_seconds": float(numba_start),
                             "kernel_load_seconds": float(kernels)}  # fmt: skip
        data = paper_dataset(get_body("cube"), noise=0.02, rng=0)
        contacts = Path(cache) / "contacts.npz"
        write_contacts(contacts, Contacts(points=data.points, normals=data.normals))
        out["cli_fit"] = _cli_fit(str(contacts), str(Path(cache) / "fit.json"), env)
    out["load_end"] = _load()
    return out


def section_score(args: argparse.Namespace) -> dict[str, Any]:
    """One environment step's scoring, and one `hapticsim score`."""
    from hapticsim.data.bodies import get_body
    from hapticsim.metrics import score
    from hapticsim.metrics.episode import TruthScorer

    truth = get_body("tapered_box")
    estimates = [
        truth.replace(a=truth.a * f, eps=e)
        for f, e in ((1.05, (0.2, 0.3)), (0.95, (1.0, 1.0)), (1.1, (0.5, 1.5)))
    ]
    scorer = TruthScorer(truth, rng=0)
    for e in estimates:
        scorer.score(e)
    step_wall, step_cpu = [], []
    for _ in range(args.score_repeats):
        for e in estimates:
            t0, c0 = time.perf_counter(), time.process_time()
            scorer.score(e)
            step_wall.append(time.perf_counter() - t0)
            step_cpu.append(time.process_time() - c0)
    score(estimates[0], truth)
    full = []
    for e in estimates:
        t0 = time.perf_counter()
        score(e, truth)
        full.append(time.perf_counter() - t0)
    return {
        "load": _load(),
        "env_step_score": {
            "samples": scorer.samples, "chamfer_samples": scorer.chamfer_samples,
            "median_seconds": float(np.median(step_wall)),
            "median_cpu_seconds": float(np.median(step_cpu)),
        },
        "hapticsim_score": {"samples": 100_000, "median_seconds": float(np.median(full))},
    }  # fmt: skip


def section_env(args: argparse.Namespace) -> dict[str, Any]:
    """Steps per second of hapticsim/HapticExplore-v0 (random touches), one and two processes."""
    from lab.benchmarks.env import benchmark_env, benchmark_vector_env

    out: dict[str, Any] = {}
    for backend in args.backends:
        episodes = args.env_episodes if backend == "analytic" else args.mujoco_episodes
        out[backend] = benchmark_env(backend, episodes) | {"load": _load()}
        out[f"{backend}_vector"] = benchmark_vector_env(
            backend, args.num_envs,
            args.vector_steps if backend == "analytic" else args.vector_steps // 2,
        ) | {"load": _load()}  # fmt: skip
    return out


def section_sim(args: argparse.Namespace) -> dict[str, Any]:
    """MuJoCo hand: physics steps per second and a 150-contact paper exploration per body."""
    from lab.benchmarks.sim import benchmark_sim

    return benchmark_sim(count=150) | {"load": _load()}


def section_tactile(args: argparse.Namespace) -> dict[str, Any]:
    """Exact against tactile sensing, same run: environment steps per second per backend and
    explore's time per body (medians over the four bodies)."""
    from hapticsim.exploration import explore
    from lab.benchmarks.env import benchmark_env

    out: dict[str, Any] = {}
    for backend in args.backends:
        episodes = args.env_episodes if backend == "analytic" else args.tactile_mujoco_episodes
        rows = {
            sensing: benchmark_env(backend, episodes, sensing=sensing) | {"load": _load()}
            for sensing in ("exact", "tactile")
        }
        for key in ("steps_per_second", "steps_per_second_with_resets", "steps_per_cpu_second"):
            rows[f"{key}_ratio"] = rows["tactile"][key] / rows["exact"][key]
        out[backend] = rows
    bodies = ("tapered_box", "cube", "cylinder", "ellipsoid")
    times: dict[str, dict[str, list[float]]] = {
        s: {"wall": [], "cpu": []} for s in ("exact", "tactile")
    }
    with tempfile.TemporaryDirectory() as tmp:
        explore("cube", seed=0, out_dir=f"{tmp}/warm", progress=False, sensing="tactile")
        for body in bodies:
            for sensing in ("exact", "tactile"):
                t, c = time.perf_counter(), time.process_time()
                explore(body, seed=0, out_dir=f"{tmp}/{body}-{sensing}", progress=False,
                        sensing=sensing)  # fmt: skip
                times[sensing]["wall"].append(time.perf_counter() - t)
                times[sensing]["cpu"].append(time.process_time() - c)
                print(f"bench tactile: explore {body} {sensing}", file=sys.stderr)
    explore_out: dict[str, Any] = {
        s: {"wall_median": float(np.median(v["wall"])), "cpu_median": float(np.median(v["cpu"])),
            "wall": v["wall"]}
        for s, v in times.items()
    }  # fmt: skip
    explore_out["wall_ratio"] = (
        explore_out["tactile"]["wall_median"] / explore_out["exact"]["wall_median"]
    )
    explore_out["cpu_ratio"] = (
        explore_out["tactile"]["cpu_median"] / explore_out["exact"]["cpu_median"]
    )
    out["explore"] = explore_out | {"load": _load()}
    return out


def section_multi(args: argparse.Namespace) -> dict[str, Any]:
    from hapticsim.data import get_body, paper_dataset
    from hapticsim.data.example_meshes import l_block
    from hapticsim.data.objects import random_composite
    from hapticsim.fitting import fit

    sets: dict[str, list[tuple[Any, Any]]] = {"l_block": [], "composites": [], "bodies": []}
    for seed in range(3):
        sets["l_block"].append(l_block().sample_surface(300, rng=seed))
    for seed in range(200, 210):
        sets["composites"].append(random_composite(seed).sample_surface(300, rng=seed))
    for k, body in enumerate(("tapered_box", "cube", "cylinder", "ellipsoid")):
        c = paper_dataset(get_body(body), noise=0.0, rng=k, count=300)
        sets["bodies"].append((c.points, c.normals))
    fit(*sets["bodies"][0], method="multi", rng=0)  # warm up (compiled kernels)
    out: dict[str, Any] = {"load_start": _load()}
    for name, data in sets.items():
        row: dict[str, Any] = {}
        for method in ("nH", "multi"):
            wall, cpu, parts = [], [], []
            for k, (points, normals) in enumerate(data):
                t0, c0 = time.perf_counter(), time.process_time()
                result = fit(points, normals, method=method, rng=k)
                wall.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
                parts.append(len(result.solid.components))
            row[method] = {"wall_median": float(np.median(wall)), "wall_max": float(np.max(wall)),
                           "cpu_median": float(np.median(cpu)), "parts": parts}  # fmt: skip
        out[name] = row
    out["load_end"] = _load()
    return out


SECTIONS: dict[str, Callable[[argparse.Namespace], dict[str, Any]]] = {
    "fit": section_fit,
    "multi": section_multi,
    "startup": section_startup,
    "score": section_score,
    "env": section_env,
    "sim": section_sim,
    "tactile": section_tactile,
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="hapticsim benchmarks (JSON on stdout)")
    parser.add_argument("--section", choices=(*SECTIONS, "all"), nargs="+", default=["all"])
    parser.add_argument("--seconds", type=float, default=2.0, help="timing per throughput case")
    parser.add_argument("--population", type=int, nargs="+", default=[40, 100])
    parser.add_argument("--poses", type=int, default=10, help="fit: random poses per body")
    parser.add_argument("--methods", nargs="+", default=None, help="fit: methods (default all)")
    parser.add_argument("--score-repeats", type=int, default=30)
    parser.add_argument("--backends", nargs="+", default=["analytic", "mujoco"])
    parser.add_argument("--env-episodes", type=int, default=20, help="env: analytic episodes")
    parser.add_argument("--mujoco-episodes", type=int, default=5, help="env: MuJoCo episodes")
    parser.add_argument("--tactile-mujoco-episodes", type=int, default=20,
                        help="tactile: MuJoCo episodes per sensing (a ratio of chaotic episodes' "
                             "costs: 5 put it anywhere in 0.44-0.54)")  # fmt: skip
    parser.add_argument("--vector-steps", type=int, default=1600,
                        help="env: analytic steps per variant (MuJoCo: half)")  # fmt: skip
    parser.add_argument("--num-envs", type=int, default=8, help="env: vector environments' N")
    args = parser.parse_args(argv)
    names = list(SECTIONS) if "all" in args.section else args.section
    out: dict[str, Any] = {"load_average_1min": _load(), "cpus": os.cpu_count()}
    for name in names:
        out[name] = SECTIONS[name](args)
        print(f"bench: {name} done", file=sys.stderr)
    out["load_average_1min_end"] = _load()
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
