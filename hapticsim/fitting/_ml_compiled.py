"""The compiled maximum-likelihood residuals of nML (numba) and their analytic Jacobian.

Per contact, body frame: the first-order signed distance ``d = (1 - s) / |n|`` to the
superquadric (positive outside) and the difference ``e = n / |n| - m`` of the model's and the
measured unit normal, weighted by ``1 / sigma_p`` and ``1 / sigma_n`` and passed through a
pseudo-Huber factor (:func:`robust_weight`); then the priors (taper, exponents, the extent
anchor) and the free-space points (:mod:`hapticsim.fitting.ml`, :mod:`hapticsim.fitting.likelihood`
say what they mean). The shape's forward and reverse passes, the frames and the Jacobian's chain
rule are the EOF kernel's (:mod:`hapticsim.geometry.eof_compiled`), inlined here; the
solvers reach these residuals through :mod:`hapticsim.fitting._problem_compiled`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hapticsim.geometry.eof_compiled import (
    INLINE,
    JIT,
    body_frame,
    jacobian_frame,
    normal_backward,
    normal_forward,
    rotate_to_body,
    shape_backward,
    shape_forward,
    to_body,
    vector_poses,
    world_column,
)
from hapticsim.geometry.layout import I_A, I_CENTER, I_EPS, I_TAPER, N_PARAMS

#: Layout of the settings array of the maximum-likelihood residuals (:func:`ml_residuals_posed`).
#: Point weight 1/sigma_p [1/m]; normal weight 1/sigma_n; robust threshold c on the normalised
#: norm of a contact's residual (<= 0: plain squares); taper prior weight 1/tau_t; eps prior
#: centre and weight 1/tau_e; free-space weight [1/m] and margin [m]; the extent anchor's weight
#: 1/tau_x [1/m] (0: none) and its 15 numbers from ML_ANCHOR on: the anchored semi-axes
#: A (3) [m], the anchored centre coordinates C (3) [m] and the three unit directions u_k (3 x 3,
#: row by row) along which the centre is anchored.
ML_POINT_WEIGHT, ML_NORMAL_WEIGHT, ML_ROBUST = 0, 1, 2
ML_TAPER_WEIGHT, ML_EPS_CENTER, ML_EPS_WEIGHT = 3, 4, 5
ML_FREE_WEIGHT, ML_FREE_MARGIN = 6, 7
ML_ANCHOR_WEIGHT, ML_ANCHOR = 8, 9
ML_ANCHOR_SIZE = 15
ML_SETTINGS = ML_ANCHOR + ML_ANCHOR_SIZE
#: With per-contact weights the settings array holds, after its ML_SETTINGS globals, one
#: multiplier per contact of its distance residual, then one per contact of its normal
#: residuals ((ML_SETTINGS + 2 n,) in all).
#: Prior residuals appended after the contacts: tx, ty, eps1, eps2, then the anchor's
#: a_k - A_k (3) and u_k . c - C_k (3).
ML_PRIORS = 10


@njit(**INLINE)
def ml_contact(
    px: float, py: float, pz: float, mx: float, my: float, mz: float,
    a1: float, a2: float, a3: float, e1: float, e2: float, tx: float, ty: float,
) -> tuple[float, float, float, float]:  # fmt: skip
    """``(d, e_x, e_y, e_z)`` of one contact: the first-order signed distance
    ``d = (1 - s) / |n|`` [m] (positive outside) and ``e = n / |n| - m``, body frame."""
    fw = shape_forward(px, py, pz, a1, a2, a3, e1, e2, tx, ty)
    nf = normal_forward(px, py, pz, fw[3], fw[4], fw[7], fw[8], fw[21], fw[22], fw[24], fw[25])
    nx, ny, nz = nf[3], nf[4], nf[8]
    il = 1.0 / (math.sqrt(nx * nx + ny * ny + nz * nz) + 1e-300)
    return (1.0 - fw[26]) * il, nx * il - mx, ny * il - my, nz * il - mz


@njit(**INLINE)
def _backward_sn(
    g_s: float, g_nx: float, g_ny: float, g_nz: float, fw: tuple, nf: tuple,
    px: float, py: float, pz: float, tx: float, ty: float, e1: float, e2: float,
) -> tuple[float, float, float, float, float, float, float, float, float, float]:  # fmt: skip
    """Gradient ``d/d(px, py, pz, a1, a2, a3, eps1, eps2, tx, ty)`` of ``g_s s + g_n . n``."""
    hu, hv, _, nx, ny, nz0, qa, qb, _ = nf
    (g_ta, g_tb, g_fx, g_fy, g_px, g_py, g_pz, g_phu, g_phv, g_psg, g_psw) = normal_backward(
        g_nx, g_ny, g_nz, px, py, pz, fw[3], fw[4], fw[7], fw[8], fw[21], fw[22], fw[24],
        hu, hv, nx, ny, nz0, qa, qb,
    )  # fmt: skip
    return shape_backward(
        g_s, g_phu, g_phv, g_psg, g_psw, 0.0, 0.0, g_pz, g_px, g_py, g_fx, g_fy, g_ta, g_tb,
        0.0, 0.0, 0.0, 0.0, 0.0, fw, px, py, pz, tx, ty, e1, e2,
    )  # fmt: skip


@njit(**INLINE)
def ml_contact_gradient(
    px: float, py: float, pz: float, mx: float, my: float, mz: float,
    a1: float, a2: float, a3: float, e1: float, e2: float, tx: float, ty: float,
    with_normals: bool,
) -> tuple:  # fmt: skip
    """:func:`ml_contact` and its derivatives (reverse mode, one pass per output).

    Returns:
        ``(values, g_d, g_ex, g_ey, g_ez)``: the 4 values, then for each the 10 derivatives
        with respect to (px, py, pz, a1, a2, a3, eps1, eps2, tx, ty); ``de_k/dm_k = -1``
        (not returned). Without normals the e entries are zero.
    """
    fw = shape_forward(px, py, pz, a1, a2, a3, e1, e2, tx, ty)
    nf = normal_forward(px, py, pz, fw[3], fw[4], fw[7], fw[8], fw[21], fw[22], fw[24], fw[25])
    nx, ny, nz = nf[3], nf[4], nf[8]
    il = 1.0 / (math.sqrt(nx * nx + ny * ny + nz * nz) + 1e-300)
    ux, uy, uz = nx * il, ny * il, nz * il
    d = (1.0 - fw[26]) * il
    # d = (1 - s) / |n|: dd/ds = -1/|n|, dd/dn = -d u / |n|
    gd = _backward_sn(
        -il, -d * ux * il, -d * uy * il, -d * uz * il, fw, nf, px, py, pz, tx, ty, e1, e2
    )
    zero = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    if not with_normals:
        return (d, 0.0, 0.0, 0.0), gd, zero, zero, zero
    # e_k = u_k - m_k: de_k/dn = (delta_k - u_k u) / |n|
    gx = _backward_sn(
        0.0, (1.0 - ux * ux) * il, -ux * uy * il, -ux * uz * il, fw, nf, px, py, pz, tx, ty,
        e1, e2,
    )  # fmt: skip
    gy = _backward_sn(
        0.0, -uy * ux * il, (1.0 - uy * uy) * il, -uy * uz * il, fw, nf, px, py, pz, tx, ty,
        e1, e2,
    )  # fmt: skip
    gz = _backward_sn(
        0.0, -uz * ux * il, -uz * uy * il, (1.0 - uz * uz) * il, fw, nf, px, py, pz, tx, ty,
        e1, e2,
    )  # fmt: skip
    return (d, ux - mx, uy - my, uz - mz), gd, gx, gy, gz


@njit(**INLINE)
def robust_weight(z: float, c: float) -> tuple[float, float]:
    """``(w, dw/dz)`` of the pseudo-Huber loss on a squared norm z: ``w^2 z = rho(z)``.

    ``rho(z) = 2 c^2 (sqrt(1 + z / c^2) - 1)``: z for small z, ``2 c sqrt(z)`` for large, so
    ``w = sqrt(2 / (1 + q))``, ``q = sqrt(1 + z / c^2)``. ``c <= 0`` gives ``(1, 0)``.
    """
    off = c <= 0.0
    ic2 = 0.0 if off else 1.0 / (c * c)
    q = math.sqrt(1.0 + z * ic2)
    w = math.sqrt(2.0 / (1.0 + q))
    dw2 = -1.0 / (q * (1.0 + q) * (1.0 + q)) * ic2
    return w, 0.5 * dw2 / w


@njit(**JIT)
def ml_residual_count(n: int, with_normals: bool, n_free: int) -> int:
    """Length of the ML residual vector: 4 (1 without normals) per contact, the priors, one per
    free-space point."""
    return (4 if with_normals else 1) * n + ML_PRIORS + n_free


@njit(**JIT)
def ml_residuals_posed(
    points: np.ndarray, normals: np.ndarray, with_normals: bool,
    a: np.ndarray, eps: np.ndarray, taper: np.ndarray, rot: np.ndarray, center: np.ndarray,
    settings: np.ndarray, free: np.ndarray, out: np.ndarray, tally: np.ndarray,
) -> None:  # fmt: skip
    """Maximum-likelihood residual vectors (P, m) into `out` for P posed bodies.

    Laid out in blocks of n (all distances, then the three normal components; without normals
    only the distances), then the priors, then the free space; per contact i:

    - ``w_i (d_i / sigma_p, e_i / sigma_n)`` with d the first-order signed distance
      ``(1 - s) / |grad log G|`` [m] and ``e = n'/|n'| - n`` (model unit normal minus measured);
      ``w_i`` the pseudo-Huber factor of the normalised squared norm (:func:`robust_weight`);
    - ``tx / tau_t``, ``ty / tau_t``, ``(eps_k - eps_0) / tau_e``; the anchor's
      ``(a_k - A_k) / tau_x`` and ``(u_k . c - C_k) / tau_x`` (zero when its weight is 0);
    - per free-space point q: ``max(0, margin - d(q)) / sigma_p``, zero outside the solid.

    Args:
        points, normals, with_normals, a, eps, taper, rot, center: as :func:`residuals_posed`.
        settings: (:data:`ML_SETTINGS`,) float, see the ``ML_*`` indices, optionally followed
            by n per-contact multipliers of the distances and n of the normal residuals
            ((ML_SETTINGS + 2 n,)).
        free: (3, f) float, free-space points [m, world] (f may be 0).
        out: (P, :func:`ml_residual_count`) float.
        tally: (1,) int64, incremented by P evaluations.
    """
    tally[0] += a.shape[0]
    n, nf = points.shape[1], free.shape[1]
    k = 4 if with_normals else 1
    wp, wn, c = settings[ML_POINT_WEIGHT], settings[ML_NORMAL_WEIGHT], settings[ML_ROBUST]
    wt, e0, we = settings[ML_TAPER_WEIGHT], settings[ML_EPS_CENTER], settings[ML_EPS_WEIGHT]
    wf, margin = settings[ML_FREE_WEIGHT], settings[ML_FREE_MARGIN]
    px_w, py_w, pz_w = points[0], points[1], points[2]
    nx_w, ny_w, nz_w = normals[0], normals[1], normals[2]
    per_contact = settings.shape[0] > ML_SETTINGS
    for b in range(a.shape[0]):
        a1, a2, a3 = a[b, 0], a[b, 1], a[b, 2]
        e1, e2 = eps[b, 0], eps[b, 1]
        tx, ty = taper[b, 0], taper[b, 1]
        f = body_frame(rot[b], center[b])
        row = out[b]
        if with_normals:
            o_d, o_x, o_y, o_z = row[0:n], row[n : 2 * n], row[2 * n : 3 * n], row[3 * n : 4 * n]
            for i in range(n):
                bx, by, bz = to_body(px_w[i], py_w[i], pz_w[i], f)[3:]
                mx, my, mz = rotate_to_body(nx_w[i], ny_w[i], nz_w[i], f)
                d, ex, ey, ez = ml_contact(bx, by, bz, mx, my, mz, a1, a2, a3, e1, e2, tx, ty)
                if per_contact:
                    m, mn = settings[ML_SETTINGS + i], settings[ML_SETTINGS + n + i]
                    d, ex, ey, ez = m * d, mn * ex, mn * ey, mn * ez
                rd, rx, ry, rz = wp * d, wn * ex, wn * ey, wn * ez
                w = robust_weight(rd * rd + rx * rx + ry * ry + rz * rz, c)[0]
                o_d[i], o_x[i], o_y[i], o_z[i] = w * rd, w * rx, w * ry, w * rz
        else:
            o_d = row[0:n]
            for i in range(n):
                bx, by, bz = to_body(px_w[i], py_w[i], pz_w[i], f)[3:]
                d = ml_contact(bx, by, bz, 0.0, 0.0, 0.0, a1, a2, a3, e1, e2, tx, ty)[0]
                if per_contact:
                    d = settings[ML_SETTINGS + i] * d
                rd = wp * d
                o_d[i] = robust_weight(rd * rd, c)[0] * rd
        base = k * n
        row[base] = wt * tx
        row[base + 1] = wt * ty
        row[base + 2] = we * (e1 - e0)
        row[base + 3] = we * (e2 - e0)
        wa = settings[ML_ANCHOR_WEIGHT]
        for q in range(3):
            row[base + 4 + q] = wa * (a[b, q] - settings[ML_ANCHOR + q])
            u = ML_ANCHOR + 6 + 3 * q
            cu = (settings[u] * center[b, 0] + settings[u + 1] * center[b, 1]
                  + settings[u + 2] * center[b, 2])  # fmt: skip
            row[base + 7 + q] = wa * (cu - settings[ML_ANCHOR + 3 + q])
        base += ML_PRIORS
        for j in range(nf):
            bx, by, bz = to_body(free[0, j], free[1, j], free[2, j], f)[3:]
            d = ml_contact(bx, by, bz, 0.0, 0.0, 0.0, a1, a2, a3, e1, e2, tx, ty)[0]
            row[base + j] = wf * max(margin - d, 0.0)


@njit(**JIT)
def ml_residuals_vectors(
    points: np.ndarray, normals: np.ndarray, with_normals: bool, vectors: np.ndarray,
    settings: np.ndarray, free: np.ndarray, out: np.ndarray, tally: np.ndarray,
) -> None:  # fmt: skip
    """:func:`ml_residuals_posed` for P parameter vectors (P, 13)."""
    a, eps, taper, rot, center = vector_poses(vectors)
    ml_residuals_posed(
        points, normals, with_normals, a, eps, taper, rot, center, settings, free, out, tally,
    )  # fmt: skip


@njit(**JIT)
def ml_jacobian_vector(
    points: np.ndarray, normals: np.ndarray, with_normals: bool, x: np.ndarray,
    settings: np.ndarray, free: np.ndarray, r_out: np.ndarray, jac_t: np.ndarray,
    tally: np.ndarray,
) -> None:  # fmt: skip
    """The ML residual vector (m,) of one parameter vector `x` (13,) and its transposed
    Jacobian (13, m) (:func:`ml_residuals_posed` for the layout; counts 13 evaluations).

    A contact's robust factor is differentiated too: with r the contact's k weighted residuals,
    ``z = |r|^2`` and ``w = w(z)``, the rows of ``w r`` have the Jacobian
    ``w J + 2 w'(z) r (r^T J)``, so the least squares minimise the robust cost exactly.
    """
    tally[0] += N_PARAMS
    n, nf = points.shape[1], free.shape[1]
    k = 4 if with_normals else 1
    wp, wn, c = settings[ML_POINT_WEIGHT], settings[ML_NORMAL_WEIGHT], settings[ML_ROBUST]
    wt, e0, we = settings[ML_TAPER_WEIGHT], settings[ML_EPS_CENTER], settings[ML_EPS_WEIGHT]
    wf, margin = settings[ML_FREE_WEIGHT], settings[ML_FREE_MARGIN]
    f, rm, jm = jacobian_frame(x)
    a1, a2, a3 = x[I_A], x[I_A + 1], x[I_A + 2]
    e1, e2, tx, ty = x[I_EPS], x[I_EPS + 1], x[I_TAPER], x[I_TAPER + 1]
    per_contact = settings.shape[0] > ML_SETTINGS
    wp0, wn0 = wp, wn
    for i in range(n):
        if per_contact:  # this contact's weights times its multipliers
            wp, wn = wp0 * settings[ML_SETTINGS + i], wn0 * settings[ML_SETTINGS + n + i]
        d0, d1, d2, bx, by, bz = to_body(points[0, i], points[1, i], points[2, i], f)
        m0 = m1 = m2 = mx = my = mz = 0.0
        if with_normals:
            m0, m1, m2 = normals[0, i], normals[1, i], normals[2, i]
            mx, my, mz = rotate_to_body(m0, m1, m2, f)
        vals, gd, gx, gy, gz = ml_contact_gradient(
            bx, by, bz, mx, my, mz, a1, a2, a3, e1, e2, tx, ty, with_normals
        )
        col = i
        world_column(
            jac_t, col, wp * gd[0], wp * gd[1], wp * gd[2], 0.0, 0.0, 0.0, wp * gd[3],
            wp * gd[4], wp * gd[5], wp * gd[6], wp * gd[7], wp * gd[8], wp * gd[9], rm, jm,
            d0, d1, d2, m0, m1, m2,
        )  # fmt: skip
        r_out[col] = wp * vals[0]
        if with_normals:
            for j in range(3):
                g = gx if j == 0 else (gy if j == 1 else gz)
                world_column(
                    jac_t, col + (1 + j) * n, wn * g[0], wn * g[1], wn * g[2],
                    -wn if j == 0 else 0.0, -wn if j == 1 else 0.0, -wn if j == 2 else 0.0,
                    wn * g[3], wn * g[4], wn * g[5], wn * g[6], wn * g[7], wn * g[8], wn * g[9],
                    rm, jm, d0, d1, d2, m0, m1, m2,
                )  # fmt: skip
                r_out[col + (1 + j) * n] = wn * vals[1 + j]
        if c > 0.0:
            z = 0.0
            for j in range(k):
                z += r_out[col + j * n] * r_out[col + j * n]
            w, dw = robust_weight(z, c)
            for p in range(N_PARAMS):
                rj = 0.0
                for j in range(k):
                    rj += r_out[col + j * n] * jac_t[p, col + j * n]
                for j in range(k):
                    jac_t[p, col + j * n] = (
                        w * jac_t[p, col + j * n] + 2.0 * dw * r_out[col + j * n] * rj
                    )
            for j in range(k):
                r_out[col + j * n] *= w
    base = k * n
    for j in range(ML_PRIORS):
        for p in range(N_PARAMS):
            jac_t[p, base + j] = 0.0
    r_out[base], jac_t[I_TAPER, base] = wt * tx, wt
    r_out[base + 1], jac_t[I_TAPER + 1, base + 1] = wt * ty, wt
    r_out[base + 2], jac_t[I_EPS, base + 2] = we * (e1 - e0), we
    r_out[base + 3], jac_t[I_EPS + 1, base + 3] = we * (e2 - e0), we
    wa = settings[ML_ANCHOR_WEIGHT]
    for q in range(3):
        r_out[base + 4 + q] = wa * (x[I_A + q] - settings[ML_ANCHOR + q])
        jac_t[I_A + q, base + 4 + q] = wa
        u = ML_ANCHOR + 6 + 3 * q
        cu = 0.0
        for j in range(3):
            cu += settings[u + j] * x[I_CENTER + j]
            jac_t[I_CENTER + j, base + 7 + q] = wa * settings[u + j]
        r_out[base + 7 + q] = wa * (cu - settings[ML_ANCHOR + 3 + q])
    base += ML_PRIORS
    for j in range(nf):
        d0, d1, d2, bx, by, bz = to_body(free[0, j], free[1, j], free[2, j], f)
        vals, gd, _, _, _ = ml_contact_gradient(
            bx, by, bz, 0.0, 0.0, 0.0, a1, a2, a3, e1, e2, tx, ty, False
        )
        h = margin - vals[0]
        col = base + j
        if h > 0.0:
            r_out[col] = wf * h
            world_column(
                jac_t, col, -wf * gd[0], -wf * gd[1], -wf * gd[2], 0.0, 0.0, 0.0, -wf * gd[3],
                -wf * gd[4], -wf * gd[5], -wf * gd[6], -wf * gd[7], -wf * gd[8], -wf * gd[9],
                rm, jm, d0, d1, d2, 0.0, 0.0, 0.0,
            )  # fmt: skip
        else:
            r_out[col] = 0.0
            for p in range(N_PARAMS):
                jac_t[p, col] = 0.0
