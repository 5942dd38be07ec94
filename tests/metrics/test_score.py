"""The Score value and score() (SPEC §4, §6)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.errors import HapticsimError
from hapticsim.geometry import Superquadric
from hapticsim.metrics import Score, score, volume_overlap
from tests.metrics.test_volume import _pair

SPEC_KEYS = {"alpha", "beta", "epsilon", "iou", "chamfer"}


def test_score_dict_has_the_spec_keys_and_the_method() -> None:
    estimate, truth = _pair()
    s = score(estimate, truth)
    d = s.to_dict()
    assert set(d) == SPEC_KEYS | {"volume_method"}
    assert json.loads(json.dumps(d)) == d
    assert d["epsilon"] == d["alpha"] + d["beta"] == s.epsilon
    assert "Monte Carlo" in d["volume_method"] and "seed 0" in d["volume_method"]
    assert "100000" in d["volume_method"]
    # The volume part is volume_overlap with the same generator, drawn first.
    v = volume_overlap(estimate, truth, rng=0)
    assert (s.alpha, s.beta, s.iou) == (v.alpha, v.beta, v.iou)
    assert 0.001 < s.chamfer < 0.01  # a few millimetres apart (measured 4.0 mm)


def test_identical_shapes() -> None:
    _, truth = _pair()
    s = score(truth, truth)
    assert (s.alpha, s.beta, s.epsilon, s.iou) == (0.0, 0.0, 0.0, 1.0)
    assert s.chamfer < 1e-4  # measured 4.9e-5 m


def test_same_seed_same_score_and_invariance_under_rigid_motion() -> None:
    estimate, truth = _pair()
    small = {"volume_samples": 20_000, "chamfer_samples": 1000}
    assert score(estimate, truth, rng=5, **small) == score(estimate, truth, rng=5, **small)
    gen_a, gen_b = np.random.default_rng(5), np.random.default_rng(5)
    assert score(estimate, truth, gen_a, **small) == score(estimate, truth, gen_b, **small)
    assert "Generator" in score(estimate, truth, np.random.default_rng(1), **small).volume_method
    rng = np.random.default_rng(6)
    rot = Superquadric.from_vector(np.r_[1, 1, 1, 1, 1, 0, 0, rng.normal(size=3), 0, 0, 0])
    shift = rng.normal(0, 0.3, 3)
    a = score(estimate, truth, rng=7)
    b = score(
        estimate.transformed(rot.rotation, shift), truth.transformed(rot.rotation, shift), rng=7
    )
    # Measured: identical alpha and beta, chamfer equal to 2e-15 relative.
    assert abs(a.alpha - b.alpha) <= 1e-4 and abs(a.beta - b.beta) <= 1e-4
    assert b.chamfer == pytest.approx(a.chamfer, rel=1e-6)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"alpha": 1.5}, "alpha"),
        ({"beta": -0.1}, "beta"),
        ({"iou": float("nan")}, "iou"),
        ({"chamfer": -1.0}, "chamfer"),
        ({"chamfer": "far"}, "chamfer"),
        ({"volume_method": 3}, "volume_method"),
    ],
)
def test_score_value_validates_itself(kwargs: dict, name: str) -> None:
    args = {"alpha": 0.1, "beta": 0.2, "iou": 0.7, "chamfer": 0.001, "volume_method": "mc"}
    with pytest.raises(HapticsimError, match=f"`{name}`"):
        Score(**(args | kwargs))


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"estimate": {"a": [1, 1, 1]}}, "estimate"),
        ({"truth": None}, "truth"),
        ({"rng": -2}, "rng"),
        ({"volume_samples": 0}, "volume_samples"),
        ({"chamfer_samples": 2.0}, "chamfer_samples"),
    ],
)
def test_bad_input_raises_naming_the_argument(kwargs: dict, name: str) -> None:
    estimate, truth = _pair()
    with pytest.raises(HapticsimError, match=f"`{name}`"):
        score(**({"estimate": estimate, "truth": truth} | kwargs))
