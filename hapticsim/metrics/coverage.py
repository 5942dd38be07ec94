"""Coverage: how much of an estimate's surface the contacts support (no ground truth).

The environment's ``"uncertainty"`` reward and the coverage-gap policies' measure of where an
estimate is least supported.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry import Superquadric
from hapticsim.geometry.sampling import fibonacci_sphere

Array = NDArray[np.float64]

#: Unit sphere directions on which the coverage uncertainty is evaluated.
N_COVERAGE: int = 256


def coverage_uncertainty(estimate: Superquadric | None, points: Array) -> float:
    """How much of the estimate's surface no contact supports, in [0, 1] (no ground truth).

    Surface points of the estimate in 256 fixed directions (uniform parametrisation) each count
    ``min(1, d / r)``, d the distance to the nearest contact and ``r = mean(a)`` of the estimate;
    the result is their mean. 1 without an estimate.

    Args:
        estimate: the current fit or None.
        points: (n, 3) float, contacts [m, world].
    """
    if estimate is None or len(points) == 0:
        return 1.0
    surf = _coverage_surface(estimate)
    d2 = np.min(np.sum((surf[:, None, :] - points[None, :, :]) ** 2, axis=-1), axis=1)
    return float(np.mean(np.minimum(1.0, np.sqrt(d2) / float(np.mean(estimate.a)))))


def _coverage_surface(estimate: Superquadric) -> Array:
    dirs = fibonacci_sphere(N_COVERAGE)
    eta = np.arcsin(np.clip(dirs[:, 2], -1, 1))
    omega = np.arctan2(dirs[:, 1], dirs[:, 0])
    return estimate.surface(eta, omega)[0]


__all__ = ["N_COVERAGE", "coverage_uncertainty"]
