"""The simulation accuracy table: a seeded ``paper`` exploration per hand and body, JSON on stdout.

    python scripts/explore_table.py [--hands hapticsim shadow adroit] [--bodies cube cylinder]
                                    [--seed 0] [--noise 0] [--markdown]

Per (hand, body): contacts, median and p95 distance of the clean contacts to the true surface
[m], median and p95 angle between measured and true normals [deg], the nH fit's epsilon, and the
exploration's wall time [s] (scene building included, fit excluded). The load average is printed
beside the times (the machine is shared). ``--markdown`` prints the table as Markdown instead.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile

from hapticsim.data.bodies import BODY_NAMES
from hapticsim.exploration import explore


def row(hand: str, body: str, seed: int, noise: float) -> dict[str, float]:
    with tempfile.TemporaryDirectory() as out:
        s = explore(body, "paper", noise=noise, method="nH", seed=seed, out_dir=out,
                    progress=False, hand=hand)  # fmt: skip
    acc = s["contact_accuracy"]
    return {
        "contacts": s["contacts"], "distance_median": acc["distance_median"],
        "distance_p95": acc["distance_p95"], "angle_median_deg": acc["angle_median_deg"],
        "angle_p95_deg": acc["angle_p95_deg"], "epsilon": s["metrics"]["epsilon"],
        "exploration_wall_seconds": s["simulation"]["wall_time"],
        "sim_seconds": s["simulation"]["sim_time"], "load_average_1min": os.getloadavg()[0],
    }  # fmt: skip


def markdown(table: dict) -> str:
    lines = ["| hand | body | contacts | distance median [mm] | angle median / p95 [deg] | "
             "nH epsilon | wall [s] (load) |", "|---|---|---:|---:|---:|---:|---:|"]  # fmt: skip
    for hand, rows in table["hands"].items():
        for body, r in rows.items():
            lines.append(
                f"| {hand} | {body} | {r['contacts']} | {r['distance_median'] * 1e3:.4f} | "
                f"{r['angle_median_deg']:.2f} / {r['angle_p95_deg']:.2f} | {r['epsilon']:.4f} | "
                f"{r['exploration_wall_seconds']:.1f} ({r['load_average_1min']:.1f}) |"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="hapticsim exploration accuracy table (JSON)")
    parser.add_argument("--hands", nargs="+", default=["hapticsim"])
    parser.add_argument("--bodies", nargs="+", default=list(BODY_NAMES), choices=BODY_NAMES)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--noise", type=float, default=0.0)
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args(argv)
    table = {"seed": args.seed, "noise": args.noise, "strategy": "paper", "method": "nH",
             "cpus": os.cpu_count(), "hands": {}}  # fmt: skip
    for hand in args.hands:
        table["hands"][hand] = {}
        for body in args.bodies:
            table["hands"][hand][body] = row(hand, body, args.seed, args.noise)
            print(f"explore_table: {hand} {body} done", file=sys.stderr)
    sys.stdout.write((markdown(table) if args.markdown else json.dumps(table, indent=2)) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
