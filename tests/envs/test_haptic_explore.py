"""HapticExplore-v0: Gymnasium contract, determinism, robustness, observation and rewards."""

from __future__ import annotations

import copy
import dataclasses
import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig, HapticExploreEnv
from hapticsim.envs.observation import decode_fit, encode_fit
from hapticsim.envs.registration import HAPTIC_EXPLORE_ID
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.metrics.coverage import coverage_uncertainty

#: Small fit budgets keep the tests fast; the contract does not depend on them.
FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)


def make(**kwargs: object) -> HapticExploreEnv:
    kwargs.setdefault("backend", "analytic")
    kwargs.setdefault("fit", FAST_FIT)
    return HapticExploreEnv(**kwargs)  # type: ignore[arg-type]


def test_check_env_passes_on_the_default_analytic_configuration() -> None:
    env = gym.make(HAPTIC_EXPLORE_ID, backend="analytic")
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def _rollout(seed: int, steps: int, action_seed: int = 0) -> list[tuple]:
    env = make(objects="random_tapered", noise=0.05)
    actions = np.random.default_rng(action_seed).uniform(-1, 1, (steps, 5)).astype(np.float32)
    obs, info = env.reset(seed=seed)
    out = [(obs, 0.0, info["epsilon"], info["truth"])]
    for a in actions:
        obs, reward, terminated, truncated, info = env.step(a)
        out.append((obs, reward, info["epsilon"], info["estimate"]))
    env.close()
    return out


def test_seeded_resets_give_identical_episodes() -> None:
    first = _rollout(seed=11, steps=8)
    second = _rollout(seed=11, steps=8)
    for (o1, r1, e1, s1), (o2, r2, e2, s2) in zip(first, second, strict=True):
        for key in o1:
            np.testing.assert_array_equal(o1[key], o2[key], err_msg=key)
        assert r1 == r2 and e1 == e2 and s1 == s2
    # A different seed draws another object (and noise).
    other = _rollout(seed=12, steps=1)
    assert other[0][3] != first[0][3]


def test_reset_observation_holds_no_information_and_no_ground_truth() -> None:
    env = make(objects="random_tapered")
    obs, info = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    assert not obs["mask"].any() and not obs["fit_valid"].any()
    for key in ("points", "normals", "fit", "eof", "touches"):
        assert not np.any(obs[key]), key
    # The truth is in info (privileged), never in the observation's keys.
    assert isinstance(info["truth"], Superquadric)
    assert set(obs) == {"points", "normals", "mask", "fit", "fit_valid", "eof", "touches"}


def test_no_fit_below_13_contacts_then_a_valid_fit() -> None:
    env = make(objects="paper")
    env.reset(seed=0)
    probe = np.array([0.0, 0.3, 0.0, -1.0, 0.0], np.float32)  # one contact per probe
    for k in range(1, 14):
        obs, reward, _, _, info = env.step(probe)
        assert info["n_contacts"] == k
        if k < 13:
            assert info["fit_status"] == "too_few_contacts" and obs["fit_valid"][0] == 0
            assert reward == 0.0 and info["epsilon"] == 1.0 and info["estimate"] is None
    assert info["fit_status"] == "full" and obs["fit_valid"][0] == 1
    assert isinstance(info["estimate"], Superquadric)


def _random_steps(env: HapticExploreEnv, steps: int, episode_length: int) -> None:
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    episodes, statuses, fits = 0, set(), set()
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs)
        assert all(np.all(np.isfinite(v)) for v in obs.values())
        assert np.isfinite(reward) and np.isfinite(info["epsilon"])
        statuses.add(info["touch_status"])
        fits.add(info["fit_status"])
        if terminated or truncated:
            episodes += 1
            obs, _ = env.reset()
    assert episodes == steps // episode_length
    assert {"ok", "blocked"} <= statuses
    assert {"too_few_contacts", "full", "refine", "kept"} <= fits


