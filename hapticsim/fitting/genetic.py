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

from hapticsim.errors import InvalidInputError
from hapticsim.fitting.objective import Objective
from hapticsim.geometry.rotations import matrix_to_rotvec, rotvec_to_matrix
from hapticsim.geometry.superquadric import (
    N_PARAMS,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
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
            raise InvalidInputError(
                f"`replacement` must be one of {REPLACEMENTS}, got {self.replacement!r}"
            )
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


# The 8 rotations S of the body frame that map the tapered superquadric family onto itself,
# with the matching change of parameters: R -> R S, a -> a[perm], taper -> sign * taper[perm].
def _symmetries() -> tuple[Array, NDArray[np.int64], NDArray[np.int64], Array]:
    mats, a_perm, t_perm, t_sign = [], [], [], []
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # about z
    half_x = np.diag([1.0, -1.0, -1.0])
    for flip in (False, True):
        for k in range(4):
            s = np.linalg.matrix_power(quarter, k)
            if flip:
                s = s @ half_x
            mats.append(s)
            swap = k % 2 == 1
            a_perm.append([1, 0, 2] if swap else [0, 1, 2])
            t_perm.append([1, 0] if swap else [0, 1])
            t_sign.append(-1.0 if flip else 1.0)
    return (
        np.array(mats),
        np.array(a_perm, dtype=np.int64),
        np.array(t_perm, dtype=np.int64),
        np.array(t_sign),
    )


SYMMETRIES, _SYM_A, _SYM_T, _SYM_SIGN = _symmetries()
# trace(M S) = sum_ik M_ik S_ki: a (9, 8) matrix turns flattened M into all 8 traces.
_SYM_TRACE = np.ascontiguousarray(SYMMETRIES.transpose(0, 2, 1).reshape(8, 9).T)
# Quarter turns about body x and y (not symmetries): R -> R J, a -> a[perm].
_JUMPS = (
    (np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]), np.array([0, 2, 1])),
    (np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]), np.array([2, 1, 0])),
)


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
    rel = np.swapaxes(reference, 1, 2) @ rotations  # R_ref^T R
    score = rel.reshape(-1, 9) @ _SYM_TRACE  # trace(R_ref^T R S) for every S
    best = np.argmax(score, axis=1)
    out = vectors.copy()
    rows = np.arange(len(best))[:, None]
    out[:, SLICE_A] = vectors[:, SLICE_A][rows, _SYM_A[best]]
    out[:, SLICE_TAPER] = vectors[:, SLICE_TAPER][rows, _SYM_T[best]] * _SYM_SIGN[best, None]
    return out, rotations @ SYMMETRIES[best]


def _gram_schmidt(m: Array) -> Array:
    """The rotations (P, 3, 3) nearest in spirit to m: columns 1, 2 orthonormalised, 3 = 1 x 2."""
    u = m[:, :, 0] / np.linalg.norm(m[:, :, 0], axis=1, keepdims=True)
    v = m[:, :, 1] - np.sum(u * m[:, :, 1], axis=1, keepdims=True) * u
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return np.stack([u, v, np.cross(u, v)], axis=2)


