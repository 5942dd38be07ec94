"""Error of fit of contact data to superquadrics (SPEC §2, paper eqs. 7-9), vectorised.

One call evaluates a whole population: the pose and shape arrays carry leading batch
dimensions ``...`` that broadcast against the (n, 3) contacts. This is the one implementation of
the EOF; the fitter and the quality measure theta both call it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.geometry import functions as fn

Array = NDArray[np.float64]


def contact_residuals(
    points_world: Array,
    normals_world: Array | None,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
) -> Array:
    """Per-contact residuals ``r_i = |D1_i| + lambda * sigma * D2_i`` (paper eq. 9).

    ``sum(r_i^2) / n`` is the EOF. Without normals, ``r_i = |D1_i|``.

    Args:
        points_world: (n, 3) float, contact points [m].
        normals_world: (n, 3) float unit normals, or None.
        a: (..., 3) [m]; eps: (..., 2); taper: (..., 2); rotation: (..., 3, 3); center: (..., 3).
        lam: weight lambda of the normal term.

    Returns:
        (..., n) float residuals [m].
    """
    body = fn.world_to_body(points_world, rotation, center)
    fx, fy = fn.taper_factors(body[..., 2], a, taper)
    sym = np.stack([body[..., 0] / fx, body[..., 1] / fy, body[..., 2]], -1)
    d1 = fn.radial_distance(sym, a, eps)
    if normals_world is None:
        return d1
    model = fn.normals_body(body, a, eps, taper)
    data = np.asarray(normals_world, dtype=np.float64) @ rotation  # into the body frame
    d2 = np.sum((data - model) ** 2, axis=-1)
    sigma = np.mean(np.asarray(a, dtype=np.float64), axis=-1)[..., None]
    return d1 + lam * sigma * d2


def error_of_fit(
    points_world: Array,
    normals_world: Array | None,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
) -> Array:
    """EOF ``D = mean(r_i^2)`` (SPEC §2), shape ``...`` of the parameters [m^2]."""
    r = contact_residuals(points_world, normals_world, a, eps, taper, rotation, center, lam)
    return np.mean(r**2, axis=-1)
