"""The per-step scorer's questions (hapticsim.metrics.scorer_kinds) and the stand's
(hapticsim.sim.object_mesh): a generic answer from the Solid interface for any kind, and the
faster answers that kinds register agree with it."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.geometry import Solid, Superquadric
from hapticsim.metrics import scorer_kinds as kinds
from hapticsim.metrics.episode import TruthScorer
from hapticsim.metrics.volume import volume_overlap
from hapticsim.sim.object_mesh import support_foot, support_half_widths, support_points
from tests.geometry.test_solid import SOLIDS, TAPERED, UNION


class Plain(Solid):
    """A new kind of solid that implements the interface alone, by delegating to another:
    what the scorer and the stand ask of it must work through their generic answers."""

    kind = "plain"
    contact_reference = "the inner solid"

    def __init__(self, inner: Solid) -> None:
        self.inner = inner
        self.center = inner.center

    def contains(self, p):  # noqa: ANN001, ANN201
        return self.inner.contains(p)

    def normals(self, p):  # noqa: ANN001, ANN201
        return self.inner.normals(p)

    def surface_distance(self, p):  # noqa: ANN001, ANN201
        return self.inner.surface_distance(p)

    def contact_errors(self, p, n):  # noqa: ANN001, ANN201
        return self.inner.contact_errors(p, n)

    def sample_interior(self, count, rng=None):  # noqa: ANN001, ANN201
        return self.inner.sample_interior(count, rng)

    def sample_surface(self, count, rng=None):  # noqa: ANN001, ANN201
        return self.inner.sample_surface(count, rng)

    volume = property(lambda self: self.inner.volume)
    bounding_radius = property(lambda self: self.inner.bounding_radius)
    bounds = property(lambda self: self.inner.bounds)
    size = property(lambda self: self.inner.size)

    def surface_mesh(self, resolution=40):  # noqa: ANN001, ANN201
        return self.inner.surface_mesh(resolution)

    def convex_pieces(self, resolution):  # noqa: ANN001, ANN201
        return self.inner.convex_pieces(resolution)

    def transformed(self, rotation, translation):  # noqa: ANN001, ANN201
        return Plain(self.inner.transformed(rotation, translation))

    def scaled(self, factor):  # noqa: ANN001, ANN201
        return Plain(self.inner.scaled(factor))

    def shape_key(self) -> bytes:
        return b"plain:" + self.inner.shape_key()

    def to_dict(self):  # noqa: ANN201
        return self.inner.to_dict()


@pytest.mark.parametrize("name", list(SOLIDS))
def test_quasi_interior_is_inside_and_about_the_count(name: str) -> None:
    solid = SOLIDS[name]
    pts = kinds.quasi_interior(solid, 4096, np.random.default_rng(4))
    assert np.all(solid.contains(pts)) and 0.9 * 4096 < len(pts) < 1.1 * 4096
    generic = kinds.quasi_interior.dispatch(Solid)(solid, 4096, np.random.default_rng(4))
    assert 0.9 * 4096 < len(generic) < 1.1 * 4096


@pytest.mark.parametrize("name", list(SOLIDS))
def test_registered_answers_agree_with_the_generic_ones(name: str) -> None:
    solid = SOLIDS[name]
    gen = np.random.default_rng(0)
    points = np.ascontiguousarray((solid.center + gen.normal(scale=0.02, size=(500, 3))).T)
    generic = kinds.count_outside.dispatch(Solid)
    assert kinds.count_outside(solid, points) == generic(solid, points)
    surface = np.ascontiguousarray(solid.sample_surface(200, rng=1)[0].T)
    near = surface + 0.003 * gen.normal(size=surface.shape)
    # foot-point iteration (a superquadric) against distances to its fine mesh, whose chords
    # cut the sharp edges of this tapered eps1 = 0.4 body: measured at most 1.02e-4 m apart
    np.testing.assert_allclose(
        kinds.foot_distances(solid, near), kinds.foot_distances.dispatch(Solid)(solid, near),
        atol=3e-4,
    )
    lattice = kinds.lattice_surface(solid, np.eye(3))
    if lattice is not None:  # points on the surface, one per direction
        assert np.max(solid.surface_distance(lattice[0].T)) < 1e-4


@pytest.mark.parametrize("name", ["superquadric", "union"])
def test_a_new_kind_is_scored_through_the_generic_answers(name: str) -> None:
    # the same solid seen as a kind that registers nothing scores as its registered self, to
    # the samples' precision (4096 interior samples; measured: epsilon 0.005 / 0.001 apart,
    # Chamfer 1.1 % / 0 %, against 100 000 Monte Carlo samples 0.0015 / 0.0022, as a truth
    # 0.008 / 0.002, for the superquadric / the union)
    solid, truth = SOLIDS[name], TAPERED.scaled(1.1)
    scorer = TruthScorer(truth, rng=0)
    fast, plain = scorer.score(solid), scorer.score(Plain(solid))
    assert plain.epsilon == pytest.approx(fast.epsilon, abs=0.04)
    assert plain.chamfer == pytest.approx(fast.chamfer, rel=0.1)
    reference = volume_overlap(solid, truth, samples=100_000, rng=0)
    assert plain.epsilon == pytest.approx(reference.epsilon, abs=0.04)
    as_truth = TruthScorer(Plain(truth), rng=0).score(solid)
    assert as_truth.epsilon == pytest.approx(fast.epsilon, abs=0.04)


def test_the_stands_questions() -> None:
    assert np.allclose(support_half_widths(TAPERED), TAPERED.a[:2])
    lo, hi = UNION.bounds
    assert np.allclose(support_half_widths(UNION), 0.5 * (hi[:2] - lo[:2]))
    mesh = SOLIDS["mesh"]
    foot = support_foot(mesh, support_points(mesh))
    # a mesh says where the vertical through its centre leaves it at the bottom
    assert foot[2] == pytest.approx(mesh.bounds[0, 2], abs=1e-9)
    for solid in (TAPERED, UNION, Plain(UNION)):
        pts = support_points(solid)
        assert pts.shape[1] == 3 and np.max(solid.surface_distance(pts)) < 1e-3  # mesh chords
        foot = support_foot(solid, pts, level=True)
        assert foot[2] == pytest.approx(pts[:, 2].min())
    assert isinstance(TAPERED, Superquadric)
