"""What the per-step scorer (:class:`hapticsim.metrics.episode.TruthScorer`) asks of a solid,
answered for any kind and faster for the kinds that allow it.

Each function is a :func:`functools.singledispatch` on the solid's kind: the generic answer uses
only the :class:`~hapticsim.geometry.solid.Solid` interface (membership, sampling, surface
distance); a superquadric registers compiled loops
(:mod:`hapticsim.geometry._sampling_compiled`), a union samples part by part. They live here,
beside their one caller, and not on ``Solid``: a new kind of object needs none of them, and
registers one only to be scored faster.

Points are ``(3, n)`` [m, world] here (the compiled loops' layout), not ``(n, 3)``.
"""

from __future__ import annotations

from functools import singledispatch

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry import _sampling_compiled as kernel
from hapticsim.geometry.mesh_solid import MeshSolid
from hapticsim.geometry.sampling import (
    AREA_STEP,
    CANDIDATES_PER_SAMPLE,
    FOOT_ITERATIONS,
    candidate_count,
    max_taper_jacobian,
    quasi_random_candidates,
    sobol_points,
)
from hapticsim.geometry.sampling import interior_from_candidates as _superquadric_interior
from hapticsim.geometry.solid import Solid
from hapticsim.geometry.superquadric import Superquadric
from hapticsim.geometry.union import SuperquadricUnion

Array = NDArray[np.float64]
Candidates = tuple[Array, Array, Array]


# ----------------------------------------------------------------- a truth's own sample
@singledispatch
def quasi_interior(solid: Solid, samples: int, gen: np.random.Generator) -> Array:
    """About `samples` points uniform inside `solid` from a scrambled Sobol sequence seeded by
    `gen`, (k, 3) [m, world]: the scorer's fixed interior sample of a truth. Generic: the points
    of the sequence in the solid's :attr:`~hapticsim.geometry.solid.Solid.bounds` (the first
    ``samples / fill`` of them) that it contains."""
    lo, hi = solid.bounds
    count = int(np.ceil(samples * float(np.prod(hi - lo)) / solid.volume))
    candidates = lo + sobol_points(3, count, gen)[:count] * (hi - lo)
    return candidates[solid.contains(candidates)]


@quasi_interior.register
def _(solid: Superquadric, samples: int, gen: np.random.Generator) -> Array:
    # as many Sobol candidates as its own acceptance needs (sampling.interior_from_candidates)
    need = candidate_count(solid, max_taper_jacobian(solid.taper), samples, None)
    candidates = quasi_random_candidates(min(need, CANDIDATES_PER_SAMPLE * samples), gen)
    return _superquadric_interior(candidates, solid, samples).T


# ----------------------------------------------------------------- an estimate's sample
@singledispatch
def interior_from_candidates(solid: Solid, candidates: Candidates, samples: int) -> Array:
    """About `samples` points inside `solid`, (3, k) [m, world], from the scorer's fixed
    quasi-random candidates (:func:`~hapticsim.geometry.sampling.quasi_random_candidates`).
    Generic: :func:`quasi_interior` with a fixed seed, the candidates unused."""
    return np.ascontiguousarray(quasi_interior(solid, samples, np.random.default_rng(0)).T)


@interior_from_candidates.register
def _(solid: Superquadric, candidates: Candidates, samples: int) -> Array:
    # what the rejection sampler keeps of the first samples / acceptance candidates
    return _superquadric_interior(candidates, solid, samples)


@interior_from_candidates.register
def _(solid: SuperquadricUnion, candidates: Candidates, samples: int) -> Array:
    # each part's sample at the union's density (samples V_part / V), kept where no earlier
    # part holds it
    v = solid.volume
    chunks = []
    for k, part in enumerate(solid.parts):
        pts = interior_from_candidates(part, candidates, max(1, round(samples * part.volume / v)))
        if k:
            pts = pts[:, SuperquadricUnion(solid.parts[:k]).outside(pts.T)]
        chunks.append(pts)
    return np.ascontiguousarray(np.concatenate(chunks, axis=1))


# ----------------------------------------------------------------- counting
@singledispatch
def count_outside(solid: Solid, points: Array) -> int:
    """How many of the points (3, n) [m, world] lie strictly outside `solid`."""
    return int(np.count_nonzero(solid.outside(np.asarray(points).T)))


@count_outside.register
def _(solid: Superquadric, points: Array) -> int:
    return int(kernel.count_outside(np.ascontiguousarray(points), *kernel.unpack(solid)))