def test_one_thousand_random_steps_without_nan_or_exceptions() -> None:
    # The contract does not depend on the fit's budget: cheap least-squares fits and no scoring
    # keep 1,000 steps fast (measured 0.04 s of CPU per step on a loaded 2-core machine). The
    # slow test below runs the default settings.
    cheap = FitSchedule(
        method="nLS", full_budget=100, refine_budget=50, full_every=100, surprise=float("inf")
    )
    env = make(
        objects="random_tapered", noise=0.1, touch_budget=10, reward="eof",
        compute_metrics=False, fit=cheap,
    )  # fmt: skip
    _random_steps(env, 1000, 10)


@pytest.mark.slow
def test_one_thousand_random_steps_with_the_default_settings() -> None:
    env = HapticExploreEnv(backend="analytic", objects="random_tapered", noise=0.1)
    _random_steps(env, 1000, 20)


def test_truncation_at_the_budget_and_termination_at_a_target() -> None:
    env = make(touch_budget=3)
    env.reset(seed=0)
    flags = [env.step(env.action_space.sample())[2:4] for _ in range(3)]
    assert flags == [(False, False), (False, False), (False, True)]
    env = make(target_epsilon=2.0)  # any estimate reaches it
    env.reset(seed=0)
    stroke = np.array([0.0, 0.3, 0.5, 1.0, 0.0], np.float32)
    terminated = False
    for _ in range(3):
        _, _, terminated, _, info = env.step(stroke)
        if info["estimate"] is not None:
            break
    assert terminated


@pytest.mark.parametrize("reward", ["epsilon", "uncertainty", "eof"])
def test_rewards_telescope(reward: str) -> None:
    env = make(reward=reward, objects="random")
    env.reset(seed=5)
    stroke = np.array([0.0, 0.3, 0.5, 1.0, 0.0], np.float32)
    total = 0.0
    for k in range(6):
        stroke[0] = k / 3.0 - 1.0  # around the object
        _, r, _, _, info = env.step(stroke)
        total += r
    if reward == "epsilon":
        assert total == pytest.approx(1.0 - info["epsilon"], abs=1e-9)
    elif reward == "uncertainty":
        assert total == pytest.approx(1.0 - info["uncertainty"], abs=1e-9)
    else:
        est = info["estimate"]
        e = 1.0 if est is None else min(1.0, np.sqrt(info["fit_eof"]) / np.mean(est.a))
        assert total == pytest.approx(1.0 - e, abs=1e-9)


def _independent_epsilon(estimate: Superquadric | None, truth: Superquadric) -> float:
    """epsilon scored apart from the environment: 60 000 Monte Carlo samples of another seed
    (standard error <= 0.002) against the truth; 1 before the first fit, as the env defines."""
    from hapticsim.metrics import volume_overlap

    if estimate is None:
        return 1.0
    overlap = volume_overlap(estimate, truth, samples=60_000, rng=123)
    return float(overlap.alpha + overlap.beta)


def independent_epsilon_run(seed: int = 1, touches: int = 12) -> dict[str, list[float]]:
    """An uncertainty-policy episode on the paper bodies: per step the env's ``epsilon``, the
    independently scored epsilon of ``info["estimate"]``, the reward, and the ratio of the
    SPEC §2 EOF of the estimate on all contacts to ``info["fit_eof"]`` (scripts/measure_bounds)."""
    from hapticsim.envs.policies import UncertaintyPolicy
    from hapticsim.geometry.eof import error_of_fit

    env = make(objects="paper", touch_budget=touches)
    policy = UncertaintyPolicy(env, rng=0)
    obs, info = env.reset(seed=seed)
    policy.reset(0)
    rows: dict[str, list[float]] = {"env": [], "independent": [], "reward": [], "eof_ratio": []}
    done = False
    while not done:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        done = terminated or truncated
        est = info["estimate"]
        rows["env"].append(round(float(info["epsilon"]), 4))
        rows["independent"].append(round(_independent_epsilon(est, info["truth"]), 4))
        rows["reward"].append(float(reward))
        if est is not None:
            c = env.contacts
            spec = error_of_fit(c.points, c.normals, est.a, est.eps, est.taper, est.rotation,
                                est.center)  # fmt: skip
            rows["eof_ratio"].append(float(spec) / info["fit_eof"])
    env.close()
    return rows


