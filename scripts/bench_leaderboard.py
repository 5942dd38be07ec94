"""The committed baseline leaderboard of the benchmark protocol (docs/leaderboard/).

    python scripts/bench_leaderboard.py [--episodes 30] [--scheduler local:2 | --workers 2]

Runs, on the test split (20 touches, analytic backend) of every family with exact and tactile
``vision`` sensing, the six baseline policies with the environment's nH estimator, and nML,
multi and GPIS (scored at touches 5, 10 and 20) with the uncertainty policy: every episode of
every cell in one map (costly tasks first) on a local Dask cluster by default. Writes one results
file per cell into ``--results`` (default ``runs/leaderboard/``: every touch's metrics and
estimate, tens of megabytes for the full board, so not committed; the command regenerates
them), the leaderboard
(``hapticsim bench report``: ``leaderboard.md``, ``index.html``), ``summary.json`` (each cell's
areas under the touch curves with their intervals and final values) and the manifest (command,
commit, machine, packages, seconds) into OUT. Progress on stderr. Needs the extras
``objects`` (the pybullet family), ``gpis`` and ``dask``.
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

from hapticsim.bench.report import write_report
from hapticsim.bench.runner import bench_jobs, bench_results, run_episode, write_results
from hapticsim.bench.tasks import FAMILIES
from hapticsim.parallel import parallel_map
from hapticsim.suites.provenance import manifest

SENSINGS = ("exact", "vision")
POLICIES = ("uncertainty", "random", "paper", "information", "learned", "learned-touch")
ESTIMATORS = ("nML", "multi", "gpis")
OUT = Path(__file__).resolve().parents[1] / "docs" / "leaderboard"
RESULTS = Path(__file__).resolve().parents[1] / "runs" / "leaderboard"
#: Relative cost of an episode by family and sensing (measured: CPU seconds per episode with the
#: uncertainty policy), to start the costly ones first.
COST = {"pybullet": 4.0, "composite": 1.5, "holed": 1.0, "paper": 0.7, "random": 0.7}


def cells(families: list[str]) -> list[tuple[str, str, str]]:
    """(task, policy, estimator) of every cell of the board."""
    out = []
    for family in families:
        for sensing in SENSINGS:
            task = f"{family}/{sensing}/analytic/t20"
            out += [(task, policy, "env-nH") for policy in POLICIES]
            out += [(task, "uncertainty", estimator) for estimator in ESTIMATORS]
    return out


def _cell_summary(results: dict) -> dict:
    """A cell's figures for ``summary.json``: per metric the area's mean and 95 % interval and
    the mean after the last scored touch (4 digits)."""

    def r(x):
        return None if x is None else round(float(x), 4)

    out = {"task": results["task"]["name"], "policy": results["policy"],
           "estimator": results["estimator"], "episodes": len(results["episodes"])}  # fmt: skip
    for metric, s in results["summary"].items():
        last = [v for v in s["mean_curve"] if v is not None]
        out[metric] = {"area": r(s["area_mean"]),
                       "ci95": None if s["area_ci95"] is None else [r(v) for v in s["area_ci95"]],
                       "last": r(last[-1]) if last else None}  # fmt: skip
    return out


def main(argv: list[str] | None = None) -> int:
    from hapticsim.errors import HapticsimError

    try:
        return _board(argv)
    except HapticsimError as exc:  # one line, exit status 2, nothing written
        print(f"bench_leaderboard: {exc}", file=sys.stderr)
        return 2


def _board(argv: list[str] | None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=30)
    parser.add_argument("--scheduler", default="local:2", help="a Dask cluster (default local:2)")
    parser.add_argument("--workers", type=int, default=None,
                        help="local processes instead of Dask")  # fmt: skip
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--results", type=Path, default=RESULTS,
                        help="the per-cell results files (default runs/leaderboard)")  # fmt: skip
    args = parser.parse_args(argv)
    command = ["python", "scripts/bench_leaderboard.py", *(argv or sys.argv[1:])]
    board = cells(args.families.split(","))
    jobs = {cell: bench_jobs(cell[0], cell[1], args.episodes, cell[2]) for cell in board}
    flat = [job for cell in board for job in jobs[cell]]
    print(f"{len(board)} cells, {len(flat)} episodes", file=sys.stderr, flush=True)
    start = time.perf_counter()
    scheduler = None if args.workers else args.scheduler

    def cost(job) -> float:
        family, sensing = job.task.split("/")[:2]
        fitted = job.estimator != "env-nH"
        scale = (2.0 if sensing == "vision" else 1.0) * (1.5 if fitted else 1.0)
        return COST.get(family, 1.0) * scale

    rows = parallel_map(run_episode, flat, workers=args.workers, desc="leaderboard",
                        names=lambda j: j.label, unit="episode", scheduler=scheduler,
                        cost=cost)  # fmt: skip
    seconds = time.perf_counter() - start
    results_dir = args.results
    args.out.mkdir(parents=True, exist_ok=True)
    results_dir.mkdir(parents=True, exist_ok=True)
    for old in [*args.out.glob("*__*.json"), *results_dir.glob("*__*.json")]:
        old.unlink()  # a board is one run: no cell of an earlier one stays behind
    paths, summary, k = [], [], 0
    for cell in board:
        n = len(jobs[cell])
        results = bench_results(jobs[cell], rows[k : k + n], "test", seconds, command)
        k += n
        task, policy, estimator = cell
        name = f"{task.replace('/', '_')}__{policy}__{estimator}.json"
        paths.append(write_results(results, results_dir / name))
        summary.append(_cell_summary(results))
    write_report(paths, args.out)
    lines = ",\n".join(json.dumps(cell) for cell in summary)  # one cell per line
    (args.out / "summary.json").write_text(f"[\n{lines}\n]\n")
    m = manifest(command) | {"files": sorted(p.name for p in paths), "seconds": seconds,
                             "cells": len(board), "episodes": len(flat)}  # fmt: skip
    (args.out / "manifest.json").write_text(json.dumps(m, indent=2) + "\n")
    print(f"{len(board)} cells in {seconds:.0f} s", file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
