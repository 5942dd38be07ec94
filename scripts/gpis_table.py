"""GPIS against nH and nML on the same contact sets: epsilon, IoU and fit time.

    python scripts/gpis_table.py --out docs/gpis/table.json --markdown

Synthetic contact sets (SPEC §5 noise, the paper's one-sided pattern, 150 contacts): the paper's
four bodies (2 seeds, sigma_N 0 / 0.05 / 0.1), random tapered superquadrics and random composites
(unions of 2-4 parts; their contacts the paper's patterns on every part) at 0.05. Needs the extra
``gpis`` (scikit-image). Prints JSON with the load average.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path


def cases() -> list[tuple[str, float, object, int]]:
    from hapticsim.data.bodies import BODIES
    from hapticsim.data.objects import random_composite, random_superquadric

    out = []
    for noise in (0.0, 0.05, 0.1):
        for body in BODIES.values():
            for seed in range(2):
                out.append(("paper bodies", noise, body, seed))
    for seed in range(6):
        out.append(("random tapered", 0.05, random_superquadric(500 + seed, True), seed))
    for seed in range(4):
        out.append(("random composites", 0.05, random_composite(700 + seed), seed))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None)
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()

    from hapticsim.data.synthetic import synthetic_dataset
    from hapticsim.fitting import fit
    from hapticsim.fitting.gpis import fit_gpis
    from hapticsim.metrics import score

    load, start, rows = os.getloadavg(), time.perf_counter(), []
    todo = cases()
    for i, (family, noise, truth, seed) in enumerate(todo):
        data = synthetic_dataset(truth, noise, rng=seed)
        row = {"family": family, "noise": noise, "seed": seed}
        g = fit_gpis(data.points, data.normals)
        s = score(g.solid, truth, rng=0)
        row["gpis"] = {"epsilon": s.epsilon, "iou": s.iou, "seconds": g.seconds,
                       "length_scale": g.length_scale}  # fmt: skip
        for method in ("nH", "nML"):
            r = fit(data.points, data.normals, method=method, rng=seed)
            s = score(r.solid, truth, rng=0)
            row[method] = {"epsilon": s.epsilon, "iou": s.iou, "seconds": r.seconds}
        rows.append(row)
        print(f"{i + 1}/{len(todo)} {family} {noise}: gpis {row['gpis']['epsilon']:.3f} "
              f"nH {row['nH']['epsilon']:.3f} nML {row['nML']['epsilon']:.3f}",
              file=sys.stderr, flush=True)  # fmt: skip
    table = []
    for key in sorted({(r["family"], r["noise"]) for r in rows}):
        sel = [r for r in rows if (r["family"], r["noise"]) == key]
        entry = {"family": key[0], "noise": key[1], "cases": len(sel)}
        for m in ("gpis", "nH", "nML"):
            entry[m] = {
                "epsilon_mean": statistics.fmean(r[m]["epsilon"] for r in sel),
                "iou_mean": statistics.fmean(r[m]["iou"] for r in sel),
                "seconds_median": statistics.median(r[m]["seconds"] for r in sel),
            }
        table.append(entry)
    out = {"cases": len(rows), "table": table, "rows": rows, "load_average": list(load),
           "seconds": round(time.perf_counter() - start, 1),
           "command": "python scripts/gpis_table.py " + " ".join(sys.argv[1:])}  # fmt: skip
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    json.dump({k: v for k, v in out.items() if k != "rows"}, sys.stdout, indent=1)
    print()
    if args.markdown:
        print("| family | σ_N | cases | GPIS ε | nH ε | nML ε | GPIS IoU | nH IoU | GPIS s "
              "| nH s |")
        print("|:---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for t in table:
            g, h, m = t["gpis"], t["nH"], t["nML"]
            print(f"| {t['family']} | {t['noise']:g} | {t['cases']} | {g['epsilon_mean']:.3f} | "
                  f"{h['epsilon_mean']:.3f} | {m['epsilon_mean']:.3f} | {g['iou_mean']:.3f} | "
                  f"{h['iou_mean']:.3f} | {g['seconds_median']:.2f} | {h['seconds_median']:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
