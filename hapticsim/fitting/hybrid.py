"""The hybrid minimiser of H and nH: genetic algorithm, then least squares (paper II-C).

Budget split, in order:

0. *seed steps*: every seed (:func:`~hapticsim.fitting.initial.seed_vectors`) takes
   :attr:`HybridOptions.seed_steps` Levenberg-Marquardt steps
   (:func:`~hapticsim.fitting.least_squares.multi_start_run`, up to 14 evaluations per seed and
   step): a seed's EOF says little about its basin (a box seed with the right axes but no taper
   can score worse than a wrong one), three steps say much more;

then one or more *rounds*, each with what is left of the budget:

1. *genetic algorithm*: :attr:`HybridOptions.ga_fraction` of what is left (it stops earlier when
   it stalls), seeded with the stepped seeds;
2. *probe*: :attr:`HybridOptions.probe_steps` Levenberg-Marquardt steps from up to
   :attr:`HybridOptions.polish` individuals of the last generation, best first, that are
   different solids (:func:`~hapticsim.fitting.genetic.solid_distance` > 1), as many as the
   budget pays for: the crowding GA keeps niches around several local minima, and on sparse
   data the GA's best is often not in the deepest basin, while a few least-squares steps tell
   the basins apart;
3. *polish*: least squares (:func:`~hapticsim.fitting.least_squares.least_squares_run`) from
   the probe that reached the lowest EOF, until it converges or the budget is gone;

and when a round ends with at least :attr:`HybridOptions.restart_fraction` of the budget unused
(its polish converged), another round starts from the same stepped seeds with a fresh random
stream, up to :attr:`HybridOptions.restarts` times. The result is the lowest EOF seen
(``objective.best_vector``).

The probes decide most of the robustness. Measured on the hardest 6 of 240 random tapered cases
(12 seeds each, ``scripts/global_minimum.py``'s criterion: the EOF within 2 % of the lowest that
eight four-times-longer runs find), the share of fits that missed the lowest EOF was 31 % with 4
probes of 8 steps, 7 % with 16 probes, 4 % with 16 probes of 12 steps; more steps were no
better. An earlier ablation on the paper's bodies (budget 6000, 20 fits per cell) found that the
GA buys the least per evaluation (mean epsilon 0.150 -> 0.142 at sigma_N = 0.1, no change at
0.02), while the seed steps decide the basin at low noise (0.055 -> 0.026 at sigma_N = 0.02).

**The defaults (GA share 0.05, 32 probes; issue 37 item 3).** Budgets count evaluations, but
time is what a fit costs, and the two parts differ: since the EOF Jacobian runs vectorised
(:mod:`hapticsim.geometry.eof_compiled`), an evaluation counted by least squares costs about
1.5 microseconds on 150 contacts (a Jacobian counts 13 and costs under two), one of the genetic
algorithm about 8 (the residuals, the offspring, the crowding). The GA share was 0.4 with 16
probes; moving the budget to probes (one round of seed steps, a GA of a few generations, up to
32 probes, the polish, all in the default 7500) was chosen on nML's ``v3`` contact sets (312
cases, ``scripts/nml_heldout.py``): mean epsilon 0.178 -> 0.175 at 0.61 of the time. On sets not
used to choose it: nML's ``guard`` (360 cases) 0.142 -> 0.138 and ``final`` (160) 0.196 ->
0.185, both at 0.6 of the time, ``scripts/fit_peers.py``'s 128 sets 0.0516 -> 0.0487, and
``scripts/global_minimum.py`` on 360 cases (seeds 1000-1059 and 7000-7029) within 2 % of the
lowest EOF in all, as before, at 0.56-0.62 of the time (``docs/fast-loop/global_minimum_split``).
Per noise level a few cells got worse by up to 0.0065.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError
from hapticsim.fitting import _ga_compiled as _ga
from hapticsim.fitting.genetic import GeneticOptions, GeneticRun, genetic_search
from hapticsim.fitting.least_squares import (
    MIN_RUN_EVALUATIONS,
    STEP_EVALUATIONS,
    least_squares_run,
    multi_start_run,
)
from hapticsim.fitting.objective import Objective
from hapticsim.geometry.rotations import rotvec_to_matrix
from hapticsim.geometry.superquadric import SLICE_ROTVEC

Array = NDArray[np.float64]


@dataclass(frozen=True)
class HybridOptions:
    """Settings of :func:`hybrid_search`.

    Attributes:
        ga_fraction: share of the budget for the genetic algorithm, in (0, 1].
        polish: most distinct GA individuals probed by least squares, >= 1.
        probe_steps: Levenberg-Marquardt steps of the probe (all starts at once), >= 1.
        seed_steps: Levenberg-Marquardt steps on all seeds before the genetic algorithm
            (:func:`~hapticsim.fitting.least_squares.multi_start_run`), >= 0.
        restarts: most further rounds (genetic algorithm, probe, polish) from the stepped seeds
            with a fresh random stream, while the budget allows, >= 0.
        restart_fraction: a restart needs at least this share of the whole budget left, in
            (0, 1].
        genetic: settings of the genetic algorithm.
    """

    ga_fraction: float = 0.05
    polish: int = 32
    probe_steps: int = 12
    seed_steps: int = 3
    restarts: int = 3
    restart_fraction: float = 0.2
    genetic: GeneticOptions = field(default_factory=GeneticOptions)

    def __post_init__(self) -> None:
        if not 0.0 < self.ga_fraction <= 1.0:
            raise InvalidInputError(f"`ga_fraction` must lie in (0, 1], got {self.ga_fraction}")
        if self.polish < 1:
            raise InvalidInputError(f"`polish` must be >= 1, got {self.polish}")
        if self.probe_steps < 1 or self.seed_steps < 0:
            raise InvalidInputError(
                f"`probe_steps` must be >= 1 and `seed_steps` >= 0, got {self.probe_steps} and "
                f"{self.seed_steps}"
            )
        if self.restarts < 0 or not 0.0 < self.restart_fraction <= 1.0:
            raise InvalidInputError(
                f"`restarts` must be >= 0 and `restart_fraction` in (0, 1], got {self.restarts} "
                f"and {self.restart_fraction}"
            )


def distinct_starts(run: GeneticRun, count: int, size: float) -> list[Array]:
    """Up to `count` individuals of the last generation, best first, pairwise different solids
    (:func:`~hapticsim.fitting.genetic.solid_distance` > 1)."""
    if count < 1:
        return []
    genes = np.ascontiguousarray(run.population, dtype=np.float64)
    rot = rotvec_to_matrix(genes[:, SLICE_ROTVEC])
    chosen = np.empty(count, np.int64)
    kept = _ga.distinct_rows(genes, rot, int(count), float(size), chosen)
    return [run.population[i] for i in chosen[:kept]]


def hybrid_search(
    objective: Objective,
    seeds: Array,
    rng: np.random.Generator,
    options: HybridOptions | None = None,
) -> tuple[GeneticRun, str]:
    """Genetic algorithm then least squares (probe, polish), within the objective's budget.

    Args:
        objective: the EOF and its budget; ``objective.best_vector`` holds the result.
        seeds: (k, 13) start vectors of the genetic algorithm.
        rng: the generator of every random choice.
        options: settings (default :class:`HybridOptions`).

    Returns:
        The genetic run and a status: ``"converged"`` when the final least-squares run
        converged, ``"budget"`` when it ran out of evaluations, or the genetic algorithm's
        status when nothing was left for least squares.
    """
    opt = HybridOptions() if options is None else options
    if opt.seed_steps and objective.remaining >= len(seeds) * (1 + STEP_EVALUATIONS):
        seeds, _ = multi_start_run(objective, seeds, opt.seed_steps)
    run, status = _round(objective, seeds, rng, opt)
    floor = max(opt.restart_fraction * objective.budget, 2 * MIN_RUN_EVALUATIONS)
    for _ in range(opt.restarts):
        if objective.remaining < floor:
            break
        _, status = _round(objective, seeds, rng, opt)
    return run, status


def _round(
    objective: Objective, seeds: Array, rng: np.random.Generator, opt: HybridOptions
) -> tuple[GeneticRun, str]:
    """One round with what is left of the budget: the genetic algorithm from `seeds`, probes
    from the distinct individuals of its last generation, the polish from the best probe."""
    ga_budget = max(1, int(opt.ga_fraction * objective.remaining))
    if objective.remaining - ga_budget < MIN_RUN_EVALUATIONS:
        ga_budget = objective.remaining
    run = genetic_search(objective, seeds, rng, ga_budget, opt.genetic)
    starts = np.array(distinct_starts(run, opt.polish, objective.bounds.size))
    if objective.remaining < MIN_RUN_EVALUATIONS or not len(starts):
        return run, run.status
    # As many probes (best first) as the budget pays for, keeping enough for the polish.
    each = 1 + opt.probe_steps * STEP_EVALUATIONS
    affordable = (objective.remaining - MIN_RUN_EVALUATIONS) // each
    starts = starts[: max(affordable, 1)]
    if len(starts) > 1:
        starts, eof = multi_start_run(objective, starts, opt.probe_steps)
        starts = starts[np.argsort(eof, kind="stable")]
    return run, least_squares_run(objective, starts[0]).status
