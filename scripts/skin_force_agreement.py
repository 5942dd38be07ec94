"""The skin's force against MuJoCo's at every recorded touch (issue 38 item 1; docs/tactile/force).

    python scripts/skin_force_agreement.py --out docs/tactile/force/force.json

Per hand (hapticsim's, Shadow's and Adroit's; the last two need the extra ``hands``), the
paper's four bodies and seeds 0-2: a tactile exploration (paper strategy, 150 contacts, ideal
skin), and at every recorded touch ``|force / force_exact - 1|``, the skin's integrated
pressure (``contacts.npz`` ``force``) against MuJoCo's normal force at the same instant. Split
by the touch's kind: settled probes (``patch``) and contour-following strokes (``stripe``, the
tip sliding). Also each run's CPU seconds and the estimated contacts' median distance to the
true surface. About 3 minutes on 2 cores. ``--skin elastomer`` (the layer law, needs the
``fem`` extra) gives docs/tactile/force/elastomer/force.json.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

BODIES = ("tapered_box", "cube", "cylinder", "ellipsoid")
HANDS = ("hapticsim", "shadow", "adroit")
SEEDS = (0, 1, 2)


def _stats(error: np.ndarray) -> dict[str, float | int]:
    if not len(error):
        return {"touches": 0}
    return {"touches": int(len(error)), "median": float(np.median(error)),
            "p95": float(np.percentile(error, 95)), "max": float(np.max(error))}  # fmt: skip


def measure(hand: str, skin: str = "ideal") -> dict[str, Any]:
    """One hand's runs and their pooled figures, with the skin preset `skin`."""
    from hapticsim.data import get_body
    from hapticsim.metrics.accuracy import contact_accuracy
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.session import run_exploration

    runs, errors, kinds = [], [], []
    for body in BODIES:
        for seed in SEEDS:
            start = time.process_time()
            config = SceneConfig(sensing="tactile", hand=hand, skin=skin)
            run = run_exploration(get_body(body), "paper", 150, seed, scene_config=config)
            seconds = time.process_time() - start
            a = run.arrays
            error = np.abs(a["force"] / np.maximum(a["force_exact"], 1e-9) - 1.0)
            names = run.explorer.recorder.pattern_kinds
            kind = np.array([names[p] for p in a["pattern"]])
            acc = contact_accuracy(run.truth, a["points_clean"], a["normals_clean"])
            runs.append({"body": body, "seed": seed, "cpu_seconds": seconds,
                         "contacts": int(run.count), "all": _stats(error),
                         "probes": _stats(error[kind == "patch"]),
                         "strokes": _stats(error[kind == "stripe"]),
                         "mujoco_force_zero": int(np.sum(a["force_exact"] <= 0)),
                         "distance_median_m": acc["distance_median"]})  # fmt: skip
            errors.append(error)
            kinds.append(kind)
            print(f"{hand} {body} seed {seed}: {runs[-1]['all']}", file=sys.stderr)
    error, kind = np.concatenate(errors), np.concatenate(kinds)
    return {"runs": runs, "all": _stats(error), "probes": _stats(error[kind == "patch"]),
            "strokes": _stats(error[kind == "stripe"]),
            "cpu_seconds_median": float(np.median([r["cpu_seconds"] for r in runs]))}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=None)
    parser.add_argument("--hands", default=",".join(HANDS))
    parser.add_argument("--skin", default="ideal", help="the skin preset (default ideal)")
    args = parser.parse_args()
    start = time.perf_counter()
    result: dict[str, Any] = {"bodies": BODIES, "seeds": SEEDS, "skin": args.skin, "hands": {}}
    for hand in args.hands.split(","):
        result["hands"][hand] = measure(hand, args.skin)
    result["seconds"] = time.perf_counter() - start
    text = json.dumps(result, indent=1)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text + "\n")
    print(json.dumps({h: {k: v for k, v in r.items() if k != "runs"}
                      for h, r in result["hands"].items()}, indent=1))  # fmt: skip


if __name__ == "__main__":
    main()
