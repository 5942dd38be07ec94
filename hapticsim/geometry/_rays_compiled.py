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

from hapticsim.geometry.eof_compiled import INLINE, JIT, log_inside_outside, shape_fields, untapered


@njit(**INLINE)
def _first_hit(
    bx: float, by: float, bz: float, ux: float, uy: float, uz: float, length: float,
    grids: np.ndarray, shape: np.ndarray, radius: float,
) -> float:  # fmt: skip
    """One ray ``b + s u`` in the body frame (u a unit vector): s of its first sample inside,
    NaN when it misses (:func:`first_hits`)."""
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    # The chord of the bounding sphere: |b + s u|^2 = radius^2 (u is a unit vector).
    half = bx * ux + by * uy + bz * uz
    disc = half * half - (bx * bx + by * by + bz * bz - radius * radius)
    if disc <= 0.0:
        return math.nan
    root = math.sqrt(disc)
    lo = max(-half - root, 0.0)
    hi = min(-half + root, length)
    if hi <= lo:
        return math.nan
    step = (hi - lo) / (grids[0] - 1)
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
            return math.nan
        if first < 0:
            first = count - 1
        first = max(first, 1)
        lo = lo + step * (first - 1)
        if level + 1 < grids.shape[0]:
            step = step / (grids[level + 1] - 1)
    return lo + step


@njit(**INLINE)
def _body(x: float, y: float, z: float, rot: np.ndarray) -> tuple[float, float, float]:
    """A world vector (x, y, z) in the body frame of rotation `rot` (its columns the axes)."""
    return (rot[0, 0] * x + rot[1, 0] * y + rot[2, 0] * z,
            rot[0, 1] * x + rot[1, 1] * y + rot[2, 1] * z,
            rot[0, 2] * x + rot[1, 2] * y + rot[2, 2] * z)  # fmt: skip


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
    for r in range(origins.shape[1]):
        bx, by, bz = _body(origins[0, r] - center[0], origins[1, r] - center[1],
                           origins[2, r] - center[2], rot)  # fmt: skip
        ux, uy, uz = _body(directions[0, r], directions[1, r], directions[2, r], rot)
        out[r] = _first_hit(bx, by, bz, ux, uy, uz, length, grids, shape, radius)


@njit(**JIT)
def segment_depths(
    points: np.ndarray, normals: np.ndarray, reach: float, grids: np.ndarray,
    shape: np.ndarray, rot: np.ndarray, center: np.ndarray, radius: float, out: np.ndarray,
) -> None:  # fmt: skip
    """How deep each point lies inside the solid along its inward normal, into `out` (k,):
    0 outside (``log F > 0``), else ``reach - s``, s where the segment from ``p - reach m``
    along ``m`` enters the solid (:func:`first_hits`' search; 0 when it finds no entry).

    Args:
        points, normals: (3, k) float, points [m, world] and their outward unit normals.
        reach: the segment's length [m].
        grids, shape, rot, center, radius: as :func:`first_hits`.
    """
    a1, a2, a3, e1, e2, tx, ty = shape_fields(shape)
    for r in range(points.shape[1]):
        px, py, pz = _body(points[0, r] - center[0], points[1, r] - center[1],
                           points[2, r] - center[2], rot)  # fmt: skip
        xs, ys, _, _ = untapered(px, py, pz, a3, tx, ty)
        if log_inside_outside(xs, ys, pz, a1, a2, a3, e1, e2)[0] > 0.0:
            out[r] = 0.0
            continue
        m0, m1, m2 = normals[0, r], normals[1, r], normals[2, r]
        bx, by, bz = _body(points[0, r] - reach * m0 - center[0],
                           points[1, r] - reach * m1 - center[1],
                           points[2, r] - reach * m2 - center[2], rot)  # fmt: skip
        ux, uy, uz = _body(m0, m1, m2, rot)
        s = _first_hit(bx, by, bz, ux, uy, uz, reach, grids, shape, radius)
        out[r] = 0.0 if math.isnan(s) else max(reach - s, 0.0)
