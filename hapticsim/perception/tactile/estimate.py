"""Contact estimation from one pad's reading: location, normal, area, force and uncertainty.

The reading ``y`` [Pa] (after the sensor model) is turned back into depths ``d = y h / E`` (the
skin's inverse, :class:`~hapticsim.perception.tactile.skin.SkinModel`; under its layer law the
layer's sinking under the reading, the depth where a taxel is pressed). A taxel at ``p`` with
outward normal
``m`` and depth ``d`` stands for the object surface point ``q = p - d m`` (the depth model,
:mod:`hapticsim.perception.tactile.depth`).

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

**Uncertainty**: ``sigma`` [m], the standard deviation of the point's distance from the
object's surface (along the normal: what nML's distance residual measures, :func:`hapticsim.
fitting.fit`'s ``sigma``), and ``sigma_normal`` [rad], that of the normal per tangential axis
(its ``sigma_normal``). Each is what the fit propagates plus a floor of the model's own error:

- the sensor's depth noise per taxel, ``sqrt(noise^2 + step^2 / 12 + (gain_spread y)^2) / (E /
  h)`` at the deepest taxel, is the least residual variance of the fits;
- peak: the variance of the fitted peak's depth, and of its tangential position over the pad's
  radius R for the normal (on a sphere the normal is the pad's at the peak); the sensor's
  crosstalk (a Gaussian blur of std b) lowers a quadratic field by ``b^2 |tr H| / 2``, which is
  added back to the peak's depth, a quarter of it counted as its standard deviation;
- plane: the plane's offset and slope variances;
- ridge: the sensor's depth noise, and a taxel's uniform spread ``pitch / sqrt(12)`` across the
  ridge over R for the normal;
- floors ``MODEL_DEPTH * pitch`` and ``MODEL_NORMAL * pitch / R`` (a flat pad: over half its
  extent), the quadratic's and the grid's own error, measured on the tuning family (paper bodies,
  seed 0, ideal skin; docs/tactile/README.md).

A pad's normal is tens of times less certain than SPEC §5's noise model makes it
(``sigma_n = sigma_p / mean(a)``): nML weighs the normals by ``sigma_normal``.

numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.perception.tactile.pad import PadLayout
from hapticsim.perception.tactile.skin import SensorModel, SkinModel

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
#: Floor of sigma [pitches]: the model's own error of a contact's distance from the surface.
MODEL_DEPTH: float = 0.007
#: Floor of sigma_normal [pitch / R]: the model's own error of the normal.
MODEL_NORMAL: float = 0.09
#: Share of the blur correction of a peak's depth counted as its standard deviation (the
#: correction is exact for a quadratic field; measured on the vision skin's tuning family the
#: corrected distances' RMS was 0.3 of the whole correction).
BLUR_UNCERTAINTY: float = 0.25
#: Smallest per-contact sigma [m] reported.
MIN_SIGMA: float = 1e-6
#: Smallest per-contact normal sigma [rad] reported.
MIN_SIGMA_NORMAL: float = 1e-4
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
        sigma_normal: standard deviation of `normal` per tangential axis [rad].
        depth: the skin's depth at the peak [m].
        taxels: number of lit taxels.
        method: how it was found (:data:`METHODS`).
    """

    point: Array
    normal: Array
    force: float
    area: float
    sigma: float
    sigma_normal: float
    depth: float
    taxels: int
    method: str


def _fit_quadratic(uv: Array, d: Array) -> tuple[Array, Array, float] | None:
    """Least-squares coefficients (6,) of ``c0 + cu u + cv v + cuu u^2 + cuv u v + cvv v^2``,
    the inverse normal matrix (6, 6) and the residual variance (None if rank deficient)."""
    u, v = uv[:, 0], uv[:, 1]
    design = np.empty((len(u), 6))
    design[:, 0], design[:, 1], design[:, 2] = 1.0, u, v
    design[:, 3], design[:, 4], design[:, 5] = u * u, u * v, v * v
    normal = design.T @ design
    scales, vectors = np.linalg.eigh(normal)  # symmetric: its condition number and inverse
    if not scales[0] > 0 or scales[-1] > 1e12 * scales[0]:
        return None
    inv = (vectors / scales) @ vectors.T
    coef = inv @ (design.T @ d)
    dof = max(len(d) - 6, 1)
    var = float(np.sum((design @ coef - d) ** 2) / dof)
    return coef, inv, var


