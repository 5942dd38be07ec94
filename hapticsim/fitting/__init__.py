"""Superquadric fitting: the error of fit as an objective, least squares, the genetic algorithm,
the hybrid, and the driver :func:`fit` (SPEC §2-3, paper II-B, II-C, IV).

One algorithm per module, like ``scipy.optimize._lsq``:

- :mod:`~hapticsim.fitting.objective`: EOF on raw parameter vectors, counting and budget;
- :mod:`~hapticsim.fitting.initial`: the paper's initial estimate and normal-derived seeds;
- :mod:`~hapticsim.fitting.least_squares`: LS and nLS, and every local stage of H and nH
  (bounded Levenberg-Marquardt, compiled: :mod:`~hapticsim.fitting._lm_compiled`);
- :mod:`~hapticsim.fitting.genetic`: the genetic algorithm (compiled:
  :mod:`~hapticsim.fitting._ga_compiled`);
- :mod:`~hapticsim.fitting.hybrid`: H and nH (genetic algorithm, then least squares);
- :mod:`~hapticsim.fitting.likelihood`, :mod:`~hapticsim.fitting.ml`: nML, a maximum-likelihood
  fit for noisy data beyond the paper (compiled residuals in
  :mod:`~hapticsim.fitting._ml_compiled`);
- :mod:`~hapticsim.fitting.problem`: the residual vector the compiled solvers minimise, the
  paper's EOF or nML's (dispatch in :mod:`~hapticsim.fitting._problem_compiled`);
- :mod:`~hapticsim.fitting.methods`: method names and the default budget;
- :mod:`~hapticsim.fitting.result`: :class:`FitResult` (and multi's :class:`PartSelection`).
"""

from hapticsim.fitting.driver import fit
from hapticsim.fitting.methods import DEFAULT_BUDGET, FIT_METHODS, METHODS
from hapticsim.fitting.ml import MLOptions
from hapticsim.fitting.result import FitResult, PartSelection

__all__ = [
    "DEFAULT_BUDGET", "FIT_METHODS", "METHODS", "FitResult", "MLOptions", "PartSelection", "fit",
]
