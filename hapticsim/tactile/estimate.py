"""Contact estimation from one pad's reading: location, normal, area, force and uncertainty.

The reading ``y`` [Pa] (after the sensor model) is turned back into depths ``d = y h / E`` (the
skin's inverse, :class:`~hapticsim.tactile.skin.SkinModel`). A taxel at ``p`` with outward normal
``m`` and depth ``d`` stands for the object surface point ``q = p - d m`` (the depth model,
:mod:`hapticsim.tactile.depth`).

**Curved pad** (a sphere, all shipped hands): where a rigid sphere sinks into a smooth object,
the deepest point of the undeformed skin lies on the contact normal, the line from the
fingertip's centre through the contact. The depth field around it is a paraboloid to second
order, ``d(u, v) ~ delta - (u, v) H (u, v)^T / 2``, so a quadratic fitted by least squares to the
lit taxels within :data:`WINDOW` taxels of the deepest one locates its peak ``(u*, v*)`` between
taxels; the pad's mapping gives the skin point ``p*`` and normal ``m*`` there, and

    point = p* - d* m*,   normal = -m*  (pointing out of the object).

With fewer than six lit taxels in the window, or a fitted field without a maximum near the
deepest taxel (a ridge along an edge), the depth-weighted centroid of the window's lit taxels
takes the peak's place.

**Flat pad**: the surface points ``q`` of the lit taxels are fitted by a plane (weighted by
depth); its normal, turned out of the object, is the normal and the weighted centroid of ``q``
the point. With fewer than three lit taxels the plate's normal and the deepest taxel's ``q``.

**Area and force**: the lit taxels' areas summed, and ``sum(y_i area_i)``.

**Uncertainty** ``sigma`` [m]: the per-coordinate standard deviation of the point, isotropic
(nML's per-contact noise, :func:`hapticsim.fitting.fit`'s ``sigma``): from the quadratic fit's
coefficient covariance (the residual variance, at least the sensor's depth noise
``sqrt(noise^2 + step^2 / 12) / (E / h)``), propagated to the peak's tangential position and its
depth (``sigma^2 = (var u* + var v* + var d*) / 3``); for the centroid fallback, a taxel's
uniform spread ``pitch / sqrt(12)`` along the surface. At least :data:`MIN_SIGMA`.

numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.tactile.pad import PadLayout
from hapticsim.tactile.skin import SkinModel

Array = NDArray[np.float64]

#: Half-width [taxels] of the window around the deepest taxel that the quadratic is fitted in.
WINDOW: int = 2
#: Largest distance [pitches] of the fitted peak from the deepest taxel.
PEAK_REACH: float = 1.5
#: RMS distance [m] of the lit taxels' surface points from their plane below which they count
#: as one face (plus twice the sensor's depth noise).
PLANE_TOLERANCE: float = 2e-5
#: Smallest ratio of the lit surface points' second spread to their first (standard
#: deviations) for a plane through them: a line of taxels along an edge spans none.
PLANE_SPREAD: float = 0.25
#: Farthest [pitches] the contact found on a face may lie from the nearest lit taxel.
PLANE_REACH: float = 2.0
#: Smallest per-contact sigma [m] reported.
MIN_SIGMA: float = 1e-6
#: Ways a contact was estimated (:attr:`TactileContact.method`).
METHODS: tuple[str, ...] = ("peak", "plane", "ridge", "taxel")


@dataclass(frozen=True)
class TactileContact:
    """A contact estimated from one pad's reading (module docstring).

    Attributes:
        point: (3,) float, the contact location on the object [m, world].
        normal: (3,) float, the object's outward unit normal there [world].
        force: normal force from the skin model [N].
        area: contact area, the lit taxels' area [m^2].
        sigma: per-coordinate standard deviation of `point` [m].
        depth: the skin's depth at the peak [m].
        taxels: number of lit taxels.
        method: how it was found (:data:`METHODS`).
    """

    point: Array
    normal: Array
    force: float
    area: float
    sigma: float
    depth: float
    taxels: int
    method: str


def _fit_quadratic(uv: Array, d: Array) -> tuple[Array, Array, float] | None:
    """Least-squares coefficients (6,) of ``c0 + cu u + cv v + cuu u^2 + cuv u v + cvv v^2``,
    the inverse normal matrix (6, 6) and the residual variance (None if rank deficient)."""
    u, v = uv[:, 0], uv[:, 1]
    design = np.column_stack([np.ones_like(u), u, v, u * u, u * v, v * v])
    normal = design.T @ design
    try:
        inv = np.linalg.inv(normal)
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(inv)) or np.linalg.cond(normal) > 1e12:
        return None
    coef = inv @ (design.T @ d)
    dof = max(len(d) - 6, 1)
    var = float(np.sum((design @ coef - d) ** 2) / dof)
    return coef, inv, var


def _peak(coef: Array) -> tuple[Array, float] | None:
    """Stationary point (2,) and value of a concave quadratic, or None."""
    c0, cu, cv, cuu, cuv, cvv = coef
    hess = np.array([[2.0 * cuu, cuv], [cuv, 2.0 * cvv]])
    if not (hess[0, 0] < 0 and np.linalg.det(hess) > 0):
        return None
    s = -np.linalg.solve(hess, np.array([cu, cv]))
    value = c0 + 0.5 * (cu * s[0] + cv * s[1])
    return s, float(value)


def _peak_covariance(coef: Array, cov: Array, s: Array) -> tuple[Array, float]:
    """Covariance (2, 2) of the peak position and variance of its value (delta method)."""
    jac = np.zeros((2, 6))
    step = 1e-7 * max(float(np.max(np.abs(coef))), 1e-12)
    for k in range(1, 6):
        bumped = coef.copy()
        bumped[k] += step
        peak = _peak(bumped)
        if peak is not None:
            jac[:, k] = (peak[0] - s) / step
    g_value = np.array([1.0, s[0], s[1], s[0] ** 2, s[0] * s[1], s[1] ** 2])
    return jac @ cov @ jac.T, float(g_value @ cov @ g_value)


def estimate_contact(
    reading: Array,
    layout: PadLayout,
    rotation: Array,
    translation: Array,
    skin: SkinModel,
    noise: float = 0.0,
    step: float = 0.0,
) -> TactileContact | None:
    """The contact one pad's reading stands for (module docstring), or None when no taxel is
    lit.

    Args:
        reading: (rows, cols) float, the pad's reading [Pa] (after the sensor model).
        layout: the pad's geometry in its carrier's frame.
        rotation: (3, 3) float, the carrier's orientation in the world (columns: its axes).
        translation: (3,) float, the carrier's origin [m, world].
        skin: the skin's elastic model (depth from pressure).
        noise: the sensor's noise std per taxel [Pa] (for `sigma`).
        step: the sensor's quantisation step [Pa] (for `sigma`).
    """
    y = np.asarray(reading, dtype=np.float64).reshape(layout.shape)
    lit = y > 0.0
    count = int(np.count_nonzero(lit))
    if count == 0:
        return None
    d = skin.depth(y)
    pos, nrm, area = layout.taxels
    rot = np.asarray(rotation, dtype=np.float64)
    t = np.asarray(translation, dtype=np.float64)
    force = float(np.sum(y * area))
    total_area = float(np.sum(area[lit]))
    sigma_depth = float(np.sqrt(noise**2 + step**2 / 12.0)) / skin.stiffness
    if layout.curved:
        point_c, normal_c, depth, sigma, method = _curved(y, d, lit, layout, sigma_depth)
    else:
        point_c, normal_c, depth, sigma, method = _flat(d, lit, pos, nrm, layout, sigma_depth)
    normal_w = rot @ normal_c
    return TactileContact(
        point=rot @ point_c + t, normal=normal_w / np.linalg.norm(normal_w), force=force,
        area=total_area, sigma=max(sigma, MIN_SIGMA), depth=depth, taxels=count, method=method,
    )  # fmt: skip


def _curved(
    y: Array, d: Array, lit: NDArray[np.bool_], layout: PadLayout, sigma_depth: float
) -> tuple[Array, Array, float, float, str]:
    """The contact on a curved pad (carrier frame): point, normal, depth, sigma, method."""
    i0, j0 = np.unravel_index(int(np.argmax(d)), d.shape)
    inner = 0 < i0 < layout.rows - 1 and 0 < j0 < layout.cols - 1
    if inner:  # the deepest taxel has neighbours all round: the peak lies on the pad
        found = _quadratic_peak(d, lit, layout, (i0, j0), sigma_depth)
        if found is not None:
            uv_peak, depth, sigma = found
            p, m = layout.map(uv_peak)
            return p - depth * m, -m, depth, sigma, "peak"
    pos, nrm, _ = layout.taxels
    q = (pos - d[..., None] * nrm)[lit]  # surface points of the lit taxels
    core = layout.origin
    plane = _plane(q) if len(q) >= 3 else None
    if plane is not None and plane[2] <= (PLANE_TOLERANCE + 2.0 * sigma_depth) ** 2:
        centre, normal, residual = plane  # one face: where a sphere about the core meets it
        if normal @ (core - centre) < 0:
            normal = -normal
        point = core - float(normal @ (core - centre)) * normal
        if np.min(np.linalg.norm(q - point, axis=1)) <= PLANE_REACH * layout.pitch:
            sigma = np.sqrt((residual + sigma_depth**2) / len(q) * 3.0
                            + layout.pitch**2 / (12.0 * len(q)))  # fmt: skip
            return point, normal, float(d.max()), float(sigma), "plane"
    uv_peak, depth = _ridge_peak(d, lit, layout, (i0, j0))  # an edge, or a few taxels
    p, m = layout.map(uv_peak)
    sigma = np.sqrt((2.0 * layout.pitch**2 / 12.0 + sigma_depth**2) / 3.0)
    return p - depth * m, -m, depth, float(sigma), "ridge"


def _ridge_peak(
    d: Array, lit: NDArray[np.bool_], layout: PadLayout, deepest: tuple[int, int]
) -> tuple[Array, float]:
    """The peak (u*, v*) [m] and depth [m] of a ridge of lit taxels (an edge of the object
    crossing the pad), or of a few lit taxels: within :data:`WINDOW` of the deepest taxel, a
    parabola through the depths along the lit taxels' major axis locates the peak along it,
    their depth-weighted mean across it."""
    i0, j0 = deepest
    rows = slice(max(i0 - WINDOW, 0), i0 + WINDOW + 1)
    cols = slice(max(j0 - WINDOW, 0), j0 + WINDOW + 1)
    window = lit[rows, cols]
    uv0 = layout.uv[i0, j0]
    uv = layout.uv[rows, cols][window] - uv0
    dw = d[rows, cols][window]
    w = dw / dw.sum()
    mean = w @ uv
    if len(dw) < 3:
        return uv0 + mean, float(dw.max())
    spread = (uv - mean).T @ ((uv - mean) * w[:, None])
    axes = np.linalg.eigh(spread)[1]
    major, minor = axes[:, 1], axes[:, 0]
    s, t = uv @ major, uv @ minor
    across = float(w @ t)
    if np.ptp(np.round(s / layout.pitch, 6)) > 0:
        c2, c1, c0 = np.polyfit(s / layout.pitch, dw, 2, w=np.sqrt(w))
        if c2 < 0:
            along = float(np.clip(-c1 / (2.0 * c2), s.min() / layout.pitch,
                                  s.max() / layout.pitch))  # fmt: skip
            peak = c0 + along * (c1 + c2 * along)
            return uv0 + along * layout.pitch * major + across * minor, float(max(peak, dw.max()))
    return uv0 + float(w @ s) * major + across * minor, float(dw.max())


def _quadratic_peak(
    d: Array, lit: NDArray[np.bool_], layout: PadLayout, deepest: tuple[int, int],
    sigma_depth: float,
) -> tuple[Array, float, float] | None:  # fmt: skip
    """The peak (u*, v*) [m], its depth [m] and sigma [m] of the quadratic fitted to the lit
    taxels within :data:`WINDOW` of the deepest one, or None (too few taxels, no maximum, or a
    maximum beyond :data:`PEAK_REACH`)."""
    i0, j0 = deepest
    rows = slice(max(i0 - WINDOW, 0), i0 + WINDOW + 1)
    cols = slice(max(j0 - WINDOW, 0), j0 + WINDOW + 1)
    window = lit[rows, cols]
    if np.count_nonzero(window) < 6:
        return None
    uv0 = layout.uv[i0, j0]
    uv = (layout.uv[rows, cols][window] - uv0) / layout.pitch  # in pitches (conditioning)
    dw = d[rows, cols][window]
    fit = _fit_quadratic(uv, dw)
    if fit is None:
        return None
    coef, inv, var = fit
    peak = _peak(coef)
    if peak is None or np.hypot(*peak[0]) > PEAK_REACH:
        return None
    cov = max(var, sigma_depth**2) * inv
    cov_s, var_value = _peak_covariance(coef, cov, peak[0])
    tangential = float(np.trace(cov_s)) * layout.pitch**2
    return uv0 + peak[0] * layout.pitch, peak[1], float(np.sqrt((tangential + var_value) / 3.0))


def _plane(q: Array) -> tuple[Array, Array, float] | None:
    """Centroid (3,), unit normal (3,) and mean squared residual [m^2] of the plane through
    points q (k, 3), or None when they lie on a line."""
    centre = q.mean(axis=0)
    sv, vecs = np.linalg.eigh((q - centre).T @ (q - centre))
    if sv[1] <= PLANE_SPREAD**2 * max(sv[2], 1e-300):
        return None
    return centre, vecs[:, 0], float(sv[0] / len(q))


def _flat(
    d: Array, lit: NDArray[np.bool_], pos: Array, nrm: Array, layout: PadLayout,
    sigma_depth: float,
) -> tuple[Array, Array, float, float, str]:  # fmt: skip
    """Plane through the surface points of a flat pad's lit taxels (carrier frame)."""
    q = (pos - d[..., None] * nrm)[lit]
    plane = _plane(q) if len(q) >= 3 else None
    if plane is None:
        peak = int(np.argmax(d[lit]))
        sigma = np.sqrt((2.0 * layout.pitch**2 / 12.0 + sigma_depth**2) / 3.0)
        return q[peak], -layout.normal, float(d[lit][peak]), float(sigma), "taxel"
    centre, normal, residual = plane
    if normal @ layout.normal > 0:
        normal = -normal
    sigma = np.sqrt((residual + sigma_depth**2) / len(q) + layout.pitch**2 / (12.0 * len(q)))
    return centre, normal, float(d[lit].max()), float(sigma), "plane"


__all__ = ["METHODS", "MIN_SIGMA", "PEAK_REACH", "TactileContact", "WINDOW", "estimate_contact"]