def _peak(coef: Array) -> tuple[Array, float] | None:
    """Stationary point (2,) and value of a concave quadratic, or None."""
    c0, cu, cv, cuu, cuv, cvv = (float(c) for c in coef)
    huu, huv, hvv = 2.0 * cuu, cuv, 2.0 * cvv  # the Hessian, in closed form (2 x 2)
    det = huu * hvv - huv * huv
    if not (huu < 0 and det > 0):
        return None
    s = np.array([(huv * cv - hvv * cu) / det, (huv * cu - huu * cv) / det])  # -H^-1 g
    value = c0 + 0.5 * (cu * s[0] + cv * s[1])
    return s, float(value)


def _peak_covariance(coef: Array, cov: Array, s: Array) -> tuple[Array, float]:
    """Covariance (2, 2) of the peak position and variance of its value (delta method).

    ``s = -H^-1 g``, so ``ds = -H^-1 (dg + dH s)``: the columns of ds/dcoef are ``-H^-1`` times
    (1, 0) and (0, 1) for (cu, cv), (2 s_u, 0), (s_v, s_u), (0, 2 s_v) for (cuu, cuv, cvv); the
    value's gradient is (1, s_u, s_v, s_u^2, s_u s_v, s_v^2) at the stationary point."""
    _, _, _, cuu, cuv, cvv = (float(c) for c in coef)
    huu, huv, hvv = 2.0 * cuu, cuv, 2.0 * cvv
    det = huu * hvv - huv * huv  # > 0 at a peak (:func:`_peak`)
    inv = np.array([[hvv, -huv], [-huv, huu]]) / det
    su, sv = s
    rhs = np.array([[0.0, 1.0, 0.0, 2.0 * su, sv, 0.0], [0.0, 0.0, 1.0, 0.0, su, 2.0 * sv]])
    jac = -inv @ rhs
    g_value = np.array([1.0, su, sv, su * su, su * sv, sv * sv])
    return jac @ cov @ jac.T, float(g_value @ cov @ g_value)


def estimate_contact(
    reading: Array,
    layout: PadLayout,
    rotation: Array,
    translation: Array,
    skin: SkinModel,
    sensor: SensorModel | None = None,
) -> TactileContact | None:
    """The contact one pad's reading stands for (module docstring), or None when no taxel is
    lit.

    Args:
        reading: (rows, cols) float, the pad's reading [Pa] (after the sensor model).
        layout: the pad's geometry in its carrier's frame.
        rotation: (3, 3) float, the carrier's orientation in the world (columns: its axes).
        translation: (3,) float, the carrier's origin [m, world].
        skin: the skin's elastic model (depth from pressure).
        sensor: the sensor model the reading went through (its noise, quantisation and gain
            spread enter the uncertainties), or None (ideal).
    """
    y = np.asarray(reading, dtype=np.float64).reshape(layout.shape)
    lit = y > 0.0
    count = int(np.count_nonzero(lit))
    if count == 0:
        return None
    d = skin.depth(y, layout.pitch)
    pos, nrm, area = layout.taxels
    rot = np.asarray(rotation, dtype=np.float64)
    t = np.asarray(translation, dtype=np.float64)
    force = float(np.sum(y * area))
    total_area = float(np.sum(area[lit]))
    sensor = SensorModel() if sensor is None else sensor
    top = float(y.max())
    noise2 = sensor.noise**2 + sensor.step**2 / 12.0 + (sensor.gain_spread * top) ** 2
    sigma_depth = float(np.sqrt(noise2)) / skin.cell_stiffness(layout.pitch)
    blur = sensor.blur * layout.pitch  # the crosstalk's std [m]
    if layout.curved:
        point_c, normal_c, depth, sigma, sigma_n, method = _curved(y, d, lit, layout, sigma_depth,
                                                                   blur)  # fmt: skip
    else:
        point_c, normal_c, depth, sigma, sigma_n, method = _flat(d, lit, pos, nrm, layout,
                                                                 sigma_depth)  # fmt: skip
    normal_w = rot @ normal_c
    return TactileContact(
        point=rot @ point_c + t, normal=normal_w / np.linalg.norm(normal_w), force=force,
        area=total_area, sigma=max(sigma, MIN_SIGMA),
        sigma_normal=max(sigma_n, MIN_SIGMA_NORMAL), depth=depth, taxels=count, method=method,
    )  # fmt: skip


