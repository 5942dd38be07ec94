"""Compiled bounded Levenberg-Marquardt on a residual vector (numba), with evaluation counting.

One implementation serves every least-squares stage of the fitter: LS and nLS, the polish of
H and nH, and the multi-start steps of the hybrid (seed steps, probes), which run
:func:`lm_multi` over many starts, and nML's stages, on whichever residual vector the *problem*
holds (the paper's EOF residuals or the maximum-likelihood ones, see
:class:`hapticsim.fitting.problem.Problem`). The whole loop runs in compiled code:
no Python call per evaluation.

The method (Marquardt's scaled damping with Nielsen's update of the damping):

- variables are scaled by ``scale`` (the typical magnitude of each parameter: the data size for
  a and the centre, 1 for eps, taper and the rotation vector), ``z = x / scale``;
- a step solves ``(A + mu diag(A)) dz = -g`` with ``A = J^T J`` and ``g = J^T r`` (Cholesky,
  13 x 13), for the *free* variables only: one at a bound whose gradient pushes it out stays
  there (projected Gauss-Newton); the trial point is clipped into the box;
- the gain ratio ``rho = actual / predicted reduction`` decides: ``rho > 0`` accepts the step and
  shrinks mu by ``max(1/3, 1 - (2 rho - 1)^3)``, else mu grows by nu (doubling each time);
- it stops on a relative cost change below ``ftol`` after an accepted step, a step below
  ``xtol (xtol + |z|)``, a scaled gradient below ``gtol`` (the tolerances of scipy's
  ``least_squares``), at ``max_iterations`` steps, or when the budget cannot pay for the next
  evaluation.

Counting (SPEC §3): the residual at a point is one evaluation, a Jacobian 13 (analytic here,
but counted as forward differences would be), so an accepted step costs 14 and a rejected one 1.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hapticsim.fitting._problem_compiled import (
    problem_jacobian,
    problem_residuals,
    residual_length,
)
from hapticsim.geometry.eof_compiled import JIT
from hapticsim.geometry.layout import N_PARAMS

#: Evaluations a Jacobian counts for (forward differences over 13 parameters, SPEC §3).
JACOBIAN_EVALUATIONS = N_PARAMS
#: Status codes of :func:`lm_run`.
STATUS_CONVERGED, STATUS_BUDGET, STATUS_ITERATIONS = 0, 1, 2
#: Initial damping relative to the largest diagonal entry of J^T J.
_TAU = 1e-3
#: The damping (relative to the diagonal) beyond which the run counts as stuck (converged).
_MU_MAX = 1e16


@njit(**JIT)
def _cholesky_solve(a: np.ndarray, b: np.ndarray, free: np.ndarray, out: np.ndarray) -> bool:
    """Solve ``a[free][:, free] x = b[free]`` by Cholesky into `out` (0 where not free).

    Returns False when the matrix is not positive definite.
    """
    idx = np.nonzero(free)[0]
    m = idx.shape[0]
    low = np.zeros((m, m))
    for i in range(m):
        for j in range(i + 1):
            s = a[idx[i], idx[j]]
            for k in range(j):
                s -= low[i, k] * low[j, k]
            if i == j:
                if not s > 0.0:
                    return False
                low[i, i] = math.sqrt(s)
            else:
                low[i, j] = s / low[j, j]
    y = np.zeros(m)
    for i in range(m):
        s = b[idx[i]]
        for k in range(i):
            s -= low[i, k] * y[k]
        y[i] = s / low[i, i]
    for i in range(N_PARAMS):
        out[i] = 0.0
    for i in range(m - 1, -1, -1):
        s = y[i]
        for k in range(i + 1, m):
            s -= low[k, i] * out[idx[k]]
        out[idx[i]] = s / low[i, i]
    return True


@njit(**JIT)
def _normal_equations(jac_t: np.ndarray, r: np.ndarray, scale: np.ndarray, a: np.ndarray,
                      g: np.ndarray) -> None:  # fmt: skip
    """``A = Jz^T Jz`` (13, 13) and ``g = Jz^T r`` (13,) for the scaled Jacobian Jz = J scale.

    Each entry is summed over the contacts in their order (the same floating-point result as
    one loop per entry); four entries of a row are summed side by side, so that the additions
    of different entries overlap instead of each waiting for the one before (150 contacts,
    called from Python on an AMD Zen 5 core: 5.8 -> 4.1 microseconds).
    """
    n = r.shape[0]
    for k in range(N_PARAMS):
        s = 0.0
        row = jac_t[k]
        for i in range(n):
            s += row[i] * r[i]
        g[k] = s * scale[k]
        m = 0
        while m + 3 <= k:
            o0, o1, o2, o3 = jac_t[m], jac_t[m + 1], jac_t[m + 2], jac_t[m + 3]
            s0 = s1 = s2 = s3 = 0.0
            for i in range(n):
                v = row[i]
                s0 += v * o0[i]
                s1 += v * o1[i]
                s2 += v * o2[i]
                s3 += v * o3[i]
            _put_pair(a, k, m, s0 * (scale[k] * scale[m]))
            _put_pair(a, k, m + 1, s1 * (scale[k] * scale[m + 1]))
            _put_pair(a, k, m + 2, s2 * (scale[k] * scale[m + 2]))
            _put_pair(a, k, m + 3, s3 * (scale[k] * scale[m + 3]))
            m += 4
        for mm in range(m, k + 1):
            other = jac_t[mm]
            s = 0.0
            for i in range(n):
                s += row[i] * other[i]
            _put_pair(a, k, mm, s * (scale[k] * scale[mm]))


@njit(**JIT)
def _put_pair(a: np.ndarray, k: int, m: int, value: float) -> None:
    """``a[k, m] = a[m, k] = value``."""
    a[k, m] = value
    a[m, k] = value


@njit(**JIT)
def lm_run(
    problem: tuple, x0: np.ndarray, lower: np.ndarray, upper: np.ndarray, scale: np.ndarray,
    max_evaluations: int, max_iterations: int, ftol: float, xtol: float, gtol: float,
    x_out: np.ndarray, tally: np.ndarray,
) -> tuple[float, int, int, int]:  # fmt: skip
    """Minimise ``sum(r^2)`` from `x0` (13,) within the box; the best vector into `x_out`.

    Args:
        problem: the residuals, paper EOF or ML (see
            :class:`hapticsim.fitting.problem.Problem`).
        x0: (13,) start, clipped into [lower, upper].
        lower, upper, scale: (13,) box and typical magnitudes.
        max_evaluations: the most evaluations to use (>= 1 for anything to happen).
        max_iterations: the most steps tried (accepted or not).
        ftol, xtol, gtol: convergence tolerances (see the module).
        tally: (1,) int64 evaluation tally of the kernels (see ``residuals_posed``).

    Returns:
        ``(cost, evaluations, status, iterations)``: cost ``sum(r^2)`` at `x_out` (inf when
        not even x0 could be evaluated), evaluations used, one of the ``STATUS_*`` codes and
        the steps tried.
    """
    n = residual_length(problem)
    x = np.empty(N_PARAMS)
    for k in range(N_PARAMS):
        x[k] = min(max(x0[k], lower[k]), upper[k])
        x_out[k] = x[k]
    if max_evaluations < 1:
        return math.inf, 0, STATUS_BUDGET, 0
    r = np.empty((1, n))
    problem_residuals(problem, x.reshape(1, N_PARAMS), r, tally)
    used = 1
    cost = 0.0
    for i in range(n):
        cost += r[0, i] * r[0, i]
    if used + JACOBIAN_EVALUATIONS > max_evaluations:
        return cost, used, STATUS_BUDGET, 0
    jac_t = np.empty((N_PARAMS, n))
    rv = np.empty(n)
    problem_jacobian(problem, x, rv, jac_t, tally)
    used += JACOBIAN_EVALUATIONS
    a = np.empty((N_PARAMS, N_PARAMS))
    g = np.empty(N_PARAMS)
    _normal_equations(jac_t, rv, scale, a, g)
    dmax = 0.0
    for k in range(N_PARAMS):
        dmax = max(dmax, a[k, k])
    mu = _TAU * max(dmax, 1e-300)
    nu = 2.0
    damped = np.empty((N_PARAMS, N_PARAMS))
    dz = np.empty(N_PARAMS)
    rhs = np.empty(N_PARAMS)
    free = np.empty(N_PARAMS, np.bool_)
    trial = np.empty((1, N_PARAMS))
    rt = np.empty((1, n))
    status = STATUS_ITERATIONS
    it = 0
    while it < max_iterations:
        # Converged by the gradient?
        gmax = 0.0
        for k in range(N_PARAMS):
            at_low = x[k] <= lower[k] and g[k] > 0.0
            at_high = x[k] >= upper[k] and g[k] < 0.0
            free[k] = not (at_low or at_high)
            if free[k]:
                gmax = max(gmax, abs(g[k]))
        if gmax <= gtol * max(cost, 1e-300) or not np.any(free):
            status = STATUS_CONVERGED
            break
        if used + 1 > max_evaluations:
            status = STATUS_BUDGET
            break
        it += 1
        for k in range(N_PARAMS):
            for m in range(N_PARAMS):
                damped[k, m] = a[k, m]
            damped[k, k] += mu * max(a[k, k], 1e-12 * dmax + 1e-300)
            rhs[k] = -g[k]
        if not _cholesky_solve(damped, rhs, free, dz):
            mu *= nu
            nu *= 2.0
            if mu > _MU_MAX * max(dmax, 1e-300):
                status = STATUS_CONVERGED
                break
            continue
        znorm = 0.0
        dnorm = 0.0
        for k in range(N_PARAMS):
            step = dz[k] * scale[k]
            value = min(max(x[k] + step, lower[k]), upper[k])
            dz[k] = (value - x[k]) / scale[k]  # the step actually taken (after clipping)
            trial[0, k] = value
            znorm += (x[k] / scale[k]) ** 2
            dnorm += dz[k] * dz[k]
        znorm, dnorm = math.sqrt(znorm), math.sqrt(dnorm)
        if dnorm <= xtol * (xtol + znorm):
            status = STATUS_CONVERGED
            break
        problem_residuals(problem, trial, rt, tally)
        used += 1
        trial_cost = 0.0
        for i in range(n):
            trial_cost += rt[0, i] * rt[0, i]
        # predicted reduction of the linear model: -(2 g.dz + dz.A dz)
        pred = 0.0
        for k in range(N_PARAMS):
            s = 0.0
            for m in range(N_PARAMS):
                s += a[k, m] * dz[m]
            pred -= 2.0 * g[k] * dz[k] + dz[k] * s
        actual = cost - trial_cost
        rho = actual / pred if pred > 0.0 else -1.0
        if actual > 0.0 and rho > 0.0:
            for k in range(N_PARAMS):
                x[k] = trial[0, k]
                x_out[k] = x[k]
            old = cost
            cost = trial_cost
            mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            nu = 2.0
            if actual <= ftol * old:
                status = STATUS_CONVERGED
                break
            if used + JACOBIAN_EVALUATIONS > max_evaluations:
                status = STATUS_BUDGET
                break
            problem_jacobian(problem, x, rv, jac_t, tally)
            used += JACOBIAN_EVALUATIONS
            _normal_equations(jac_t, rv, scale, a, g)
            for k in range(N_PARAMS):
                dmax = max(dmax, a[k, k])
        else:
            mu *= nu
            nu *= 2.0
            if mu > _MU_MAX * max(dmax, 1e-300):
                status = STATUS_CONVERGED
                break
    return cost, used, status, it


@njit(**JIT)
def lm_multi(
    problem: tuple, starts: np.ndarray, lower: np.ndarray, upper: np.ndarray, scale: np.ndarray,
    evaluations_each: int, max_iterations: int, ftol: float, xtol: float, gtol: float,
    x_out: np.ndarray, cost_out: np.ndarray, tally: np.ndarray,
) -> int:  # fmt: skip
    """:func:`lm_run` from each row of `starts` (P, 13) with `evaluations_each` evaluations.

    Results into `x_out` (P, 13) and `cost_out` (P,); returns the evaluations used in all.
    """
    total = 0
    for p in range(starts.shape[0]):
        cost, used, _, _ = lm_run(
            problem, starts[p], lower, upper, scale,
            evaluations_each, max_iterations, ftol, xtol, gtol, x_out[p], tally,
        )  # fmt: skip
        cost_out[p] = cost
        total += used
    return total
