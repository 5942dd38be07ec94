"""The EOF as an objective: known values, residuals, counting and the budget."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.fitting.objective import BudgetExhausted, Objective
from hapticsim.geometry import Superquadric
from hapticsim.geometry.eof import error_of_fit


def _sphere_case() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    points = rng.normal(size=(20, 3)) * 0.05 + np.array([0.1, -0.2, 0.3])
    normals = rng.normal(size=(20, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    # A sphere of radius 0.04 at (0.1, -0.2, 0.3), rotated (a sphere does not care).
    vector = np.array([0.04, 0.04, 0.04, 1.0, 1.0, 0.0, 0.0, 0.3, -0.2, 0.5, 0.1, -0.2, 0.3])
    return points, normals, vector


def test_eof_of_a_sphere_matches_the_closed_form() -> None:
    points, normals, vector = _sphere_case()
    rel = points - vector[10:13]
    dist = np.linalg.norm(rel, axis=1)
    d1 = np.abs(dist - 0.04)  # radial distance to a sphere
    d2 = np.sum((normals - rel / dist[:, None]) ** 2, axis=1)  # the sphere's normal is radial
    expected = np.mean((d1 + 0.5 * 0.04 * d2) ** 2)
    objective = Objective(points, normals, lam=0.5, budget=10)
    assert objective.eof(vector[None])[0] == pytest.approx(expected, rel=1e-12)
    without = Objective(points, None, lam=0.5, budget=10)
    assert without.eof(vector[None])[0] == pytest.approx(np.mean(d1**2), rel=1e-12)


def test_residuals_square_sum_is_count_times_eof(box_contacts) -> None:
    truth, points, normals = box_contacts
    rng = np.random.default_rng(3)
    vectors = truth.to_vector() + rng.normal(0, 0.02, size=(9, 13)) * np.r_[[0.05] * 3, [1] * 10]
    objective = Objective(points, normals, lam=0.5, budget=100)
    r = objective.residuals(vectors)
    eof = objective.eof(vectors)
    np.testing.assert_allclose(np.sum(r**2, axis=1), len(points) * eof, rtol=1e-13)
    # The same numbers as the geometry's public EOF, vector by vector.
    for v, e in zip(vectors, eof, strict=True):
        sq = Superquadric.from_vector(v)
        ref = error_of_fit(points, normals, sq.a, sq.eps, sq.taper, sq.rotation, sq.center)
        assert e == pytest.approx(float(ref), rel=1e-10)


def test_counting_and_budget(box_contacts) -> None:
    truth, points, normals = box_contacts
    objective = Objective(points, normals, lam=0.5, budget=10)
    v = np.tile(truth.to_vector(), (4, 1))
    objective.eof(v)
    objective.residuals(v[:3])
    assert objective.evaluations == 7 and objective.remaining == 3
    with pytest.raises(BudgetExhausted):
        objective.eof(v)
    assert objective.evaluations == 7  # nothing evaluated past the budget
    evals, best = objective.history()
    assert evals.tolist() == [4, 7]
    assert best[-1] == objective.best_eof == pytest.approx(0.0, abs=1e-20)
    np.testing.assert_allclose(objective.best_vector, truth.to_vector())


def test_tapered_distance_is_the_world_distance_to_the_ray_point(box_contacts) -> None:
    truth, points, _ = box_contacts
    rng = np.random.default_rng(5)
    off = points + rng.normal(0, 0.005, size=points.shape)
    objective = Objective(off, None, lam=0.5, budget=1, distance="tapered")
    r = objective.residuals(truth.to_vector()[None])[0]
    np.testing.assert_allclose(r, np.linalg.norm(off - truth.project(off), axis=1), atol=1e-15)
