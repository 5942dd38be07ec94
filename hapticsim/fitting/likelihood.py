"""The maximum-likelihood objective of nML: residuals weighted by the sensor noise, a robust loss,
weak priors and free space.

The noise model of SPEC §5: point noise of std ``sigma_p = sigma_N * mean(a)`` [m] per
coordinate, normal noise of std ``sigma_n = sigma_N`` per component (then renormalised). Under it
the negative log-likelihood of a surface is, up to constants, half the sum of squares of

- per contact i, ``d_i / sigma_p`` and the three components of ``e_i / sigma_n``, with
  ``d_i = (1 - s_i) / |grad log G(p_i)|`` [m] the first-order (Taubin) signed distance of the
  contact to the surface (``G = F^(eps1/2)`` the solid's gauge, ``s = 1/G`` the radial scale;
  exact for planes and spheres) and ``e_i = n'(p_i) / |n'(p_i)| - n_i`` the model's unit normal
  minus the measured one. The gauge is homogeneous of degree 1 along rays, so the model normal at
  ``p_i`` equals the one at the ray's surface point ``s_i p_i`` (exactly without taper);
- each contact's block is scaled by a pseudo-Huber factor (:attr:`Likelihood.robust` = c):
  ``rho(z) = 2 c^2 (sqrt(1 + z / c^2) - 1)`` of its squared norm z, quadratic below ``z ~ c^2``
  and linear in ``sqrt(z)`` above, so that a few bad contacts (a hull edge, a slipping fingertip)
  cannot pull the surface;
- priors, as residuals: ``t_x / tau_t``, ``t_y / tau_t`` (tapers near 0) and
  ``(eps_k - eps_0) / tau_e``: weak (the data's terms grow as 1/sigma_N^2, these do not), they
  only decide what the contacts leave undetermined;
- free space: per point q the fingertip passed through, ``max(0, margin - d(q)) / sigma_p``,
  zero while q is outside the solid.

``sigma_p / sigma_n = mean(a)`` does not depend on sigma_N, so the data terms alone have the same
minimiser at every noise level; sigma_N sets how much the priors, the robust threshold and the
free space count. When it is not given it is estimated from a fit's residuals
(:func:`estimate_noise`).

Contacts of different reliability (a tactile skin's estimates, each with its own standard
deviations ``sigma_i`` of the point [m] and ``sigma_n,i`` of the normal [rad],
:mod:`hapticsim.perception.tactile.estimate`) weigh in by their multipliers
(:func:`contact_weights`):
``median(sigma) / sigma_i`` on the distance and ``median(sigma_n) / sigma_n,i`` on the normal
residuals, each clipped to [1 / :data:`WEIGHT_RANGE`, :data:`WEIGHT_RANGE`], as if contact i's
noise were that much larger or smaller. The normals' level follows their ratio to the points'
(:func:`normal_ratio`, ``median(sigma_n) / median(sigma)``: ``sigma_n = ratio * sigma_p``)
instead of SPEC §5's ``sigma_n = sigma_p / mean(a)``: a pad's normal is as uncertain as its
point is along the surface, over the pad's radius, tens of times more than SPEC §5's model says.
The noise level sigma_N is still estimated (from the scaled distances), so the sigmas set the
contacts' relative weights and the normals' share, not the overall level, and a skin's
miscalibrated uncertainty cannot make the fit overconfident.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError
from hapticsim.fitting import _ml_compiled as kernel
from hapticsim.fitting.problem import Problem, problem_residuals
from hapticsim.geometry.eof import ContactSet
from hapticsim.geometry.rotations import rotvec_to_matrix
from hapticsim.geometry.superquadric import SLICE_A, SLICE_CENTER, SLICE_ROTVEC

Array = NDArray[np.float64]

#: Share of the largest |distances| the noise estimate leaves out.
TRIM: float = 0.1
#: Largest ratio of a contact's weight multiplier to the median's, either way.
WEIGHT_RANGE: float = 10.0
#: ``E[x^2 | |x| < z]`` for a standard normal x and ``P(|x| < z) = 1 - TRIM``:
#: ``1 - 2 z phi(z) / (1 - TRIM)`` with z = 1.6449.
TRIM_FACTOR: float = 0.6230


@dataclass(frozen=True)
class Likelihood:
    """Weights of the ML residuals (module docstring).

    Attributes:
        noise: relative noise level sigma_N, > 0.
        length: the length scale L [m], > 0: ``sigma_p = noise * length`` (SPEC §5: mean(a)).
        robust: pseudo-Huber threshold c on a contact's normalised residual norm, >= 0
            (0: plain squares).
        taper_prior: std tau_t of the Gaussian prior on each taper, > 0, or None.
        eps_prior: ``(eps_0, tau_e)`` of the Gaussian prior on each shape exponent, or None.
        free_margin: how far outside the solid [m] free-space points must lie (0: outside).
        multipliers: (2, n) float, each contact's weight multipliers of its distance (row 0)
            and its normal residuals (row 1) (:func:`contact_weights`), or None (all 1).
        anchor: (15,) float, the extent anchor (:func:`extent_anchor`): semi-axes A (3) [m],
            centre coordinates C (3) [m] along three unit directions u_k, then u_k (3 x 3, row
            by row); or None (no anchor).
        anchor_sigma: std tau_x [m] of the anchor's Gaussian prior on each semi-axis and
            centre coordinate, > 0 (used with `anchor`).
        normal_factor: ``sigma_n = normal_factor * noise``, > 0. The sensor's normal noise is
            sigma_N (factor 1), but the model normal is taken at the *measured* point: on a
            surface of curvature kappa the point noise moves it by ``kappa sigma_p`` per
            tangential component, about sigma_N again on a round body (``kappa ~ 1 / mean(a)``),
            0 on a flat face; a factor between 1 and sqrt(2) accounts for that.
    """

    noise: float
    length: float
    robust: float = 0.0
    taper_prior: float | None = None
    eps_prior: tuple[float, float] | None = None
    free_margin: float = 0.0
    normal_factor: float = 1.0
    multipliers: Array | None = None
    anchor: Array | None = None
    anchor_sigma: float = 1.0

    def __post_init__(self) -> None:
        for name in ("noise", "length", "normal_factor"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise InvalidInputError(f"`{name}` must be finite and > 0, got {value!r}")
        if not (np.isfinite(self.robust) and self.robust >= 0):
            raise InvalidInputError(f"`robust` must be finite and >= 0, got {self.robust!r}")
        if self.taper_prior is not None and not self.taper_prior > 0:
            raise InvalidInputError(f"`taper_prior` must be > 0 or None, got {self.taper_prior!r}")
        if self.eps_prior is not None and not (len(self.eps_prior) == 2 and self.eps_prior[1] > 0):
            raise InvalidInputError(
                f"`eps_prior` must be (eps_0, tau_e) with tau_e > 0, or None, got "
                f"{self.eps_prior!r}"
            )
        if not np.isfinite(self.free_margin):
            raise InvalidInputError(f"`free_margin` must be finite, got {self.free_margin!r}")
        if self.anchor is not None:
            anchor = np.asarray(self.anchor, dtype=np.float64)
            if anchor.shape != (kernel.ML_ANCHOR_SIZE,) or not np.all(np.isfinite(anchor)):
                raise InvalidInputError(
                    f"`anchor` must be ({kernel.ML_ANCHOR_SIZE},) finite, got shape {anchor.shape}"
                )
            if not (np.isfinite(self.anchor_sigma) and self.anchor_sigma > 0):
                raise InvalidInputError(
                    f"`anchor_sigma` must be finite and > 0, got {self.anchor_sigma!r}"
                )
        if self.multipliers is not None:
            m = np.asarray(self.multipliers, dtype=np.float64)
            if m.ndim != 2 or m.shape[0] != 2 or not np.all(np.isfinite(m)) or np.any(m <= 0):
                raise InvalidInputError("`multipliers` must be (2, n) finite and > 0")

    @property
    def point_sigma(self) -> float:
        """sigma_p [m]."""
        return self.noise * self.length

    def settings(self) -> Array:
        """The (ML_SETTINGS,) settings array of the compiled ML residuals
        (``_ml_compiled.ML_*``), with the per-contact multipliers after them
        ((ML_SETTINGS + 2 n,)) when there are any."""
        out = np.zeros(kernel.ML_SETTINGS)
        out[kernel.ML_POINT_WEIGHT] = 1.0 / self.point_sigma
        out[kernel.ML_NORMAL_WEIGHT] = 1.0 / (self.normal_factor * self.noise)
        out[kernel.ML_ROBUST] = self.robust
        if self.taper_prior is not None:
            out[kernel.ML_TAPER_WEIGHT] = 1.0 / self.taper_prior
        if self.eps_prior is not None:
            out[kernel.ML_EPS_CENTER] = self.eps_prior[0]
            out[kernel.ML_EPS_WEIGHT] = 1.0 / self.eps_prior[1]
        out[kernel.ML_FREE_WEIGHT] = 1.0 / self.point_sigma
        out[kernel.ML_FREE_MARGIN] = self.free_margin
        if self.anchor is not None:
            out[kernel.ML_ANCHOR_WEIGHT] = 1.0 / self.anchor_sigma
            out[kernel.ML_ANCHOR : kernel.ML_SETTINGS] = self.anchor
        if self.multipliers is not None:
            out = np.concatenate([out, np.asarray(self.multipliers, dtype=np.float64).ravel()])
        return out


def extent_anchor(start: Array, reference: Array) -> Array:
    """The extent anchor (:attr:`Likelihood.anchor`) that holds a fit started at `start` to the
    extents of `reference`.

    The directions u_k are the body axes of `start`; each takes the semi-axis of the
    `reference` axis most nearly parallel to it (so that a solid whose axes are named in
    another order is anchored to the same extents) and the reference centre's coordinate along
    it. A Gaussian prior on ``a_k - A_k`` and ``u_k . c - C_k`` then holds both faces of the
    solid along u_k near the reference's, where the contacts do not fix them.

    Args:
        start: (13,) parameter vector of the fit's start.
        reference: (13,) parameter vector of the solid to anchor to.

    Returns:
        (15,) float: A (3) [m], C (3) [m], u (3 x 3, row k = u_k).
    """
    axes = rotvec_to_matrix(np.asarray(start, dtype=np.float64)[SLICE_ROTVEC])
    ref = np.asarray(reference, dtype=np.float64)
    ref_axes = rotvec_to_matrix(ref[SLICE_ROTVEC])
    match = np.argmax(np.abs(ref_axes.T @ axes), axis=0)
    a = ref[SLICE_A][match]
    c = axes.T @ ref[SLICE_CENTER]
    return np.concatenate([a, c, axes.T.ravel()])


def anchor_gap(vector: Array, anchor: Array) -> Array:
    """The extent anchor's gaps (6,) [m] of a parameter vector (13,): ``a_k - A_k`` (3), then
    ``u_k . c - C_k`` (3) (:func:`extent_anchor`; the compiled ML residuals divide them by
    tau_x)."""
    v, held = np.asarray(vector, dtype=np.float64), np.asarray(anchor, dtype=np.float64)
    axes = held[6:].reshape(3, 3)
    return np.concatenate([v[SLICE_A] - held[:3], axes @ v[SLICE_CENTER] - held[3:6]])


def _relative(s: Array) -> Array:
    return np.clip(np.median(s) / s, 1.0 / WEIGHT_RANGE, WEIGHT_RANGE)


def contact_weights(sigma: Array, sigma_normal: Array | None = None) -> Array:
    """Weight multipliers (2, n) of contacts with standard deviations `sigma` (n,) [m] of the
    points and `sigma_normal` (n,) [rad] of the normals (module docstring): row 0
    ``median(sigma) / sigma_i``, row 1 ``median(sigma_normal) / sigma_normal_i`` (row 0 again
    without `sigma_normal`), clipped to [1 / WEIGHT_RANGE, WEIGHT_RANGE]."""
    point = _relative(np.asarray(sigma, dtype=np.float64))
    if sigma_normal is None:
        return np.stack([point, point])
    return np.stack([point, _relative(np.asarray(sigma_normal, dtype=np.float64))])


def normal_ratio(sigma: Array, sigma_normal: Array) -> float:
    """``median(sigma_normal) / median(sigma)`` [1/m]: the normals' noise per metre of the
    points' (module docstring)."""
    return float(np.median(sigma_normal) / np.median(sigma))


