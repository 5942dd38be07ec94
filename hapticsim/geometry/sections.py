"""A stroke's geometry on a convex solid: the tangent frame at a contact, the plane a stroke
follows, and the points along that plane's section of the solid (the analytic backend's
contour following, and the hand's stroke planning on the rough estimate).

Angles in radians, lengths in metres, world frame.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.rays import RAY_GRID, REFINE_GRID, raycast, raycast_many
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]


def tangent_frame(normal: Array) -> tuple[Array, Array]:
    """Horizontal and upward unit tangents ``(t_h, t_v)`` at a surface with outward `normal`.

    ``t_h = z x n`` normalised (``x x n`` when n is vertical), ``t_v = n x t_h``.

    Args:
        normal: (3,) float unit vector.

    Returns:
        two (3,) float unit vectors, orthogonal to each other and to `normal`.
    """
    n = np.asarray(normal, dtype=np.float64)
    t = np.cross(np.array([0.0, 0.0, 1.0]), n)
    if np.linalg.norm(t) < 1e-6:
        t = np.cross(np.array([1.0, 0.0, 0.0]), n)
    t = t / np.linalg.norm(t)
    return t, np.cross(n, t)


#: Rays from inside a stroke's section that sample its curve.
_SECTION_RAYS: int = 160


def stroke_plane(shape: Solid, first: Array, stroke_angle: float) -> tuple[Array, Array]:
    """Initial direction and plane normal of a stroke from `first` (action semantics).

    Args:
        shape: the surface the stroke starts on.
        first: (3,) float, first contact [m, world] (on `shape`).
        stroke_angle: psi [rad] in the tangent frame of :func:`tangent_frame`.

    Returns:
        direction (3,) unit tangent, plane_normal (3,) unit normal of the stroke's plane.
    """
    n0 = shape.normals(first[None, :])[0]
    t_h, t_v = tangent_frame(n0)
    direction = np.cos(stroke_angle) * t_h + np.sin(stroke_angle) * t_v
    return direction, np.cross(n0, direction)


def section_walk(
    shape: Solid,
    first: Array,
    stroke_angle: float,
    n_steps: int,
    spacing: float,
    keep: Callable[[Array], bool] | None = None,
) -> list[Array]:
    """Points `spacing` apart (arc length) along the section of `shape` by a stroke's plane.

    The section of the convex solid by the plane through `first` spanned by its normal and the
    stroke direction (:func:`stroke_plane`) is a convex curve; seen from a point inside it (the
    middle of the chord along the first normal) each direction meets it once. The curve is
    sampled on 160 such rays, walked from `first` in the stroke direction, and the points at
    arc lengths ``spacing, 2 spacing, ...`` are moved back onto the exact surface along their
    rays, so a stroke rolls over edges and corners onto the next face.

    Args:
        shape: the convex superquadric.
        first: (3,) float, start point on the surface [m, world].
        stroke_angle: psi [rad] (:func:`stroke_plane`).
        n_steps: points to add after `first`.
        spacing: arc length between points [m].
        keep: stop before the first point for which this returns False (e.g. the support).

    Returns:
        ``[first, p1, p2, ...]``, at most ``n_steps + 1`` points (3,) [m, world].
    """
    first = np.asarray(first, dtype=np.float64)
    out: list[Array] = [first]
    if n_steps <= 0:
        return out
    direction, plane = stroke_plane(shape, first, stroke_angle)
    n0 = shape.normals(first[None, :])[0]
    reach = 4.0 * shape.bounding_radius + 4.0 * float(np.linalg.norm(first - shape.center))
    back = raycast(shape, first - reach * n0, n0, reach)
    center = first if back is None else 0.5 * (first + (first - reach * n0 + back * n0))
    e1 = first - center
    rho = float(np.linalg.norm(e1))
    if rho < 1e-9:
        return out
    e1 /= rho
    e2 = np.cross(plane, e1)
    sign = 1.0 if direction @ e2 >= 0 else -1.0  # walk towards the stroke direction
    theta = sign * np.linspace(0.0, 2.0 * np.pi, _SECTION_RAYS)
    rays = np.cos(theta)[:, None] * e1 + np.sin(theta)[:, None] * e2
    curve = center + _boundary(shape, center, rays, reach, (32, 16, 16))[:, None] * rays
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
    targets = spacing * np.arange(1, n_steps + 1)
    targets = targets[targets < arc[-1] - spacing]  # not all the way round
    if len(targets) == 0:
        return out
    approx = np.stack([np.interp(targets, arc, curve[:, k]) for k in range(3)], axis=1)
    rays = approx - center
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    points = center + _boundary(shape, center, rays, reach)[:, None] * rays
    for q in points:
        if keep is not None and not keep(q):
            break
        out.append(q)
    return out


def _boundary(
    shape: Solid,
    inside: Array,
    rays: Array,
    reach: float,
    grids: tuple[int, ...] = (RAY_GRID, REFINE_GRID, REFINE_GRID),
) -> Array:
    """(k,) distances [m] from an interior point along unit `rays` to the surface."""
    s = raycast_many(shape, inside + reach * rays, -rays, reach, grids=grids)
    return reach - np.nan_to_num(s, nan=reach)


__all__ = ["section_walk", "stroke_plane", "tangent_frame"]
