"""One SHA-256 over fits, a Laplace covariance and seeded episodes: did a refactor move anything?

Run it before and after a change that should move nothing (on the same machine and packages:
the digits depend on the CPU's code-generation target, docs/suites/README.md). It hashes the
estimates (each part of a union), EOFs and evaluation counts of 72 fits (LS, H, nLS, nH, nML,
multi x the paper's four bodies x sigma_N 0, 0.05, 0.1, seed 3), one Laplace covariance, and
the rewards of three seeded analytic episodes of HapticExplore-v0 with seeded random actions.
About 15 s on a warm cache.

    python scripts/refactor_digest.py   # {"fits": 72, "digest": "...", ...}
"""

from __future__ import annotations

import hashlib
import json
import os
import time

import gymnasium as gym
import numpy as np

import hapticsim  # noqa: F401 - registers the environments
from hapticsim.data import get_body, paper_dataset
from hapticsim.fitting import fit
from hapticsim.fitting.uncertainty import laplace

METHODS = ("LS", "H", "nLS", "nH", "nML", "multi")


def main() -> None:
    start = time.perf_counter()
    digest = hashlib.sha256()

    def add(values: object) -> None:
        digest.update(np.ascontiguousarray(np.asarray(values, dtype=np.float64)).tobytes())

    fits = 0
    for name in ("cube", "tapered_box", "cylinder", "ellipsoid"):
        truth = get_body(name)
        for noise in (0.0, 0.05, 0.1):
            data = paper_dataset(truth, noise=noise, rng=3)
            for method in METHODS:
                result = fit(data.points, data.normals, method=method, rng=3)
                for part in result.solid.components:  # the estimate: one superquadric, or parts
                    add(part.to_vector())
                add([result.eof, result.evaluations])
                fits += 1
    data = paper_dataset(get_body("cube"), noise=0.05, rng=1)
    result = fit(data.points, data.normals, method="nH", rng=1)
    add(laplace(result.superquadric, data.points, data.normals, 0.5, "untapered").covariance)
    env = gym.make("hapticsim/HapticExplore-v0")
    for episode in range(3):
        env.reset(seed=episode)
        env.action_space.seed(episode)
        for _ in range(8):
            add([env.step(env.action_space.sample())[1]])
    env.close()
    print(json.dumps({"fits": fits, "episodes": 3, "digest": digest.hexdigest(),
                      "seconds": round(time.perf_counter() - start, 1),
                      "load_average_1min": os.getloadavg()[0]}))  # fmt: skip


if __name__ == "__main__":
    main()
