"""Error of fit of contact data to superquadrics (SPEC §2, paper eqs. 7-9).

The public face of the one EOF implementation, the compiled kernel
:mod:`hapticsim.geometry.eof_compiled`; the fitter, the quality measure theta and the
environment's fit schedule all call it.

- :func:`contact_residuals` and :func:`error_of_fit` take superquadric parameter arrays with
  leading batch dimensions ``...`` (a whole population in one call);
- :class:`ContactSet` holds contacts laid out for the kernel, and :meth:`ContactSet.residuals`
  / :meth:`ContactSet.jacobian` evaluate raw 13-vectors (:meth:`Superquadric.to_vector` order),
  which is what the fitter works on.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.errors import ChoiceError
from hapticsim.geometry import eof_compiled as kernel
from hapticsim.geometry.layout import (
    N_PARAMS,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_TAPER,
)

Array = NDArray[np.float64]

#: Ways of measuring the contact distance D1 (see :func:`contact_residuals`).
DISTANCES: tuple[str, ...] = ("untapered", "tapered")
#: Parameters of a superquadric vector (a, eps, taper, rotation vector, centre).


def check_distance(distance: str) -> bool:
    """Whether `distance` (one of :data:`DISTANCES`) is ``"tapered"``; else InvalidInputError."""
    if distance not in DISTANCES:
        raise ChoiceError("distance", distance, DISTANCES)
    return distance == "tapered"


@dataclass(frozen=True, eq=False)
class ContactSet:
    """Contacts laid out for the compiled kernel: one row per coordinate, unit normals.

    Attributes:
        points: (3, n) float, contact points [m, world] (row k holds coordinate k).
        normals: (3, n) float unit normals, zeros when `with_normals` is False.
        with_normals: whether the EOF includes the normal term.
        tally: (1,) int64, the evaluations the kernels did on these contacts (one per vector,
            13 per Jacobian): what evaluation budgets are checked against.
    """

    points: Array
    normals: Array
    with_normals: bool
    tally: NDArray[np.int64] = field(default_factory=lambda: np.zeros(1, np.int64))

    @classmethod
    def from_arrays(cls, points_world: Array, normals_world: Array | None) -> ContactSet:
        """From (n, 3) points [m] and (n, 3) normals (normalised here) or None."""
        points = np.ascontiguousarray(np.asarray(points_world, dtype=np.float64).T)
        if normals_world is None:
            return cls(points, np.zeros_like(points), False)
        normals = np.asarray(normals_world, dtype=np.float64)
        normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
        return cls(points, np.ascontiguousarray(normals.T), True)

    @property
    def count(self) -> int:
        """The number of contacts n."""
        return int(self.points.shape[1])

    def residuals(self, vectors: Array, lam: float, tapered: bool) -> Array:
        """Residuals (P, n) [m] of P parameter vectors (P, 13)."""
        v = np.ascontiguousarray(vectors, dtype=np.float64).reshape(-1, N_PARAMS)
        out = np.empty((v.shape[0], self.count))
        kernel.residuals_vectors(
            self.points,
            self.normals,
            self.with_normals,
            v,
            float(lam),
            bool(tapered),
            out,
            self.tally,
        )
        return out

    def residuals_posed(self, vectors: Array, rotations: Array, lam: float, tapered: bool) -> Array:
        """Residuals (P, n) [m] of P vectors (P, 13) whose rotations are given as matrices
        (P, 3, 3) instead (the rotation-vector entries of `vectors` are ignored)."""
        v = np.ascontiguousarray(vectors, dtype=np.float64).reshape(-1, N_PARAMS)
        rot = np.ascontiguousarray(rotations, dtype=np.float64).reshape(-1, 3, 3)
        out = np.empty((v.shape[0], self.count))
        kernel.residuals_posed(
            self.points, self.normals, self.with_normals, np.ascontiguousarray(v[:, SLICE_A]),
            np.ascontiguousarray(v[:, SLICE_EPS]), np.ascontiguousarray(v[:, SLICE_TAPER]), rot,
            np.ascontiguousarray(v[:, SLICE_CENTER]), float(lam), bool(tapered), out, self.tally,
        )  # fmt: skip
        return out

    def jacobian(self, vector: Array, lam: float, tapered: bool) -> tuple[Array, Array]:
        """Residuals (n,) [m] and their analytic Jacobian (n, 13) at one vector (13,)."""
        x = np.ascontiguousarray(vector, dtype=np.float64).reshape(N_PARAMS)
        r = np.empty(self.count)
        jac_t = np.empty((N_PARAMS, self.count))
        kernel.jacobian_vector(
            self.points,
            self.normals,
            self.with_normals,
            x,
            float(lam),
            bool(tapered),
            r,
            jac_t,
            self.tally,
        )
        return r, jac_t.T


def contact_residuals(
    points_world: Array,
    normals_world: Array | None,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
    distance: str = "untapered",
) -> Array:
    """Per-contact residuals ``r_i = |D1_i| + lambda * sigma * D2_i`` (paper eq. 9).

    ``sum(r_i^2) / n`` is the EOF. Without normals, ``r_i = |D1_i|``.

    Args:
        points_world: (n, 3) float, contact points [m].
        normals_world: (n, 3) float normals (normalised here), or None.
        a: (..., 3) [m]; eps: (..., 2); taper: (..., 2); rotation: (..., 3, 3); center: (..., 3).
        lam: weight lambda of the normal term.
        distance: how D1 is measured, one of :data:`DISTANCES`. ``"untapered"`` (SPEC §2):
            ``|p| |1 - s|`` with p the untapered body-frame point and ``s = F(p)^(-eps1/2)``.
            ``"tapered"``: the world distance between the contact and the same ray's surface
            point ``s p`` mapped back through the taper. The two agree without taper; with it,
            the untapered distance shrinks by about the taper factor ``1 + t z / a3`` where the
            solid is wide, which rewards extreme tapers on noisy data.

    Returns:
        (..., n) float residuals [m].
    """
    tapered = check_distance(distance)
    contacts = ContactSet.from_arrays(points_world, normals_world)
    a = np.asarray(a, dtype=np.float64)
    eps = np.asarray(eps, dtype=np.float64)
    taper = np.asarray(taper, dtype=np.float64)
    rotation = np.asarray(rotation, dtype=np.float64)
    center = np.asarray(center, dtype=np.float64)
    batch = np.broadcast_shapes(
        a.shape[:-1], eps.shape[:-1], taper.shape[:-1], rotation.shape[:-2], center.shape[:-1]
    )
    count = int(np.prod(batch, dtype=np.int64))

    def flat(x: Array, tail: tuple[int, ...]) -> Array:
        # A writable copy: a read-only view (what broadcasting gives) is another numba type,
        # which would compile the kernel a second time beside the solvers' cached one.
        return np.array(np.broadcast_to(x, batch + tail).reshape((count, *tail)), order="C")

    out = np.empty((count, contacts.count))
    kernel.residuals_posed(
        contacts.points, contacts.normals, contacts.with_normals, flat(a, (3,)), flat(eps, (2,)),
        flat(taper, (2,)), flat(rotation, (3, 3)), flat(center, (3,)), float(lam), tapered, out,
        contacts.tally,
    )  # fmt: skip
    return out.reshape((*batch, contacts.count))


def error_of_fit(
    points_world: Array,
    normals_world: Array | None,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
    distance: str = "untapered",
) -> Array:
    """EOF ``D = mean(r_i^2)`` (SPEC §2), shape ``...`` of the parameters [m^2].

    Arguments as :func:`contact_residuals`.
    """
    r = contact_residuals(
        points_world, normals_world, a, eps, taper, rotation, center, lam, distance
    )
    return np.mean(r**2, axis=-1)
