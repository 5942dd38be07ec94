"""The MuJoCo backend: touches executed by the simulated hand (short here, longer under slow)."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from hapticsim.data.bodies import get_body
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.envs.mujoco_backend import MujocoBackend
from hapticsim.envs.touch import Touch, encode_touch
from hapticsim.errors import InvalidInputError
from hapticsim.perception.vision import vision_estimate

FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)


@pytest.fixture(scope="module")
def backend() -> MujocoBackend:
    b = MujocoBackend(noise=0.0)
    cube = get_body("cube")
    rough = vision_estimate(cube, 0).moved(cube.center + np.array([0.002, -0.001, 0.0]))
    b.reset(cube, np.random.default_rng(0), rough)
    return b


def test_probe_records_a_contact_on_the_true_surface(backend: MujocoBackend) -> None:
    truth = get_body("cube")
    res = backend.touch(Touch(np.array([1.0, 0.2, 0.3]), 0.0, 0.0, 1), truth.center)
    assert res.status == "ok" and len(res) == 1
    assert np.all(res.finger == 1) and np.all(res.force > 0)
    # MuJoCo contacts on the convex hull of a 128-longitude mesh: within 1 mm of the surface,
    # normals within 10 degrees (measured: ~1e-5 m and under 1 degree on a face).
    assert np.max(np.abs(truth.radial_distance(res.points))) < 1e-3
    assert np.min(np.sum(res.normals * truth.normals(res.points), axis=1)) > np.cos(0.17)


def test_stroke_follows_the_contour(backend: MujocoBackend) -> None:
    truth = get_body("cube")
    res = backend.touch(Touch(np.array([0.0, 1.0, 0.2]), np.pi / 2, 0.04, 2), truth.center)
    assert res.status == "ok" and len(res) >= 4
    assert np.all(res.finger == 2)
    assert np.max(np.abs(truth.radial_distance(res.points))) < 1e-3
    assert np.all(np.diff(res.time) > 0)
    assert res.points[-1, 2] > res.points[0, 2]  # upwards


def test_touch_under_the_object_is_blocked_by_the_stand(backend: MujocoBackend) -> None:
    res = backend.touch(Touch(np.array([0.0, 0.0, -1.0]), 0.0, 0.0, 1), np.zeros(3))
    assert res.status == "blocked" and len(res) == 0


def test_env_steps_with_the_hand() -> None:
    env = HapticExploreEnv(
        backend="mujoco", objects="paper", fit=FAST_FIT, touch_budget=3,
        render_mode="rgb_array", width=160, height=120,
    )  # fmt: skip
    obs, info = env.reset(seed=0)
    total = 0
    for k in range(3):
        action = encode_touch(
            np.array([np.cos(k), np.sin(k), 0.3]), np.pi / 2, 0.04, k + 1, 0.05, env.n_fingers
        )
        obs, reward, terminated, truncated, info = env.step(action)
        assert env.observation_space.contains(obs)
        total += info["new_contacts"]
    assert truncated and total >= 6 and info["n_contacts"] == total
    assert set(np.unique(env.contacts.extra["finger"])) <= {1, 2, 3}
    img = env.render()
    assert img.shape == (120, 160, 3) and img.dtype == np.uint8 and img.std() > 5
    env.close()


@pytest.mark.slow
def test_check_env_mujoco() -> None:
    env = HapticExploreEnv(backend="mujoco", fit=FAST_FIT, touch_budget=5)
    check_env(env, skip_render_check=True)
    env.close()


@pytest.mark.slow
def test_seeded_mujoco_episodes_are_identical() -> None:
    def run() -> list[np.ndarray]:
        env = HapticExploreEnv(backend="mujoco", fit=FAST_FIT, touch_budget=6, noise=0.05)
        env.reset(seed=3)
        rng = np.random.default_rng(1)
        out = []
        for _ in range(6):
            obs, reward, *_ = env.step(rng.uniform(-1, 1, 5).astype(np.float32))
            out += [obs["points"], obs["fit"], np.array([reward])]
        env.close()
        return out

    for a, b in zip(run(), run(), strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.slow
def test_random_steps_with_the_hand_without_nan() -> None:
    env = HapticExploreEnv(backend="mujoco", objects="random_tapered", fit=FAST_FIT, noise=0.05)
    env.action_space.seed(0)
    env.reset(seed=0)
    statuses = set()
    for _ in range(100):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert all(np.all(np.isfinite(v)) for v in obs.values()) and np.isfinite(reward)
        statuses.add(info["touch_status"])
        if terminated or truncated:
            env.reset()
    assert "ok" in statuses
    env.close()


# ---------------------------------------------------------------------------- other hands
def _needs_hands_extra() -> None:
    pytest.importorskip("gymnasium_robotics", reason="the `hands` extra is not installed")


def test_env_with_the_shadow_hand_steps_and_renders() -> None:
    _needs_hands_extra()
    env = HapticExploreEnv(
        hand="shadow", fit=FAST_FIT, touch_budget=3, render_mode="rgb_array", width=160,
        height=120,
    )  # fmt: skip
    assert env.n_fingers == 5
    env.reset(seed=0)
    total = 0
    for k in range(3):
        action = encode_touch(
            np.array([np.cos(k), np.sin(k), 0.3]), np.pi / 2, 0.04, k + 1, 0.05, env.n_fingers
        )
        obs, reward, terminated, truncated, info = env.step(action)
        assert env.observation_space.contains(obs)
        total += info["new_contacts"]
    # measured (seed 0): 16 contacts from the ff, mf and rf strokes
    assert truncated and total >= 6
    img = env.render()
    assert img.shape == (120, 160, 3) and img.std() > 5
    env.close()


def test_unknown_hand_is_a_clear_error() -> None:
    with pytest.raises(InvalidInputError, match="hapticsim, shadow, adroit"):
        HapticExploreEnv(hand="allegro")


@pytest.mark.slow
def test_check_env_and_200_random_steps_with_the_shadow_hand() -> None:
    """Issue 12: ``HapticExplore-v0(hand="shadow")`` passes check_env and runs 200 random steps
    without NaN (measured: ~0.06 s a touch, statuses ok/missed/blocked)."""
    _needs_hands_extra()
    env = HapticExploreEnv(hand="shadow", fit=FAST_FIT, touch_budget=20, noise=0.02)
    check_env(env, skip_render_check=True)
    env.action_space.seed(0)
    env.reset(seed=0)
    statuses = set()
    for _ in range(200):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert all(np.all(np.isfinite(v)) for v in obs.values()) and np.isfinite(reward)
        statuses.add(info["touch_status"])
        if terminated or truncated:
            env.reset()
    assert "ok" in statuses
    env.close()
