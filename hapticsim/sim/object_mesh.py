"""Collision geometry of objects (:func:`collision_parts`) and the stand under them
(:func:`support_foot`, :func:`support_radius`), for any solid (SPEC §10).

MuJoCo collides with convex hulls. Each kind of solid says which convex pieces it collides as
(:meth:`~hapticsim.geometry.solid.Solid.convex_pieces`, in a body frame of its own):

- a superquadric: one piece, the hull of the vertices of its uniform and natural meshes
  (paper eqs. 6 and 1: the uniform grid spreads vertices evenly over faces, the natural one
  crowds them into the rounded edges of box-like shapes, where a uniform hull's normals are off
  by 10-20 degrees; every vertex lies on the true surface);
- a union of superquadrics: one such piece per part;
- a mesh: itself when convex, else its convex decomposition by coacd (extra ``meshes``); its
  true surface stays the mesh.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import SimulationError
from hapticsim.geometry.mesh_solid import DECOMPOSITION_THRESHOLD
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class CollisionParts:
    """The convex pieces MuJoCo collides with, in the object's body frame.

    Attributes:
        parts: vertex arrays (k, 3) [m, body frame], one per convex piece (MuJoCo builds the
            hull of each).
        body_position: (3,) float, origin of the object body [m, world].
        body_rotation: (3, 3) float, orientation of the object body.
        method: how the pieces were made (stated in reports).
    """

    parts: tuple[Array, ...]
    body_position: Array
    body_rotation: Array
    method: str

    @property
    def vertices_world(self) -> Array:
        """(n, 3) float, all piece vertices in the world [m]."""
        return np.concatenate(self.parts) @ self.body_rotation.T + self.body_position


def collision_parts(truth: Solid, resolution: int) -> CollisionParts:
    """The collision geometry of an object (module docstring).

    Args:
        truth: the object in the world.
        resolution: mesh longitudes of a superquadric (or a union's parts), >= 8.

    Raises:
        SimulationError: not a solid, a non-convex mesh without coacd installed, or a failed
            decomposition.
    """
    if not isinstance(truth, Solid):
        raise SimulationError(
            "the object must be a solid (Superquadric, SuperquadricUnion or MeshSolid), got "
            f"{type(truth).__name__}"
        )
    parts, position, rotation, method = truth.convex_pieces(resolution)
    return CollisionParts(parts, position, rotation, method)


def support_foot(truth: Solid, points_world: Array, level: bool = False) -> Array:
    """(3,) float, where the stand touches the object [m, world].

    The lowest point of its surface on the vertical through the centre, where the solid says
    (:meth:`~hapticsim.geometry.solid.Solid.lowest_on_vertical`: a mesh); else, of `points_world`
    (n, 3) within 1 mm of the lowest, the one nearest the centre's vertical, at the lowest
    height with `level`.
    """
    center = np.asarray(truth.center, dtype=np.float64)
    z = truth.lowest_on_vertical(center[:2])
    if z is not None:
        return np.array([center[0], center[1], z])
    low_z = float(points_world[:, 2].min())
    low = points_world[points_world[:, 2] < low_z + 1e-3]
    foot = low[np.argmin(np.linalg.norm(low[:, :2] - center[:2], axis=1))].copy()
    if level:
        foot[2] = low_z
    return foot


def support_radius(truth: Solid, stand_radius: float) -> float:
    """Radius [m] of the stand under an object: `stand_radius`, or 0.3 of the object's smallest
    horizontal half-width when that is less (:meth:`~hapticsim.geometry.solid.Solid.
    support_half_widths`: a superquadric's semi-axes a1, a2; half its box's width otherwise)."""
    return min(stand_radius, 0.3 * float(np.min(truth.support_half_widths())))


__all__ = [
    "DECOMPOSITION_THRESHOLD",
    "CollisionParts",
    "collision_parts",
    "support_foot",
    "support_radius",
]
