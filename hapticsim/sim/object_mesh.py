"""Collision meshes of objects: superquadrics and mesh solids (:func:`collision_parts`).

MuJoCo collides with a mesh's convex hull. The uniform parametrisation (paper eq. 6) spreads
vertices evenly over faces but leaves the rounded edges of box-like shapes (eps ~ 0.1) with a
single chamfer of vertices, where hull normals are off by 10-20 degrees; the natural
parametrisation (eq. 1) crowds vertices into exactly those edges. The collision mesh is the
convex hull of the vertices of both meshes (the grids of :meth:`Superquadric.to_mesh` with each
parametrisation, taken from :func:`hapticsim.geometry.mesh.surface_grid` without building trimesh
objects): every vertex lies on the true surface, faces and edges are both well sampled. MuJoCo
builds the hull itself (a mesh asset given without faces is its vertices' convex hull).

A mesh object (:class:`~hapticsim.geometry.mesh_solid.MeshSolid`) collides as it is when it is
convex; a non-convex one is split into convex parts by coacd (one geom each), and its true
surface stays the mesh.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import positive_int
from hapticsim.errors import SimulationError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.mesh import surface_grid
from hapticsim.geometry.mesh_solid import MeshSolid

Array = NDArray[np.float64]


def object_vertices(shape: Superquadric, resolution: int) -> Array:
    """Vertices of the collision mesh of a superquadric, in its body frame.

    Args:
        shape: the superquadric (its pose is ignored: vertices are in the body frame).
        resolution: longitudes of each of the two grids (``res * (res // 2 - 1) + 2`` vertices
            each, see :meth:`Superquadric.to_mesh`), >= 8.

    Returns:
        (n, 3) float, distinct surface points [m, body frame] whose convex hull is the mesh.
    """
    res = positive_int(resolution, "resolution", minimum=8)
    body = shape.replace(rotation=np.eye(3), center=np.zeros(3))
    vertices = np.concatenate(
        [surface_grid(body, res, "uniform")[0], surface_grid(body, res, "natural")[0]]
    )
    return np.unique(np.round(vertices, 12), axis=0)


# ----------------------------------------------------------------------------- any object
#: Concavity threshold of the convex decomposition of non-convex meshes (coacd's ``threshold``,
#: relative to the bounding-box diagonal). The L-block of ``hapticsim.data.example_meshes``
#: splits into its two bars exactly at 0.05 and at 0.02.
DECOMPOSITION_THRESHOLD: float = 0.03
#: Decompositions kept in memory (by mesh content), so repeated episodes do not redo them.
_DECOMPOSITION_CACHE_SIZE: int = 16
_decompositions: dict[str, tuple[Array, ...]] = {}


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


def collision_parts(truth: Superquadric | MeshSolid, resolution: int) -> CollisionParts:
    """The collision geometry of an object.

    - a superquadric: one piece, :func:`object_vertices` in its body frame;
    - a convex mesh: one piece, its own vertices (body frame at the centroid, world axes);
    - a non-convex mesh: a convex decomposition by coacd (optional dependency, extra ``meshes``)
      at :data:`DECOMPOSITION_THRESHOLD`; the true surface stays the mesh.

    Args:
        truth: the object in the world.
        resolution: superquadric mesh resolution (see :func:`object_vertices`).

    Raises:
        SimulationError: a non-convex mesh without coacd installed, or a failed decomposition.
    """
    if isinstance(truth, Superquadric):
        return CollisionParts(
            (object_vertices(truth, resolution),), truth.center, truth.rotation,
            "superquadric mesh: hull of the uniform and natural grids",
        )  # fmt: skip
    if not isinstance(truth, MeshSolid):
        raise SimulationError(
            f"the object must be a Superquadric or MeshSolid, got {type(truth).__name__}"
        )
    center = truth.centroid
    if truth.is_convex:
        return CollisionParts(
            (np.asarray(truth.vertices) - center,), center, np.eye(3), "convex mesh, as it is"
        )
    parts = _decompose(truth)
    method = (
        f"convex decomposition by coacd (threshold {DECOMPOSITION_THRESHOLD}, seed 0): "
        f"{len(parts)} convex parts"
    )
    return CollisionParts(tuple(p - center for p in parts), center, np.eye(3), method)


def _decompose(truth: MeshSolid) -> tuple[Array, ...]:
    key = hashlib.sha1(
        np.ascontiguousarray(truth.vertices).tobytes() + np.ascontiguousarray(truth.faces).tobytes()
    ).hexdigest()
    if key in _decompositions:
        return _decompositions[key]
    try:
        import coacd
    except ImportError:
        raise SimulationError(
            "the mesh is not convex and MuJoCo collides with convex hulls only: install the "
            "convex decomposition (pip install 'hapticsim[meshes]', which adds coacd) or give "
            "a convex mesh"
        ) from None
    coacd.set_log_level("error")
    try:
        mesh = coacd.Mesh(np.asarray(truth.vertices, float), np.asarray(truth.faces, np.int64))
        result = coacd.run_coacd(mesh, threshold=DECOMPOSITION_THRESHOLD, seed=0)
    except Exception as exc:  # coacd raises RuntimeError and friends from C++
        raise SimulationError(f"the convex decomposition of the mesh failed: {exc}") from exc
    parts = tuple(np.asarray(v, dtype=np.float64) for v, _ in result if len(v) >= 4)
    if not parts:
        raise SimulationError("the convex decomposition of the mesh returned no parts")
    if len(_decompositions) >= _DECOMPOSITION_CACHE_SIZE:
        _decompositions.pop(next(iter(_decompositions)))
    _decompositions[key] = parts
    return parts


def support_foot(truth: Superquadric | MeshSolid, vertices_world: Array) -> Array:
    """(3,) float, where the stand touches the object [m, world].

    A superquadric: the collision vertex nearest the centre's vertical among the lowest ones
    (within 1 mm). A mesh: the lowest point of its surface on the vertical through the
    centroid, when that line meets the mesh; else as for a superquadric on its vertices.
    """
    center = truth.center
    if isinstance(truth, MeshSolid):
        z = _vertical_hits(truth, center[:2])
        if z.size:
            return np.array([center[0], center[1], float(z.min())])
    low_z = float(vertices_world[:, 2].min())
    low = vertices_world[vertices_world[:, 2] < low_z + 1e-3]
    return low[np.argmin(np.linalg.norm(low[:, :2] - center[:2], axis=1))]


def _vertical_hits(solid: MeshSolid, xy: Array) -> Array:
    """Heights [m] where the vertical line through `xy` (2,) meets the faces of a mesh."""
    t = np.asarray(solid.triangles)
    a, b, c = (t[:, k, :2] - xy for k in range(3))
    wa = b[:, 0] * c[:, 1] - c[:, 0] * b[:, 1]
    wb = c[:, 0] * a[:, 1] - a[:, 0] * c[:, 1]
    wc = a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]
    total = wa + wb + wc
    inside = (((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))) & (
        np.abs(total) > 0
    )
    w = np.stack([wa, wb, wc], axis=1)[inside] / total[inside, None]
    return np.einsum("ij,ij->i", w, t[inside, :, 2])


def support_radius(truth: Superquadric | MeshSolid, stand_radius: float) -> float:
    """Radius [m] of the stand under an object: `stand_radius`, or 0.3 of the object's smallest
    horizontal half-width when that is less (semi-axes a1, a2 of a superquadric; half the
    bounding-box width in x and y of a mesh)."""
    if isinstance(truth, MeshSolid):
        lo, hi = truth.bounds
        half = 0.5 * (hi[:2] - lo[:2])
    else:
        half = truth.a[:2]
    return min(stand_radius, 0.3 * float(np.min(half)))


__all__ = [
    "DECOMPOSITION_THRESHOLD",
    "CollisionParts",
    "collision_parts",
    "object_vertices",
    "support_foot",
    "support_radius",
]
