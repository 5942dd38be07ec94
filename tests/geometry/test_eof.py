"""Error of fit (SPEC §2, paper eqs. 7-9)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.geometry import Superquadric
from hapticsim.geometry.eof import contact_residuals, error_of_fit
from tests.core_helpers import random_rigid, random_superquadric, surface_samples


def _params(sq: Superquadric) -> tuple:
    return sq.a, sq.eps, sq.taper, sq.rotation, sq.center


def test_eof_is_zero_on_clean_surface_data_and_known_off_it() -> None:
    rng = np.random.default_rng(0)
    for _ in range(30):
        sq = random_superquadric(rng)
        points, normals = surface_samples(sq, rng, 100)
        assert error_of_fit(points, normals, *_params(sq)) < 1e-24
        # Flipped normals: D2 = |n - (-n)|^2 = 4 at every point, D1 = 0.
        sigma = float(np.mean(sq.a))
        r = contact_residuals(points, -normals, *_params(sq), lam=0.5)
        np.testing.assert_allclose(r, 0.5 * sigma * 4, rtol=1e-9)
        # Points moved along their rays: D1 is the distance moved, the normal term unchanged.
        factor = rng.uniform(0.5, 1.5, (100, 1))
        moved = sq.center + factor * (points - sq.center) if not np.any(sq.taper) else None
        if moved is not None:
            d1 = contact_residuals(moved, None, *_params(sq))
            np.testing.assert_allclose(d1, np.linalg.norm(moved - points, axis=1), rtol=1e-9)


def test_eof_is_the_mean_square_residual_and_lambda_weights_normals() -> None:
    rng = np.random.default_rng(1)
    sq = random_superquadric(rng)
    points, normals = surface_samples(sq, rng, 80)
    points = points + rng.normal(0, 0.003, points.shape)
    normals = normals + rng.normal(0, 0.1, normals.shape)
    for lam in (0.0, 0.5, 2.0):
        r = contact_residuals(points, normals, *_params(sq), lam=lam)
        assert error_of_fit(points, normals, *_params(sq), lam=lam) == pytest.approx(
            np.mean(r**2), rel=1e-12
        )
    d1 = contact_residuals(points, None, *_params(sq))
    np.testing.assert_allclose(contact_residuals(points, normals, *_params(sq), lam=0.0), d1)
    np.testing.assert_allclose(d1, sq.radial_distance(points), rtol=1e-9, atol=1e-15)


def test_batched_eof_equals_one_by_one() -> None:
    rng = np.random.default_rng(2)
    shapes = [random_superquadric(rng) for _ in range(7)]
    points, normals = surface_samples(shapes[0], rng, 60)
    stacked = [
        np.stack([getattr(s, k) for s in shapes])
        for k in ("a", "eps", "taper", "rotation", "center")
    ]
    batch = error_of_fit(points, normals, *stacked)
    assert batch.shape == (7,)
    single = [float(error_of_fit(points, normals, *_params(s))) for s in shapes]
    np.testing.assert_allclose(batch, single, rtol=1e-10)


def test_eof_is_invariant_under_rigid_transforms() -> None:
    rng = np.random.default_rng(3)
    for _ in range(20):
        sq, data = random_superquadric(rng), random_superquadric(rng)
        points, normals = surface_samples(data, rng, 50)
        rot, shift = random_rigid(rng)
        moved = sq.transformed(rot, shift)
        a = error_of_fit(points, normals, *_params(sq))
        b = error_of_fit(points @ rot.T + shift, normals @ rot.T, *_params(moved))
        assert b == pytest.approx(a, rel=1e-8)
