"""The :class:`Solid`: what every object is, truth or estimate (SPEC §10).

A solid is a closed region of space in the world frame. Three kinds implement it, each in a module
of its own: :class:`~hapticsim.geometry.superquadric.Superquadric` (SPEC §1),
:class:`~hapticsim.geometry.union.SuperquadricUnion` (a union of superquadrics: inside any part is
inside) and :class:`~hapticsim.geometry.mesh_solid.MeshSolid` (a closed triangle mesh). Metrics,
the simulation's object builder, the vision estimate and the environment take any solid through
this interface and do not ask which kind it is; a new kind of object is one more class.

What a solid answers (points and normals are (n, 3) float [m, world]):

- **membership**: :meth:`contains` (inside or on the surface) and :meth:`outside` (strictly
  outside; the volume measures count with it);
- **surface**: :meth:`normals` (outward unit normals at or near the surface),
  :meth:`surface_distance` (distance to the surface, as the Chamfer distance measures it) and
  :meth:`contact_errors` (distance and normal angle of measured contacts, SPEC §7);
- **sampling**: :meth:`sample_interior` (uniform inside; by default rejection from the bounds),
  :meth:`sample_surface` (uniform by area,
  with normals);
- **ray casting**: :meth:`first_hits` (distance to where each ray first enters);
- **measures**: :attr:`volume` (exact for every kind), :attr:`center`, :attr:`bounding_radius`,
  :attr:`bounds`, :attr:`size` (the length of SPEC §5's relative noise);
- **meshes and pieces**: :meth:`surface_mesh` (vertices and faces of the surface, for pictures
  and depth images) and :meth:`convex_pieces` (the convex parts MuJoCo collides with);
- **placement**: :meth:`transformed`, :meth:`scaled`, :attr:`pose` and :meth:`shape_key` (what
  identifies the shape apart from its pose, for caches of compiled scenes);
- **files**: :meth:`to_dict` (its JSON) and :attr:`kind`.

What one caller alone asks is answered beside that caller, for any solid through this interface
and faster for the kinds that register a way: the per-step scorer's samples and counts
(:mod:`hapticsim.metrics.scorer_kinds`), the stand's size and foot
(:mod:`hapticsim.sim.object_mesh`).

numpy only (trimesh, scipy and coacd are imported where a kind needs them).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]


class Solid(ABC):
    """The interface of every object (module docstring)."""

    #: Short name of the kind: ``"superquadric"``, ``"union"`` or ``"mesh"``.
    kind: ClassVar[str] = ""
    #: What :meth:`contact_errors` measures against (stated in contact-accuracy reports).
    contact_reference: ClassVar[str] = ""

    # ----------------------------------------------------------------- membership
    @abstractmethod
    def contains(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, True for points inside or on the solid."""

    def outside(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, True for points strictly outside (default: not :meth:`contains`)."""
        return ~self.contains(points_world)

    # ----------------------------------------------------------------- surface
    @abstractmethod
    def normals(self, points_world: Array) -> Array:
        """(n, 3) float, outward unit normals at (or nearest to) points at or near the surface."""

    @abstractmethod
    def surface_distance(self, points_world: Array) -> Array:
        """(n,) float, distance [m] of points to the surface, inside or outside alike (the
        Chamfer distance's; a kind may approximate it to a few 1e-5 m)."""

    @abstractmethod
    def contact_errors(self, points_world: Array, normals_world: Array) -> tuple[Array, Array]:
        """Distance [m] of contacts to the surface and angle [deg] of their normals against the
        surface's there, each (n,) (SPEC §7's contact accuracy)."""

    # ----------------------------------------------------------------- sampling
    def sample_interior(
        self, count: int, rng: np.random.Generator | int | None = None
    ) -> Array:
        """(count, 3) float, points uniform inside the solid [m, world]. Default: rejection from
        :attr:`bounds` by :meth:`contains` (a kind with a sampler of its own overrides it).

        Args:
            count: number of points, >= 1.
            rng: seed or generator.
        """
        from hapticsim._validate import as_generator, positive_int

        n = positive_int(count, "count")
        gen = as_generator(rng)
        lo, hi = self.bounds
        fill = self.volume / float(np.prod(hi - lo))
        chunks: list[Array] = []
        have = 0
        while have < n:
            k = min(int((n - have) / fill * 1.05) + 64, 1_000_000)
            cand = gen.uniform(lo, hi, size=(k, 3))
            keep = cand[self.contains(cand)]
            chunks.append(keep)
            have += len(keep)
        return np.concatenate(chunks)[:n]

    @abstractmethod
    def sample_surface(
        self, count: int, rng: np.random.Generator | int | None = None
    ) -> tuple[Array, Array]:
        """`count` points uniform by area on the surface (count, 3) [m, world] and their
        outward unit normals (count, 3)."""

    # ----------------------------------------------------------------- rays
    def first_hits(
        self, origins: Array, directions: Array, length: float, grids: tuple[int, ...]
    ) -> Array:
        """(k,) float, distance along each ray ``origin + s direction``, ``s in [0, length]``,
        to the first sample inside the solid, NaN where it misses: :meth:`contains` on a coarse
        grid refined on finer ones (each spanning one step of the previous); a kind may do it
        faster (:func:`hapticsim.geometry.rays.raycast_many`)."""
        origins = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
        directions = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
        k = len(origins)
        lo = np.zeros(k)
        step = np.full(k, float(length) / (grids[0] - 1))
        hit = np.ones(k, dtype=bool)
        rows = np.arange(k)
        for level, count in enumerate(grids):
            s = lo[:, None] + step[:, None] * np.arange(count)[None, :]
            pts = origins[:, None, :] + s[..., None] * directions[:, None, :]
            inside = self.contains(pts.reshape(-1, 3)).reshape(k, count)
            any_in = inside.any(axis=1)
            if level == 0:
                hit = any_in
            first = np.maximum(np.where(any_in, np.argmax(inside, axis=1), count - 1), 1)
            lo = s[rows, first - 1]
            if level + 1 < len(grids):
                step = step / (grids[level + 1] - 1)  # the next grid spans one step of this one
        return np.where(hit, lo + step, np.nan)  # the first sample inside

    def segment_depths(
        self, points: Array, normals: Array, reach: float, grids: tuple[int, ...]
    ) -> Array:
        """(k,) float, how deep each point (k, 3) [m, world] lies inside the solid along its
        inward unit normal (normals (k, 3), outward): 0 outside, else ``reach - s``, s where
        the segment from ``p - reach m`` along ``m`` enters the solid (:meth:`first_hits` on
        `grids`; 0 when it finds no entry). The tactile depth model's
        (:func:`hapticsim.perception.tactile.depth.taxel_depths`); a kind may do it faster."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        m = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
        out = np.zeros(len(p))
        inside = np.flatnonzero(self.contains(p)) if len(p) else np.zeros(0, dtype=np.int64)
        if len(inside):  # only a point inside has a depth: cast only those rays
            s = self.first_hits(p[inside] - reach * m[inside], m[inside], reach, grids)
            out[inside] = np.where(np.isnan(s), 0.0, np.maximum(reach - s, 0.0))
        return out

    # ----------------------------------------------------------------- measures
    @property
    @abstractmethod
    def volume(self) -> float:
        """Exact volume [m^3]."""

    #: (3,) float, the solid's reference point [m, world] (a superquadric's centre, a mesh's
    #: centroid, a union's volume-weighted centre of its parts): an attribute or a property of
    #: every kind.
    center: Array

    @property
    @abstractmethod
    def bounding_radius(self) -> float:
        """Radius [m] of a sphere about :attr:`center` that contains the solid."""

    @property
    @abstractmethod
    def bounds(self) -> Array:
        """(2, 3) float, lowest and highest corner of a box that contains the solid [m]."""

    @property
    @abstractmethod
    def size(self) -> float:
        """The length [m] that scales relative sensor noise (SPEC §5: ``mean(a)``)."""

    # ----------------------------------------------------------------- meshes, pieces
    @abstractmethod
    def surface_mesh(self, resolution: int = 40) -> tuple[Array, NDArray[np.int64]]:
        """Vertices (v, 3) [m, world] and faces (f, 3) of the surface, outward (a kind meshed
        from parameters at `resolution` longitudes, a mesh as it is)."""

    @abstractmethod
    def convex_pieces(self, resolution: int) -> tuple[tuple[Array, ...], Array, Array, str]:
        """The convex pieces MuJoCo collides with: their vertices (each (v, 3), in the body frame),
        the body frame's position (3,) and rotation (3, 3) in the world, and how they were made.
        """

    @property
    def components(self) -> tuple[Solid, ...]:
        """The solids this one is the union of, for pictures that colour them apart (default:
        itself; a union: its parts)."""
        return (self,)

    def to_trimesh(self, resolution: int = 40) -> Any:
        """A ``trimesh.Trimesh`` of :meth:`surface_mesh`."""
        import trimesh

        vertices, faces = self.surface_mesh(resolution)
        return trimesh.Trimesh(np.asarray(vertices), np.asarray(faces), process=False)

    # ----------------------------------------------------------------- placement
    @abstractmethod
    def transformed(self, rotation: Array, translation: Array) -> Solid:
        """The same solid moved rigidly: ``x -> rotation @ x + translation``."""

    @abstractmethod
    def scaled(self, factor: float) -> Solid:
        """The solid scaled about the world origin by `factor` (> 0): ``x -> factor * x``."""

    @property
    def pose(self) -> tuple[Array, Array]:
        """The rotation (3, 3) and position (3,) of the body frame of :meth:`convex_pieces`
        (default: the world's axes at :attr:`center`). Two solids with equal
        :meth:`shape_key` are the same shape in this frame: equal poses, the same solid."""
        return np.eye(3), np.asarray(self.center, dtype=np.float64)

    @abstractmethod
    def shape_key(self) -> bytes:
        """Bytes that identify the shape in the frame of :attr:`pose`: equal keys, the same
        body-frame shape (a compiled scene can then be moved, not compiled again)."""

    # ----------------------------------------------------------------- files
    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description (SPEC §6 for a superquadric, §10 for a union)."""


def solid_arg(value: Any, name: str) -> Solid:
    """`value` if it is a :class:`Solid`, else InvalidInputError naming `name`."""

    if not isinstance(value, Solid):
        raise InvalidInputError(
            f"`{name}` must be a solid (Superquadric, SuperquadricUnion or MeshSolid), got "
            f"{type(value).__name__}"
        )
    return value


__all__ = ["Solid", "solid_arg"]
