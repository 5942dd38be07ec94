"""How uncertain a fitted superquadric is: a Laplace approximation at the optimum (SPEC §6).

The fit minimises a sum of squared residuals r(θ) over the 13 parameters θ (SPEC §2: the
contacts' radial distances and, for nLS, nH and nML, their normals' term). Near the optimum θ*
the residuals are linear, r(θ) ≈ r(θ*) + J (θ - θ*), so with Gaussian residuals of one variance

    s² = |r(θ*)|² / (m - 13),    Σ = s² (JᵀJ)⁺

is the covariance of θ (m residuals; J by central differences of the fit's residuals; the
pseudo-inverse leaves
directions the data do not fix at zero variance, which is what one-sided data would make
infinite: see :attr:`Uncertainty.rank`). From Σ, :func:`laplace` draws parameter vectors (a
fixed seed), clipped into the fitter's bounds, and reports per-parameter standard deviations
(the rotation as the rotation vector from the estimate to each draw), the volume's mean and 50 %
and 90 % intervals, and 90 % intervals of the semi-axes. nML is scored on the same residuals
(its own likelihood weighs them differently; the approximation is then rougher); ``multi``'s
unions have none.

How often the intervals hold the truth is measured in ``docs/uncertainty.md``
(``python scripts/uncertainty_table.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from hapticsim.fitting.objective import Bounds
from hapticsim.geometry import Superquadric, rotvec_to_matrix
from hapticsim.geometry import functions as fn
from hapticsim.geometry.eof import ContactSet, check_distance
from hapticsim.geometry.superquadric import (
    N_PARAMS,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
)

#: Central-difference step, relative to the parameter's scale (the data size for lengths).
STEP: float = 1e-6
#: Draws from the Laplace posterior behind the intervals (a fixed seed: the same fit, the same
#: intervals).
DRAWS: int = 2000
DRAW_SEED: int = 20260
METHOD: str = "laplace"


@dataclass(frozen=True)
class Uncertainty:
    """The Laplace approximation of one fit (module docstring).

    Attributes:
        covariance: (13, 13) of the parameter vector (``Superquadric.to_vector`` order).
        noise: s, the residuals' estimated standard deviation.
        rank: rank of JᵀJ (13: every direction fixed by the data).
        draws: (DRAWS, 13) parameter vectors drawn from it, clipped into the bounds.
        volumes: (DRAWS,) their volumes [m^3].
        rotation_draws: (DRAWS, 3) rotation vector from the estimate's rotation to each draw's
            [rad].
    """

    covariance: np.ndarray
    noise: float
    rank: int
    draws: np.ndarray
    volumes: np.ndarray
    rotation_draws: np.ndarray

    def interval(self, values: np.ndarray, level: float) -> list[float]:
        """The central interval holding `level` of `values`."""
        lo, hi = np.quantile(values, [(1 - level) / 2, (1 + level) / 2])
        return [float(lo), float(hi)]

    def to_dict(self) -> dict[str, Any]:
        """SPEC §6's ``"uncertainty"`` block (m, m^3, rad), with its method."""
        d = self.draws
        std = d.std(axis=0)
        return {
            "method": METHOD,
            "std": {
                "a": std[SLICE_A].tolist(), "eps": std[SLICE_EPS].tolist(),
                "taper": std[SLICE_TAPER].tolist(), "center": std[SLICE_CENTER].tolist(),
                "rotation": self.rotation_draws.std(axis=0).tolist(),
            },
            "volume": {
                "mean": float(self.volumes.mean()),
                "interval50": self.interval(self.volumes, 0.5),
                "interval90": self.interval(self.volumes, 0.9),
            },
            "a": {"interval90": [self.interval(d[:, k], 0.9) for k in range(3)]},
            "noise": self.noise,
            "rank": self.rank,
            "draws": int(len(d)),
        }  # fmt: skip


def laplace(
    estimate: Superquadric, points: np.ndarray, normals: np.ndarray | None, lam: float,
    distance: str,
) -> Uncertainty:  # fmt: skip
    """The Laplace approximation at `estimate` of the residuals the fit minimised.

    Args:
        estimate: the fitted superquadric.
        points: (n, 3) contacts [m]; normals: (n, 3) or None (LS, H).
        lam: the normals' weight; distance: the search distance (``"tapered"``/``"untapered"``).
    """
    bounds = Bounds.from_points(points)
    theta = estimate.to_vector()
    contacts = ContactSet.from_arrays(points, normals)
    tapered = check_distance(distance)
    h = STEP * bounds.scale
    r = contacts.residuals(np.vstack([theta[None], theta + np.diag(h), theta - np.diag(h)]),
                           lam, tapered)  # fmt: skip
    r0, rp, rm = r[0], r[1:1 + N_PARAMS], r[1 + N_PARAMS:]
    jac = ((rp - rm) / (2 * h[:, None])).T  # (m, 13)
    m = len(r0)
    s2 = float(r0 @ r0) / max(m - N_PARAMS, 1)
    jtj = jac.T @ jac
    # scale to unit columns before the pseudo-inverse: lengths and angles differ by 1e3
    d = np.sqrt(np.maximum(np.diag(jtj), 1e-300))
    scaled = jtj / np.outer(d, d)
    rank = int(np.linalg.matrix_rank(scaled, tol=1e-10))
    cov = s2 * np.linalg.pinv(scaled, rcond=1e-10) / np.outer(d, d)
    cov = (cov + cov.T) / 2
    gen = np.random.default_rng(DRAW_SEED)
    values, vectors = np.linalg.eigh(cov)
    root = vectors * np.sqrt(np.clip(values, 0.0, None))
    draws = theta + gen.standard_normal((DRAWS, N_PARAMS)) @ root.T
    draws = np.clip(draws, bounds.lower, bounds.upper)
    from scipy.spatial.transform import Rotation

    base = Rotation.from_matrix(rotvec_to_matrix(theta[SLICE_ROTVEC]))
    rot = (base.inv() * Rotation.from_rotvec(draws[:, SLICE_ROTVEC])).as_rotvec()
    volumes = np.array([fn.volume(v[SLICE_A], v[SLICE_EPS], v[SLICE_TAPER]) for v in draws])
    return Uncertainty(covariance=cov, noise=float(np.sqrt(s2)), rank=rank, draws=draws,
                       volumes=volumes, rotation_draws=rot)  # fmt: skip


__all__ = ["DRAWS", "METHOD", "Uncertainty", "laplace"]
