"""Scoring a superquadric against a mesh truth: Monte Carlo against exact booleans, exact
closest points, contact accuracy with normal cones at edges, the per-step scorer."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from hapticsim.data.example_meshes import EXAMPLE_MESHES, l_block, rounded_box
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import MeshSolid, Superquadric, rotvec_to_matrix
from hapticsim.geometry.triangles import closest_point_on_triangles
from hapticsim.metrics import boolean_overlap, score, volume_overlap
from hapticsim.metrics.episode import TruthScorer

BOX = MeshSolid(*(lambda m: (m.vertices, m.faces))(trimesh.creation.box((0.06, 0.04, 0.05))))


def _estimates(solid: MeshSolid, count: int, seed: int) -> list[Superquadric]:
    """Superquadrics near the solid: its principal box, perturbed."""
    gen = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        out.append(
            Superquadric(
                a=solid.half_extents * gen.uniform(0.8, 1.2, 3),
                eps=gen.uniform(0.1, 1.0, 2),
                taper=gen.uniform(-0.2, 0.2, 2),
                rotation=solid.principal_axes @ rotvec_to_matrix(gen.normal(0.0, 0.15, 3)),
                center=solid.centroid + gen.normal(0.0, 0.003, 3),
            )
        )
    return out


def _worst_difference(per_mesh: int, samples: int) -> float:
    worst = 0.0
    for k, name in enumerate(EXAMPLE_MESHES):
        solid = EXAMPLE_MESHES[name]()
        for est in _estimates(solid, per_mesh, k):
            mc = volume_overlap(est, solid, samples=samples, rng=k)
            exact = boolean_overlap(est, solid)
            for key in ("alpha", "beta", "iou"):
                worst = max(worst, abs(getattr(mc, key) - getattr(exact, key)))
    return worst


def test_monte_carlo_agrees_with_exact_booleans() -> None:
    # one estimate per example mesh at 40k samples (standard error <= 0.0025): measured largest
    # |MC - booleans| 0.0016 in alpha, beta and IoU; the bar is 0.01
    assert _worst_difference(1, 40_000) < 0.01


@pytest.mark.slow
def test_monte_carlo_agrees_with_exact_booleans_at_the_default_samples() -> None:
    # 12 pairs at the default 100k samples (standard error <= 0.0016): measured 0.0016
    assert _worst_difference(3, 100_000) < 0.006


def test_a_superquadric_against_its_own_mesh_scores_near_zero() -> None:
    sq = Superquadric(a=(0.03, 0.025, 0.04), eps=(0.5, 0.8), taper=(0.2, -0.1))
    mesh = sq.to_mesh(128)
    solid = MeshSolid(mesh.vertices, mesh.faces)
    s = score(sq, solid, volume_samples=50_000, chamfer_samples=2000)
    # the 128-longitude mesh is inscribed: V(mesh)/V = 0.9986 (measured), so alpha ~ 0.0015
    assert s.alpha < 0.006 and s.beta < 0.003 and s.iou > 0.99
    assert s.chamfer < 1e-4
    assert "mesh truth" in s.volume_method


def test_score_states_the_method() -> None:
    est = _estimates(BOX, 1, 0)[0]
    mc = score(est, BOX, rng=0, volume_samples=20_000, chamfer_samples=500)
    exact = score(est, BOX, rng=0, chamfer_samples=500, volume_method="booleans")
    assert mc.volume_method.startswith("Monte Carlo against a mesh truth: 20000 points")
    assert "manifold3d" in exact.volume_method
    assert mc.chamfer == pytest.approx(exact.chamfer, rel=0.1)  # other Chamfer samples
    assert score(est, BOX, rng=3).to_dict() == score(est, BOX, rng=3).to_dict()
    with pytest.raises(InvalidInputError, match="volume_method"):
        score(est, BOX, volume_method="voxels")
    with pytest.raises(InvalidInputError, match="must be a solid"):
        volume_overlap(est, "box")  # type: ignore[arg-type]


@pytest.mark.parametrize("solid", [BOX, l_block(), rounded_box()], ids=["box", "l", "rounded"])
def test_closest_points_are_exact(solid: MeshSolid) -> None:
    gen = np.random.default_rng(1)
    lo, hi = solid.bounds
    near, _ = solid.sample_surface(300, gen)
    pts = np.concatenate([near + gen.normal(0, 0.002, near.shape), gen.uniform(lo, hi, (300, 3))])
    q, face = solid.nearest(pts)
    tri = np.asarray(solid.triangles)
    pairs_p = np.repeat(pts, len(tri), axis=0)
    pairs_t = np.tile(tri, (len(pts), 1, 1))
    every = np.linalg.norm(closest_point_on_triangles(pairs_t, pairs_p) - pairs_p, axis=1)
    brute = np.nanmin(every.reshape(len(pts), len(tri)), axis=1)
    assert np.allclose(np.linalg.norm(q - pts, axis=1), brute, atol=1e-12)
    own = np.linalg.norm(closest_point_on_triangles(tri[face], pts) - pts, axis=1)
    assert np.allclose(own, brute, atol=1e-12)  # the face returned holds the closest point


def test_contact_normals_at_an_edge_count_against_its_cone() -> None:
    # a fingertip on the edge between the +x and +z faces of the box measures any normal
    # between them; one off the cone by 10 degrees is 10 degrees off
    edge = np.array([[0.03, 0.0, 0.025]] * 3)
    tilt = np.radians(10.0)
    normals = np.array(
        [[np.sqrt(0.5), 0.0, np.sqrt(0.5)], [1.0, 0.0, 0.0],
         [np.cos(np.pi / 4), np.sin(tilt), np.sin(np.pi / 4)]]
    )  # fmt: skip
    dist, angle = BOX.contact_errors(edge, normals)
    assert np.allclose(dist, 0.0, atol=1e-12)
    assert angle[0] == pytest.approx(0.0, abs=1e-6) and angle[1] == pytest.approx(0.0, abs=1e-6)
    assert angle[2] == pytest.approx(np.degrees(np.arcsin(np.sin(tilt) / np.linalg.norm(
        normals[2]))), abs=0.01)  # fmt: skip
    on_face = np.array([[0.03, 0.01, 0.0]])
    _, a = BOX.contact_errors(on_face, np.array([[0.0, 0.0, 1.0]]))
    assert a[0] == pytest.approx(90.0)


def test_the_per_step_scorer_matches_the_one_off_score() -> None:
    solid = l_block()
    est = _estimates(solid, 1, 4)[0]
    scorer = TruthScorer(solid, chamfer_samples=500)  # 4096 quasi-random volume samples
    fast = scorer.score(est).to_dict()
    slow = score(est, solid, rng=9, volume_samples=400_000, chamfer_samples=500)
    # Measured over 6 estimates x 3 scorer seeds against 400k Monte Carlo samples (standard
    # error 0.0008): |alpha error| <= 0.0068, |beta error| <= 0.0025 (RMS 0.0025 / 0.0009);
    # Monte Carlo at 10k has a standard error of 0.005. Chamfer: random samples, within 10 %.
    assert fast["alpha"] == pytest.approx(slow.alpha, abs=0.012)
    assert fast["beta"] == pytest.approx(slow.beta, abs=0.006)
    assert fast["chamfer"] == pytest.approx(slow.chamfer, rel=0.1)
    assert scorer.score(est).to_dict() == fast  # the same samples every call
