"""Collision geometry of objects (:func:`collision_parts`) and the stand under them
(:func:`support_foot`, :func:`support_radius`, from what the stand asks of a solid:
:func:`support_points`, :func:`lowest_on_vertical`, :func:`support_half_widths`), for any solid
(SPEC §10).

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
from functools import singledispatch

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import SimulationError
from hapticsim.geometry.mesh_solid import DECOMPOSITION_THRESHOLD, MeshSolid
from hapticsim.geometry.solid import Solid
from hapticsim.geometry.superquadric import Superquadric

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


# ----------------------------------------------------------------- the stand
# What the stand asks of a solid, generic and per kind (singledispatch): its caller's questions,
# not the solid's geometric contract.
@singledispatch
def support_points(truth: Solid) -> Array:
    """(n, 3) float, surface points [m, world] the stand's foot is chosen among where
    :func:`lowest_on_vertical` says nothing (generic: the surface mesh's vertices at 64
    longitudes)."""
    return np.asarray(truth.surface_mesh(64)[0], dtype=np.float64)


@support_points.register
def _(truth: Superquadric) -> Array:
    # (16471, 3) surface points on a 91 x 181 grid of the angles (eta, omega)
    eta = np.linspace(-np.pi / 2, np.pi / 2, 91)
    omega = np.linspace(-np.pi, np.pi, 181)
    ee, oo = np.meshgrid(eta, omega)
    return truth.surface(ee.ravel(), oo.ravel())[0]


@support_points.register
def _(truth: MeshSolid) -> Array:
    return np.array(truth.vertices)


@singledispatch
def lowest_on_vertical(truth: Solid, xy: Array) -> float | None:
    """Height [m] of the lowest surface point on the vertical line through `xy` (2,), or None
    where a kind does not say (generic; a mesh says)."""
    return None


@lowest_on_vertical.register
def _(truth: MeshSolid, xy: Array) -> float | None:
    # the lowest point where the vertical through xy meets the faces (barycentric signs)
    t = np.asarray(truth.triangles)
    xy = np.asarray(xy, dtype=np.float64)
    a, b, c = (t[:, k, :2] - xy for k in range(3))
    wa = b[:, 0] * c[:, 1] - c[:, 0] * b[:, 1]
    wb = c[:, 0] * a[:, 1] - a[:, 0] * c[:, 1]
    wc = a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]
    total = wa + wb + wc
    inside = (((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))) & (
        np.abs(total) > 0
    )
    w = np.stack([wa, wb, wc], axis=1)[inside] / total[inside, None]
    z = np.einsum("ij,ij->i", w, t[inside, :, 2])
    return float(z.min()) if z.size else None


@singledispatch
def support_half_widths(truth: Solid) -> Array:
    """(2,) float, the horizontal half-widths [m] the stand under the solid is sized by
    (generic: half its bounding box's width in x and y)."""
    lo, hi = truth.bounds
    return 0.5 * (hi[:2] - lo[:2])


@support_half_widths.register
def _(truth: Superquadric) -> Array:
    return np.array(truth.a[:2])  # the semi-axes a1, a2


def support_foot(truth: Solid, points_world: Array, level: bool = False) -> Array:
    """(3,) float, where the stand touches the object [m, world].

    The lowest point of its surface on the vertical through the centre, where the solid says
    (:func:`lowest_on_vertical`: a mesh); else, of `points_world` (n, 3) within 1 mm of the
    lowest, the one nearest the centre's vertical, at the lowest height with `level`.
    """
    center = np.asarray(truth.center, dtype=np.float64)
    z = lowest_on_vertical(truth, center[:2])
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
    horizontal half-width when that is less (:func:`support_half_widths`)."""
    return min(stand_radius, 0.3 * float(np.min(support_half_widths(truth))))


__all__ = [
    "DECOMPOSITION_THRESHOLD",
    "CollisionParts",
    "collision_parts",
    "lowest_on_vertical",
    "support_foot",
    "support_half_widths",
    "support_points",
    "support_radius",
]
