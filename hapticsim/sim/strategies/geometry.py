"""Exploration patterns planned on the rough object: patches in (eta, omega), edge contours.

All functions work on a :class:`~hapticsim.perception.vision.RoughObject` only (what a controller
may
know); their points are *expected* surface points, the contacts come from the simulation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.perception.vision import RoughObject
from hapticsim.sim.controllers import Probe

Array = NDArray[np.float64]

#: Latitude of a box corner in the uniform parametrisation, atan(1/sqrt(2)) [rad].
CORNER_ETA: float = float(np.arctan(1.0 / np.sqrt(2.0)))


def patch_probes(
    rough: RoughObject,
    eta_range: tuple[float, float],
    omega_range: tuple[float, float],
    count: int,
    rng: np.random.Generator,
) -> list[Probe]:
    """A randomised patch (paper III-A): `count` directions drawn uniformly from a rectangle in
    (eta, omega) [rad]; each probe aims at the rough surface point and approaches along its
    inward rough normal."""
    eta = rng.uniform(eta_range[0], eta_range[1], count)
    omega = rng.uniform(omega_range[0], omega_range[1], count)
    points, normals = rough.surface(eta, omega)
    return [Probe(p, -n) for p, n in zip(points, normals, strict=True)]


def _ray_to_surface(rough: RoughObject, origins_body: Array, dirs_body: Array) -> Array:
    """Distances s (n,) [m] with ``origin + s dir`` on the rough surface (bisection)."""
    shape = rough.shape
    lo = np.zeros(len(dirs_body))
    hi = np.full(len(dirs_body), 2.0 * rough.radius + 0.01)
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        pts = shape.to_world(origins_body + dirs_body * mid[:, None])
        inside = shape.inside_outside(pts) < 1.0
        lo = np.where(inside, mid, lo)
        hi = np.where(inside, hi, mid)
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class EdgeContour:
    """The rough object's contour in a plane across an edge between faces A and B.

    Attributes:
        points_world: (n, 3) float, contour points from face A over the edge to face B [m].
        normals_world: (n, 3) float, rough outward normals there.
        arc: (n,) float, arc length from the first point [m].
        edge_index: index of the point on the edge (normal halfway between the faces).
        plane_normal_world: (3,) float, unit normal of the plane (along the edge).
        face_a_end: arc length [m] of the middle of face A (start limit of a stripe).
        face_b_end: arc length [m] of the middle of face B (end limit of a stripe).
    """

    points_world: Array
    normals_world: Array
    arc: Array
    edge_index: int
    plane_normal_world: Array
    face_a_end: float
    face_b_end: float

    @property
    def edge_arc(self) -> float:
        """Arc length [m] of the edge point."""
        return float(self.arc[self.edge_index])

    def at(self, arc: float) -> tuple[Array, Array]:
        """Contour point (3,) [m] and normal (3,) at an arc length (linear interpolation)."""
        s = float(np.clip(arc, self.arc[0], self.arc[-1]))
        p = np.array([np.interp(s, self.arc, self.points_world[:, k]) for k in range(3)])
        n = np.array([np.interp(s, self.arc, self.normals_world[:, k]) for k in range(3)])
        return p, n / np.linalg.norm(n)

    def shifted(self, offset_world: Array) -> EdgeContour:
        """The same contour moved by a vector (for a parallel stripe of a prismatic body)."""
        return EdgeContour(
            self.points_world + offset_world, self.normals_world, self.arc, self.edge_index,
            self.plane_normal_world, self.face_a_end, self.face_b_end,
        )  # fmt: skip


def edge_contour(
    rough: RoughObject,
    face_a: tuple[int, float],
    face_b: tuple[int, float],
    offset: float = 0.0,
    samples: int = 241,
) -> EdgeContour:
    """The contour of the rough object in the plane across the edge between two faces.

    Faces are given as (body axis, sign), e.g. ``(0, +1.0)`` for the face whose outward normal is
    +x of the body. The plane is normal to the third axis, `offset` [m] from the centre.

    Returns:
        The contour from the middle of face A (angle 0) over the edge to the middle of face B
        (angle 90 deg), extended 15 deg past both.
    """
    i, sa = face_a
    j, sb = face_b
    k = 3 - i - j
    ea, eb, ek = np.eye(3)[i] * sa, np.eye(3)[j] * sb, np.eye(3)[k]
    theta = np.radians(np.linspace(-15.0, 105.0, samples))
    dirs = np.cos(theta)[:, None] * ea + np.sin(theta)[:, None] * eb
    origins = np.tile(ek * offset, (samples, 1))
    s = _ray_to_surface(rough, origins, dirs)
    points = rough.shape.to_world(origins + dirs * s[:, None])
    normals = rough.shape.normals(points)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    na, nb = rough.shape.rotation @ ea, rough.shape.rotation @ eb
    edge = int(np.argmin(np.abs(normals @ (na - nb))[samples // 8 : -samples // 8])) + samples // 8
    a_mid = int(np.argmin(np.abs(theta)))
    b_mid = int(np.argmin(np.abs(theta - np.pi / 2)))
    return EdgeContour(
        points_world=points, normals_world=normals, arc=arc, edge_index=edge,
        plane_normal_world=rough.shape.rotation @ ek, face_a_end=float(arc[a_mid]),
        face_b_end=float(arc[b_mid]),
    )  # fmt: skip


def corner_direction(signs: tuple[float, float, float]) -> tuple[float, float]:
    """(eta, omega) [rad] of a box corner with the given body-axis signs (uniform param.)."""
    sx, sy, sz = signs
    return float(sz * CORNER_ETA), float(np.arctan2(sy, sx))


def corner_probes(
    rough: RoughObject,
    signs: tuple[float, float, float],
    count: int,
    rng: np.random.Generator,
    half_width: float = np.radians(16.0),
) -> list[Probe]:
    """A patch around a corner of a prismatic body, covering the adjacent faces (paper IV)."""
    eta0, omega0 = corner_direction(signs)
    return patch_probes(
        rough, (eta0 - half_width, eta0 + half_width), (omega0 - half_width, omega0 + half_width),
        count, rng,
    )  # fmt: skip


__all__ = [
    "CORNER_ETA",
    "EdgeContour",
    "corner_direction",
    "corner_probes",
    "edge_contour",
    "patch_probes",
]
