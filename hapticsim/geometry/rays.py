"""Ray casting on solids: the first point where a ray enters the solid.

A superquadric is searched by the compiled kernel :func:`hapticsim.geometry._rays_compiled.
first_hits` (its chord through the bounding sphere, a coarse grid refined twice); any other solid
with an inside test (``contains``: a mesh) by the same grids, vectorised by numpy. The analytic
touch backend casts its approach rays with it, the tactile depth model its taxels' rays
(:mod:`hapticsim.tactile.depth`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry._eof_compiled import unpack
from hapticsim.geometry._rays_compiled import first_hits
from hapticsim.geometry.superquadric import Superquadric

Array = NDArray[np.float64]

#: Grid points of the coarse search along a ray.
RAY_GRID: int = 64
#: Grid points of each refinement.
REFINE_GRID: int = 32


def raycast_many(
    shape: Any,
    origins: Array,
    directions: Array,
    length: float,
    grids: tuple[int, ...] = (RAY_GRID, REFINE_GRID, REFINE_GRID),
) -> Array:
    """Distances along rays to their first intersections with the solid (batched).

    The ray ``origin + s * direction``, ``s in [0, length]``, is sampled on a coarse grid of
    ``grids[0]`` points and the first step into the solid (``F <= 1``) is refined on finer grids,
    so the distance is accurate to ``chord / prod(g - 1 for g in grids)`` for rays that do not
    graze the surface, the chord being the ray's part inside the bounding sphere (2e-6 m for a
    12 cm chord with the default grids). Compiled
    (:func:`hapticsim.geometry._rays_compiled.first_hits`): only the chord is searched, and each
    level stops at its first sample inside.

    Args:
        shape: the solid: a superquadric, or anything with ``contains(points) -> bool``.
        origins: (k, 3) float, starts of the rays [m, world].
        directions: (k, 3) float, unit directions.
        length: how far to search [m].
        grids: samples per level, each >= 2.

    Returns:
        (k,) float, s [m] of the first intersection, NaN for rays that do not enter the solid.
    """
    if isinstance(shape, Superquadric):
        origins = np.ascontiguousarray(np.asarray(origins, dtype=np.float64).reshape(-1, 3).T)
        directions = np.ascontiguousarray(np.asarray(directions, dtype=np.float64).reshape(-1, 3).T)
        out = np.empty(origins.shape[1])
        first_hits(
            origins, directions, float(length), np.asarray(grids, dtype=np.int64), *unpack(shape),
            1.0001 * shape.bounding_radius, out,
        )  # fmt: skip
        return out
    # A mesh solid: its containment test on the grids, vectorised by numpy.
    origins = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    directions = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    k = len(origins)
    lo = np.zeros(k)
    step = np.full(k, float(length) / (grids[0] - 1))
    hit = np.ones(k, dtype=bool)
    rows = np.arange(k)
    for level, count in enumerate(grids):
        s = lo[:, None] + step[:, None] * np.arange(count)[None, :]
        pts = origins[:, None, :] + s[..., None] * directions[:, None, :]
        inside = shape.contains(pts.reshape(-1, 3)).reshape(k, count)  # F <= 1 (or a mesh)
        any_in = inside.any(axis=1)
        if level == 0:
            hit = any_in
        first = np.maximum(np.where(any_in, np.argmax(inside, axis=1), count - 1), 1)
        lo = s[rows, first - 1]
        if level + 1 < len(grids):
            step = step / (grids[level + 1] - 1)  # the next grid spans one step of this one
    return np.where(hit, lo + step, np.nan)  # the first sample inside


def raycast(shape: Any, origin: Array, direction: Array, length: float) -> float | None:
    """Distance along one ray to its first intersection with the solid, or None.

    See :func:`raycast_many`.

    Args:
        shape: the superquadric.
        origin: (3,) float, start of the ray [m, world].
        direction: (3,) float, unit direction.
        length: how far to search [m].
    """
    s = float(raycast_many(shape, origin[None, :], direction[None, :], length)[0])
    return None if np.isnan(s) else s


__all__ = ["RAY_GRID", "REFINE_GRID", "raycast", "raycast_many"]
