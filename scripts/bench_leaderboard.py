"""The committed baseline leaderboard of the benchmark protocol (docs/leaderboard/).

    python scripts/bench_leaderboard.py [--episodes 30] [--workers 2]

Runs every baseline policy on the test split of each task below (``hapticsim bench run``'s
runner, the environment's nH estimator) and writes one results file per (task, policy) and the
leaderboard (``hapticsim bench report``) into docs/leaderboard/, with the folder's manifest.
Progress on stderr.
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
from hapticsim.bench.runner import run_bench, write_results
from hapticsim.suites.provenance import manifest

TASKS = ("paper/exact/analytic/t20", "random/exact/analytic/t20")
POLICIES = ("uncertainty", "random", "paper", "information", "learned", "learned-touch")
OUT = Path(__file__).resolve().parents[1] / "docs" / "leaderboard"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=30)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    command = ["python", "scripts/bench_leaderboard.py", *(argv or sys.argv[1:])]
    paths, start = [], time.perf_counter()
    for task in TASKS:
        for policy in POLICIES:
            results = run_bench(task, policy, args.episodes, workers=args.workers,
                                progress=False, command=command)  # fmt: skip
            name = f"{task.replace('/', '_')}__{policy.replace(':', '_')}.json"
            paths.append(write_results(results, args.out / name))
            s = results["summary"]
            print(f"{task} {policy}: IoU area {s['iou']['area_mean']:.3f}, "
                  f"{results['seconds']:.0f} s ({time.perf_counter() - start:.0f} s in all)",
                  file=sys.stderr, flush=True)  # fmt: skip
    write_report(paths, args.out)
    m = manifest(command) | {"files": sorted(p.name for p in paths),
                             "seconds": time.perf_counter() - start}  # fmt: skip
    (args.out / "manifest.json").write_text(json.dumps(m, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
