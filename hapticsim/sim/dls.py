"""Damped least squares (Levenberg-Marquardt) steps for fingertip position control."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def dls_step(jacobian: Array, error: Array, damping: float) -> Array:
    """Joint step ``dq = J^T (J J^T + lambda^2 I)^-1 e`` that moves a point by about `error`.

    Args:
        jacobian: (3, n) float, d(point)/d(q) [m/rad].
        error: (3,) float, desired displacement of the point [m].
        damping: lambda [m], > 0; trades accuracy near singularities for bounded steps.

    Returns:
        (n,) float, joint step [rad].
    """
    # Called every control tick for every finger: plain floats beat numpy's per-call overhead
    # on 3 x 3 problems by an order of magnitude. (3, 3) SPD inverse via the adjugate.
    j = np.asarray(jacobian, dtype=np.float64).tolist()
    r0, r1, r2 = j
    lam2 = damping * damping
    p = sum(x * x for x in r0) + lam2
    s = sum(x * x for x in r1) + lam2
    u = sum(x * x for x in r2) + lam2
    q = sum(x * y for x, y in zip(r0, r1, strict=True))
    r = sum(x * y for x, y in zip(r0, r2, strict=True))
    t = sum(x * y for x, y in zip(r1, r2, strict=True))
    c00, c01, c02 = s * u - t * t, r * t - q * u, q * t - r * s
    c11, c12, c22 = p * u - r * r, q * r - p * t, p * s - q * q
    det = p * c00 + q * c01 + r * c02
    e0, e1, e2 = np.asarray(error, dtype=np.float64).tolist()
    y0 = (c00 * e0 + c01 * e1 + c02 * e2) / det
    y1 = (c01 * e0 + c11 * e1 + c12 * e2) / det
    y2 = (c02 * e0 + c12 * e1 + c22 * e2) / det
    return np.array([a * y0 + b * y1 + c * y2 for a, b, c in zip(r0, r1, r2, strict=True)])


__all__ = ["dls_step"]