def _curved(
    y: Array, d: Array, lit: NDArray[np.bool_], layout: PadLayout, sigma_depth: float,
    blur: float = 0.0,
) -> tuple[Array, Array, float, float, float, str]:  # fmt: skip
    """The contact on a curved pad (carrier frame): point, normal, depth, sigma, normal sigma,
    method. `blur` [m] is the sensor's crosstalk std: a Gaussian blur of a quadratic field adds
    ``blur^2 tr(H) / 2`` to it, so the peak's depth is corrected by that much (and the
    correction counts in sigma)."""
    radius = float(layout.radius)
    i0, j0 = np.unravel_index(int(np.argmax(d)), d.shape)
    inner = 0 < i0 < layout.rows - 1 and 0 < j0 < layout.cols - 1
    if inner:  # the deepest taxel has neighbours all round: the peak lies on the pad
        found = _quadratic_peak(d, lit, layout, (i0, j0), sigma_depth)
        if found is not None:
            uv_peak, depth, var_depth, tangential, trace = found
            correction = -0.5 * blur**2 * trace  # the blur lowered the peak by this much
            depth += correction
            var_depth += (BLUR_UNCERTAINTY * correction) ** 2
            p, m = layout.map(uv_peak)
            sigma, sigma_n = _floored(layout, var_depth, tangential / 2.0 / radius**2, radius)
            return p - depth * m, -m, depth, sigma, sigma_n, "peak"
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
            variance = residual + sigma_depth**2
            sigma, sigma_n = _floored(layout, variance / len(q), _slope_variance(q, variance),
                                      radius)  # fmt: skip
            return point, normal, float(d.max()), sigma, sigma_n, "plane"
    uv_peak, depth, unresolved = _ridge_peak(d, lit, layout, (i0, j0))  # an edge, few taxels
    # the peak lies anywhere within a taxel's cell along each unresolved axis: its depth is
    # pitch^2 / (24 R) deeper than the taxel's on average (a uniform offset over a sphere)
    deficit = unresolved * layout.pitch**2 / (24.0 * radius)
    depth += deficit
    p, m = layout.map(uv_peak)
    sigma, sigma_n = _floored(layout, sigma_depth**2 + deficit**2,
                              layout.pitch**2 / 12.0 / radius**2, radius)  # fmt: skip
    return p - depth * m, -m, depth, sigma, sigma_n, "ridge"


def _floored(
    layout: PadLayout, var_depth: float, var_normal: float, radius: float
) -> tuple[float, float]:
    """``sigma`` [m] and ``sigma_normal`` [rad] from a method's variances, with the model's
    floors (module docstring)."""
    sigma = np.sqrt(var_depth + (MODEL_DEPTH * layout.pitch) ** 2)
    sigma_n = np.sqrt(var_normal + (MODEL_NORMAL * layout.pitch / radius) ** 2)
    return float(sigma), float(sigma_n)


def _slope_variance(q: Array, variance: float) -> float:
    """Variance [rad^2] of the normal of a plane fitted to points q (k, 3) whose distances from
    it have `variance` [m^2], per axis: the slopes' of a least-squares plane (the narrower
    spread)."""
    spread = np.linalg.eigvalsh((q - q.mean(axis=0)).T @ (q - q.mean(axis=0)))
    return float(variance / max(spread[1], 1e-300))


