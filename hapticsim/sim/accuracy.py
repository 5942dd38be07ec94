"""How close simulated contacts are to the true object (SPEC §7): distance of the contact points
to the analytic surface and angle between measured and analytic normals."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import normals_array, points_array
from hapticsim.geometry import Superquadric
from hapticsim.geometry.superquadric import superquadric_arg

Array = NDArray[np.float64]


def surface_distance(truth: Superquadric, points_world: Array) -> Array:
    """(n,) float, distance [m] of points near the surface to the analytic surface.

    ``|(p - q) . n(q)|`` with ``q`` the radial projection of ``p`` and ``n(q)`` the outward
    normal there: the Euclidean distance to first order in ``|p - q|`` (exact on flat faces,
    error ``|p - q|^2 * curvature`` elsewhere, under 1e-8 m for contacts within 0.1 mm).
    """
    p = points_array(points_world, "points_world", min_count=1)
    q = truth.project(p)
    return np.abs(np.einsum("ij,ij->i", p - q, truth.normals(q)))


def normal_angle_deg(truth: Superquadric, points_world: Array, normals_world: Array) -> Array:
    """(n,) float, angle [deg] between measured normals and the analytic outward normal at the
    radial projection of each point."""
    p = points_array(points_world, "points_world", min_count=1)
    n = normals_array(normals_world, len(p), "normals_world")
    cos = np.clip(np.einsum("ij,ij->i", n, truth.normals(truth.project(p))), -1.0, 1.0)
    return np.degrees(np.arccos(cos))


def contact_accuracy(
    truth: Superquadric, points_world: Array, normals_world: Array
) -> dict[str, Any]:
    """Summary of contact accuracy against the true object.

    Returns:
        ``distance_median``, ``distance_p95``, ``distance_max`` [m], ``angle_median_deg``,
        ``angle_p95_deg``, ``angle_max_deg`` [deg] and ``count``.
    """
    truth = superquadric_arg(truth, "truth")
    dist = surface_distance(truth, points_world)
    ang = normal_angle_deg(truth, points_world, normals_world)
    return {
        "count": int(len(dist)),
        "distance_median": float(np.median(dist)),
        "distance_p95": float(np.percentile(dist, 95)),
        "distance_max": float(np.max(dist)),
        "angle_median_deg": float(np.median(ang)),
        "angle_p95_deg": float(np.percentile(ang, 95)),
        "angle_max_deg": float(np.max(ang)),
    }


__all__ = ["contact_accuracy", "normal_angle_deg", "surface_distance"]