def _random_axis_rotations(rng: np.random.Generator, angles: Array) -> Array:
    axes = rng.standard_normal((len(angles), 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    return rotvec_to_matrix(axes * angles[:, None])


def _tournament(rng: np.random.Generator, eof: Array, count: int, size: int) -> NDArray[np.int64]:
    entrants = rng.integers(0, len(eof), size=(count, size))
    return entrants[np.arange(count), np.argmin(eof[entrants], axis=1)]


def _offspring(
    rng: np.random.Generator,
    genes: Array,
    rot: Array,
    eof: Array,
    count: int,
    options: GeneticOptions,
    shrink: float,
    size: float,
) -> tuple[Array, Array]:
    """`count` children (genes (count, 13), rotations (count, 3, 3)) of a population:
    selection, crossover, mutation and jumps."""
    first = _tournament(rng, eof, count, options.tournament)
    second = _tournament(rng, eof, count, options.tournament)
    p1, r1 = genes[first], rot[first]
    p2, r2 = align_to(r1, rot[second], genes[second])

    # Crossover: BLX-0.25 per gene (geometric for a); rotations blended and re-orthonormalised
    # (after alignment the parents' axes are close, so this follows the geodesic closely).
    cross = rng.random(count) < options.crossover_rate
    w = rng.uniform(-0.25, 1.25, size=(count, N_PARAMS))
    w[~cross] = 0.0
    child = p1 + w * (p2 - p1)
    child[:, SLICE_A] = p1[:, SLICE_A] * (p2[:, SLICE_A] / p1[:, SLICE_A]) ** w[:, SLICE_A]
    rotation = _gram_schmidt(r1 + w[:, 7, None, None] * (r2 - r1))
    rotation[~cross] = r1[~cross]

    # Mutation, group by group, sizes shrinking with the budget used.
    groups = rng.random((count, 5)) < options.mutation_rate
    noise = rng.standard_normal((count, 10))
    child[:, SLICE_A] *= np.exp(groups[:, 0:1] * (shrink * options.sigma_a) * noise[:, 0:3])
    child[:, SLICE_EPS] += groups[:, 1:2] * (shrink * options.sigma_eps) * noise[:, 3:5]
    child[:, SLICE_TAPER] += groups[:, 2:3] * (shrink * options.sigma_taper) * noise[:, 5:7]
    child[:, SLICE_CENTER] += (
        groups[:, 4:5] * (shrink * options.sigma_center * size) * noise[:, 7:10]
    )
    turn = groups[:, 3]
    angles = (shrink * options.sigma_angle) * rng.standard_normal(int(turn.sum()))
    rotation[turn] = _random_axis_rotations(rng, angles) @ rotation[turn]

    # Jumps: a quarter turn about body x or y, a permuted to keep the extents in place.
    jump = rng.random(count) < options.jump_rate
    which = rng.integers(0, 2, size=count)
    for k, (quarter, perm) in enumerate(_JUMPS):
        sel = jump & (which == k)
        rotation[sel] = rotation[sel] @ quarter
        child[sel, SLICE_A] = child[sel][:, perm]
        child[sel, SLICE_TAPER] = 0.0
    return child, rotation


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
    aligned, aligned_rot = align_to(other_rot, rot, genes)
    cos = (np.sum(other_rot * aligned_rot, axis=(1, 2)) - 1.0) / 2.0
    angle = np.arccos(np.clip(cos, -1.0, 1.0))
    d_a = np.sum(np.abs(np.log(aligned[:, SLICE_A] / other_genes[:, SLICE_A])), axis=1)
    d_c = np.linalg.norm(aligned[:, SLICE_CENTER] - other_genes[:, SLICE_CENTER], axis=1)
    d_e = np.sum(np.abs(aligned[:, SLICE_EPS] - other_genes[:, SLICE_EPS]), axis=1)
    d_t = np.sum(np.abs(aligned[:, SLICE_TAPER] - other_genes[:, SLICE_TAPER]), axis=1)
    return angle / 0.5 + d_a / 0.3 + d_c / (0.2 * size) + (d_e + d_t) / 0.5


def _crowd(
    rng: np.random.Generator,
    genes: Array,
    rot: Array,
    eof: Array,
    kids: Array,
    kid_rot: Array,
    kid_eof: Array,
    window: int,
    size: float,
) -> None:
    """Restricted tournament replacement, in place: each child replaces the most similar of
    `window` random individuals if it is fitter (children in turn)."""
    count = len(kids)
    entrants = np.argsort(rng.random((count, len(genes))), axis=1)[:, :window]
    flat = entrants.ravel()
    dist = solid_distance(
        np.repeat(kids, window, axis=0), np.repeat(kid_rot, window, axis=0),
        genes[flat], rot[flat], size,
    ).reshape(count, window)  # fmt: skip
    nearest = entrants[np.arange(count), np.argmin(dist, axis=1)]
    for i, j in enumerate(nearest):
        if kid_eof[i] < eof[j]:
            genes[j], rot[j], eof[j] = kids[i], kid_rot[i], kid_eof[i]


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
    start = objective.evaluations
    cap = start + min(max_evaluations, objective.remaining)
    genes = bounds.clip(np.atleast_2d(np.asarray(seeds, dtype=np.float64)))[: cap - start]
    rot = rotvec_to_matrix(genes[:, SLICE_ROTVEC])
    n = opt.population
    if 0 < len(genes) < n:
        pick = rng.integers(0, len(genes), size=n - len(genes))
        kids, kid_rot = _offspring(
            rng, genes[pick], rot[pick], np.zeros(len(pick)), len(pick), opt, 1.0, bounds.size
        )
        genes = np.concatenate([genes, bounds.clip(kids)])[: cap - start]
        rot = np.concatenate([rot, kid_rot])[: cap - start]
    eof = objective.eof(genes, rot) if len(genes) else np.zeros(0)
    order = np.argsort(eof, kind="stable")[:n]
    genes, rot, eof = genes[order], rot[order], eof[order]

    generations, stall, status = 0, 0, "budget"
    best = float(eof[0]) if len(eof) else np.inf
    crowding = opt.replacement == "crowding"
    while True:
        children = len(genes) if crowding else len(genes) - opt.elite
        if children < 1 or objective.evaluations + children > cap:
            status = "budget"
            break
        if opt.max_generations is not None and generations >= opt.max_generations:
            status = "generations"
            break
        if best <= opt.target_eof:
            status = "target"
            break
        if stall >= opt.stall_generations:
            status = "stall"
            break
        used = (objective.evaluations - start) / max(cap - start, 1)
        kids, kid_rot = _offspring(
            rng, genes, rot, eof, children, opt, 1.0 - 0.75 * used, bounds.size
        )
        kids = bounds.clip(kids)
        kid_eof = objective.eof(kids, kid_rot)
        if crowding:
            _crowd(rng, genes, rot, eof, kids, kid_rot, kid_eof, opt.window, bounds.size)
        else:
            genes = np.concatenate([genes[: opt.elite], kids])
            rot = np.concatenate([rot[: opt.elite], kid_rot])
            eof = np.concatenate([eof[: opt.elite], kid_eof])
        order = np.argsort(eof, kind="stable")
        genes, rot, eof = genes[order], rot[order], eof[order]
        generations += 1
        stall = 0 if eof[0] < best * (1.0 - 1e-4) else stall + 1
        best = min(best, float(eof[0]))
    genes = genes.copy()
    if len(genes):
        genes[:, SLICE_ROTVEC] = matrix_to_rotvec(rot)
    return GeneticRun(
        population=genes,
        eof=eof,
        generations=generations,
        evaluations=objective.evaluations - start,
        status=status,
    )
