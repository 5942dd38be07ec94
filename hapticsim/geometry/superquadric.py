"""The :class:`Superquadric` value: a posed, tapered superellipsoid (SPEC §1).

Parameter vector order (the only place that defines it; only the fitter works on raw vectors)::

    index  0-2   a        semi-axes a1, a2, a3 [m]
           3-4   eps      eps1, eps2
           5-6   taper    tx, ty
           7-9   rotvec   rotation vector of R (axis * angle) [rad]
           10-12 center   x0 [m]
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._files import read_json, write_text_atomic
from hapticsim._validate import (
    as_generator,
    finite_array,
    normals_array,
    points_array,
    positive_int,
)
from hapticsim.constants import (
    EPS_MAX,
    EPS_MIN,
    MAX_COORDINATE,
    MIN_LENGTH,
    ROTATION_TOL,
    TAPER_MAX,
)
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import functions as fn
from hapticsim.geometry.layout import (  # noqa: F401  (the layout's names, re-exported)
    N_PARAMS,
    PARAM_NAMES,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
)
from hapticsim.geometry.mesh import superquadric_mesh, surface_grid
from hapticsim.geometry.parametrization import parametrize
from hapticsim.geometry.rotations import (
    is_rotation,
    matrix_to_quaternion,
    matrix_to_rotvec,
    orthonormalize,
    quaternion_to_matrix,
    rotvec_to_matrix,
)
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]


#: Keys a superquadric JSON must have (SPEC §6); ``taper`` defaults to [0, 0].
REQUIRED_KEYS: tuple[str, ...] = ("a", "eps", "rotation", "center")

_EPS_SLACK = 1e-9
#: Largest |R^T R - I| entry kept as is; SVD output and float round trips stay below ~1e-15.
_ORTHO_EXACT = 1e-14


def _frozen(arr: Array) -> Array:
    arr = np.array(arr, dtype=np.float64)
    arr.setflags(write=False)
    return arr


def _columns(vectors: Array) -> Array:
    """(3, k) contiguous float64 columns of (..., 3) vectors (the compiled kernels' layout)."""
    return np.ascontiguousarray(np.asarray(vectors, dtype=np.float64).reshape(-1, 3).T)


@dataclass(frozen=True, eq=False)
class Superquadric(Solid):
    """A superquadric in the world: ``x = R D_t(chi(eta, omega)) + x0`` (paper eqs. 1-2).

    Attributes:
        a: (3,) float, semi-axes a1, a2, a3 [m], > 0.
        eps: (2,) float, (eps1, eps2): eps1 shapes the z profile, eps2 the xy cross-section;
            in [0.1, 2.0].
        taper: (2,) float, (tx, ty) linear tapering along z, in [-1, 1].
        rotation: (3, 3) float, R, body axes as columns in the world frame.
        center: (3,) float, x0, body origin in the world [m].

    Instances are immutable and validated on construction; arrays are read-only. A
    :class:`~hapticsim.geometry.solid.Solid` (kind ``"superquadric"``).
    """

    kind = "superquadric"
    contact_reference = "analytic superquadric surface and normal"

    a: Array
    eps: Array
    taper: Array = field(default_factory=lambda: np.zeros(2))
    rotation: Array = field(default_factory=lambda: np.eye(3))
    center: Array = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        a = finite_array(self.a, "a", (3,))
        eps = finite_array(self.eps, "eps", (2,))
        taper = finite_array(self.taper, "taper", (2,))
        rotation = finite_array(self.rotation, "rotation", (3, 3))
        center = finite_array(self.center, "center", (3,))
        if np.any(a <= 0):
            raise InvalidInputError(f"`a` must be > 0 (semi-axes [m]), got {a.tolist()}")
        if np.any(eps < EPS_MIN - _EPS_SLACK) or np.any(eps > EPS_MAX + _EPS_SLACK):
            raise InvalidInputError(f"`eps` must lie in [{EPS_MIN}, {EPS_MAX}], got {eps.tolist()}")
        if np.any(np.abs(taper) > TAPER_MAX + _EPS_SLACK):
            raise InvalidInputError(f"`taper` must lie in [-1, 1], got {taper.tolist()}")
        if not is_rotation(rotation, tol=ROTATION_TOL):
            raise InvalidInputError(
                "`rotation` must be a proper rotation matrix (orthonormal, det +1), got "
                f"{np.round(rotation, 6).tolist()}"
            )
        # Re-orthonormalise only what needs it: an SVD of an already orthonormal matrix changes
        # its last bits, and then JSON and replace() round trips would not be exact.
        if np.max(np.abs(rotation.T @ rotation - np.eye(3))) > _ORTHO_EXACT:
            rotation = orthonormalize(rotation)
        for name, value in (
            ("a", a), ("eps", np.clip(eps, EPS_MIN, EPS_MAX)), ("taper", np.clip(taper, -1, 1)),
            ("rotation", rotation), ("center", center),
        ):  # fmt: skip
            object.__setattr__(self, name, _frozen(value))

    # ----------------------------------------------------------------- construction, export
    @classmethod
    def from_vector(cls, vector: Array) -> Superquadric:
        """Build from the 13-element parameter vector (order in the module docstring)."""
        v = finite_array(vector, "vector", (N_PARAMS,))
        return cls(
            a=v[SLICE_A], eps=v[SLICE_EPS], taper=v[SLICE_TAPER],
            rotation=rotvec_to_matrix(v[SLICE_ROTVEC]), center=v[SLICE_CENTER],
        )  # fmt: skip

    def to_vector(self) -> Array:
        """The 13-element parameter vector, rotation as a rotation vector with angle in [0, pi]."""
        return np.concatenate(
            [self.a, self.eps, self.taper, matrix_to_rotvec(self.rotation), self.center]
        )

    @classmethod
    def from_quaternion(
        cls, a: Array, eps: Array, quaternion: Array, center: Array, taper: Array = (0.0, 0.0)
    ) -> Superquadric:
        """Build with the orientation given as a quaternion (w, x, y, z), as in MuJoCo."""
        q = finite_array(quaternion, "quaternion", (4,))
        if np.linalg.norm(q) < 1e-12:
            raise InvalidInputError("`quaternion` must be non-zero")
        return cls(a=a, eps=eps, taper=taper, rotation=quaternion_to_matrix(q), center=center)

    @property
    def quaternion(self) -> Array:
        """(4,) float, the orientation as a unit quaternion (w, x, y, z), w >= 0."""
        return matrix_to_quaternion(self.rotation)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary in the SPEC §6 layout."""
        return {
            "a": self.a.tolist(),
            "eps": self.eps.tolist(),
            "taper": self.taper.tolist(),
            "rotation": self.rotation.tolist(),
            "center": self.center.tolist(),
        }

    @classmethod
    def from_dict(cls, data: Any) -> Superquadric:
        """Read the SPEC §6 layout; a fit result (with key ``superquadric``) is accepted too.

        ``a``, ``eps``, ``rotation`` and ``center`` are required (:data:`REQUIRED_KEYS`): a
        missing shape or pose would silently become another solid. ``taper`` may be left out
        and then is ``[0, 0]`` (untapered). Semi-axes must be at least
        :data:`~hapticsim.constants.MIN_LENGTH` and semi-axes and centre at most
        :data:`~hapticsim.constants.MAX_COORDINATE` [m].

        Raises:
            InvalidInputError: not a JSON object, a required key missing (named), an unknown
                key, or a value out of its domain.
        """
        if isinstance(data, dict) and "superquadric" in data:
            data = data["superquadric"]
        if not isinstance(data, dict):
            raise InvalidInputError(
                f"a superquadric must be a JSON object, got {type(data).__name__}"
            )
        missing = [k for k in REQUIRED_KEYS if k not in data]
        if missing:
            raise InvalidInputError(
                f"superquadric is missing required key(s) {', '.join(missing)} (required: "
                f"{', '.join(REQUIRED_KEYS)}; optional: taper)"
            )
        unknown = sorted(set(data) - {"a", "eps", "taper", "rotation", "center"})
        if unknown:
            raise InvalidInputError(
                f"superquadric has unknown key(s) {unknown}; valid keys are "
                "a, eps, taper, rotation, center"
            )
        sq = cls(
            a=data["a"], eps=data["eps"], taper=data.get("taper", (0.0, 0.0)),
            rotation=data["rotation"], center=data["center"],
        )  # fmt: skip
        if sq.a.min() < MIN_LENGTH or sq.a.max() > MAX_COORDINATE:
            raise InvalidInputError(
                f"`a` must lie in [{MIN_LENGTH:g}, {MAX_COORDINATE:g}] m, got {sq.a.tolist()}"
            )
        if np.abs(sq.center).max() > MAX_COORDINATE:
            raise InvalidInputError(
                f"`center` must lie within +-{MAX_COORDINATE:g} m, got {sq.center.tolist()}"
            )
        return sq

    def to_json(self, path: str | Path | None = None) -> str:
        """The JSON text; also written to `path` when given."""
        text = json.dumps(self.to_dict(), indent=2)
        if path is not None:

            write_text_atomic(path, text + "\n")
        return text

    @classmethod
    def from_json(cls, path_or_text: str | Path) -> Superquadric:
        """Read a superquadric (or a fit result) from a JSON file path or a JSON string."""

        return cls.from_dict(read_json(path_or_text))

    def replace(self, **changes: Any) -> Superquadric:
        """A copy with some fields changed (validated again)."""
        fields = dict(
            a=self.a, eps=self.eps, taper=self.taper, rotation=self.rotation, center=self.center
        )
        fields.update(changes)
        return Superquadric(**fields)

    def transformed(self, rotation: Array, translation: Array) -> Superquadric:
        """The same solid moved by the rigid transform ``x -> rotation @ x + translation``."""
        rot = finite_array(rotation, "rotation", (3, 3))
        t = finite_array(translation, "translation", (3,))
        return self.replace(rotation=rot @ self.rotation, center=rot @ self.center + t)

    def scaled(self, factor: float) -> Superquadric:
        """The superquadric scaled about the world origin: semi-axes and centre times `factor`
        (> 0); exponents, tapers and orientation stay."""
        f = _positive_factor(factor)
        return self.replace(a=self.a * f, center=self.center * f)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Superquadric):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, k), getattr(other, k))
            for k in ("a", "eps", "taper", "rotation", "center")
        )

    def __hash__(self) -> int:
        return hash(self.to_vector().tobytes())

    def __getstate__(self) -> dict[str, Any]:
        """Its parameters alone: the surface meshes it keeps once asked for
        (:func:`hapticsim.geometry.sampling.surface_mesh_of`) are made again where needed, not
        sent to another process."""
        return {k: v for k, v in self.__dict__.items() if not k.startswith("_")}

    def __repr__(self) -> str:
        f = np.array2string
        return (
            f"Superquadric(a={f(self.a, precision=4)}, eps={f(self.eps, precision=3)}, "
            f"taper={f(self.taper, precision=3)}, center={f(self.center, precision=4)}, "
            f"quaternion={f(self.quaternion, precision=4)})"
        )

    # ----------------------------------------------------------------- geometry
    def to_body(self, points_world: Array) -> Array:
        """Tapered body-frame coordinates ``R^T (x - x0)`` of (n, 3) world points [m]."""
        p = finite_array(points_world, "points_world", (None, 3))
        return fn.world_to_body(p, self.rotation, self.center)

    def to_world(self, points_body: Array) -> Array:
        """World coordinates ``R p + x0`` of (n, 3) tapered body-frame points [m]."""
        p = finite_array(points_body, "points_body", (None, 3))
        return fn.body_to_world(p, self.rotation, self.center)

    def _sym(self, points_world: Array) -> Array:
        return fn.untaper(self.to_body(points_world), self.a, self.taper)

    def inside_outside(self, points_world: Array) -> Array:
        """F of (n, 3) world points (SPEC §1): < 1 inside, 1 on the surface, > 1 outside. (n,)."""
        return fn.inside_outside(self._sym(points_world), self.a, self.eps)

    def contains(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, True for world points inside or on the solid."""
        return self.inside_outside(points_world) <= 1.0

    def log_inside_outside(self, points_world: Array) -> Array:
        """(n,) float, log F of world points (< 0 inside)."""
        return fn.log_inside_outside(self._sym(points_world), self.a, self.eps)

    def outside(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, True strictly outside (``log F > 0``: the volume measures' test)."""
        return self.log_inside_outside(points_world) > 0.0

    def radial_distance(self, points_world: Array) -> Array:
        """(n,) float, the radial distance D1 of SPEC §2 [m] (untapered body frame)."""
        return fn.radial_distance(self._sym(points_world), self.a, self.eps)

    def normals(self, points_world: Array) -> Array:
        """(n, 3) float, outward unit normals in the world frame (paper eq. 5).

        For a point off the surface this is the normal at its radial projection (the normal of the
        level set of F through it), the n' of the EOF (SPEC §2).
        """
        nb = fn.normals_body(self.to_body(points_world), self.a, self.eps, self.taper)
        return nb @ self.rotation.T

    def project(self, points_world: Array) -> Array:
        """(n, 3) float, radial projections of world points onto the surface [m]."""
        sym = self._sym(points_world)
        on = sym * fn.radial_scale(sym, self.a, self.eps)[:, None]
        return fn.body_to_world(fn.apply_taper(on, self.a, self.taper), self.rotation, self.center)

    def surface(
        self, eta: Array, omega: Array, parametrization: str = "uniform"
    ) -> tuple[Array, Array]:
        """Surface points and outward unit normals in the world frame.

        Args:
            eta: (n,) float latitudes [rad], in (-pi/2, pi/2) or at its ends.
            omega: (n,) float longitudes [rad], from -pi to pi.
            parametrization: ``"uniform"`` (eq. 6, default) or ``"natural"`` (eq. 1).

        Returns:
            points_world (n, 3) [m] and normals_world (n, 3), unit length.
        """
        eta = finite_array(np.atleast_1d(eta), "eta", (None,))
        omega = finite_array(np.atleast_1d(omega), "omega", (None,))
        if eta.shape != omega.shape:
            raise InvalidInputError(
                f"`eta` and `omega` must have the same length, got {eta.shape[0]} and "
                f"{omega.shape[0]}"
            )
        sym = parametrize(eta, omega, self.a, self.eps, parametrization)
        body = fn.apply_taper(sym, self.a, self.taper)
        normals_b = fn.normals_body(body, self.a, self.eps, self.taper)
        return (
            fn.body_to_world(body, self.rotation, self.center),
            normals_b @ self.rotation.T,
        )

    @property
    def volume(self) -> float:
        """Exact volume [m^3] (closed form with beta functions, see :func:`functions.volume`)."""
        return fn.volume(self.a, self.eps, self.taper)

    @property
    def _half_box(self) -> Array:
        """(3,) float, half-extents of a body-frame box holding the tapered solid [m]."""
        # |x| <= a1 (1 + |tx|) etc. on the tapered body.
        return self.a * np.array([1 + abs(self.taper[0]), 1 + abs(self.taper[1]), 1])

    @property
    def bounding_radius(self) -> float:
        """Radius [m] of a sphere about ``center`` that contains the solid."""
        return float(np.linalg.norm(self._half_box))

    @property
    def bounds(self) -> Array:
        """(2, 3) float, a world-axis box holding the solid (its body box, posed) [m]."""
        half = np.abs(self.rotation) @ self._half_box
        return np.stack([self.center - half, self.center + half])

    @property
    def size(self) -> float:
        """``mean(a)`` [m], SPEC §5's noise scale."""
        return float(np.mean(self.a))

    @property
    def surface_area(self) -> float:
        """Surface area [m^2] of its fine mesh (:class:`~hapticsim.geometry.sampling.
        SurfaceMesh`, 96 longitudes: a little less than the exact area)."""
        from hapticsim.geometry.sampling import DEFAULT_MESH_RESOLUTION, surface_mesh_of

        return surface_mesh_of(self, DEFAULT_MESH_RESOLUTION).area

    # ----------------------------------------------------------------- Solid: sampling
    def sample_interior(self, count: int, rng: np.random.Generator | int | None = None) -> Array:
        """(count, 3) float, points uniform inside (rejection sampling,
        :func:`~hapticsim.geometry.sampling.superquadric_interior`) [m, world]."""
        from hapticsim.geometry.sampling import superquadric_interior

        return superquadric_interior(self, count, rng)

    def interior_from_unit(self, u: Array) -> Array:
        """The points the rejection sampler keeps of candidates `u` (k, 4) in [0, 1): the first
        three coordinates in the cube of scaled untapered coordinates, the fourth the taper's
        acceptance, (j, 3) [m, world]."""
        from hapticsim.geometry.sampling import max_taper_jacobian

        u = np.asarray(u, dtype=np.float64)
        unit = 2.0 * u[:, :3] - 1.0
        keep = fn.log_inside_outside(unit, np.ones(3), self.eps) < 0.0
        top = max_taper_jacobian(self.taper)
        jac = (1.0 + self.taper[0] * unit[:, 2]) * (1.0 + self.taper[1] * unit[:, 2])
        keep &= u[:, 3] * top < jac
        body = fn.apply_taper(unit[keep] * self.a, self.a, self.taper)
        return fn.body_to_world(body, self.rotation, self.center)

    def sample_surface(
        self, count: int, rng: np.random.Generator | int | None = None, resolution: int = 96
    ) -> tuple[Array, Array]:
        """`count` points uniform by area on the surface (random points on the triangles of its
        fine mesh, moved radially onto the exact surface) and their outward normals."""
        from hapticsim.geometry.sampling import surface_mesh_of

        n = positive_int(count, "count")
        points = surface_mesh_of(self, resolution).sample(n, as_generator(rng))
        return points, self.normals(points)

    # ----------------------------------------------------------------- Solid: surface
    def surface_distance(self, points_world: Array, resolution: int = 96) -> Array:
        """(n,) distances [m] to its fine mesh (vertices on the surface; the chords add a few
        1e-5 m at 96 longitudes)."""
        from hapticsim.geometry.sampling import surface_mesh_of

        p = finite_array(points_world, "points_world", (None, 3))
        return surface_mesh_of(self, resolution).distance(p)

    def contact_errors(self, points_world: Array, normals_world: Array) -> tuple[Array, Array]:
        """Distance [m] of contacts to the surface, ``|(p - q) . n(q)|`` with q the radial
        projection (the Euclidean distance to first order: exact on flat faces, error
        ``|p - q|^2 * curvature`` elsewhere, under 1e-8 m within 0.1 mm), and the angle [deg]
        of their normals against the outward normal at q."""

        p = points_array(points_world, "points_world", min_count=1)
        n = normals_array(normals_world, len(p), "normals_world")
        q = self.project(p)
        nq = self.normals(q)
        distance = np.abs(np.einsum("ij,ij->i", p - q, nq))
        angle = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", n, nq), -1.0, 1.0)))
        return distance, angle

    def first_hits(
        self, origins: Array, directions: Array, length: float, grids: tuple[int, ...]
    ) -> Array:
        """Ray casting, compiled (:func:`hapticsim.geometry._rays_compiled.first_hits`): only
        each ray's chord through the bounding sphere is searched."""
        from hapticsim.geometry._rays_compiled import first_hits
        from hapticsim.geometry.eof_compiled import unpack

        o, d = _columns(origins), _columns(directions)
        out = np.empty(o.shape[1])
        first_hits(o, d, float(length), np.asarray(grids, dtype=np.int64), *unpack(self),
                   1.0001 * self.bounding_radius, out)  # fmt: skip
        return out

    def segment_depths(
        self, points: Array, normals: Array, reach: float, grids: tuple[int, ...]
    ) -> Array:
        """:meth:`Solid.segment_depths`, compiled in one pass
        (:func:`hapticsim.geometry._rays_compiled.segment_depths`: the inside test is ``log F
        <= 0``)."""
        from hapticsim.geometry._rays_compiled import segment_depths
        from hapticsim.geometry.eof_compiled import unpack

        p, m = _columns(points), _columns(normals)
        out = np.empty(p.shape[1])
        segment_depths(p, m, float(reach), np.asarray(grids, dtype=np.int64), *unpack(self),
                       1.0001 * self.bounding_radius, out)  # fmt: skip
        return out

    # ----------------------------------------------------------------- Solid: pieces, pose
    def surface_mesh(self, resolution: int = 40) -> tuple[Array, NDArray[np.int64]]:
        """Vertices and faces of its mesh (:func:`hapticsim.geometry.mesh.surface_grid`)."""

        return surface_grid(self, resolution)

    def convex_pieces(self, resolution: int) -> tuple[tuple[Array, ...], Array, Array, str]:
        """One piece: the distinct vertices of its uniform and natural grids at `resolution`
        longitudes in its body frame (the hull MuJoCo builds of them is its collision mesh)."""

        res = positive_int(resolution, "resolution", minimum=8)
        body = self.replace(rotation=np.eye(3), center=np.zeros(3))
        vertices = np.concatenate(
            [surface_grid(body, res, "uniform")[0], surface_grid(body, res, "natural")[0]]
        )
        return ((np.unique(np.round(vertices, 12), axis=0),), self.center, self.rotation,
                "superquadric mesh: hull of the uniform and natural grids")  # fmt: skip

    @property
    def pose(self) -> tuple[Array, Array]:
        """Its rotation and centre: :meth:`shape_key` is of the body-frame shape."""
        return self.rotation, self.center

    def shape_key(self) -> bytes:
        """The body-frame shape's parameters (a, eps, taper)."""
        return np.concatenate([self.a, self.eps, self.taper]).tobytes()

    def to_mesh(self, resolution: int = 64, parametrization: str = "uniform") -> Any:
        """A watertight ``trimesh.Trimesh`` of the surface in the world frame.

        See :func:`hapticsim.geometry.mesh.superquadric_mesh`.
        """

        return superquadric_mesh(self, resolution=resolution, parametrization=parametrization)


def _positive_factor(factor: Any) -> float:
    """`factor` as a finite float > 0, else InvalidInputError."""
    try:
        f = float(factor)
    except (TypeError, ValueError):
        f = float("nan")
    if not np.isfinite(f) or f <= 0:
        raise InvalidInputError(f"`factor` must be a finite number > 0, got {factor!r}")
    return f


def superquadric_arg(value: Any, name: str) -> Superquadric:
    """`value` if it is a :class:`Superquadric`, else InvalidInputError naming `name`."""
    if not isinstance(value, Superquadric):
        raise InvalidInputError(f"`{name}` must be a Superquadric, got {type(value).__name__}")
    return value
