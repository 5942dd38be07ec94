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

from hapticsim.fitting.likelihood import Likelihood
from hapticsim.fitting.objective import Bounds
from hapticsim.fitting.problem import Problem, problem_jacobian
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


def posterior_covariance(
    estimate: Superquadric, points: np.ndarray, normals: np.ndarray | None, lam: float,
    distance: str,
) -> tuple[np.ndarray, float, int]:  # fmt: skip
    """The Laplace covariance at `estimate` of the residuals the fit minimised (module
    docstring): ``(covariance (13, 13), residual noise s, rank)``.

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
    return cov, float(np.sqrt(s2)), rank


def laplace(
    estimate: Superquadric, points: np.ndarray, normals: np.ndarray | None, lam: float,
    distance: str,
) -> Uncertainty:  # fmt: skip
    """The Laplace approximation at `estimate` of the residuals the fit minimised
    (:func:`posterior_covariance`), with :data:`DRAWS` fixed-seed draws from it.

    Args:
        estimate: the fitted superquadric.
        points: (n, 3) contacts [m]; normals: (n, 3) or None (LS, H).
        lam: the normals' weight; distance: the search distance (``"tapered"``/``"untapered"``).
    """
    cov, noise, rank = posterior_covariance(estimate, points, normals, lam, distance)
    bounds = Bounds.from_points(points)
    theta = estimate.to_vector()
    gen = np.random.default_rng(DRAW_SEED)
    values, vectors = np.linalg.eigh(cov)
    root = vectors * np.sqrt(np.clip(values, 0.0, None))
    draws = theta + gen.standard_normal((DRAWS, N_PARAMS)) @ root.T
    draws = np.clip(draws, bounds.lower, bounds.upper)
    from scipy.spatial.transform import Rotation

    base = Rotation.from_matrix(rotvec_to_matrix(theta[SLICE_ROTVEC]))
    rot = (base.inv() * Rotation.from_rotvec(draws[:, SLICE_ROTVEC])).as_rotvec()
    volumes = np.array([fn.volume(v[SLICE_A], v[SLICE_EPS], v[SLICE_TAPER]) for v in draws])
    return Uncertainty(covariance=cov, noise=noise, rank=rank, draws=draws, volumes=volumes,
                       rotation_draws=rot)  # fmt: skip


def with_prior(covariance: np.ndarray, size: float) -> np.ndarray:
    """The posterior covariance (13, 13) combined with a broad Gaussian prior: std `size` [m] on
    the semi-axes and the centre, 1 on the exponents and tapers, pi on the rotation vector.

    A Laplace covariance is unbounded along what the contacts do not fix (the rotation of a
    round cross-section about its axis, a shape exponent no edge shows): there it takes the
    prior's variance instead, ``Sigma (I + P^-1 Sigma)^-1`` in the prior's units, computed by an
    eigendecomposition so that infinite or huge variances stay finite.
    """
    std = np.ones(N_PARAMS)
    std[SLICE_A] = std[SLICE_CENTER] = size
    std[SLICE_ROTVEC] = np.pi
    scaled = np.nan_to_num(covariance / np.outer(std, std), nan=0.0, posinf=1e300, neginf=-1e300)
    values, vectors = np.linalg.eigh((scaled + scaled.T) / 2)
    values = np.clip(values, 0.0, None)
    shrunk = (vectors * (values / (1.0 + values))) @ vectors.T
    return shrunk * np.outer(std, std)


def expected_information(
    estimate: Superquadric, covariance: np.ndarray, noise: float, points: np.ndarray,
    normals: np.ndarray | None = None,
) -> np.ndarray:  # fmt: skip
    """Expected information [nats] of one more contact at each of k points on the estimate.

    A contact at p with normal n observes the orthogonal distance d (noise ``sigma_p = s``) and
    the unit normal (noise ``sigma_n = s / mean(a)`` per component, SPEC §5's ratio) with the
    Jacobian J (4, 13) of the ML residuals (:mod:`hapticsim.fitting.likelihood`) at the
    estimate; under the Gaussian posterior of covariance Sigma its expected information is the
    entropy drop ``0.5 log det(I + W J Sigma J^T W)``, ``W = diag(1/sigma_p, 1/sigma_n x 3)``
    (D-optimal design): large where the posterior lets the surface move, small where contacts
    already pin it.

    Args:
        estimate: the current superquadric.
        covariance: (13, 13) its posterior covariance (:func:`posterior_covariance`).
        noise: s [m], the residual noise (:func:`posterior_covariance`), > 0.
        points: (k, 3) candidate contacts on the estimate's surface [m].
        normals: (k, 3) their outward normals, or None (the estimate's at the points).

    Returns:
        (k,) float, >= 0 (0 where the estimate has no gradient, or the covariance is not
        finite).
    """
    j, ok = _contact_jacobians(estimate, noise, points, normals)
    out = np.zeros(len(j))
    if np.any(ok) and np.all(np.isfinite(covariance)):
        gain = np.eye(4)[None] + np.einsum("kap,pq,kbq->kab", j[ok], covariance, j[ok])
        out[ok] = 0.5 * np.linalg.slogdet(gain)[1]
    return out


#: Surface points over which :func:`expected_surface_reduction` sums the variance.
SURFACE_SAMPLES: int = 256


def expected_surface_reduction(
    estimate: Superquadric, covariance: np.ndarray, noise: float, points: np.ndarray,
    normals: np.ndarray | None = None,
) -> np.ndarray:  # fmt: skip
    """Expected drop [m^2] of the surface's positional variance from one more contact at each
    of k points on the estimate.

    The variance of the estimate's surface along its normal, summed over
    :data:`SURFACE_SAMPLES` points q_j spread over it (``sum_j g_j^T Sigma g_j``, g_j the
    gradient of q_j's orthogonal distance), falls with a contact of whitened Jacobian J
    (:func:`expected_information`) by ``trace(J Sigma G^T G Sigma J^T (J Sigma J^T + I)^-1)``:
    the shape's uncertainty where it decides the volume metrics, instead of every parameter's
    (rotation and exponents included) as the entropy weighs them.

    Args: as :func:`expected_information`.

    Returns:
        (k,) float [m^2 summed over the samples], >= 0.
    """
    j, ok = _contact_jacobians(estimate, noise, points, normals)
    out = np.zeros(len(j))
    if not (np.any(ok) and np.all(np.isfinite(covariance))):
        return out
    surface, surface_normals = estimate.sample_surface(SURFACE_SAMPLES, np.random.default_rng(0))
    g, g_ok = _contact_jacobians(estimate, 1.0, surface, surface_normals)
    g = g[g_ok, 0, :]  # (m, 13) [1]: the distance rows
    middle = covariance @ (g.T @ g) @ covariance
    s = np.eye(4)[None] + np.einsum("kap,pq,kbq->kab", j[ok], covariance, j[ok])
    a = np.einsum("kap,pq,kbq->kab", j[ok], middle, j[ok])
    out[ok] = np.einsum("kaa->k", np.linalg.solve(s, a))
    return out


def _contact_jacobians(
    estimate: Superquadric, noise: float, points: np.ndarray, normals: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """(k, 4, 13): the ML residuals (d, e_x, e_y, e_z) of a contact at each point, whitened by
    ``sigma_p = noise`` and ``sigma_n = noise / mean(a)``, differentiated by the parameters;
    and (k,) bool, where they are finite (a point on a crease of the estimate, where its
    gradient is undefined, has none: it counts as telling nothing)."""

    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    k = len(pts)
    if k == 0:
        return np.empty((0, 4, N_PARAMS)), np.empty(0, dtype=bool)
    nrm = estimate.normals(pts) if normals is None else np.asarray(normals, dtype=np.float64)
    contacts = ContactSet.from_arrays(pts, nrm)
    problem = Problem.ml(contacts, Likelihood(noise=1.0, length=1.0).settings())
    _, jac = problem_jacobian(contacts, problem, estimate.to_vector())
    sigma_p = max(float(noise), 1e-12)
    weights = np.array([1.0 / sigma_p] + [float(np.mean(estimate.a)) / sigma_p] * 3)
    rows = np.arange(k)[:, None] + k * np.arange(4)[None, :]  # d, e_x, e_y, e_z of each
    j = jac[rows] * weights[None, :, None]
    return j, np.all(np.isfinite(j), axis=(1, 2))


__all__ = [
    "DRAWS",
    "METHOD",
    "Uncertainty",
    "SURFACE_SAMPLES",
    "expected_information",
    "expected_surface_reduction",
    "laplace",
    "posterior_covariance",
    "with_prior",
]
