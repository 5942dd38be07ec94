"""The taxel depth model: along each taxel's normal, against any solid."""

from __future__ import annotations

import numpy as np

from hapticsim.data.example_meshes import example_mesh
from hapticsim.geometry import Superquadric
from hapticsim.perception.tactile import PadLayout, taxel_depths

RADIUS = 0.008
PAD = PadLayout(21, 21, 0.0015, RADIUS, [0, 0, -1], [0, 1, 0], [0, 0, 0])


def test_known_depths_against_a_flat_face() -> None:
    """A sphere sunk delta into z <= 0: a taxel at angle theta from -z reads
    ``R - (R - delta) / cos(theta)`` (the part of its ray below the face)."""
    face = Superquadric([0.3] * 3, [0.1, 0.1], center=[0, 0, -0.3])
    delta = 6e-4
    centre = np.array([0, 0, RADIUS - delta])
    pos, nrm, _ = PAD.taxels
    depth = taxel_depths(face, pos + centre, nrm, RADIUS)
    cos = -nrm[..., 2]
    expected = np.where(cos > 0, np.maximum(RADIUS - (RADIUS - delta) / np.where(cos > 0, cos, 1),
                                            0.0), 0.0)  # fmt: skip
    np.testing.assert_allclose(depth, expected, atol=3e-7)  # the ray cast's resolution
    assert depth.max() == depth[10, 10] and abs(depth[10, 10] - delta) < 3e-7


def test_a_mesh_reads_like_the_superquadric_it_was_made_of() -> None:
    """The hexagonal prism's top face read as a mesh and as the equivalent flat plane."""
    prism = example_mesh("hexagonal_prism")
    top = prism.bounds[1, 2]
    face = Superquadric([0.3] * 3, [0.1, 0.1], center=[0, 0, top - 0.3])
    centre = np.array([0, 0, top + RADIUS - 5e-4])
    pos, nrm, _ = PAD.taxels
    mesh_depth = taxel_depths(prism, pos + centre, nrm, RADIUS)
    plane_depth = taxel_depths(face, pos + centre, nrm, RADIUS)
    assert mesh_depth.max() > 4e-4
    np.testing.assert_allclose(mesh_depth, plane_depth, atol=1e-6)


def test_no_taxel_inside_reads_zero() -> None:
    far = Superquadric([0.01] * 3, [1, 1], center=[1.0, 0, 0])
    pos, nrm, _ = PAD.taxels
    assert not taxel_depths(far, pos, nrm, RADIUS).any()