def _ridge_peak(
    d: Array, lit: NDArray[np.bool_], layout: PadLayout, deepest: tuple[int, int]
) -> tuple[Array, float, int]:
    """The peak (u*, v*) [m] and depth [m] of a ridge of lit taxels (an edge of the object
    crossing the pad), or of a few lit taxels: within :data:`WINDOW` of the deepest taxel, a
    parabola through the depths along the lit taxels' major axis locates the peak along it,
    their depth-weighted mean across it; and how many of the two axes it leaves unresolved
    (no parabola's peak along them)."""
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
        return uv0 + mean, float(dw.max()), 2
    spread = (uv - mean).T @ ((uv - mean) * w[:, None])
    axes = np.linalg.eigh(spread)[1]
    major, minor = axes[:, 1], axes[:, 0]
    s, t = uv @ major, uv @ minor
    across = float(w @ t)
    if len(np.unique(np.round(s / layout.pitch, 6))) >= 3:  # a parabola needs three
        c2, c1, c0 = np.polyfit(s / layout.pitch, dw, 2, w=np.sqrt(w))
        if c2 < 0:
            along = float(np.clip(-c1 / (2.0 * c2), s.min() / layout.pitch,
                                  s.max() / layout.pitch))  # fmt: skip
            peak = c0 + along * (c1 + c2 * along)
            return (uv0 + along * layout.pitch * major + across * minor,
                    float(max(peak, dw.max())), 1)  # fmt: skip
    return uv0 + float(w @ s) * major + across * minor, float(dw.max()), 2


def _quadratic_peak(
    d: Array, lit: NDArray[np.bool_], layout: PadLayout, deepest: tuple[int, int],
    sigma_depth: float,
) -> tuple[Array, float, float, float, float] | None:  # fmt: skip
    """The peak (u*, v*) [m], its depth [m], the variances of its depth [m^2] and of its
    tangential position [m^2], and the trace of the fitted Hessian [1/m] of the quadratic
    fitted to the lit taxels within :data:`WINDOW` of the deepest one, or None (too few
    taxels, no maximum, or a maximum beyond :data:`PEAK_REACH`)."""
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
    trace = 2.0 * (coef[3] + coef[5]) / layout.pitch**2  # tr(H) [1/m], negative at a peak
    return uv0 + peak[0] * layout.pitch, peak[1], var_value, tangential, float(trace)


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
) -> tuple[Array, Array, float, float, float, str]:  # fmt: skip
    """Plane through the surface points of a flat pad's lit taxels (carrier frame)."""
    q = (pos - d[..., None] * nrm)[lit]
    plane = _plane(q) if len(q) >= 3 else None
    if plane is None:
        peak = int(np.argmax(d[lit]))
        # the plate's normal stands for the face's: a tilt of up to about 30 deg
        half = 0.5 * max(layout.extent[0], layout.extent[1], layout.pitch)
        sigma, _ = _floored(layout, sigma_depth**2, 0.0, half)
        return q[peak], -layout.normal, float(d[lit][peak]), sigma, 0.3, "taxel"
    centre, normal, residual = plane
    if normal @ layout.normal > 0:
        normal = -normal
    variance = residual + sigma_depth**2
    half = 0.5 * max(layout.extent[0], layout.extent[1], layout.pitch)
    sigma, sigma_n = _floored(layout, variance / len(q), _slope_variance(q, variance), half)
    return centre, normal, float(d[lit].max()), sigma, sigma_n, "plane"


__all__ = [
    "METHODS",
    "MIN_SIGMA",
    "MIN_SIGMA_NORMAL",
    "MODEL_DEPTH",
    "MODEL_NORMAL",
    "PEAK_REACH",
    "TactileContact",
    "WINDOW",
    "estimate_contact",
]
