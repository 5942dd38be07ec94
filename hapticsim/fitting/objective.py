"""The error of fit as an optimisation objective on raw parameter vectors, with a budget.

Every method of :mod:`hapticsim.fitting` evaluates the EOF (SPEC §2) only through an
:class:`Objective`, which counts evaluations (one per parameter vector, SPEC §3), refuses to go
beyond the budget, and remembers the best vector seen and the history of the best EOF. The
vector order is that of :meth:`Superquadric.to_vector` (a, eps, taper, rotation vector, centre).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import EPS_MAX, EPS_MIN, TAPER_MAX
from hapticsim.fitting._problem_compiled import problem_residuals_posed
from hapticsim.fitting.problem import Problem, problem_residuals
from hapticsim.geometry.eof import ContactSet, check_distance
from hapticsim.geometry.rotations import matrix_to_rotvec
from hapticsim.geometry.superquadric import (
    N_PARAMS,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
)

Array = NDArray[np.float64]

#: Smallest semi-axis as a fraction of the data size (keeps the fit away from degenerate bodies).
A_MIN_FRACTION: float = 1e-3
#: Largest semi-axis and largest centre offset from the data centroid, in data sizes.
A_MAX_FRACTION: float = 10.0


class BudgetExhausted(Exception):  # noqa: N818 (a signal, not an error)
    """Raised by :class:`Objective` when an evaluation would exceed the budget (internal)."""


@dataclass(frozen=True)
class Bounds:
    """Box bounds on the 13-vector, from the size of the data.

    Attributes:
        lower, upper: (13,) float. Rotation-vector entries are unbounded (+-inf).
        scale: (13,) float, typical magnitude of each entry (data size for a and centre, 1 else),
            for finite-difference steps, mutation sizes and ``x_scale``.
    """

    lower: Array
    upper: Array
    scale: Array

    @classmethod
    def from_points(cls, points_world: Array) -> Bounds:
        """Bounds for contacts (n, 3) [m]: a in [1e-3 s, 10 s], centre within 10 s of the centroid.

        ``s`` is the data size: the largest distance of a contact from the centroid.
        """
        centroid = points_world.mean(axis=0)
        size = float(np.max(np.linalg.norm(points_world - centroid, axis=1)))
        lower = np.empty(N_PARAMS)
        upper = np.empty(N_PARAMS)
        scale = np.ones(N_PARAMS)
        lower[SLICE_A], upper[SLICE_A] = A_MIN_FRACTION * size, A_MAX_FRACTION * size
        lower[SLICE_EPS], upper[SLICE_EPS] = EPS_MIN, EPS_MAX
        lower[SLICE_TAPER], upper[SLICE_TAPER] = -TAPER_MAX, TAPER_MAX
        lower[SLICE_ROTVEC], upper[SLICE_ROTVEC] = -np.inf, np.inf
        lower[SLICE_CENTER] = centroid - A_MAX_FRACTION * size
        upper[SLICE_CENTER] = centroid + A_MAX_FRACTION * size
        scale[SLICE_A] = scale[SLICE_CENTER] = size
        return cls(lower=lower, upper=upper, scale=scale)

    @property
    def size(self) -> float:
        """The data size s [m]."""
        return float(self.scale[0])

    def clip(self, vectors: Array) -> Array:
        """Vectors (..., 13) clipped into the bounds (a copy)."""
        return np.clip(vectors, self.lower, self.upper)


class Objective:
    """EOF of contact data as a function of parameter vectors, with evaluation counting.

    Args:
        points_world: (n, 3) float contacts [m].
        normals_world: (n, 3) float unit normals, or None for the EOF without normals.
        lam: weight lambda of the normal term (SPEC §2).
        budget: the most evaluations allowed, >= 1.
        distance: how the contact distance D1 is measured, ``"untapered"`` (SPEC §2) or
            ``"tapered"`` (see :func:`hapticsim.geometry.eof.contact_residuals`).
        settings: None for the paper's EOF; else the (8,) settings of the maximum-likelihood
            residuals of nML (:class:`hapticsim.fitting.likelihood.Likelihood`), whose
            ``sum(r^2) / n`` then takes the place of the EOF everywhere below.
        free: (f, 3) float free-space points [m, world] of the ML residuals, or None.

    Attributes:
        evaluations: evaluations used so far.
        best_vector: (13,) float, the vector of the lowest EOF seen (None before any).
        best_eof: that EOF [m^2].
    """

    def __init__(
        self,
        points_world: Array,
        normals_world: Array | None,
        lam: float,
        budget: int,
        distance: str = "untapered",
        settings: Array | None = None,
        free: Array | None = None,
    ) -> None:
        self.points = points_world
        self.distance = distance
        self.tapered = check_distance(distance)
        self.normals = normals_world
        self.lam = float(lam)
        self.budget = int(budget)
        self.count = int(points_world.shape[0])
        self.bounds = Bounds.from_points(points_world)
        self.contacts = ContactSet.from_arrays(points_world, normals_world)
        self.problem = (Problem.eof(self.contacts, self.lam, self.tapered) if settings is None
                        else Problem.ml(self.contacts, settings, free))  # fmt: skip
        self.ml = settings is not None
        self.evaluations = 0
        self.best_vector: Array | None = None
        self.best_eof = np.inf
        self._history_evals: list[int] = []
        self._history_eof: list[float] = []

    @property
    def remaining(self) -> int:
        """Evaluations left in the budget."""
        return self.budget - self.evaluations

    @property
    def with_normals(self) -> bool:
        """Whether the EOF includes the normal term."""
        return self.normals is not None

    def residuals(self, vectors: Array, rotations: Array | None = None) -> Array:
        """Residuals r (P, m) of P vectors (P, 13); ``sum(r**2, -1) / n`` is the EOF.

        m = n [m] for the paper's EOF; for the ML residuals m is their vector length
        (dimensionless).

        Counts P evaluations and updates the best vector.

        Args:
            vectors: (P, 13) float parameter vectors.
            rotations: optional (P, 3, 3) rotation matrices; when given they are used instead of
                the rotation vectors in `vectors` (which may then hold anything).

        Raises:
            BudgetExhausted: P exceeds the remaining budget (nothing is evaluated).
        """
        v = np.ascontiguousarray(vectors, dtype=np.float64).reshape(-1, N_PARAMS)
        if v.shape[0] > self.remaining:
            raise BudgetExhausted
        if self.ml:
            r = self._ml_residuals(v, rotations)
        elif rotations is None:
            r = self.contacts.residuals(v, self.lam, self.tapered)
        else:
            r = self.contacts.residuals_posed(v, rotations, self.lam, self.tapered)
        eof = np.einsum("ij,ij->i", r, r) / self.count
        best = int(np.argmin(eof))
        if eof[best] < self.best_eof and rotations is not None:
            v = v[best : best + 1].copy()
            v[0, SLICE_ROTVEC] = matrix_to_rotvec(rotations[best])
            self.record(len(eof), v, eof[best : best + 1])
        else:
            self.record(len(eof), v, eof)
        return r

    def _ml_residuals(self, v: Array, rotations: Array | None) -> Array:
        if rotations is None:
            return problem_residuals(self.contacts, self.problem, v)
        rot = np.ascontiguousarray(rotations, dtype=np.float64).reshape(-1, 3, 3)
        out = np.empty((v.shape[0], self.problem.length))
        problem_residuals_posed(
            self.problem, np.ascontiguousarray(v[:, SLICE_A]),
            np.ascontiguousarray(v[:, SLICE_EPS]), np.ascontiguousarray(v[:, SLICE_TAPER]), rot,
            np.ascontiguousarray(v[:, SLICE_CENTER]), out, self.contacts.tally,
        )  # fmt: skip
        return out

    def reweight(self, settings: Array) -> None:
        """Replace the ML settings (nML re-estimates the noise between stages) and forget the
        best vector, whose value was in the old weights; counting and history go on."""
        if not self.ml:
            raise ValueError("reweight needs an objective with ML settings")
        self.problem.settings[:] = np.asarray(settings, dtype=np.float64)
        self.best_vector, self.best_eof = None, np.inf

    def record(
        self,
        evaluations: int,
        vectors: Array,
        eof: Array,
        history: tuple[NDArray[np.int64], Array] | None = None,
    ) -> None:
        """Count `evaluations` done elsewhere (a compiled stage) and offer their results.

        Args:
            evaluations: evaluations used (> 0 adds a history entry).
            vectors: (k, 13) float, vectors those evaluations reached.
            eof: (k,) float, their EOF [m^2]; the lowest becomes the best if it beats it.
            history: optional (evaluations since the stage began (h,), best EOF of the stage
                so far (h,)), entries of the history within the stage.
        """
        if evaluations <= 0:
            return
        if history is not None:
            for used, best in zip(*history, strict=True):
                if 0 < used < evaluations:
                    self._history_evals.append(self.evaluations + int(used))
                    self._history_eof.append(min(self.best_eof, float(best)))
        self.evaluations += int(evaluations)
        if len(eof):
            best = int(np.argmin(eof))
            if eof[best] < self.best_eof:
                self.best_eof = float(eof[best])
                self.best_vector = np.array(vectors[best], dtype=np.float64)
        self._history_evals.append(self.evaluations)
        self._history_eof.append(self.best_eof)

    def eof(self, vectors: Array, rotations: Array | None = None) -> Array:
        """EOF (P,) [m^2] of P vectors (P, 13); counts P evaluations (see :meth:`residuals`)."""
        r = self.residuals(vectors, rotations)
        return np.einsum("ij,ij->i", r, r) / self.count

    def history(self) -> tuple[NDArray[np.int64], Array]:
        """(evaluations (k,) int, best EOF so far (k,) float) after each call."""
        return np.asarray(self._history_evals, dtype=np.int64), np.asarray(self._history_eof)
