"""Tactile sensing in the environment: ``sensing="tactile"`` on both backends and
``hapticsim/HapticExploreTactile-v0`` (taxel images in the observation)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import hapticsim  # noqa: F401  (registers the environments)
from hapticsim.envs.haptic_explore_tactile_v0 import HapticExploreTactileEnv
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.errors import InvalidInputError
from hapticsim.metrics.accuracy import contact_accuracy

TACTILE_ID = "hapticsim/HapticExploreTactile-v0"


@pytest.mark.parametrize("backend", ["analytic", "mujoco"])
def test_check_env_passes(backend: str) -> None:
    env = gym.make(TACTILE_ID, backend=backend, touch_budget=3)
    check_env(env.unwrapped)  # the core
    assert env.observation_space["taxels"].shape == (4, 31, 31)
    with pytest.warns(UserWarning, match="different from the unwrapped"):  # as it says
        check_env(HapticExploreTactileEnv(backend=backend, touch_budget=3))  # and its wrapper


@pytest.mark.parametrize("backend", ["analytic", "mujoco"])
def test_the_last_contacts_images_are_observed_and_episodes_repeat(backend: str) -> None:
    def episode() -> tuple[list[np.ndarray], np.ndarray]:
        env = HapticExploreTactileEnv(backend=backend, touch_budget=4)
        obs, _ = env.reset(seed=3)
        assert not obs["taxels"].any()  # nothing felt yet
        seen = []
        env.action_space.seed(3)
        for _ in range(4):
            obs, _, _, _, info = env.step(env.action_space.sample())
            seen.append(obs["taxels"])
        return seen, env.unwrapped.contacts.points

    first, pts = episode()
    second, pts2 = episode()
    assert any(t.any() for t in first)
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(pts, pts2)


@pytest.mark.parametrize("backend", ["analytic", "mujoco"])
def test_tactile_contacts_are_estimates_near_the_truth(backend: str) -> None:
    """Measured (paper bodies, random actions, seed 0, 6 touches, ideal skin): distance to the
    true surface median 0.004 mm (analytic) / 0.005 mm (hand)."""
    env = HapticExploreEnv(backend=backend, sensing="tactile", touch_budget=6, noise=0.0)
    env.reset(seed=0)
    env.action_space.seed(0)
    for _ in range(6):
        env.step(env.action_space.sample())
    c = env.contacts
    assert len(c) >= 3  # strokes record only settled touches (tactile sensing)
    acc = contact_accuracy(env.truth, c.extra["points_clean"], c.extra["normals_clean"])
    assert acc["distance_median"] < 5e-5 and acc["angle_median_deg"] < 2.0
    assert not np.array_equal(c.extra["points_clean"], c.extra["points_exact"])
    assert np.all(c.extra["sigma"] > 0)


def test_v0_with_tactile_sensing_keeps_its_observation() -> None:
    exact = HapticExploreEnv(backend="analytic")
    tactile = HapticExploreEnv(backend="analytic", sensing="tactile", skin="vision")
    assert tactile.observation_space == exact.observation_space
    assert tactile.config.skin.name == "vision"


def test_the_skins_pitch_sets_the_image_grid() -> None:
    env = gym.make(TACTILE_ID, backend="analytic", skin="capacitive")
    assert env.observation_space["taxels"].shape == (4, 9, 9)


def test_bad_tactile_arguments_name_the_problem() -> None:
    with pytest.raises(InvalidInputError, match="`sensing` must be 'tactile'"):
        HapticExploreTactileEnv(backend="analytic", sensing="exact")
    with pytest.raises(InvalidInputError, match="`sensing` must be one of exact, tactile"):
        HapticExploreEnv(backend="analytic", sensing="haptic")
    with pytest.raises(InvalidInputError, match="did you mean 'capacitive'"):
        HapticExploreEnv(backend="analytic", sensing="tactile", skin="capacitve")


def test_registered_beside_the_main_environment() -> None:
    assert TACTILE_ID in gym.registry and "hapticsim/HapticExplore-v0" in gym.registry


TRACTION_ID = "hapticsim/HapticExploreTactile-v1"


@pytest.mark.parametrize("backend", ["analytic", "mujoco"])
def test_v1_observes_the_traction_field_within_coulombs_bound(backend: str) -> None:
    """HapticExploreTactile-v1 (SPEC §11): shear and taxel states beside v0's images; the
    shear never exceeds mu times the pressure, free taxels carry none; check_env passes."""
    env = gym.make(TRACTION_ID, backend=backend, touch_budget=6)
    check_env(env.unwrapped)
    space = env.observation_space
    assert space["shear"].shape == (4, 31, 31, 2) and space["taxel_state"].shape == (4, 31, 31)
    obs, _ = env.reset(seed=1)
    assert not obs["shear"].any() and not obs["taxel_state"].any()
    env.action_space.seed(1)
    states = set()
    mu = 0.2
    for _ in range(6):
        obs, *_ = env.step(env.action_space.sample())
        assert space.contains(obs)
        shear = np.hypot(obs["shear"][..., 0], obs["shear"][..., 1])
        pressure = env.unwrapped.last_traction[0][..., 0] / 1e5 if (
            env.unwrapped.last_traction is not None) else np.zeros(shear.shape)  # fmt: skip
        assert np.all(shear <= mu * pressure * (1 + 1e-5) + 1e-7)
        assert not shear[obs["taxel_state"] == 0].any()
        states |= set(np.unique(obs["taxel_state"]).tolist())
    assert {0, 1} <= states or {0, 2} <= states  # something was felt