def policy_epsilon_curve(seed: int) -> list[float]:
    """Independently scored epsilon after each touch of an uncertainty-policy episode."""
    return independent_epsilon_run(seed)["independent"]


def test_reward_and_epsilon_agree_with_an_independent_score() -> None:
    rows = independent_epsilon_run()
    env_eps, indep = np.array(rows["env"]), np.array(rows["independent"])
    # Measured (seeds 0-4, 12 touches): |env - independent| <= 0.011 (the env's 10 000 samples
    # have a standard error <= 0.005); the limit 0.03 fails a score of anything else.
    assert np.max(np.abs(env_eps - indep)) < 0.03
    # each reward is the drop of epsilon, here of the independent score (measured: within
    # 0.011; two scores' errors add up to 0.022 at most)
    drops = -np.diff(np.r_[1.0, indep])
    assert np.max(np.abs(np.array(rows["reward"]) - drops)) < 0.04
    # info["fit_eof"] is the SPEC §2 EOF of the estimate on every contact (measured ratio 1.0)
    assert rows["eof_ratio"] and np.allclose(rows["eof_ratio"], 1.0, rtol=1e-9)


def test_a_sensible_policy_lowers_epsilon_over_an_episode() -> None:
    # Over twelve episodes, not one: a CPU that rounds numpy's and BLAS's routines differently
    # sends an episode down another path, and one episode of twelve may end high (seed 3 ends
    # at 0.104 on an AMD Zen 4 core and with an AVX2 machine's targets, at 0.016 with only the
    # BLAS kernel and numba's target set to Haswell). Measured (uncertainty policy, analytic
    # backend, paper bodies, seeds 0-11, 12 touches) natively on Zen 4 / with NUMBA_CPU_NAME=
    # haswell OPENBLAS_CORETYPE=Haswell / with NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL" too:
    # median epsilon after 12 touches 0.019 / 0.020 / 0.019, worst 0.104 / 0.029 / 0.104; at
    # least 11 of 12 episodes end below half their first fit. A fitter or simulation that loses
    # a millimetre scores ~0.1 in most episodes: the median's limit 0.05 fails it, and the count
    # allows two episodes of twelve to take a bad path on any CPU.
    finals, halved = [], 0
    for seed in range(12):
        curve = env_epsilon_curve(seed)
        fitted = [e for e in curve if e < 1.0]
        assert len(fitted) >= 8, (seed, curve)
        finals.append(curve[-1])
        halved += curve[-1] < 0.5 * fitted[0]
    assert np.median(finals) < 0.05, finals
    assert halved >= 10, finals


def env_epsilon_curve(seed: int, touches: int = 12) -> list[float]:
    """The environment's epsilon after each touch of an uncertainty-policy episode on the paper
    bodies (checked against an independent score by the test above)."""
    from hapticsim.envs.policies import UncertaintyPolicy

    env = make(objects="paper", touch_budget=touches)
    policy = UncertaintyPolicy(env, rng=0)
    obs, info = env.reset(seed=seed)
    policy.reset(0)
    curve, done = [], False
    while not done:
        obs, _, terminated, truncated, info = env.step(policy(obs))
        done = terminated or truncated
        curve.append(float(info["epsilon"]))
    env.close()
    return curve


def test_fit_encoding_round_trip() -> None:
    origin = np.array([0.01, -0.02, 0.3])
    sq = Superquadric(
        a=(0.02, 0.03, 0.05), eps=(0.3, 1.2), taper=(0.2, -0.1),
        rotation=np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]), center=(0.015, -0.02, 0.31),
    )  # fmt: skip
    enc = encode_fit(sq, origin, 0.1)
    assert enc.dtype == np.float32 and enc.shape == (13,)
    back = decode_fit(enc, 0.1)
    np.testing.assert_allclose(back.a, sq.a, rtol=1e-6)
    np.testing.assert_allclose(back.eps, sq.eps, rtol=1e-6)
    np.testing.assert_allclose(back.center + origin, sq.center, atol=1e-7)
    np.testing.assert_allclose(back.rotation, sq.rotation, atol=1e-6)
    assert not encode_fit(None, origin, 0.1).any()


