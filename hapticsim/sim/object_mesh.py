"""Collision meshes of superquadric objects.

MuJoCo collides with a mesh's convex hull. The uniform parametrisation (paper eq. 6) spreads
vertices evenly over faces but leaves the rounded edges of box-like shapes (eps ~ 0.1) with a
single chamfer of vertices, where hull normals are off by 10-20 degrees; the natural
parametrisation (eq. 1) crowds vertices into exactly those edges. The collision mesh is the
convex hull of the vertices of both meshes (the grids of :meth:`Superquadric.to_mesh` with each
parametrisation, taken from :func:`hapticsim.geometry.mesh.surface_grid` without building trimesh
objects): every vertex lies on the true surface, faces and edges are both well sampled. MuJoCo
builds the hull itself (a mesh asset given without faces is its vertices' convex hull).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import positive_int
from hapticsim.geometry import Superquadric
from hapticsim.geometry.mesh import surface_grid

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


__all__ = ["object_vertices"]
