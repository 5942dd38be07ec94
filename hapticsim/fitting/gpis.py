"""The field's baseline: a Gaussian-process implicit surface (GPIS) from points and normals.

An implicit function f, negative inside, zero on the surface and growing outward, gets a GP prior
around a sphere: in coordinates u = (x - c) / R (c the contacts' centroid, R their mean distance
from it), f(u) = (|u|^2 - 1) / 2 + g(u) with g ~ GP(0, s^2 k), k the squared exponential of length
scale l. Each contact observes f = 0 (noise s_v) and each normal the gradient of f (noise s_g): a
joint Gaussian of 4n values, whose covariance holds the kernel's first and second derivatives.
The hyperparameters (l, s_v, s_g; s^2 profiled out) maximise the marginal likelihood
(Nelder-Mead on their logarithms). The estimate is the zero level set of the posterior mean on a
grid around the contacts, meshed by marching cubes (scikit-image, extra ``gpis``), its largest
closed piece as a :class:`~hapticsim.geometry.MeshSolid`: the same metrics score it as any solid.

:func:`fit_gpis` returns it with its hyperparameters and time. Tables against nH and nML:
``docs/gpis.md`` (``python scripts/gpis_table.py``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hapticsim._validate import normals_array, physical_points, positive_int
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import MeshSolid

#: Grid cells per axis of the level set, and the margin of the grid around the contacts' box
#: (a fraction of R).
RESOLUTION: int = 40
MARGIN: float = 0.35
#: Floors of log(l / R, s_v / R, s_g): noise-free data would drive the noises to 0 and the
#: covariance to singular.
LOG_FLOOR: np.ndarray = np.log([0.02, 1e-4, 1e-3])
#: Most contacts a GPIS takes: its covariance is 4n x 4n and every likelihood evaluation factors
#: it (measured here: 150 contacts 4 s, 300 contacts 15 s, 600 contacts 57 s).
MAX_GPIS_CONTACTS: int = 400
#: Starting hyperparameters (length scale in units of R, value noise in R, gradient noise).
START: tuple[float, float, float] = (0.6, 0.01, 0.1)


@dataclass(frozen=True)
class GpisFit:
    """A GPIS estimate.

    Attributes:
        solid: the zero level set of the posterior mean, a closed mesh [m, world].
        length_scale: l [m]; value_noise: s_v [m]; gradient_noise: s_g (unitless).
        log_likelihood: the maximised marginal log-likelihood.
        seconds: wall-clock time of the fit [s].
    """

    solid: Any
    length_scale: float
    value_noise: float
    gradient_noise: float
    log_likelihood: float
    seconds: float
    info: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (the mesh's size, not its vertices)."""
        return {
            "method": "gpis", "length_scale": self.length_scale, "value_noise": self.value_noise,
            "gradient_noise": self.gradient_noise, "log_likelihood": self.log_likelihood,
            "seconds": self.seconds, "vertices": int(len(self.solid.vertices)),
            "faces": int(len(self.solid.faces)),
        }  # fmt: skip


def _kernel_blocks(u: np.ndarray, v: np.ndarray, length: float) -> tuple[np.ndarray, ...]:
    """k (n, m), its derivative in v (n, m, 3) and, for u is v, the second derivative blocks."""
    d = u[:, None, :] - v[None, :, :]
    k = np.exp(-np.sum(d * d, axis=2) / (2 * length**2))
    dk = k[:, :, None] * d / length**2  # cov(f(u), grad f(v))
    return k, dk, d


def _covariance(u: np.ndarray, length: float, noise_v: float, noise_g: float) -> np.ndarray:
    """The (4n, 4n) covariance of [f(u_i); grad f(u_i)] per unit prior variance, with noise."""
    n = len(u)
    k, dk, d = _kernel_blocks(u, u, length)
    kgg = k[:, :, None, None] * (
        np.eye(3)[None, None] / length**2 - d[:, :, :, None] * d[:, :, None, :] / length**4
    )
    cov = np.empty((4 * n, 4 * n))
    cov[:n, :n] = k
    cov[:n, n:] = dk.reshape(n, 3 * n)
    cov[n:, :n] = cov[:n, n:].T
    cov[n:, n:] = kgg.transpose(0, 2, 1, 3).reshape(3 * n, 3 * n)
    cov[np.diag_indices(n)] += noise_v**2
    idx = np.arange(n, 4 * n)
    cov[idx, idx] += noise_g**2
    return cov


def _profiled(theta: np.ndarray, u: np.ndarray, y: np.ndarray) -> tuple[float, Any]:
    """Negative profiled log-likelihood of log(l, s_v, s_g) and the factor behind it."""
    from scipy.linalg import cho_factor, cho_solve

    length, nv, ng = np.exp(np.maximum(theta, LOG_FLOOR))
    try:
        factor = cho_factor(_covariance(u, length, nv, ng), lower=True, check_finite=False)
    except np.linalg.LinAlgError:
        return 1e30, None
    alpha = cho_solve(factor, y, check_finite=False)
    m = len(y)
    scale = float(y @ alpha) / m  # s^2, profiled out
    logdet = 2.0 * float(np.sum(np.log(np.diag(factor[0]))))
    return 0.5 * (m * np.log(scale) + logdet + m), (factor, alpha, scale)


