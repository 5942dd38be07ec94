"""Rotations as matrices, rotation vectors and quaternions (w, x, y, z).

All functions are vectorised over leading dimensions. A rotation matrix R has the body axes as
columns expressed in the world frame, so ``v_world = R @ v_body``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import ROTATION_TOL


def skew(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cross-product matrices of vectors.

    Args:
        v: (..., 3) float.

    Returns:
        (..., 3, 3) float with ``skew(v) @ u == cross(v, u)``.
    """
    v = np.asarray(v, dtype=np.float64)
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack(
        [np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], -2
    )


def rotvec_to_matrix(rotvec: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rodrigues' formula: rotation vectors (axis * angle [rad]) to matrices.

    ``R = I + s K + c K^2`` with ``K = skew(v)``, ``s = sin(t)/t``, ``c = (1 - cos t)/t^2`` and
    ``K^2 = v v^T - t^2 I``; the nine entries are written directly (no 3x3 products).

    Args:
        rotvec: (..., 3) float.

    Returns:
        (..., 3, 3) float rotation matrices.
    """
    v = np.asarray(rotvec, dtype=np.float64)
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    xx, yy, zz = x * x, y * y, z * z
    t2 = xx + yy + zz
    theta = np.sqrt(t2)
    small = theta < 1e-4
    safe = np.where(small, 1.0, theta)
    # sin(t)/t and (1-cos t)/t^2 with their Taylor limits near zero (error < 1e-17 there).
    s = np.where(small, 1.0 - t2 / 6.0, np.sin(safe) / safe)
    c = np.where(small, 0.5 - t2 / 24.0, (1.0 - np.cos(safe)) / (safe * safe))
    cxy, cxz, cyz = c * x * y, c * x * z, c * y * z
    sx, sy, sz = s * x, s * y, s * z
    out = np.empty((*v.shape[:-1], 3, 3))
    out[..., 0, 0] = 1.0 - c * (yy + zz)
    out[..., 0, 1] = cxy - sz
    out[..., 0, 2] = cxz + sy
    out[..., 1, 0] = cxy + sz
    out[..., 1, 1] = 1.0 - c * (xx + zz)
    out[..., 1, 2] = cyz - sx
    out[..., 2, 0] = cxz - sy
    out[..., 2, 1] = cyz + sx
    out[..., 2, 2] = 1.0 - c * (xx + yy)
    return out


def matrix_to_rotvec(matrix: NDArray[np.float64]) -> NDArray[np.float64]:
    """Inverse of :func:`rotvec_to_matrix`, angle in [0, pi].

    Args:
        matrix: (..., 3, 3) float rotation matrices.

    Returns:
        (..., 3) float rotation vectors.
    """
    return quaternion_to_rotvec(matrix_to_quaternion(matrix))


def quaternion_to_rotvec(quat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit quaternions (w, x, y, z) to rotation vectors with angle in [0, pi]."""
    q = np.asarray(quat, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    q = np.where(q[..., :1] < 0, -q, q)
    vec_norm = np.linalg.norm(q[..., 1:], axis=-1)
    angle = 2.0 * np.arctan2(vec_norm, q[..., 0])
    small = vec_norm < 1e-12
    scale = np.where(small, 2.0, angle / np.where(small, 1.0, vec_norm))
    return q[..., 1:] * scale[..., None]


def quaternion_to_matrix(quat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Quaternions (w, x, y, z), normalised first, to rotation matrices (..., 3, 3)."""
    q = np.asarray(quat, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def matrix_to_quaternion(matrix: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrices (..., 3, 3) to unit quaternions (w, x, y, z) with w >= 0.

    Uses the numerically stable branch on the largest of w, x, y, z.
    """
    m = np.asarray(matrix, dtype=np.float64)
    tr = np.trace(m, axis1=-2, axis2=-1)
    cand = np.stack(
        [
            1 + tr,
            1 + 2 * m[..., 0, 0] - tr,
            1 + 2 * m[..., 1, 1] - tr,
            1 + 2 * m[..., 2, 2] - tr,
        ],
        -1,
    )  # 4 * q_i^2
    i = np.argmax(cand, axis=-1)
    qi = 0.5 * np.sqrt(np.maximum(np.take_along_axis(cand, i[..., None], -1)[..., 0], 1e-300))
    d = 4 * qi
    a_ = (m[..., 2, 1] - m[..., 1, 2]) / d
    b_ = (m[..., 0, 2] - m[..., 2, 0]) / d
    c_ = (m[..., 1, 0] - m[..., 0, 1]) / d
    xy = (m[..., 0, 1] + m[..., 1, 0]) / d
    xz = (m[..., 0, 2] + m[..., 2, 0]) / d
    yz = (m[..., 1, 2] + m[..., 2, 1]) / d
    branch = i[..., None]
    q = np.select(
        [branch == 0, branch == 1, branch == 2],
        [
            np.stack([qi, a_, b_, c_], -1),
            np.stack([a_, qi, xy, xz], -1),
            np.stack([b_, xy, qi, yz], -1),
        ],
        np.stack([c_, xz, yz, qi], -1),
    )
    q = np.where(q[..., :1] < 0, -q, q)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def is_rotation(matrix: NDArray[np.float64], tol: float = ROTATION_TOL) -> bool:
    """True when `matrix` is a (3, 3) proper rotation within `tol`."""
    m = np.asarray(matrix, dtype=np.float64)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        return False
    return bool(np.allclose(m.T @ m, np.eye(3), atol=tol) and abs(np.linalg.det(m) - 1.0) < tol)


def orthonormalize(matrix: NDArray[np.float64]) -> NDArray[np.float64]:
    """Nearest proper rotation to `matrix` (..., 3, 3) in the Frobenius norm (via SVD)."""
    u, _, vt = np.linalg.svd(np.asarray(matrix, dtype=np.float64))
    d = np.sign(np.linalg.det(u @ vt))
    u = u.copy()
    u[..., :, -1] *= d[..., None]
    return u @ vt


def random_rotation(rng: np.random.Generator, size: int | None = None) -> NDArray[np.float64]:
    """Uniformly distributed rotation matrices (3, 3), or (size, 3, 3)."""
    shape = (4,) if size is None else (size, 4)
    return quaternion_to_matrix(rng.standard_normal(shape))
