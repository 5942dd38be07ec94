"""Plot and tabulate the learning curves of scripts/train_policy.py runs (docs/policies/learned).

Each run folder holds ``curve.csv`` (steps, wall seconds, validation epsilon mean and median) and
``checkpoint/state.json`` (or a copy, ``state.json``) or ``summary.json`` (the run's settings).
Prints a Markdown table (one row per run: algorithm, steps, wall time, validation epsilon at the
last and best point) and writes a plot of validation epsilon against environment steps and
against wall time:

    python scripts/learning_curves.py runs/select-sac runs/select-tqc --labels SAC TQC \\
        --out docs/policies/learned/selection.png
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path


def read_curve(run: Path) -> list[dict[str, float]]:
    with (run / "curve.csv").open() as fh:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(fh)]


def run_algo(run: Path) -> str:
    """The run's algorithm, from its state (``checkpoint/state.json``, or ``state.json`` in a
    copied run without checkpoint) or its summary."""
    for state_path in (run / "checkpoint" / "state.json", run / "state.json"):
        if state_path.is_file():
            return str(json.loads(state_path.read_text())["args"]["algo"])
    summary_path = run / "summary.json"
    if summary_path.is_file():
        return str(json.loads(summary_path.read_text())["algo"])
    return "?"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=Path, help="run folders of train_policy.py")
    parser.add_argument("--labels", nargs="+", default=None, help="one label per run")
    parser.add_argument("--out", type=Path, required=True, help="the plot (.png)")
    parser.add_argument("--title", default="validation: mean epsilon after 10 touches")
    parser.add_argument(
        "--reference", nargs="*", default=[], metavar="NAME=EPS",
        help="horizontal reference lines, e.g. random=0.074 uncertainty=0.018",
    )  # fmt: skip
    args = parser.parse_args(argv)
    labels = args.labels or [r.name for r in args.runs]
    if len(labels) != len(args.runs):
        parser.error("--labels needs one label per run")
    for run in args.runs:
        if not (run / "curve.csv").is_file():
            parser.error(f"{run} has no curve.csv")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.0))
    rows = ["| run | algorithm | steps | wall [min] | last val. mean (median) | best val. mean |",
            "|---|---|---|---|---|---|"]  # fmt: skip
    for run, label in zip(args.runs, labels, strict=True):
        curve = read_curve(run)
        algo = run_algo(run)
        steps = [r["steps"] for r in curve]
        mean = [r["val_mean"] for r in curve]
        axes[0].plot(steps, mean, "o-", markersize=3, label=label)
        axes[1].plot([r["wall_seconds"] / 60 for r in curve], mean, "o-", markersize=3, label=label)
        last = curve[-1]
        rows.append(
            f"| {label} | {algo.upper()} | {int(last['steps'])} | {last['wall_seconds'] / 60:.0f} "
            f"| {last['val_mean']:.3f} ({last['val_median']:.3f}) | {min(mean):.3f} |"
        )
    for ref in args.reference:
        name, _, value = ref.partition("=")
        for ax in axes:
            ax.axhline(float(value), ls=":", color="gray")
            ax.text(ax.get_xlim()[0], float(value), f" {name}", va="bottom", fontsize=8)
    for ax, xlabel in zip(axes, ("environment steps (touches)", "wall time [min]"), strict=True):
        ax.set_xlabel(xlabel)
        ax.set_ylabel("validation mean epsilon")
        ax.set_yscale("log")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle(args.title, fontsize=10)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print("\n".join(rows))
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
