"""Benchmark of the MuJoCo simulation (also ``scripts/bench.py --section sim``): physics steps per
second of the hand + object scene with a fingertip pressing, and the wall (and CPU) time of a
150-contact ``paper`` exploration per body. Prints JSON on stdout.

    python scripts/bench_sim.py [--bodies cube ellipsoid] [--count 150] [--repeat 1]

Wall times depend on the machine's load; the CPU time of the process is reported beside them.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import os
import sys

from hapticsim.data.bodies import BODY_NAMES
from lab.benchmarks.sim import benchmark_sim


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="hapticsim simulation benchmark (JSON)")
    parser.add_argument("--bodies", nargs="+", default=list(BODY_NAMES), choices=BODY_NAMES)
    parser.add_argument("--count", type=int, default=150)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args(argv)
    out = {"load_average_1min": os.getloadavg()[0], "cpus": os.cpu_count()}
    out.update(benchmark_sim(args.bodies, args.count, args.repeat))
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
