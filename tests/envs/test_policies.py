"""Baseline policies: valid actions, determinism, the behaviour each one promises."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.envs.episodes import run_episode, summarize
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.envs.policies import (
    PAPER_PATTERN,
    POLICY_NAMES,
    UncertaintyPolicy,
    make_policy,
)
from hapticsim.envs.touch import decode_action
from hapticsim.errors import InvalidInputError

FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)


def make(**kwargs: object) -> HapticExploreEnv:
    kwargs.setdefault("fit", FAST_FIT)
    return HapticExploreEnv(backend="analytic", **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize("name", POLICY_NAMES)
def test_policies_act_in_the_action_space_and_are_seeded(name: str) -> None:
    env = make(touch_budget=6)
    records = []
    for _ in range(2):
        policy = make_policy(name, env)
        records.append(run_episode(env, policy, seed=4))
    assert len(records[0].epsilon) == 6
    np.testing.assert_array_equal(records[0].epsilon, records[1].epsilon)
    np.testing.assert_array_equal(records[0].n_contacts, records[1].n_contacts)
    obs, _ = env.reset(seed=0)
    assert env.action_space.contains(make_policy(name, env, rng=0)(obs))


def test_make_policy_lists_the_choices() -> None:
    with pytest.raises(InvalidInputError, match="uncertainty"):
        make_policy("greedy", make())


def test_paper_policy_follows_the_pattern() -> None:
    env = make()
    policy = make_policy("paper", env)
    obs, _ = env.reset(seed=0)
    policy.reset(0)
    for az, el, _psi, frac, finger in PAPER_PATTERN[:5]:
        touch = decode_action(policy(obs), env.config.max_stroke, 1e-6, env.n_fingers)
        expect = np.radians([az, el])
        assert np.degrees(np.arctan2(touch.approach[1], touch.approach[0])) == pytest.approx(
            az, abs=1e-3
        )
        assert np.arcsin(touch.approach[2]) == pytest.approx(expect[1], abs=1e-5)
        assert touch.finger == finger
        assert touch.stroke_length == pytest.approx(frac * env.config.max_stroke, abs=1e-6)
        obs, *_ = env.step(policy(obs))


def test_uncertainty_policy_touches_away_from_the_contacts() -> None:
    env = make(objects="paper")
    policy = UncertaintyPolicy(env, rng=0)
    obs, _ = env.reset(seed=1)
    policy.reset(0)
    approaches = []
    for _ in range(6):
        action = policy(obs)
        approaches.append(decode_action(action, 0.05, 0.005, env.n_fingers).approach)
        obs, *_ = env.step(action)
    approaches = np.array(approaches)
    # Spread out: no two of the first six approaches within 30 degrees of each other
    # (measured: 41.7 deg at least here; 37.6-46.6 deg over reset seeds 1-3).
    cos = approaches @ approaches.T
    assert np.max(cos[~np.eye(6, dtype=bool)]) < np.cos(np.radians(30))


def test_summarize_pads_short_episodes() -> None:
    from hapticsim.envs.episodes import EpisodeRecord

    rec = EpisodeRecord(np.array([1.0, 0.5]), np.zeros(2), np.zeros(2, np.int64), np.zeros(2), 0.5)
    out = summarize([rec, rec], budget=4)
    np.testing.assert_array_equal(out["mean"], [1.0, 0.5, 0.5, 0.5])
    assert np.all(out["std"] == 0)


def test_comparison_runs_writes_and_reads_back(tmp_path) -> None:  # noqa: ANN001
    from hapticsim.envs.evaluation import compare_policies
    from lab.benchmarks.comparison import load_comparison, write_comparison

    cmp = compare_policies(
        ["random", "uncertainty"], ["paper"], episodes=2, workers=1, progress=False,
        backend="analytic", touch_budget=3, fit=FAST_FIT,
    )  # fmt: skip
    assert cmp.epsilon("random", "paper").shape == (2, 3)
    paths = write_comparison(cmp, tmp_path, "test")
    assert {p.name for p in paths.values()} == {
        "epsilon.csv",
        "epsilon.png",
        "README.md",
        "raw.json",
    }
    back = load_comparison(paths["json"])
    np.testing.assert_array_equal(
        back.epsilon("uncertainty", "paper"), cmp.epsilon("uncertainty", "paper")
    )
    assert "| 3 |" in paths["md"].read_text()


def test_information_policy_scores_by_the_posterior_once_fitted() -> None:
    from scipy.stats import spearmanr

    from hapticsim.envs.policies import InformationPolicy, observed_contacts

    env = make(objects="paper")
    correlations = []
    for seed in range(3):
        policy = InformationPolicy(env, rng=0)
        obs, _ = env.reset(seed=seed)
        policy.reset(0)
        while not (int(obs["fit_valid"][0]) and int(obs["mask"].sum()) >= 13):
            obs, *_ = env.step(policy(obs))
        contacts = observed_contacts(obs, env.config.obs_scale)
        estimate = policy._estimate(obs)
        candidates = policy._candidates(estimate).points
        policy.prepare(obs)
        surface = policy._score(candidates, contacts, estimate, obs)
        by_entropy = InformationPolicy(env, criterion="entropy")
        by_entropy.prepare(obs)
        entropy = by_entropy._score(candidates, contacts, estimate, obs)
        coverage = UncertaintyPolicy(env)._score(candidates, contacts, estimate, obs)
        assert np.all(surface >= 0) and np.all(entropy >= 0)
        correlations += [spearmanr(surface, coverage)[0], spearmanr(entropy, coverage)[0]]
    # Not the coverage gap in disguise: the posterior's scores rank the candidates otherwise.
    # A property of the scores, not of one state's best candidate (which two scores may share
    # on one CPU and not on another). Measured (seeds 0-5, Zen 4): Spearman correlations with the
    # coverage gap 0.11-0.86; a rescaled coverage gap would give 1.
    assert np.median(correlations) < 0.95 and max(correlations) < 0.99, correlations
    with pytest.raises(InvalidInputError, match="criterion"):
        InformationPolicy(env, criterion="volume")
