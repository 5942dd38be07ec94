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

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import MIN_TAPER_FACTOR

Array = NDArray[np.float64]

_TINY = 1e-300


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


def log_inside_outside(points_sym: Array, a: Array, eps: Array) -> Array:
    """Natural log of the inside-outside function F of an untapered superquadric (SPEC §1).

    ``F(p) = (|x/a1|^(2/eps2) + |y/a2|^(2/eps2))^(eps2/eps1) + |z/a3|^(2/eps1)``.

    Args:
        points_sym: (..., n, 3) float, untapered body-frame points [m].
        a: (..., 3) semi-axes [m]. eps: (..., 2) exponents.

    Returns:
        (..., n) float, log F (``-inf`` at the centre).
    """
    p = np.asarray(points_sym, dtype=np.float64)
    e1, e2 = _p(eps, 0), _p(eps, 1)
    with np.errstate(divide="ignore"):
        lx = np.log(np.abs(p[..., 0] / _p(a, 0)))
        ly = np.log(np.abs(p[..., 1] / _p(a, 1)))
        lz = np.log(np.abs(p[..., 2] / _p(a, 2)))
    lxy = np.logaddexp((2.0 / e2) * lx, (2.0 / e2) * ly)
    return np.logaddexp((e2 / e1) * lxy, (2.0 / e1) * lz)


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
        (..., n) float, non-negative distances [m]; 0 at the centre by convention... of the
        limit ``|p| -> 0`` (the centre itself returns ``a``-free 0 * inf, replaced by 0).
    """
    p = np.asarray(points_sym, dtype=np.float64)
    norm = np.linalg.norm(p, axis=-1)
    with np.errstate(invalid="ignore"):
        out = norm * np.abs(1.0 - radial_scale(p, a, eps))
    return np.where(norm > 0, out, 0.0)


def gradient_sym(points_sym: Array, a: Array, eps: Array) -> Array:
    """Direction of the gradient of F at untapered points, up to a positive factor per point.

    F is homogeneous along rays, so the direction equals the outward surface normal at the
    radial projection of the point (paper eq. 3 for points on the surface). Returned vectors are
    scaled for numerical range and are not unit length.

    Returns:
        (..., n, 3) float.
    """
    p = np.asarray(points_sym, dtype=np.float64)
    e1, e2 = _p(eps, 0), _p(eps, 1)
    u = p / np.asarray(a, dtype=np.float64)[..., None, :]
    with np.errstate(divide="ignore"):
        lu = np.log(np.maximum(np.abs(u), _TINY))
    # log of |x/a1|^(2/e2) etc. and of the xy term g.
    lax, lay = (2.0 / e2) * lu[..., 0], (2.0 / e2) * lu[..., 1]
    lg = np.logaddexp(lax, lay)
    laz = (2.0 / e1) * lu[..., 2]
    # dF/dx ~ g^(e2/e1 - 1) |x/a1|^(2/e2 - 1) sign(x) / a1 (common factor 2/e1 dropped).
    # Work relative to the log of F to keep the magnitudes near 1.
    lf = np.logaddexp((e2 / e1) * lg, laz)
    lxy_common = (e2 / e1 - 1.0) * lg - lf
    gx = np.sign(u[..., 0]) * np.exp(lxy_common + lax - lu[..., 0]) / _p(a, 0)
    gy = np.sign(u[..., 1]) * np.exp(lxy_common + lay - lu[..., 1]) / _p(a, 1)
    gz = np.sign(u[..., 2]) * np.exp(laz - lu[..., 2] - lf) / _p(a, 2)
    return np.stack([gx, gy, gz], -1)


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
    fx, fy = taper_factors(p[..., 2], a, taper)
    sym = np.stack([p[..., 0] / fx, p[..., 1] / fy, np.broadcast_to(p[..., 2], fx.shape)], -1)
    g = gradient_sym(sym, a, eps)
    a3 = _p(a, 2)
    nz = (
        g[..., 2]
        - g[..., 0] * sym[..., 0] * _p(taper, 0) / (a3 * fx)
        - g[..., 1] * sym[..., 1] * _p(taper, 1) / (a3 * fy)
    )
    n = np.stack([g[..., 0] / fx, g[..., 1] / fy, nz], -1)
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    return n / np.where(norm > 0, norm, 1.0)


def unit_superellipse_area(eps2: float) -> float:
    """Area of ``|x|^(2/eps2) + |y|^(2/eps2) <= 1``: ``4 Gamma(1+eps2/2)^2 / Gamma(1+eps2)``."""
    from math import exp, lgamma

    return 4.0 * exp(2.0 * lgamma(1.0 + eps2 / 2.0) - lgamma(1.0 + eps2))


def _beta(x: float, y: float) -> float:
    from math import exp, lgamma

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