def test_coverage_uncertainty_falls_as_contacts_cover_the_estimate() -> None:
    sq = Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0))
    assert coverage_uncertainty(None, np.zeros((0, 3))) == 1.0
    eta = np.linspace(-1.5, 1.5, 20).repeat(20)
    omega = np.tile(np.linspace(-np.pi, np.pi, 20), 20)
    dense = sq.surface(eta, omega)[0]
    one_side = dense[dense[:, 0] > 0.02]
    u_side, u_all = coverage_uncertainty(sq, one_side), coverage_uncertainty(sq, dense)
    assert 0.0 <= u_all < u_side < 1.0
    # Measured: u_all 0.082, u_side 0.667 (a tenth of the points, all on one side); no
    # randomness, so the limit guards a change of the coverage measure, not noise
    assert u_all < 0.1


def test_render_rgb_array() -> None:
    env = make(render_mode="rgb_array", width=160, height=120)
    env.reset(seed=0)
    for _ in range(4):
        env.step(np.array([0.2, 0.5, 0.5, 1.0, 0.0], np.float32))
    img = env.render()
    assert img is not None and img.shape == (120, 160, 3) and img.dtype == np.uint8
    assert img.std() > 5  # a picture, not a blank frame
    env.close()


def test_invalid_configuration_lists_the_choices() -> None:
    with pytest.raises(InvalidInputError, match="mujoco"):
        HapticExploreConfig(backend="bullet")
    with pytest.raises(InvalidInputError, match="uncertainty"):
        HapticExploreConfig(reward="score")
    with pytest.raises(InvalidInputError, match="random_tapered"):
        HapticExploreConfig(objects="sphere")
    with pytest.raises(InvalidInputError, match="touch_budget"):
        HapticExploreConfig(touch_budget=0)
    with pytest.raises(InvalidInputError, match="render_mode"):
        HapticExploreEnv(render_mode="human", backend="analytic")
    env = make()
    with pytest.raises(InvalidInputError, match="reset"):
        env.step(env.action_space.sample())
    with pytest.raises(InvalidInputError, match="action"):
        env.reset(seed=0)
        env.step(np.zeros(3, np.float32))


def test_reset_with_a_given_shape() -> None:
    env = make()
    shape = Superquadric(a=(0.02, 0.03, 0.04), eps=(0.5, 0.5), center=(0.0, 0.0, 0.1))
    _, info = env.reset(seed=0, options={"shape": shape})
    assert info["truth"] == shape
    np.testing.assert_allclose(info["origin"], shape.center, atol=0.03)


def test_the_fitter_draws_from_a_stream_of_its_own() -> None:
    # A schedule that never fits draws no fitter seeds, the default draws one per fit; the
    # object, rough position and (noisy) contacts of an estimate-blind policy must not notice,
    # so that two fitters can be compared on the same contacts (scripts/paired_fitters.py).
    from hapticsim.envs.episodes import run_episode
    from hapticsim.envs.policies import make_policy

    runs = []
    for schedule in (FitSchedule(), FitSchedule(min_contacts=10**6)):
        env = HapticExploreEnv(backend="analytic", objects="random", touch_budget=8, fit=schedule)
        record = run_episode(env, make_policy("random", env, rng=3), seed=3, policy_seed=3)
        runs.append((env.truth, env.origin.copy(), env.contacts.points.copy(), record))
        env.close()
    (truth_a, origin_a, points_a, rec_a), (truth_b, origin_b, points_b, rec_b) = runs
    assert truth_a == truth_b
    assert np.array_equal(origin_a, origin_b) and np.array_equal(points_a, points_b)
    assert len(points_a) > 13  # enough contacts for fits to have run
    assert not np.array_equal(rec_a.epsilon, rec_b.epsilon)  # the fits themselves differ


