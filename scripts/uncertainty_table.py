"""Calibration of the fits' uncertainty: how often its intervals hold the truth.

    python scripts/uncertainty_table.py --out docs/uncertainty/calibration.json --markdown

Four families of synthetic contact sets (SPEC §5 noise, the paper's one-sided pattern), none of
them used to build the approximation (it has no tuned constant): the paper's four bodies at 150
contacts, random tapered superquadrics, few contacts (40) on the paper's bodies, and elongated or
flat shapes. Each set is fitted by METHOD with ``uncertainty=True``; a case counts a hit when the
true volume lies in the 50 % / 90 % volume interval, and when each true semi-axis lies in its 90 %
interval. Prints JSON (rates per family and noise level, with the load average).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

NOISES = (0.02, 0.05, 0.1)
ELONGATED = (  # semi-axes [m] and exponents of the elongated / flat family
    ((0.06, 0.015, 0.012), (0.3, 0.5)), ((0.015, 0.05, 0.01), (1.0, 1.0)),
    ((0.04, 0.04, 0.008), (0.2, 0.8)), ((0.012, 0.012, 0.06), (0.6, 0.3)),
    ((0.05, 0.02, 0.02), (1.5, 0.2)),
)  # fmt: skip


def families() -> list[tuple[str, float, object, int, int]]:
    """(family, noise, truth, count, seed) of every case."""
    from hapticsim.data.bodies import BODIES
    from hapticsim.data.objects import random_superquadric
    from hapticsim.geometry import Superquadric

    cases = []
    for noise in NOISES:
        for body in BODIES.values():
            for seed in range(10):
                cases.append(("paper bodies, 150", noise, body, 150, seed))
        for seed in range(30):
            cases.append(("random tapered, 150", noise, random_superquadric(1000 + seed, True),
                          150, seed))  # fmt: skip
    for noise in (0.05, 0.1):
        for body in BODIES.values():
            for seed in range(5):
                cases.append(("paper bodies, 40", noise, body, 40, 100 + seed))
    for k, (a, eps) in enumerate(ELONGATED):
        for seed in range(4):
            truth = Superquadric(a=a, eps=eps)
            cases.append(("elongated / flat, 150", 0.05, truth, 150, 200 + 10 * k + seed))
    return cases


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", default="nH")
    parser.add_argument("--out", default=None)
    parser.add_argument("--markdown", action="store_true", help="also print a Markdown table")
    args = parser.parse_args()

    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting import fit

    rows = []
    start, load = time.perf_counter(), os.getloadavg()
    cases = families()
    for i, (family, noise, truth, count, seed) in enumerate(cases):
        data = paper_dataset(truth, noise, rng=seed, count=count)
        result = fit(data.points, data.normals, method=args.method, rng=seed, uncertainty=True)
        u = result.uncertainty.to_dict()
        vol = truth.volume
        lo50, hi50 = u["volume"]["interval50"]
        lo90, hi90 = u["volume"]["interval90"]
        a90 = u["a"]["interval90"]
        # the fit may name the axes in another order: compare sorted semi-axes
        order = np.argsort(result.superquadric.a)
        true_a = np.sort(truth.a)
        a_hits = [a90[j][0] <= t <= a90[j][1] for j, t in zip(order, true_a, strict=True)]
        rows.append({
            "family": family, "noise": noise, "seed": seed,
            "volume50": bool(lo50 <= vol <= hi50), "volume90": bool(lo90 <= vol <= hi90),
            "a90": float(np.mean(a_hits)), "rank": u["rank"],
            "volume_error": float(result.superquadric.volume / vol - 1),
            "interval90_width": float((hi90 - lo90) / vol),
        })  # fmt: skip
        if (i + 1) % 25 == 0:
            print(f"{i + 1}/{len(cases)} cases", file=sys.stderr, flush=True)
    table = []
    keys = sorted({(r["family"], r["noise"]) for r in rows}, key=lambda k: (k[0], k[1]))
    for family, noise in keys + [("all", None)]:
        sel = [r for r in rows
               if family == "all" or (r["family"] == family and r["noise"] == noise)]
        table.append({
            "family": family, "noise": noise, "cases": len(sel),
            "volume50": float(np.mean([r["volume50"] for r in sel])),
            "volume90": float(np.mean([r["volume90"] for r in sel])),
            "a90": float(np.mean([r["a90"] for r in sel])),
            "median_interval90_width": float(np.median([r["interval90_width"] for r in sel])),
            "median_abs_volume_error": float(np.median([abs(r["volume_error"]) for r in sel])),
        })  # fmt: skip
    out = {
        "method": args.method, "cases": len(rows), "table": table, "rows": rows,
        "seconds": round(time.perf_counter() - start, 1), "load_average": list(load),
        "command": "python scripts/uncertainty_table.py " + " ".join(sys.argv[1:]),
    }  # fmt: skip
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    json.dump({k: v for k, v in out.items() if k != "rows"}, sys.stdout, indent=1)
    print()
    if args.markdown:
        print("| family | σ_N | cases | volume in 50 % | volume in 90 % | a in 90 % | "
              "90 % width / V | median abs(V error) |")
        print("|:---|---:|---:|---:|---:|---:|---:|---:|")
        for t in table:
            noise = "all" if t["noise"] is None else f"{t['noise']:g}"
            print(f"| {t['family']} | {noise} | {t['cases']} | {t['volume50']:.0%} | "
                  f"{t['volume90']:.0%} | {t['a90']:.0%} | {t['median_interval90_width']:.3f} | "
                  f"{t['median_abs_volume_error']:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
