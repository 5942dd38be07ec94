"""The taxel depth model: how far each taxel of a pad lies inside the object.

The skin at a taxel is compressed along the taxel's own normal (the Winkler foundation of
:mod:`hapticsim.perception.tactile.skin`), so the depth of a taxel at ``p`` with outward unit
normal ``m``
is the length of the part of the segment from the fingertip's core ``p - reach m`` to ``p`` that
lies inside the object:

    d(p) = reach - s,   s the distance from the core along m to where the segment enters,

0 when ``p`` lies outside (``reach`` is the pad's radius: the segment runs from the fingertip
sphere's centre; only the taxels inside are cast). The surface point ``p - d m`` lies on the
object. The ray cast is the solid's own (:meth:`~hapticsim.geometry.solid.Solid.segment_depths`:
compiled in one pass with the inside test on a superquadric, ``contains`` and
:func:`hapticsim.geometry.rays.raycast_many` otherwise: a mesh, a union), on the grids
:data:`TAXEL_GRIDS` (the segment's end, the taxel, is always a sample, so a shallow taxel is never
missed): its resolution is ``reach / 23625`` (0.34 um on an 8 mm fingertip), in at most 56
evaluations of the inside test per taxel.

MuJoCo's ``<tactile>`` sensor reads the object's Euclidean signed distance at the taxel
instead; for a sphere of radius R pressed by delta into a flat face the two differ by at most
``delta^2 / (4 R)`` (0.008 mm for delta = 0.5 mm, R = 8 mm): the along-normal depth is the
Euclidean one divided by the cosine of the angle between the taxel's normal and the face's.

numpy only.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float

Array = NDArray[np.float64]

#: Samples per level of a taxel's ray cast: a coarse grid of 8 along the segment from the core,
#: refined three times (the inside part is near the segment's end: 64 coarse samples, the
#: approach rays' grid, cost twice the evaluations for nothing).
TAXEL_GRIDS: tuple[int, ...] = (8, 16, 16, 16)


def taxel_depths(solid: Any, positions: Array, normals: Array, reach: float) -> Array:
    """Depths [m] of taxels inside a solid, along their inward normals (module docstring).

    Args:
        solid: a :class:`~hapticsim.geometry.solid.Solid` in the world frame.
        positions: (..., 3) float, taxel positions [m, world].
        normals: (..., 3) float, the taxels' outward unit normals [world].
        reach: the distance from the fingertip's core to the taxels [m], > 0 (the pad's radius):
            depths are at most `reach`.

    Returns:
        (...) float, depths >= 0 [m].
    """
    pos = np.asarray(positions, dtype=np.float64)
    nrm = np.asarray(normals, dtype=np.float64)
    length = finite_float(reach, "reach", low=1e-9)
    shape = pos.shape[:-1]
    out = solid.segment_depths(pos.reshape(-1, 3), nrm.reshape(-1, 3), length, TAXEL_GRIDS)
    return out.reshape(shape)


__all__ = ["TAXEL_GRIDS", "taxel_depths"]