def count_outside_of(
    solid: Solid, other: Solid, candidates: Candidates, samples: int
) -> tuple[int, int]:
    """``(outside, kept)``: of `other`'s interior sample from the candidates
    (:func:`interior_from_candidates`), how many lie outside `solid`, and how many it has.
    Two superquadrics: sampled and tested in one compiled pass
    (:func:`hapticsim.geometry._sampling_compiled.interior_outside`)."""
    if isinstance(solid, Superquadric) and isinstance(other, Superquadric):
        unit, log_unit, accept = candidates
        top = max_taper_jacobian(other.taper)
        count = candidate_count(other, top, samples, accept.shape[0])
        outside, kept = kernel.interior_outside(
            unit, log_unit, accept, top, count, *kernel.unpack(other), *kernel.unpack(solid)
        )
        return int(outside), int(kept)
    points = interior_from_candidates(other, candidates, samples)
    return count_outside(solid, points), int(points.shape[1])


# ----------------------------------------------------------------- surfaces
@singledispatch
def lattice_surface(solid: Solid, directions: Array) -> tuple[Array, Array] | None:
    """Surface points (3, K) [m, world] on fixed unit `directions` (3, K) from the centre, with
    their area weights, for a solid whose surface meets every such ray once; None (generic)
    where it does not: the scorer samples its surface instead."""
    return None


@lattice_surface.register
def _(solid: Superquadric, directions: Array) -> tuple[Array, Array]:
    # a superquadric meets each ray from its centre once (_sampling_compiled.surface_sample)
    count = directions.shape[1]
    points, weights = np.empty((3, count)), np.empty(count)
    kernel.surface_sample(directions, AREA_STEP, *kernel.unpack(solid), points, weights)
    return points, weights


@singledispatch
def foot_distances(solid: Solid, points: Array) -> Array:
    """(K,) distances [m] of points (3, K) to the surface of `solid` (generic: its
    :meth:`~hapticsim.geometry.solid.Solid.surface_distance`)."""
    return solid.surface_distance(np.asarray(points).T)


@foot_distances.register
def _(solid: Superquadric, points: Array) -> Array:
    # exact distances by foot-point iteration, compiled (_sampling_compiled.surface_distances)
    out = np.empty(points.shape[1])
    kernel.surface_distances(np.ascontiguousarray(points), *kernel.unpack(solid),
                             FOOT_ITERATIONS, out, _NONE, _NONE)  # fmt: skip
    return out


#: An empty (3, 0) array: the compiled distances' "not asked" for normals and starts.
_NONE = np.empty((3, 0))


@singledispatch
def foot_normals(solid: Solid, points: Array, surface: Array) -> tuple[Array, Array]:
    """``(distances (K,) [m], normals (3, K))``: the distance of each point (3, K) to the surface
    of `solid` and the surface's outward normal at the closest point [world]; `surface` (3, M)
    are points on that surface (a superquadric's searches also start from the nearest of them,
    which finds the foot point beyond a sharp edge). Generic: its
    :meth:`~hapticsim.geometry.solid.Solid.surface_distance` and the normal at the closest point
    of its surface mesh (:func:`hapticsim.metrics.surface.normals_at_closest`)."""
    from hapticsim.metrics.surface import normals_at_closest

    pts = np.asarray(points).T
    return solid.surface_distance(pts), np.ascontiguousarray(normals_at_closest(solid, pts).T)


@foot_normals.register
def _(solid: Superquadric, points: Array, surface: Array) -> tuple[Array, Array]:
    # the foot-point iteration's own normal at the foot point, in the same compiled pass
    from scipy.spatial import cKDTree

    points = np.ascontiguousarray(points)
    _, nearest = cKDTree(surface.T).query(points.T)
    starts = np.ascontiguousarray(surface[:, nearest])
    out, normals = np.empty(points.shape[1]), np.empty((3, points.shape[1]))
    kernel.surface_distances(points, *kernel.unpack(solid), FOOT_ITERATIONS, out, normals,
                             starts)  # fmt: skip
    return out, normals


@foot_normals.register
def _(solid: MeshSolid, points: Array, surface: Array) -> tuple[Array, Array]:
    # one search gives both: the closest point and its face's normal
    pts = np.asarray(points).T
    closest, face = solid.nearest(pts, exact=False)
    normals = np.asarray(solid.face_normals)[face]
    return np.linalg.norm(closest - pts, axis=1), np.ascontiguousarray(normals.T)


__all__ = [
    "count_outside",
    "count_outside_of",
    "foot_distances",
    "foot_normals",
    "interior_from_candidates",
    "lattice_surface",
    "quasi_interior",
]
