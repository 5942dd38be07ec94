"""hapticsim/HapticExploreTouchTactile-v0: the touch history felt through taxel pads, each touch's
pooled pad image in its set element; actors trained on it."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from hapticsim.envs.episodes import run_episode
from hapticsim.envs.haptic_explore_tactile_v0 import HapticExploreTactileEnv
from hapticsim.envs.haptic_explore_touch_tactile_v0 import HapticExploreTouchTactileEnv
from hapticsim.envs.haptic_explore_touch_v0 import (
    MAX_TOUCHES,
    OBS_DIM,
    TACTILE_ENV_ID,
    TACTILE_OBS_DIM,
    TACTILE_SETS,
    TACTILE_TOUCH_WIDTH,
    TAXEL_GRID,
    TOUCH_WIDTH,
    TOUCHES_OFFSET,
    HapticExploreTouchEnv,
    TouchObserver,
    pool_taxels,
)
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.envs.policies import make_policy
from hapticsim.errors import InvalidInputError
from tests.envs.test_haptic_explore_touch_v0 import KW, random_set_actor


def test_pooling_takes_the_pad_that_felt_most_block_by_block() -> None:
    rng = np.random.default_rng(0)
    images = np.zeros((3, 16, 16))
    images[0, 2:5, 3:6] = 0.5  # a weaker pad
    images[2] = rng.uniform(0, 1, (16, 16)) * (rng.uniform(size=(16, 16)) > 0.7)
    pooled = pool_taxels(images)
    # 16 taxels per side: blocks of 2 x 2, by hand
    blocks = np.array([[images[2, 2 * i : 2 * i + 2, 2 * j : 2 * j + 2].mean()
                        for j in range(8)] for i in range(8)])  # fmt: skip
    np.testing.assert_allclose(pooled, (blocks / blocks.max()).ravel(), rtol=1e-12)
    assert pooled.shape == (TAXEL_GRID**2,) and pooled.max() == 1.0
    assert not pool_taxels(np.zeros((2, 9, 9))).any()  # no contact, no image


def test_pooling_uneven_pads_and_refusing_small_ones() -> None:
    image = np.zeros((1, 31, 31))
    image[0, 30, 30] = 2.0  # the last taxel: in the last block, of 3 x 3 taxels (31 = 7 x 4 + 3)
    pooled = pool_taxels(image).reshape(8, 8)
    assert pooled[7, 7] == 1.0 and pooled.sum() == 1.0
    image[0, 0, 0] = 2.0  # the first block has 4 x 4 taxels: the same pressure reads smaller
    pooled = pool_taxels(image).reshape(8, 8)
    assert pooled[0, 0] == pytest.approx(9 / 16) and pooled[7, 7] == 1.0
    with pytest.raises(InvalidInputError, match="rows and cols >= 8"):
        pool_taxels(np.ones((2, 7, 9)))
    with pytest.raises(InvalidInputError, match=r"\(pads, rows, cols\)"):
        pool_taxels(np.ones((9, 9)))


def test_each_touch_carries_its_pad_image() -> None:
    """The tactile observation is the touch observation plus each touch's pooled pad image: the
    same head, contacts, approaches and counts as a plain touch observer of the same v0
    observations, and the image of the touch's last contact (zeros for a touch without)."""

    env = HapticExploreTouchTactileEnv(**(KW | {"touch_budget": 8}))
    assert env.config.core.sensing == "tactile"
    obs, _ = env.reset(seed=4)
    assert obs.shape == (TACTILE_OBS_DIM,) == env.observation_space.shape
    plain = TouchObserver()
    tactile = env.env  # the tactile observation wrapper of the core: v0's observation and pads

    def v0_observation() -> dict:
        return tactile.observation(env.unwrapped._observation())

    v0_obs = v0_observation()
    np.testing.assert_array_equal(plain.reset(v0_obs), obs[:OBS_DIM])
    rng = np.random.default_rng(1)
    empty = felt = 0
    for k in range(8):
        obs, _, _, _, info = env.step(rng.uniform(-1, 1, 5).astype(np.float32))
        v0_obs = v0_observation()
        expected = plain.update(v0_obs, info["approach"])
        assert env.observation_space.contains(obs)
        np.testing.assert_array_equal(obs[:TOUCHES_OFFSET], expected[:TOUCHES_OFFSET])
        touches = obs[TOUCHES_OFFSET:].reshape(MAX_TOUCHES, TACTILE_TOUCH_WIDTH)
        reference = expected[TOUCHES_OFFSET:].reshape(MAX_TOUCHES, TOUCH_WIDTH)
        np.testing.assert_array_equal(touches[: k + 1, :4], reference[: k + 1, :4])
        assert touches[: k + 1, -1].all() and not touches[k + 1 :].any()
        image = touches[k, 4:-1]
        if info["new_contacts"]:
            np.testing.assert_allclose(image, pool_taxels(v0_obs["taxels"]), atol=1e-7)
            felt += 1
        else:
            assert not image.any()
            empty += 1
    assert felt >= 3
    # the images are those the pads felt: a touch's block sums to more than zero
    assert touches[:8][touches[:8, 3] > 0, 4:-1].max(axis=1).min() == pytest.approx(1.0)


