"""Collision meshes of superquadric objects.

MuJoCo collides with a mesh's convex hull. The uniform parametrisation (paper eq. 6) spreads
vertices evenly over faces but leaves the rounded edges of box-like shapes (eps ~ 0.1) with a
single chamfer of vertices, where hull normals are off by 10-20 degrees; the natural
parametrisation (eq. 1) crowds vertices into exactly those edges. The collision mesh is the
convex hull of the vertices of both meshes (:meth:`Superquadric.to_mesh` with each
parametrisation): every vertex lies on the true surface, faces and edges are both well sampled.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry import Superquadric

Array = NDArray[np.float64]


def object_mesh(shape_body: Superquadric, resolution: int) -> tuple[Array, NDArray[np.int64]]:
    """Vertices and faces of the collision mesh of a superquadric, in its body frame.

    Args:
        shape_body: the superquadric (its pose is ignored: the mesh is in the body frame).
        resolution: longitudes of each of the two meshes (see :meth:`Superquadric.to_mesh`).

    Returns:
        vertices (n, 3) float [m, body frame] and faces (m, 3) int of the convex hull, outward.
    """
    from scipy.spatial import ConvexHull

    body = shape_body.replace(rotation=np.eye(3), center=np.zeros(3))
    vertices = np.concatenate(
        [body.to_mesh(resolution, "uniform").vertices, body.to_mesh(resolution, "natural").vertices]
    )
    vertices = np.unique(np.round(vertices, 12), axis=0)
    hull = ConvexHull(vertices)
    faces = hull.simplices.copy()
    # orient outward: the normal of each face must point away from the centroid
    tri = vertices[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", normal, tri[:, 0] - vertices.mean(axis=0)) < 0
    faces[flip] = faces[flip][:, ::-1]
    used = np.unique(faces)
    remap = np.full(len(vertices), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return vertices[used], remap[faces]


__all__ = ["object_mesh"]
