"""Helpers shared by the tests of the core (geometry, data, metrics)."""

from __future__ import annotations

import numpy as np

from hapticsim.geometry import Superquadric, random_rotation


def random_superquadric(
    rng: np.random.Generator,
    taper: float = 1.0,
    eps: tuple[float, float] = (0.1, 2.0),
    posed: bool = True,
) -> Superquadric:
    """A random superquadric: a in [1, 10] cm, eps uniform in `eps`, |taper| <= `taper`."""
    return Superquadric(
        a=rng.uniform(0.01, 0.1, 3),
        eps=rng.uniform(eps[0], eps[1], 2),
        taper=rng.uniform(-taper, taper, 2),
        rotation=random_rotation(rng) if posed else np.eye(3),
        center=rng.normal(0.0, 0.1, 3) if posed else np.zeros(3),
    )


def random_rigid(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A random rotation (3, 3) and translation (3,) [m]."""
    return random_rotation(rng), rng.normal(0.0, 0.2, 3)


def surface_samples(
    sq: Superquadric, rng: np.random.Generator, count: int = 200
) -> tuple[np.ndarray, np.ndarray]:
    """Points and normals at uniformly random (eta, omega) of the uniform parametrisation."""
    eta = rng.uniform(-np.pi / 2, np.pi / 2, count)
    omega = rng.uniform(-np.pi, np.pi, count)
    return sq.surface(eta, omega)


def log_f_world(sq: Superquadric, points: np.ndarray) -> np.ndarray:
    """log F of world points, the function whose gradient direction is the outward normal."""
    return np.log(sq.inside_outside(points))


def fd_gradient(sq: Superquadric, points: np.ndarray, step: float) -> np.ndarray:
    """Central finite-difference gradient of log F at world points, (n, 3)."""
    cols = [
        (log_f_world(sq, points + step * e) - log_f_world(sq, points - step * e)) / (2 * step)
        for e in np.eye(3)
    ]
    return np.stack(cols, -1)
