"""Minimisation quality theta (paper eq. 10, SPEC §4)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data.bodies import get_body
from hapticsim.data.synthetic import paper_dataset
from hapticsim.errors import HapticsimError
from hapticsim.geometry.eof import error_of_fit
from hapticsim.metrics import theta
from tests.core_helpers import random_rigid


def _eof(sq, points, normals, lam=0.5) -> float:
    return float(error_of_fit(points, normals, sq.a, sq.eps, sq.taper, sq.rotation, sq.center, lam))


def test_theta_known_answers() -> None:
    truth = get_body("tapered_box")
    clean = paper_dataset(truth, noise=0.0, rng=0)
    assert theta(truth, truth, clean.points, clean.normals) == pytest.approx(0.0, abs=1e-24)
    noisy = paper_dataset(truth, noise=0.1, rng=0)
    d = _eof(truth, noisy.points, noisy.normals)
    assert d > 0
    assert theta(truth, truth, noisy.points, noisy.normals) == pytest.approx(d / (d + 1))
    estimate = truth.replace(a=truth.a * 1.1)
    de = _eof(estimate, noisy.points, noisy.normals)
    assert theta(estimate, truth, noisy.points, noisy.normals) == pytest.approx(de / (d + 1))
    # Without normals: theta^(1) over D^(1) = mean(D1^2).
    d1 = _eof(truth, noisy.points, None)
    de1 = _eof(estimate, noisy.points, None)
    assert theta(estimate, truth, noisy.points) == pytest.approx(de1 / (d1 + 1))
    # lambda weights the normal term only.
    assert theta(estimate, truth, noisy.points, noisy.normals, lam=0.0) == pytest.approx(
        de1 / (d1 + 1)
    )


def test_theta_is_invariant_under_rigid_transforms() -> None:
    truth = get_body("cylinder")
    estimate = truth.replace(eps=(0.3, 0.8), center=(0.001, 0.0, 0.002))
    data = paper_dataset(truth, noise=0.1, rng=1)
    rot, shift = random_rigid(np.random.default_rng(2))
    a = theta(estimate, truth, data.points, data.normals)
    b = theta(
        estimate.transformed(rot, shift),
        truth.transformed(rot, shift),
        data.points @ rot.T + shift,
        data.normals @ rot.T,
    )
    assert b == pytest.approx(a, rel=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"estimate": None}, "estimate"),
        ({"truth": "cube"}, "truth"),
        ({"points": np.zeros((5, 2))}, "points"),
        ({"points": np.zeros((0, 3)), "normals": None}, "points"),
        ({"normals": np.ones((4, 3))}, "normals"),
        ({"lam": -1.0}, "lam"),
        ({"lam": float("nan")}, "lam"),
    ],
)
def test_bad_input_raises_naming_the_argument(kwargs: dict, name: str) -> None:
    truth = get_body("cube")
    args = {"estimate": truth, "truth": truth, "points": np.zeros((5, 3))}
    args |= {"normals": np.eye(3)[[0, 1, 2, 0, 1]], "lam": 0.5} | kwargs
    with pytest.raises(HapticsimError, match=f"`{name}`"):
        theta(**args)
