"""Vectorised use: SyncVectorEnv, AsyncVectorEnv and gymnasium.make_vec."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from hapticsim.envs.registration import HAPTIC_EXPLORE_ID

KWARGS = {
    "backend": "analytic",
    "touch_budget": 4,
    "fit": {"full_budget": 800, "refine_budget": 100},
}


def _run(envs: gym.vector.VectorEnv, steps: int = 6) -> None:
    obs, info = envs.reset(seed=[0, 1])
    assert envs.observation_space.contains(obs)
    assert obs["points"].shape == (2, 256, 3) and obs["fit"].shape == (2, 13)
    envs.action_space.seed(0)
    for _ in range(steps):
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
        assert reward.shape == (2,) and np.all(np.isfinite(reward))
        assert envs.observation_space.contains(obs)
        assert info["epsilon"].shape == (2,)
    envs.close()


def test_sync_vector_env() -> None:
    _run(gym.vector.SyncVectorEnv([lambda: gym.make(HAPTIC_EXPLORE_ID, **KWARGS)] * 2))


def test_async_vector_env() -> None:
    _run(gym.vector.AsyncVectorEnv([lambda: gym.make(HAPTIC_EXPLORE_ID, **KWARGS)] * 2))


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_make_vec(mode: str) -> None:
    _run(gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=2, vectorization_mode=mode, **KWARGS))


def test_vector_envs_are_seeded_alike() -> None:
    def rollout(mode: str) -> list[np.ndarray]:
        envs = gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=2, vectorization_mode=mode, **KWARGS)
        obs, _ = envs.reset(seed=[3, 4])
        out = [obs["touches"].copy()]
        rng = np.random.default_rng(0)
        for _ in range(5):
            obs, reward, *_ = envs.step(rng.uniform(-1, 1, (2, 5)).astype(np.float32))
            out += [obs["points"].copy(), obs["fit"].copy(), reward.copy()]
        envs.close()
        return out

    for a, b in zip(rollout("sync"), rollout("async"), strict=True):
        np.testing.assert_array_equal(a, b)
