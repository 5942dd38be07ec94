"""The compiled solvers' one entry to their residuals: a problem.

The least squares (:mod:`hapticsim.fitting._lm_compiled`) and the genetic algorithm
(:mod:`hapticsim.fitting._ga_compiled`) minimise ``sum(r^2)`` of whichever residual vector a
problem holds: the paper's EOF residuals (eq. 9, :mod:`hapticsim.geometry.eof_compiled`; the
problem's ``settings`` is None) or nML's maximum-likelihood residuals
(:mod:`hapticsim.fitting._ml_compiled`; ``settings`` an array). The functions here dispatch on
the *numba type* of ``settings``, at compile time: each solver is compiled once per residual
model with only that model's code, so an nH fit never compiles the ML residuals and their
Jacobian (which tripled the first fit's compilation).
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.extending import overload

from hapticsim.fitting._ml_compiled import (
    ml_jacobian_vector,
    ml_residual_count,
    ml_residuals_posed,
    ml_residuals_vectors,
)
from hapticsim.geometry.eof_compiled import (
    JIT,
    jacobian_vector,
    residuals_posed,
    residuals_vectors,
)


def _is_ml(problem: types.Type) -> bool:
    """Whether a problem's numba type is of the ML residuals (its ``settings`` an array; the
    paper EOF's problems carry None there)."""
    settings = problem.types[problem.fields.index("settings")]
    return not isinstance(settings, types.NoneType)


def _length(problem):  # pragma: no cover - replaced by the overload below in compiled code
    raise NotImplementedError


@overload(_length, jit_options=JIT)
def _length_model(problem):
    if _is_ml(problem):

        def ml(problem):
            return ml_residual_count(
                problem.points.shape[1], problem.with_normals, problem.free.shape[1]
            )

        return ml

    def eof(problem):
        return problem.points.shape[1]

    return eof


@njit(**JIT)
def residual_length(problem: tuple) -> int:
    """Length m of the residual vector of a problem: n for the paper's EOF, the contacts' rows,
    the priors and the free-space points for the ML residuals
    (:func:`~hapticsim.fitting._ml_compiled.ml_residual_count`)."""
    return _length(problem)


def _posed(problem, a, eps, taper, rot, center, out, tally):  # pragma: no cover
    raise NotImplementedError


@overload(_posed, jit_options=JIT)
def _posed_model(problem, a, eps, taper, rot, center, out, tally):
    if _is_ml(problem):

        def ml(problem, a, eps, taper, rot, center, out, tally):
            ml_residuals_posed(
                problem.points, problem.normals, problem.with_normals, a, eps, taper, rot,
                center, problem.settings, problem.free, out, tally,
            )  # fmt: skip

        return ml

    def eof(problem, a, eps, taper, rot, center, out, tally):
        residuals_posed(
            problem.points, problem.normals, problem.with_normals, a, eps, taper, rot, center,
            problem.lam, problem.tapered, out, tally,
        )  # fmt: skip

    return eof


@njit(**JIT)
def problem_residuals_posed(
    problem: tuple, a: np.ndarray, eps: np.ndarray, taper: np.ndarray, rot: np.ndarray,
    center: np.ndarray, out: np.ndarray, tally: np.ndarray,
) -> None:  # fmt: skip
    """Residuals (P, m) of P posed bodies into `out` (see :func:`residual_length`)."""
    _posed(problem, a, eps, taper, rot, center, out, tally)


def _vectors(problem, vectors, out, tally):  # pragma: no cover
    raise NotImplementedError


@overload(_vectors, jit_options=JIT)
def _vectors_model(problem, vectors, out, tally):
    if _is_ml(problem):

        def ml(problem, vectors, out, tally):
            ml_residuals_vectors(
                problem.points, problem.normals, problem.with_normals, vectors,
                problem.settings, problem.free, out, tally,
            )  # fmt: skip

        return ml

    def eof(problem, vectors, out, tally):
        residuals_vectors(
            problem.points, problem.normals, problem.with_normals, vectors, problem.lam,
            problem.tapered, out, tally,
        )  # fmt: skip

    return eof


@njit(**JIT)
def problem_residuals(
    problem: tuple, vectors: np.ndarray, out: np.ndarray, tally: np.ndarray
) -> None:
    """Residuals (P, m) of P parameter vectors (P, 13) into `out`."""
    _vectors(problem, vectors, out, tally)


def _jacobian(problem, x, r_out, jac_t, tally):  # pragma: no cover
    raise NotImplementedError


@overload(_jacobian, jit_options=JIT)
def _jacobian_model(problem, x, r_out, jac_t, tally):
    if _is_ml(problem):

        def ml(problem, x, r_out, jac_t, tally):
            ml_jacobian_vector(
                problem.points, problem.normals, problem.with_normals, x, problem.settings,
                problem.free, r_out, jac_t, tally,
            )  # fmt: skip

        return ml

    def eof(problem, x, r_out, jac_t, tally):
        jacobian_vector(
            problem.points, problem.normals, problem.with_normals, x, problem.lam,
            problem.tapered, r_out, jac_t, tally,
        )  # fmt: skip

    return eof


@njit(**JIT)
def problem_jacobian(
    problem: tuple, x: np.ndarray, r_out: np.ndarray, jac_t: np.ndarray, tally: np.ndarray
) -> None:
    """Residuals (m,) and transposed Jacobian (13, m) of one vector (counts 13 evaluations)."""
    _jacobian(problem, x, r_out, jac_t, tally)
