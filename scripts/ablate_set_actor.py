"""Test-time ablations of a set-encoder actor (``learned-touch``): weight files that see less.

Each copy of the actor is blind to one part of its observation, by weights alone:

- ``no-points``: the contact set's pooled features are zero (its network's last layer zeroed);
- ``no-touches``: the same for the set of past touches;
- ``no-head``: the first layer above the encoders ignores the fit, its error and the counts
  (their columns zeroed);
- ``no-taxels`` (actors of ``HapticExploreTouchTactile-v0`` only): the touch set's network
  ignores each touch's pad image (the columns of its first layer zeroed).

Run them as ``learned:PATH`` on the same episodes as the actor to see what it acts on::

    python scripts/ablate_set_actor.py hapticsim/envs/data/learned_touch_policy.npz \
        --out runs/ablations
    hapticsim policies evaluate --policy learned:runs/ablations/no-points.npz --episodes 100
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from hapticsim.envs.haptic_explore_touch_v0 import TACTILE_TOUCH_WIDTH, TOUCH_WIDTH
from hapticsim.envs.learned import Actor, load_actor


def _with_set_params(actor: Actor, j: int, params: list[np.ndarray]) -> Actor:
    """`actor` with set `j`'s network arrays replaced."""
    sets = list(actor.sets)
    sets[j] = replace(sets[j], params=tuple(params))
    return Actor(actor.layers, actor.params, actor.squash, dict(actor.meta), tuple(sets))


def blind_set(actor: Actor, j: int) -> Actor:
    """`actor` with set `j`'s pooled features zero."""
    params = list(actor.sets[j].params)
    last = max(i for i, p in enumerate(params) if p.ndim == 2)  # the last linear's W
    params[last] = np.zeros_like(params[last])
    params[last + 1] = np.zeros_like(params[last + 1])
    return _with_set_params(actor, j, params)


def blind_head(actor: Actor) -> Actor:
    """`actor` ignoring the observation's head (the entries before the first set)."""
    params = list(actor.params)
    w = params[0].copy()
    w[:, : actor.sets[0].offset] = 0.0
    params[0] = w
    return Actor(actor.layers, tuple(params), actor.squash, dict(actor.meta), actor.sets)


def blind_taxels(actor: Actor) -> Actor:
    """`actor` with its touch set's network ignoring each touch's pad image."""
    params = list(actor.sets[1].params)
    w = params[0].copy()  # (hidden, element inputs): approach, count, image, [present dropped]
    w[:, TOUCH_WIDTH - 1 : TACTILE_TOUCH_WIDTH - 1] = 0.0
    params[0] = w
    return _with_set_params(actor, 1, params)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("weights", type=Path, help="a weight file with set encoders")
    parser.add_argument("--out", type=Path, required=True, help="folder for the copies")
    args = parser.parse_args(argv)
    actor = load_actor(args.weights)
    if len(actor.sets) != 2:
        raise SystemExit(f"{args.weights}: expected an actor with two sets, got {len(actor.sets)}")
    args.out.mkdir(parents=True, exist_ok=True)
    copies = [("no-points", blind_set(actor, 0)), ("no-touches", blind_set(actor, 1)),
              ("no-head", blind_head(actor))]  # fmt: skip
    if actor.sets[1].width == TACTILE_TOUCH_WIDTH:
        copies.append(("no-taxels", blind_taxels(actor)))
    for name, ablated in copies:
        ablated.meta["ablation"] = name
        print(ablated.save(args.out / f"{name}.npz"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
