"""hapticsim/HapticExploreTouch-v0 (the touch history as sets), set encoders in weight files, and
the ``learned-touch`` policy."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from hapticsim.envs.episodes import run_episode
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_compact_v0 import (
    ACTION_DIM_V1,
    HEAD_DIM,
    HapticExploreCompactEnv,
)
from hapticsim.envs.haptic_explore_touch_v0 import (
    ENV_ID,
    MAX_POINTS,
    MAX_TOUCHES,
    OBS_DIM,
    POINT_WIDTH,
    POINTS_OFFSET,
    SETS,
    TOUCH_WIDTH,
    TOUCHES_OFFSET,
    HapticExploreTouchEnv,
    point_indices,
)
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.envs.learned import Actor, SetEncoder, load_actor
from hapticsim.envs.policies import (
    LEARNED_TOUCH_WEIGHTS,
    POLICY_NAMES,
    LearnedTouchPolicy,
    make_policy,
)
from hapticsim.errors import InvalidInputError
from tests.envs.test_learned import SETTINGS

FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)
KW = {"backend": "analytic", "objects": "random", "fit": FAST_FIT, "touch_budget": 5}


def random_set_actor(
    seed: int = 0, env_id: str = ENV_ID, sets: tuple[tuple[int, int, int], ...] = SETS
) -> Actor:
    """A touch actor of random weights (float32 values, as stored), for the observation whose
    sets are `sets`."""
    rng = np.random.default_rng(seed)

    def mlp(widths: list[int]) -> tuple[tuple[str, ...], tuple[np.ndarray, ...]]:
        kinds: list[str] = []
        arrays: list[np.ndarray] = []
        for a, b in zip(widths[:-1], widths[1:], strict=True):
            kinds += ["linear", "relu"]
            arrays += [(rng.normal(size=(b, a)) / np.sqrt(a)).astype(np.float32),
                       rng.normal(size=b).astype(np.float32)]  # fmt: skip
        return tuple(kinds), tuple(arrays)

    encoders = tuple(SetEncoder(o, c, w, *mlp([w - 1, 6, 4])) for o, c, w in sets)
    kinds, arrays = mlp([HEAD_DIM + 2 * 4 * len(sets), 8])
    kinds += ("linear",)
    arrays += (rng.normal(size=(ACTION_DIM_V1, 8)).astype(np.float32),
               rng.normal(size=ACTION_DIM_V1).astype(np.float32))  # fmt: skip
    meta = {"env_id": env_id, "settings": dict(SETTINGS)}
    return Actor(kinds, arrays, "clip", meta, encoders)


def test_the_observation_is_the_touch_history() -> None:
    env = HapticExploreTouchEnv(**KW)
    obs, _ = env.reset(seed=3)
    assert obs.shape == (OBS_DIM,) == env.observation_space.shape and obs.dtype == np.float32
    assert env.observation_space.contains(obs)
    assert not obs[POINTS_OFFSET:].any()  # no contact, no touch yet
    approaches = []
    for k in range(4):
        obs, _, _, _, info = env.step(np.array([0.3 * k - 0.5, 0.4, 1.0, 0.2, 1.0], np.float32))
        approaches.append(info["approach"])
    points = obs[POINTS_OFFSET:TOUCHES_OFFSET].reshape(MAX_POINTS, POINT_WIDTH)
    touches = obs[TOUCHES_OFFSET:].reshape(MAX_TOUCHES, TOUCH_WIDTH)
    contacts = env.contacts
    shown = point_indices(len(contacts.points))
    expected = (contacts.points[shown] - env.origin) / env.config.core.obs_scale
    np.testing.assert_allclose(points[: len(shown), :3], expected, atol=1e-5)
    np.testing.assert_allclose(points[: len(shown), 3:6], contacts.normals[shown], atol=1e-6)
    assert points[: len(shown), 6].all() and not points[len(shown) :].any()
    np.testing.assert_allclose(touches[:4, :3], np.array(approaches), atol=1e-6)
    assert touches[:4, 4].all() and not touches[4:].any()
    shown_in_all = min(len(contacts.points), env.config.core.max_contacts)
    assert touches[:4, 3].sum() * 10 == pytest.approx(shown_in_all)
    assert obs[HEAD_DIM - 2] == pytest.approx(0.4)  # touches / 10


def test_same_task_as_the_compact_environment() -> None:
    """Only the observation differs: the same actions give the same rewards and infos."""
    touch = HapticExploreTouchEnv(**KW, coverage_weight=2.0)
    compact = HapticExploreCompactEnv(**KW, coverage_weight=2.0)
    a, _ = touch.reset(seed=5)
    b, _ = compact.reset(seed=5)
    np.testing.assert_array_equal(a[:HEAD_DIM], b[:HEAD_DIM])
    rng = np.random.default_rng(0)
    for _ in range(5):
        action = rng.uniform(-1, 1, 5).astype(np.float32)
        a, ra, ta, _, ia = touch.step(action)
        b, rb, tb, _, ib = compact.step(action)
        assert (ra, ta, ia["epsilon"]) == (rb, tb, ib["epsilon"])
        np.testing.assert_array_equal(a[:HEAD_DIM], b[:HEAD_DIM])
    assert ta


def test_contacts_beyond_the_set_are_spread_over_the_history() -> None:
    np.testing.assert_array_equal(point_indices(5), np.arange(5))
    keep = point_indices(1000)
    assert len(keep) == MAX_POINTS and keep[0] == 0 and keep[-1] == 999
    assert np.all(np.diff(keep) > 0)


def test_registered_with_a_vector_entry_point() -> None:
    env = gym.make(ENV_ID, **KW)
    assert env.observation_space.shape == (OBS_DIM,)
    env.close()


def test_a_set_encoder_ignores_order_and_absent_elements() -> None:
    actor = random_set_actor()
    env = HapticExploreTouchEnv(**KW)
    obs, _ = env.reset(seed=1)
    for _ in range(3):
        obs, *_ = env.step(env.action_space.sample())
    points = obs[POINTS_OFFSET:TOUCHES_OFFSET].reshape(MAX_POINTS, POINT_WIDTH)
    n = int(points[:, 6].sum())
    assert n > 3
    shuffled = obs.copy()
    block = shuffled[POINTS_OFFSET:TOUCHES_OFFSET].reshape(MAX_POINTS, POINT_WIDTH)
    block[:n] = points[np.random.default_rng(0).permutation(n)]
    block[n:, :6] = 7.0  # what absent elements hold does not count
    np.testing.assert_allclose(actor(shuffled), actor(obs), atol=1e-6)
    assert actor(np.stack([obs, shuffled])).shape == (2, ACTION_DIM_V1)
    # the forward pass by hand: per-element network, max and mean pooling, then the MLP
    e = obs[POINTS_OFFSET:TOUCHES_OFFSET].reshape(MAX_POINTS, POINT_WIDTH)[:n, :6]
    s = actor.sets[0]
    h = np.maximum(np.maximum(e @ s.params[0].T + s.params[1], 0) @ s.params[2].T + s.params[3], 0)
    z = actor.sets[0](obs[None].astype(np.float64), 1e-3)[0]
    np.testing.assert_allclose(z, np.concatenate([h.max(axis=0), h.mean(axis=0)]), rtol=1e-9)
    empty = actor.sets[1](np.zeros((1, OBS_DIM)), 1e-3)
    assert not empty.any()


def test_set_actors_round_trip_and_bad_ones_are_refused(tmp_path) -> None:  # noqa: ANN001
    actor = random_set_actor()
    path = actor.save(tmp_path / "touch.npz")
    again = load_actor(path)
    assert again.meta["format_version"] == 2 and len(again.sets) == 2
    x = np.random.default_rng(2).normal(size=(3, OBS_DIM))
    x[:, POINTS_OFFSET + 6 : TOUCHES_OFFSET : POINT_WIDTH] = 1.0
    np.testing.assert_array_equal(again(x), actor(x))
    assert again.obs_dim == OBS_DIM
    s0, s1 = actor.sets
    with pytest.raises(InvalidInputError, match="follow one another"):
        Actor(actor.layers, actor.params, "clip", {}, (s0, SetEncoder(s1.offset + 1, s1.count,
              s1.width, s1.layers, s1.params)))  # fmt: skip
    with pytest.raises(InvalidInputError, match="inputs after a layer"):
        Actor(actor.layers, actor.params, "clip", {}, (s0,))
    with pytest.raises(InvalidInputError, match="count >= 1"):
        SetEncoder(0, 0, 7, s0.layers, s0.params)


def test_a_touch_actor_runs_on_v0_as_on_its_own_environment(tmp_path) -> None:  # noqa: ANN001
    """The policy's own touch observation is the environment's: the same episode either way."""
    path = random_set_actor(seed=4).save(tmp_path / "touch.npz")
    v0 = HapticExploreEnv(**KW)
    own = HapticExploreTouchEnv(**KW)
    on_v0 = run_episode(v0, make_policy(f"learned:{path}", v0), seed=8)
    on_own = run_episode(own, make_policy(f"learned:{path}", own), seed=8)
    np.testing.assert_array_equal(on_v0.epsilon, on_own.epsilon)
    np.testing.assert_array_equal(on_v0.n_contacts, on_own.n_contacts)
    with pytest.raises(InvalidInputError, match="observations of size"):
        make_policy(f"learned:{path}", HapticExploreCompactEnv(**KW))


def test_the_shipped_touch_policy_loads_and_runs() -> None:
    assert "learned-touch" in POLICY_NAMES
    assert LEARNED_TOUCH_WEIGHTS.is_file() and LEARNED_TOUCH_WEIGHTS.stat().st_size < 400_000
    actor = load_actor(LEARNED_TOUCH_WEIGHTS)
    assert actor.meta["env_id"] == ENV_ID and actor.obs_dim == OBS_DIM and len(actor.sets) == 2
    assert actor.meta["training"]["steps"] >= 1_000_000
    assert "--env touch" in actor.meta["training"]["command"]
    env = HapticExploreEnv(**KW)
    policy = make_policy("learned-touch", env)
    assert isinstance(policy, LearnedTouchPolicy)
    first = run_episode(env, policy, seed=2)
    again = run_episode(env, make_policy("learned-touch", env), seed=2)
    np.testing.assert_array_equal(first.epsilon, again.epsilon)
    assert first.n_contacts[-1] > 0
