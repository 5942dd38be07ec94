"""The analytic backend: ray casting and contour strokes on the true superquadric."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.envs.analytic import AnalyticBackend
from hapticsim.envs.touch import Touch
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric, random_rotation
from hapticsim.geometry.rays import raycast, raycast_many

SHAPES = {
    "box": Superquadric(a=(0.025, 0.035, 0.05), eps=(0.1, 0.1), taper=(0.4, 0.3)),
    "ellipsoid": Superquadric(a=(0.04, 0.03, 0.05), eps=(1.0, 1.0), center=(0.01, -0.02, 0.3)),
    "posed": Superquadric(
        a=(0.03, 0.02, 0.04),
        eps=(0.5, 1.5),
        taper=(-0.3, 0.2),
        rotation=random_rotation(np.random.default_rng(3)),
        center=(0.1, 0.0, 0.2),
    ),  # fmt: skip
}


@pytest.mark.parametrize("name", SHAPES)
def test_raycast_hits_the_surface(name: str) -> None:
    shape = SHAPES[name]
    rng = np.random.default_rng(0)
    d = rng.normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    origins = shape.center + 0.3 * d
    s = raycast_many(shape, origins, -d, 0.6)
    assert not np.any(np.isnan(s))
    hits = origins - s[:, None] * d
    # Grid resolution 0.6 / 191 / 47 / 47 = 1.4e-6 m along the ray: |D1| well below 1e-5 m.
    assert np.max(np.abs(shape.radial_distance(hits))) < 1e-5
    # First intersection: the point just before is outside.
    before = hits + 1e-5 * d
    assert np.all(shape.inside_outside(before) > 1.0)


def test_raycast_misses() -> None:
    shape = SHAPES["ellipsoid"]
    assert raycast(shape, np.array([1.0, 1.0, 1.0]), np.array([1.0, 0.0, 0.0]), 1.0) is None
    s = raycast_many(shape, np.array([[1.0, 1.0, 1.0]]), np.array([[0.0, 1.0, 0.0]]), 1.0)
    assert np.isnan(s[0])


def _backend(**kwargs: object) -> tuple[AnalyticBackend, Superquadric]:
    backend = AnalyticBackend(**kwargs)  # type: ignore[arg-type]
    truth = backend.reset(SHAPES["box"], np.random.default_rng(0))
    return backend, truth


def test_probe_from_the_side_gives_one_contact_on_the_surface() -> None:
    backend, truth = _backend()
    res = backend.touch(Touch(np.array([1.0, 0.0, 0.0]), 0.0, 0.0, 1), truth.center)
    assert res.status == "ok" and len(res) == 1
    assert abs(truth.radial_distance(res.points)[0]) < 1e-5
    # The +x face of the tapered box at z = 0 is at x = a1 = 0.025 m, normal close to +x.
    assert res.points[0, 0] == pytest.approx(0.025, abs=1e-4)
    assert res.normals[0] @ np.array([1.0, 0.0, 0.0]) > 0.9
    np.testing.assert_array_equal(res.points, res.points_clean)  # noise 0


def test_stroke_follows_the_contour_over_an_edge() -> None:
    backend, truth = _backend(stroke_spacing=0.005)
    res = backend.touch(Touch(np.array([1.0, 0.0, 0.0]), np.pi / 2, 0.08, 1), truth.center)
    assert res.status == "ok" and len(res) == 17
    # Section rays resolve the surface to reach / (95 * 47 * 47), about 1.5e-6 m here.
    assert np.max(np.abs(truth.radial_distance(res.points))) < 5e-6
    steps = np.linalg.norm(np.diff(res.points, axis=0), axis=1)
    assert np.all(steps < 0.0055) and np.all(steps > 0.002)
    # Upwards: z grows, and the stroke crosses the top edge (z = a3 = 0.05 m) onto the top.
    assert np.all(np.diff(res.points[:, 2]) >= -5e-6)
    assert res.normals[-1, 2] > 0.9
    assert np.all(res.finger == 1) and np.all(np.diff(res.time) > 0)


def test_the_stand_blocks_touches_next_to_it() -> None:
    backend, truth = _backend()
    support = backend.support
    assert support.kind == "stand" and support.foot[2] == pytest.approx(-0.05, abs=1e-4)
    np.testing.assert_allclose(support.foot[:2], 0.0, atol=2e-3)
    res = backend.touch(Touch(np.array([0.0, 0.0, -1.0]), 0.0, 0.0, 0), truth.center)
    assert res.status == "blocked" and len(res) == 0
    free, _ = _backend(support="none")
    assert free.touch(Touch(np.array([0.0, 0.0, -1.0]), 0.0, 0.0, 0), truth.center).status == "ok"
    # The bottom face away from the stand is reachable ...
    res = backend.touch(Touch(np.array([0.0, 0.4, -1.0]), 0.0, 0.0, 0), truth.center)
    assert res.status == "ok" and res.normals[0, 2] < -0.9
    # ... and a stroke down the side stops a fingertip away from the stand (the bottom face is
    # 3 cm wide in x: all of it along y = 0 is within 16 mm of the stand's axis).
    res = backend.touch(Touch(np.array([1.0, 0.0, 0.0]), -np.pi / 2, 0.2, 0), truth.center)
    assert res.points[-1, 2] < -0.042
    assert not any(support.blocks(p) for p in res.points)
    table, _ = _backend(support="table")
    res = table.touch(Touch(np.array([1.0, 0.0, 0.0]), -np.pi / 2, 0.2, 0), truth.center)
    assert res.points[:, 2].min() >= -0.05 + table.support.clearance


def test_sensor_noise_is_seeded_and_kept_apart() -> None:
    runs = []
    for _ in range(2):
        backend = AnalyticBackend(noise=0.1)
        truth = backend.reset(SHAPES["box"], np.random.default_rng(7))
        runs.append(backend.touch(Touch(np.array([1.0, 1, 1]), 0.5, 0.03, 0), truth.center))
    np.testing.assert_array_equal(runs[0].points, runs[1].points)
    assert not np.allclose(runs[0].points, runs[0].points_clean)
    np.testing.assert_allclose(np.linalg.norm(runs[0].normals, axis=1), 1.0)


def test_backend_checks_its_inputs() -> None:
    with pytest.raises(InvalidInputError, match="reset"):
        AnalyticBackend().touch(Touch(np.ones(3), 0.0, 0.0, 0), np.zeros(3))
    backend, truth = _backend(n_fingers=4)
    with pytest.raises(InvalidInputError, match="finger"):
        backend.touch(Touch(np.ones(3), 0.0, 0.0, 4), truth.center)
    with pytest.raises(InvalidInputError, match="noise"):
        AnalyticBackend(noise=-1.0)


def test_stroke_stays_in_its_plane_around_a_corner() -> None:
    backend = AnalyticBackend(support="none")
    truth = backend.reset(
        Superquadric(a=(0.03, 0.03, 0.03), eps=(0.1, 0.1)), np.random.default_rng(0)
    )
    # Sideways (psi = 0) from the +x face: the plane is horizontal through the first contact.
    res = backend.touch(Touch(np.array([1.0, 0.0, 0.2]), 0.0, 0.06, 2), truth.center)
    assert len(res) == 13
    np.testing.assert_allclose(res.points[:, 2], res.points[0, 2], atol=1e-6)
    # It turns the vertical edge onto the +y face (the tangent z x n points towards +y).
    assert res.points[-1, 1] == pytest.approx(0.03, abs=1e-4) and res.normals[-1, 1] > 0.99
