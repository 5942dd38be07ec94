"""Compare exploration policies on hapticsim/HapticExplore-v0 (table + plot under docs/policies).

Epsilon of the current fit after N = 1..budget touches, for the random, paper and
uncertainty-driven baselines, on the same objects (seeds), in 2 processes:

    python scripts/compare_policies.py                       # analytic backend, 24 + 20 episodes
    python scripts/compare_policies.py --backend mujoco --episodes 20 --out docs/policies/mujoco

Policies are names of ``hapticsim.envs.policies`` (``learned``, or ``learned:PATH`` for a weight
file); ``--fresh-envs`` runs every episode in a new environment, so the numbers do not depend on
the worker count.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import sys
import time
from pathlib import Path

from hapticsim.data.distributions import OBJECT_KINDS
from hapticsim.envs.backends import BACKENDS
from hapticsim.envs.evaluation import compare_policies
from hapticsim.envs.policies import POLICY_NAMES
from lab.benchmarks.comparison import write_comparison


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", choices=BACKENDS, default="analytic")
    parser.add_argument(
        "--policies", nargs="+", default=["random", "paper", "uncertainty"],
        help=f"names from {POLICY_NAMES} or learned:PATH (default: the three baselines)",
    )  # fmt: skip
    parser.add_argument(
        "--objects", nargs="+", choices=OBJECT_KINDS, default=["random_tapered", "paper"]
    )
    parser.add_argument("--episodes", type=int, default=24, help="objects per object set")
    parser.add_argument("--budget", type=int, default=20, help="touches per episode")
    parser.add_argument("--noise", type=float, default=0.02, help="sensor noise sigma_N")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--scheduler", default=None, help="a Dask cluster instead: tcp://host:port or local:N"
    )
    parser.add_argument("--fresh-envs", action="store_true", help="a new environment per episode")
    parser.add_argument("--out", type=Path, default=Path("docs/policies"))
    args = parser.parse_args(argv)

    start = time.perf_counter()
    cmp = compare_policies(
        args.policies, args.objects, args.episodes, seed=args.seed, workers=args.workers,
        scheduler=args.scheduler, fresh_envs=args.fresh_envs,
        backend=args.backend, touch_budget=args.budget, noise=args.noise,
    )  # fmt: skip
    command = "python scripts/compare_policies.py " + " ".join(
        sys.argv[1:] if argv is None else argv
    )
    paths = write_comparison(cmp, args.out, command.strip())
    print(paths["md"].read_text())
    print(
        f"wrote {', '.join(str(p) for p in paths.values())} in {time.perf_counter() - start:.0f} s",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