def test_registered_tactile_with_a_vector_entry_point() -> None:
    env = gym.make(TACTILE_ENV_ID, **KW)
    assert env.observation_space.shape == (TACTILE_OBS_DIM,)
    # one core, wrapped: the touch wrapper around the tactile observation wrapper around it
    assert isinstance(env.unwrapped, HapticExploreEnv)
    assert env.unwrapped.config.sensing == "tactile"
    chain, inner = [], env
    while isinstance(inner, gym.Wrapper):
        chain.append(type(inner))
        inner = inner.env
    assert chain[-2:] == [HapticExploreTouchTactileEnv, HapticExploreTactileEnv]
    env.close()
    with pytest.raises(InvalidInputError, match="sensing"):
        HapticExploreTouchTactileEnv(**KW, sensing="exact")
    capacitive = HapticExploreTouchTactileEnv(**KW, skin="capacitive")  # 9 x 9 taxels: enough
    assert capacitive.env.taxel_shape[1:] == (9, 9)
    vec = gym.make_vec(TACTILE_ENV_ID, num_envs=2, workers=0, **KW)
    obs, _ = vec.reset(seed=0)
    assert obs.shape == (2, TACTILE_OBS_DIM)
    vec.close()


def test_a_tactile_actor_runs_on_the_tactile_v0_as_on_its_own_environment(tmp_path) -> None:  # noqa: ANN001
    path = random_set_actor(seed=5, env_id=TACTILE_ENV_ID, sets=TACTILE_SETS).save(
        tmp_path / "tactile.npz"
    )
    v0 = HapticExploreTactileEnv(**KW)
    own = HapticExploreTouchTactileEnv(**KW)
    on_v0 = run_episode(v0, make_policy(f"learned:{path}", v0), seed=6)
    on_own = run_episode(own, make_policy(f"learned:{path}", own), seed=6)
    np.testing.assert_array_equal(on_v0.epsilon, on_own.epsilon)
    np.testing.assert_array_equal(on_v0.n_contacts, on_own.n_contacts)
    with pytest.raises(InvalidInputError, match="feels the pads' images"):
        make_policy(f"learned:{path}", HapticExploreEnv(**KW))
    with pytest.raises(InvalidInputError, match="observations of size"):
        make_policy(f"learned:{path}", HapticExploreTouchEnv(**KW))


def test_pads_coarser_than_the_pooling_are_refused(tmp_path) -> None:  # noqa: ANN001
    skin = tmp_path / "coarse.toml"
    skin.write_text('name = "coarse"\npitch = 0.006\n[skin]\nmodulus = 2.0e5\nthickness = 0.002\n')
    with pytest.raises(InvalidInputError, match="6 x 6 taxels.*8 x 8 blocks"):
        HapticExploreTouchTactileEnv(**KW, skin=str(skin))
