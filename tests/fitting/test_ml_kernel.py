"""The compiled maximum-likelihood residuals of nML: known values and the analytic Jacobian."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.fitting import _ml_compiled as kernel
from hapticsim.fitting._problem_compiled import problem_residuals_posed
from hapticsim.fitting.likelihood import Likelihood, anchor_gap, extent_anchor
from hapticsim.fitting.problem import Problem, problem_jacobian, problem_residuals
from hapticsim.geometry import Superquadric, random_rotation
from hapticsim.geometry.eof import ContactSet
from hapticsim.geometry.rotations import rotvec_to_matrix
from tests.geometry import eof_oracle as oracle


def _plain(n: int, length: float = 1.0) -> tuple:
    """Settings giving the raw (d [m], e) residuals: sigma_N = 1, L = 1 m, nothing else."""
    return Likelihood(noise=1.0, length=length).settings()


def test_distance_is_exact_on_a_sphere_and_normal_residual_is_the_vector_difference() -> None:
    rng = np.random.default_rng(0)
    sphere = Superquadric(a=(0.05, 0.05, 0.05), eps=(1.0, 1.0), rotation=random_rotation(rng),
                          center=(0.1, -0.2, 0.3))  # fmt: skip
    dirs = rng.normal(size=(30, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    radius = rng.uniform(0.01, 0.12, 30)
    points = sphere.center + radius[:, None] * dirs
    normals = rng.normal(size=(30, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    contacts = ContactSet.from_arrays(points, normals)
    r = problem_residuals(contacts, Problem.ml(contacts, _plain(30)), sphere.to_vector())[0]
    # (1 - s) / |grad log G| with G = |p| / R: exactly |p| - R, inside and outside.
    np.testing.assert_allclose(r[:30], radius - 0.05, rtol=1e-12, atol=1e-15)
    e_body = r[30:120].reshape(3, 30).T  # the normal residual is in the body frame
    np.testing.assert_allclose(e_body @ sphere.rotation.T, dirs - normals, rtol=1e-10, atol=1e-13)
    np.testing.assert_array_equal(r[120:], 0.0)  # no priors set


def test_distance_on_a_box_face_is_the_orthogonal_distance() -> None:
    box = Superquadric(a=(0.03, 0.04, 0.05), eps=(0.1, 0.1))
    # Off the +x face, away from its edges: the radial distance overestimates, this does not.
    points = np.array([[0.032, 0.01, 0.02], [0.029, -0.015, 0.01], [0.031, 0.0, 0.0]])
    contacts = ContactSet.from_arrays(points, np.tile([1.0, 0.0, 0.0], (3, 1)))
    r = problem_residuals(contacts, Problem.ml(contacts, _plain(3)), box.to_vector())[0]
    # Measured: within 2e-5 m of x - a1 (the eps = 0.1 face is slightly curved).
    np.testing.assert_allclose(r[:3], points[:, 0] - 0.03, atol=2e-5)
    radial = oracle.contact_residuals(points, None, box.a, box.eps, box.taper, box.rotation,
                                      box.center)  # fmt: skip
    assert radial[0] > 1.2 * abs(r[0])


def _case(seed: int, n: int = 50) -> tuple[Superquadric, np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(500 + seed)
    sq = Superquadric(
        a=rng.uniform(0.02, 0.06, 3),
        eps=rng.uniform(0.2, 1.9, 2),
        taper=rng.uniform(-0.6, 0.6, 2),
        rotation=random_rotation(rng),
        center=rng.normal(0, 0.1, 3),
    )
    body = rng.uniform(-1.4, 1.4, (n, 3)) * sq.a * np.array([1.0, 1.0, 0.7])
    points = sq.center + body @ sq.rotation.T
    normals = rng.normal(size=(n, 3))
    free = sq.center + (rng.uniform(-1.5, 1.5, (12, 3)) * sq.a * [1, 1, 0.7]) @ sq.rotation.T
    return sq, points, normals / np.linalg.norm(normals, axis=1, keepdims=True), free


@pytest.mark.parametrize("seed", range(8))
def test_ml_jacobian_matches_central_differences(seed: int) -> None:
    sq, points, normals, free = _case(seed)
    body = (points - sq.center) @ sq.rotation
    factors = 1.0 + np.outer(body[:, 2] / sq.a[2], sq.taper)
    keep = np.all(np.abs(body) > 1e-4, axis=1) & np.all(factors > 0.05, axis=1)
    points, normals = points[keep], normals[keep]
    x = sq.to_vector()
    held = extent_anchor(x + np.random.default_rng(seed).normal(0, 0.05, 13), x)
    lik = Likelihood(noise=0.05, length=float(np.mean(sq.a)), robust=2.0, taper_prior=0.3,
                     eps_prior=(0.5, 0.4), anchor=held, anchor_sigma=0.004)  # fmt: skip
    step = 1e-6 * np.r_[sq.a, [1.0] * 7, [float(np.mean(sq.a))] * 3]
    for nrm in (normals, None):
        contacts = ContactSet.from_arrays(points, nrm)
        problem = Problem.ml(contacts, lik.settings(), free)
        r, jac = problem_jacobian(contacts, problem, x)
        np.testing.assert_allclose(r, problem_residuals(contacts, problem, x)[0], rtol=1e-12)
        assert len(r) == (4 if nrm is not None else 1) * len(points) + kernel.ML_PRIORS + len(free)
        prior = r[len(r) - len(free) - 6 : len(r) - len(free)]
        np.testing.assert_allclose(prior, anchor_gap(x, held) / 0.004, rtol=1e-12, atol=1e-12)
        numeric = np.empty_like(jac)
        for k in range(13):
            up, down = x.copy(), x.copy()
            up[k] += step[k]
            down[k] -= step[k]
            numeric[:, k] = (
                problem_residuals(contacts, problem, up)[0]
                - problem_residuals(contacts, problem, down)[0]
            ) / (2 * step[k])
        # The hinge of a free-space point has a kink at the surface: compare away from it.
        active = r[-len(free) :] > 0
        d_free = problem_residuals(contacts, problem, x)[0][-len(free) :]
        near = np.abs(d_free) < 1e-3
        rows = np.ones(len(r), dtype=bool)
        rows[len(r) - len(free) :] = ~near | ~active
        # Measured over these 8 cases: median relative error ~3e-10, largest ~1e-6.
        scale = np.abs(numeric) + 1e-3 * np.abs(numeric).max(axis=0)
        err = (np.abs(jac - numeric) / scale)[rows]
        assert np.median(err) < 1e-7 and np.max(err) < 1e-3, np.max(err)


def test_population_and_posed_entry_points_agree() -> None:
    sq, points, normals, free = _case(11)
    lik = Likelihood(noise=0.1, length=0.04, robust=3.0, taper_prior=0.3)
    contacts = ContactSet.from_arrays(points, normals)
    problem = Problem.ml(contacts, lik.settings(), free)
    rng = np.random.default_rng(1)
    vectors = sq.to_vector() + rng.normal(size=(5, 13)) * 0.01
    by_vector = problem_residuals(contacts, problem, vectors)
    rot = rotvec_to_matrix(vectors[:, 7:10])
    out = np.empty_like(by_vector)
    problem_residuals_posed(
        problem, vectors[:, 0:3].copy(), vectors[:, 3:5].copy(), vectors[:, 5:7].copy(), rot,
        vectors[:, 10:13].copy(), out, contacts.tally,
    )  # fmt: skip
    np.testing.assert_allclose(out, by_vector, rtol=1e-13, atol=1e-13)
