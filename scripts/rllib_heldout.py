"""RLlib runs' best modules on held-out objects, against random touches: JSON on stdout.

``scripts/train_rllib.py`` keeps, in ``OUT/best/``, the module of the validation point with the
lowest mean epsilon on its 32 validation objects (seeds 10,000 + i). That choice was made on those
objects, so their figure flatters it. This script runs each run's best module (deterministic:
the mode of its action distribution) and uniform random touches on other objects (seeds 20,000 +
i by default, never trained or validated on), one episode each, and compares them episode by
episode (paired two-sided Wilcoxon test on epsilon after the last touch). ``--actor NAME=FILE``
adds an exported actor (``hapticsim.envs.learned``, e.g. the shipped SB3 ``learned`` one) on the
same objects. Needs the ``ray`` extra::

    python scripts/rllib_heldout.py runs/rllib-ppo-s1 runs/rllib-ppo-s2 > held_out.json
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

import numpy as np
from scipy.stats import wilcoxon

from hapticsim.envs.haptic_explore_compact_v0 import OBS_DIM
from hapticsim.envs.learned import load_actor
from lab.training.rllib import deterministic_policy, final_epsilons

#: First environment seed of the held-out objects (validation uses 10,000 + i).
HELD_OUT_SEED = 20_000


def _summary(values: list[float]) -> dict[str, float]:
    return {"mean": float(np.mean(values)), "median": float(np.median(values))}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("runs", nargs="+", type=Path, help="train_rllib.py output folders")
    p.add_argument("--episodes", type=int, default=100)
    p.add_argument("--seed", type=int, default=HELD_OUT_SEED, help="first object seed")
    p.add_argument("--actor", action="append", default=[], metavar="NAME=FILE",
                   help="an exported actor (.npz) to run on the same objects")  # fmt: skip
    args = p.parse_args()
    actors = {}
    for item in args.actor:
        name, sep, path = item.partition("=")
        if not sep or not name or not Path(path).is_file():
            p.error(f"--actor must be NAME=FILE with an existing file, got {item!r}")
        actors[name] = load_actor(path, obs_dim=OBS_DIM)
    if args.episodes < 2:
        p.error(f"--episodes must be >= 2, got {args.episodes}")
    for run in args.runs:
        if not (run / "best").is_dir() or not (run / "summary.json").is_file():
            p.error(f"{run} has no best/ module or no summary.json (a train_rllib.py output?)")
    try:
        from ray.rllib.core.rl_module.rl_module import RLModule
    except ImportError:
        sys.exit("rllib_heldout.py needs the ray extra: pip install -e '.[ray]'")
    env_config = json.loads((args.runs[0] / "summary.json").read_text())["env_config"]
    print(f"random touches on {args.episodes} objects", file=sys.stderr, flush=True)
    random = final_epsilons(None, env_config, args.episodes, args.seed)
    out = {
        "command": "python " + " ".join(sys.argv),
        "episodes": args.episodes,
        "first_seed": args.seed,
        "env_config": env_config,
        "random": _summary(random) | {"episodes_epsilon": random},
        "runs": {},
    }
    policies = {}
    for run in args.runs:
        summary = json.loads((run / "summary.json").read_text())
        if summary["env_config"] != env_config:
            sys.exit(f"{run}: trained on other settings than {args.runs[0]}")
        module = RLModule.from_checkpoint(str((run / "best").resolve()))
        policies[str(run)] = (deterministic_policy(module), {"best_validation": summary["best"]})
    for name, actor in actors.items():
        policies[name] = (actor, {"actor": actor.meta.get("training", {})})
    for name, (policy, extra) in policies.items():
        start = time.perf_counter()
        values = final_epsilons(policy, env_config, args.episodes, args.seed)
        diff = np.asarray(values) - np.asarray(random)
        out["runs"][name] = _summary(values) | extra | {
            "better_than_random_in": int(np.sum(diff < 0)),
            "wilcoxon_p_vs_random": float(wilcoxon(values, random).pvalue),
            "episodes_epsilon": values,
        }
        r = out["runs"][name]
        print(f"{name}: mean {r['mean']:.4f} (random {out['random']['mean']:.4f}), better in "
              f"{r['better_than_random_in']}/{args.episodes}, p = {r['wilcoxon_p_vs_random']:.2g} "
              f"({time.perf_counter() - start:.0f} s)", file=sys.stderr, flush=True)  # fmt: skip
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
