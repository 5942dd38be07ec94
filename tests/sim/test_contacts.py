"""Contact reading: normals point out of the object, points lie on its surface."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.geometry import Superquadric
from hapticsim.perception.vision import RoughObject
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import build_scene

SPHERE = Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0), center=(0.0, 0.0, 0.05))
# Known approach directions (toward the centre): from +x, -y, +z, and two obliques.
DIRECTIONS = np.array(
    [[-1.0, 0, 0], [0, 1.0, 0], [0, 0, -1.0], [-1.0, -1.0, -1.0], [1.0, 0.0, -1.0]]
)


@pytest.fixture(scope="module")
def probed() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    scene = build_scene(SPHERE)
    rough = RoughObject(SPHERE, has_edges=False)
    recorder = Recorder()
    explorer = Explorer(scene, rough, recorder)
    directions = DIRECTIONS / np.linalg.norm(DIRECTIONS, axis=1, keepdims=True)
    for d in directions:
        aim = SPHERE.center - d * SPHERE.a[0]
        explorer.probe_patch(1, [Probe(aim, d)])
    arrays = recorder.arrays()
    return directions, arrays["points_clean"], arrays["normals_clean"]


def test_every_probe_records_one_contact(probed) -> None:
    directions, points, _ = probed
    assert len(points) == len(directions)


def test_normals_point_out_of_the_sphere_along_the_probe(probed) -> None:
    directions, points, normals = probed
    # outward: opposite to the approach direction (a radial approach hits where n = -d);
    # measured ~0.9 deg at mesh resolution 128 (hull facets), limit 2 deg
    angle = np.degrees(np.arccos(np.clip(np.sum(normals * -directions, axis=1), -1, 1)))
    assert np.all(angle < 2.0), angle
    radial = (points - SPHERE.center) / np.linalg.norm(points - SPHERE.center, axis=1)[:, None]
    assert np.all(np.sum(normals * radial, axis=1) > np.cos(np.radians(2.0)))


def test_points_lie_on_the_surface(probed) -> None:
    _, points, _ = probed
    # dist-corrected midpoint: measured < 0.02 mm from the sphere; limit 0.2 mm
    dist = np.abs(np.linalg.norm(points - SPHERE.center, axis=1) - SPHERE.a[0])
    assert np.all(dist < 2e-4), dist
