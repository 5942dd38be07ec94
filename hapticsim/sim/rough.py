"""What a controller may know about the object before touching it: a rough, vision-like estimate.

Controllers plan approach points and palm poses on this estimate; every recorded contact still
comes from MuJoCo's contact data on the true object.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, finite_float
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.superquadric import superquadric_arg

Array = NDArray[np.float64]

#: Shape exponent below which a body counts as having edges (box-like or cylinder-like).
EDGE_EPS: float = 0.5


@dataclass(frozen=True)
class RoughObject:
    """A rough superquadric of the object (position and size off by a few millimetres).

    Attributes:
        shape: the rough superquadric, world frame.
        has_edges: True for prismatic bodies (some eps < :data:`EDGE_EPS`); such bodies get corner
            patches and edge-crossing stripes.
    """

    shape: Superquadric
    has_edges: bool

    def __post_init__(self) -> None:
        superquadric_arg(self.shape, "shape")

    @property
    def center(self) -> Array:
        """(3,) float, rough centre [m, world]."""
        return self.shape.center

    @property
    def radius(self) -> float:
        """Bounding radius of the rough shape [m]."""
        return self.shape.bounding_radius

    def surface(self, eta: Array, omega: Array) -> tuple[Array, Array]:
        """Rough surface points (n, 3) [m, world] and outward unit normals (n, 3) at (eta, omega)
        of the uniform parametrisation (paper eq. 6)."""
        return self.shape.surface(np.atleast_1d(eta), np.atleast_1d(omega))


def vision_estimate(
    truth: Superquadric,
    rng: np.random.Generator | int | None = None,
    position_sigma: float = 0.002,
    size_sigma: float = 0.03,
) -> RoughObject:
    """A rough estimate of the object as a camera would give it.

    Args:
        truth: the true object.
        rng: seed or generator of the perturbation.
        position_sigma: standard deviation of the centre error per axis [m].
        size_sigma: relative standard deviation of the semi-axes.

    Returns:
        The rough object (same orientation, shape exponents and taper as the truth).
    """
    truth = superquadric_arg(truth, "truth")
    gen = as_generator(rng)
    ps = finite_float(position_sigma, "position_sigma", low=0.0)
    ss = finite_float(size_sigma, "size_sigma", low=0.0)
    if ss >= 0.3:
        raise InvalidInputError(f"`size_sigma` must be < 0.3, got {size_sigma!r}")
    center = truth.center + gen.normal(0.0, ps, 3)
    a = truth.a * np.clip(1.0 + gen.normal(0.0, ss, 3), 0.7, 1.3)
    shape = truth.replace(a=a, center=center)
    return RoughObject(shape=shape, has_edges=bool(np.min(truth.eps) < EDGE_EPS))


__all__ = ["EDGE_EPS", "RoughObject", "vision_estimate"]
