"""A mesh truth seen through the interface the analytic backend uses on a superquadric.

The analytic backend's ray casts and strokes (:mod:`hapticsim.envs.analytic`) need of the true
object only ``contains`` (points inside), ``normals`` (outward unit normals at surface points),
``center`` and ``bounding_radius``. :class:`MeshSurface` gives them for a
:class:`~hapticsim.geometry.mesh_solid.MeshSolid`: containment by the mesh's ray parity, the
normal of the closest face (:func:`hapticsim.metrics.mesh_truth.closest_points`).

A stroke walks the section of the solid by its plane as seen from a point inside it; for a
non-convex mesh whose section is not star-shaped from that point the walk follows the outer
hull of the section where the two differ.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError
from hapticsim.geometry.mesh_solid import MeshSolid

Array = NDArray[np.float64]


class MeshSurface:
    """The analytic backend's view of a mesh solid (module docstring).

    Args:
        solid: the mesh truth, world frame.
    """

    def __init__(self, solid: MeshSolid) -> None:
        if not isinstance(solid, MeshSolid):
            raise InvalidInputError(f"`solid` must be a MeshSolid, got {type(solid).__name__}")
        self.solid = solid

    @property
    def center(self) -> Array:
        """(3,) float, the centroid [m, world]."""
        return self.solid.centroid

    @property
    def bounding_radius(self) -> float:
        """Radius [m] of a sphere about :attr:`center` containing the solid."""
        return self.solid.bounding_radius

    def contains(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, True inside the solid."""
        return self.solid.contains(points_world)

    def normals(self, points_world: Array) -> Array:
        """(n, 3) float, outward unit normals of the faces closest to the points."""
        from hapticsim.metrics.mesh_truth import closest_points

        _, face = closest_points(self.solid, np.asarray(points_world, dtype=np.float64))
        return np.array(self.solid.face_normals[face])


__all__ = ["MeshSurface"]
