"""The supertoroid: a superquadric with a hole (Barr's toroidal superquadric), SPEC §10's part
kind ``"supertoroid"``.

In its body frame (z the axis of the hole) the surface is, for eta, omega in [-pi, pi):

    x = a1 (hole + cos^eps1 eta) cos^eps2 omega
    y = a2 (hole + cos^eps1 eta) sin^eps2 omega
    z = a3 sin^eps1 eta

(``c^e`` the signed power ``sign(c) |c|^e``), and the inside-outside function is

    F(p) = (r(p) - hole)^(2/eps1) + |z/a3|^(2/eps1),
    r(p) = (|x/a1|^(2/eps2) + |y/a2|^(2/eps2))^(eps2/2)

with F < 1 inside, 1 on the surface. ``hole`` > 1 is the ring's radius over the tube's: the
tube's cross-section is the superellipse of exponent eps1 and half-widths (a1 or a2, a3) about a
centre line at ``hole`` times (a1, a2); the hole's half-width is ``(hole - 1) a1``. Its volume is
exact: ``V = 2 a1 a2 a3 hole A(eps1) A(eps2)``, A(e) the area of the unit superellipse of
exponent e (the tube's cross-section swept round the axis; Pappus's theorem for superellipses).

Distances to the surface and surface samples come from a fine mesh of the parametrisation (its
vertices on the surface); normals, membership and contact errors (a radial projection in the
tube's cross-section, first order as a superquadric's) from F.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, finite_float, positive_int
from hapticsim.constants import EPS_MAX, EPS_MIN, ROTATION_TOL
from hapticsim.errors import InvalidInputError
from hapticsim.geometry.functions import signed_power, unit_superellipse_area
from hapticsim.geometry.rotations import is_rotation, orthonormalize
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]

#: The smallest and largest hole ratio: at 1 the tube touches the axis and the hole closes.
HOLE_MIN, HOLE_MAX = 1.05, 20.0
#: Keys of a supertoroid's JSON beside ``"kind": "supertoroid"``.
REQUIRED_KEYS: tuple[str, ...] = ("a", "eps", "hole", "rotation", "center")
#: Mesh longitudes of the fine mesh behind distances, samples and contact errors.
FINE_RESOLUTION: int = 128
#: Angular sectors MuJoCo collides with (each the hull of a piece of the ring).
SECTORS: int = 16


def _frozen(arr: Array) -> Array:
    arr = np.array(arr, dtype=np.float64)
    arr.setflags(write=False)
    return arr


def tube_coordinates(b: Array, a: Array, eps: Array, hole: float) -> tuple[Array, ...]:
    """Body-frame points `b` (n, 3) in the tube's terms (module docstring), each (n,): ``r``
    the xy superellipse radius (in units of a1, a2), ``u = r - hole`` and ``w = z / a3`` the
    offsets from the tube's centre line, and ``F = |u|^(2/eps1) + |w|^(2/eps1)``."""
    a1, a2, a3 = a
    e1, e2 = eps
    r = (np.abs(b[:, 0] / a1) ** (2 / e2) + np.abs(b[:, 1] / a2) ** (2 / e2)) ** (e2 / 2)
    u, w = r - hole, b[:, 2] / a3
    return r, u, w, np.abs(u) ** (2 / e1) + np.abs(w) ** (2 / e1)


