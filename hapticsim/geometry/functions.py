"""Superquadric functions on arrays: the single home of the inside-outside function.

Everything here is vectorised. Shape parameters broadcast over leading "batch" dimensions against
point sets, so one call can evaluate a whole population of superquadrics:

- ``a``: (..., 3) semi-axes [m]; ``eps``: (..., 2) exponents (eps1, eps2); ``taper``: (..., 2)
- ``points``: (..., n, 3) [m]; the batch dimensions of the parameters broadcast against ``...``.

Body-frame points are "tapered" (they lie on the deformed solid); :func:`untaper` maps them back
to the symmetric superquadric of paper eq. (1), on which the inside-outside function is defined.

The inside-outside function is evaluated in the log domain so that the large exponents of
box-like shapes (2/eps up to 20) neither overflow nor underflow for far or near points.
"""

from __future__ import annotations

from math import exp, lgamma

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import MIN_TAPER_FACTOR

Array = NDArray[np.float64]

# Smallest |x/a| used in logs: keeps 1/|u| and F^(-eps1/2) far from overflow (< 1e150).
_TINY = 1e-150


def signed_power(x: Array, exponent: Array | float) -> Array:
    """``sign(x) * |x| ** exponent``, the signed power of paper eq. (1)."""
    x = np.asarray(x, dtype=np.float64)
    return np.sign(x) * np.abs(x) ** exponent


def _p(param: Array, index: int) -> Array:
    """Component `index` of a (..., k) parameter, shaped (..., 1) to broadcast over n points."""
    return np.asarray(param, dtype=np.float64)[..., index, None]


def taper_factors(z: Array, a: Array, taper: Array) -> tuple[Array, Array]:
    """The tapering factors ``1 + t*z/a3`` of paper eq. (2) for x and y.

    Args:
        z: (..., n) float, body-frame heights [m].
        a: (..., 3) semi-axes [m]; taper: (..., 2) (tx, ty).

    Returns:
        fx, fy: (..., n) float, clipped below at ``MIN_TAPER_FACTOR`` so that points beyond an
        apex (only reachable by bad estimates) do not flip sides.
    """
    scale = z / _p(a, 2)
    fx = np.maximum(1.0 + _p(taper, 0) * scale, MIN_TAPER_FACTOR)
    fy = np.maximum(1.0 + _p(taper, 1) * scale, MIN_TAPER_FACTOR)
    return fx, fy


def apply_taper(points_body: Array, a: Array, taper: Array) -> Array:
    """Deform symmetric body-frame points by tapering, paper eq. (2). (..., n, 3) -> (..., n, 3)."""
    p = np.asarray(points_body, dtype=np.float64)
    fx, fy = taper_factors(p[..., 2], a, taper)
    return np.stack([p[..., 0] * fx, p[..., 1] * fy, np.broadcast_to(p[..., 2], fx.shape)], -1)


def untaper(points_body: Array, a: Array, taper: Array) -> Array:
    """Inverse of :func:`apply_taper`: divide x, y by their tapering factors. (..., n, 3)."""
    p = np.asarray(points_body, dtype=np.float64)
    fx, fy = taper_factors(p[..., 2], a, taper)
    return np.stack([p[..., 0] / fx, p[..., 1] / fy, np.broadcast_to(p[..., 2], fx.shape)], -1)


def world_to_body(points_world: Array, rotation: Array, center: Array) -> Array:
    """``R^T (x - x0)`` for (..., n, 3) points, (..., 3, 3) rotations and (..., 3) centres."""
    center = np.asarray(center, dtype=np.float64)
    return (np.asarray(points_world, dtype=np.float64) - center[..., None, :]) @ rotation


def body_to_world(points_body: Array, rotation: Array, center: Array) -> Array:
    """``R p + x0`` for (..., n, 3) points."""
    center = np.asarray(center, dtype=np.float64)
    # A contiguous copy of R^T: matmul with the transposed view of a read-only array (as a
    # Superquadric holds) is ~30 times slower for (n, 3) points.
    rotation_t = np.ascontiguousarray(np.swapaxes(rotation, -1, -2))
    return points_body @ rotation_t + center[..., None, :]


