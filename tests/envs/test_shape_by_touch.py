"""hapticsim/ShapeByTouch-v0: an ap_gym active perception task (extra apgym)."""

from __future__ import annotations

import numpy as np
import pytest

ap_gym = pytest.importorskip("ap_gym")

import gymnasium as gym  # noqa: E402
from gymnasium.utils.env_checker import check_env  # noqa: E402

from hapticsim.envs.shape_by_touch_v0 import BaselineAgent, shape_target  # noqa: E402
from hapticsim.errors import InvalidInputError  # noqa: E402

KW = {"backend": "analytic", "objects": "random_tapered", "touch_budget": 6}


def test_it_is_an_ap_gym_environment_gymnasium_accepts() -> None:
    env = gym.make("hapticsim/ShapeByTouch-v0", **KW)
    check_env(env.unwrapped, skip_render_check=True)
    assert isinstance(ap_gym.ensure_active_perception_env(env), ap_gym.BaseActivePerceptionEnv)
    log = ap_gym.ActivePerceptionLogWrapper(env)
    obs, _ = log.reset(seed=0)
    done, steps = False, 0
    while not done:  # a random agent: random touches and predictions
        obs, reward, terminated, truncated, info = log.step(log.action_space.sample())
        loss = float(info["prediction"]["loss"])
        assert reward == pytest.approx(-loss) and loss >= 0
        done, steps = terminated or truncated, steps + 1
    assert steps == 6 and "stats" in info  # the log wrapper's episode statistics
    with pytest.raises(InvalidInputError, match="superquadric truth"):
        gym.make("hapticsim/ShapeByTouch-v0", backend="analytic", objects="random_composite")


def test_the_vector_version_and_its_log_wrapper() -> None:
    venv = gym.make_vec("hapticsim/ShapeByTouch-v0", num_envs=2, **(KW | {"touch_budget": 3}))
    log = ap_gym.ActivePerceptionVectorLogWrapper(ap_gym.ensure_active_perception_vector_env(venv))
    log.reset(seed=0)
    ended = 0
    for _ in range(7):  # two episodes each, reset in the step that ends them
        _, reward, terminated, truncated, info = log.step(log.action_space.sample())
        assert reward.shape == (2,) and info["prediction"]["loss"].shape == (2,)
        ended += int(np.sum(terminated | truncated))
    assert ended == 4
    log.close()


def test_the_loss_is_normalised_to_a_blind_guess_and_baselines_act_through_it() -> None:
    env = gym.make("hapticsim/ShapeByTouch-v0", **(KW | {"touch_budget": 10}))
    inner = env.unwrapped
    # the blind guess scores 1 on average over objects it was not estimated on (2,000 draws)
    rng = np.random.default_rng(7)
    objects = inner.inner.unwrapped.config.objects
    targets = np.stack([shape_target(objects.sample(rng), 0.1) for _ in range(2000)])
    guess = np.repeat(inner.blind_guess[None], len(targets), axis=0)
    assert inner.loss_fn(guess, targets, (len(targets),)).mean() == pytest.approx(1.0, abs=0.1)
    finals = {}
    for kind in ("random", "uncertainty"):
        losses = []
        for episode in range(4):
            obs, _ = env.reset(seed=50 + episode)
            agent = BaselineAgent(env, kind, seed=episode)
            agent.reset()
            done = False
            while not done:
                obs, _, terminated, truncated, info = env.step(agent(obs))
                done = terminated or truncated
            losses.append(float(info["prediction"]["loss"]))
        finals[kind] = float(np.mean(losses))
    # measured (seeds 50-53, 10 touches): random touches 0.01-0.04, the heuristic 0.001-0.01;
    # both far below the blind guess's 1 (the prediction is the environment's own nH fit)
    assert finals["uncertainty"] < 0.5 and finals["random"] < 0.5
    env.close()
