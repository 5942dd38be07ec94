"""Ray casting on solids: the first point where a ray enters the solid.

Every solid casts its own rays (:meth:`hapticsim.geometry.solid.Solid.first_hits`): a
superquadric by the compiled kernel :func:`hapticsim.geometry._rays_compiled.first_hits` (its
chord through the bounding sphere, a coarse grid refined twice), any other solid by its inside
test on the same grids, vectorised by numpy. The analytic touch backend casts its approach rays
with it, the tactile depth model its taxels' rays (:mod:`hapticsim.perception.tactile.depth`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.solid import Solid, solid_arg

Array = NDArray[np.float64]

#: Grid points of the coarse search along a ray.
RAY_GRID: int = 64
#: Grid points of each refinement.
REFINE_GRID: int = 32


def raycast_many(
    shape: Solid,
    origins: Array,
    directions: Array,
    length: float,
    grids: tuple[int, ...] = (RAY_GRID, REFINE_GRID, REFINE_GRID),
) -> Array:
    """Distances along rays to their first intersections with the solid (batched).

    The ray ``origin + s * direction``, ``s in [0, length]``, is sampled on a coarse grid of
    ``grids[0]`` points and the first step into the solid is refined on finer grids, so the
    distance is accurate to ``chord / prod(g - 1 for g in grids)`` for rays that do not graze
    the surface, the chord being the searched part of the ray (a superquadric searches only its
    bounding sphere's chord: 2e-6 m for a 12 cm chord with the default grids).

    Args:
        shape: the solid.
        origins: (k, 3) float, starts of the rays [m, world].
        directions: (k, 3) float, unit directions.
        length: how far to search [m].
        grids: samples per level, each >= 2.

    Returns:
        (k,) float, s [m] of the first intersection, NaN for rays that do not enter the solid.
    """
    return solid_arg(shape, "shape").first_hits(origins, directions, length, tuple(grids))


def raycast(shape: Solid, origin: Array, direction: Array, length: float) -> float | None:
    """Distance along one ray to its first intersection with the solid, or None.

    See :func:`raycast_many`.

    Args:
        shape: the solid.
        origin: (3,) float, start of the ray [m, world].
        direction: (3,) float, unit direction.
        length: how far to search [m].
    """
    s = float(raycast_many(shape, origin[None, :], direction[None, :], length)[0])
    return None if np.isnan(s) else s


__all__ = ["RAY_GRID", "REFINE_GRID", "raycast", "raycast_many"]
