"""Properties of the inside-outside function, normals, radial distance and volume (SPEC §1-2)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.geometry import Superquadric
from hapticsim.geometry import functions as fn
from tests.core_helpers import (
    fd_gradient,
    random_rigid,
    random_superquadric,
    surface_samples,
)

SHAPES = 120  # random shapes per property test (each with 200 surface points)


def _shapes(seed: int, taper: float = 1.0) -> list[Superquadric]:
    rng = np.random.default_rng(seed)
    shapes = [random_superquadric(rng, taper=taper) for _ in range(SHAPES)]
    # The corners of the parameter box, where the exponents are most extreme.
    for e1 in (0.1, 2.0):
        for e2 in (0.1, 2.0):
            shapes.append(random_superquadric(rng, taper=taper).replace(eps=(e1, e2)))
    return shapes


@pytest.mark.parametrize("parametrization", ["uniform", "natural"])
def test_surface_points_have_f_one_and_unit_outward_normals(parametrization: str) -> None:
    rng = np.random.default_rng(1)
    worst_f = 0.0
    for sq in _shapes(1):
        eta = rng.uniform(-np.pi / 2, np.pi / 2, 200)
        omega = rng.uniform(-np.pi, np.pi, 200)
        points, normals = sq.surface(eta, omega, parametrization)
        worst_f = max(worst_f, float(np.max(np.abs(sq.inside_outside(points) - 1.0))))
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-12)
        # Outward: a small step along the normal leaves the solid. (The step against it need
        # not enter: at the apex of a cone, |taper| ~ 1, it leaves too.)
        step = 1e-4 * float(np.mean(sq.a))
        assert np.all(sq.inside_outside(points + step * normals) > 1.0)
    assert worst_f < 1e-12  # measured 1.8e-13


@pytest.mark.parametrize(
    ("taper", "max_deg", "p99_deg"),
    [
        (0.0, 0.01, 1e-4),  # measured: max 1.9e-3 deg, 99th percentile 1.7e-6 deg
        (0.9, 0.1, 1e-4),  # measured: max 0.027 deg, 99th percentile 1.7e-6 deg
        # |taper| up to 1 brings the apex of a cone into play, where F is not smooth; measured:
        # max 0.076 deg here, 0.66 deg in a wider scan of 300 shapes (eps1 = 1.98, tx = 0.98).
        (1.0, 2.0, 1e-4),
    ],
)
def test_normals_match_finite_difference_gradient(
    taper: float, max_deg: float, p99_deg: float
) -> None:
    rng = np.random.default_rng(2)
    angles = []
    for sq in _shapes(2, taper=taper):
        points, normals = surface_samples(sq, rng)
        grad = fd_gradient(sq, points, step=1e-6 * float(np.mean(sq.a)))
        grad /= np.linalg.norm(grad, axis=1, keepdims=True)
        cos = np.clip(np.sum(grad * normals, axis=1), -1.0, 1.0)
        angles.append(np.degrees(np.arccos(cos)))
    angles = np.concatenate(angles)
    assert np.max(angles) < max_deg
    assert np.percentile(angles, 99) < p99_deg


def test_off_surface_points_project_radially_and_keep_the_level_set_normal() -> None:
    rng = np.random.default_rng(3)
    for sq in _shapes(3, taper=0.9)[:40]:
        points, _ = surface_samples(sq, rng, 50)
        # Scaling the untapered body point along its ray projects back to the same point.
        sym = fn.untaper(sq.to_body(points), sq.a, sq.taper)
        for factor in (0.5, 1.7):
            moved = sq.to_world(fn.apply_taper(factor * sym, sq.a, sq.taper))
            np.testing.assert_allclose(sq.project(moved), points, atol=1e-12)
        # Untapered, F is homogeneous along rays: the normal (of the level set) is unchanged.
        flat = sq.replace(taper=(0.0, 0.0))
        p, n = surface_samples(flat, rng, 50)
        inner = flat.center + 0.6 * (p - flat.center)
        np.testing.assert_allclose(flat.normals(inner), n, atol=1e-10)


def test_inside_outside_is_finite_far_and_near() -> None:
    sq = Superquadric(a=(0.01, 0.02, 0.03), eps=(0.1, 0.1))
    far = np.array([[1e3, 1e3, 1e3], [1e-3, 0.0, 0.0], [0.0, 0.0, 1e-12], [0.0, 0.0, 0.0]])
    f = sq.inside_outside(far)
    assert f[0] == np.inf or f[0] > 1e100
    assert np.all(f[1:] < 1.0)
    logf = fn.log_inside_outside(far, sq.a, sq.eps)
    assert np.all(np.isfinite(logf))
    d = sq.radial_distance(far)
    assert np.all(np.isfinite(d)) and np.all(d >= 0)


def test_radial_distance_is_zero_on_the_surface_and_the_ray_distance_off_it() -> None:
    rng = np.random.default_rng(4)
    for sq in _shapes(4, taper=0.0)[:40]:
        points, _ = surface_samples(sq, rng, 50)
        np.testing.assert_allclose(sq.radial_distance(points), 0.0, atol=1e-12)
        # Along the ray through the centre, D1 = |p| |1 - F^(-eps1/2)| = |p - p_surface|.
        factor = rng.uniform(0.2, 3.0, (len(points), 1))
        moved = sq.center + factor * (points - sq.center)
        expected = np.linalg.norm(moved - points, axis=1)
        np.testing.assert_allclose(sq.radial_distance(moved), expected, rtol=1e-9, atol=1e-15)


def test_signed_power() -> None:
    x = np.array([-8.0, -1.0, 0.0, 1.0, 8.0])
    np.testing.assert_allclose(fn.signed_power(x, 1 / 3), [-2.0, -1.0, 0.0, 1.0, 2.0])


# ------------------------------------------------------------------ invariance under rigid motion
def test_f_radial_distance_and_normals_are_invariant_under_rigid_transforms() -> None:
    rng = np.random.default_rng(5)
    for sq in _shapes(5)[:60]:
        rot, shift = random_rigid(rng)
        moved = sq.transformed(rot, shift)
        points = sq.center + rng.normal(0.0, 1.5 * float(np.mean(sq.a)), (100, 3))
        points_moved = points @ rot.T + shift
        np.testing.assert_allclose(
            moved.inside_outside(points_moved), sq.inside_outside(points), rtol=1e-9
        )
        np.testing.assert_allclose(
            moved.radial_distance(points_moved), sq.radial_distance(points), rtol=1e-9, atol=1e-15
        )
        np.testing.assert_allclose(
            moved.normals(points_moved), sq.normals(points) @ rot.T, atol=1e-9
        )
        assert moved.volume == pytest.approx(sq.volume, rel=1e-12)


# ------------------------------------------------------------------ volume
def _mc_volume(sq: Superquadric, rng: np.random.Generator, count: int) -> tuple[float, float]:
    """Monte Carlo volume and its standard error [m^3], independent of the closed form.

    Points u uniform in the cube [-1, 1]^3 of scaled untapered coordinates; tapering (paper eq. 2)
    scales areas at height z by (1 + tx z/a3)(1 + ty z/a3), so
    V = 8 a1 a2 a3 E[1(F(a u) <= 1) (1 + tx u_z)(1 + ty u_z)]. Each u is paired with its mirror
    image in z (F is even in z), which halves the variance of the taper weight.
    """
    u = rng.uniform(-1.0, 1.0, (count, 3))
    inside = fn.inside_outside(u * sq.a, sq.a, sq.eps) <= 1.0
    z = u[:, 2]
    mirror = (1 - sq.taper[0] * z) * (1 - sq.taper[1] * z)
    weight = inside * 0.5 * ((1 + sq.taper[0] * z) * (1 + sq.taper[1] * z) + mirror)
    box = 8.0 * float(np.prod(sq.a))
    return box * float(np.mean(weight)), box * float(np.std(weight)) / np.sqrt(count)


@pytest.mark.parametrize(
    ("eps", "taper"),
    [
        ((0.1, 0.1), (0.0, 0.0)),
        ((0.1, 0.1), (0.4, 0.3)),
        ((1.0, 1.0), (-0.8, 0.5)),
        ((0.1, 1.0), (1.0, 1.0)),
        ((1.2, 1.6), (0.6, 0.9)),
        ((1.5, 0.3), (-1.0, -0.7)),
    ],
)
def test_closed_form_volume_matches_monte_carlo(eps: tuple, taper: tuple) -> None:
    rng = np.random.default_rng(6)
    sq = Superquadric(a=(0.03, 0.045, 0.05), eps=eps, taper=taper)
    estimate, std = _mc_volume(sq, rng, 1_000_000)
    # The SPEC asks for agreement within 0.5 %; that must be >= 3 standard errors to mean
    # anything (measured standard errors 0.01-0.14 %, errors 0.01-0.1 %).
    assert std < 0.005 / 3 * sq.volume
    assert estimate == pytest.approx(sq.volume, rel=0.005)


def test_closed_form_volume_known_answers() -> None:
    a = np.array([0.02, 0.03, 0.05])
    abc = float(np.prod(a))
    assert fn.volume(a, (1.0, 1.0), (0.0, 0.0)) == pytest.approx(4 / 3 * np.pi * abc, rel=1e-12)
    # eps = (2, 2): the octahedron |x/a1| + |y/a2| + |z/a3| <= 1.
    assert fn.volume(a, (2.0, 2.0), (0.0, 0.0)) == pytest.approx(4 / 3 * abc, rel=1e-12)
    # eps1 -> 0 gives a prism of height 2 a3; eps2 = 1 a disc cross-section (cylinder).
    assert fn.volume(a, (0.1, 1.0), (0.0, 0.0)) == pytest.approx(
        np.pi * a[0] * a[1] * 2 * a[2], rel=0.05
    )
    # Tapering a solid symmetric in z changes its volume only through the tx * ty term.
    assert fn.volume(a, (1.0, 1.0), (0.7, 0.0)) == pytest.approx(4 / 3 * np.pi * abc, rel=1e-12)