def body_normals(b: Array, a: Array, eps: Array, hole: float) -> Array:
    """(n, 3) outward unit normals at body-frame points `b` (n, 3): F's gradient (module
    docstring), finite off the axis; a point on the tube's centre line gets the radial
    direction. (The fit calls it on raw parameters, without making a solid.)"""
    a1, a2, a3 = a
    e1, e2 = eps
    ux, uy = np.abs(b[:, 0] / a1), np.abs(b[:, 1] / a2)
    s = ux ** (2 / e2) + uy ** (2 / e2)
    r = s ** (e2 / 2)
    d = r - hole
    # dF/dr and dF/dz, then dr/dx, dr/dy (chain rule through the xy superellipse)
    df_dr = (2 / e1) * np.sign(d) * np.abs(d) ** (2 / e1 - 1)
    df_dz = (2 / e1) * np.sign(b[:, 2]) * np.abs(b[:, 2] / a3) ** (2 / e1 - 1) / a3
    with np.errstate(divide="ignore", invalid="ignore"):
        common = np.where(s > 0, s ** (e2 / 2 - 1), 0.0)
        dr_dx = common * np.sign(b[:, 0]) * ux ** (2 / e2 - 1) / a1
        dr_dy = common * np.sign(b[:, 1]) * uy ** (2 / e2 - 1) / a2
    grad = np.stack([df_dr * dr_dx, df_dr * dr_dy, df_dz], axis=1)
    grad = np.nan_to_num(grad, nan=0.0, posinf=0.0, neginf=0.0)
    norm = np.linalg.norm(grad, axis=1)
    radial = np.stack([b[:, 0], b[:, 1], np.zeros(len(b))], axis=1)
    radial /= np.maximum(np.linalg.norm(radial, axis=1, keepdims=True), 1e-300)
    return np.where(norm[:, None] > 0, grad / np.maximum(norm, 1e-300)[:, None], radial)


