"""RLlib training (lab.training.rllib): the environment creator, the configs, and a
few PPO and SAC iterations with 2 EnvRunners on a local Ray cluster started by ``ray start``."""

from __future__ import annotations

import os
import secrets
import shutil
import socket
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from hapticsim.envs.vector import HapticVectorEnv
from hapticsim.errors import ExecutionError, InvalidInputError
from lab.training import rllib
from lab.training.rllib import build_config, make_env, train, validate

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


def test_train_rllib_refuses_a_learning_rate_schedule_it_cannot_apply(tmp_path: Path) -> None:
    script = Path(__file__).resolve().parents[2] / "scripts" / "train_rllib.py"
    for bad in (["--algo", "sac", "--lr-end", "1e-5"], ["--lr-end", "0"]):
        run = subprocess.run([sys.executable, str(script), *bad, "--out", str(tmp_path / "x")],
                             capture_output=True, text=True, timeout=120)  # fmt: skip
        assert run.returncode == 2 and "--lr-end must be > 0" in run.stderr
        assert not (tmp_path / "x").exists()


def test_rllib_heldout_refuses_folders_and_arguments_it_cannot_use(tmp_path: Path) -> None:
    script = Path(__file__).resolve().parents[2] / "scripts" / "rllib_heldout.py"
    cases = [([str(tmp_path)], "no best/ module"),
             ([str(tmp_path), "--episodes", "1"], "--episodes must be >= 2"),
             ([str(tmp_path), "--actor", "x"], "--actor must be NAME=FILE")]  # fmt: skip
    for args, message in cases:
        run = subprocess.run([sys.executable, str(script), *args], capture_output=True,
                             text=True, timeout=120)  # fmt: skip
        assert run.returncode == 2 and message in run.stderr, run.stderr


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_token_is_found_where_ray_looks_for_one(tmp_path: Path) -> None:
    home = tmp_path / "home"
    assert not rllib._token_available({}, home)
    assert rllib._token_available({"RAY_AUTH_TOKEN": "abc"}, home)
    token = tmp_path / "token"
    assert not rllib._token_available({"RAY_AUTH_TOKEN_PATH": str(token)}, home)
    token.write_text("abc")
    assert rllib._token_available({"RAY_AUTH_TOKEN_PATH": str(token)}, home)
    (home / ".ray").mkdir(parents=True)
    (home / ".ray" / "auth_token").write_text("abc")
    assert rllib._token_available({}, home)


@pytest.mark.slow  # needs ray, which CI installs for the slow run
def test_a_cluster_that_cannot_be_joined_raises_a_clear_error(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ray = pytest.importorskip("ray")

    def refuse(**kwargs: object) -> None:
        raise ConnectionError("Failed to connect to Ray cluster at 10.0.0.9:6379")

    monkeypatch.setattr(ray, "init", refuse)
    monkeypatch.setenv("RAY_AUTH_MODE", "disabled")
    with pytest.raises(ExecutionError, match=r"10\.0\.0\.9:6379.*RAY_AUTH_TOKEN_PATH"):
        rllib.join_cluster("10.0.0.9:6379")


@pytest.fixture(scope="module")
def ray_cluster(tmp_path_factory: pytest.TempPathFactory):
    """A local cluster as a user starts one, ``ray start --head`` (2 CPUs), then ``ray stop``.

    With token authentication (Ray's default when a token is at hand) and a token of its own,
    so it does not depend on ``~/.ray``. The driver gets only the token's path, as a user on
    another machine would: joining by address must turn authentication on by itself (CI
    failed on exactly that while ``~/.ray/auth_token`` existed).
    """
    pytest.importorskip("ray.rllib")
    pytest.importorskip("torch")
    ray_cli = str(Path(sys.executable).parent / "ray")
    if not Path(ray_cli).exists():
        ray_cli = shutil.which("ray") or pytest.skip("no `ray` command")
    port = _free_port()
    temp = tmp_path_factory.mktemp("ray")
    token = temp / "auth_token"
    token.write_text(secrets.token_hex(32))
    keys = ("RAY_AUTH_MODE", "RAY_AUTH_TOKEN", "RAY_AUTH_TOKEN_PATH")
    saved = {key: os.environ.get(key) for key in keys}
    for key in saved:
        os.environ.pop(key, None)
    head_env = {**os.environ, "RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN_PATH": str(token)}
    start = [ray_cli, "start", "--head", "--num-cpus", "2", "--port", str(port),
             "--include-dashboard", "false", "--temp-dir", str(temp),
             "--disable-usage-stats"]  # fmt: skip
    subprocess.run(start, check=True, capture_output=True, timeout=120, env=head_env)
    os.environ["RAY_AUTH_TOKEN_PATH"] = str(token)
    try:
        yield f"127.0.0.1:{port}"
    finally:
        import ray

        ray.shutdown()
        subprocess.run([ray_cli, "stop", "--force"], capture_output=True, timeout=120,
                       env=head_env)  # fmt: skip
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


@pytest.mark.slow
@pytest.mark.parametrize(
    ("algo", "vectorize"), [("ppo", "sync"), ("sac", "sync"), ("ppo", "native")]
)
def test_rllib_trains_with_two_env_runners_on_a_cluster(
    algo: str, vectorize: str, ray_cluster: str, tmp_path: Path
) -> None:
    training = (
        {"train_batch_size_per_learner": 64, "minibatch_size": 32, "num_epochs": 1,
         "lr": [[0, 3e-4], [96, 3e-5]]}  # a schedule, as train_rllib.py --lr-end makes
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
    assert summary["num_env_runners"] == 2 and summary["seed"] == 0
    if algo == "ppo":
        assert summary["lr"] == [[0, 3e-4], [96, 3e-5]]
    assert np.isfinite(summary["best"]["val_mean"])
    assert (tmp_path / "curve.csv").read_text().startswith("steps,")
    assert (tmp_path / "best").is_dir()
