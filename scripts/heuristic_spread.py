"""How much the uncertainty policy's touch depends on its own dice: JSON on stdout.

The ``uncertainty`` heuristic turns its 96 candidate approaches by a random rotation at every
step and breaks near-ties at random. At each step of its episodes this script asks a copy of the
policy, with another generator, for the touch of the same observation, and compares the two as
v1 actions (approach x, y, z, stroke angle / pi, stroke length; the labels of
``scripts/bc_heuristic.py``): their mean squared difference per number (for two independent draws
twice the variance a least-squares fit cannot explain, so half of it is that fit's floor) and
the angle between the two approaches.

    python scripts/heuristic_spread.py > docs/policies/learned_touch/bc/spread.json   # ~1 min
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import copy
import json
import sys

import gymnasium as gym
import numpy as np

from hapticsim.envs.haptic_explore_compact_v0 import encode_action_v1
from hapticsim.envs.policies import make_policy
from hapticsim.envs.registration import HAPTIC_EXPLORE_ID, register_envs
from hapticsim.envs.touch import decode_action
from lab.training.rllib import DEFAULT_ENV_CONFIG

#: The environment of ``scripts/bc_heuristic.py`` (``learned-touch``'s training settings).
SETTINGS = {k: DEFAULT_ENV_CONFIG[k] for k in ("backend", "objects", "touch_budget", "noise")}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--episodes", type=int, default=100)
    p.add_argument("--seed", type=int, default=3_000_000, help="first environment seed")
    args = p.parse_args()
    if args.episodes < 1:
        p.error(f"--episodes must be >= 1, got {args.episodes}")
    register_envs()
    env = gym.make(HAPTIC_EXPLORE_ID, **SETTINGS)
    cfg, fingers = env.unwrapped.config, env.unwrapped.n_fingers
    policy = make_policy("uncertainty", env)

    def label(action: np.ndarray) -> np.ndarray:
        t = decode_action(action, cfg.max_stroke, cfg.stroke_spacing, fingers)
        return encode_action_v1(t.approach, t.stroke_angle, t.stroke_length / cfg.max_stroke)

    squared, angles = [], []
    for i in range(args.episodes):
        obs, _ = env.reset(seed=args.seed + i)
        policy.reset(args.seed + i)
        done = False
        while not done:
            other = copy.deepcopy(policy)
            other.rng = np.random.default_rng([args.seed + i, len(squared)])
            action = policy(obs)
            a, b = label(action), label(other(obs))
            squared.append(float(np.mean((a - b) ** 2)))
            angles.append(float(np.degrees(np.arccos(np.clip(a[:3] @ b[:3], -1.0, 1.0)))))
            obs, _, terminated, truncated, _ = env.step(action)
            done = terminated or truncated
    env.close()
    ang = np.asarray(angles)
    print(json.dumps({
        "command": "python " + " ".join(sys.argv),
        "settings": SETTINGS, "episodes": args.episodes, "first_seed": args.seed,
        "steps": len(squared),
        "mean_squared_difference": float(np.mean(squared)),
        "least_squares_floor": float(np.mean(squared) / 2.0),
        "approach_angle_deg": {"median": float(np.median(ang)), "mean": float(ang.mean()),
                               "share_over_45": float(np.mean(ang > 45.0))},
    }, indent=1))  # fmt: skip


if __name__ == "__main__":
    main()