def _logaddexp(x: Array, y: Array, out: Array, tmp: Array) -> Array:
    """``log(exp(x) + exp(y))`` into `out` (`tmp` is scratch); many times faster than np.logaddexp.

    Inputs must be finite. ``max(x, y) + log(1 + exp(-|x - y|))``; log of 1 + e rather than
    log1p(e), which is slower here: the absolute error (< 1e-16) is far below what matters.
    """
    np.subtract(x, y, out=tmp)
    np.abs(tmp, out=tmp)
    np.negative(tmp, out=tmp)
    np.exp(tmp, out=tmp)
    tmp += 1.0
    np.log(tmp, out=tmp)
    np.maximum(x, y, out=out)
    out += tmp
    return out


def log_abs_scaled(x: Array, scale: Array | float, out: Array | None = None) -> Array:
    """``log(|x| * scale + TINY)``: the log of a scaled coordinate such as ``|x / a1|``.

    Finite for points on a body plane (or at the centre). ``scale`` broadcasts against ``x``.
    """
    out = np.abs(x, out=out)
    out *= scale
    out += _TINY
    return np.log(out, out=out)


#: Below this, a value of :func:`log_abs_scaled` may come from a coordinate that is exactly 0.
LOG_ZERO: float = float(np.log(2.0 * _TINY))

#: Rows of the array returned by :func:`log_inside_outside_terms`.
TERM_AU, TERM_AV, TERM_LOG_G, TERM_L1, TERM_L2, TERM_LOG_F = range(6)


def log_inside_outside_terms(
    log_u: Array, log_v: Array, log_w: Array, e1: Array, e2: Array, out: Array | None = None
) -> Array:
    """The inside-outside function in the log domain, with its intermediate terms.

    This is the single implementation of F (SPEC §1); every other function calls it.
    With ``u = x/a1, v = y/a2, w = z/a3`` (untapered body frame) and
    ``g = |u|^(2/eps2) + |v|^(2/eps2)``, ``F = g^(eps2/eps1) + |w|^(2/eps1)``.

    Args:
        log_u, log_v, log_w: (..., n) float, ``log|u|`` etc. (finite, e.g. from
            :func:`log_abs_scaled`).
        e1, e2: eps1, eps2, broadcastable against them (e.g. (..., 1)).
        out: optional (7, ..., n) float buffer to fill (the last row is scratch).

    Returns:
        (7, ..., n) float; rows (indices ``TERM_*``): ``(2/eps2) log|u|``, ``(2/eps2) log|v|``,
        ``log g``, ``L1 = (eps2/eps1) log g``, ``L2 = (2/eps1) log|w|``, ``log F``, scratch.
    """
    if out is None:
        out = np.empty((7, *np.broadcast_shapes(np.shape(log_u), np.shape(e1), np.shape(e2))))
    au, av, log_g, l1, l2, log_f, tmp = out
    k2 = 2.0 / e2
    np.multiply(log_u, k2, out=au)
    np.multiply(log_v, k2, out=av)
    _logaddexp(au, av, log_g, tmp)
    np.multiply(log_g, e2 / e1, out=l1)
    np.multiply(log_w, 2.0 / e1, out=l2)
    _logaddexp(l1, l2, log_f, tmp)
    return out


def _scaled_logs(points_sym: Array, a: Array) -> tuple[Array, Array, Array]:
    p = np.asarray(points_sym, dtype=np.float64)
    inv_a = 1.0 / np.asarray(a, dtype=np.float64)
    return tuple(log_abs_scaled(p[..., i], inv_a[..., i, None]) for i in range(3))


def log_inside_outside(points_sym: Array, a: Array, eps: Array) -> Array:
    """Natural log of the inside-outside function F of an untapered superquadric (SPEC §1).

    ``F(p) = (|x/a1|^(2/eps2) + |y/a2|^(2/eps2))^(eps2/eps1) + |z/a3|^(2/eps1)``.

    Args:
        points_sym: (..., n, 3) float, untapered body-frame points [m].
        a: (..., 3) semi-axes [m]. eps: (..., 2) exponents.

    Returns:
        (..., n) float, log F (about ``-345 * 2/eps1`` at the centre, where F is 0).
    """
    lu, lv, lw = _scaled_logs(points_sym, a)
    return log_inside_outside_terms(lu, lv, lw, _p(eps, 0), _p(eps, 1))[TERM_LOG_F]


