"""Trained actors: the weight file format, its checks, the numpy forward pass and the exporter."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.envs.haptic_explore_compact_v0 import ACTION_DIM_V1, ENV_ID, OBS_DIM
from hapticsim.envs.learned import Actor, load_actor
from hapticsim.errors import InvalidInputError

SETTINGS = {"obs_scale": 0.1, "max_stroke": 0.05, "stroke_spacing": 0.005, "touch_budget": 10}


def random_actor(
    obs_dim: int = OBS_DIM, env_id: str = ENV_ID, seed: int = 0, renorm: bool = False
) -> Actor:
    rng = np.random.default_rng(seed)
    layers: list[str] = []
    params: list[np.ndarray] = []
    width = obs_dim
    for out in (8, 8):
        if renorm:
            layers.append("batch_renorm")
            params += [rng.normal(size=width), rng.uniform(0.5, 2, width), rng.normal(size=width),
                       rng.normal(size=width)]  # fmt: skip
        layers += ["linear", "relu"]
        params += [rng.normal(size=(out, width)) / np.sqrt(width), rng.normal(size=out)]
        width = out
    layers.append("linear")
    params += [rng.normal(size=(ACTION_DIM_V1, width)), rng.normal(size=ACTION_DIM_V1)]
    meta = {"env_id": env_id, "settings": dict(SETTINGS), "batch_renorm_eps": 1e-3}
    # float32 values, as stored: the round trip is then exact
    return Actor(tuple(layers), tuple(p.astype(np.float32) for p in params), "tanh", meta)


def test_forward_pass_is_the_mlp() -> None:
    actor = random_actor()
    x = np.random.default_rng(1).normal(size=(4, OBS_DIM))
    w1, b1, w2, b2, w3, b3 = actor.params
    h = np.maximum(x @ w1.T + b1, 0)
    h = np.maximum(h @ w2.T + b2, 0)
    np.testing.assert_allclose(actor(x), np.tanh(h @ w3.T + b3), rtol=1e-6, atol=1e-6)
    np.testing.assert_array_equal(actor(x[0]), actor(x)[0])
    assert actor(x).dtype == np.float32
    assert np.all(np.abs(actor(10 * x)) <= 1)


def test_batch_renorm_layers_normalise_with_the_running_statistics() -> None:
    actor = random_actor(renorm=True)
    x = np.random.default_rng(2).normal(size=OBS_DIM)
    mean, var, scale, bias, w1, b1 = actor.params[:6]
    h = np.maximum(((x - mean) / np.sqrt(var + 1e-3) * scale + bias) @ w1.T + b1, 0)
    mean, var, scale, bias, w2, b2, w3, b3 = actor.params[6:]
    h = np.maximum(((h - mean) / np.sqrt(var + 1e-3) * scale + bias) @ w2.T + b2, 0)
    np.testing.assert_allclose(actor(x), np.tanh(h @ w3.T + b3), rtol=1e-6, atol=1e-6)


def test_save_and_load_round_trip(tmp_path) -> None:  # noqa: ANN001
    actor = random_actor(renorm=True)
    path = actor.save(tmp_path / "actor.npz")
    back = load_actor(path, env_id=ENV_ID, obs_dim=OBS_DIM, action_dim=ACTION_DIM_V1)
    assert back.layers == actor.layers
    for a, b in zip(actor.params, back.params, strict=True):
        np.testing.assert_array_equal(a, b)
    assert back.meta["settings"] == SETTINGS
    x = np.random.default_rng(3).normal(size=OBS_DIM)
    np.testing.assert_array_equal(back(x), actor(x))
    assert path.stat().st_size < 20_000


def test_weights_for_another_env_version_or_observation_size_are_refused(tmp_path) -> None:  # noqa: ANN001
    path = random_actor(env_id="hapticsim/HapticExplore-v0").save(tmp_path / "v0.npz")
    with pytest.raises(InvalidInputError, match="trained for hapticsim/HapticExplore-v0") as err:
        load_actor(path, env_id=ENV_ID, obs_dim=OBS_DIM)
    assert "runs learned policies for hapticsim/HapticExploreCompact-v0" in str(err.value)
    path = random_actor(obs_dim=40).save(tmp_path / "small.npz")
    with pytest.raises(InvalidInputError, match="observation size 40") as err:
        load_actor(path, env_id=ENV_ID, obs_dim=OBS_DIM)
    assert f"observation size {OBS_DIM}" in str(err.value)


def test_settings_that_change_the_meaning_are_refused() -> None:
    actor = random_actor()
    actor.check_settings({"obs_scale": 0.1, "max_stroke": 0.05, "stroke_spacing": 0.005})
    with pytest.raises(InvalidInputError, match="max_stroke=0.08"):
        actor.check_settings({"obs_scale": 0.1, "max_stroke": 0.08, "stroke_spacing": 0.005})


def test_bad_files_are_refused_with_a_message(tmp_path) -> None:  # noqa: ANN001
    with pytest.raises(InvalidInputError, match="does not exist"):
        load_actor(tmp_path / "none.npz")
    (tmp_path / "junk.npz").write_bytes(b"not a zip file")
    with pytest.raises(InvalidInputError, match="not a readable .npz"):
        load_actor(tmp_path / "junk.npz")
    np.savez(tmp_path / "nometa.npz", param_0=np.zeros(3))
    with pytest.raises(InvalidInputError, match="no `meta`"):
        load_actor(tmp_path / "nometa.npz")
    np.savez(tmp_path / "other.npz", meta=np.array(json.dumps({"format": "keras"})))
    with pytest.raises(InvalidInputError, match="not a hapticsim-actor file"):
        load_actor(tmp_path / "other.npz")
    good = random_actor().save(tmp_path / "good.npz")
    with np.load(good) as data:
        files = dict(data.items())
    files.pop("param_3")
    np.savez(tmp_path / "short.npz", **files)
    with pytest.raises(InvalidInputError, match="lacks arrays"):
        load_actor(tmp_path / "short.npz")
    with pytest.raises(InvalidInputError, match=".npz"):
        random_actor().save(tmp_path / "actor.pt")


def test_actor_values_are_checked() -> None:
    actor = random_actor()
    params = list(actor.params)
    params[0] = params[0].copy()
    params[0][0, 0] = np.nan
    with pytest.raises(InvalidInputError, match="NaN"):
        Actor(actor.layers, tuple(params), "tanh", actor.meta)
    with pytest.raises(InvalidInputError, match="layers"):
        Actor(("linear", "gelu"), actor.params[:2], "tanh")
    with pytest.raises(InvalidInputError, match="inputs after a layer"):
        Actor(("linear", "linear"), (actor.params[0], actor.params[1]) * 2, "tanh")
    with pytest.raises(InvalidInputError, match="obs"):
        actor(np.zeros(OBS_DIM + 1))


@pytest.mark.parametrize("algo", ["SAC", "PPO", "CrossQ"])
def test_export_matches_the_models_deterministic_action(algo: str) -> None:
    """The numpy actor gives the trained model's deterministic action (float32 weights)."""
    pytest.importorskip("stable_baselines3")
    pytest.importorskip("torch")
    import gymnasium as gym
    from gymnasium import spaces

    from lab.training.export import actor_from_sb3

    class Toy(gym.Env):
        observation_space = spaces.Box(-10, 10, (OBS_DIM,), np.float32)
        action_space = spaces.Box(-1, 1, (ACTION_DIM_V1,), np.float32)

        def reset(self, *, seed=None, options=None):  # noqa: ANN001, ANN202
            super().reset(seed=seed)
            return self.np_random.normal(size=OBS_DIM).astype(np.float32), {}

        def step(self, action):  # noqa: ANN001, ANN202
            obs = self.np_random.normal(size=OBS_DIM).astype(np.float32)
            return obs, float(-np.sum(action**2)), False, False, {}

    if algo == "PPO":
        from stable_baselines3 import PPO

        model = PPO("MlpPolicy", Toy(), n_steps=64, batch_size=32, n_epochs=1, seed=0,
                    policy_kwargs={"net_arch": [16, 16]}, device="cpu")  # fmt: skip
    elif algo == "SAC":
        from stable_baselines3 import SAC

        model = SAC("MlpPolicy", Toy(), learning_starts=20, batch_size=16, seed=0,
                    policy_kwargs={"net_arch": [16, 16]}, device="cpu")  # fmt: skip
    else:
        sb3_contrib = pytest.importorskip("sb3_contrib")
        model = sb3_contrib.CrossQ(
            "MlpPolicy", Toy(), learning_starts=20, batch_size=16, seed=0, device="cpu",
            policy_kwargs={"net_arch": {"pi": [16, 16], "qf": [16, 16]},
                           "renorm_warmup_steps": 10},
        )  # fmt: skip
    model.learn(80)
    actor = actor_from_sb3(model, {"env_id": ENV_ID})
    obs = np.random.default_rng(0).normal(size=(6, OBS_DIM)).astype(np.float32)
    expected, _ = model.predict(obs, deterministic=True)
    np.testing.assert_allclose(actor(obs), expected, atol=1e-5)
