"""Behaviour cloning of the uncertainty policy into a learned actor's network: a diagnostic.

The touch-learned actors (``learned-touch``, PPO, 1M steps) stay behind the ``uncertainty``
heuristic (mean epsilon 0.021 against 0.017 after 10 touches). Is that the learning (the reward,
the exploration, the budget of steps) or what the actor sees? The heuristic decides on the current
fit (it ray casts the estimate to predict where each approach lands); the touch observation has
no fit, only the contacts, normals and past touches. This script records the heuristic's touches
on ``HapticExplore-v0`` together with the touch observation an actor would have seen
(:class:`~hapticsim.envs.haptic_explore_touch_v0.TouchObserver`), fits the same network as
``learned-touch`` (``TouchSetExtractor`` + MLP, PPO's policy) to those actions by least squares,
and exports it as a weight file that ``hapticsim policies evaluate --policy learned:PATH`` runs.
``--observation compact`` does the same with the compact observation of ``learned``
(``HapticExploreCompact-v0``: the current fit and the coverage gaps, a plain MLP): the control.

    python scripts/bc_heuristic.py --out runs/bc_touch      # ~7 min on 2 cores
    hapticsim policies evaluate --policy learned:runs/bc_touch/policy.npz --objects random \\
        --episodes 100 --seed 0 --touches 10 --quiet > bc.json

Episodes use environment seeds from ``--seed`` (default 2,000,000: not the evaluation's 0..99,
the training's 1,000,000.. or the validation's 10,000..). Writes ``policy.npz``,
``summary.json`` (losses per epoch, data, settings) and, with ``--keep-data``, ``data.npz``.
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
from pathlib import Path

import numpy as np

from hapticsim.envs.haptic_explore_compact_v0 import encode_action_v1
from hapticsim.envs.registration import HAPTIC_EXPLORE_COMPACT_ID, HAPTIC_EXPLORE_TOUCH_ID
from lab.training.rllib import DEFAULT_ENV_CONFIG

#: Environment settings of ``learned-touch``'s training (scripts/train_policy.py defaults).
SETTINGS = {k: DEFAULT_ENV_CONFIG[k] for k in ("backend", "objects", "touch_budget", "noise")}
#: The observations an actor can be cloned on, and their environments.
ENV_IDS = {"touch": HAPTIC_EXPLORE_TOUCH_ID, "compact": HAPTIC_EXPLORE_COMPACT_ID}


def collect(episodes: int, seed: int, observation: str) -> tuple[np.ndarray, np.ndarray, dict]:
    """The uncertainty policy's touches: the observations an actor of `observation` would have
    seen (n, 545 or 85) and the v1 actions that make the same touches (n, 5)."""
    import gymnasium as gym

    from hapticsim.envs.policies import LEARNED_OBSERVATIONS, make_policy
    from hapticsim.envs.registration import HAPTIC_EXPLORE_ID, register_envs
    from hapticsim.envs.touch import decode_action

    register_envs()
    env = gym.make(HAPTIC_EXPLORE_ID, **SETTINGS)
    cfg = env.unwrapped.config
    n_fingers = env.unwrapped.n_fingers
    policy = make_policy("uncertainty", env)
    observations, actions, finals = [], [], []
    start = time.perf_counter()
    for i in range(episodes):
        obs, _ = env.reset(seed=seed + i)
        policy.reset(seed + i)
        observer = LEARNED_OBSERVATIONS[ENV_IDS[observation]][1](cfg.obs_scale)
        features = observer.reset(obs)
        done, info = False, {}
        while not done:
            action = policy(obs)
            touch = decode_action(action, cfg.max_stroke, cfg.stroke_spacing, n_fingers)
            observations.append(features)
            actions.append(encode_action_v1(touch.approach, touch.stroke_angle,
                                            touch.stroke_length / cfg.max_stroke))  # fmt: skip
            obs, _, terminated, truncated, info = env.step(action)
            features = observer.update(obs, touch.approach)
            done = terminated or truncated
        finals.append(float(info["epsilon"]))
        if (i + 1) % 200 == 0 or i + 1 == episodes:
            print(f"collected {i + 1}/{episodes} episodes ({time.perf_counter() - start:.0f} s, "
                  f"load {os.getloadavg()[0]:.1f})", file=sys.stderr, flush=True)  # fmt: skip
    env.close()
    data = {"episodes": episodes, "first_seed": seed, "samples": len(actions),
            "uncertainty_final_epsilon_mean": float(np.mean(finals))}  # fmt: skip
    return np.asarray(observations, np.float32), np.asarray(actions, np.float32), data


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--observation", choices=sorted(ENV_IDS), default="touch")
    p.add_argument("--episodes", type=int, default=4000)
    p.add_argument("--seed", type=int, default=2_000_000)
    p.add_argument("--epochs", type=int, default=60)
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--batch-size", type=int, default=256)
    p.add_argument("--net", type=int, nargs="+", default=[128, 128])
    p.add_argument("--set-net", type=int, nargs="+", default=[64, 64])
    p.add_argument("--keep-data", action="store_true")
    p.add_argument("--out", type=Path, required=True)
    args = p.parse_args()
    if args.episodes < 10 or args.epochs < 1:
        p.error("--episodes must be >= 10 and --epochs >= 1")
    try:
        import torch
        from stable_baselines3 import PPO
    except ImportError:
        sys.exit("bc_heuristic.py needs the rl extra: pip install -e '.[rl]'")
    import gymnasium as gym

    from hapticsim.envs.haptic_explore_touch_v0 import SETS
    from lab.training.export import actor_from_sb3, recorded_settings
    from lab.training.sb3 import TouchSetExtractor

    args.out.mkdir(parents=True, exist_ok=True)
    x, y, data = collect(args.episodes, args.seed, args.observation)
    if args.keep_data:
        np.savez_compressed(args.out / "data.npz", observations=x, actions=y)
    env_id = ENV_IDS[args.observation]
    touch_env = gym.make(env_id, **SETTINGS)
    extractor = {}
    if args.observation == "touch":
        extractor = {"features_extractor_class": TouchSetExtractor,
                     "features_extractor_kwargs": {"hidden": tuple(args.set_net), "sets": SETS}}
    model = PPO(
        "MlpPolicy", touch_env, seed=0, device="cpu",
        policy_kwargs={"net_arch": {"pi": list(args.net), "vf": list(args.net)},
                       "activation_fn": torch.nn.Tanh, **extractor},
    )  # fmt: skip
    policy = model.policy
    torch.manual_seed(0)
    # the last tenth of the episodes is held out for the loss curve
    split = int(round(0.9 * args.episodes)) * SETTINGS["touch_budget"]
    xt, yt = torch.as_tensor(x[:split]), torch.as_tensor(y[:split])
    xv, yv = torch.as_tensor(x[split:]), torch.as_tensor(y[split:])
    params = (list(policy.features_extractor.parameters())
              + list(policy.mlp_extractor.policy_net.parameters())
              + list(policy.action_net.parameters()))  # fmt: skip
    opt = torch.optim.Adam(params, lr=args.lr)

    def mean_action(obs: torch.Tensor) -> torch.Tensor:
        features = policy.extract_features(obs, policy.pi_features_extractor)
        return policy.action_net(policy.mlp_extractor.forward_actor(features))

    curve = []
    gen = np.random.default_rng(0)
    start = time.perf_counter()
    for epoch in range(args.epochs):
        order = torch.as_tensor(gen.permutation(len(xt)))
        total = 0.0
        for k in range(0, len(xt), args.batch_size):
            idx = order[k : k + args.batch_size]
            loss = torch.mean((mean_action(xt[idx]) - yt[idx]) ** 2)
            opt.zero_grad()
            loss.backward()
            opt.step()
            total += loss.item() * len(idx)
        with torch.no_grad():
            held = float(torch.mean((mean_action(xv).clamp(-1, 1) - yv) ** 2))
        curve.append({"epoch": epoch + 1, "train_mse": total / len(xt), "held_out_mse": held})
        if (epoch + 1) % 10 == 0 or epoch + 1 == args.epochs:
            seconds = time.perf_counter() - start
            print(f"epoch {epoch + 1}: train {total / len(xt):.4f}, held out {held:.4f} "
                  f"({seconds:.0f} s)", file=sys.stderr, flush=True)  # fmt: skip
    settings = recorded_settings(touch_env, objects=SETTINGS["objects"])
    command = "python scripts/bc_heuristic.py " + " ".join(sys.argv[1:])
    meta = {"env_id": env_id, "settings": settings,
            "training": {"algo": "behaviour cloning of the uncertainty policy",
                         "steps": int(len(x)), "seed": 0, "command": command}}  # fmt: skip
    actor_from_sb3(model, meta).save(args.out / "policy.npz")
    summary = {"command": command, "observation": args.observation, "data": data, "epochs": curve,
               "settings": settings, "net": args.net, "set_net": args.set_net}  # fmt: skip
    (args.out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps({k: summary[k] for k in ("command", "data")} | {"last": curve[-1]}))


if __name__ == "__main__":
    main()
