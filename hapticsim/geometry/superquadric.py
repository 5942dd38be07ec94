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

from hapticsim._validate import finite_array
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
from hapticsim.geometry.parametrization import parametrize
from hapticsim.geometry.rotations import (
    is_rotation,
    matrix_to_quaternion,
    matrix_to_rotvec,
    orthonormalize,
    quaternion_to_matrix,
    rotvec_to_matrix,
)

Array = NDArray[np.float64]

#: Length of the parameter vector (paper: 13 parameters).
N_PARAMS: int = 13
#: Slices of the parameter vector.
SLICE_A = slice(0, 3)
SLICE_EPS = slice(3, 5)
SLICE_TAPER = slice(5, 7)
SLICE_ROTVEC = slice(7, 10)
SLICE_CENTER = slice(10, 13)
PARAM_NAMES: tuple[str, ...] = (
    "a1", "a2", "a3", "eps1", "eps2", "tx", "ty", "rx", "ry", "rz", "x0", "y0", "z0",
)  # fmt: skip

#: Keys a superquadric JSON must have (SPEC §6); ``taper`` defaults to [0, 0].
REQUIRED_KEYS: tuple[str, ...] = ("a", "eps", "rotation", "center")

_EPS_SLACK = 1e-9
#: Largest |R^T R - I| entry kept as is; SVD output and float round trips stay below ~1e-15.
_ORTHO_EXACT = 1e-14


def _frozen(arr: Array) -> Array:
    arr = np.array(arr, dtype=np.float64)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Superquadric:
    """A superquadric in the world: ``x = R D_t(chi(eta, omega)) + x0`` (paper eqs. 1-2).

    Attributes:
        a: (3,) float, semi-axes a1, a2, a3 [m], > 0.
        eps: (2,) float, (eps1, eps2): eps1 shapes the z profile, eps2 the xy cross-section;
            in [0.1, 2.0].
        taper: (2,) float, (tx, ty) linear tapering along z, in [-1, 1].
        rotation: (3, 3) float, R, body axes as columns in the world frame.
        center: (3,) float, x0, body origin in the world [m].

    Instances are immutable and validated on construction; arrays are read-only.
    """

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
            from hapticsim._files import write_text_atomic

            write_text_atomic(path, text + "\n")
        return text

    @classmethod
    def from_json(cls, path_or_text: str | Path) -> Superquadric:
        """Read a superquadric (or a fit result) from a JSON file path or a JSON string."""
        from hapticsim._files import read_json

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

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Superquadric):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, k), getattr(other, k))
            for k in ("a", "eps", "taper", "rotation", "center")
        )

    def __hash__(self) -> int:
        return hash(self.to_vector().tobytes())

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
            eta: (n,) float latitudes in [-pi/2, pi/2] [rad].
            omega: (n,) float longitudes in [-pi, pi] [rad].
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
    def bounding_radius(self) -> float:
        """Radius [m] of a sphere about ``center`` that contains the solid."""
        # |x| <= a1 (1 + |tx|) etc. on the tapered body.
        return float(
            np.linalg.norm(self.a * np.array([1 + abs(self.taper[0]), 1 + abs(self.taper[1]), 1]))
        )

    def to_mesh(self, resolution: int = 64, parametrization: str = "uniform") -> Any:
        """A watertight ``trimesh.Trimesh`` of the surface in the world frame.

        See :func:`hapticsim.geometry.mesh.superquadric_mesh`.
        """
        from hapticsim.geometry.mesh import superquadric_mesh

        return superquadric_mesh(self, resolution=resolution, parametrization=parametrization)


def superquadric_arg(value: Any, name: str) -> Superquadric:
    """`value` if it is a :class:`Superquadric`, else InvalidInputError naming `name`."""
    if not isinstance(value, Superquadric):
        raise InvalidInputError(f"`{name}` must be a Superquadric, got {type(value).__name__}")
    return value
