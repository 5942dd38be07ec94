"""Symmetric Chamfer distance (SPEC §4)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import HapticsimError
from hapticsim.geometry import Superquadric
from hapticsim.metrics import chamfer, sample_surface, surface_distance
from hapticsim.metrics.chamfer import closest_point_on_triangles
from tests.core_helpers import random_rigid


def _sphere(r: float, center=(0.0, 0.0, 0.0)) -> Superquadric:
    return Superquadric(a=(r, r, r), eps=(1.0, 1.0), center=center)


BOX = Superquadric(a=(0.025, 0.035, 0.05), eps=(0.1, 0.1), taper=(0.4, 0.3))


def test_identical_shapes_are_about_zero_apart() -> None:
    # Only the mesh chords of the target surface remain: measured 4.9e-5 m for the tapered box.
    assert chamfer(BOX, BOX) < 1e-4
    assert chamfer(_sphere(0.03), _sphere(0.03)) < 1e-4  # measured 2.0e-5 m


def test_concentric_spheres_are_the_radius_difference_apart() -> None:
    # Every point of either sphere is exactly r from the other: chamfer = r (measured -0.05 %).
    assert chamfer(_sphere(0.02), _sphere(0.04)) == pytest.approx(0.02, rel=3e-3)


def test_surface_distance_to_a_sphere() -> None:
    rng = np.random.default_rng(0)
    points = rng.normal(0.0, 0.05, (500, 3))
    expected = np.abs(np.linalg.norm(points, axis=1) - 0.03)
    # Mesh chords at 96 longitudes (sagitta of a 3 cm sphere 1.6e-5 m): measured 3.2e-5 m at most.
    np.testing.assert_allclose(surface_distance(points, _sphere(0.03)), expected, atol=1e-4)


def test_surface_samples_are_on_the_surface_and_area_uniform() -> None:
    points = sample_surface(BOX, 20_000, rng=1)
    np.testing.assert_allclose(BOX.inside_outside(points), 1.0, atol=1e-9)
    # Area-uniform on a sphere: each octant gets 1/8 (binomial std 0.0023; measured <= 0.0026).
    pts = sample_surface(_sphere(0.03), 20_000, rng=2)
    octant = (pts > 0) @ np.array([1, 2, 4])
    np.testing.assert_allclose(np.bincount(octant, minlength=8) / 20_000, 1 / 8, atol=0.01)


def test_chamfer_is_symmetric_seeded_and_rigidly_invariant() -> None:
    other = BOX.replace(a=(0.027, 0.033, 0.05), eps=(0.3, 0.2), center=(0.002, 0.0, -0.003))
    a = chamfer(BOX, other, rng=3)
    assert a == chamfer(BOX, other, rng=3)
    # The two directions trade places; 5000 samples each: measured difference 0.12 %.
    assert chamfer(other, BOX, rng=3) == pytest.approx(a, rel=0.03)
    rot, shift = random_rigid(np.random.default_rng(4))
    moved = chamfer(BOX.transformed(rot, shift), other.transformed(rot, shift), rng=3)
    assert moved == pytest.approx(a, rel=1e-6)


def test_closest_point_on_triangles_matches_trimesh() -> None:
    triangles_mod = pytest.importorskip("trimesh.triangles")
    rng = np.random.default_rng(5)
    tri = rng.normal(size=(20_000, 3, 3))
    points = 2 * rng.normal(size=(20_000, 3))  # every Voronoi region gets points
    ours = closest_point_on_triangles(tri, points)
    np.testing.assert_allclose(ours, triangles_mod.closest_point(tri, points), atol=1e-12)
    flat = np.array([[[0.0, 0, 0], [1, 0, 0], [2, 0, 0]], [[1.0, 1, 1], [1, 1, 1], [1, 1, 1]]])
    np.testing.assert_allclose(
        closest_point_on_triangles(flat, np.array([[1.5, 1, 0], [0, 0, 0]])),
        [[1.5, 0, 0], [1, 1, 1]],
    )


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: chamfer("box", BOX), "estimate"),
        (lambda: chamfer(BOX, 0), "truth"),
        (lambda: chamfer(BOX, BOX, samples=0), "samples"),
        (lambda: chamfer(BOX, BOX, rng=0.5), "rng"),
        (lambda: sample_surface(BOX, 0), "count"),
        (lambda: surface_distance(np.zeros((2, 2)), BOX), "points_world"),
        (lambda: surface_distance(np.full((2, 3), np.nan), BOX), "points_world"),
        (lambda: surface_distance(np.zeros((2, 3)), None), "solid"),
    ],
)
def test_bad_input_raises_naming_the_argument(call, name: str) -> None:
    with pytest.raises(HapticsimError, match=f"`{name}`"):
        call()
