"""The held-out families of docs/policies/learned_touch in one table (Markdown and JSON).

Reads ``docs/policies/learned_touch/json/FAMILY-POLICY.json`` (``hapticsim policies evaluate``
output; see ``commands.sh``) and prints, per family, every policy's mean (median) epsilon after
the last touch and the paired two-sided Wilcoxon tests of ``learned-touch`` against the
uncertainty policy and the shipped ``learned`` one; writes the same as ``summary.json``::

    python scripts/learned_touch_table.py docs/policies/learned_touch

``--subject``, ``--policies``, ``--against`` and ``--families`` make the same table of another
folder (``docs/policies/learned_touch_tactile/commands.sh``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np
from scipy.stats import wilcoxon

#: Families in the order of the table, with what they are.
FAMILIES: dict[str, str] = {
    "random": "analytic, random objects, 100 (seeds 0..99)",
    "tapered": "analytic, random tapered objects, 100",
    "paper": "analytic, the paper's bodies, 40",
    "composite": "analytic, multi-part unions (random_composite), 50",
    "noise10": "analytic, random objects, noise 0.1 (trained at 0.02), 100",
    "mujoco": "MuJoCo hand, the paper's bodies, 20",
    "validation": "analytic, random objects, validation seeds 10,000..10,031, 32",
}
#: Policies in the order of the table (file suffixes).
POLICIES: tuple[str, ...] = ("learned-touch", "best", "learned", "uncertainty", "random")


def final(path: Path) -> np.ndarray:
    return np.array([row[-1] for row in json.loads(path.read_text())["episodes_epsilon"]])


def paired(a: np.ndarray, b: np.ndarray) -> dict[str, Any]:
    p = float(wilcoxon(a, b).pvalue) if np.any(a != b) else 1.0
    return {"mean_difference": float(np.mean(a - b)), "better_in": int(np.sum(a < b)),
            "episodes": len(a), "p_value": p}  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--subject", default="learned-touch", help="the policy tested")
    parser.add_argument("--policies", nargs="+", default=list(POLICIES),
                        help="columns (file suffixes), the subject among them")  # fmt: skip
    parser.add_argument("--against", nargs="+", default=["uncertainty", "learned"],
                        help="policies the subject is tested against")  # fmt: skip
    parser.add_argument("--families", nargs="+", default=None, metavar="NAME=WHAT",
                        help="rows (default: learned_touch's seven)")  # fmt: skip
    args = parser.parse_args(argv)
    families = FAMILIES
    if args.families:
        families = dict(f.split("=", 1) for f in args.families)
    subject, against = args.subject, args.against
    rows: dict[str, Any] = {}
    lines = [
        "| family | " + " | ".join(args.policies) + " | "
        + " | ".join(f"{subject} vs {b}" for b in against) + " |",
        "|---" * (1 + len(args.policies) + len(against)) + "|",
    ]  # fmt: skip
    for family, what in families.items():
        eps = {p: final(args.folder / "json" / f"{family}-{p}.json") for p in args.policies}
        tests = {b: paired(eps[subject], eps[b]) for b in against}
        rows[family] = {
            "what": what,
            "mean": {p: float(v.mean()) for p, v in eps.items()},
            "median": {p: float(np.median(v)) for p, v in eps.items()},
            f"{subject} vs": tests,
        }
        cells = [f"{eps[p].mean():.4f} ({np.median(eps[p]):.4f})" for p in args.policies]
        for b in against:
            t = tests[b]
            cells.append(f"{t['mean_difference']:+.4f}, better in {t['better_in']}/"
                         f"{t['episodes']}, p = {t['p_value']:.2g}")  # fmt: skip
        lines.append(f"| {what} | " + " | ".join(cells) + " |")
    (args.folder / "summary.json").write_text(json.dumps(rows, indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
