"""Shared data for the fitting tests: the paper's bodies at fixed poses, with synthetic contacts."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.geometry import Superquadric, random_rotation


def posed(body: Superquadric, seed: int) -> Superquadric:
    """`body` moved to a random pose (rotation, translation ~ 0.1 m) drawn from `seed`."""
    rng = np.random.default_rng(seed)
    return body.transformed(random_rotation(rng), rng.normal(0.0, 0.1, size=3))


def surface_contacts(
    sq: Superquadric, count: int, seed: int, eta_max: float = 1.4
) -> tuple[np.ndarray, np.ndarray]:
    """`count` uniform-parametrisation surface points and normals of `sq` (world frame)."""
    rng = np.random.default_rng(seed)
    eta = rng.uniform(-eta_max, eta_max, count)
    omega = rng.uniform(-np.pi, np.pi, count)
    return sq.surface(eta, omega)


@pytest.fixture
def box_contacts() -> tuple[Superquadric, np.ndarray, np.ndarray]:
    """A posed, tapered box and 60 clean contacts all around it."""
    truth = posed(Superquadric(a=(0.03, 0.04, 0.05), eps=(0.2, 0.3), taper=(0.2, -0.1)), 7)
    points, normals = surface_contacts(truth, 60, 1)
    return truth, points, normals
