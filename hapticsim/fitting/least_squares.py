"""Nonlinear least squares on the EOF residuals (LS, nLS; every local stage of H, nH).

A bounded Levenberg-Marquardt method (SPEC §3: "Levenberg-Marquardt family") that runs entirely
in compiled code (:mod:`hapticsim.fitting._lm_compiled`): no Python call per evaluation, an
analytic Jacobian, and the bounds a > 0, eps in [0.1, 2], taper in [-1, 1] and the centre box
handled by projection. :func:`least_squares_run` minimises ``sum(r_i^2) = n * EOF`` from one
start; :func:`multi_start_run` takes a few steps from many starts at once (the hybrid's seed
steps and probes).

Budgets (SPEC §3): each residual evaluation counts one, each Jacobian 13 (what forward
differences over the 13 parameters would cost), all through the
:class:`~hapticsim.fitting.objective.Objective`, which keeps the best vector seen.

It replaced ``scipy.optimize.least_squares`` ("dogbox"), whose Python callbacks cost about
0.8 ms per evaluation; over the paper's bodies it reaches the same fits (measured in
``scripts/fit_table.py`` and the regression tests).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.fitting import _lm_compiled as lm
from hapticsim.fitting.objective import Objective
from hapticsim.geometry.superquadric import N_PARAMS

Array = NDArray[np.float64]

#: Evaluations one Levenberg-Marquardt step costs when accepted: a residual and a Jacobian.
STEP_EVALUATIONS: int = N_PARAMS + 1
#: Fewest evaluations worth starting a run with (initial residual + two Jacobians and steps).
MIN_RUN_EVALUATIONS: int = 2 * STEP_EVALUATIONS + 1
#: Convergence tolerances (on the cost, the step and the gradient; as scipy's least_squares).
TOLERANCES: dict[str, float] = {"ftol": 1e-8, "xtol": 1e-8, "gtol": 1e-8}
#: Most steps of one run: the budget or the tolerances stop it long before.
MAX_ITERATIONS: int = 100_000

_STATUS = {lm.STATUS_CONVERGED: "converged", lm.STATUS_BUDGET: "budget",
           lm.STATUS_ITERATIONS: "iterations"}  # fmt: skip


@dataclass(frozen=True)
class LeastSquaresRun:
    """Outcome of one least-squares run.

    Attributes:
        x: (13,) float, the final iterate (the objective keeps the best vector overall).
        eof: EOF at ``x`` [m^2].
        evaluations: evaluations this run used.
        status: ``"converged"``, ``"budget"`` or ``"iterations"``.
        message: why the run stopped.
    """

    x: Array
    eof: float
    evaluations: int
    status: str
    message: str


_MESSAGES = {
    "converged": "tolerances met",
    "budget": "evaluation budget exhausted",
    "iterations": "step limit reached",
}


def _args(objective: Objective) -> tuple:
    return (objective.problem,)


def _bounds(objective: Objective) -> tuple[Array, Array, Array]:
    b = objective.bounds
    return b.lower, b.upper, b.scale


def least_squares_run(
    objective: Objective, x0: Array, max_evaluations: int | None = None
) -> LeastSquaresRun:
    """Minimise the EOF from `x0` by bounded Levenberg-Marquardt within a budget.

    Args:
        objective: the EOF with its budget; all evaluations are counted there.
        x0: (13,) float start vector (clipped into the bounds).
        max_evaluations: the most evaluations for this run (default: all that remain).

    Returns:
        The :class:`LeastSquaresRun`; ``objective.best_vector`` is the best vector of all runs.
    """
    available = objective.remaining if max_evaluations is None else max_evaluations
    cap = int(min(available, objective.remaining))
    x = np.empty(N_PARAMS)
    start = np.ascontiguousarray(x0, dtype=np.float64)
    cost, used, code, _ = lm.lm_run(
        *_args(objective), start, *_bounds(objective), cap, MAX_ITERATIONS,
        TOLERANCES["ftol"], TOLERANCES["xtol"], TOLERANCES["gtol"], x, objective.contacts.tally,
    )  # fmt: skip
    eof = cost / objective.count
    objective.record(used, x[None], np.array([eof]))
    status = _STATUS[code]
    return LeastSquaresRun(
        x=x, eof=float(eof), evaluations=int(used), status=status, message=_MESSAGES[status]
    )


def multi_start_run(objective: Objective, starts: Array, steps: int) -> tuple[Array, Array]:
    """Up to `steps` Levenberg-Marquardt steps from every row of `starts`, within the budget.

    Each start gets ``1 + steps * 14`` evaluations (its residual, then a residual and a Jacobian
    per step) when the budget allows all starts that many, else an equal share of what is left;
    a start stops earlier when it converges.

    Args:
        objective: the EOF and its budget.
        starts: (P, 13) float start vectors (clipped into the bounds).
        steps: the most steps per start, >= 0.

    Returns:
        ``(vectors (P, 13), eof (P,))`` after the steps [m^2]; starts the budget cannot even
        evaluate come back unchanged with an EOF of inf.
    """
    x0 = np.ascontiguousarray(np.atleast_2d(starts), dtype=np.float64)
    count = x0.shape[0]
    each = min(1 + steps * STEP_EVALUATIONS, objective.remaining // max(count, 1))
    x = np.empty_like(x0)
    cost = np.empty(count)
    used = lm.lm_multi(
        *_args(objective), x0, *_bounds(objective), int(each), int(steps),
        TOLERANCES["ftol"], TOLERANCES["xtol"], TOLERANCES["gtol"], x, cost,
        objective.contacts.tally,
    )  # fmt: skip
    eof = cost / objective.count
    objective.record(used, x, eof)
    return x, eof