def require_marching_cubes() -> Any:
    """scikit-image's ``marching_cubes``, or one line saying how to install it.

    Raises:
        InvalidInputError: scikit-image is not installed.
    """
    try:
        from skimage.measure import marching_cubes
    except ImportError:
        raise InvalidInputError("GPIS needs scikit-image: pip install 'hapticsim[gpis]'") from None
    return marching_cubes


def fit_gpis(
    points: Any, normals: Any, resolution: int = RESOLUTION, max_iterations: int = 80,
) -> GpisFit:  # fmt: skip
    """Fit a GPIS to contacts and their outward normals (module docstring).

    Args:
        points: (n, 3) contacts [m]; normals: (n, 3) outward normals.
        resolution: grid cells per axis of the level set (>= 16).
        max_iterations: Nelder-Mead iterations of the hyperparameters.

    Raises:
        InvalidInputError: bad arrays, more than :data:`MAX_GPIS_CONTACTS` contacts,
            scikit-image missing (``pip install 'hapticsim[gpis]'``), or no closed level set
            (the message says so).
    """
    from scipy.optimize import minimize

    marching_cubes = require_marching_cubes()
    pts = physical_points(points, "points", min_count=4)
    if len(pts) > MAX_GPIS_CONTACTS:
        raise InvalidInputError(
            f"GPIS takes at most {MAX_GPIS_CONTACTS} contacts (its covariance is 4n x 4n: "
            f"minutes beyond), got {len(pts)}; subsample them"
        )
    nrm = normals_array(normals, len(pts), "normals")
    res = positive_int(resolution, "resolution", minimum=16, maximum=160)
    start = time.perf_counter()
    center = pts.mean(axis=0)
    radius = float(np.mean(np.linalg.norm(pts - center, axis=1)))
    u = (pts - center) / radius
    n = len(u)
    # observations of g = f - prior: f = 0 at the contacts, grad f = normal
    y = np.concatenate([-(np.sum(u * u, axis=1) - 1.0) / 2.0, (nrm - u).reshape(-1)])
    best = minimize(lambda t: _profiled(t, u, y)[0], np.log(START), method="Nelder-Mead",
                    options={"maxiter": max_iterations, "xatol": 1e-3, "fatol": 1e-3})  # fmt: skip
    nll, (factor, alpha, scale) = _profiled(best.x, u, y)
    length, nv, ng = np.exp(np.maximum(best.x, LOG_FLOOR))
    # the posterior mean on a grid around the contacts
    lo = u.min(axis=0) - MARGIN
    hi = u.max(axis=0) + MARGIN
    axes = [np.linspace(lo[k], hi[k], res + 1) for k in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    mean = np.empty(len(grid))
    for s in range(0, len(grid), 8192):
        g = grid[s:s + 8192]
        k, dk, _ = _kernel_blocks(g, u, length)
        # cov(f(x), grad f(u_j)) = k (x - u_j) / l^2: dk
        cross = np.concatenate([k, dk.reshape(len(g), 3 * n)], axis=1)
        mean[s:s + 8192] = (np.sum(g * g, axis=1) - 1.0) / 2.0 + cross @ alpha
    volume = mean.reshape(res + 1, res + 1, res + 1)
    if not (volume.min() < 0.0 < volume.max()):
        raise InvalidInputError("GPIS: the posterior mean has no zero level set in the grid")
    volume[[0, -1], :, :] = volume[:, [0, -1], :] = volume[:, :, [0, -1]] = max(volume.max(), 1.0)
    spacing = tuple(float(a[1] - a[0]) for a in axes)
    verts, faces, _, _ = marching_cubes(volume, level=0.0, spacing=spacing)
    solid = _largest_closed_piece(verts + lo, faces, center, radius)
    return GpisFit(
        solid=solid, length_scale=float(length * radius), value_noise=float(nv * radius),
        gradient_noise=float(ng), log_likelihood=float(-nll),
        seconds=time.perf_counter() - start,
        info={"iterations": int(best.nit), "converged": bool(best.success),
              "prior_scale": float(scale)},
    )  # fmt: skip


def _largest_closed_piece(verts: np.ndarray, faces: np.ndarray, center: np.ndarray,
                          radius: float) -> Any:  # fmt: skip
    import trimesh

    mesh = trimesh.Trimesh(verts * radius + center, faces[:, ::-1], process=True)
    pieces = list(mesh.split(only_watertight=True))
    if not pieces:
        raise InvalidInputError("GPIS: the zero level set has no closed piece")
    piece = max(pieces, key=lambda p: abs(p.volume))
    trimesh.repair.fix_normals(piece)  # outward
    return MeshSolid(np.asarray(piece.vertices), np.asarray(piece.faces))


__all__ = ["MAX_GPIS_CONTACTS", "GpisFit", "fit_gpis"]
