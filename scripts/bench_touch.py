"""Benchmark of the MuJoCo backend's touch and reset (issue 9 item 5), JSON on stdout.

    python scripts/bench_touch.py [--episodes 20] [--hand hapticsim] [--seed 0]

Random actions on ``HapticExplore-v0(backend="mujoco")`` with the default configuration: the
median ``info["timings"].touch`` and the reset per episode (median, and the mean: amortised over
the episodes, including the first compile of each paper body). The load average is printed
beside the timings (the machine is shared).
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import sys

from lab.benchmarks.env import benchmark_touch


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="hapticsim touch/reset benchmark (JSON)")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--hand", default="hapticsim")
    args = parser.parse_args(argv)
    out = benchmark_touch(args.episodes, args.seed, args.hand)
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
