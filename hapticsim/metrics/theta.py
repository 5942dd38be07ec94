"""Minimisation quality theta (paper eq. 10, SPEC §4)."""

from __future__ import annotations

from typing import Any

import numpy as np

from hapticsim._validate import finite_float, normals_array, points_array
from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.geometry import Superquadric
from hapticsim.geometry.eof import error_of_fit
from hapticsim.geometry.superquadric import superquadric_arg


def _eof(sq: Superquadric, points: Any, normals: Any, lam: float) -> float:
    return float(error_of_fit(points, normals, sq.a, sq.eps, sq.taper, sq.rotation, sq.center, lam))


def theta(
    estimate: Superquadric,
    truth: Superquadric,
    points: Any,
    normals: Any | None = None,
    lam: float = DEFAULT_LAMBDA,
) -> float:
    """``theta = D(S_e) / (D(S_s) + 1)`` (paper eq. 10), D the error of fit on the (noisy) data.

    D is the EOF of SPEC §2 (paper eq. 9) with normals, or ``mean(D1^2)`` without them (the
    paper's theta^(1)); both are in m^2, so theta is about D(S_e) for data in metres. theta > 1
    means the estimate does not reach the EOF of the truth.

    Args:
        estimate: the estimated superquadric S_e.
        truth: the true superquadric S_s.
        points: (n, 3) float, contact points [m, world].
        normals: (n, 3) float outward normals (normalised here), or None.
        lam: weight lambda of the normal term, finite and >= 0.

    Returns:
        theta, >= 0.
    """
    estimate = superquadric_arg(estimate, "estimate")
    truth = superquadric_arg(truth, "truth")
    pts = points_array(points, "points", min_count=1)
    nrm = None if normals is None else normals_array(normals, len(pts))
    weight = finite_float(lam, "lam", low=0.0)
    return _theta(estimate, truth, pts, nrm, weight)


def theta_checked(
    estimate: Superquadric, truth: Superquadric, points: Any, normals: Any | None, lam: float
) -> float:
    """:func:`theta` of arguments checked already (two superquadrics, (n, 3) points, non-zero
    normals or None, lam >= 0): for a caller that validated its inputs once at its own entry
    (:func:`hapticsim.exploration.run_trial`). The normals are normalised here as
    :func:`theta` normalises them (the same arithmetic, so the same digits)."""
    if normals is not None:
        normals = normals / np.linalg.norm(normals, axis=1)[:, None]
    return _theta(estimate, truth, points, normals, lam)


def _theta(
    estimate: Superquadric, truth: Superquadric, points: Any, normals: Any | None, lam: float
) -> float:
    return _eof(estimate, points, normals, lam) / (_eof(truth, points, normals, lam) + 1.0)


__all__ = ["theta", "theta_checked"]
