"""Soak test of hapticsim/HapticExplore-v0: memory, file descriptors and threads over long runs.

    python scripts/soak.py [--analytic 1000] [--mujoco 100] [--render-every 10] [--seed 0]
                           [--touches 20] [--out soak.json]

Runs random-policy episodes in one process, first on the analytic backend, then with the
MuJoCo hand (:func:`tests.soak.soak.soak`; every ``--render-every``-th episode in a fresh
environment with ``render_mode="rgb_array"``, rendering every step), and prints JSON: the
curves' end points (resident memory after the first 10 % of episodes and at the end, their
difference, the extremes; open fds and threads), the whole curves with ``--curves``, the load
average and the machine. Issue 14's bars: growth <= 20 MB over the last 900 of 1,000 analytic
episodes, <= 50 MB over the last 90 of 100 MuJoCo episodes, fds constant.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
os.environ.setdefault("MUJOCO_GL", "egl")

from tests.soak.soak import log_progress, soak, summary, to_rows  # noqa: E402

#: Issue 14's bars [MB] on the growth over the last 90 % of the episodes.
BARS_MB = {"analytic": 20.0, "mujoco": 50.0}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--analytic", type=int, default=1000, help="analytic episodes")
    parser.add_argument("--mujoco", type=int, default=100, help="MuJoCo-hand episodes")
    parser.add_argument("--render-every", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--touches", type=int, default=20, help="touches per episode")
    parser.add_argument("--curves", action="store_true", help="include every sample")
    parser.add_argument("--out", type=Path, default=None, help="also write the JSON here")
    args = parser.parse_args()
    start = time.perf_counter()
    report: dict[str, object] = {
        "command": " ".join(["python", "scripts/soak.py", *sys.argv[1:]]),
        "load_average_start": [round(x, 2) for x in os.getloadavg()],
    }
    ok = True
    for backend, episodes in (("analytic", args.analytic), ("mujoco", args.mujoco)):
        if episodes <= 0:
            continue
        samples = soak(backend, episodes, args.render_every, args.seed, args.touches,
                       progress=log_progress(max(1, episodes // 20)))  # fmt: skip
        result = summary(samples, max(1, episodes // 10))
        growth = next(v for k, v in result.items() if k.startswith("rss_growth_mb"))
        fds = result["fds"]
        result["bar_mb"] = BARS_MB[backend]
        result["meets_bar"] = bool(growth <= BARS_MB[backend] and fds["min"] == fds["max"])
        ok = ok and result["meets_bar"]
        if args.curves:
            result["curve"] = to_rows(samples)
        report[backend] = result
    report["seconds"] = round(time.perf_counter() - start, 1)
    report["load_average_end"] = [round(x, 2) for x in os.getloadavg()]
    report["machine"] = (
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    )
    text = json.dumps(report, indent=2)
    if args.out is not None:
        args.out.write_text(text + "\n")
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
