"""The fast population EOF kernel against a direct, unfused evaluation of SPEC §2."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric, random_rotation
from hapticsim.geometry.eof import (
    ResidualWorkspace,
    contact_residuals,
    contacts_homogeneous,
    population_residuals,
)


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


def test_population_blocks_and_workspace_reuse_give_the_same_numbers() -> None:
    cases = [_case(s) for s in range(300)]
    points, normals = cases[0][1], cases[0][2]
    params = [np.stack([getattr(c[0], k) for c in cases]) for k in ("a", "eps", "taper")]
    rot = np.stack([c[0].rotation for c in cases])
    cen = np.stack([c[0].center for c in cases])
    homog = contacts_homogeneous(points, normals)
    work = ResidualWorkspace()
    big = population_residuals(homog, True, *params, rot, cen, workspace=work)  # 3 blocks
    again = population_residuals(homog, True, *params, rot, cen, workspace=work)
    np.testing.assert_array_equal(big, again)
    for k in (0, 150, 299):
        one = population_residuals(
            homog, True, *(p[k : k + 1] for p in params), rot[k : k + 1], cen[k : k + 1]
        )
        np.testing.assert_allclose(big[k], one[0], rtol=1e-13)


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
