"""MeshSolid: validation, exact measures, containment and sampling against known answers."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import random_rotation
from hapticsim.geometry.mesh_solid import MeshSolid


def _solid(mesh: trimesh.Trimesh) -> MeshSolid:
    return MeshSolid(mesh.vertices, mesh.faces)


BOX = _solid(trimesh.creation.box((0.06, 0.04, 0.05)))
SPHERE = _solid(trimesh.creation.icosphere(4, 0.03))
L_BLOCK = _solid(
    trimesh.boolean.union(
        [
            trimesh.creation.box((0.06, 0.02, 0.05)),
            trimesh.creation.box(
                (0.02, 0.06, 0.05), transform=trimesh.transformations.translation_matrix(
                    (-0.02, 0.02, 0.0)
                ),
            ),
        ],
        engine="manifold",
    )
)  # fmt: skip


def test_box_measures_are_exact() -> None:
    assert BOX.volume == pytest.approx(0.06 * 0.04 * 0.05, rel=1e-12)
    assert BOX.area == pytest.approx(2 * (0.06 * 0.04 + 0.06 * 0.05 + 0.04 * 0.05), rel=1e-12)
    assert np.allclose(BOX.centroid, 0.0, atol=1e-15)
    assert BOX.bounding_radius == pytest.approx(0.5 * np.sqrt(0.06**2 + 0.04**2 + 0.05**2))
    assert np.allclose(np.sort(BOX.half_extents), [0.02, 0.025, 0.03])
    assert BOX.is_convex and SPHERE.is_convex and not L_BLOCK.is_convex


def test_l_block_centroid_and_volume() -> None:
    # two 6x2 cm bars sharing a 2x2 cm square: 1e-4 m^3, centroid pulled into the corner
    # (manifold3d's union rounds vertices to float32: measured relative error 1.1e-8)
    assert L_BLOCK.volume == pytest.approx(1e-4, rel=1e-6)
    assert np.allclose(L_BLOCK.centroid, [-0.008, 0.012, 0.0], atol=1e-8)


def test_containment_matches_signed_distance() -> None:
    rng = np.random.default_rng(0)
    for solid in (BOX, SPHERE, L_BLOCK):
        pts = rng.uniform(-0.045, 0.045, size=(4000, 3))
        inside = solid.contains(pts)
        depth = trimesh.proximity.signed_distance(solid.to_trimesh(), pts)  # > 0 inside
        clear = np.abs(depth) > 1e-9
        assert np.array_equal(inside[clear], depth[clear] > 0)


def test_interior_samples_estimate_the_volume_fraction() -> None:
    # V(L) / V(bounding box) by counting box samples; binomial std 0.0016 at 100k points
    pts = L_BLOCK.sample_interior(20_000, rng=1)
    assert np.all(L_BLOCK.contains(pts))
    lo, hi = L_BLOCK.bounds
    box = np.random.default_rng(2).uniform(lo, hi, size=(100_000, 3))
    fraction = L_BLOCK.contains(box).mean()
    assert fraction == pytest.approx(L_BLOCK.volume / np.prod(hi - lo), abs=0.006)


def test_surface_samples_lie_on_faces_with_outward_normals() -> None:
    pts, normals = SPHERE.sample_surface(2000, rng=3)
    r = np.linalg.norm(pts, axis=1)
    assert np.all(r <= 0.03 + 1e-12) and np.all(r > 0.0299)  # on the chords of the icosphere
    assert np.all(np.einsum("ij,ij->i", normals, pts) > 0)
    a, _ = SPHERE.sample_surface(10, rng=4)
    b, _ = SPHERE.sample_surface(10, rng=4)
    assert np.array_equal(a, b)


def test_rigid_motion_keeps_the_measures() -> None:
    rot = random_rotation(np.random.default_rng(5))
    moved = L_BLOCK.transformed(rot, np.array([0.1, -0.2, 0.3]))
    assert moved.volume == pytest.approx(L_BLOCK.volume, rel=1e-12)
    assert np.allclose(moved.centroid, rot @ L_BLOCK.centroid + [0.1, -0.2, 0.3], atol=1e-12)
    assert moved.scaled(2.0).volume == pytest.approx(8.0 * moved.volume, rel=1e-12)


def test_open_mesh_is_refused() -> None:
    m = trimesh.creation.box((1, 1, 1))
    with pytest.raises(InvalidInputError, match="not watertight"):
        MeshSolid(m.vertices, m.faces[:-1])


def test_inward_and_inconsistent_faces_are_refused() -> None:
    m = trimesh.creation.box((1, 1, 1))
    with pytest.raises(InvalidInputError, match="point inward"):
        MeshSolid(m.vertices, m.faces[:, ::-1])
    faces = m.faces.copy()
    faces[0] = faces[0, ::-1]
    with pytest.raises(InvalidInputError, match="consistently oriented|watertight"):
        MeshSolid(m.vertices, faces)


@pytest.mark.parametrize(
    ("vertices", "faces", "message"),
    [
        (np.zeros((4, 2)), np.zeros((4, 3), int), "vertices"),
        (np.zeros((4, 3)), np.zeros((3, 3), int), "at least 4 faces"),
        (np.eye(3), np.array([[0, 1, 5]] * 4), "index vertices"),
        (np.full((4, 3), np.nan), np.zeros((4, 3), int), "NaN"),
        (np.zeros((4, 3)), np.zeros((4, 3)), "int"),
    ],
)
def test_bad_arrays_name_the_problem(vertices: object, faces: object, message: str) -> None:
    with pytest.raises(InvalidInputError, match=message):
        MeshSolid(vertices, faces)  # type: ignore[arg-type]


def test_a_mesh_solid_reads_back_from_its_json() -> None:
    import json

    from hapticsim.geometry.solid_io import solid_from_dict

    box = trimesh.creation.box((0.02, 0.03, 0.04))
    solid = MeshSolid(np.asarray(box.vertices), np.asarray(box.faces))
    back = solid_from_dict(json.loads(json.dumps({"solid": solid.to_dict()})))
    assert isinstance(back, MeshSolid)
    assert back.volume == pytest.approx(0.02 * 0.03 * 0.04, rel=1e-12)
    with pytest.raises(InvalidInputError, match="mesh solid must be"):
        solid_from_dict({"mesh": {"vertices": []}})
