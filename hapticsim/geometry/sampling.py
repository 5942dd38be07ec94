"""Sampling a superquadric: uniform interior points (Monte Carlo and quasi-random), area-uniform
surface points, and the fine surface mesh the Chamfer distance measures against.

- :func:`superquadric_interior`: rejection sampling in the body frame (paper eq. 2's taper
  Jacobian as the acceptance), the Monte Carlo volume measures' sampler
  (:mod:`hapticsim.metrics.volume`);
- :func:`sobol_points`, :func:`quasi_random_candidates`, :func:`interior_from_candidates`: the
  same rejection run on fixed scrambled Sobol candidates, the per-step scorer's
  (:class:`hapticsim.metrics.episode.TruthScorer`);
- :class:`SurfaceMesh`: a superquadric's fine mesh (vertices on the exact surface), its
  area-uniform points moved radially onto the surface and distances to it (exactly to its
  triangles, among those of the 4 nearest centroids); one per (superquadric, resolution) is
  kept (:func:`surface_mesh_of`).

- :func:`fibonacci_sphere`: nearly uniform fixed unit directions (approach and coverage
  directions).

Used by :class:`~hapticsim.geometry.superquadric.Superquadric`'s sampling methods.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, positive_int
from hapticsim.geometry import _sampling_compiled as kernel
from hapticsim.geometry import functions as fn
from hapticsim.geometry.eof_compiled import TINY
from hapticsim.geometry.mesh import surface_grid
from hapticsim.geometry.triangles import closest_point_on_triangles

Array = NDArray[np.float64]

_UNIT_AXES = np.ones(3)
#: Largest number of candidates drawn at once (memory: 24 bytes each).
_MAX_BATCH = 1_000_000
#: Candidate triangles (nearest centroids) searched per query point of a surface mesh.
_CANDIDATES: int = 4
#: Default mesh resolution (longitudes) of a superquadric's surface mesh for distances.
DEFAULT_MESH_RESOLUTION: int = 96
#: Candidates drawn per interior sample of an estimate by the per-step scorer: an estimate uses
#: ``samples / acceptance`` of them, and any superquadric with eps <= 2 keeps at least 1/6
#: (untapered) or about 1/16 (fully tapered); if one ever keeps less, it is scored with the
#: samples it has.
CANDIDATES_PER_SAMPLE: int = 16
#: Angular step [rad] of the differences behind the area weights of lattice surface points.
AREA_STEP: float = 1e-4
#: Foot-point iterations per distance (converged to < 1e-9 m near the surface after 3-4).
FOOT_ITERATIONS: int = 6


def max_taper_jacobian(taper: Array) -> float:
    """``max over s in [-1, 1] of (1 + tx s)(1 + ty s)``: the largest area factor of tapering."""
    tx, ty = float(taper[0]), float(taper[1])
    s = [-1.0, 1.0]
    if tx * ty != 0.0:
        s.append(min(max(-(tx + ty) / (2.0 * tx * ty), -1.0), 1.0))
    return max((1.0 + tx * v) * (1.0 + ty * v) for v in s)


def superquadric_interior(
    sq: Any, count: int, rng: np.random.Generator | int | None = None
) -> Array:
    """Points distributed uniformly inside a (tapered, posed) superquadric.

    Rejection sampling in the body frame: candidates uniform in the cube ``[-1, 1]^3`` of scaled
    untapered coordinates ``(x/a1, y/a2, z/a3)`` are kept when ``F < 1`` (SPEC §1) and, with
    probability ``(1 + tx z/a3)(1 + ty z/a3) / max``, for the volume change of tapering (paper
    eq. 2, Jacobian determinant ``(1 + tx z/a3)(1 + ty z/a3)``); the kept points are scaled by
    ``a``, tapered and posed. The acceptance rate is ``V / (8 a1 a2 a3 max)``, about 0.98 for a
    box, 0.52 for an ellipsoid and 1/6 or more for any untapered shape with eps <= 2.

    Args:
        sq: the superquadric.
        count: number of points, >= 1.
        rng: seed or generator.

    Returns:
        (count, 3) float, world points [m], all with ``F <= 1``.
    """
    n = positive_int(count, "count")
    gen = as_generator(rng)
    tapered = bool(np.any(sq.taper != 0.0))
    top = max_taper_jacobian(sq.taper)
    unit_box = 8.0 * float(np.prod(sq.a))
    acceptance = sq.volume / (unit_box * top)
    chunks: list[Array] = []
    have = 0
    while have < n:
        k = min(int((n - have) / acceptance * 1.05) + 64, _MAX_BATCH)
        u = gen.uniform(-1.0, 1.0, size=(k, 3))
        keep = fn.log_inside_outside(u, _UNIT_AXES, sq.eps) < 0.0
        if tapered:
            jac = (1.0 + sq.taper[0] * u[:, 2]) * (1.0 + sq.taper[1] * u[:, 2])
            keep &= gen.uniform(0.0, top, size=k) < jac
        chunks.append(u[keep])
        have += int(np.count_nonzero(keep))
    body = np.concatenate(chunks)[:n] * sq.a
    body = fn.apply_taper(body, sq.a, sq.taper)
    return fn.body_to_world(body, sq.rotation, sq.center)


def sobol_points(dimensions: int, count: int, gen: np.random.Generator) -> Array:
    """The first ``2^m >= count`` points of a scrambled Sobol sequence in [0, 1)^dimensions
    (scrambling seeded by `gen`), (2^m, dimensions): a balanced prefix. The sequence is the same
    whatever `count`, so a longer set starts with a shorter one."""
    from scipy.stats import qmc

    sobol = qmc.Sobol(dimensions, scramble=True, seed=gen)
    return sobol.random_base2(int(np.ceil(np.log2(max(count, 1)))))


def quasi_random_candidates(count: int, gen: np.random.Generator) -> tuple[Array, Array, Array]:
    """At least `count` candidates of the rejection sampler from :func:`sobol_points` in four
    dimensions: the first three coordinates mapped to the cube [-1, 1]^3 (``unit``, with
    ``log(|u| + TINY)``), the fourth the acceptance numbers."""
    sobol = sobol_points(4, count, gen)
    unit = np.ascontiguousarray(2.0 * sobol[:, :3].T - 1.0)
    return unit, np.log(np.abs(unit) + TINY), np.ascontiguousarray(sobol[:, 3])


def candidate_count(sq: Any, top: float, samples: int, available: int | None) -> int:
    """Candidates for about `samples` kept points of `sq` (its acceptance is
    ``V / (8 a1 a2 a3 top)``), at most `available` (None: no limit)."""
    acceptance = sq.volume / (8.0 * float(np.prod(sq.a)) * top)
    count = int(np.ceil(samples / acceptance))
    return count if available is None else min(available, count)


def interior_from_candidates(
    candidates: tuple[Array, Array, Array], sq: Any, samples: int
) -> Array:
    """About `samples` points uniform inside `sq`, (3, k) [m, world]: what the rejection sampler
    keeps of the first ``samples / acceptance`` of the fixed `candidates`
    (:func:`quasi_random_candidates`)."""
    unit, log_unit, accept = candidates
    top = max_taper_jacobian(sq.taper)
    count = candidate_count(sq, top, samples, accept.shape[0])
    return kernel.interior_points(unit, log_unit, accept, top, count, *kernel.unpack(sq))


@dataclass(frozen=True, eq=False)
class SurfaceMesh:
    """A superquadric with a fine mesh, its face areas and a centroid tree.

    Attributes:
        sq: the superquadric.
        resolution: mesh longitudes.
    """

    sq: Any
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

    @property
    def area(self) -> float:
        """Surface area of the mesh [m^2] (its vertices lie on the surface: a little less than
        the superquadric's)."""
        return float(self.cumulative_area[-1])

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


#: The attribute of a superquadric under which its surface meshes are kept, per resolution.
#: They live in the superquadric's own ``__dict__`` and go with it: a weak-key table whose values
#: held their key (a :class:`SurfaceMesh` keeps its superquadric) never freed either.
_SURFACES_ATTRIBUTE = "_surface_meshes"


def surface_mesh_of(sq: Any, resolution: int) -> SurfaceMesh:
    """The :class:`SurfaceMesh` of `sq` at `resolution`, built once per superquadric object."""
    res = positive_int(resolution, "resolution", minimum=8)
    meshes = sq.__dict__.get(_SURFACES_ATTRIBUTE)
    if meshes is None:
        meshes = {}
        object.__setattr__(sq, _SURFACES_ATTRIBUTE, meshes)  # a frozen dataclass's cache
    mesh = meshes.get(res)
    if mesh is None:
        mesh = meshes[res] = SurfaceMesh(sq, res)
    return mesh


def fibonacci_sphere(n: int) -> Array:
    """(n, 3) float, nearly uniform unit vectors (Fibonacci lattice), deterministic."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    phi = np.pi * (1.0 + 5.0**0.5) * i
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


__all__ = [
    "fibonacci_sphere",
    "AREA_STEP",
    "CANDIDATES_PER_SAMPLE",
    "FOOT_ITERATIONS",
    "DEFAULT_MESH_RESOLUTION",
    "SurfaceMesh",
    "candidate_count",
    "interior_from_candidates",
    "max_taper_jacobian",
    "quasi_random_candidates",
    "sobol_points",
    "superquadric_interior",
    "surface_mesh_of",
]
