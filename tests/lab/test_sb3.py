"""stable-baselines3 glue (lab.training.sb3): the touch encoder, its numpy export, and
the native vector environment as an SB3 VecEnv."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")

from stable_baselines3 import PPO  # noqa: E402
from stable_baselines3.common.env_util import make_vec_env  # noqa: E402

from hapticsim.envs.haptic_explore_touch_v0 import ENV_ID, OBS_DIM  # noqa: E402
from hapticsim.envs.learned import load_actor  # noqa: E402
from hapticsim.errors import InvalidInputError  # noqa: E402
from lab.training.export import actor_from_sb3  # noqa: E402
from lab.training.sb3 import NativeVecEnv, TouchSetExtractor  # noqa: E402

KW = {"backend": "analytic", "objects": "random", "touch_budget": 3, "chamfer_samples": 10,
      "fit": {"full_budget": 600, "refine_budget": 60}}  # fmt: skip


def test_native_vec_env_steps_as_sb3s_own() -> None:
    """Observations, rewards, episode ends and last observations equal DummyVecEnv's."""
    native = NativeVecEnv(ENV_ID, 3, workers=2, **KW)
    dummy = make_vec_env("hapticsim:" + ENV_ID, n_envs=3, env_kwargs=KW)
    try:
        native.seed(11)
        dummy.seed(11)
        np.testing.assert_array_equal(native.reset(), dummy.reset())
        rng = np.random.default_rng(0)
        ends = 0
        for _ in range(7):
            actions = rng.uniform(-1, 1, (3, 5)).astype(np.float32)
            a_obs, a_rew, a_done, a_info = native.step(actions)
            b_obs, b_rew, b_done, b_info = dummy.step(actions)
            np.testing.assert_array_equal(a_obs, b_obs)
            np.testing.assert_array_equal(a_rew, b_rew)
            np.testing.assert_array_equal(a_done, b_done)
            for i in np.flatnonzero(a_done):
                ends += 1
                np.testing.assert_array_equal(
                    a_info[i]["terminal_observation"], b_info[i]["terminal_observation"]
                )
                assert a_info[i]["epsilon"] == b_info[i]["epsilon"]
                assert a_info[i]["TimeLimit.truncated"] is False
        assert ends == 6
        assert native.get_attr("n_fingers") == [4, 4, 4]
        assert native.env_is_wrapped(object) == [False] * 3
        with pytest.raises(InvalidInputError, match="step_async"):
            native.step_wait()
    finally:
        native.close()
        dummy.close()


def test_the_touch_encoder_exports_to_the_numpy_actor(tmp_path) -> None:  # noqa: ANN001
    env = NativeVecEnv(ENV_ID, 2, workers=0, **KW)
    try:
        model = PPO(
            "MlpPolicy", env, n_steps=8, batch_size=16, n_epochs=1, device="cpu", seed=0,
            policy_kwargs={"net_arch": {"pi": [16], "vf": [16]},
                           "features_extractor_class": TouchSetExtractor,
                           "features_extractor_kwargs": {"hidden": (8, 8)}},
        )  # fmt: skip
        model.learn(16)
        actor = load_actor(actor_from_sb3(model, {"env_id": ENV_ID}).save(tmp_path / "a.npz"))
        assert actor.obs_dim == OBS_DIM and [s.count for s in actor.sets] == [64, 16]
        obs = env.reset()
        for _ in range(2):  # observations with contacts and touches in them
            obs, *_ = env.step(np.ones((2, 5), np.float32))
        with torch.no_grad():
            mean = model.policy.get_distribution(torch.as_tensor(obs)).distribution.mean.numpy()
        np.testing.assert_allclose(actor(obs), np.clip(mean, -1, 1), atol=2e-5)
    finally:
        env.close()


def test_the_encoder_checks_the_observation_layout() -> None:
    from gymnasium import spaces

    with pytest.raises(InvalidInputError, match="sets end at 545"):
        TouchSetExtractor(spaces.Box(-1, 1, (85,), np.float32))
