"""The vision estimate: a primitive fitted to one noisy depth image, never the true shape."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data.bodies import BODIES, get_body
from hapticsim.data.example_meshes import l_block, truncated_pyramid
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.geometry import Superquadric
from hapticsim.perception.vision import (
    BOX_EPS,
    DepthCamera,
    RoughObject,
    depth_cloud,
    vision_estimate,
)


def test_the_cloud_shows_only_the_side_facing_the_camera() -> None:
    sphere = Superquadric(a=(0.04, 0.04, 0.04), eps=(1.0, 1.0))
    cam = DepthCamera(depth_noise=0.0)
    cloud, eye = depth_cloud(sphere, 0, cam)
    towards = (eye - sphere.center) / np.linalg.norm(eye - sphere.center)
    # visible cap of the sphere: no point behind the silhouette (80 degree incidence limit)
    assert np.min(cloud @ towards) > 0.0
    assert np.allclose(np.linalg.norm(cloud, axis=1), 0.04, atol=1e-4)  # on the surface
    assert 1500 < len(cloud) < 6000  # one point per pixel the sphere covers (~1.4 mm pixels)


def test_depth_noise_is_along_the_rays_and_seeded() -> None:
    cube = get_body("cube")
    a, eye = depth_cloud(cube, 5)
    b, _ = depth_cloud(cube, 5)
    assert np.array_equal(a, b)
    error = np.abs(cube.radial_distance(a))
    # 1 mm noise along rays: median radial error ~0.5 mm (measured 0.53 mm), far below 3 mm
    assert 2e-4 < np.median(error) < 1.5e-3


def test_paper_bodies_get_an_honest_primitive() -> None:
    # Measured (seed 0, default camera): plane fractions 0.36 / 0.28 / 0.18 / 0.08; box centres
    # within 4 mm and semi-axes within 3-10 % of the true extents; ellipsoid within 1 mm.
    for name, truth in BODIES.items():
        rough = vision_estimate(truth, 0)
        assert np.all(rough.shape.taper == 0.0)  # never the true taper
        if name == "ellipsoid":
            assert not rough.has_edges and np.allclose(rough.shape.eps, 1.0)
            assert np.allclose(rough.shape.a, truth.a, rtol=0.1)
        else:
            assert rough.has_edges and np.allclose(rough.shape.eps, BOX_EPS)
        assert np.linalg.norm(rough.center - truth.center) < 0.008
        assert rough.vision is not None and rough.vision["points"] > 1000
        assert rough.cloud is not None and len(rough.cloud) == rough.vision["points"]


def test_the_box_of_a_cube_has_its_extents_and_axes() -> None:
    cube = get_body("cube")
    rough = vision_estimate(cube, 1)
    assert np.allclose(rough.shape.a, 0.03, atol=0.002)
    assert np.allclose(np.abs(rough.shape.rotation), np.eye(3), atol=0.05)
    turned = cube.transformed(
        np.array([[np.cos(0.5), -np.sin(0.5), 0], [np.sin(0.5), np.cos(0.5), 0], [0, 0, 1.0]]),
        np.zeros(3),
    )
    r2 = vision_estimate(turned, 1)
    cos = np.abs(r2.shape.rotation.T @ turned.rotation)
    assert np.allclose(np.sort(cos.max(axis=0)), 1.0, atol=0.01)  # axes found, any order


def test_mesh_objects_get_boxes() -> None:
    for solid in (l_block(), truncated_pyramid()):
        rough = vision_estimate(solid, 0)
        assert rough.has_edges
        lo, hi = solid.bounds
        assert np.all(rough.shape.a < 0.6 * (hi - lo) + 0.003)


def test_same_seed_same_estimate() -> None:
    truth = get_body("tapered_box")
    assert vision_estimate(truth, 2).to_dict() == vision_estimate(truth, 2).to_dict()
    assert vision_estimate(truth, 2).to_dict() != vision_estimate(truth, 3).to_dict()


def test_moved_estimate_keeps_the_rest() -> None:
    rough = vision_estimate(get_body("cube"), 0)
    moved = rough.moved(np.array([0.01, 0.0, 0.0]))
    assert np.allclose(moved.center, [0.01, 0.0, 0.0]) and moved.has_edges == rough.has_edges
    assert moved.cloud is not None and rough.cloud is not None
    assert np.allclose(moved.cloud - rough.cloud, moved.center - rough.center)
    assert RoughObject(rough.shape, has_edges=False).vision is None


def test_too_small_an_object_is_refused() -> None:
    speck = Superquadric(a=(0.002, 0.002, 0.002), eps=(1.0, 1.0))
    with pytest.raises(SimulationError, match="sees only"):
        vision_estimate(speck, 0)


@pytest.mark.parametrize(
    ("field", "value"), [("distance", -1.0), ("width", 2), ("depth_noise", -0.1)]
)
def test_camera_settings_are_checked(field: str, value: float) -> None:
    with pytest.raises(InvalidInputError, match=field):
        DepthCamera(**{field: value})


def test_a_round_object_stands_upright_unless_tilted_clearly() -> None:
    from hapticsim.data.objects import random_superquadric
    from hapticsim.geometry import rotvec_to_matrix

    ellipsoid = get_body("ellipsoid")
    tilted = ellipsoid.transformed(rotvec_to_matrix(np.array([0.7, 0.2, 0.0])), np.zeros(3))
    rough = vision_estimate(tilted, 0)
    assert "tilted" in rough.vision["method"]
    # the tilted fit is kept: its longest axis near the truth's (its z): measured 11 degrees
    longest = rough.shape.rotation[:, int(np.argmax(rough.shape.a))]
    assert abs(longest @ tilted.rotation[:, 2]) > np.cos(np.radians(20))
    # a tapered round body, which no ellipsoid fits, stays upright (measured RMS ratio 0.82)
    tapered = vision_estimate(random_superquadric(9, tapered=True), 0)
    assert not tapered.has_edges and "upright" in tapered.vision["method"]
    assert np.allclose(tapered.shape.rotation[:, 2], [0.0, 0.0, 1.0])


def test_an_object_no_ellipsoid_fits_gets_a_box_about_what_was_seen() -> None:
    # a round head across a handle, in six orientations: least-squares ellipsoids of such clouds
    # were centred outside the cloud (5-8 cm off), so every approach through their centre
    # missed the object (hammers explored by the uncertainty policy: 40 touches in a row)
    from hapticsim.geometry import SuperquadricUnion, random_rotation

    handle = Superquadric(a=(0.008, 0.008, 0.05), eps=(0.6, 1.0))
    head = Superquadric(a=(0.03, 0.012, 0.012), eps=(0.6, 1.0), center=(0.0, 0.0, 0.057))
    boxed = 0
    for seed in range(6):
        union = SuperquadricUnion([handle, head]).transformed(
            random_rotation(np.random.default_rng(seed)), np.zeros(3))  # fmt: skip
        rough = vision_estimate(union, seed)
        lo, hi = np.percentile(rough.cloud, 0.5, axis=0), np.percentile(rough.cloud, 99.5, axis=0)
        assert np.all((rough.shape.center >= lo) & (rough.shape.center <= hi)), seed
        boxed += "principal axes" in rough.vision["method"]
    assert boxed >= 2  # the case arises (measured: 4 of 6, each centred outside before)
