"""Symmetric Chamfer distance between two superquadric surfaces (SPEC §4).

Definition (the mean of both directions' mean distances, not squared)::

    chamfer(A, B) = ( mean_{p on dA} d(p, dB) + mean_{q on dB} d(q, dA) ) / 2     [m]

with ``d(p, dB)`` the Euclidean distance from a point to the surface, and the means over the
surface area. Method: ``samples`` points area-uniform on each surface (random points on the
triangles of a fine mesh, moved radially onto the exact surface), and for each the distance to
the other surface's mesh, found exactly (:func:`closest_point_on_triangles`) among the triangles
with the 4 nearest centroids (scipy ``cKDTree``). The mesh's vertices lie on the exact surface,
so two identical shapes score 2e-5 to 5e-5 m (mesh chords at 96 longitudes), far below the
0.5-1 mm floor of a point-cloud-to-point-cloud Chamfer distance with the same sample count.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, points_array, positive_int
from hapticsim.geometry import Superquadric
from hapticsim.geometry.mesh import surface_grid
from hapticsim.geometry.superquadric import superquadric_arg
from hapticsim.geometry.triangles import closest_point_on_triangles

Array = NDArray[np.float64]

#: Default number of surface points per shape.
DEFAULT_CHAMFER_SAMPLES: int = 5_000
#: Default mesh resolution (longitudes) of :meth:`Superquadric.to_mesh` for the distances.
DEFAULT_MESH_RESOLUTION: int = 96
#: Candidate triangles (nearest centroids) searched per query point.
_CANDIDATES: int = 4


@dataclass(frozen=True, eq=False)
class _Surface:
    """A superquadric with a fine mesh, its face areas and a centroid tree (internal)."""

    sq: Superquadric
    resolution: int
    triangles: Array = field(init=False)
    cumulative_area: Array = field(init=False)
    tree: Any = field(init=False)

    def __post_init__(self) -> None:
        from scipy.spatial import cKDTree

        vertices, faces = surface_grid(self.sq, self.resolution)
        tri = vertices[faces]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        object.__setattr__(self, "triangles", tri)
        object.__setattr__(self, "cumulative_area", np.cumsum(area))
        object.__setattr__(self, "tree", cKDTree(tri.mean(axis=1)))

    def sample(self, count: int, gen: np.random.Generator) -> Array:
        """`count` area-uniform points on the exact surface, (count, 3) [m]."""
        total = self.cumulative_area[-1]
        face = np.searchsorted(self.cumulative_area, gen.uniform(0.0, total, count), side="right")
        face = np.minimum(face, len(self.triangles) - 1)
        r = gen.random((count, 2))
        flip = r.sum(axis=1) > 1.0
        r[flip] = 1.0 - r[flip]
        tri = self.triangles[face]
        points = tri[:, 0] + r[:, :1] * (tri[:, 1] - tri[:, 0]) + r[:, 1:] * (tri[:, 2] - tri[:, 0])
        return self.sq.project(points)

    def distance(self, points: Array) -> Array:
        """(n,) distances [m] of world points to the mesh surface."""
        k = min(_CANDIDATES, len(self.triangles))
        _, idx = self.tree.query(points, k=k)
        idx = idx.reshape(len(points), k)
        query = np.repeat(points, k, axis=0)
        nearest = closest_point_on_triangles(self.triangles[idx.ravel()], query)
        dist = np.linalg.norm(nearest - query, axis=1)
        return np.where(np.isfinite(dist), dist, np.inf).reshape(-1, k).min(axis=1)


def sample_surface(
    sq: Superquadric,
    count: int,
    rng: np.random.Generator | int | None = None,
    resolution: int = DEFAULT_MESH_RESOLUTION,
) -> Array:
    """Points distributed uniformly by area on the surface of a superquadric.

    Random points on the triangles of a mesh (triangle chosen with probability proportional to its
    area, then uniform barycentric coordinates), moved radially onto the exact surface.

    Args:
        sq: the superquadric.
        count: number of points, >= 1.
        rng: seed or generator.
        resolution: mesh longitudes, >= 8.

    Returns:
        (count, 3) float, world points [m] with ``F = 1``.
    """
    sq = superquadric_arg(sq, "sq")
    n = positive_int(count, "count")
    res = positive_int(resolution, "resolution", minimum=8)
    return _Surface(sq, res).sample(n, as_generator(rng))


def surface_distance(
    points_world: Array, sq: Superquadric, resolution: int = DEFAULT_MESH_RESOLUTION
) -> Array:
    """Euclidean distance of points to the surface of a superquadric (via a fine mesh).

    Args:
        points_world: (n, 3) float, points [m].
        sq: the superquadric.
        resolution: mesh longitudes, >= 8; the mesh's chords add at most a few 1e-5 m at 96.

    Returns:
        (n,) float, non-negative distances [m], inside or outside alike.
    """
    pts = points_array(points_world, "points_world", min_count=1)
    sq = superquadric_arg(sq, "sq")
    res = positive_int(resolution, "resolution", minimum=8)
    return _Surface(sq, res).distance(pts)


def chamfer(
    estimate: Superquadric,
    truth: Superquadric,
    samples: int = DEFAULT_CHAMFER_SAMPLES,
    rng: np.random.Generator | int | None = 0,
    resolution: int = DEFAULT_MESH_RESOLUTION,
) -> float:
    """Symmetric Chamfer distance between two surfaces [m] (module docstring).

    ``(mean_{p on dS_e} d(p, dS_s) + mean_{q on dS_s} d(q, dS_e)) / 2``, each mean over
    `samples` area-uniform points; the generator draws the estimate's points first.

    Args:
        estimate: S_e.
        truth: S_s (the measure is symmetric).
        samples: surface points per shape, >= 1.
        rng: seed or generator (default seed 0).
        resolution: mesh longitudes, >= 8.

    Returns:
        The distance [m], >= 0.
    """
    estimate = superquadric_arg(estimate, "estimate")
    truth = superquadric_arg(truth, "truth")
    n = positive_int(samples, "samples")
    res = positive_int(resolution, "resolution", minimum=8)
    gen = as_generator(rng)
    surf_e, surf_s = _Surface(estimate, res), _Surface(truth, res)
    to_truth = surf_s.distance(surf_e.sample(n, gen))
    to_estimate = surf_e.distance(surf_s.sample(n, gen))
    return float(0.5 * (np.mean(to_truth) + np.mean(to_estimate)))


__all__ = [
    "DEFAULT_CHAMFER_SAMPLES",
    "DEFAULT_MESH_RESOLUTION",
    "chamfer",
    "closest_point_on_triangles",
    "sample_surface",
    "surface_distance",
]
