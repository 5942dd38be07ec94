"""Compiled sampling and distances on a superquadric (numba): interior samples, inside tests and
distances to the surface, behind its quality measures (:mod:`hapticsim.geometry.sampling`).

They use the one compiled inside-outside function
(:func:`hapticsim.geometry.eof_compiled.log_inside_outside`); each loop over points is
straight-line code that LLVM vectorises.

A superquadric is passed as ``shape`` (7,) = (a1, a2, a3, eps1, eps2, tx, ty), ``rot`` (3, 3)
(columns: the body axes in the world frame) and ``center`` (3,) [m]: see
:func:`hapticsim.geometry.eof_compiled.unpack`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hapticsim.geometry.eof_compiled import (
    JIT,
    _logaddexp_shares,
    exp_,
    log_inside_outside,
    shape_fields,
    unpack,
    untapered,
)

__all__ = [
    "count_outside",
    "interior_outside",
    "interior_points",
    "surface_distances",
    "surface_sample",
    "unpack",
]

_INLINE = {"forceinline": True, **JIT}


@njit(**JIT)
def count_outside(
    points: np.ndarray, shape: np.ndarray, rot: np.ndarray, center: np.ndarray
) -> int:
    """How many of the world points (3, n) lie strictly outside the solid (``F > 1``)."""
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    c0, c1, c2 = center[0], center[1], center[2]
    r00, r01, r02 = rot[0, 0], rot[0, 1], rot[0, 2]
    r10, r11, r12 = rot[1, 0], rot[1, 1], rot[1, 2]
    r20, r21, r22 = rot[2, 0], rot[2, 1], rot[2, 2]
    px_w, py_w, pz_w = points[0], points[1], points[2]
    out = 0
    for i in range(points.shape[1]):
        d0, d1, d2 = px_w[i] - c0, py_w[i] - c1, pz_w[i] - c2
        bx = r00 * d0 + r10 * d1 + r20 * d2
        by = r01 * d0 + r11 * d1 + r21 * d2
        bz = r02 * d0 + r12 * d1 + r22 * d2
        xs, ys, _, _ = untapered(bx, by, bz, a3, tx, ty)
        log_f = log_inside_outside(xs, ys, bz, a1, a2, a3, e1, e2)[0]
        out += 1 if log_f > 0.0 else 0
    return out


@njit(**_INLINE)
def _kept(
    unit: np.ndarray, log_unit: np.ndarray, accept: np.ndarray, top: float, count: int,
    e1: float, e2: float, tx: float, ty: float,
) -> np.ndarray:  # fmt: skip
    """Indices of the candidates k < `count` that the rejection sampler keeps for a solid of
    exponents (e1, e2) and taper (tx, ty): ``F(u) < 1`` and ``top * accept[k] < (1 + tx u_z)
    (1 + ty u_z)`` (a branch-free loop over all candidates, which vectorises)."""
    keep = np.empty(count, np.bool_)
    k2, k1, ratio = 2.0 / e2, 2.0 / e1, e2 / e1
    for k in range(count):
        uz = unit[2, k]
        log_g = _logaddexp_shares(log_unit[0, k] * k2, log_unit[1, k] * k2)[0]
        log_f = _logaddexp_shares(log_g * ratio, log_unit[2, k] * k1)[0]
        keep[k] = log_f < 0.0 and top * accept[k] < (1.0 + tx * uz) * (1.0 + ty * uz)
    return np.nonzero(keep)[0]


@njit(**JIT)
def interior_points(
    unit: np.ndarray, log_unit: np.ndarray, accept: np.ndarray, top: float, count: int,
    shape: np.ndarray, rot: np.ndarray, center: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """The interior sample of a solid from fixed candidates (as :func:`interior_outside` draws
    it): the kept candidates among the first `count`, scaled by a, tapered and posed, (3, kept)
    world points [m]."""
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    index = _kept(unit, log_unit, accept, top, count, e1, e2, tx, ty)
    out = np.empty((3, index.shape[0]))
    for i in range(index.shape[0]):
        k = index[i]
        ux, uy, uz = unit[0, k], unit[1, k], unit[2, k]
        bx, by, bz = ux * a1 * (1.0 + tx * uz), uy * a2 * (1.0 + ty * uz), uz * a3
        out[0, i] = rot[0, 0] * bx + rot[0, 1] * by + rot[0, 2] * bz + center[0]
        out[1, i] = rot[1, 0] * bx + rot[1, 1] * by + rot[1, 2] * bz + center[1]
        out[2, i] = rot[2, 0] * bx + rot[2, 1] * by + rot[2, 2] * bz + center[2]
    return out


@njit(**JIT)
def interior_outside(
    unit: np.ndarray, log_unit: np.ndarray, accept: np.ndarray, top: float, count: int,
    shape: np.ndarray, rot: np.ndarray, center: np.ndarray,
    other_shape: np.ndarray, other_rot: np.ndarray, other_center: np.ndarray,
) -> tuple[int, int]:  # fmt: skip
    """Rejection-sample the interior of a solid from fixed candidates and test them in another.

    Candidate k < `count`, ``unit[:, k]`` uniform in [-1, 1]^3 (scaled untapered body
    coordinates; `log_unit` holds ``log(|u| + TINY)``, which no estimate changes), is kept when
    ``F(u) < 1`` (unit semi-axes) and ``top * accept[k] < (1 + tx u_z)(1 + ty u_z)`` (the volume
    change of tapering; `accept` uniform in [0, 1), `top` the largest factor), exactly as
    :func:`hapticsim.metrics.volume.sample_interior` does with fresh random numbers. Kept points
    are scaled by a, tapered, posed and tested
    against the other solid. Two passes, each a branch-free loop that vectorises: the keep test
    over all candidates, then the other solid's test over the kept ones.

    Returns:
        ``(outside, kept)``: kept points outside the other solid, and points kept.
    """
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    b1, b2, b3, f1, f2, sx, sy = shape_fields(other_shape)
    index = _kept(unit, log_unit, accept, top, count, e1, e2, tx, ty)
    # world = R b + c; the other solid's body frame: R_o^T (world - c_o) = M b + t, M = R_o^T R.
    m = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            m[i, j] = (
                other_rot[0, i] * rot[0, j]
                + other_rot[1, i] * rot[1, j]
                + (other_rot[2, i] * rot[2, j])
            )
    dc = center - other_center
    t0 = other_rot[0, 0] * dc[0] + other_rot[1, 0] * dc[1] + other_rot[2, 0] * dc[2]
    t1 = other_rot[0, 1] * dc[0] + other_rot[1, 1] * dc[1] + other_rot[2, 1] * dc[2]
    t2 = other_rot[0, 2] * dc[0] + other_rot[1, 2] * dc[1] + other_rot[2, 2] * dc[2]
    outside = 0
    for i in range(index.shape[0]):
        k = index[i]
        ux, uy, uz = unit[0, k], unit[1, k], unit[2, k]
        bx, by, bz = ux * a1 * (1.0 + tx * uz), uy * a2 * (1.0 + ty * uz), uz * a3
        qx = m[0, 0] * bx + m[0, 1] * by + m[0, 2] * bz + t0
        qy = m[1, 0] * bx + m[1, 1] * by + m[1, 2] * bz + t1
        qz = m[2, 0] * bx + m[2, 1] * by + m[2, 2] * bz + t2
        xs, ys, _, _ = untapered(qx, qy, qz, b3, sx, sy)
        outside += 1 if log_inside_outside(xs, ys, qz, b1, b2, b3, f1, f2)[0] > 0.0 else 0
    return outside, index.shape[0]


@njit(**_INLINE)
def _radial_point(
    qx: float, qy: float, qz: float, shape: np.ndarray
) -> tuple[float, float, float, float, float, float]:
    """The surface point on the ray through a tapered body point q, and the unit outward normal
    there: ``(x, y, z, nx, ny, nz)`` in the body frame."""
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    xs, ys, _, _ = untapered(qx, qy, qz, a3, tx, ty)
    log_f, phu, phv, psg, psw = log_inside_outside(xs, ys, qz, a1, a2, a3, e1, e2)
    s = exp_(log_f * (-0.5 * e1))
    # The surface point (untapered s * (xs, ys, z)) tapered back; the shares of F are the same
    # all along the ray, so the gradient comes from those at q.
    zs = s * qz
    ia3 = 1.0 / a3
    fx = max(1.0 + tx * ia3 * zs, 1e-6)
    fy = max(1.0 + ty * ia3 * zs, 1e-6)
    x, y = s * xs * fx, s * ys * fy
    hu, hv, hw = phu * psg, phv * psg, psw
    sx, sy = s * xs, s * ys
    gx = hu / sx if sx != 0.0 else 0.0
    gy = hv / sy if sy != 0.0 else 0.0
    gz = hw / zs if zs != 0.0 else 0.0
    # J_t^-T grad F (eq. 4): x, y divided by the taper factors, z corrected.
    nx, ny = gx / fx, gy / fy
    nz = gz - tx * ia3 * sx * gx / fx - ty * ia3 * sy * gy / fy
    norm = math.sqrt(nx * nx + ny * ny + nz * nz)
    norm = norm if norm > 0.0 else 1.0
    return x, y, zs, nx / norm, ny / norm, nz / norm


#: Sine of the angle between q - p and the normal at which :func:`_foot_search` stops early
#: (|q - p| is then the distance to about 1e-10 of it: measured, the Chamfer distances of the
#: scorer moved by < 1e-11 relative against a stop at 1e-8, for 30 % less time).
_CONVERGED: float = 1e-5


@njit(**_INLINE)
def _foot_search(
    qx: float,
    qy: float,
    qz: float,
    sx: float,
    sy: float,
    sz: float,
    shape: np.ndarray,
    iterations: int,
) -> tuple[float, float, float, float, float]:
    """From the start s (a body point whose ray gives the first surface point), alternate: the
    surface point p on the ray, then q's projection onto the tangent plane at p for the next ray.

    Returns ``(smallest |q - p| seen, sine of the angle between q - p and the normal there, that
    normal (body frame, unit))``: every p is on the surface, so the first is an upper bound of the
    distance; it is the distance (a foot point) when the second is 0.
    """
    best, off = math.inf, 1.0
    bx, by, bz = 0.0, 0.0, 1.0
    for _ in range(iterations + 1):
        x, y, z, nx, ny, nz = _radial_point(sx, sy, sz, shape)
        ex, ey, ez = qx - x, qy - y, qz - z
        dist = math.sqrt(ex * ex + ey * ey + ez * ez)
        along = ex * nx + ey * ny + ez * nz
        if dist < best:
            best = dist
            off = math.sqrt(max(dist * dist - along * along, 0.0)) / dist if dist > 0.0 else 0.0
            bx, by, bz = nx, ny, nz
        if off < _CONVERGED:  # q - p along the normal: a foot point, the next step returns p
            break
        sx, sy, sz = qx - along * nx, qy - along * ny, qz - along * nz
    return best, off, bx, by, bz


#: Directions (body frame, before scaling by a) of the restarts of :func:`surface_distances`:
#: the 26 face, edge and corner directions of a cube.
_RESTARTS = np.array(
    [
        [i, j, k]
        for i in (-1, 0, 1)
        for j in (-1, 0, 1)
        for k in (-1, 0, 1)
        if (i, j, k) != (0, 0, 0)
    ],
    dtype=np.float64,
)


@njit(**JIT)
def surface_distances(
    points: np.ndarray, shape: np.ndarray, rot: np.ndarray, center: np.ndarray,
    iterations: int, out: np.ndarray, normals: np.ndarray, starts: np.ndarray,
) -> None:  # fmt: skip
    """Euclidean distance [m] of world points (3, n) to the surface, into `out` (n,), and where
    `normals` is (3, n) (not (3, 0)) the surface's unit outward normal at each point's foot
    point [world], into it. Where `starts` is (3, n) (not (3, 0)), a further search starts from
    each point's start (a world point near its foot point, such as the nearest of a surface
    sample: on sharp edges the search from the point's own ray may stop short of the foot).

    A foot-point search (:func:`_foot_search`) from the point's own ray. Outside the (convex)
    solid the foot point is unique and the search finds it in two or three steps. Inside, there
    may be several (one per face): there the distance is the smallest distance to a tangent
    plane (the solid is the intersection of its tangent half-spaces), so the tangent planes at
    the 26 face, edge and corner directions of the solid's box are tried too, and a second
    search starts from the nearest of them; the smaller result is kept (and the normal of the
    plane or foot point it came from). (Two passes, the first over all points and branch-free,
    so that it vectorises.)
    """
    n = points.shape[1]
    keep = normals.shape[1] == n
    a1, a2, a3 = shape[0], shape[1], shape[2]
    e1, e2, tx, ty = shape[3], shape[4], shape[5], shape[6]
    body = np.empty((3, n))
    foot = np.empty((3, n))
    inside = np.empty(n, np.bool_)
    for i in range(n):
        d0, d1, d2 = points[0, i] - center[0], points[1, i] - center[1], points[2, i] - center[2]
        qx = rot[0, 0] * d0 + rot[1, 0] * d1 + rot[2, 0] * d2
        qy = rot[0, 1] * d0 + rot[1, 1] * d1 + rot[2, 1] * d2
        qz = rot[0, 2] * d0 + rot[1, 2] * d1 + rot[2, 2] * d2
        body[0, i], body[1, i], body[2, i] = qx, qy, qz
        out[i], _, foot[0, i], foot[1, i], foot[2, i] = _foot_search(
            qx, qy, qz, qx, qy, qz, shape, iterations
        )
        xs, ys, _, _ = untapered(qx, qy, qz, a3, tx, ty)
        inside[i] = log_inside_outside(xs, ys, qz, a1, a2, a3, e1, e2)[0] < 0.0
    planes = np.empty((_RESTARTS.shape[0], 6))
    for r in range(_RESTARTS.shape[0]):
        planes[r] = _radial_point(
            a1 * _RESTARTS[r, 0], a2 * _RESTARTS[r, 1], a3 * _RESTARTS[r, 2], shape
        )
    for i in np.nonzero(inside)[0]:
        qx, qy, qz = body[0, i], body[1, i], body[2, i]
        plane, sx, sy, sz = math.inf, qx, qy, qz
        px, py, pz = 0.0, 0.0, 1.0
        for r in range(planes.shape[0]):
            x, y, z, nx, ny, nz = planes[r]
            gap = (x - qx) * nx + (y - qy) * ny + (z - qz) * nz  # >= the distance
            if gap < plane:
                plane, sx, sy, sz = gap, qx + gap * nx, qy + gap * ny, qz + gap * nz
                px, py, pz = nx, ny, nz
        dist, _, fx, fy, fz = _foot_search(qx, qy, qz, sx, sy, sz, shape, iterations)
        if dist < out[i]:
            foot[0, i], foot[1, i], foot[2, i] = fx, fy, fz
        if plane < min(out[i], dist):
            foot[0, i], foot[1, i], foot[2, i] = px, py, pz
        out[i] = min(out[i], dist, plane)
    if starts.shape[1] == n:
        for i in range(n):
            d0, d1 = starts[0, i] - center[0], starts[1, i] - center[1]
            d2 = starts[2, i] - center[2]
            sx = rot[0, 0] * d0 + rot[1, 0] * d1 + rot[2, 0] * d2
            sy = rot[0, 1] * d0 + rot[1, 1] * d1 + rot[2, 1] * d2
            sz = rot[0, 2] * d0 + rot[1, 2] * d1 + rot[2, 2] * d2
            dist, _, fx, fy, fz = _foot_search(
                body[0, i], body[1, i], body[2, i], sx, sy, sz, shape, iterations
            )
            if dist < out[i]:
                out[i], foot[0, i], foot[1, i], foot[2, i] = dist, fx, fy, fz
    if keep:
        for i in range(n):
            for k in range(3):
                normals[k, i] = (rot[k, 0] * foot[0, i] + rot[k, 1] * foot[1, i]
                                 + rot[k, 2] * foot[2, i])  # fmt: skip


@njit(**JIT)
def surface_sample(
    directions: np.ndarray, step: float, shape: np.ndarray, rot: np.ndarray,
    center: np.ndarray, points: np.ndarray, weights: np.ndarray,
) -> None:  # fmt: skip
    """Surface points for unit directions, with their area weights.

    Direction d (3, K) maps to the body point ``q = a * d`` (on the ellipsoid of the semi-axes,
    inside the taper's valid range) and on to the surface point on the ray through q (in
    untapered coordinates, as :func:`surface_distances` does), posed into `points` (3, K) [m]:
    a smooth one-to-one map of the sphere onto the surface. `weights` (K,) gets its area
    element ``dA / dOmega`` (by differences over `step` radians along two tangents), so that
    for directions uniform on the sphere ``sum(w f) / sum(w)`` is the mean of f over the surface
    area.
    """
    for k in range(directions.shape[1]):
        dx, dy, dz = directions[0, k], directions[1, k], directions[2, k]
        # Two unit tangents of the sphere at d.
        if abs(dz) < 0.9:
            ux, uy, uz = -dy, dx, 0.0
        else:
            ux, uy, uz = 0.0, -dz, dy
        nu = math.sqrt(ux * ux + uy * uy + uz * uz)
        ux, uy, uz = ux / nu, uy / nu, uz / nu
        vx, vy, vz = dy * uz - dz * uy, dz * ux - dx * uz, dx * uy - dy * ux
        a1, a2, a3 = shape[0], shape[1], shape[2]
        x, y, z, _, _, _ = _radial_point(a1 * dx, a2 * dy, a3 * dz, shape)
        x1, y1, z1, _, _, _ = _radial_point(
            a1 * (dx + step * ux), a2 * (dy + step * uy), a3 * (dz + step * uz), shape
        )
        x2, y2, z2, _, _, _ = _radial_point(
            a1 * (dx + step * vx), a2 * (dy + step * vy), a3 * (dz + step * vz), shape
        )
        e1x, e1y, e1z = x1 - x, y1 - y, z1 - z
        e2x, e2y, e2z = x2 - x, y2 - y, z2 - z
        cx, cy, cz = e1y * e2z - e1z * e2y, e1z * e2x - e1x * e2z, e1x * e2y - e1y * e2x
        weights[k] = math.sqrt(cx * cx + cy * cy + cz * cz) / (step * step)
        points[0, k] = rot[0, 0] * x + rot[0, 1] * y + rot[0, 2] * z + center[0]
        points[1, k] = rot[1, 0] * x + rot[1, 1] * y + rot[1, 2] * z + center[1]
        points[2, k] = rot[2, 0] * x + rot[2, 1] * y + rot[2, 2] * z + center[2]
