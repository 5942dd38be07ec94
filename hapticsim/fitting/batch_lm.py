"""Levenberg-Marquardt steps for a whole population at once (local search of the hybrid).

scipy's least squares improves one vector at a time; each of its iterations costs a single
evaluation plus a 13-vector Jacobian, dominated by Python overhead. Here P vectors take their
steps together: one population call evaluates the 13 P perturbed vectors of all forward-difference
Jacobians (13 P evaluations), P small damped normal equations
``(J^T J + mu diag(J^T J)) d = -J^T r`` are solved as one batch, and one more population call
evaluates the P trial vectors (P evaluations). A step is kept where it lowers the EOF (then the
damping mu shrinks), else mu grows, individually. Trial vectors are clipped into the bounds.

The hybrid uses it to refine all seeds a few steps before the genetic algorithm: a seed's EOF
says little about the basin it lies in (a box seed with the right axes but no taper can score
worse than a wrong one), a few steps say much more, and at P ~ 50 they run at the full
throughput of the vectorised EOF.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.fitting.least_squares import FD_STEP
from hapticsim.fitting.objective import Objective
from hapticsim.geometry.superquadric import N_PARAMS

Array = NDArray[np.float64]

#: Initial damping of each individual.
INITIAL_DAMPING: float = 1e-3


def evaluations_per_step(count: int) -> int:
    """Evaluations of one step for `count` vectors: 13 per Jacobian and one trial each."""
    return (N_PARAMS + 1) * count


def batch_levenberg_marquardt(
    objective: Objective, vectors: Array, steps: int
) -> tuple[Array, Array]:
    """Up to `steps` Levenberg-Marquardt steps on every row of `vectors`, within the budget.

    Args:
        objective: the EOF and its budget.
        vectors: (P, 13) float start vectors (clipped into the bounds).
        steps: the most steps; fewer when the budget runs short (a step is all-or-nothing).

    Returns:
        ``(vectors (P, 13), eof (P,))`` after the steps; the EOF of each row [m^2]. When not even
        the start vectors fit in the budget, they come back with an EOF of inf.
    """
    bounds = objective.bounds
    x = bounds.clip(np.atleast_2d(np.asarray(vectors, dtype=np.float64)))
    count = x.shape[0]
    if count > objective.remaining:
        return x, np.full(count, np.inf)
    r = objective.residuals(x)
    cost = np.einsum("ij,ij->i", r, r)
    mu = np.full(count, INITIAL_DAMPING)
    step = FD_STEP * bounds.scale
    rows = np.arange(N_PARAMS)
    for _ in range(steps):
        if objective.remaining < evaluations_per_step(count):
            break
        h = np.where(x + step > bounds.upper, -step, step)  # (P, 13)
        perturbed = np.repeat(x[:, None, :], N_PARAMS, axis=1)
        perturbed[:, rows, rows] += h
        rp = objective.residuals(perturbed.reshape(-1, N_PARAMS)).reshape(count, N_PARAMS, -1)
        jt = (rp - r[:, None, :]) / h[:, :, None]  # J^T, (P, 13, n)
        jtj = jt @ np.swapaxes(jt, 1, 2)
        grad = np.einsum("pkn,pn->pk", jt, r)
        diag = np.diagonal(jtj, axis1=1, axis2=2)
        damped = jtj + (mu[:, None] * (diag + 1e-30))[:, :, None] * np.eye(N_PARAMS)
        try:
            delta = np.linalg.solve(damped, -grad[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:  # a singular system: leave every vector where it is
            break
        trial = bounds.clip(x + delta)
        rt = objective.residuals(trial)
        trial_cost = np.einsum("ij,ij->i", rt, rt)
        better = trial_cost < cost
        x[better], r[better], cost[better] = trial[better], rt[better], trial_cost[better]
        mu = np.where(better, mu / 3.0, mu * 4.0)
    return x, cost / objective.count
