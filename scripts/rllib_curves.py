"""Plot RLlib learning curves (``curve.csv`` of scripts/train_rllib.py) against random touches.

    python scripts/rllib_curves.py docs/vector/rllib_ppo docs/vector/rllib_sac \
        --out docs/vector/rllib_curves.png
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("runs", nargs="+", type=Path, help="folders with curve.csv and summary.json")
    p.add_argument("--out", type=Path, required=True, help="PNG to write")
    args = p.parse_args()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharex=True)
    random = None
    for run in args.runs:
        rows = list(csv.DictReader((run / "curve.csv").open()))
        summary = json.loads((run / "summary.json").read_text())
        random = summary["random_validation"]
        # the seed and a learning-rate schedule where the summary records them (runs since
        # 2026-12-05), else the folder's name
        tag = f"seed {summary['seed']}" if summary.get("seed") is not None else run.name
        if isinstance(summary.get("lr"), list):
            tag += f", lr {summary['lr'][0][1]:g} to {summary['lr'][-1][1]:g}"
        label = f"{summary['algo'].removesuffix('Config')} ({tag})"
        steps = [int(r["steps"]) for r in rows]
        for ax, key in zip(axes, ("val_mean", "val_median"), strict=True):
            ax.plot(steps, [float(r[key]) for r in rows], "o-", markersize=3, label=label)
    for ax, key, name in zip(axes, ("mean", "median"), ("mean", "median"), strict=True):
        if random is not None:
            ax.axhline(random[key], color="0.4", linestyle="--", label="random touches")
        ax.set_yscale("log")
        ax.set_xlabel("environment steps (touches)")
        ax.set_ylabel(f"validation epsilon after 10 touches ({name})")
        ax.legend(fontsize=8)
    fig.suptitle("RLlib on HapticExploreCompact-v0 (analytic, 32 validation objects, "
                 "deterministic policy)", fontsize=10)  # fmt: skip
    fig.tight_layout()
    fig.savefig(args.out, dpi=130)
    print(args.out)


if __name__ == "__main__":
    main()
