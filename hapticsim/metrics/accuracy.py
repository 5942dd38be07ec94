"""How close simulated contacts are to the true object (SPEC §7): the distance of the contact
points to the true surface and the angle between measured and true normals, each solid measuring
them against itself (:meth:`~hapticsim.geometry.solid.Solid.contact_errors`: a superquadric's
analytic surface and normal, a union's nearest part, a mesh's closest face or the normal cone at
an edge or vertex)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.solid import Solid, solid_arg

Array = NDArray[np.float64]


def contact_accuracy(truth: Solid, points_world: Array, normals_world: Array) -> dict[str, Any]:
    """Summary of contact accuracy against the true object (any solid).

    Returns:
        ``distance_median``, ``distance_p95``, ``distance_max`` [m], ``angle_median_deg``,
        ``angle_p95_deg``, ``angle_max_deg`` [deg], ``count`` and ``against`` (what the
        contacts were checked against).
    """
    return accuracy_checked(solid_arg(truth, "truth"), points_world, normals_world)


def accuracy_checked(truth: Solid, points_world: Array, normals_world: Array) -> dict[str, Any]:
    """:func:`contact_accuracy` of a truth known to be a solid: for a caller that validated its
    inputs once at its own entry (:func:`hapticsim.exploration.run_trial`)."""
    dist, ang = truth.contact_errors(points_world, normals_world)
    return {
        "count": int(len(dist)),
        "distance_median": float(np.median(dist)),
        "distance_p95": float(np.percentile(dist, 95)),
        "distance_max": float(np.max(dist)),
        "angle_median_deg": float(np.median(ang)),
        "angle_p95_deg": float(np.percentile(ang, 95)),
        "angle_max_deg": float(np.max(ang)),
        "against": truth.contact_reference,
    }


__all__ = ["accuracy_checked", "contact_accuracy"]
