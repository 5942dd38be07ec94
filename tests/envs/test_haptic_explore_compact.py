"""HapticExploreCompact-v0 (was -v1): compact observation, action without finger, log-epsilon."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import hapticsim  # noqa: F401  (registers the environments)
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_compact_v0 import (
    DIRECTIONS,
    ENV_ID,
    FAILED_CONE,
    N_DIRECTIONS,
    OBS_DIM,
    OBS_NAMES,
    CompactObserver,
    HapticExploreCompactEnv,
    HapticExploreV1Config,
    decode_action_v1,
    encode_action_v1,
    finger_for_touch,
    v0_action,
)
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.envs.registration import HAPTIC_EXPLORE_COMPACT_ID, HAPTIC_EXPLORE_ID
from hapticsim.envs.touch import decode_action
from hapticsim.errors import InvalidInputError

FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)
GAPS = slice(17, 17 + N_DIRECTIONS)
FAILED = slice(17 + N_DIRECTIONS, 17 + 2 * N_DIRECTIONS)


def make(**kwargs: object) -> HapticExploreCompactEnv:
    kwargs.setdefault("fit", FAST_FIT)
    kwargs.setdefault("objects", "random")
    return HapticExploreCompactEnv(backend="analytic", **kwargs)  # type: ignore[arg-type]


def test_the_compact_task_has_a_name_of_its_own_and_v0_warns_of_nothing() -> None:
    assert HAPTIC_EXPLORE_COMPACT_ID == ENV_ID == "hapticsim/HapticExploreCompact-v0"
    spec = gym.spec(HAPTIC_EXPLORE_COMPACT_ID)
    assert spec.entry_point == "hapticsim.envs.haptic_explore_compact_v0:HapticExploreCompactEnv"
    assert spec.version == 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # "out of date, upgrade to v1" was a DeprecationWarning
        gym.make(HAPTIC_EXPLORE_ID, backend="analytic").close()
    with pytest.warns(FutureWarning, match="HapticExplore-v1 is now hapticsim/HapticExploreCo"):
        old = gym.make("hapticsim/HapticExplore-v1", backend="analytic", touch_budget=2)
    assert isinstance(old.env, HapticExploreCompactEnv)  # inside gym.make's OrderEnforcing
    assert old.unwrapped.config.touch_budget == 2  # the core's settings
    old.close()
    assert gym.spec(HAPTIC_EXPLORE_ID).entry_point.endswith("haptic_explore_v0:HapticExploreEnv")
    env = gym.make(HAPTIC_EXPLORE_COMPACT_ID, backend="analytic", fit=FAST_FIT, touch_budget=2)
    assert env.observation_space.shape == (OBS_DIM,)
    assert env.action_space.shape == (5,)
    env.close()


def test_check_env_passes() -> None:
    env = make(touch_budget=3)
    check_env(env)
    env.close()


def test_observation_names_match_the_space() -> None:
    assert len(OBS_NAMES) == OBS_DIM == 13 + 4 + 2 * N_DIRECTIONS + 4
    assert DIRECTIONS.shape == (N_DIRECTIONS, 3)
    np.testing.assert_allclose(np.linalg.norm(DIRECTIONS, axis=1), 1.0)


def test_seeded_episodes_repeat_and_the_log_reward_sums_to_minus_log_epsilon() -> None:
    env = make(touch_budget=5)
    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, (5, 5)).astype(np.float32)
    runs = []
    for _ in range(2):
        obs, _ = env.reset(seed=11)
        observations, rewards, infos = [obs], [], []
        for t, action in enumerate(actions):
            obs, reward, terminated, truncated, info = env.step(action)
            observations.append(obs)
            rewards.append(reward)
            infos.append(info)
            assert not truncated
            assert terminated == (t == len(actions) - 1)  # the budget ends the task
            assert env.observation_space.contains(obs)
        runs.append((np.array(observations), np.array(rewards), infos))
    np.testing.assert_array_equal(runs[0][0], runs[1][0])
    np.testing.assert_array_equal(runs[0][1], runs[1][1])
    eps = runs[0][2][-1]["epsilon"]
    assert np.sum(runs[0][1]) == pytest.approx(-np.log(max(eps, 1e-3)), abs=1e-9)
    env.close()


def test_the_coverage_term_adds_the_drop_of_the_mean_gap() -> None:
    env = make(touch_budget=3, coverage_weight=2.0)
    obs, _ = env.reset(seed=2)
    assert np.mean(obs[GAPS]) == 1.0
    total = 0.0
    for _ in range(3):
        obs, reward, _, _, info = env.step(np.array([1, 0.2, 0.3, 0.5, 1], np.float32))
        total += reward
    assert info["coverage_gap"] == pytest.approx(np.mean(obs[GAPS]), abs=1e-6)
    expect = -np.log(max(info["epsilon"], 1e-3)) + 2.0 * (1.0 - info["coverage_gap"])
    assert total == pytest.approx(expect, abs=1e-6)
    with pytest.raises(InvalidInputError, match="coverage_weight"):
        make(coverage_weight=-1.0)


def test_the_epsilon_reward_is_v0s() -> None:
    env = make(touch_budget=3, reward="epsilon")
    env.reset(seed=2)
    total = 0.0
    for _ in range(3):
        _, reward, _, _, info = env.step(np.array([1, 0.2, 0.3, 0.5, 1], np.float32))
        total += reward
    assert total == pytest.approx(1.0 - info["epsilon"], abs=1e-12)


def test_v1_runs_the_v0_action_of_its_action() -> None:
    """Same seed, same touches: v1 and v0 (given v1's mapped actions) give the same contacts."""
    v1 = make(touch_budget=3)
    v0 = HapticExploreEnv(backend="analytic", objects="random", fit=FAST_FIT, touch_budget=3)
    v1.reset(seed=5)
    v0.reset(seed=5)
    rng = np.random.default_rng(0)
    for t in range(3):
        action = rng.uniform(-1, 1, 5).astype(np.float32)
        _, _, _, _, info1 = v1.step(action)
        _, _, _, _, info0 = v0.step(v0_action(action, t, v0.config.max_stroke, v0.n_fingers)[0])
        assert info1["epsilon"] == info0["epsilon"]
    np.testing.assert_array_equal(v1.contacts.points, v0.contacts.points)


def test_decode_action_v1() -> None:
    d, psi, frac = decode_action_v1(np.array([0.0, 3.0, 0.0, 0.5, 1.0]))  # clipped to 1
    np.testing.assert_allclose(d, [0, 1, 0])
    assert psi == pytest.approx(np.pi / 2)
    assert frac == 1.0
    d, _, frac = decode_action_v1(np.zeros(5))
    np.testing.assert_allclose(d, [0, 0, 1])  # the zero vector: from above
    assert frac == 0.5
    with pytest.raises(InvalidInputError, match="action"):
        decode_action_v1(np.zeros(4))
    with pytest.raises(InvalidInputError, match="action"):
        decode_action_v1(np.array([np.nan, 0, 0, 0, 0]))


def test_encode_action_v1_is_the_inverse_of_decode() -> None:
    gen = np.random.default_rng(0)
    for _ in range(20):
        d = gen.normal(size=3)
        psi, frac = float(gen.uniform(-np.pi, np.pi)), float(gen.uniform(0, 1))
        back_d, back_psi, back_frac = decode_action_v1(encode_action_v1(3.0 * d, psi, frac))
        np.testing.assert_allclose(back_d, d / np.linalg.norm(d), atol=1e-12)
        assert back_psi == pytest.approx(psi, abs=1e-12)
        assert back_frac == pytest.approx(frac, abs=1e-12)
    # psi wraps to [-pi, pi]
    assert encode_action_v1([0, 0, 1], 3 * np.pi / 2, 1.0)[3] == pytest.approx(-0.5)


def test_fingers_in_turn_and_the_v0_action_decodes_back() -> None:
    assert [finger_for_touch(t, 4) for t in range(5)] == [1, 2, 3, 0, 1]
    action, approach = v0_action(np.array([0.3, -0.4, 0.5, -0.5, 1.0]), 2, 0.05, 4)
    touch = decode_action(action, 0.05, 0.005, 4)
    np.testing.assert_allclose(touch.approach, approach, atol=1e-6)
    np.testing.assert_allclose(approach, np.array([0.3, -0.4, 0.5]) / np.sqrt(0.5))
    assert touch.finger == 3
    assert touch.stroke_length == pytest.approx(0.05, abs=1e-7)
    assert touch.stroke_angle == pytest.approx(-np.pi / 2, abs=1e-6)


def _obs(points: np.ndarray, touches: int) -> dict[str, np.ndarray]:
    m = 16
    out = {
        "points": np.zeros((m, 3), np.float32), "normals": np.zeros((m, 3), np.float32),
        "mask": np.zeros(m, np.int8), "fit": np.zeros(13, np.float32),
        "fit_valid": np.zeros(1, np.int8), "eof": np.zeros(1, np.float32),
        "touches": np.array([touches], np.float32),
    }  # fmt: skip
    out["points"][: len(points)] = points
    out["mask"][: len(points)] = 1
    return out


def test_observer_gaps_and_failed_directions() -> None:
    observer = CompactObserver(obs_scale=0.1)
    first = observer.reset(_obs(np.zeros((0, 3)), 0))
    gaps, failed = first[GAPS], first[FAILED]
    np.testing.assert_array_equal(gaps, 1.0)  # nothing touched yet
    np.testing.assert_array_equal(failed, 0.0)
    # A touch from +z that brought nothing: the directions within the cone are marked.
    after_miss = observer.update(_obs(np.zeros((0, 3)), 1), np.array([0.0, 0.0, 1.0]))
    marked = after_miss[FAILED].astype(bool)
    np.testing.assert_array_equal(marked, DIRECTIONS[:, 2] > np.cos(FAILED_CONE))
    assert marked.any()
    # A contact on top of the stand-in sphere: the top direction is covered, the bottom is not.
    top = np.array([[0.0, 0.0, 0.4]])  # 0.04 m / obs_scale 0.1
    after_hit = observer.update(_obs(top, 2), np.array([1.0, 0.0, 0.0]))
    gaps = after_hit[GAPS]
    # sphere of radius 0.04 m (the contact's distance): gap = 0.04 |u - e_z| / 0.04, capped at 1
    expect = np.minimum(1.0, np.linalg.norm(DIRECTIONS - [0.0, 0.0, 1.0], axis=1))
    np.testing.assert_allclose(gaps, expect, atol=1e-3)
    np.testing.assert_array_equal(after_hit[FAILED].astype(bool), marked)
    # the widest open gap: the first unmarked direction of gap 1 (the bottom half has gap 1)
    k = int(np.argmax(np.where(marked, -1.0, gaps)))
    assert not marked[k] and gaps[k] == 1.0
    np.testing.assert_allclose(after_hit[81:84], DIRECTIONS[k], atol=1e-6)
    assert after_hit[84] == 1.0
    # with every direction marked, the widest gap over all of them
    everything = CompactObserver(0.1)
    everything.reset(_obs(np.zeros((0, 3)), 0))
    for d in DIRECTIONS:
        last = everything.update(_obs(np.zeros((0, 3)), 1), d)
    assert last[FAILED].all()
    np.testing.assert_allclose(last[81:84], DIRECTIONS[0], atol=1e-6)
    assert after_hit[15] == pytest.approx(0.2)  # touches / 10
    assert after_hit[16] == pytest.approx(0.01)  # contacts / 100


def test_bad_settings_are_refused() -> None:
    with pytest.raises(InvalidInputError, match="reward"):
        make(reward="uncertainty")
    with pytest.raises(InvalidInputError, match="epsilon_floor"):
        make(epsilon_floor=0.0)
    with pytest.raises(InvalidInputError, match="backend"):
        HapticExploreCompactEnv(backend="bullet")
    with pytest.raises(InvalidInputError, match="either"):
        HapticExploreCompactEnv(
            config=HapticExploreV1Config.from_kwargs(backend="analytic"), noise=0.1
        )
    with pytest.raises(InvalidInputError, match="obs_scale"):
        CompactObserver(0.0)
    env = make()
    with pytest.raises(InvalidInputError, match="reset"):
        env.step(np.zeros(5, np.float32))
