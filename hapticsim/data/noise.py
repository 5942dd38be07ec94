"""Gaussian measurement noise on contact points and normals (SPEC §5, paper III-A).

The noise level ``sigma_N`` is relative to the object: point noise has standard deviation
``sigma_N * scale`` [m] per coordinate, with ``scale = mean(a)`` of the true superquadric; normal
noise has standard deviation ``sigma_N`` per component, after which normals are renormalised.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, finite_float
from hapticsim.data.io import as_points_normals
from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]


def add_noise(
    points: Any,
    normals: Any | None,
    noise: float,
    scale: float,
    rng: np.random.Generator | int | None = None,
) -> tuple[Array, Array | None]:
    """Noisy copies of contact points and normals (SPEC §5).

    Draws the (n, 3) point noise first, then the (n, 3) normal noise, from one generator, so a
    seed fixes both bit for bit. A normal that noise reduces to (nearly) zero length keeps its
    clean direction.

    Args:
        points: (n, 3) float, clean contact points [m].
        normals: (n, 3) float outward normals (normalised first), or None.
        noise: relative noise level sigma_N, finite and >= 0.
        scale: length scale [m], > 0; SPEC §5 uses ``mean(a)`` of the true superquadric.
        rng: seed or generator.

    Returns:
        points (n, 3) [m] and unit normals (n, 3) (None if `normals` is None), new arrays.
    """
    pts, nrm = as_points_normals(points, normals, min_count=0)
    sigma = finite_float(noise, "noise", low=0.0)
    length = finite_float(scale, "scale", low=0.0)
    if length <= 0.0:
        raise InvalidInputError(f"`scale` must be > 0 [m], got {scale!r}")
    gen = as_generator(rng)
    noisy_points = pts + gen.normal(0.0, sigma * length, size=pts.shape)
    if nrm is None:
        return noisy_points, None
    noisy = nrm + gen.normal(0.0, sigma, size=nrm.shape)
    norm = np.linalg.norm(noisy, axis=1, keepdims=True)
    degenerate = norm < 1e-12
    noisy = np.where(degenerate, nrm, noisy / np.where(degenerate, 1.0, norm))
    return noisy_points, noisy


__all__ = ["add_noise"]
