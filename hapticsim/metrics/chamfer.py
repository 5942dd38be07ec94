"""Symmetric Chamfer distance between the surfaces of two solids (SPEC §4).

Definition (the mean of both directions' mean distances, not squared)::

    chamfer(A, B) = ( mean_{p on dA} d(p, dB) + mean_{q on dB} d(q, dA) ) / 2     [m]

with ``d(p, dB)`` the Euclidean distance from a point to the surface, and the means over the
surface area. Method: ``samples`` points area-uniform on each surface (each solid's
:meth:`~hapticsim.geometry.solid.Solid.sample_surface`) and for each the distance to the other
surface (its :meth:`~hapticsim.geometry.solid.Solid.surface_distance`). A superquadric's are
random points on the triangles of a fine mesh moved radially onto the exact surface and the
distance to that mesh, found exactly among the triangles with the 4 nearest centroids
(:class:`hapticsim.geometry.sampling.SurfaceMesh`): two identical shapes score 2e-5 to 5e-5 m
(mesh chords at 96 longitudes), far below the 0.5-1 mm floor of a point-cloud-to-point-cloud
Chamfer distance with the same sample count. A mesh's are exact to its triangles.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, points_array, positive_int
from hapticsim.geometry.sampling import DEFAULT_MESH_RESOLUTION
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.geometry.triangles import closest_point_on_triangles

Array = NDArray[np.float64]

#: Default number of surface points per shape.
DEFAULT_CHAMFER_SAMPLES: int = 5_000


def sample_surface(
    solid: Solid, count: int, rng: np.random.Generator | int | None = None
) -> Array:
    """(count, 3) float, points uniform by area on a solid's surface [m, world]."""
    return solid_arg(solid, "solid").sample_surface(positive_int(count, "count"), rng)[0]


def surface_distance(points_world: Array, solid: Solid) -> Array:
    """(n,) float, distance [m] of points to a solid's surface, inside or outside alike (a
    superquadric's through its fine mesh: the chords add at most a few 1e-5 m)."""
    pts = points_array(points_world, "points_world", min_count=1)
    return solid_arg(solid, "solid").surface_distance(pts)


def chamfer(
    estimate: Solid,
    truth: Solid,
    samples: int = DEFAULT_CHAMFER_SAMPLES,
    rng: np.random.Generator | int | None = 0,
) -> float:
    """Symmetric Chamfer distance between two surfaces [m] (module docstring).

    ``(mean_{p on dS_e} d(p, dS_s) + mean_{q on dS_s} d(q, dS_e)) / 2``, each mean over
    `samples` area-uniform points; the generator draws the estimate's points first.

    Args:
        estimate: S_e.
        truth: S_s (the measure is symmetric).
        samples: surface points per shape, >= 1.
        rng: seed or generator (default seed 0).

    Returns:
        The distance [m], >= 0.
    """
    estimate = solid_arg(estimate, "estimate")
    truth = solid_arg(truth, "truth")
    return chamfer_checked(estimate, truth, positive_int(samples, "samples"), as_generator(rng))


def chamfer_checked(estimate: Solid, truth: Solid, n: int, gen: np.random.Generator) -> float:
    """:func:`chamfer` of arguments already checked (two solids, ``n`` >= 1, a generator)."""
    to_truth = truth.surface_distance(estimate.sample_surface(n, gen)[0])
    to_estimate = estimate.surface_distance(truth.sample_surface(n, gen)[0])
    return float(0.5 * (np.mean(to_truth) + np.mean(to_estimate)))


__all__ = [
    "DEFAULT_CHAMFER_SAMPLES",
    "DEFAULT_MESH_RESOLUTION",
    "chamfer",
    "chamfer_checked",
    "closest_point_on_triangles",
    "sample_surface",
    "surface_distance",
]
