"""Vectorised use: SyncVectorEnv, AsyncVectorEnv, gymnasium.make_vec and HapticVectorEnv."""

from __future__ import annotations

import os
import time

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

from hapticsim.envs.registration import HAPTIC_EXPLORE_COMPACT_ID, HAPTIC_EXPLORE_ID
from hapticsim.envs.vector import HapticVectorEnv, VectorEnvError
from hapticsim.errors import InvalidInputError

KWARGS = {
    "backend": "analytic",
    "touch_budget": 4,
    "fit": {"full_budget": 800, "refine_budget": 100},
}


def _run(envs: gym.vector.VectorEnv, steps: int = 6) -> None:
    obs, info = envs.reset(seed=[0, 1])
    assert envs.observation_space.contains(obs)
    assert obs["points"].shape == (2, 256, 3) and obs["fit"].shape == (2, 13)
    envs.action_space.seed(0)
    for _ in range(steps):
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
        assert reward.shape == (2,) and np.all(np.isfinite(reward))
        assert envs.observation_space.contains(obs)
        assert info["epsilon"].shape == (2,)
    envs.close()


def test_sync_vector_env() -> None:
    _run(gym.vector.SyncVectorEnv([lambda: gym.make(HAPTIC_EXPLORE_ID, **KWARGS)] * 2))


def test_async_vector_env() -> None:
    _run(gym.vector.AsyncVectorEnv([lambda: gym.make(HAPTIC_EXPLORE_ID, **KWARGS)] * 2))


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_make_vec(mode: str) -> None:
    _run(gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=2, vectorization_mode=mode, **KWARGS))


def test_vector_envs_are_seeded_alike() -> None:
    def rollout(mode: str) -> list[np.ndarray]:
        envs = gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=2, vectorization_mode=mode, **KWARGS)
        obs, _ = envs.reset(seed=[3, 4])
        out = [obs["touches"].copy()]
        rng = np.random.default_rng(0)
        for _ in range(5):
            obs, reward, *_ = envs.step(rng.uniform(-1, 1, (2, 5)).astype(np.float32))
            out += [obs["points"].copy(), obs["fit"].copy(), reward.copy()]
        envs.close()
        return out

    for a, b in zip(rollout("sync"), rollout("async"), strict=True):
        np.testing.assert_array_equal(a, b)


# ---------------------------------------------------------------- HapticVectorEnv (native)


def _rollout(envs: gym.vector.VectorEnv, steps: int = 10, seed: int = 3) -> list[object]:
    """Everything a seeded rollout returns, as plain values (across autoresets: budget 4)."""
    obs, info = envs.reset(seed=seed)
    out: list[object] = [obs, info["epsilon"].copy()]
    rng = np.random.default_rng(0)
    n = envs.num_envs
    for _ in range(steps):
        obs, reward, terminated, truncated, info = envs.step(
            rng.uniform(-1, 1, (n, 5)).astype(np.float32)
        )
        out += [obs, reward, terminated, truncated]
        out += [info[k].copy() for k in ("epsilon", "n_contacts", "fit_status", "fit_eof")]
    envs.close()
    return out


def _assert_same(a: list[object], b: list[object]) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        if isinstance(x, dict):
            assert x.keys() == y.keys()
            for k in x:
                np.testing.assert_array_equal(x[k], y[k], err_msg=k)
        else:
            np.testing.assert_array_equal(x, y)


def test_make_vec_defaults_to_the_native_vector_env() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=2, workers=0, **KWARGS)
    assert isinstance(envs, HapticVectorEnv)
    assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    _run(envs)


@pytest.mark.parametrize("workers", [0, 2, 3])
def test_native_matches_sync_bit_for_bit(workers: int) -> None:
    """Each environment of the batch gives what it gives alone (Gymnasium's SyncVectorEnv),
    across autoresets, whatever the sharding (3 workers: shards of 2, 1, 1)."""
    sync = _rollout(gym.make_vec(HAPTIC_EXPLORE_ID, 4, vectorization_mode="sync", **KWARGS))
    native = _rollout(gym.make_vec(HAPTIC_EXPLORE_ID, 4, workers=workers, **KWARGS))
    _assert_same(sync, native)


def _wait_for_draws(envs: gym.vector.VectorEnv, timeout: float = 60.0) -> None:
    """Wait until every environment holds its next episode's draws (the helpers run at idle
    priority: on a busy machine they may take a while); a wrapped environment's core holds them."""
    end = time.monotonic() + timeout
    while True:
        pending = envs.get_attr("_ahead")  # the core's, through any wrapper
        if all(d is not None for d in pending):
            return
        assert time.monotonic() < end, "the helpers drew nothing in time"
        time.sleep(0.02)