def inside_outside(points_sym: Array, a: Array, eps: Array) -> Array:
    """Inside-outside function F (< 1 inside, 1 on, > 1 outside) of untapered points, (..., n)."""
    with np.errstate(over="ignore"):
        return np.exp(log_inside_outside(points_sym, a, eps))


def radial_scale(points_sym: Array, a: Array, eps: Array) -> Array:
    """``F(p)^(-eps1/2)``: the factor that moves p along its ray onto the surface. (..., n)."""
    with np.errstate(over="ignore"):
        return np.exp(-0.5 * _p(eps, 0) * log_inside_outside(points_sym, a, eps))


def radial_distance(points_sym: Array, a: Array, eps: Array) -> Array:
    """Radial Euclidean distance of Boulton and Gross (SPEC §2): ``|p| |1 - F^(-eps1/2)|``.

    Args:
        points_sym: (..., n, 3) float, untapered body-frame points [m].

    Returns:
        (..., n) float, non-negative distances [m]; 0 at the centre (the limit ``|p| -> 0``).
    """
    p = np.asarray(points_sym, dtype=np.float64)
    norm = np.linalg.norm(p, axis=-1)
    return norm * np.abs(1.0 - radial_scale(p, a, eps))


def gradient_shares(terms: Array, out: Array | None = None) -> Array:
    """``u dF/du / ((2/eps1) F)`` for u, v, w: each term's share of F, in [0, 1].

    From the rows of :func:`log_inside_outside_terms`:
    ``h_u = (g^(eps2/eps1) / F) (|u|^(2/eps2) / g)``, ``h_v`` likewise and
    ``h_w = |w|^(2/eps1) / F``; ``h_u + h_v + h_w = 1``. Dividing ``h_u`` by the body coordinate
    x (tapered or not, see :func:`normals_body`) gives the gradient without any power of a small
    number, so nothing overflows or underflows for far or near points.

    Args:
        terms: (7, ..., n) from :func:`log_inside_outside_terms`.
        out: optional (3, ..., n) buffer.

    Returns:
        (3, ..., n) float, ``(h_u, h_v, h_w)``.
    """
    if out is None:
        out = np.empty((3, *terms.shape[1:]))
    hu, hv, hw = out
    # common = L1 - log g - log F = log(g^(eps2/eps1) / (g F)).
    common = terms[6]
    np.subtract(terms[TERM_L1], terms[TERM_LOG_G], out=common)
    common -= terms[TERM_LOG_F]
    np.add(terms[TERM_AU], common, out=hu)
    np.exp(hu, out=hu)
    np.add(terms[TERM_AV], common, out=hv)
    np.exp(hv, out=hv)
    np.subtract(terms[TERM_L2], terms[TERM_LOG_F], out=hw)
    np.exp(hw, out=hw)
    return out


