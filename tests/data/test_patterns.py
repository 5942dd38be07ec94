"""Stripes and patches (paper III-A, SPEC §5)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data.patterns import Patch, Stripe, sample_patterns
from hapticsim.errors import HapticsimError
from hapticsim.geometry import Superquadric
from tests.core_helpers import random_superquadric


def test_stripe_is_equidistant_in_angle_and_deterministic() -> None:
    stripe = Stripe(start=(-0.5, 0.2), end=(0.7, 1.0), count=7)
    eta, omega = stripe.angles()
    np.testing.assert_allclose(eta, np.linspace(-0.5, 0.7, 7))
    np.testing.assert_allclose(omega, np.linspace(0.2, 1.0, 7))
    assert Stripe((0.1, 0.2), (0.3, 0.4), 1).angles()[0].tolist() == [0.1]
    sq = random_superquadric(np.random.default_rng(0))
    p1, n1 = stripe.sample(sq, rng=1)
    p2, n2 = stripe.sample(sq, rng=2)
    assert np.array_equal(p1, p2) and np.array_equal(n1, n2)


def test_patch_draws_inside_its_rectangle_and_is_seeded() -> None:
    patch = Patch(eta=(-0.2, 0.4), omega=(2.5, 3.8), count=500)
    eta, omega = patch.angles(np.random.default_rng(0))
    assert eta.min() >= -0.2 and eta.max() <= 0.4
    assert omega.min() >= 2.5 and omega.max() <= 3.8
    # Uniform: both halves of each range get about half of the points (binomial std 11).
    assert abs(np.sum(eta < 0.1) - 250) < 50 and abs(np.sum(omega < 3.15) - 250) < 50
    a, b = patch.angles(7), patch.angles(7)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_patterns_lie_on_the_surface_with_the_truth_normals() -> None:
    rng = np.random.default_rng(1)
    for _ in range(20):
        sq = random_superquadric(rng)
        patterns = [Stripe((-1.2, -2.0), (1.3, 2.5), 30), Patch((-1.5, 1.5), (-3.0, 6.0), 40)]
        points, normals, ids = sample_patterns(sq, patterns, rng)
        assert points.shape == (70, 3) and normals.shape == (70, 3)
        assert ids.tolist() == [0] * 30 + [1] * 40
        np.testing.assert_allclose(sq.inside_outside(points), 1.0, atol=1e-12)
        np.testing.assert_allclose(sq.normals(points), normals, atol=1e-9)


def test_pattern_directions_are_in_the_body_frame() -> None:
    # The stripe at omega = 0, eta = 0 touches the +x face of the body, wherever it is posed.
    base = Superquadric(a=(0.02, 0.03, 0.04), eps=(0.1, 0.1))
    rng = np.random.default_rng(2)
    rot = Superquadric.from_vector(
        np.r_[0.02, 0.03, 0.04, 0.1, 0.1, 0, 0, rng.normal(size=3), 1, 2, 3]
    )
    p0, n0 = Stripe((0.0, 0.0), (0.0, 0.0), 1).sample(base)
    p1, n1 = Stripe((0.0, 0.0), (0.0, 0.0), 1).sample(rot)
    np.testing.assert_allclose(p0, [[0.02, 0.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(rot.to_body(p1), p0, atol=1e-12)
    np.testing.assert_allclose(n1 @ rot.rotation, n0, atol=1e-12)


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: Stripe((0.0, 0.0), (0.0, 0.0), 0), "count"),
        (lambda: Stripe((0.0, 0.0), (0.0, 0.0), 2.5), "count"),
        (lambda: Stripe((2.0, 0.0), (0.0, 0.0), 3), "start/end"),
        (lambda: Stripe((0.0, 0.0), (0.0, 7.0), 3), "start/end"),
        (lambda: Stripe((0.0, np.nan), (0.0, 0.0), 3), "start"),
        (lambda: Stripe((0.0,), (0.0, 0.0), 3), "start"),
        (lambda: Patch((0.5, 0.1), (0.0, 1.0), 3), "eta"),
        (lambda: Patch((0.0, 0.1), (1.0, 0.0), 3), "omega"),
        (lambda: Patch((-2.0, 0.1), (0.0, 1.0), 3), "eta"),
        (lambda: Patch((0.0, 0.1), (0.0, 1.0), -1), "count"),
        (lambda: Patch((0.0, 0.1), (0.0, 1.0), 3).angles(rng=-1), "rng"),
        (lambda: Patch((0.0, 0.1), (0.0, 1.0), 3).sample("cube"), "sq"),
        (lambda: sample_patterns("cube", [Stripe((0, 0), (0, 0), 1)]), "sq"),
        (lambda: sample_patterns(Superquadric((1, 1, 1), (1, 1)), []), "patterns"),
        (lambda: sample_patterns(Superquadric((1, 1, 1), (1, 1)), Stripe((0, 0), (0, 0), 1)),
         "patterns"),
        (lambda: sample_patterns(Superquadric((1, 1, 1), (1, 1)), [object()]), "patterns[0]"),
    ],
)
def test_bad_input_raises_naming_the_argument(make, name: str) -> None:
    with pytest.raises(HapticsimError, match=f"`{name}`".replace("[", r"\[").replace("]", r"\]")):
        make()
