"""nML against nH and the truth-started oracle, with an ablation of nML's ingredients.

Cases: the paper's four bodies at random poses (pose seeds ``--paper-seeds``, as in
``scripts/fit_table.py``) and random tapered superquadrics (``ObjectDistribution
("random_tapered")``, shape seeds ``--random-seeds``, each at a random pose drawn from the same
seed), 150 contacts from ``paper_dataset`` at each noise level sigma_N. Per case: default nH, the
oracle (nLS from the truth on the paper EOF, as ``fit_table.py``), and nML variants:

- ``nML``: the default (noise estimated from the residuals);
- ``nML-known``: the true sigma_N given (``noise=``);
- ``nML-mlsearch``: the hybrid search on the ML objective itself instead of nH's EOF search;
- ``-robust``: no robust loss (plain squares); ``-prior``: no taper prior; ``-refine``: no
  re-estimation after the search (weights from the data size and the assumed noise only);
- ``nML-eps``: adds a prior on the shape exponents;
- ``nML:field=value;...``: any :class:`~hapticsim.fitting.ml.MLOptions` fields (the tuning).

Printed on stdout: JSON with, per variant, group (``paper``, ``random``, ``all``) and noise level,
the mean epsilon (Monte Carlo, ``--samples`` points per solid), its standard error, and the
median fit seconds; per nML run the estimated sigma_N (mean ratio to the truth). ``--rows``
writes every run.

    python scripts/nml_table.py --paper-seeds 100-109 --random-seeds 1000-1059   # held out
    python scripts/nml_table.py --paper-seeds 200-204 --random-seeds 2000-2019   # tuning
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any

import numpy as np

from hapticsim.parallel import parallel_map

VARIANTS = ("nH", "oracle", "nML", "nML-known", "nML-mlsearch", "nML-robust", "nML-prior",
            "nML-refine", "nML-eps")  # fmt: skip


def _seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def _truth(kind: str, seed: int) -> Any:
    from hapticsim.data.bodies import get_body
    from hapticsim.data.distributions import ObjectDistribution
    from hapticsim.geometry import random_rotation

    rng = np.random.default_rng(seed)
    if kind == "random":
        shape = ObjectDistribution("random_tapered").sample(rng)
    else:
        shape = get_body(kind)
    return shape.transformed(random_rotation(rng), rng.normal(0.0, 0.1, size=3))


def _fit(variant: str, contacts: Any, truth: Any, noise: float, seed: int) -> Any:
    from hapticsim.fitting import fit
    from hapticsim.fitting.ml import with_options

    pts, nrm = contacts.points, contacts.normals
    if variant == "nH":
        return fit(pts, nrm, method="nH", rng=seed)
    if variant == "oracle":
        return fit(pts, nrm, method="nLS", initial=truth)
    if ":" in variant:  # nML:field=value,...: any MLOptions fields (floats, None, a,b tuples)
        changes = {}
        for item in variant.split(":", 1)[1].split(";"):
            key, _, value = item.partition("=")
            parsed: Any = None if value == "None" else (
                tuple(float(v) for v in value.split(",")) if "," in value else
                (value if key == "search" else float(value)))  # fmt: skip
            changes[key] = int(parsed) if key in ("refine", "candidates") else parsed
        return fit(pts, nrm, method="nML", rng=seed, options=with_options(None, **changes))
    changes: dict[str, Any] = {
        "nML": {}, "nML-known": {}, "nML-robust": {"robust": 0.0},
        "nML-prior": {"taper_prior": None}, "nML-refine": {"refine": 0},
        "nML-eps": {"eps_prior": (0.5, 0.5)}, "nML-mlsearch": {"search": "ml"},
    }[variant]  # fmt: skip
    known = noise if variant == "nML-known" else None
    return fit(pts, nrm, method="nML", rng=seed, noise=known, options=with_options(None, **changes))


def _task(args: tuple[str, int, float, tuple[str, ...], int]) -> list[dict[str, Any]]:
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.metrics import volume_overlap

    kind, seed, noise, variants, samples = args
    truth = _truth(kind, seed)
    contacts = paper_dataset(truth, noise=noise, rng=seed + 7919)
    rows = []
    for variant in variants:
        cpu = time.process_time()
        result = _fit(variant, contacts, truth, noise, seed)
        cpu = time.process_time() - cpu
        overlap = volume_overlap(result.superquadric, truth, samples=samples, rng=seed)
        rows.append({
            "group": "random" if kind == "random" else "paper", "body": kind, "seed": seed,
            "noise": noise, "variant": variant, "epsilon": overlap.alpha + overlap.beta,
            "seconds": result.seconds, "cpu_seconds": cpu, "evaluations": result.evaluations,
            "noise_estimate": result.noise,
        })  # fmt: skip
    return rows


def _summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for variant in dict.fromkeys(r["variant"] for r in rows):
        out[variant] = {}
        for group in ("paper", "random", "all"):
            cells = {}
            for noise in sorted({r["noise"] for r in rows}):
                sel = [r for r in rows if r["variant"] == variant and r["noise"] == noise
                       and group in ("all", r["group"])]  # fmt: skip
                eps = np.array([r["epsilon"] for r in sel])
                cell = {
                    "epsilon": float(eps.mean()),
                    "stderr": float(eps.std(ddof=1) / np.sqrt(len(eps))) if len(eps) > 1 else 0.0,
                    "seconds_median": float(np.median([r["seconds"] for r in sel])),
                    # CPU time: what a fit costs whatever else the shared machine runs
                    "cpu_seconds_median": float(np.median([r["cpu_seconds"] for r in sel])),
                    "runs": len(sel),
                }
                est = [
                    r["noise_estimate"] / noise
                    for r in sel
                    if r["noise_estimate"] is not None and noise > 0 and variant == "nML"
                ]
                if est:
                    cell["noise_ratio_mean"] = float(np.mean(est))
                    cell["noise_ratio_within_20pct"] = float(np.mean(np.abs(np.array(est) - 1)
                                                                     <= 0.2))  # fmt: skip
                cells[str(noise)] = cell
            out[variant][group] = cells
    return out


def _markdown(table: dict[str, Any], group: str) -> str:
    noises = list(next(iter(table.values()))[group])
    lines = [f"| {group} | " + " | ".join(f"sigma_N={n}" for n in noises) + " | median s |",
             "|---" * (len(noises) + 2) + "|"]  # fmt: skip
    for variant, groups in table.items():
        cells = [f"{groups[group][n]['epsilon']:.4f} ± {groups[group][n]['stderr']:.4f}"
                 for n in noises]  # fmt: skip
        secs = np.median([groups[group][n]["seconds_median"] for n in noises])
        lines.append(f"| {variant} | " + " | ".join(cells) + f" | {secs:.3f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--variants", default=",".join(VARIANTS), help="comma- (or |-) separated variants"
    )
    parser.add_argument("--bodies", default="tapered_box,cube,cylinder,ellipsoid")
    parser.add_argument("--paper-seeds", default="100-109", help="pose seeds, LO-HI")
    parser.add_argument("--random-seeds", default="1000-1059", help="shape seeds, LO-HI")
    parser.add_argument("--noise", default="0,0.02,0.05,0.1", help="comma-separated sigma_N")
    parser.add_argument("--samples", type=int, default=100_000, help="Monte Carlo points")
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--rows", default=None, help="also write every run as JSON here")
    parser.add_argument("--markdown", action="store_true", help="Markdown tables instead")
    args = parser.parse_args(argv)

    variants = (
        tuple(args.variants.split("|")) if "|" in args.variants else tuple(args.variants.split(","))
    )
    kinds = [(b, s) for b in args.bodies.split(",") for s in _seeds(args.paper_seeds)]
    kinds += [("random", s) for s in _seeds(args.random_seeds)]
    tasks = [(k, s, float(n), variants, args.samples) for n in args.noise.split(",")
             for k, s in kinds]  # fmt: skip
    start, load = time.perf_counter(), os.getloadavg()
    chunks = parallel_map(_task, tasks, args.processes, "nML table")
    rows = [row for chunk in chunks for row in chunk]
    table = _summary(rows)
    if args.rows:
        with open(args.rows, "w") as fh:
            json.dump(rows, fh)
    if args.markdown:
        sys.stdout.write("\n\n".join(_markdown(table, g) for g in ("all", "paper", "random")))
        sys.stdout.write("\n")
        return 0
    out = {
        "table": table,
        "cases_per_noise": len(kinds),
        "volume_method": f"Monte Carlo, {args.samples} points per solid",
        "wall_seconds": time.perf_counter() - start,
        "load_average": {"start": load, "end": os.getloadavg()},
    }
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