@dataclass(frozen=True, eq=False)
class Supertoroid(Solid):
    """A supertoroid in the world (module docstring).

    Attributes:
        a: (3,) float, a1, a2 (the tube's half-widths in x and y, which the ring's radius
            scales) and a3 (its half-height) [m], > 0.
        eps: (2,) float, (eps1, eps2): eps1 the tube's cross-section, eps2 the ring's outline in
            xy; in [0.1, 2.0].
        hole: the ring's radius over the tube's, in [:data:`HOLE_MIN`, :data:`HOLE_MAX`].
        rotation: (3, 3) float, body axes as columns in the world (z the axis of the hole).
        center: (3,) float, the centre of the hole [m, world].
    """

    kind = "supertoroid"
    contact_reference = "analytic supertoroid surface (radial projection) and normal"

    a: Array
    eps: Array
    hole: float
    rotation: Array = field(default_factory=lambda: np.eye(3))
    center: Array = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        a = finite_array(self.a, "a", (3,))
        eps = finite_array(self.eps, "eps", (2,))
        hole = finite_float(self.hole, "hole")
        rotation = finite_array(self.rotation, "rotation", (3, 3))
        center = finite_array(self.center, "center", (3,))
        if np.any(a <= 0):
            raise InvalidInputError(f"`a` must be > 0 (half-widths [m]), got {a.tolist()}")
        if np.any(eps < EPS_MIN - 1e-9) or np.any(eps > EPS_MAX + 1e-9):
            raise InvalidInputError(f"`eps` must lie in [{EPS_MIN}, {EPS_MAX}], got {eps.tolist()}")
        if not HOLE_MIN <= hole <= HOLE_MAX:
            raise InvalidInputError(
                f"`hole` (the ring's radius over the tube's) must lie in [{HOLE_MIN}, "
                f"{HOLE_MAX}], got {hole!r}: at 1 or below the tube reaches the axis and the "
                "solid has no hole"
            )
        if not is_rotation(rotation, tol=ROTATION_TOL):
            raise InvalidInputError(
                "`rotation` must be a proper rotation matrix (orthonormal, det +1), got "
                f"{np.round(rotation, 6).tolist()}"
            )
        object.__setattr__(self, "a", _frozen(a))
        object.__setattr__(self, "eps", _frozen(np.clip(eps, EPS_MIN, EPS_MAX)))
        object.__setattr__(self, "hole", float(hole))
        if np.max(np.abs(rotation.T @ rotation - np.eye(3))) > 1e-14:  # only what needs it:
            rotation = orthonormalize(rotation)  # an exact round trip keeps its bits
        object.__setattr__(self, "rotation", _frozen(rotation))
        object.__setattr__(self, "center", _frozen(center))

    # ----------------------------------------------------------------- the body frame
    def to_body(self, points_world: Array) -> Array:
        """(n, 3) points in the body frame."""
        p = np.asarray(points_world, dtype=np.float64).reshape(-1, 3)
        return (p - self.center) @ self.rotation

    def inside_outside(self, points_world: Array) -> Array:
        """(n,) F (module docstring): < 1 inside, 1 on the surface."""
        b = self.to_body(points_world)
        return self._f_body(b)

    def _f_body(self, b: Array) -> Array:
        return tube_coordinates(b, self.a, self.eps, self.hole)[3]

    def log_inside_outside(self, points_world: Array) -> Array:
        """(n,) float, log F (< 0 inside): the union's measure of which part is nearest."""
        with np.errstate(divide="ignore"):
            return np.log(np.maximum(self.inside_outside(points_world), 1e-300))

    def interior_from_unit(self, u: Array) -> Array:
        """The points of candidates `u` (k, >= 3) in [0, 1) that lie inside, the first three
        coordinates spread over its body box (a union's overlap count), (j, 3) [m, world]. The
        box turns with the ring, as a superquadric's cube does: a rigid motion carries the same
        candidates along, so a moved union measures the same overlaps (the world's bounding box
        did not: a union with a ring changed its volume by 5e-5 when turned)."""
        body = (2.0 * np.asarray(u, dtype=np.float64)[:, :3] - 1.0) * self.half_extents
        pts = body @ self.rotation.T + self.center
        return pts[self.contains(pts)]

    @property
    def surface_area(self) -> float:
        """Surface area [m^2] of its fine mesh (vertices on the surface: a little less than the
        exact area)."""
        return float(self._fine().area)

    def surface_points(self, eta: Array, omega: Array) -> Array:
        """(n, 3) surface points [m, world] at the angles (module docstring's parametrisation)."""
        e1, e2 = self.eps
        a1, a2, a3 = self.a
        ring = self.hole + signed_power(np.cos(eta), e1)
        body = np.stack([a1 * ring * signed_power(np.cos(omega), e2),
                         a2 * ring * signed_power(np.sin(omega), e2),
                         a3 * signed_power(np.sin(eta), e1)], axis=-1)  # fmt: skip
        return body @ self.rotation.T + self.center

    # ----------------------------------------------------------------- membership
    def contains(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, F <= 1."""
        return self.inside_outside(points_world) <= 1.0

    def outside(self, points_world: Array) -> NDArray[np.bool_]:
        """(n,) bool, F > 1."""
        return self.inside_outside(points_world) > 1.0

    # ----------------------------------------------------------------- surface
    def normals(self, points_world: Array) -> Array:
        """(n, 3) outward unit normals: F's gradient at the points (:func:`body_normals`)."""
        return body_normals(self.to_body(points_world), self.a, self.eps, self.hole) @ (
            self.rotation.T
        )

    def _fine(self) -> Any:
        """The fine mesh (a :class:`~hapticsim.geometry.mesh_solid.MeshSolid`), kept with it."""
        fine = self.__dict__.get("_fine_mesh")
        if fine is None:
            from hapticsim.geometry.mesh_solid import MeshSolid

            fine = MeshSolid(*self.surface_mesh(FINE_RESOLUTION))
            object.__setattr__(self, "_fine_mesh", fine)
        return fine

    def surface_distance(self, points_world: Array) -> Array:
        """(n,) distances [m] to its fine mesh (vertices on the surface)."""
        return self._fine().surface_distance(points_world)

    def project(self, points_world: Array) -> Array:
        """(n, 3) the radial projections of points onto the surface [m, world]: along the line
        from the tube's centre line in the point's cross-section (the superquadric's radial
        projection, with the tube in its place)."""
        b = self.to_body(points_world)
        r, u, w, f = tube_coordinates(b, self.a, self.eps, self.hole)
        t = np.maximum(f ** (self.eps[0] / 2), 1e-12)
        r_q = self.hole + u / t
        scale = np.where(r > 1e-12, r_q / np.maximum(r, 1e-12), 1.0)
        q = np.stack([b[:, 0] * scale, b[:, 1] * scale, self.a[2] * w / t], axis=1)
        return q @ self.rotation.T + self.center

    def contact_errors(self, points_world: Array, normals_world: Array) -> tuple[Array, Array]:
        """Distance [m] of contacts to the surface, ``|(p - q) . n(q)|`` with q the radial
        projection (:meth:`project`; the Euclidean distance to first order, as a
        superquadric's), and the angle [deg] of their normals against the normal at q."""
        from hapticsim._validate import normals_array, points_array

        p = points_array(points_world, "points_world", min_count=1)
        unit = normals_array(normals_world, len(p), "normals_world")
        q = self.project(p)
        nq = self.normals(q)
        distance = np.abs(np.einsum("ij,ij->i", p - q, nq))
        angle = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", unit, nq), -1.0, 1.0)))
        return distance, angle

    def first_hits(
        self, origins: Array, directions: Array, length: float, grids: tuple[int, ...]
    ) -> Array:
        """As :meth:`Solid.first_hits`, with a first grid fine enough (steps of at most half
        the tube's smallest half-width) that a ray through the tube's thick part is not missed
        between samples (a ray grazing its edge can still be)."""
        need = int(np.ceil(float(length) / (0.5 * float(np.min(self.a))))) + 1
        return super().first_hits(origins, directions, length, (max(grids[0], need), *grids[1:]))

    # ----------------------------------------------------------------- sampling
    def sample_surface(
        self, count: int, rng: np.random.Generator | int | None = None
    ) -> tuple[Array, Array]:
        """`count` points uniform by area on its fine mesh, moved onto the exact surface by
        :meth:`project` (as a superquadric's), and the analytic normals there."""
        pts, _ = self._fine().sample_surface(positive_int(count, "count"), rng)
        pts = self.project(pts)
        return pts, self.normals(pts)

    # ----------------------------------------------------------------- measures
    @property
    def volume(self) -> float:
        """``2 a1 a2 a3 hole A(eps1) A(eps2)`` [m^3] (module docstring)."""
        a1, a2, a3 = self.a
        e1, e2 = self.eps
        return float(2.0 * a1 * a2 * a3 * self.hole * unit_superellipse_area(e1)
                     * unit_superellipse_area(e2))  # fmt: skip

    @property
    def half_extents(self) -> Array:
        """(3,) float, half its size along the body axes [m]."""
        return np.array([self.a[0] * (self.hole + 1), self.a[1] * (self.hole + 1), self.a[2]])

    @property
    def bounding_radius(self) -> float:
        """Radius of a sphere about the centre that holds it [m]."""
        return float(np.linalg.norm(self.half_extents))

    @property
    def bounds(self) -> Array:
        """(2, 3) float, the box of the rotated body box's corners [m]."""
        half = np.abs(self.rotation) @ self.half_extents
        return np.stack([self.center - half, self.center + half])

    @property
    def size(self) -> float:
        """The mean half extent [m] (SPEC §5's relative noise)."""
        return float(np.mean(self.half_extents))

    # ----------------------------------------------------------------- meshes, pieces
    def _grid(self, resolution: int) -> tuple[Array, Array, int, int]:
        res = positive_int(resolution, "resolution", minimum=8)
        n_omega, n_eta = res, max(8, res // 2)
        omega = -np.pi + 2 * np.pi * np.arange(n_omega) / n_omega
        eta = -np.pi + 2 * np.pi * np.arange(n_eta) / n_eta
        return omega, eta, n_omega, n_eta

    def surface_mesh(self, resolution: int = 40) -> tuple[Array, NDArray[np.int64]]:
        """A closed mesh of the surface: `resolution` longitudes round the axis, half as many
        round the tube; vertices on the surface [m, world], faces outward."""
        omega, eta, n_omega, n_eta = self._grid(resolution)
        oo, ee = np.meshgrid(omega, eta, indexing="ij")  # (n_omega, n_eta)
        vertices = self.surface_points(ee.ravel(), oo.ravel())
        i, j = np.meshgrid(np.arange(n_omega), np.arange(n_eta), indexing="ij")
        v00 = (i * n_eta + j).ravel()
        v10 = (((i + 1) % n_omega) * n_eta + j).ravel()
        v01 = (i * n_eta + (j + 1) % n_eta).ravel()
        v11 = (((i + 1) % n_omega) * n_eta + (j + 1) % n_eta).ravel()
        faces = np.concatenate([np.stack([v00, v10, v11], 1), np.stack([v00, v11, v01], 1)])
        return vertices, faces.astype(np.int64)

    def convex_pieces(self, resolution: int) -> tuple[tuple[Array, ...], Array, Array, str]:
        """:data:`SECTORS` pieces, each the vertices of one angular sector of the ring (with its
        neighbours' boundary rows), in the body frame."""
        body = Supertoroid(self.a, self.eps, self.hole)
        res = max(positive_int(resolution, "resolution", minimum=8), 2 * SECTORS)
        omega, eta, n_omega, n_eta = self._grid(res)
        edges = np.linspace(-np.pi, np.pi, SECTORS + 1)
        pieces = []
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            w = np.concatenate([[lo], omega[(omega > lo) & (omega < hi)], [hi]])
            oo, ee = np.meshgrid(w, eta, indexing="ij")
            pieces.append(body.surface_points(ee.ravel(), oo.ravel()))
        return (tuple(pieces), self.center, self.rotation,
                f"supertoroid: hulls of {SECTORS} sectors of the ring")  # fmt: skip

    # ----------------------------------------------------------------- placement
    def transformed(self, rotation: Array, translation: Array) -> Supertoroid:
        """The same solid moved rigidly: ``x -> rotation @ x + translation``."""
        rot = finite_array(rotation, "rotation", (3, 3))
        t = finite_array(translation, "translation", (3,))
        return Supertoroid(self.a, self.eps, self.hole, rot @ self.rotation, rot @ self.center + t)

    def scaled(self, factor: float) -> Supertoroid:
        """Scaled about the world origin by `factor` (> 0)."""
        f = finite_float(factor, "factor")
        if f <= 0:
            raise InvalidInputError(f"`factor` must be > 0, got {factor!r}")
        return Supertoroid(self.a * f, self.eps, self.hole, self.rotation, self.center * f)

    @property
    def pose(self) -> tuple[Array, Array]:
        """Its rotation and centre."""
        return self.rotation, self.center

    def shape_key(self) -> bytes:
        """The body-frame shape's parameters."""
        return b"supertoroid:" + np.concatenate([self.a, self.eps, [self.hole]]).tobytes()

    # ----------------------------------------------------------------- files
    def to_dict(self) -> dict[str, Any]:
        """SPEC §10's part JSON: ``{"kind": "supertoroid", "a", "eps", "hole", "rotation",
        "center"}``."""
        return {"kind": self.kind, "a": self.a.tolist(), "eps": self.eps.tolist(),
                "hole": self.hole, "rotation": self.rotation.tolist(),
                "center": self.center.tolist()}  # fmt: skip

    @classmethod
    def from_dict(cls, data: Any) -> Supertoroid:
        """Read :meth:`to_dict`'s layout (``kind`` may be left out).

        Raises:
            InvalidInputError: not an object, a missing key (named), an unknown key, or a value
                out of its domain.
        """
        if not isinstance(data, dict):
            raise InvalidInputError(
                f"a supertoroid must be a JSON object, got {type(data).__name__}"
            )
        missing = [k for k in REQUIRED_KEYS if k not in data]
        if missing:
            raise InvalidInputError(
                f"supertoroid is missing required key(s) {', '.join(missing)} (required: "
                f"{', '.join(REQUIRED_KEYS)})"
            )
        unknown = sorted(set(data) - {"kind", *REQUIRED_KEYS})
        if unknown:
            raise InvalidInputError(
                f"supertoroid has unknown key(s) {unknown}; valid keys are kind, "
                f"{', '.join(REQUIRED_KEYS)}"
            )
        try:
            return cls(data["a"], data["eps"], data["hole"], data["rotation"], data["center"])
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(f"supertoroid: {exc}") from None

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Supertoroid):
            return NotImplemented
        return self.to_dict() == other.to_dict()

    def __hash__(self) -> int:
        return int.from_bytes(hashlib.sha1(self.shape_key()).digest()[:8], "little")

    def __getstate__(self) -> dict[str, Any]:
        """Its parameters alone (the fine mesh is made again where needed)."""
        return {k: v for k, v in self.__dict__.items() if not k.startswith("_")}

    def __repr__(self) -> str:
        f = np.array2string
        return (f"Supertoroid(a={f(self.a, precision=4)}, eps={f(self.eps, precision=3)}, "
                f"hole={self.hole:.3f}, center={f(self.center, precision=4)})")  # fmt: skip


__all__ = ["HOLE_MAX", "HOLE_MIN", "SECTORS", "Supertoroid", "body_normals", "tube_coordinates"]
