"""Triangle meshes of superquadrics (trimesh).

The functions take a superquadric (anything with its fields ``a``, ``eps``, ``taper``,
``rotation``, ``center``) without importing its class, which meshes itself through them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from hapticsim._validate import positive_int
from hapticsim.geometry import functions as fn
from hapticsim.geometry.parametrization import parametrize

if TYPE_CHECKING:
    import trimesh


def sphere_grid_faces(n_lat: int, n_lon: int) -> np.ndarray:
    """Faces of a latitude-longitude grid with single-vertex poles, outward for a right-handed
    (eta up, omega counter-clockwise) layout.

    Vertex order: south pole, ``n_lat - 1`` rings of ``n_lon`` vertices from south to north,
    north pole.

    Returns:
        (2 * n_lon * (n_lat - 1), 3) int.
    """
    rings = n_lat - 1
    south, north = 0, 1 + rings * n_lon
    j = np.arange(n_lon)
    jn = (j + 1) % n_lon

    def ring(r: int, k: np.ndarray) -> np.ndarray:
        return 1 + r * n_lon + k

    faces = [np.stack([np.full(n_lon, south), ring(0, jn), ring(0, j)], -1)]
    for r in range(rings - 1):
        faces.append(np.stack([ring(r, j), ring(r, jn), ring(r + 1, jn)], -1))
        faces.append(np.stack([ring(r, j), ring(r + 1, jn), ring(r + 1, j)], -1))
    faces.append(np.stack([np.full(n_lon, north), ring(rings - 1, j), ring(rings - 1, jn)], -1))
    return np.concatenate(faces)


def surface_grid(
    sq: Any, resolution: int = 64, parametrization: str = "uniform"
) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of :func:`superquadric_mesh` as arrays, without building a mesh.

    Returns:
        vertices (m, 3) float, world points on the surface [m], and faces (k, 3) int, outward
        (counter-clockwise seen from outside: a proper rotation and tapering factors > 0 keep
        the orientation of :func:`sphere_grid_faces`).
    """
    n_lon = positive_int(resolution, "resolution", minimum=8)
    n_lat = max(n_lon // 2, 4)
    eta = np.linspace(-np.pi / 2, np.pi / 2, n_lat + 1)[1:-1]
    omega = np.linspace(-np.pi, np.pi, n_lon, endpoint=False)
    ee, oo = np.meshgrid(eta, omega, indexing="ij")
    ring_pts = parametrize(ee.ravel(), oo.ravel(), sq.a, sq.eps, parametrization)
    poles = np.array([[0.0, 0.0, -sq.a[2]], [0.0, 0.0, sq.a[2]]])
    sym = np.concatenate([poles[:1], ring_pts, poles[1:]])
    body = fn.apply_taper(sym, sq.a, sq.taper)
    world = fn.body_to_world(body, sq.rotation, sq.center)
    return world, sphere_grid_faces(n_lat, n_lon)


def superquadric_mesh(
    sq: Any, resolution: int = 64, parametrization: str = "uniform"
) -> trimesh.Trimesh:
    """A watertight, outward-oriented triangle mesh of a superquadric in the world frame.

    Vertices lie exactly on the surface, on a grid of ``resolution`` longitudes by
    ``resolution // 2`` latitude bands of the chosen parametrisation (eq. 6 by default, which
    spreads vertices evenly; eq. 1 crowds them at edges), plus one vertex per pole. The vertex
    count is ``resolution * (resolution // 2 - 1) + 2``.

    Args:
        sq: the superquadric.
        resolution: number of longitudes, >= 8.
        parametrization: ``"uniform"`` or ``"natural"``.

    Returns:
        trimesh.Trimesh, watertight with positive volume.
    """
    import trimesh

    vertices, faces = surface_grid(sq, resolution, parametrization)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    if mesh.volume < 0:
        mesh.invert()
    return mesh
