"""scripts/train_policy.py end to end (slow): train, checkpoint, resume, export, evaluate; and
scripts/bc_heuristic.py (behaviour cloning of the uncertainty policy) on a few episodes.

A pipeline test, not a quality test: a few thousand steps of SAC with small networks.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "train_policy.py"


def train(out: Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), MUJOCO_GL="egl")
    return subprocess.run(
        [sys.executable, str(SCRIPT), "--out", str(out), *args],
        capture_output=True, text=True, env=env, timeout=3600,
    )  # fmt: skip


@pytest.mark.slow
def test_training_checkpoints_resumes_and_exports(tmp_path) -> None:  # noqa: ANN001
    pytest.importorskip("stable_baselines3")
    pytest.importorskip("torch")
    out = tmp_path / "run"
    first = train(
        out, "--algo", "sac", "--timesteps", "2000", "--n-envs", "2", "--net", "32", "32",
        "--learning-starts", "500", "--buffer-size", "5000", "--batch-size", "64",
        "--val-episodes", "2", "--val-every", "1000", "--checkpoint-every", "1000",
    )  # fmt: skip
    assert first.returncode == 0, first.stderr[-2000:]
    summary = json.loads(first.stdout)
    assert summary["steps"] == 2000
    for name in ("policy.npz", "policy_last.npz", "curve.csv", "curve.png", "train.log"):
        assert (out / name).is_file(), name
    assert (out / "checkpoint" / "model.zip").is_file()
    assert (out / "checkpoint" / "replay_buffer.pkl").is_file()

    # A second start on the same folder without --resume is refused; with it, the run goes on.
    again = train(out, "--timesteps", "3000")
    assert again.returncode == 2 and "--resume" in again.stderr
    resumed = train(out, "--resume", "--timesteps", "3000")
    assert resumed.returncode == 0, resumed.stderr[-2000:]
    rows = (out / "curve.csv").read_text().splitlines()
    steps = [int(r.split(",")[0]) for r in rows[1:]]
    assert steps == [0, 1000, 2000, 3000]
    walls = [float(r.split(",")[1]) for r in rows[1:]]
    assert walls == sorted(walls)  # wall time adds up across the resume
    assert "resumed sac at 2000 steps" in (out / "train.log").read_text()

    # The exported actor is a learned policy for the v0 environment and the command line.
    from hapticsim.envs.episodes import run_episode
    from hapticsim.envs.estimator import FitSchedule
    from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
    from hapticsim.envs.policies import make_policy

    env = HapticExploreEnv(
        backend="analytic", objects="random", touch_budget=3,
        fit=FitSchedule(full_budget=1000, refine_budget=100),
    )  # fmt: skip
    policy = make_policy(f"learned:{out / 'policy_last.npz'}", env)
    assert policy.meta["training"]["steps"] == 3000
    assert policy.meta["training"]["algo"] == "sac"
    record = run_episode(env, policy, seed=0)
    assert np.all(np.isfinite(record.epsilon))


@pytest.mark.slow
@pytest.mark.parametrize("observation", ["touch", "touch-tactile"])
def test_ppo_on_the_touch_history_with_the_native_vector_env(tmp_path, observation: str) -> None:  # noqa: ANN001
    """The recipe of the shipped ``learned-touch`` actor, in small: PPO, the set encoder, the
    native vector environment; the exported actor runs as a policy on v0 (the tactile one with
    its pads' images for ``touch-tactile``)."""
    pytest.importorskip("stable_baselines3")
    pytest.importorskip("torch")
    out = tmp_path / "touch"
    run = train(
        out, "--algo", "ppo", "--env", observation, "--vector", "native", "--n-envs", "4",
        "--n-steps", "64", "--n-epochs", "1", "--batch-size", "64", "--timesteps", "512",
        "--net", "16", "--set-net", "8", "8", "--val-episodes", "2", "--val-every", "256",
        "--checkpoint-every", "512", "--chamfer-samples", "10",
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-2000:]
    assert json.loads(run.stdout)["steps"] == 512
    from hapticsim.envs.episodes import run_episode
    from hapticsim.envs.estimator import FitSchedule
    from hapticsim.envs.haptic_explore_tactile_v0 import HapticExploreTactileEnv
    from hapticsim.envs.haptic_explore_touch_v0 import ENV_ID, TACTILE_ENV_ID
    from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
    from hapticsim.envs.policies import make_policy

    tactile = observation == "touch-tactile"
    env = (HapticExploreTactileEnv if tactile else HapticExploreEnv)(
        backend="analytic", objects="random", touch_budget=3,
        fit=FitSchedule(full_budget=1000, refine_budget=100),
    )  # fmt: skip
    policy = make_policy(f"learned:{out / 'policy_last.npz'}", env)
    assert policy.meta["env_id"] == (TACTILE_ENV_ID if tactile else ENV_ID)
    assert len(policy.actor.sets) == 2
    assert policy.meta["settings"]["sensing"] == ("tactile" if tactile else "exact")
    assert np.all(np.isfinite(run_episode(env, policy, seed=0).epsilon))


@pytest.mark.slow
@pytest.mark.parametrize("observation", ["touch", "compact"])
def test_behaviour_cloning_of_the_heuristic_exports_an_actor_that_runs(tmp_path,  # noqa: ANN001
                                                                        observation: str) -> None:
    """scripts/bc_heuristic.py end to end on a few episodes: the weight file it writes is an actor
    of the chosen observation that `policies evaluate` runs."""
    pytest.importorskip("stable_baselines3")
    pytest.importorskip("torch")
    from hapticsim.envs.learned import load_actor

    out = tmp_path / "bc"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    run = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "bc_heuristic.py"), "--observation", observation,
         "--episodes", "12", "--epochs", "1", "--out", str(out)],
        capture_output=True, text=True, env=env, timeout=600,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-2000:]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["data"]["samples"] == 120 and summary["observation"] == observation
    assert np.isfinite(summary["epochs"][-1]["held_out_mse"])
    actor = load_actor(out / "policy.npz", obs_dim=545 if observation == "touch" else 85)
    assert actor.meta["training"]["algo"].startswith("behaviour cloning")
    evaluate = subprocess.run(
        [sys.executable, "-m", "hapticsim.cli", "policies", "evaluate", "--policy",
         f"learned:{out / 'policy.npz'}", "--episodes", "1", "--touches", "2", "--quiet"],
        capture_output=True, text=True, env=env, timeout=600,
    )  # fmt: skip
    assert evaluate.returncode == 0, evaluate.stderr[-2000:]
    assert len(json.loads(evaluate.stdout)["episodes_epsilon"][0]) == 2