def _paced_rollout(envs: gym.vector.VectorEnv, steps: int, ahead: bool) -> list[object]:
    """A rollout as :func:`_rollout`; with `ahead`, each vector step waits until the helpers
    have drawn every environment's next episode (as a learner's update gives them time to)."""
    obs, info = envs.reset(seed=5)
    out: list[object] = [obs]
    rng = np.random.default_rng(4)
    for _ in range(steps):
        if ahead:
            _wait_for_draws(envs)
        obs, reward, terminated, truncated, info = envs.step(
            rng.uniform(-1, 1, (envs.num_envs, 5)).astype(np.float32)
        )
        out += [obs, reward, terminated, truncated, info["epsilon"].copy()]
    return out


@pytest.mark.parametrize(
    "settings",
    [{}, {"noise": 0.1, "objects": "random"}, {"sensing": "tactile", "objects": "random_tapered"}],
)
def test_episodes_drawn_ahead_are_the_episodes_drawn_alone(settings: dict) -> None:
    """With time to draw ahead, resets take their draws from the helpers (counted), and every
    environment still gives what SyncVectorEnv gives, bit for bit: paper bodies (sent as their
    index), random objects (sent whole), sensor noise and tactile sensing (their own streams,
    which leave the environment's generator alone during an episode)."""
    kwargs = KWARGS | settings
    sync = gym.make_vec(HAPTIC_EXPLORE_ID, 3, vectorization_mode="sync", **kwargs)
    expected = _paced_rollout(sync, 14, ahead=False)
    sync.close()
    native = gym.make_vec(HAPTIC_EXPLORE_ID, 3, workers=2, **kwargs)
    got = _paced_rollout(native, 14, ahead=True)
    drawn_ahead = native.get_attr("resets_drawn_ahead")
    native.close()
    _assert_same(expected, got)
    assert drawn_ahead == (2, 2, 2)  # budget 4: autoresets at steps 5 and 10, both drawn ahead


def test_the_compact_environment_draws_ahead_too() -> None:
    """v1 (and the touch environments built on it) run v0 inside: its draws are made ahead."""
    envs = gym.make_vec(HAPTIC_EXPLORE_COMPACT_ID, 2, workers=2, **KWARGS)
    envs.reset(seed=0)
    for _ in range(5):  # budget 4: the 5th step resets
        _wait_for_draws(envs)
        envs.step(np.zeros((2, 5), np.float32))
    assert envs.get_attr("resets_drawn_ahead") == (1, 1)
    envs.close()


def test_without_drawing_ahead_no_reset_is_drawn_ahead() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, draw_ahead=False,
                        batch_scheduling=False, **KWARGS)  # fmt: skip
    _paced_rollout(envs, 6, ahead=False)
    assert envs.get_attr("resets_drawn_ahead") == (0, 0)
    assert all(shard.helper is None for shard in envs._shards)
    envs.close()


def _policies_can_be_set() -> bool:
    """Whether this machine lets a process take SCHED_BATCH and SCHED_IDLE (Linux, and not
    forbidden by a sandbox)."""
    import subprocess
    import sys

    if not hasattr(os, "SCHED_IDLE"):
        return False
    code = ("import os; os.sched_setscheduler(0, os.SCHED_BATCH, os.sched_param(0)); "
            "os.sched_setscheduler(0, os.SCHED_IDLE, os.sched_param(0))")  # fmt: skip
    return subprocess.run([sys.executable, "-c", code], check=False).returncode == 0


@pytest.mark.skipif(not _policies_can_be_set(), reason="no SCHED_BATCH / SCHED_IDLE here")
def test_workers_run_as_batch_and_helpers_as_idle_processes() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, **KWARGS)
    envs.reset(seed=0)  # the workers have set their policy: they answered
    end = time.monotonic() + 30.0  # the helpers set theirs first thing, if not yet
    while time.monotonic() < end and any(
        os.sched_getscheduler(shard.helper.pid) != os.SCHED_IDLE for shard in envs._shards
    ):
        time.sleep(0.05)
    for shard in envs._shards:
        assert os.sched_getscheduler(shard.process.pid) == os.SCHED_BATCH
        assert os.sched_getscheduler(shard.helper.pid) == os.SCHED_IDLE
    envs.close()
    plain = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, batch_scheduling=False, **KWARGS)
    plain.reset(seed=0)
    assert os.sched_getscheduler(plain._shards[0].process.pid) == os.SCHED_OTHER
    plain.close()


