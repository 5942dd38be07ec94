"""Soak test of hapticsim/HapticExplore-v0: memory, file descriptors and threads over long runs.

    python scripts/soak.py [--analytic 1000] [--mujoco 100] [--render-every 10] [--seed 0]
                           [--touches 20] [--out soak.json] [--plot soak.png] [--curves]

Runs random-policy episodes in one process, first on the analytic backend, then with the
MuJoCo hand (:func:`tests.soak.soak.soak`; every ``--render-every``-th episode in a fresh
environment with ``render_mode="rgb_array"``, rendering every step), and prints JSON: the
curves' end points (resident memory after the first 10 % of episodes and at the end, their
difference, the extremes; open fds and threads), the whole curves with ``--curves``, the load
average and the machine; ``--plot`` draws the curves (resident memory and open fds against the
episode, one panel per backend, rendered episodes marked). Issue 14's bars: growth <= 20 MB
over the last 900 of 1,000 analytic episodes, <= 50 MB over the last 90 of 100 MuJoCo
episodes, fds constant.
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


def plot(curves: dict[str, list], path: Path) -> None:
    """Resident memory [MB] and open fds against the episode, one panel per backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(curves), figsize=(5.5 * len(curves), 3.6), squeeze=False)
    for ax, (backend, samples) in zip(axes[0], curves.items(), strict=True):
        episodes = [s.episode + 1 for s in samples]
        ax.plot(episodes, [s.rss_mb for s in samples], color="tab:blue", lw=1.2, label="RSS")
        marks = [s for s in samples if s.rendered]
        ax.plot([s.episode + 1 for s in marks], [s.rss_mb for s in marks], "o", ms=2.5,
                color="tab:orange", label="rgb_array episode")  # fmt: skip
        skip = max(1, len(samples) // 10)
        ax.axvline(skip, color="gray", lw=0.8, ls=":")
        bar = f"bar: +{BARS_MB[backend]:.0f} MB after episode {skip}"
        ax.axhline(samples[skip - 1].rss_mb + BARS_MB[backend], color="tab:red", lw=0.8,
                   ls="--", label=bar)  # fmt: skip
        ax.set_xlabel("episode")
        ax.set_ylabel("resident memory [MB]")
        ax.set_title(f"{backend}: {len(samples)} episodes")
        twin = ax.twinx()
        twin.step(episodes, [s.fds for s in samples], where="post", color="tab:green", lw=1.0)
        twin.set_ylabel("open fds", color="tab:green")
        lo, hi = min(s.fds for s in samples), max(s.fds for s in samples)
        twin.set_ylim(lo - 5, hi + 5)
        ax.legend(loc="lower right", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--analytic", type=int, default=1000, help="analytic episodes")
    parser.add_argument("--mujoco", type=int, default=100, help="MuJoCo-hand episodes")
    parser.add_argument("--render-every", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--touches", type=int, default=20, help="touches per episode")
    parser.add_argument("--curves", action="store_true", help="include every sample")
    parser.add_argument("--out", type=Path, default=None, help="also write the JSON here")
    parser.add_argument("--plot", type=Path, default=None, help="draw the curves (PNG) here")
    args = parser.parse_args()
    curves: dict[str, list] = {}
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
        curves[backend] = samples
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
    if args.plot is not None and curves:
        plot(curves, args.plot)
    if args.out is not None:
        args.out.write_text(text + "\n")
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
