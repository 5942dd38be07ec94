"""The one exploration pipeline: a trial validated once, its seeds, its record."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.data.objects import ObjectSpec
from hapticsim.errors import InvalidInputError
from hapticsim.exploration import Trial, TrialHooks, TrialSeeds, run_trial


def test_a_trial_checks_itself_once_when_made() -> None:
    trial = Trial("ellipsoid", explorer="patch", count=25, noise=0.05, estimator="nLS", seed=2)
    assert isinstance(trial.object, ObjectSpec) and trial.name == "ellipsoid"
    assert Trial(get_body("cube")).name == "superquadric"
    bad = [
        ({"object": 3.5}, "`object` must be"),
        ({"object": "no_such_body"}, "no_such_body"),
        ({"explorer": "zigzag"}, "`strategy` must be one of"),
        ({"estimator": "nHH"}, "`method` must be one of"),
        ({"noise": -0.1}, "noise"),
        ({"noise": float("nan")}, "noise"),
        ({"seed": -1}, "seed"),
        ({"count": 5}, "count"),
        ({"scene": "hapticsim"}, "`scene` must be a SceneConfig"),
    ]
    for kwargs, match in bad:
        with pytest.raises(InvalidInputError, match=match):
            Trial(**kwargs)


def test_seeds_are_derived_in_one_place_and_streams_are_independent() -> None:
    a, b = TrialSeeds.from_seed(7), TrialSeeds.from_seed(7)
    draws = {s: a.generator(s).random(4) for s in ("object", "sim", "noise", "fit", "score")}
    for stream, values in draws.items():  # the same seed, the same streams
        np.testing.assert_array_equal(values, b.generator(stream).random(4))
    assert len({tuple(v) for v in draws.values()}) == 5  # five different streams
    # explore's scheme: SeedSequence(seed).spawn(4) = sim, noise, fit (a 32-bit int), object;
    # the score is seeded by the seed itself (metrics.json states it)
    children = np.random.SeedSequence(7).spawn(4)
    np.testing.assert_array_equal(draws["sim"], np.random.default_rng(children[0]).random(4))
    assert a.fit == int(children[2].generate_state(1)[0]) and a.rng("score") == 7
    # a suite case's: the data seed gives (object), sim and noise, the case seed fit and score
    data, case = np.random.SeedSequence(1), np.random.SeedSequence(2)
    shaped = TrialSeeds.from_case(np.random.SeedSequence(1), np.random.SeedSequence(2), True)
    plain = TrialSeeds.from_case(data, case, False)
    assert shaped.noise.spawn_key == (2,) and plain.noise.spawn_key == (1,)
    assert isinstance(plain.rng("fit"), np.random.Generator)


def test_a_trial_runs_explore_estimate_score_and_says_what_it_does() -> None:
    said: list[str] = []
    counts: list[int] = []
    trial = Trial("cube", explorer="patch", count=30, noise=0.02, estimator="nLS", seed=4)
    hooks = TrialHooks(progress=counts.append, status=said.append)
    record = run_trial(trial, hooks=hooks)
    again = run_trial(trial)
    assert said == ["fitting", "scoring"] and counts and counts[-1] <= 30
    run = record.exploration
    assert run.count == len(record.points) == len(record.normals)
    # noise is added to the clean contacts: sigma_N * mean(a) per coordinate
    moved = np.linalg.norm(record.points - run.arrays["points_clean"], axis=1)
    assert 0 < np.median(moved) < 5 * 0.02 * record.truth.size * np.sqrt(3)
    assert record.fit is not None and record.estimate is record.fit.solid
    m = record.metrics()
    assert m["epsilon"] == pytest.approx(m["alpha"] + m["beta"]) and 0 <= m["iou"] <= 1
    assert m["theta"] is not None and m["eof"] is not None and "parts" not in m
    # the same trial, the same record, bit for bit
    np.testing.assert_array_equal(record.points, again.points)
    assert record.metrics() == again.metrics() and record.fit.to_dict()["superquadric"] == (
        again.fit.to_dict()["superquadric"]
    )


def test_a_plug_in_fitter_replaces_the_estimator_and_is_scored_alike() -> None:
    truth = get_body("cube")
    calls = []

    def fitter(points: np.ndarray, normals: np.ndarray) -> object:
        calls.append(len(points))
        return truth  # a perfect estimator

    trial = Trial(truth, explorer="patch", count=25, estimator="nH", seed=1)
    record = run_trial(trial, fitter=fitter)
    assert calls == [record.exploration.count] and record.fit is None
    assert record.fit_info["fitter"] is None and record.metrics()["epsilon"] < 0.01