def test_a_dead_helper_only_stops_drawing_ahead() -> None:
    """A worker whose helper died draws its own episodes: same results, no error."""
    sync = gym.make_vec(HAPTIC_EXPLORE_ID, 2, vectorization_mode="sync", **KWARGS)
    expected = _paced_rollout(sync, 12, ahead=False)
    sync.close()
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, **KWARGS)
    for shard in envs._shards:
        shard.helper.kill()
        shard.helper.join()
    got = _paced_rollout(envs, 12, ahead=False)
    assert envs.get_attr("resets_drawn_ahead") == (0, 0)
    envs.close()
    _assert_same(expected, got)


def test_same_step_autoreset_matches_sync() -> None:
    def rollout(envs: gym.vector.VectorEnv) -> list[object]:
        envs.reset(seed=7)
        out: list[object] = []
        rng = np.random.default_rng(1)
        for _ in range(5):  # budget 4: the 4th step ends and resets at once
            obs, reward, terminated, truncated, info = envs.step(
                rng.uniform(-1, 1, (2, 5)).astype(np.float32)
            )
            out += [obs["points"], obs["touches"], reward, truncated]
            if truncated.any():
                assert info["_final_obs"].tolist() == truncated.tolist()
                out += [info["final_obs"][0]["points"], info["final_info"]["epsilon"]]
        envs.close()
        return out

    sync = rollout(gym.make_vec(
        HAPTIC_EXPLORE_ID, 2, vectorization_mode="sync",
        vector_kwargs={"autoreset_mode": AutoresetMode.SAME_STEP}, **KWARGS,
    ))  # fmt: skip
    native = rollout(gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, autoreset_mode="same_step",
                                  **KWARGS))  # fmt: skip
    assert any(np.any(x) for x in sync[3::4][:4])  # a truncation happened
    _assert_same(sync, native)


def test_reset_mask_resets_only_those() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, **KWARGS)
    envs.reset(seed=0)
    obs, _, _, _, _ = envs.step(np.zeros((2, 5), np.float32))
    obs, info = envs.reset(seed=[5, None], options={"reset_mask": np.array([True, False])})
    assert obs["touches"][:, 0].tolist() == [0.0, 1.0]
    assert info["_epsilon"].tolist() == [True, False]
    envs.close()


def test_call_get_attr_and_set_attr() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 3, workers=2, **KWARGS)
    envs.reset(seed=0)
    assert envs.get_attr("n_fingers") == (4, 4, 4)
    origins = envs.call("origin")  # a property: read, not called
    assert len(origins) == 3 and all(o.shape == (3,) for o in origins)
    envs.set_attr("marker", [1, 2, 3])
    assert envs.get_attr("marker") == (1, 2, 3)
    envs.close()


def test_errors_name_the_environment() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 3, workers=2, **KWARGS)
    envs.reset(seed=0)
    actions = np.zeros((3, 5), np.float32)
    actions[2, 0] = np.nan
    with pytest.raises(InvalidInputError, match=r"environment 2: .*action"):  # as alone
        envs.step(actions)
    envs.close()
    envs.close()  # twice is fine
    with pytest.raises(InvalidInputError, match="closed"):
        envs.step(np.zeros((3, 5), np.float32))


def test_an_error_in_the_first_worker_leaves_the_others_in_step() -> None:
    """After environment 0's bad action, the next step's answers are that step's: the second
    worker's answer to the failed step was read, not left in its pipe. (The environments of
    other shards did step in the failed call; the failed one did not.)"""
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, **KWARGS)
    envs.reset(seed=0)
    bad = np.zeros((2, 5), np.float32)
    bad[0, 0] = np.nan
    with pytest.raises(InvalidInputError, match="environment 0"):
        envs.step(bad)
    obs = envs.step(np.full((2, 5), 0.3, np.float32))[0]
    assert obs["touches"][:, 0].tolist() == [1.0, 2.0]
    envs.close()


def test_a_dead_worker_is_reported() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 2, workers=2, **KWARGS)
    envs.reset(seed=0)
    envs._shards[1].process.kill()
    envs._shards[1].process.join()
    with pytest.raises(VectorEnvError, match="worker 1 died"):
        envs.step(np.zeros((2, 5), np.float32))
    envs.close()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"num_envs": 0}, "num_envs"),
        ({"num_envs": 2, "workers": -1}, "workers"),
        ({"num_envs": 2, "autoreset_mode": "sometimes"}, "autoreset_mode"),
        ({"num_envs": 2, "context": "teleport"}, "context"),
        ({"num_envs": 2, "draw_ahead": "yes"}, "draw_ahead"),
        ({"num_envs": 2, "batch_scheduling": 1}, "batch_scheduling"),
        ({"num_envs": 2, "touch_budget": 0}, "environment 0: .*touch_budget"),
        ({"num_envs": 2, "workers": 0, "touch_budget": 0}, "environment 0: .*touch_budget"),
    ],
)
def test_bad_settings_raise_clear_errors(kwargs: dict, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match):
        HapticVectorEnv(HAPTIC_EXPLORE_ID, **(KWARGS | kwargs))


