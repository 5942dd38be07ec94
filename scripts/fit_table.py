"""Quality and speed of the four fitting methods and an oracle on the paper's bodies.

For each of the paper's four bodies, each seed and each noise level sigma_N, the body is placed at
a random pose (rotation and translation drawn from the seed), a synthetic data set of 150 contacts
is drawn with ``paper_dataset(truth, noise, rng)``, and every method fits it with the default
budget. The oracle is nLS started from the ground truth (calibration: what a local minimiser of
the same EOF reaches from the right basin). Printed on stdout: JSON with, per method and noise
level, the mean epsilon (alpha + beta, Monte Carlo, see ``volume_method``), the mean theta
(eq. 10, SPEC EOF) and the median seconds of a fit; ``--markdown`` prints a Markdown table instead.

    python scripts/fit_table.py                       # 4 bodies x 10 seeds x 4 noise levels
    python scripts/fit_table.py --seeds 3 --noise 0.1 --methods nH,oracle --markdown
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from typing import Any

import numpy as np

from hapticsim.parallel import parallel_map

METHODS = ("LS", "H", "nLS", "nH", "oracle")


def _task(args: tuple[str, int, float, tuple[str, ...], int | None, str, int]) -> list[dict]:
    from hapticsim.data.bodies import get_body
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting import fit
    from hapticsim.geometry import random_rotation
    from hapticsim.metrics import theta, volume_overlap

    name, seed, noise, methods, budget, distance, samples = args
    pose_rng, data_rng = (np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(2))
    truth = get_body(name).transformed(random_rotation(pose_rng), pose_rng.normal(0.0, 0.1, size=3))
    contacts = paper_dataset(truth, noise=noise, rng=data_rng)
    rows = []
    for method in methods:
        if method == "oracle":
            result = fit(
                contacts.points, contacts.normals, method="nLS", budget=budget,
                initial=truth, distance=distance,
            )  # fmt: skip
        else:
            result = fit(
                contacts.points, contacts.normals, method=method, budget=budget, rng=seed,
                distance=distance,
            )  # fmt: skip
        est = result.superquadric
        normals = contacts.normals if method in ("nLS", "nH", "oracle") else None
        overlap = volume_overlap(est, truth, samples=samples, rng=seed)
        rows.append(
            {
                "body": name,
                "seed": seed,
                "noise": noise,
                "method": method,
                "epsilon": overlap.alpha + overlap.beta,
                "theta": float(theta(est, truth, contacts.points, normals)),
                "seconds": result.seconds,
                "evaluations": result.evaluations,
                "eof": result.eof,
            }
        )
    return rows


def _summary(rows: list[dict], methods: tuple[str, ...], noises: list[float]) -> dict[str, Any]:
    table: dict[str, Any] = {}
    for method in methods:
        table[method] = {}
        for noise in noises:
            sel = [r for r in rows if r["method"] == method and r["noise"] == noise]
            table[method][str(noise)] = {
                "epsilon": float(np.mean([r["epsilon"] for r in sel])),
                "theta": float(np.mean([r["theta"] for r in sel])),
                "seconds": float(np.median([r["seconds"] for r in sel])),
                "runs": len(sel),
            }
    return table


def _markdown(table: dict[str, Any], noises: list[float]) -> str:
    head = "| method | " + " | ".join(f"sigma_N={n}" for n in noises) + " |"
    lines = [head, "|---" * (len(noises) + 1) + "|"]
    for method, cols in table.items():
        cells = [
            f"eps {c['epsilon']:.3f}, theta {c['theta']:.2e}, {c['seconds']:.2f} s"
            for c in (cols[str(n)] for n in noises)
        ]
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument("--bodies", default="tapered_box,cube,cylinder,ellipsoid")
    parser.add_argument("--noise", default="0,0.02,0.05,0.1", help="comma-separated sigma_N")
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--budget", type=int, default=None, help="default: DEFAULT_BUDGET")
    parser.add_argument("--distance", default="tapered", help="D1 metric of the search")
    parser.add_argument("--samples", type=int, default=100_000, help="Monte Carlo points")
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--markdown", action="store_true", help="Markdown instead of JSON")
    parser.add_argument("--rows", default=None, help="also write every run as JSON here")
    args = parser.parse_args(argv)

    methods = tuple(args.methods.split(","))
    noises = [float(n) for n in args.noise.split(",")]
    tasks = [
        (body, seed, noise, methods, args.budget, args.distance, args.samples)
        for noise in noises
        for body in args.bodies.split(",")
        for seed in range(args.seeds)
    ]
    start = time.perf_counter()
    chunks = parallel_map(_task, tasks, args.processes, "fit table")
    rows = [row for chunk in chunks for row in chunk]
    table = _summary(rows, methods, noises)
    if args.rows:
        with open(args.rows, "w") as fh:
            json.dump(rows, fh)
    if args.markdown:
        sys.stdout.write(_markdown(table, noises) + "\n")
    else:
        out = {
            "table": table,
            "runs_per_cell": len(tasks) // len(noises),
            "volume_method": f"Monte Carlo, {args.samples} points per solid",
            "wall_seconds": time.perf_counter() - start,
        }
        sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
