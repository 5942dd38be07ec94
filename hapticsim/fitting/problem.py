"""What the compiled least squares and genetic algorithm minimise: a :class:`Problem`.

A problem names the residual vector r whose ``sum(r^2)`` the solvers minimise (the genetic
algorithm ranks by ``sum(r^2) / n``): the paper's EOF residuals (eq. 9) of a
:class:`~hapticsim.geometry.eof.ContactSet`, or nML's maximum-likelihood residuals
(:mod:`hapticsim.fitting.likelihood` makes their settings). Build one with :meth:`Problem.eof`
or :meth:`Problem.ml`; :func:`problem_residuals` and :func:`problem_jacobian` evaluate it from
numpy (the compiled solvers call :mod:`hapticsim.fitting._problem_compiled` directly).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError
from hapticsim.fitting import _problem_compiled as compiled
from hapticsim.fitting._ml_compiled import ML_SETTINGS
from hapticsim.geometry.eof import ContactSet
from hapticsim.geometry.layout import N_PARAMS

Array = NDArray[np.float64]


class Problem(NamedTuple):
    """A residual vector for the compiled solvers (a named tuple, which numba compiles).

    Attributes:
        points: (3, n) float, the contacts [m, world], one row per coordinate.
        normals: (3, n) float unit normals (zeros without normals).
        with_normals: whether the residuals use the normals.
        lam: the paper EOF's weight lambda of the normal term (0 for ML).
        tapered: the paper EOF's distance mode (``"tapered"``; True for ML, which ignores it).
        settings: None for the paper's EOF; else nML's (ML_SETTINGS,) settings array
            (``_ml_compiled.ML_*`` layout), optionally followed by the per-contact multipliers of
            the distance and of the normal residuals ((ML_SETTINGS + 2 n,)). The compiled code
            specialises on its type, so an EOF problem carries None, not an empty array.
        free: (3, f) float free-space points [m, world] of the ML residuals (f may be 0).
    """

    points: Array
    normals: Array
    with_normals: bool
    lam: float
    tapered: bool
    settings: Array | None
    free: Array

    @classmethod
    def eof(cls, contacts: ContactSet, lam: float, tapered: bool) -> Problem:
        """The paper's EOF residuals of `contacts` (m = n)."""
        return cls(contacts.points, contacts.normals, contacts.with_normals, float(lam),
                   bool(tapered), None, np.zeros((3, 0)))  # fmt: skip

    @classmethod
    def ml(cls, contacts: ContactSet, settings: Array, free: Array | None = None) -> Problem:
        """nML's residuals of `contacts` with `settings` and the (f, 3) free-space points
        `free` [m, world] (or None); InvalidInputError for settings of another shape."""
        ml = np.asarray(settings, np.float64)
        if ml.shape not in ((ML_SETTINGS,), (ML_SETTINGS + 2 * contacts.count,)):
            raise InvalidInputError(
                f"`settings` must be ({ML_SETTINGS},) or ({ML_SETTINGS} + 2 x "
                f"{contacts.count},), got {ml.shape}"
            )
        pts = np.zeros((3, 0)) if free is None else np.asarray(free, dtype=np.float64).T
        return cls(contacts.points, contacts.normals, contacts.with_normals, 0.0, True,
                   np.ascontiguousarray(ml), np.ascontiguousarray(pts))  # fmt: skip

    @property
    def length(self) -> int:
        """The length m of the residual vector."""
        return int(compiled.residual_length(self))


def problem_residuals(contacts: ContactSet, problem: Problem, vectors: Array) -> Array:
    """Residual vectors (P, m) of `problem` at P parameter vectors (P, 13); the evaluations
    count in ``contacts.tally``."""
    v = np.ascontiguousarray(vectors, dtype=np.float64).reshape(-1, N_PARAMS)
    out = np.empty((v.shape[0], problem.length))
    compiled.problem_residuals(problem, v, out, contacts.tally)
    return out


def problem_jacobian(contacts: ContactSet, problem: Problem, vector: Array) -> tuple[Array, Array]:
    """Residual vector (m,) of `problem` at one parameter vector and its analytic Jacobian
    (m, 13); counts 13 evaluations in ``contacts.tally``."""
    x = np.ascontiguousarray(vector, dtype=np.float64).reshape(N_PARAMS)
    m = problem.length
    r, jac_t = np.empty(m), np.empty((N_PARAMS, m))
    compiled.problem_jacobian(problem, x, r, jac_t, contacts.tally)
    return r, jac_t.T


__all__ = ["Problem", "problem_jacobian", "problem_residuals"]