def test_compact_id_vectorises_natively() -> None:
    envs = gym.make_vec(HAPTIC_EXPLORE_COMPACT_ID, num_envs=2, workers=0, **KWARGS)
    assert isinstance(envs, HapticVectorEnv)
    obs, _ = envs.reset(seed=0)
    assert obs.shape == (2, 85)
    obs, reward, *_ = envs.step(envs.action_space.sample())
    assert obs.shape == (2, 85) and reward.shape == (2,)
    envs.close()


def test_each_environment_gives_what_it_gives_alone() -> None:
    """Environment 1 of a native batch against the same environment made and stepped alone
    (seed 3 + 1, the same actions, a reset without seed after its episode ends)."""
    rng = np.random.default_rng(2)
    actions = rng.uniform(-1, 1, (7, 3, 5)).astype(np.float32)
    envs = gym.make_vec(HAPTIC_EXPLORE_ID, 3, workers=2, **KWARGS)
    batch = [envs.reset(seed=3)[0]["points"][1]]
    batch += [envs.step(a)[0]["points"][1] for a in actions]
    envs.close()
    env = gym.make(HAPTIC_EXPLORE_ID, **KWARGS)
    alone = [env.reset(seed=4)[0]["points"]]
    done = False
    for a in actions:
        if done:  # NEXT_STEP autoreset: this step's action is not used
            obs, _ = env.reset()
            done = False
        else:
            obs, _, terminated, truncated, _ = env.step(a[1])
            done = terminated or truncated
        alone.append(obs["points"])
    env.close()
    for x, y in zip(batch, alone, strict=True):
        np.testing.assert_array_equal(x, y)


def test_schedule_estimates_by_hand() -> None:
    """Two shards of two environments; the first shard's two steps each have an 8 s full fit."""
    from lab.benchmarks.env import schedule_estimates

    parts = {
        "step": np.array([[10.0], [10.0], [2.0], [2.0]]),
        "touch": np.ones((4, 1)),
        "fit": np.array([[8.0], [8.0], [0.5], [0.5]]),
        "full": np.array([[True], [True], [False], [False]]),
    }
    # static: shard 0 takes 20 s against an ideal 12 s
    # sharing: shard 0 touches twice (2 s) and fits env 0 (10 s), shard 1 finishes its own steps
    # (4 s) and fits env 1 (12 s); env 1's metrics then wait for it: 13 s
    # whole steps: 10 + 2 on each core
    got = schedule_estimates(parts, shards=2, job_cost=0.0)
    assert got["static"] == pytest.approx(12 / 20)
    assert got["fit_sharing_full"] == pytest.approx(12 / 13)
    # every fit pooled: shard 1 fits its own two (3 s), then env 0's (11 s), and all finish by 12
    assert got["fit_sharing_all"] == pytest.approx(1.0)
    assert got["whole_steps"] == pytest.approx(1.0)
    # a message costs 0.5 s: shard 0 is handed its fit (10.5 s), shard 1 is handed env 1's and
    # sends it back (4 + 8 + 1.5 = 13.5 s); env 1 finishes at 14.5 s
    assert schedule_estimates(parts, 2, 0.5)["fit_sharing_full"] == pytest.approx(12 / 14.5)


def test_a_starved_helper_is_not_asked_more_than_it_can_hold() -> None:
    """A helper that never runs (a machine busy with other work) gets at most two requests per
    environment: the worker's sends never fill its pipe, so they never block the worker."""
    import multiprocessing

    from hapticsim.envs.vector_worker import Shard

    worker_end, helper_end = multiprocessing.Pipe()
    shard = Shard(HAPTIC_EXPLORE_ID, KWARGS | {"touch_budget": 1}, 2, AutoresetMode.NEXT_STEP,
                   helper=worker_end)  # fmt: skip
    shard.make()
    shard.reset([0, 1], None, [True, True])
    for _ in range(30):  # 15 resets per environment
        shard.step([np.zeros(5, np.float32)] * 2)
    messages = []
    while helper_end.poll():
        messages.append(helper_end.recv())
    assert [m[0] for m in messages] == ["drawers"] + ["draw"] * 4
    helper_end.send((0, None))  # one answer frees one request
    shard.step([np.zeros(5, np.float32)] * 2)
    shard.step([np.zeros(5, np.float32)] * 2)
    assert helper_end.poll() and helper_end.recv()[0] == "draw" and not helper_end.poll()
    shard.close()
