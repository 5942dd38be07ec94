"""What a pool of threads could give, were the environment step (nearly) free of the GIL: JSON.

The native vector environment's shards reach ~1.6x one environment on 2 cores, and the issue's
bar is 1.8x (analytic, N = 8). Threads stepping whole environments would balance best, but today
about half of an analytic step holds the GIL (Python: the section walk, the fitter's driver,
metrics, observation). This script asks what a port would have to reach: it replays measured
vector steps of 8 analytic environments (:func:`lab.benchmarks.env.step_components`) as
synthetic steps of the same durations, a fraction ``g`` of each spent holding the GIL (small
numpy calls) and the rest in a compiled loop that releases it (numba, ``nogil``), in six
alternating pieces per step. Each vector step is handed to a pool of 2 threads, either in the
environments' order (what a pool does without knowing the costs) or largest first (the costs
known in advance), and timed against the same steps run one after the other.

    python scripts/vector_threads_model.py > docs/vector/threads_model.json   # ~2 min, 2 cores

The speed-ups are over the steps run serially in this process, i.e. over one environment; a
real port would add its own overhead (the vector environment's batching, cold caches).
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
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numba import njit

from lab.benchmarks.env import step_components

#: Pieces each synthetic step alternates between holding and releasing the GIL.
PIECES = 6


@njit(nogil=True, cache=False)
def _compiled(n: int) -> float:
    """Compiled work that releases the GIL: n sines."""
    s = 0.0
    for i in range(n):
        s += np.sin(i * 1e-3)
    return s


_VECTOR = np.arange(8.0)


def _python(n: int) -> float:
    """Work that holds the GIL: n small numpy calls (as the environment's Python does)."""
    s = 0.0
    for _ in range(n):
        s += float(np.dot(_VECTOR, _VECTOR))
    return s


def _rates() -> tuple[float, float]:
    """Units of compiled and Python work per second on this machine (median of 5)."""
    _compiled(10)
    c, p = [], []
    for _ in range(5):
        t = time.perf_counter()
        _compiled(400_000)
        c.append(400_000 / (time.perf_counter() - t))
        t = time.perf_counter()
        _python(20_000)
        p.append(20_000 / (time.perf_counter() - t))
    return float(np.median(c)), float(np.median(p))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--vector-steps", type=int, default=60, help="measured vector steps replayed")
    p.add_argument("--gil", type=float, nargs="+", default=[0.5, 0.4, 0.3, 0.2, 0.1, 0.05, 0.0],
                   help="fractions of each step holding the GIL")  # fmt: skip
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args()
    load = os.getloadavg()[0]
    print(f"measuring {args.vector_steps} vector steps of 8 analytic environments (load "
          f"{load:.2f})", file=sys.stderr, flush=True)  # fmt: skip
    steps = step_components("analytic", num_envs=8, steps=args.vector_steps)["step"]  # (8, K)
    compiled_rate, python_rate = _rates()

    def run(seconds_and_gil: tuple[float, float]) -> None:
        seconds, gil = seconds_and_gil
        py = int(seconds * gil * python_rate / PIECES)
        co = int(seconds * (1.0 - gil) * compiled_rate / PIECES)
        for _ in range(PIECES):
            _python(py)
            _compiled(co)

    out = {
        "command": "python " + " ".join(sys.argv),
        "cpus": os.cpu_count(),
        "threads": args.threads,
        "load_start": load,
        "vector_steps": int(steps.shape[1]),
        "step_ms": {"mean": float(steps.mean() * 1e3), "median": float(np.median(steps) * 1e3)},
        "speedup": {},
    }
    with ThreadPoolExecutor(args.threads) as pool:
        for gil in args.gil:
            row = {}
            start = time.perf_counter()
            for k in range(steps.shape[1]):
                for s in steps[:, k]:
                    run((s, gil))
            serial = time.perf_counter() - start
            for order in ("in_order", "largest_first"):
                start = time.perf_counter()
                for k in range(steps.shape[1]):
                    column = steps[:, k]
                    if order == "largest_first":
                        column = np.sort(column)[::-1]
                    list(pool.map(run, [(s, gil) for s in column]))
                row[order] = serial / (time.perf_counter() - start)
            out["speedup"][f"{gil:g}"] = row
            print(f"GIL share {gil:g}: in order {row['in_order']:.3f}x, largest first "
                  f"{row['largest_first']:.3f}x (load {os.getloadavg()[0]:.2f})",
                  file=sys.stderr, flush=True)  # fmt: skip
    out["load_end"] = os.getloadavg()[0]
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