def divide_or_zero(numerator: Array, coordinate: Array, out: Array, check: bool = True) -> Array:
    """``numerator / coordinate`` into `out`, 0 where the coordinate is exactly 0.

    The gradient component ``h_u / x`` tends to 0 on the plane x = 0 for eps < 2.
    ``check=False`` skips the search for zeros (for a caller that knows there are none).
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        np.divide(numerator, coordinate, out=out)
    if check and not np.all(coordinate):
        out[np.broadcast_to(coordinate == 0, out.shape)] = 0.0
    return out


def normals_body(points_body: Array, a: Array, eps: Array, taper: Array) -> Array:
    """Outward unit normals, in the body frame, of the tapered superquadric (paper eqs. 3-4).

    The normal at a point is that of the level set of ``F(untaper(p))`` through it, i.e. the
    surface normal at the point's radial projection: ``J_t^(-T) grad F``, with ``J_t`` the
    Jacobian of tapering (eq. 4 up to the positive factor det J_t).

    Args:
        points_body: (..., n, 3) float, tapered body-frame points [m].

    Returns:
        (..., n, 3) float unit vectors.
    """
    p = np.asarray(points_body, dtype=np.float64)
    a = np.asarray(a, dtype=np.float64)
    taper = np.asarray(taper, dtype=np.float64)
    fx, fy = taper_factors(p[..., 2], a, taper)
    lu = log_abs_scaled(p[..., 0] / fx, 1.0 / _p(a, 0))
    lv = log_abs_scaled(p[..., 1] / fy, 1.0 / _p(a, 1))
    lw = log_abs_scaled(p[..., 2], 1.0 / _p(a, 2))
    h = gradient_shares(log_inside_outside_terms(lu, lv, lw, _p(eps, 0), _p(eps, 1)))
    n = np.empty((3, *h.shape[1:]))
    tapered_normals(h, p[..., 0], p[..., 1], p[..., 2], fx, fy, a, taper, out=n)
    norm = np.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    n /= np.where(norm > 0, norm, 1.0)
    return np.moveaxis(n, 0, -1)


def tapered_normals(
    shares: Array,
    x: Array,
    y: Array,
    z: Array,
    fx: Array,
    fy: Array,
    a: Array,
    taper: Array,
    out: Array,
    tmp: Array | None = None,
    zeros: bool = True,
) -> Array:
    """Unnormalised outward normals ``J_t^(-T) grad F`` (paper eq. 4) in the body frame.

    With ``(h_u, h_v, h_w)`` from :func:`gradient_shares` and tapered body coordinates x, y, z,
    ``grad F ~ (h_u / x_s, h_v / y_s, h_w / z)`` at the untapered point ``x_s = x / fx``, and
    ``J_t^(-T)`` divides the x and y components by fx, fy and subtracts
    ``t_x / a3 * (grad_x x_s) / fx + t_y / a3 * (grad_y y_s) / fy`` from the z component;
    hence ``n = (h_u / x, h_v / y, h_w / z - (t_x/a3) h_u / fx - (t_y/a3) h_v / fy)``.

    Args:
        shares: (3, ..., n) from :func:`gradient_shares`.
        x, y, z: (..., n) tapered body-frame coordinates [m]; fx, fy: their taper factors.
        a: (..., 3) [m]; taper: (..., 2).
        out: (3, ..., n) buffer for the result; tmp: optional (..., n) scratch.
        zeros: False when the caller knows that no coordinate is exactly 0 (skips the checks).

    Returns:
        `out`, (3, ..., n) float, not unit length [1/m].
    """
    hu, hv, hw = shares
    nx, ny, nz = out
    tmp = np.empty(nx.shape) if tmp is None else tmp
    divide_or_zero(hu, x, nx, zeros)
    divide_or_zero(hv, y, ny, zeros)
    divide_or_zero(hw, z, nz, zeros)
    inv_a3 = 1.0 / _p(a, 2)
    np.divide(hu, fx, out=tmp)
    tmp *= _p(taper, 0) * inv_a3
    nz -= tmp
    np.divide(hv, fy, out=tmp)
    tmp *= _p(taper, 1) * inv_a3
    nz -= tmp
    return out


def unit_superellipse_area(eps2: float) -> float:
    """Area of ``|x|^(2/eps2) + |y|^(2/eps2) <= 1``: ``4 Gamma(1+eps2/2)^2 / Gamma(1+eps2)``."""

    return 4.0 * exp(2.0 * lgamma(1.0 + eps2 / 2.0) - lgamma(1.0 + eps2))


def _beta(x: float, y: float) -> float:
    return exp(lgamma(x) + lgamma(y) - lgamma(x + y))


def volume(a: Array, eps: Array, taper: Array) -> float:
    """Exact volume of a tapered superquadric [m^3].

    The cross-section at height z is a superellipse of area
    ``a1 a2 C(eps2) s(z)^2 (1 + tx z/a3)(1 + ty z/a3)`` with ``s = (1 - |z/a3|^(2/eps1))^(eps1/2)``.
    The term linear in z integrates to zero, so

    ``V = a1 a2 a3 C(eps2) eps1 [B(eps1/2, eps1+1) + tx ty B(3 eps1/2, eps1+1)]``

    with ``C(eps2) = 4 Gamma(1+eps2/2)^2 / Gamma(1+eps2)`` and B the beta function.
    """
    a1, a2, a3 = (float(v) for v in np.asarray(a, dtype=np.float64))
    e1, e2 = (float(v) for v in np.asarray(eps, dtype=np.float64))
    tx, ty = (float(v) for v in np.asarray(taper, dtype=np.float64))
    c = unit_superellipse_area(e2)
    return a1 * a2 * a3 * c * e1 * (_beta(e1 / 2, e1 + 1) + tx * ty * _beta(1.5 * e1, e1 + 1))
