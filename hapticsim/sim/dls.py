"""Damped least squares (Levenberg-Marquardt) steps for fingertip position control."""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def dls_step(jacobian: Array, error: Array, damping: float) -> Array:
    """Joint step ``dq = J^T (J J^T + lambda^2 I)^-1 e`` that moves a point by about `error`.

    Args:
        jacobian: (3, n) float, d(point)/d(q) [m/rad], any number n of joints.
        error: (3,) float, desired displacement of the point [m].
        damping: lambda [m], > 0; trades accuracy near singularities for bounded steps.

    Returns:
        (n,) float, joint step [rad].
    """
    # Called every control tick for every finger: MuJoCo's small dense-matrix routines (a
    # Cholesky solve of the (3, 3) system) cost a few microseconds where numpy's per-call
    # overhead costs several times that.
    jac = np.ascontiguousarray(jacobian, dtype=np.float64)
    gram = np.empty((3, 3))
    mujoco.mju_mulMatMatT(gram, jac, jac)
    lam2 = damping * damping
    gram[0, 0] += lam2
    gram[1, 1] += lam2
    gram[2, 2] += lam2
    mujoco.mju_cholFactor(gram, 0.0)
    y = np.empty(3)
    mujoco.mju_cholSolve(y, gram, np.ascontiguousarray(error, dtype=np.float64))
    step = np.empty(jac.shape[1])
    mujoco.mju_mulMatTVec(step, jac, y)
    return step


__all__ = ["dls_step"]
