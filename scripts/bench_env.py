"""Benchmark of hapticsim/HapticExplore-v0: environment steps per second in one process.

Random-policy episodes on each backend; JSON on stdout (progress on stderr). The same numbers
come from ``python scripts/bench.py --section env``.

    python scripts/bench_env.py                       # both backends, 3 episodes each
    python scripts/bench_env.py --backend analytic --episodes 10 --out bench_env.json
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
from pathlib import Path

from hapticsim.data.io import write_text_atomic
from hapticsim.envs.backends import BACKENDS
from lab.benchmarks.env import benchmark_env


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", choices=(*BACKENDS, "all"), default="all")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--objects", default="paper")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=None, help="also write the JSON here")
    args = parser.parse_args(argv)
    backends = BACKENDS if args.backend == "all" else (args.backend,)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    result = {
        "load_average_1min": load,
        "cpus": os.cpu_count(),
        "env": [benchmark_env(b, args.episodes, args.seed, args.objects) for b in backends],
    }
    text = json.dumps(result, indent=2)
    if args.out is not None:
        write_text_atomic(args.out, text + "\n")
    sys.stdout.write(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
