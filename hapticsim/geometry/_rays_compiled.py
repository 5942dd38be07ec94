"""Compiled ray casting on a superquadric (numba): the first point where a ray enters the solid.

The search of :func:`hapticsim.geometry.rays.raycast_many`, compiled: the ray
``origin + s * direction``, ``s in [0, length]``, is sampled on a coarse grid, and the step into
the solid (``F <= 1``, i.e. ``log F <= 0``, with the one compiled inside-outside function) is
refined on finer grids that each span one step of the previous one. Only the ray's chord through a
sphere that contains the solid is searched, and each level stops at its first sample inside, so a
ray costs a few dozen evaluations of F.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hapticsim.geometry.eof_compiled import JIT, log_inside_outside, shape_fields, untapered


@njit(**JIT)
def first_hits(
    origins: np.ndarray, directions: np.ndarray, length: float, grids: np.ndarray,
    shape: np.ndarray, rot: np.ndarray, center: np.ndarray, radius: float, out: np.ndarray,
) -> None:  # fmt: skip
    """Distance along each ray to its first intersection with the solid, into `out` (k,).

    Only the ray's chord through the sphere of `radius` about the centre (which holds the
    solid) is searched, so the grids' resolution goes where the solid can be.

    Args:
        origins, directions: (3, k) float, ray starts [m, world] and unit directions.
        length: how far to search [m].
        grids: (m,) int64, samples per level (each >= 2).
        shape: (7,) a1, a2, a3, eps1, eps2, tx, ty; rot: (3, 3); center: (3,) [m].
        radius: radius of a sphere about the centre that contains the solid [m].
        out: (k,) float: s [m] of the first sample inside, NaN for rays that miss.
    """
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    for r in range(origins.shape[1]):
        # The ray in the body frame: p(s) = b + s u.
        d0, d1, d2 = origins[0, r] - center[0], origins[1, r] - center[1], origins[2, r] - center[2]
        w0, w1, w2 = directions[0, r], directions[1, r], directions[2, r]
        bx = rot[0, 0] * d0 + rot[1, 0] * d1 + rot[2, 0] * d2
        by = rot[0, 1] * d0 + rot[1, 1] * d1 + rot[2, 1] * d2
        bz = rot[0, 2] * d0 + rot[1, 2] * d1 + rot[2, 2] * d2
        ux = rot[0, 0] * w0 + rot[1, 0] * w1 + rot[2, 0] * w2
        uy = rot[0, 1] * w0 + rot[1, 1] * w1 + rot[2, 1] * w2
        uz = rot[0, 2] * w0 + rot[1, 2] * w1 + rot[2, 2] * w2
        # The chord of the bounding sphere: |b + s u|^2 = radius^2 (u is a unit vector).
        half = bx * ux + by * uy + bz * uz
        disc = half * half - (bx * bx + by * by + bz * bz - radius * radius)
        if disc <= 0.0:
            out[r] = math.nan
            continue
        root = math.sqrt(disc)
        lo = max(-half - root, 0.0)
        hi = min(-half + root, length)
        if hi <= lo:
            out[r] = math.nan
            continue
        step = (hi - lo) / (grids[0] - 1)
        hit = True
        for level in range(grids.shape[0]):
            count = grids[level]
            first = -1
            for j in range(count):
                s = lo + step * j
                px, py, pz = bx + s * ux, by + s * uy, bz + s * uz
                xs, ys, _, _ = untapered(px, py, pz, a3, tx, ty)
                if log_inside_outside(xs, ys, pz, a1, a2, a3, e1, e2)[0] <= 0.0:
                    first = j
                    break
            if level == 0 and first < 0:
                hit = False
                break
            if first < 0:
                first = count - 1
            first = max(first, 1)
            lo = lo + step * (first - 1)
            if level + 1 < grids.shape[0]:
                step = step / (grids[level + 1] - 1)
        out[r] = lo + step if hit else math.nan