def test_the_next_object_does_not_depend_on_the_last_episode() -> None:
    # The sensor draws from a stream of its own too: the objects of a seeded run's later
    # episodes (autoresets without seed) are the same whatever the policy touched, and however
    # many noisy contacts that made.
    truths = []
    for action_seed in (0, 1):
        env = make(objects="random", noise=0.05, touch_budget=3)
        rng = np.random.default_rng(action_seed)
        env.reset(seed=11)
        seen = []
        for _ in range(3):
            for _ in range(3):
                env.step(rng.uniform(-1, 1, 5).astype(np.float32))
            seen.append((len(env.contacts.points), env.truth))
            env.reset()
        seen.append((0, env.truth))
        truths.append(seen)
        env.close()
    assert [t for _, t in truths[0]] == [t for _, t in truths[1]]
    assert [n for n, _ in truths[0]] != [n for n, _ in truths[1]]  # the episodes differed


def _episode(env: HapticExploreEnv, seed: int | None, actions: np.ndarray) -> list[object]:
    obs, info = env.reset(seed=seed)
    out: list[object] = [obs, info["truth"], info["origin"]]
    for a in actions:
        obs, reward, *_ = env.step(a)
        out += [obs, reward]
    return out


@pytest.mark.parametrize("objects", ["paper", "random"])
def test_a_draw_made_ahead_gives_the_same_episode(objects: str) -> None:
    actions = np.random.default_rng(5).uniform(-1, 1, (4, 5)).astype(np.float32)
    runs, used = [], []
    for ahead in (False, True):
        env = make(objects=objects, noise=0.05)
        _episode(env, 8, actions)
        if ahead:  # drawn from a copy, packed and sent as to another process
            draw = env.drawer.draw(copy.deepcopy(env.np_random))
            env.offer_draw(pickle.loads(pickle.dumps(env.drawer.pack(draw))))
        runs.append(_episode(env, None, actions))
        used.append(env.resets_drawn_ahead)
        env.close()
    assert used == [0, 1]
    for x, y in zip(*runs, strict=True):
        if isinstance(x, dict):
            for k in x:
                np.testing.assert_array_equal(x[k], y[k], err_msg=k)
        else:
            assert np.array_equal(x, y) if isinstance(x, np.ndarray) else x == y


def test_a_draw_from_elsewhere_is_ignored() -> None:
    env = make()
    env.reset(seed=0)
    stale = env.drawer.draw(copy.deepcopy(env.np_random))
    env.reset()  # the generator has moved on
    expected = env.drawer.draw(copy.deepcopy(env.np_random))
    env.offer_draw(stale)
    _, info = env.reset()
    assert env.resets_drawn_ahead == 0 and info["truth"] is expected.shape
    env.offer_draw(env.drawer.draw(copy.deepcopy(env.np_random)))
    env.reset(seed=3)  # seeded elsewhere: its own draws
    assert env.resets_drawn_ahead == 0
    with pytest.raises(InvalidInputError, match="EpisodeDraw"):
        env.offer_draw("draw")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="index below 4"):
        env.offer_draw(dataclasses.replace(expected, shape=7))


def test_fixed_solids_pack_to_their_index() -> None:
    from hapticsim.data.bodies import BODY_NAMES, get_body
    from hapticsim.data.distributions import ObjectDistribution, ObjectSet

    assert ObjectDistribution("paper").fixed_solids() == tuple(get_body(b) for b in BODY_NAMES)
    assert ObjectDistribution("paper", yaw_range=0.5).fixed_solids() == ()
    assert ObjectDistribution("random").fixed_solids() == ()
    box = Superquadric(a=(0.02, 0.03, 0.04), eps=(0.5, 0.5), center=(0.0, 0.0, 0.1))
    assert ObjectSet(("cube", "random", box)).fixed_solids()[1] is box
    env = make(objects=["random", box])
    env.reset(seed=0)
    kinds = set()
    for _ in range(8):
        draw = env.drawer.draw(copy.deepcopy(env.np_random))
        packed = env.drawer.pack(draw)
        kinds.add(draw.shape is box)
        restored = env.drawer.unpack(pickle.loads(pickle.dumps(packed))).shape
        if draw.shape is box:  # sent as its index, back as the same instance
            assert packed.shape == 0 and restored is box
        else:  # sent whole
            assert packed.shape is draw.shape and restored == draw.shape
        env.reset()
    assert kinds == {True, False}  # both the fixed box and random shapes came up
    env.close()
