"""The genetic algorithm of the hybrid methods (paper II-C).

Chromosome: the 13 parameters (a, eps, taper, rotation, centre). The rotation is carried as a
matrix during the search (composition, blending and the symmetries are matrix products; a rotation
vector, additive near 0, wraps at pi) and returned as a rotation vector. A population evolves
generation by generation:

- **fitness**: the EOF (eq. 9), lower is fitter; the whole generation is one population call;
- **selection**: tournaments of :attr:`GeneticOptions.tournament` individuals (the fittest wins);
- **crossover**: the second parent is first rewritten, among its 8 equivalent parameter sets
  (quarter and half turns about the body z axis, half turns about x and y, with a, taper
  permuted and flipped to match: the same solid), into the one whose axes are closest to the
  first parent's, so that genes are blended only between like axes. Then a, eps, taper and
  centre are blended gene by gene with weights drawn from [-0.25, 1.25] (BLX-0.25, so children may
  leave the parents' segment; a geometrically), and the rotation matrices linearly with a weight
  from the same range and re-orthonormalised (after the alignment the parents' axes are close, so
  this stays near the geodesic between them);
- **mutation**: log-normal on a, Gaussian on eps, taper and centre, a rotation about a random axis
  by a Gaussian angle; the sizes shrink linearly to a quarter as the budget is used up;
- **jumps**: with a small probability a quarter turn about body x or y (a and the axis carrying
  eps1 change place), so that the search can rotate far from where it started: the same solid has
  several parameter sets, but the z axis of a cylinder or a tapered box is not among them;
- **replacement with elitism**: by default *restricted tournament replacement* (crowding): each
  child meets :attr:`GeneticOptions.window` random individuals and replaces the most similar of
  them (:func:`solid_distance`) if it is fitter. Niches around different local minima (say, a box
  standing on either of two faces) survive side by side until the least-squares stage can tell
  them apart, instead of the population collapsing on the first basin found; and an individual
  only ever gives way to a fitter one, so the best is never lost (elitism). The classic
  generational scheme (the :attr:`GeneticOptions.elite` best pass unchanged, the children
  replace the rest) is available as ``replacement="generational"``;
- **abort**: budget, generation count, a target EOF, or a stall of the best EOF.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.fitting import _ga_compiled as _ga
from hapticsim.fitting.objective import Objective
from hapticsim.geometry.rotations import matrix_to_rotvec, rotvec_to_matrix
from hapticsim.geometry.superquadric import (
    N_PARAMS,
    SLICE_ROTVEC,
)

Array = NDArray[np.float64]

#: Replacement schemes of :class:`GeneticOptions`.
REPLACEMENTS: tuple[str, ...] = ("crowding", "generational")


@dataclass(frozen=True)
class GeneticOptions:
    """Settings of :func:`genetic_search`.

    Attributes:
        population: individuals per generation, >= 4.
        replacement: ``"crowding"`` (restricted tournament replacement) or ``"generational"``.
        window: individuals a child is compared with under crowding, in [1, population].
        elite: under generational replacement, the best individuals copied unchanged into the
            next generation, in [1, population).
        tournament: individuals per selection tournament, >= 1.
        crossover_rate: probability that a child is a blend of two parents, in [0, 1].
        mutation_rate: probability that a gene group (a, eps, taper, rotation, centre) of a
            child is mutated, in [0, 1].
        jump_rate: probability of a quarter turn about body x or y, in [0, 1].
        sigma_a: std of log a (relative size change).
        sigma_eps: std of eps.
        sigma_taper: std of the taper.
        sigma_angle: std of the rotation angle [rad].
        sigma_center: std of the centre, in data sizes.
        stall_generations: stop after this many generations without a relative improvement of
            1e-4 in the best EOF, >= 1.
        max_generations: stop after this many generations (None: budget only).
        target_eof: stop once the best EOF is at or below this [m^2].
    """

    population: int = 40
    replacement: str = "crowding"
    window: int = 16
    elite: int = 2
    tournament: int = 3
    crossover_rate: float = 0.7
    mutation_rate: float = 0.4
    jump_rate: float = 0.05
    sigma_a: float = 0.15
    sigma_eps: float = 0.15
    sigma_taper: float = 0.1
    sigma_angle: float = 0.15
    sigma_center: float = 0.05
    stall_generations: int = 30
    max_generations: int | None = None
    target_eof: float = 0.0

    def __post_init__(self) -> None:
        if self.population < 4:
            raise InvalidInputError(f"`population` must be >= 4, got {self.population}")
        if not 1 <= self.elite < self.population:
            raise InvalidInputError(
                f"`elite` must lie in [1, population), got {self.elite} (population "
                f"{self.population})"
            )
        if self.replacement not in REPLACEMENTS:
            raise ChoiceError("replacement", self.replacement, REPLACEMENTS)
        if not 1 <= self.window <= self.population:
            raise InvalidInputError(f"`window` must lie in [1, population], got {self.window}")
        if self.tournament < 1 or self.stall_generations < 1:
            raise InvalidInputError("`tournament` and `stall_generations` must be >= 1")
        for name in ("crossover_rate", "mutation_rate", "jump_rate"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise InvalidInputError(f"`{name}` must lie in [0, 1], got {getattr(self, name)}")


@dataclass(frozen=True)
class GeneticRun:
    """Outcome of :func:`genetic_search`.

    Attributes:
        population: (N, 13) float, the last generation sorted by EOF, best first.
        eof: (N,) float, their EOF [m^2].
        generations: generations evolved after the initial one.
        evaluations: evaluations used.
        status: why it stopped: ``"budget"``, ``"generations"``, ``"target"`` or ``"stall"``.
    """

    population: Array
    eof: Array
    generations: int
    evaluations: int
    status: str


#: The 8 body-frame rotations S that map the tapered superquadric family onto itself (8, 3, 3).
SYMMETRIES = _ga.SYMMETRIES
#: Status names of :class:`GeneticRun`, indexed by the compiled run's status codes.
STATUSES: tuple[str, ...] = ("budget", "generations", "target", "stall")


def align_to(reference: Array, rotations: Array, vectors: Array) -> tuple[Array, Array]:
    """Rewrite solids among their equivalent parameter sets to match reference rotations.

    Args:
        reference: (P, 3, 3) rotations to match.
        rotations: (P, 3, 3) rotations of the solids.
        vectors: (P, 13) their parameter vectors (rotation entries are not read).

    Returns:
        ``(vectors, rotations)`` of the same solids, (P, 13) and (P, 3, 3): for each row, of the 8
        equivalent parameter sets the one whose rotation is closest to the reference (largest
        ``trace(R_ref^T R S)``). The rotation entries of the vectors are left as they were.
    """
    ref = np.ascontiguousarray(reference, dtype=np.float64)
    rot = np.ascontiguousarray(rotations, dtype=np.float64)
    genes = np.ascontiguousarray(vectors, dtype=np.float64)
    out, out_rot = np.empty_like(genes), np.empty_like(rot)
    _ga.align_many(ref, rot, genes, out, out_rot)
    return out, out_rot


def solid_distance(
    genes: Array, rot: Array, other_genes: Array, other_rot: Array, size: float
) -> Array:
    """A dimensionless distance between pairs of solids, after aligning their parameter sets.

    Sum of: rotation angle / 0.5 rad, ``sum |log(a / a')|`` / 0.3, centre distance / (0.2 size),
    ``sum |eps - eps'|`` / 0.5 and ``sum |t - t'|`` / 0.5: about 1 for solids that a least-squares
    run would merge, much more for different basins.

    Args:
        genes, other_genes: (P, 13) parameter vectors (rotation entries not read).
        rot, other_rot: (P, 3, 3) their rotations.
        size: the data size [m].

    Returns:
        (P,) float.
    """
    args = [np.ascontiguousarray(x, dtype=np.float64) for x in (genes, rot, other_genes, other_rot)]
    out = np.empty(args[0].shape[0])
    _ga.solid_distance_many(*args, float(size), out)
    return out


def genetic_search(
    objective: Objective,
    seeds: Array,
    rng: np.random.Generator,
    max_evaluations: int,
    options: GeneticOptions | None = None,
) -> GeneticRun:
    """Evolve a population from seed vectors within an evaluation budget.

    The initial generation holds all seeds (the most promising :attr:`~GeneticOptions.population`
    of them survive) and, when there are fewer seeds than individuals, mutated copies of them.

    Args:
        objective: the EOF and its budget.
        seeds: (k, 13) float start vectors, k >= 1 (first ones are kept if the budget is short).
        rng: the generator of every random choice.
        max_evaluations: the most evaluations for this search.
        options: settings (default :class:`GeneticOptions`).

    Returns:
        The :class:`GeneticRun`.
    """
    opt = GeneticOptions() if options is None else options
    bounds = objective.bounds
    cap = int(min(max_evaluations, objective.remaining))
    genes = np.ascontiguousarray(bounds.clip(np.atleast_2d(np.asarray(seeds, dtype=np.float64))))
    rot = rotvec_to_matrix(genes[:, SLICE_ROTVEC])
    n = opt.population
    children = n if opt.replacement == "crowding" else n - opt.elite
    hist_size = cap // max(children, 1) + 2
    hist_evals, hist_best = np.empty(hist_size, np.int64), np.empty(hist_size)
    out_genes, out_rot, out_eof = np.empty((n, N_PARAMS)), np.empty((n, 3, 3)), np.empty(n)
    settings = np.array(
        [opt.tournament, opt.crossover_rate, opt.mutation_rate, opt.jump_rate, opt.sigma_a,
         opt.sigma_eps, opt.sigma_taper, opt.sigma_angle, opt.sigma_center], dtype=np.float64,
    )  # fmt: skip
    c = objective.contacts
    count, generations, used, status, n_hist = _ga.ga_run(
        objective.problem, genes, rot,
        bounds.lower, bounds.upper, bounds.size, cap, rng, n,
        opt.replacement == "crowding", opt.window, opt.elite, settings, opt.stall_generations,
        -1 if opt.max_generations is None else opt.max_generations, opt.target_eof,
        out_genes, out_rot, out_eof, hist_evals, hist_best, c.tally,
    )  # fmt: skip
    genes, rot, eof = out_genes[:count].copy(), out_rot[:count], out_eof[:count].copy()
    if count:
        genes[:, SLICE_ROTVEC] = matrix_to_rotvec(rot)
    objective.record(used, genes[:1], eof[:1], history=(hist_evals[:n_hist], hist_best[:n_hist]))
    return GeneticRun(
        population=genes,
        eof=eof,
        generations=int(generations),
        evaluations=int(used),
        status=STATUSES[status],
    )
