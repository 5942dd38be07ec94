"""The :class:`MeshSolid` value: a closed triangle mesh and the solid it bounds (a mesh truth).

An object that is not a superquadric (a lab's own part, read from STL/OBJ/PLY/OFF by
:mod:`hapticsim.data.objects`) is held as its vertices and faces in the world frame. This module
is numpy only: the volume and centroid by the divergence theorem, point containment by the parity
of an upward ray's crossings (a uniform xy grid of faces keeps it fast), area-uniform surface
samples and uniform interior samples. ``trimesh`` is imported only by :meth:`MeshSolid.to_trimesh`.

Closed means: every edge is shared by exactly two faces that traverse it in opposite directions
(a consistently oriented, edge-manifold surface without boundary), checked on construction; the
faces are counter-clockwise seen from outside (positive volume).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import (
    as_generator,
    finite_array,
    normals_array,
    points_array,
    positive_int,
)
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.geometry.rotations import is_rotation
from hapticsim.geometry.solid import Solid
from hapticsim.geometry.triangles import (
    TriangleSearch,
    all_pairs_nearest,
    closest_point_on_triangles,
    sample_triangles,
)

Array = NDArray[np.float64]

#: Points tested per batch by :meth:`MeshSolid.contains` (memory grows with points x faces/cell).
_CONTAINS_BATCH: int = 50_000
#: Faces per grid cell aimed at by the containment grid.
_FACES_PER_CELL: float = 2.0
#: Largest number of grid cells per axis of the containment grid.
_MAX_GRID: int = 256
#: Relative tolerance of the convexity test (fraction of the bounding radius).
_CONVEX_TOL: float = 1e-5
#: Concavity threshold of the convex decomposition of non-convex meshes (coacd's ``threshold``,
#: relative to the bounding-box diagonal). The L-block of ``hapticsim.data.example_meshes``
#: splits into its two bars exactly at 0.05 and at 0.02.
DECOMPOSITION_THRESHOLD: float = 0.03
#: Decompositions kept in memory (by mesh content), so repeated episodes do not redo them.
_DECOMPOSITION_CACHE_SIZE: int = 16
_decompositions: dict[bytes, tuple[Array, ...]] = {}


def _frozen(arr: np.ndarray) -> np.ndarray:
    arr = np.array(arr)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class MeshSolid(Solid):
    """A solid bounded by a closed, outward-oriented triangle mesh, in the world frame (a
    :class:`~hapticsim.geometry.solid.Solid` of kind ``"mesh"``).

    Attributes:
        vertices: (n, 3) float, vertex positions [m, world].
        faces: (m, 3) int, vertex indices of each triangle, counter-clockwise seen from outside.
        pieces: the convex pieces it collides as, when its source gives them (a URDF's collision
            hulls: :mod:`hapticsim.data.library`): vertex arrays (k, 3) [m, world], each the
            vertices of one convex hull; None (default): itself when convex, else coacd's.
        repair: what the loader mended (:mod:`hapticsim.data.mesh_repair`'s record, a dict),
            carried along its transforms; None for a mesh made in code.

    Instances are immutable and validated on construction (finite vertices, indices in range,
    at least 4 faces, no zero-area face, closed and consistently oriented, positive volume);
    arrays are read-only.

    Raises:
        InvalidInputError: any of the checks fails; the message names it.
    """

    vertices: Array
    faces: NDArray[np.int64]
    pieces: tuple[Array, ...] | None = None
    repair: dict[str, Any] | None = field(default=None, repr=False)

    kind = "mesh"

    def __post_init__(self) -> None:
        v = finite_array(self.vertices, "vertices", (None, 3))
        try:
            f = np.asarray(self.faces)
        except (TypeError, ValueError) as exc:
            raise InvalidInputError("`faces` must be (m, 3) int") from exc
        if f.ndim != 2 or f.shape[1] != 3 or not np.issubdtype(f.dtype, np.integer):
            raise InvalidInputError(f"`faces` must be (m, 3) int, got {f.dtype} {f.shape}")
        if len(f) < 4:
            raise InvalidInputError(f"a closed mesh needs at least 4 faces, got {len(f)}")
        f = f.astype(np.int64)
        if f.min() < 0 or f.max() >= len(v):
            raise InvalidInputError(
                f"`faces` index vertices 0..{len(v) - 1}, got indices {f.min()}..{f.max()}"
            )
        tri = v[f]
        doubled_area = np.linalg.norm(
            np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1
        )
        scale = float(np.ptp(v, axis=0).max())
        if scale <= 0 or np.any(doubled_area <= 1e-14 * scale**2):
            raise InvalidInputError(
                f"the mesh has {int(np.count_nonzero(doubled_area <= 1e-14 * scale**2))} "
                "zero-area faces"
            )
        _check_closed(f, len(v))
        object.__setattr__(self, "vertices", _frozen(v))
        object.__setattr__(self, "faces", _frozen(f))
        if self.pieces is not None:
            pieces = tuple(finite_array(p, "pieces", (None, 3)) for p in self.pieces)
            if not pieces or any(len(p) < 4 for p in pieces):
                raise InvalidInputError("`pieces` must be convex hulls of at least 4 vertices each")
            object.__setattr__(self, "pieces", tuple(_frozen(p) for p in pieces))
        if self.volume <= 0:
            raise InvalidInputError(
                f"the faces point inward (volume {self.volume:.3e} m^3 < 0): invert them"
            )

    # ----------------------------------------------------------------- measures
    @cached_property
    def triangles(self) -> Array:
        """(m, 3, 3) float, the vertices of each face [m, world]."""
        return _frozen(self.vertices[self.faces])

    @cached_property
    def face_normals(self) -> Array:
        """(m, 3) float, outward unit normals of the faces."""
        t = self.triangles
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        return _frozen(n / np.linalg.norm(n, axis=1, keepdims=True))

    @cached_property
    def face_areas(self) -> Array:
        """(m,) float, face areas [m^2]."""
        t = self.triangles
        return _frozen(0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1))

    @property
    def area(self) -> float:
        """Surface area [m^2]."""
        return float(np.sum(self.face_areas))

    @cached_property
    def _volume_and_centroid(self) -> tuple[float, Array]:
        # Signed tetrahedra (origin at the mean vertex, for round-off) of the divergence theorem.
        origin = self.vertices.mean(axis=0)
        t = self.triangles - origin
        six_v = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2]))
        volume = float(np.sum(six_v) / 6.0)
        weights = six_v / max(np.sum(six_v), 1e-300)
        centroid = origin + np.einsum("i,ij->j", weights, t.sum(axis=1) / 4.0)
        return volume, _frozen(centroid)

    @property
    def volume(self) -> float:
        """Volume [m^3] (divergence theorem, exact for the mesh)."""
        return self._volume_and_centroid[0]

    @property
    def centroid(self) -> Array:
        """(3,) float, centre of volume [m, world]."""
        return self._volume_and_centroid[1]

    @property
    def center(self) -> Array:
        """(3,) float, the centroid [m, world] (the reference point, like a superquadric's x0)."""
        return self.centroid

    @cached_property
    def bounding_radius(self) -> float:
        """Radius [m] of the smallest sphere about :attr:`center` that contains the solid."""
        return float(np.max(np.linalg.norm(self.vertices - self.centroid, axis=1)))

    @property
    def bounds(self) -> Array:
        """(2, 3) float, lowest and highest corner of the axis-aligned bounding box [m, world]."""
        return np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    @cached_property
    def principal_axes(self) -> Array:
        """(3, 3) float, columns the principal axes of the vertex spread (right-handed)."""
        d = self.vertices - self.vertices.mean(axis=0)
        _, vecs = np.linalg.eigh(d.T @ d)
        vecs = vecs[:, ::-1]
        if np.linalg.det(vecs) < 0:
            vecs[:, 2] *= -1.0
        return _frozen(vecs)

    @cached_property
    def half_extents(self) -> Array:
        """(3,) float, half-extents [m] of the solid along :attr:`principal_axes`."""
        p = (self.vertices - self.centroid) @ self.principal_axes
        return _frozen(0.5 * (p.max(axis=0) - p.min(axis=0)))

    @property
    def size(self) -> float:
        """Mean of :attr:`half_extents` [m]: the length that scales relative noise (SPEC §5),
        as ``mean(a)`` does for a superquadric."""
        return float(np.mean(self.half_extents))

    @cached_property
    def is_convex(self) -> bool:
        """True when every vertex lies on or behind the plane of every face, within 1e-5 of the
        bounding radius: above the precision of an STL's float32 coordinates (6e-8 of a
        coordinate) and of a mesh's facets along a curved surface, as trimesh's own test
        (1e-5 of the mesh's scale)."""
        tol = _CONVEX_TOL * self.bounding_radius
        n, p0 = self.face_normals, self.triangles[:, 0]
        offsets = np.einsum("ij,ij->i", n, p0)
        for start in range(0, len(n), 2048):
            s = slice(start, start + 2048)
            if np.any(self.vertices @ n[s].T - offsets[s] > tol):
                return False
        return True

    # ----------------------------------------------------------------- queries
    def contains(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, True where points lie inside the solid.

        The parity of the crossings of an upward vertical ray with the faces (the mesh is
        closed); faces are found through a uniform grid over their xy bounding boxes. Exact
        except for points whose ray passes exactly through an edge or a vertex (measure zero).

        Args:
            points_world: (n, 3) float [m, world].
        """
        p = points_array(points_world, "points_world")
        out = np.zeros(len(p), dtype=bool)
        lo, hi = self.bounds
        box = np.all((p >= lo) & (p <= hi), axis=1)
        idx = np.flatnonzero(box)
        for start in range(0, len(idx), _CONTAINS_BATCH):
            sel = idx[start : start + _CONTAINS_BATCH]
            out[sel] = self._grid.parity(p[sel])
        return out

    def closest_points(self, points_world: Array) -> tuple[Array, NDArray[np.int64]]:
        """The closest point of the surface to each point and the face it lies on (exact: every
        face is tested, in batches; :meth:`nearest` is the accelerated version for many points on
        large meshes).

        Args:
            points_world: (n, 3) float [m, world].

        Returns:
            closest (n, 3) float [m, world] and face (n,) int.
        """
        p = points_array(points_world, "points_world", min_count=1)
        return all_pairs_nearest(np.asarray(self.triangles), p)

    @cached_property
    def _grid(self) -> _ColumnGrid:
        return _ColumnGrid(self.triangles)

    @cached_property
    def _search(self) -> TriangleSearch:
        """The faces split into pieces with edges of at most 1/16 of the bounding radius."""
        return TriangleSearch(np.asarray(self.triangles), self.bounding_radius / 16)

    def nearest(
        self, points_world: Array, exact: bool = True
    ) -> tuple[Array, NDArray[np.int64]]:
        """The closest point of the surface to each point and the face it lies on, fast
        (:class:`~hapticsim.geometry.triangles.TriangleSearch`; ``exact=False`` tests each
        point's 16 nearest pieces only).

        Args:
            points_world: (n, 3) float [m, world].
            exact: keep testing until the nearest point is certain.

        Returns:
            closest (n, 3) float [m, world] and face (n,) int.
        """
        return self._search.nearest(points_array(points_world, "points_world", min_count=1), exact)

    # ----------------------------------------------------------------- Solid: surface
    def normals(self, points_world: Array) -> Array:
        """(n, 3) float, outward unit normals of the faces closest to the points."""
        _, face = self.nearest(points_world)
        return np.array(self.face_normals[face])

    def surface_distance(self, points_world: Array) -> Array:
        """(n,) distances [m] to the surface (:meth:`nearest`, ``exact=False``: the Chamfer
        distance's)."""
        p = points_array(points_world, "points_world", min_count=1)
        closest, _ = self.nearest(p, exact=False)
        return np.linalg.norm(closest - p, axis=1)

    #: What :meth:`contact_errors` measures against.
    contact_reference = (
        "mesh surface (exact closest point); normal of its face, or the normal cone of the "
        "adjacent faces at an edge or vertex"
    )

    def contact_errors(self, points_world: Array, normals_world: Array) -> tuple[Array, Array]:
        """Distance [m] of contacts to the surface and angle [deg] of their normals against the
        surface normal there: :func:`mesh_contact_errors` at its default feature tolerance."""
        return mesh_contact_errors(self, points_world, normals_world)

    # ----------------------------------------------------------------- sampling
    def sample_surface(
        self, count: int, rng: np.random.Generator | int | None = None
    ) -> tuple[Array, Array]:
        """Points uniform by area on the surface and the outward normals of their faces.

        Args:
            count: number of points, >= 1.
            rng: seed or generator.

        Returns:
            points (count, 3) [m, world] and unit normals (count, 3).
        """
        n = positive_int(count, "count")
        pts, face = sample_triangles(self.triangles, self.face_areas, n, as_generator(rng))
        return pts, self.face_normals[face].copy()

    # ----------------------------------------------------------------- Solid: pieces, pose
    def surface_mesh(self, resolution: int = 40) -> tuple[Array, NDArray[np.int64]]:
        """Its own vertices and faces (`resolution` is for solids meshed from parameters)."""
        return np.array(self.vertices), np.array(self.faces)

    def convex_pieces(self, resolution: int) -> tuple[tuple[Array, ...], Array, Array, str]:
        """A convex mesh: its own vertices; a non-convex one: its convex decomposition by coacd
        (optional dependency, extra ``meshes``) at :data:`DECOMPOSITION_THRESHOLD`; in a body
        frame at the centroid with the world's axes.

        Raises:
            SimulationError: a non-convex mesh without coacd installed, or a failed
                decomposition.
        """
        center = self.centroid
        if self.pieces is not None:
            return (tuple(np.asarray(p) - center for p in self.pieces), center, np.eye(3),
                    f"the {len(self.pieces)} convex pieces given with the mesh")  # fmt: skip
        if self.is_convex:
            return ((np.asarray(self.vertices) - center,), center, np.eye(3),
                    "convex mesh, as it is")  # fmt: skip
        parts = self._decomposition()
        method = (
            f"convex decomposition by coacd (threshold {DECOMPOSITION_THRESHOLD}, seed 0): "
            f"{len(parts)} convex parts"
        )
        return tuple(p - center for p in parts), center, np.eye(3), method

    def _decomposition(self) -> tuple[Array, ...]:
        key = self.shape_key()
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
            mesh = coacd.Mesh(np.asarray(self.vertices, float), np.asarray(self.faces, np.int64))
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

    def shape_key(self) -> bytes:
        """The mesh's content (vertices and faces, world frame: a mesh's key holds its pose)."""

        digest = hashlib.sha1(np.ascontiguousarray(self.vertices).tobytes())
        digest.update(np.ascontiguousarray(self.faces).tobytes())
        for piece in self.pieces or ():
            digest.update(np.ascontiguousarray(piece).tobytes())
        return b"mesh:" + digest.digest()

    # ----------------------------------------------------------------- transforms, export
    def transformed(self, rotation: Array, translation: Array) -> MeshSolid:
        """The solid moved rigidly: ``x -> rotation @ x + translation``.

        Args:
            rotation: (3, 3) float, a proper rotation.
            translation: (3,) float [m].
        """

        r = finite_array(rotation, "rotation", (3, 3))
        t = finite_array(translation, "translation", (3,))
        if not is_rotation(r, tol=1e-6):
            raise InvalidInputError("`rotation` must be a proper rotation matrix")
        pieces = None if self.pieces is None else tuple(p @ r.T + t for p in self.pieces)
        return MeshSolid(self.vertices @ r.T + t, self.faces, pieces, self.repair)

    def scaled(self, factor: float) -> MeshSolid:
        """The solid scaled about the world origin by `factor` (> 0)."""
        f = float(factor)
        if not np.isfinite(f) or f <= 0:
            raise InvalidInputError(f"`factor` must be a finite number > 0, got {factor!r}")
        pieces = None if self.pieces is None else tuple(p * f for p in self.pieces)
        return MeshSolid(self.vertices * f, self.faces, pieces, self.repair)

    def to_trimesh(self) -> Any:
        """A ``trimesh.Trimesh`` of the surface (same vertices and faces, not processed)."""
        import trimesh

        return trimesh.Trimesh(np.array(self.vertices), np.array(self.faces), process=False)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready ``{"mesh": {"vertices": [[x, y, z], ...], "faces": [[i, j, k], ...]}}``."""
        return {"mesh": {"vertices": self.vertices.tolist(), "faces": self.faces.tolist()}}

    def __repr__(self) -> str:
        c = np.round(self.centroid, 4).tolist()
        return (
            f"MeshSolid({len(self.vertices)} vertices, {len(self.faces)} faces, "
            f"volume={self.volume:.3e} m^3, centroid={c})"
        )


def _cone_angle(normal: Array, cone: Array) -> float:
    """Angle [rad] between a unit vector and the convex cone spanned by unit vectors (k, 3):
    0 inside, else the angle to its projection on the cone (non-negative least squares)."""
    from scipy.optimize import nnls

    if len(cone) == 1:
        return float(np.arccos(np.clip(normal @ cone[0], -1.0, 1.0)))
    weights, _ = nnls(cone.T, normal)
    proj = cone.T @ weights
    size = float(np.linalg.norm(proj))
    if size < 1e-12:
        return float(np.arccos(np.clip(np.max(cone @ normal), -1.0, 1.0)))
    return float(np.arccos(np.clip(proj @ normal / size, -1.0, 1.0)))


def _check_closed(faces: NDArray[np.int64], n_vertices: int) -> None:
    """Raise unless every directed edge occurs once and its reverse once (closed, oriented)."""
    a = faces.ravel()
    b = np.roll(faces, -1, axis=1).ravel()
    directed = a * n_vertices + b
    unique, counts = np.unique(directed, return_counts=True)
    if np.any(counts > 1):
        raise InvalidInputError(
            f"the mesh is not consistently oriented or not manifold: {int(np.sum(counts > 1))} "
            "edges are traversed twice in the same direction"
        )
    reverse = b * n_vertices + a
    missing = ~np.isin(reverse, unique)
    if np.any(missing):
        raise InvalidInputError(
            f"the mesh is not watertight: {int(np.count_nonzero(missing))} edges belong to a "
            "single face (holes or open boundaries)"
        )


class _ColumnGrid:
    """Faces binned by their xy bounding boxes on a uniform grid, for vertical-ray parity."""

    def __init__(self, triangles: Array) -> None:
        n = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
        keep = np.abs(n[:, 2]) > 1e-15 * np.max(np.abs(n))  # vertical faces never cross
        self.tri = triangles[keep]
        xy = self.tri[:, :, :2]
        self.lo = xy.min(axis=(0, 1))
        span = np.maximum(xy.max(axis=(0, 1)) - self.lo, 1e-12)
        cells = int(np.clip(np.sqrt(len(self.tri) / _FACES_PER_CELL), 1, _MAX_GRID))
        self.shape = (cells, cells)
        self.cell = span / cells
        i0 = self._index(xy.min(axis=1))
        i1 = self._index(xy.max(axis=1))
        nx = i1[:, 0] - i0[:, 0] + 1
        ny = i1[:, 1] - i0[:, 1] + 1
        count = nx * ny
        face = np.repeat(np.arange(len(self.tri)), count)
        offset = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
        cx = i0[face, 0] + offset % nx[face]
        cy = i0[face, 1] + offset // nx[face]
        cell_id = cx * cells + cy
        order = np.argsort(cell_id, kind="stable")
        self.cell_faces = face[order]
        self.starts = np.searchsorted(cell_id[order], np.arange(cells * cells + 1))

    def _index(self, xy: Array) -> NDArray[np.int64]:
        i = np.floor((xy - self.lo) / self.cell).astype(np.int64)
        return np.clip(i, 0, self.shape[0] - 1)

    def parity(self, points: Array) -> NDArray[np.bool_]:
        ij = self._index(points[:, :2])
        cell_id = ij[:, 0] * self.shape[0] + ij[:, 1]
        begin, end = self.starts[cell_id], self.starts[cell_id + 1]
        count = end - begin
        total = int(count.sum())
        if total == 0:
            return np.zeros(len(points), dtype=bool)
        point = np.repeat(np.arange(len(points)), count)
        offset = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
        face = self.cell_faces[np.repeat(begin, count) + offset]
        t = self.tri[face]
        p = points[point]
        a, b, c = t[:, 0], t[:, 1], t[:, 2]
        # signed doubled areas of the sub-triangles in xy (barycentric coordinates)
        wa = (b[:, 0] - p[:, 0]) * (c[:, 1] - p[:, 1]) - (c[:, 0] - p[:, 0]) * (b[:, 1] - p[:, 1])
        wb = (c[:, 0] - p[:, 0]) * (a[:, 1] - p[:, 1]) - (a[:, 0] - p[:, 0]) * (c[:, 1] - p[:, 1])
        wc = (a[:, 0] - p[:, 0]) * (b[:, 1] - p[:, 1]) - (b[:, 0] - p[:, 0]) * (a[:, 1] - p[:, 1])
        total_w = wa + wb + wc
        inside = ((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))
        inside &= total_w != 0
        with np.errstate(divide="ignore", invalid="ignore"):
            z = (wa * a[:, 2] + wb * b[:, 2] + wc * c[:, 2]) / total_w
        crossing = inside & (z > p[:, 2])
        hits = np.bincount(point[crossing], minlength=len(points))
        return (hits % 2) == 1



#: Faces within this distance [m] of a contact's closest point meet there: an edge or a vertex.
FEATURE_TOLERANCE: float = 1e-6


def mesh_contact_errors(
    mesh: MeshSolid, points_world: Array, normals_world: Array,
    feature_tolerance: float = FEATURE_TOLERANCE,
) -> tuple[Array, Array]:  # fmt: skip
    """Distance [m] of contacts (n, 3) to the mesh's surface and angle [deg] of their unit
    normals (n, 3) against the surface normal there, each (n,).

    The normal at a contact is the outward normal of the face it lies on. At an edge or a
    vertex (every face within `feature_tolerance` [m] of the closest point counts) the surface
    has a cone of normals, spanned by the adjacent faces' normals, and the angle is the one to
    that cone (0 inside it): a fingertip rolling over a sharp edge measures the normals in
    between, and each of them is right. (:meth:`MeshSolid.contact_errors` is this at
    :data:`FEATURE_TOLERANCE`; a study of the tolerance calls it with others.)
    """
    p = points_array(points_world, "points_world", min_count=1)
    unit = normals_array(normals_world, len(p), "normals_world")
    closest, face = mesh.closest_points(p)
    tri = np.asarray(mesh.triangles)
    normals = np.asarray(mesh.face_normals)
    angle = np.empty(len(p))
    for i in range(len(p)):
        q = np.repeat(closest[i][None, :], len(tri), axis=0)
        d = np.linalg.norm(closest_point_on_triangles(tri, q) - q, axis=1)
        faces = np.flatnonzero(np.nan_to_num(d, nan=np.inf) <= feature_tolerance)
        angle[i] = _cone_angle(unit[i], normals[faces if len(faces) else face[i : i + 1]])
    return np.linalg.norm(closest - p, axis=1), np.degrees(angle)

__all__ = ["DECOMPOSITION_THRESHOLD", "FEATURE_TOLERANCE", "MeshSolid", "mesh_contact_errors"]
