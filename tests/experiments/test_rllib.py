"""RLlib training (hapticsim.experiments.rllib): the environment creator, the configs, and a
few PPO and SAC iterations with 2 EnvRunners on a local Ray cluster started by ``ray start``."""

from __future__ import annotations

import shutil
import socket
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from hapticsim.envs.vector import HapticVectorEnv
from hapticsim.errors import InvalidInputError
from hapticsim.experiments.rllib import build_config, make_env, train, validate

SMALL = {"touch_budget": 3, "chamfer_samples": 10, "fit": {"full_budget": 600, "refine_budget": 60}}


def test_make_env_gives_one_or_a_native_vector_env() -> None:
    env = make_env({"backend": "analytic", **SMALL})
    assert isinstance(env.unwrapped, gym.Env) and env.observation_space.shape == (85,)
    env.close()
    vec = make_env({"backend": "analytic", "num_envs": 2, "workers": 0, **SMALL})
    assert isinstance(vec, HapticVectorEnv) and vec.num_envs == 2
    vec.close()


def test_validate_runs_random_touches_on_fixed_objects() -> None:
    a = validate(None, SMALL, episodes=2)
    b = validate(None, SMALL, episodes=2)
    assert a == b and 0.0 <= a["mean"] <= 1.0


def test_bad_arguments_raise_clear_errors() -> None:
    with pytest.raises(InvalidInputError, match="algo"):
        build_config("dqn")
    with pytest.raises(InvalidInputError, match="vectorize"):
        build_config("ppo", vectorize="async")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def ray_cluster(tmp_path_factory: pytest.TempPathFactory):
    """A local cluster as a user starts one: ``ray start --head`` (2 CPUs), then ``ray stop``."""
    pytest.importorskip("ray.rllib")
    pytest.importorskip("torch")
    ray_cli = str(Path(sys.executable).parent / "ray")
    if not Path(ray_cli).exists():
        ray_cli = shutil.which("ray") or pytest.skip("no `ray` command")
    port = _free_port()
    temp = tmp_path_factory.mktemp("ray")
    start = [ray_cli, "start", "--head", "--num-cpus", "2", "--port", str(port),
             "--include-dashboard", "false", "--temp-dir", str(temp),
             "--disable-usage-stats"]  # fmt: skip
    subprocess.run(start, check=True, capture_output=True, timeout=120)
    try:
        yield f"127.0.0.1:{port}"
    finally:
        import ray

        ray.shutdown()
        subprocess.run([ray_cli, "stop", "--force"], capture_output=True, timeout=120)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("algo", "vectorize"), [("ppo", "sync"), ("sac", "sync"), ("ppo", "native")]
)
def test_rllib_trains_with_two_env_runners_on_a_cluster(
    algo: str, vectorize: str, ray_cluster: str, tmp_path: Path
) -> None:
    training = (
        {"train_batch_size_per_learner": 64, "minibatch_size": 32, "num_epochs": 1}
        if algo == "ppo" else
        {"train_batch_size_per_learner": 32, "num_steps_sampled_before_learning_starts": 32}
    )  # fmt: skip
    native = vectorize == "native"  # 2 environments per runner in 1 worker process each
    config = build_config(
        algo, env_config={**SMALL, "objects": "paper", **({"workers": 1} if native else {})},
        num_env_runners=2, num_envs_per_env_runner=2 if native else 1, vectorize=vectorize,
        hidden=(32,), seed=0, **training,
    ).env_runners(rollout_fragment_length=16)
    summary = train(config, 96, tmp_path, eval_every=10_000, val_episodes=2, address=ray_cluster,
                    progress=False)  # fmt: skip
    assert summary["steps"] >= 96
    assert summary["num_env_runners"] == 2
    assert np.isfinite(summary["best"]["val_mean"])
    assert (tmp_path / "curve.csv").read_text().startswith("steps,")
    assert (tmp_path / "best").is_dir()