def contact_distances(contacts: ContactSet, vector: Array) -> Array:
    """The first-order signed distances d (n,) [m] of the contacts to a parameter vector's
    surface (positive outside; module docstring)."""
    plain = Likelihood(noise=1.0, length=1.0)
    problem = Problem.ml(contacts, plain.settings())
    return problem_residuals(contacts, problem, vector)[0, : contacts.count]


def estimate_noise(
    contacts: ContactSet, vector: Array, length: float, multipliers: Array | None = None
) -> float:
    """The relative noise level sigma_N estimated from a fit's residuals.

    From the distances alone, by a trimmed root mean square: with the :data:`TRIM` share of the
    largest ``|d|`` left out, ``sigma_N = sqrt(mean(d^2) / TRIM_FACTOR) / L``, ``TRIM_FACTOR``
    the mean of ``x^2`` over the central 90 % of a standard normal (0.6230), so that a few far
    contacts (a wrong patch of the fit, an outlier) do not count, at about 80 % of the
    efficiency of the plain RMS (the median absolute deviation has 37 %: measured +-10 % per
    estimate on 150 contacts). Not from the normal residuals: a contact within the point noise
    of an edge of a box-like solid (eps ~ 0.1) gets the neighbouring face's model normal, which
    inflates them (the paper's cube at sigma_N = 0.1: 0.127 from both terms at the true solid).
    The 13 fitted parameters take about 13 / n of the residual variance (9 % for 150
    contacts); not corrected.

    Args:
        contacts: the contacts.
        vector: (13,) the fit.
        length: L [m], the fit's mean semi-axis (SPEC §5's point-noise scale).
        multipliers: (2, n) per-contact weight multipliers (the distances are scaled by row 0:
            the noise level of a contact of multiplier 1), or None.
    """
    d = contact_distances(contacts, vector)
    if multipliers is not None:
        d = d * np.asarray(multipliers, dtype=np.float64)[0]
    d = np.sort(np.abs(d))
    kept = d[: max(1, int(round((1.0 - TRIM) * len(d))))]
    return float(np.sqrt(np.mean(kept**2) / TRIM_FACTOR) / length)


__all__ = [
    "TRIM",
    "TRIM_FACTOR",
    "WEIGHT_RANGE",
    "Likelihood",
    "anchor_gap",
    "contact_distances",
    "contact_weights",
    "estimate_noise",
    "extent_anchor",
    "normal_ratio",
]
