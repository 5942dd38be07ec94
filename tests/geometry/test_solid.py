"""Every kind of solid answers the Solid interface alike (SPEC §10): one set of checks, run on a
superquadric, a union of superquadrics and a mesh."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from hapticsim.data.example_meshes import l_block
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import (
    MeshSolid,
    Solid,
    Superquadric,
    SuperquadricUnion,
    Supertoroid,
    random_rotation,
    solid_arg,
    solid_from_dict,
)

TAPERED = Superquadric(
    a=(0.03, 0.02, 0.035), eps=(0.4, 0.7), taper=(0.3, -0.2),
    rotation=random_rotation(np.random.default_rng(3)), center=(0.01, -0.02, 0.03),
)  # fmt: skip
#: an L of two boxes (overlapping in one corner) and a ball on top
UNION = SuperquadricUnion((
    Superquadric(a=(0.03, 0.01, 0.025), eps=(0.2, 0.2), center=(0.0, 0.0, 0.0)),
    Superquadric(a=(0.01, 0.03, 0.025), eps=(0.2, 0.2), center=(-0.02, 0.02, 0.0)),
    Superquadric(a=(0.012, 0.012, 0.012), eps=(1.0, 1.0), center=(0.02, 0.0, 0.03)),
))  # fmt: skip
#: a ring with a squarish tube, tilted: the kind with a hole
RING = Supertoroid(
    a=(0.01, 0.014, 0.012), eps=(0.5, 1.2), hole=2.4,
    rotation=random_rotation(np.random.default_rng(8)), center=(0.0, 0.01, -0.01),
)  # fmt: skip
#: a cup with a ring handle: a union with a part that has a hole
HANDLED = SuperquadricUnion((
    Superquadric(a=(0.03, 0.03, 0.04), eps=(0.2, 1.0)),
    Supertoroid(a=(0.006, 0.006, 0.008), eps=(1.0, 1.0), hole=2.6,
                rotation=((1, 0, 0), (0, 0, -1), (0, 1, 0)), center=(0.035, 0.0, 0.0)),
))  # fmt: skip
SOLIDS = {"superquadric": TAPERED, "union": UNION, "mesh": l_block(), "supertoroid": RING,
          "handled": HANDLED}  # fmt: skip


@pytest.fixture(params=list(SOLIDS), ids=list(SOLIDS))
def solid(request: pytest.FixtureRequest) -> Solid:
    return SOLIDS[request.param]


def test_membership_and_bounds(solid: Solid) -> None:
    pts = solid.sample_interior(3000, rng=0)
    assert pts.shape == (3000, 3) and np.all(solid.contains(pts))
    assert not np.any(solid.outside(pts))
    lo, hi = solid.bounds
    assert np.all(pts >= lo - 1e-12) and np.all(pts <= hi + 1e-12)
    assert np.all(np.linalg.norm(pts - solid.center, axis=1) <= solid.bounding_radius + 1e-12)
    far = solid.center + 2.0 * solid.bounding_radius * np.eye(3)
    assert np.all(solid.outside(far)) and not np.any(solid.contains(far))


def test_volume_matches_the_box_fill(solid: Solid) -> None:
    # the fraction of a box's uniform points inside: binomial std < 0.0017 at 10^5 points
    lo, hi = solid.bounds
    pts = np.random.default_rng(1).uniform(lo, hi, (100_000, 3))
    fill = float(np.mean(solid.contains(pts)))
    assert solid.volume == pytest.approx(fill * float(np.prod(hi - lo)), rel=0.02)


def test_surface_samples_lie_on_the_surface_with_outward_normals(solid: Solid) -> None:
    pts, nrm = solid.sample_surface(400, rng=2)
    assert pts.shape == nrm.shape == (400, 3)
    assert np.allclose(np.linalg.norm(nrm, axis=1), 1.0)
    # the kinds meshed from parameters measure to their meshes: chords of up to ~1e-4 m
    assert np.max(solid.surface_distance(pts)) < 3e-4
    assert np.median(solid.surface_distance(pts)) < 5e-5
    dist, angle = solid.contact_errors(pts, nrm)
    assert np.max(dist) < 1e-6 and np.median(angle) < 1.0
    # a step along the normal leaves the solid, a step against it enters
    assert np.mean(solid.outside(pts + 1e-3 * nrm)) > 0.97
    assert np.mean(solid.contains(pts - 1e-3 * nrm)) > 0.97
    assert np.median(np.einsum("ij,ij->i", solid.normals(pts), nrm)) > 0.999


def test_rays_stop_where_the_solid_starts(solid: Solid) -> None:
    gen = np.random.default_rng(5)
    d = gen.normal(size=(50, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    reach = 3.0 * solid.bounding_radius
    target = solid.sample_interior(50, rng=5)  # rays through points inside: every one hits
    origins = target + reach * d
    s = solid.first_hits(origins, -d, 2.0 * reach, (64, 32, 32))
    hit = origins - s[:, None] * d
    assert np.all(np.isfinite(s))
    assert np.all(solid.contains(hit))
    assert np.all(solid.outside(origins - (s[:, None] - 1e-5) * d))
    origins = solid.center + reach * d
    miss = solid.first_hits(origins, d, reach, (64, 32, 32))  # pointing away
    assert np.all(np.isnan(miss))


def test_moving_keeps_the_shape_and_moves_the_pose(solid: Solid) -> None:
    rot = random_rotation(np.random.default_rng(6))
    moved = solid.transformed(rot, np.array([0.01, 0.02, -0.01]))
    assert moved.volume == pytest.approx(solid.volume, rel=1e-6)
    assert np.allclose(moved.center, rot @ solid.center + [0.01, 0.02, -0.01])
    pts = solid.sample_interior(500, rng=7)
    assert np.all(moved.contains(pts @ rot.T + [0.01, 0.02, -0.01]))
    same = solid.transformed(np.eye(3), np.zeros(3))
    assert same.shape_key() == solid.shape_key()
    rotation, position = solid.pose
    assert rotation.shape == (3, 3) and position.shape == (3,)


def test_meshes_and_pieces(solid: Solid) -> None:
    vertices, faces = solid.surface_mesh(32)
    assert vertices.shape[1] == 3 and faces.shape[1] == 3 and faces.max() < len(vertices)
    if solid.kind == "mesh" and importlib.util.find_spec("coacd") is None:
        pytest.skip("a non-convex mesh's pieces need the convex decomposition (extra `meshes`)")
    pieces, position, rotation, method = solid.convex_pieces(16)
    assert len(pieces) >= 1 and all(p.shape[1] == 3 for p in pieces) and method
    world = np.concatenate(pieces) @ rotation.T + position
    # the pieces' vertices lie on (or, for a mesh's decomposition, within a few mm of) the surface
    assert np.median(solid.surface_distance(world)) < 2e-3
    assert solid.size > 0
    assert solid.kind in ("superquadric", "union", "mesh", "supertoroid")
    assert solid.contact_reference


def test_json_round_trip() -> None:
    for solid in (TAPERED, UNION):
        again = solid_from_dict(solid.to_dict())
        assert type(again) is type(solid) and again == solid
    assert solid_from_dict({"solid": UNION.to_dict(), "method": "multi"}) == UNION
    mesh = l_block()
    assert MeshSolid(**mesh.to_dict()["mesh"]).volume == pytest.approx(mesh.volume)


def test_solid_arg_names_the_argument() -> None:
    assert solid_arg(UNION, "x") is UNION
    with pytest.raises(InvalidInputError, match="`truth` must be a solid"):
        solid_arg("cube", "truth")
