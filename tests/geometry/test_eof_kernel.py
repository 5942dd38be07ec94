"""The compiled EOF kernel against the numpy oracle, direct formulas and finite differences."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric, random_rotation
from hapticsim.geometry import eof_compiled as kernel
from hapticsim.geometry.eof import DISTANCES, ContactSet, contact_residuals
from hapticsim.geometry.rotations import rotvec_to_matrix
from tests.geometry import eof_oracle as oracle


def _direct_residuals(sq: Superquadric, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """SPEC §2 written out with plain powers (fine for moderate exponents and distances)."""
    body = (points - sq.center) @ sq.rotation
    a1, a2, a3 = sq.a
    e1, e2 = sq.eps
    fx = 1 + sq.taper[0] * body[:, 2] / a3
    fy = 1 + sq.taper[1] * body[:, 2] / a3
    x, y, z = body[:, 0] / fx, body[:, 1] / fy, body[:, 2]
    g = np.abs(x / a1) ** (2 / e2) + np.abs(y / a2) ** (2 / e2)
    f = g ** (e2 / e1) + np.abs(z / a3) ** (2 / e1)
    d1 = np.sqrt(x**2 + y**2 + z**2) * np.abs(1 - f ** (-e1 / 2))
    # Gradient of F in untapered coordinates, then J_t^-T (eq. 4), then unit length.
    gx = (2 / e1) * g ** (e2 / e1 - 1) * np.sign(x) * np.abs(x / a1) ** (2 / e2 - 1) / a1
    gy = (2 / e1) * g ** (e2 / e1 - 1) * np.sign(y) * np.abs(y / a2) ** (2 / e2 - 1) / a2
    gz = (2 / e1) * np.sign(z) * np.abs(z / a3) ** (2 / e1 - 1) / a3
    n = np.stack(
        [
            gx / fx,
            gy / fy,
            gz - gx * x * sq.taper[0] / (a3 * fx) - gy * y * sq.taper[1] / (a3 * fy),
        ],
        axis=1,
    )
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    d2 = np.sum((normals @ sq.rotation - n) ** 2, axis=1)
    return d1 + 0.5 * np.mean(sq.a) * d2


def _case(seed: int) -> tuple[Superquadric, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    sq = Superquadric(
        a=rng.uniform(0.02, 0.06, 3),
        eps=rng.uniform(0.3, 1.8, 2),
        taper=rng.uniform(-0.5, 0.5, 2),
        rotation=random_rotation(rng),
        center=rng.normal(0, 0.1, 3),
    )
    # Within |z| < 0.9 a3 of the body, so that no taper factor comes near 0 (an apex).
    body = rng.uniform(-1.5, 1.5, (40, 3)) * sq.a * np.array([1.0, 1.0, 0.6])
    points = sq.center + body @ sq.rotation.T
    normals = rng.normal(size=(40, 3))
    return sq, points, normals / np.linalg.norm(normals, axis=1, keepdims=True)


@pytest.mark.parametrize("seed", range(5))
def test_kernel_matches_direct_formulas(seed: int) -> None:
    sq, points, normals = _case(seed)
    r = contact_residuals(points, normals, sq.a, sq.eps, sq.taper, sq.rotation, sq.center)
    np.testing.assert_allclose(r, _direct_residuals(sq, points, normals), rtol=1e-9)


def _random_case(seed: int, n: int = 120) -> tuple[Superquadric, np.ndarray, np.ndarray]:
    """A random tapered superquadric (eps anywhere in [0.1, 2], some exactly 0.1) and contacts
    around it with random normals.

    Even seeds: a random pose. Odd seeds: the body frame is the world frame, and in a third of
    the contacts one or two body coordinates are within 1e-9 a of 0 (near the body planes and
    axes). Posing such contacts would change their body coordinates by rounding (an ulp of the
    centre, relatively 1e-8 of a coordinate of 1e-9 m), so both kernels would see different
    inputs.
    """
    rng = np.random.default_rng(1000 + seed)
    eps = rng.uniform(0.1, 2.0, 2)
    eps[rng.random(2) < 0.3] = 0.1
    posed = seed % 2 == 0
    sq = Superquadric(
        a=rng.uniform(0.01, 0.08, 3),
        eps=eps,
        taper=rng.uniform(-0.95, 0.95, 2),
        rotation=random_rotation(rng) if posed else np.eye(3),
        center=rng.normal(0, 0.1, 3) if posed else np.zeros(3),
    )
    body = rng.uniform(-1.6, 1.6, (n, 3)) * sq.a * np.array([1.0, 1.0, 0.8])
    if not posed:
        near = np.zeros((n, 3), dtype=bool)
        rows = rng.random(n) < 1 / 3
        for i in np.flatnonzero(rows):
            near[i, rng.choice(3, size=rng.integers(1, 3), replace=False)] = True
        body[near] = (rng.normal(0.0, 1e-9, (n, 3)) * sq.a)[near]
    points = sq.center + body @ sq.rotation.T
    normals = rng.normal(size=(n, 3))
    return sq, points, normals / np.linalg.norm(normals, axis=1, keepdims=True)


@pytest.mark.parametrize("seed", range(40))
def test_compiled_kernel_agrees_with_the_numpy_oracle(seed: int) -> None:
    sq, points, normals = _random_case(seed)
    args = (sq.a, sq.eps, sq.taper, sq.rotation, sq.center)
    worst = 0.0
    for nrm in (normals, None):
        for distance in DISTANCES:
            got = contact_residuals(points, nrm, *args, lam=0.5, distance=distance)
            ref = oracle.contact_residuals(points, nrm, *args, lam=0.5, distance=distance)
            worst = max(worst, float(np.max(np.abs(got - ref) / np.maximum(np.abs(ref), 1e-300))))
    # Measured over these 40 cases: at most 2.7e-13 (the kernel's own exp and log are accurate
    # to about 1e-15; the rest is the order of operations).
    assert worst < 1e-10, worst


@pytest.mark.parametrize("seed", range(12))
def test_analytic_jacobian_matches_central_differences_of_the_oracle(seed: int) -> None:
    sq, points, normals = _random_case(seed, n=60)
    # Away from the planes (the residual has kinks there) and from an apex (beyond it the taper
    # factor is clipped at 1e-6 and the residual, thousands of metres, cancels catastrophically).
    body = (points - sq.center) @ sq.rotation
    factors = 1.0 + np.outer(body[:, 2] / sq.a[2], sq.taper)
    keep = np.all(np.abs(body) > 1e-4, axis=1) & np.all(factors > 0.05, axis=1)
    points, normals = points[keep], normals[keep]
    x = sq.to_vector()
    step = 1e-6 * np.r_[sq.a, [1.0] * 7, [float(np.mean(sq.a))] * 3]
    for nrm in (normals, None):
        for distance in DISTANCES:
            contacts = ContactSet.from_arrays(points, nrm)
            r, jac = contacts.jacobian(x, 0.5, distance == "tapered")
            numeric = np.empty_like(jac)
            for k in range(13):
                up, down = x.copy(), x.copy()
                up[k] += step[k]
                down[k] -= step[k]
                f = [
                    oracle.contact_residuals(
                        points, nrm, v[0:3], v[3:5], v[5:7], rotvec_to_matrix(v[7:10]), v[10:13],
                        distance=distance,
                    )
                    for v in (up, down)
                ]  # fmt: skip
                numeric[:, k] = (f[0] - f[1]) / (2 * step[k])
            np.testing.assert_allclose(r, contacts.residuals(x, 0.5, distance == "tapered")[0])
            # Measured over these 12 cases: median relative error <= 4e-10, largest 1.6e-6
            # (the truncation and rounding of central differences).
            scale = np.abs(numeric) + 1e-3 * np.abs(numeric).max(axis=0)
            err = np.abs(jac - numeric) / scale
            assert np.median(err) < 1e-7 and np.max(err) < 1e-3, np.max(err)


def test_population_rows_equal_single_evaluations_and_rotation_inputs() -> None:
    cases = [_random_case(s, n=50) for s in range(30)]
    points, normals = cases[0][1], cases[0][2]
    vectors = np.stack([c[0].to_vector() for c in cases])
    contacts = ContactSet.from_arrays(points, normals)
    many = contacts.residuals(vectors, 0.5, True)
    rot = np.stack([c[0].rotation for c in cases])
    np.testing.assert_allclose(contacts.residuals_posed(vectors, rot, 0.5, True), many, rtol=1e-12)
    for k in (0, 17, 29):
        np.testing.assert_array_equal(contacts.residuals(vectors[k], 0.5, True)[0], many[k])
    assert contacts.tally[0] == 30 + 30 + 3


def test_exp_and_log_match_libm() -> None:
    x = np.concatenate([np.linspace(-745, 710, 20001), np.random.default_rng(0).normal(0, 3, 5000)])
    got = np.array([kernel.exp_(v) for v in x[:2000]])  # scalar calls: the compiled helpers
    ref = np.exp(x[:2000])
    ok = x[:2000] > -708
    np.testing.assert_allclose(got[ok], ref[ok], rtol=2e-15)
    assert np.all(got[~ok] == 0.0) and kernel.exp_(710.0) == np.inf
    y = np.exp(np.random.default_rng(1).uniform(-700, 700, 2000))
    np.testing.assert_allclose([kernel.log_(v) for v in y], np.log(y), rtol=1e-15, atol=1e-15)


def test_points_on_body_planes_and_at_the_centre_are_finite() -> None:
    sq = Superquadric(a=(0.03, 0.04, 0.05), eps=(0.5, 1.5))
    points = np.array([[0.0, 0.0, 0.07], [0.05, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.02, 0.0]])
    normals = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    r = contact_residuals(points, normals, sq.a, sq.eps, sq.taper, sq.rotation, sq.center)
    assert np.all(np.isfinite(r))
    # On the axes the model normal is the axis: only D1 remains; at the centre D1 = 0.
    np.testing.assert_allclose(r[[0, 1, 3]], [0.02, 0.02, 0.02], atol=1e-12)


def test_tapered_distance_is_the_world_distance_to_the_radial_projection() -> None:
    sq, points, _ = _case(11)
    rt = contact_residuals(
        points, None, sq.a, sq.eps, sq.taper, sq.rotation, sq.center, distance="tapered"
    )
    np.testing.assert_allclose(rt, np.linalg.norm(points - sq.project(points), axis=1), atol=1e-14)
    flat = sq.replace(taper=(0.0, 0.0))
    args = (points, None, flat.a, flat.eps, flat.taper, flat.rotation, flat.center)
    np.testing.assert_array_equal(
        contact_residuals(*args, distance="tapered"), contact_residuals(*args)
    )
    with pytest.raises(InvalidInputError, match="distance"):
        contact_residuals(*args, distance="euclid")
