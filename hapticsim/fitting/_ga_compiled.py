"""The genetic algorithm of the hybrid methods, compiled (numba): the whole run in one call.

:mod:`hapticsim.fitting.genetic` describes the algorithm and is its public driver; this module
runs it without returning to Python between generations (selection, crossover, mutation, jumps,
crowding and the population EOF all compiled; before, their numpy overhead cost more than the
evaluations themselves). Random numbers come from numba's generator, seeded once per run from
the caller's :class:`numpy.random.Generator`, so the same seed gives the same run, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hapticsim.fitting._problem_compiled import problem_residuals_posed, residual_length
from hapticsim.geometry.eof_compiled import INLINE, JIT, vector_fields
from hapticsim.geometry.layout import I_A, I_CENTER, I_EPS, I_TAPER, N_PARAMS

#: Status codes of :func:`ga_run`, in the order of ``genetic.STATUSES``.
STATUS_BUDGET, STATUS_GENERATIONS, STATUS_TARGET, STATUS_STALL = 0, 1, 2, 3


def _symmetry_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The 8 body-frame rotations S mapping the tapered family onto itself, with the change of
    parameters: R -> R S, a -> a[perm], taper -> sign * taper[perm]."""
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


SYMMETRIES, SYM_A, SYM_T, SYM_SIGN = _symmetry_tables()
#: Each S is a signed permutation: column i of S has its one entry SYM_VAL[s, i] in row
#: SYM_IDX[s, i], so ``(R S)[:, i] = SYM_VAL[s, i] R[:, SYM_IDX[s, i]]``.
SYM_IDX = np.argmax(np.abs(SYMMETRIES), axis=1).astype(np.int64)
SYM_VAL = np.take_along_axis(SYMMETRIES, SYM_IDX[:, None, :], axis=1)[:, 0, :].copy()
#: The tables :func:`align` takes.
TABLES = (SYM_IDX, SYM_VAL, SYM_A, SYM_T, SYM_SIGN)
#: Quarter turns about body x and y (not symmetries): R -> R J, a -> a[perm].
JUMP_MATS = np.array(
    [
        [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
    ]
)
JUMP_PERM = np.array([[0, 2, 1], [2, 1, 0]], dtype=np.int64)


@njit(**INLINE)
def _copy3(a: np.ndarray, out: np.ndarray) -> None:
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, j]


@njit(**INLINE)
def _matmul3(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]


@njit(**INLINE)
def align(
    ref: np.ndarray, rot: np.ndarray, genes: np.ndarray, out_genes: np.ndarray,
    out_rot: np.ndarray, sym_idx: np.ndarray, sym_val: np.ndarray, sym_a: np.ndarray,
    sym_t: np.ndarray, sym_sign: np.ndarray,
) -> None:  # fmt: skip
    """One solid (genes (13,), rotation (3, 3)) rewritten among its 8 equivalent parameter sets
    into the one whose rotation is closest to `ref` (largest ``trace(ref^T R S)``)."""
    # trace(ref^T R S) = sum_i (ref^T R)[i, idx_i] val_i for the signed permutation S.
    best, best_score = 0, -math.inf
    for s in range(8):
        score = 0.0
        for i in range(3):
            j = sym_idx[s, i]
            score += (ref[0, i] * rot[0, j] + ref[1, i] * rot[1, j] + ref[2, i] * rot[2, j]) * (
                sym_val[s, i]
            )
        if score > best_score:
            best, best_score = s, score
    for k in range(N_PARAMS):
        out_genes[k] = genes[k]
    for k in range(3):
        out_genes[I_A + k] = genes[I_A + sym_a[best, k]]
    for k in range(2):
        out_genes[I_TAPER + k] = genes[I_TAPER + sym_t[best, k]] * sym_sign[best]
    for i in range(3):
        col, val = sym_idx[best, i], sym_val[best, i]
        for j in range(3):
            out_rot[j, i] = rot[j, col] * val


@njit(**INLINE)
def solid_distance(
    genes: np.ndarray, rot: np.ndarray, other: np.ndarray, other_rot: np.ndarray, size: float,
    tables: tuple, aligned: np.ndarray, aligned_rot: np.ndarray, limit: float = math.inf,
) -> float:  # fmt: skip
    """The dimensionless distance of :func:`hapticsim.fitting.genetic.solid_distance`
    (`aligned` (13,) and `aligned_rot` (3, 3) are scratch), or inf when it is not below
    `limit`.

    The distance is ``((angle + sizes) + centre) + shape``, each term >= 0. Rounding is
    monotone, so the sum is at least the rounded ``centre + shape``: when that alone reaches
    `limit`, the logarithms and the arccosine are skipped and inf returned, which a search for
    the nearest individual (``d < nearest``) treats exactly as the distance itself.
    """
    align(other_rot, rot, genes, aligned, aligned_rot, *tables)
    d_c = math.sqrt(
        (aligned[I_CENTER] - other[I_CENTER]) ** 2
        + (aligned[I_CENTER + 1] - other[I_CENTER + 1]) ** 2
        + (aligned[I_CENTER + 2] - other[I_CENTER + 2]) ** 2
    )  # fmt: skip
    d_s = 0.0
    for k in range(I_EPS, I_TAPER + 2):  # exponents and tapers
        d_s += abs(aligned[k] - other[k])
    centre, shape = d_c / (0.2 * size), d_s / 0.5
    if centre + shape >= limit:
        return math.inf
    cos = -1.0
    for i in range(3):
        for j in range(3):
            cos += other_rot[i, j] * aligned_rot[i, j]
    cos = min(max(cos / 2.0, -1.0), 1.0)
    d_a = 0.0
    for k in range(3):
        d_a += abs(math.log(aligned[I_A + k] / other[I_A + k]))
    return math.acos(cos) / 0.5 + d_a / 0.3 + centre + shape


@njit(**INLINE)
def distance_bound(genes: np.ndarray, other: np.ndarray, size: float) -> float:
    """A lower bound of :func:`solid_distance` from its terms that no re-parametrisation changes
    (the centre and the shape exponents): no alignment needed."""
    d_c = math.sqrt(
        (genes[I_CENTER] - other[I_CENTER]) ** 2
        + (genes[I_CENTER + 1] - other[I_CENTER + 1]) ** 2
        + (genes[I_CENTER + 2] - other[I_CENTER + 2]) ** 2
    )  # fmt: skip
    return (
        d_c / (0.2 * size)
        + (abs(genes[I_EPS] - other[I_EPS]) + abs(genes[I_EPS + 1] - other[I_EPS + 1])) / 0.5
    )


@njit(**INLINE)
def _orthonormalise(m: np.ndarray, out: np.ndarray) -> None:
    """Gram-Schmidt on the first two columns of m, third = first x second."""
    n0 = math.sqrt(m[0, 0] ** 2 + m[1, 0] ** 2 + m[2, 0] ** 2)
    u = (m[0, 0] / n0, m[1, 0] / n0, m[2, 0] / n0)
    d = u[0] * m[0, 1] + u[1] * m[1, 1] + u[2] * m[2, 1]
    v0, v1, v2 = m[0, 1] - d * u[0], m[1, 1] - d * u[1], m[2, 1] - d * u[2]
    n1 = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    v0, v1, v2 = v0 / n1, v1 / n1, v2 / n1
    out[0, 0], out[1, 0], out[2, 0] = u
    out[0, 1], out[1, 1], out[2, 1] = v0, v1, v2
    out[0, 2] = u[1] * v2 - u[2] * v1
    out[1, 2] = u[2] * v0 - u[0] * v2
    out[2, 2] = u[0] * v1 - u[1] * v0


@njit(**INLINE)
def _axis_angle(axis: np.ndarray, angle: float, out: np.ndarray) -> None:
    """Rotation by `angle` [rad] about the unit `axis` (Rodrigues)."""
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    x, y, z = axis[0], axis[1], axis[2]
    out[0, 0], out[0, 1], out[0, 2] = t * x * x + c, t * x * y - s * z, t * x * z + s * y
    out[1, 0], out[1, 1], out[1, 2] = t * x * y + s * z, t * y * y + c, t * y * z - s * x
    out[2, 0], out[2, 1], out[2, 2] = t * x * z - s * y, t * y * z + s * x, t * z * z + c


@njit(**INLINE)
def _tournament(rng: np.random.Generator, eof: np.ndarray, size: int) -> int:
    best = rng.integers(0, eof.shape[0])
    for _ in range(size - 1):
        k = rng.integers(0, eof.shape[0])
        if eof[k] < eof[best]:
            best = k
    return best


@njit(**JIT)
def offspring(
    rng: np.random.Generator, genes: np.ndarray, rot: np.ndarray, eof: np.ndarray, count: int,
    settings: np.ndarray,
    shrink: float, size: float, lower: np.ndarray, upper: np.ndarray, tables: tuple,
    kids: np.ndarray, kid_rot: np.ndarray,
) -> None:  # fmt: skip
    """`count` children into `kids` (count, 13) and `kid_rot` (count, 3, 3), clipped into the
    bounds: tournament selection, aligned BLX-0.25 crossover, group mutation, jumps.

    `settings`: tournament, crossover rate, mutation rate, jump rate, sigma a, eps, taper,
    angle, centre (see :class:`~hapticsim.fitting.genetic.GeneticOptions`).
    """
    tournament = int(settings[0])
    p2 = np.empty(N_PARAMS)
    r2 = np.empty((3, 3))
    blend = np.empty((3, 3))
    turn = np.empty((3, 3))
    tmp = np.empty((3, 3))
    axis = np.empty(3)
    w = np.empty(N_PARAMS)
    for c in range(count):
        first = _tournament(rng, eof, tournament)
        second = _tournament(rng, eof, tournament)
        p1, r1 = genes[first], rot[first]
        align(r1, rot[second], genes[second], p2, r2, *tables)
        child, crot = kids[c], kid_rot[c]
        if rng.random() < settings[1]:
            for k in range(N_PARAMS):
                w[k] = -0.25 + 1.5 * rng.random()
            for k in range(N_PARAMS):
                child[k] = p1[k] + w[k] * (p2[k] - p1[k])
            for k in range(3):  # geometric blend of the semi-axes
                child[k] = p1[k] * (p2[k] / p1[k]) ** w[k]
            for i in range(3):
                for j in range(3):
                    blend[i, j] = r1[i, j] + w[7] * (r2[i, j] - r1[i, j])
            _orthonormalise(blend, crot)
        else:
            for k in range(N_PARAMS):
                child[k] = p1[k]
            for i in range(3):
                for j in range(3):
                    crot[i, j] = r1[i, j]
        # Mutation by gene group, sizes shrinking as the budget is used.
        if rng.random() < settings[2]:
            for k in range(3):
                child[k] *= math.exp(shrink * settings[4] * rng.standard_normal())
        if rng.random() < settings[2]:
            for k in range(3, 5):
                child[k] += shrink * settings[5] * rng.standard_normal()
        if rng.random() < settings[2]:
            for k in range(5, 7):
                child[k] += shrink * settings[6] * rng.standard_normal()
        if rng.random() < settings[2]:
            for k in range(3):
                axis[k] = rng.standard_normal()
            norm = math.sqrt(axis[0] ** 2 + axis[1] ** 2 + axis[2] ** 2)
            for k in range(3):
                axis[k] /= norm
            _axis_angle(axis, shrink * settings[7] * rng.standard_normal(), turn)
            _matmul3(turn, crot, tmp)
            _copy3(tmp, crot)
        if rng.random() < settings[2]:
            for k in range(10, 13):
                child[k] += shrink * settings[8] * size * rng.standard_normal()
        # Jump: a quarter turn about body x or y, a permuted to keep the extents in place.
        if rng.random() < settings[3]:
            which = rng.integers(0, 2)
            _matmul3(crot, JUMP_MATS[which], tmp)
            _copy3(tmp, crot)
            a0, a1, a2 = child[0], child[1], child[2]
            old = (a0, a1, a2)
            for k in range(3):
                child[k] = old[JUMP_PERM[which, k]]
            child[5] = 0.0
            child[6] = 0.0
        for k in range(N_PARAMS):
            child[k] = min(max(child[k], lower[k]), upper[k])


@njit(**JIT)
def _after(x: float, y: float) -> bool:
    """Whether x sorts after y: larger, or NaN against a number (numpy sorts NaN last)."""
    return x > y or (x != x and y == y)


@njit(**JIT)
def _stable_order(values: np.ndarray) -> np.ndarray:
    """``np.argsort(values, kind="mergesort")``: a stable insertion sort, NaN last.

    The same permutation (both are stable), written as a loop: numpy's mergesort and fancy
    indexing cost numba seconds to compile, the loop a fraction of one; populations are small.
    """
    n = values.shape[0]
    order = np.empty(n, np.int64)
    for i in range(n):
        order[i] = i
    for i in range(1, n):
        k = order[i]
        j = i - 1
        while j >= 0 and _after(values[order[j]], values[k]):
            order[j + 1] = order[j]
            j -= 1
        order[j + 1] = k
    return order


@njit(**INLINE)
def _put(
    genes: np.ndarray, rot: np.ndarray, i: int, src_genes: np.ndarray, src_rot: np.ndarray, j: int
) -> None:
    """Row i of genes (P, 13) and rot (P, 3, 3) := row j of the sources."""
    for k in range(N_PARAMS):
        genes[i, k] = src_genes[j, k]
    for a in range(3):
        for b in range(3):
            rot[i, a, b] = src_rot[j, a, b]


@njit(**JIT)
def _gather(
    genes: np.ndarray, rot: np.ndarray, eof: np.ndarray, order: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``genes[order], rot[order], eof[order]`` (new arrays)."""
    count = order.shape[0]
    out_genes, out_rot = np.empty((count, N_PARAMS)), np.empty((count, 3, 3))
    out_eof = np.empty(count)
    for i in range(count):
        _put(out_genes, out_rot, i, genes, rot, order[i])
        out_eof[i] = eof[order[i]]
    return out_genes, out_rot, out_eof


@njit(**JIT)
def _evaluate(
    problem: tuple, genes: np.ndarray, rot: np.ndarray, eof: np.ndarray, tally: np.ndarray
) -> None:
    """Fitness of each row of genes/rot into `eof`: ``sum(r^2) / n`` of the problem's residuals
    (the EOF [m^2] for the paper's model)."""
    count, n = genes.shape[0], problem.points.shape[1]
    m = residual_length(problem)
    r = np.empty((count, m))
    a, eps, taper, center = vector_fields(genes)
    problem_residuals_posed(problem, a, eps, taper, rot, center, r, tally)
    for k in range(count):
        s = 0.0
        for i in range(m):
            s += r[k, i] * r[k, i]
        eof[k] = s / n


@njit(**JIT)
def ga_run(
    problem: tuple, seeds: np.ndarray, seed_rot: np.ndarray, lower: np.ndarray,
    upper: np.ndarray, size: float, cap: int, rng: np.random.Generator, population: int,
    crowding: bool, window: int, elite: int,
    settings: np.ndarray, stall_generations: int, max_generations: int, target_eof: float,
    out_genes: np.ndarray, out_rot: np.ndarray, out_eof: np.ndarray,
    hist_evals: np.ndarray, hist_best: np.ndarray, tally: np.ndarray,
) -> tuple[int, int, int, int, int]:  # fmt: skip
    """One genetic search (see :func:`hapticsim.fitting.genetic.genetic_search`).

    Args:
        problem: the residuals whose sum of squares is the fitness (see
            :class:`hapticsim.fitting.problem.Problem`).
        seeds: (k, 13) start vectors, clipped; seed_rot: (k, 3, 3) their rotations.
        cap: the most evaluations; rng: the generator of every random choice.
        max_generations: -1 for no limit.
        out_genes, out_rot, out_eof: (population, ...) buffers for the last generation, sorted
            by EOF (the first ``count`` rows are valid).
        hist_evals, hist_best: buffers for (evaluations so far, best EOF) after each population
            call (the first ``n_hist`` entries are valid).

    Returns:
        ``(count, generations, evaluations, status, n_hist)``.
    """
    tables = TABLES
    n = population
    k = min(seeds.shape[0], cap)
    total = k
    if 0 < k < n:
        total = min(n, cap)
    genes = np.empty((total, N_PARAMS))
    rot = np.empty((total, 3, 3))
    for i in range(k):
        _put(genes, rot, i, seeds, seed_rot, i)
    if total > k:
        # Fill the generation with mutated copies of random seeds.
        pick = rng.integers(0, k, total - k)
        zero = np.zeros(total - k)
        parents, parent_rot = np.empty((total - k, N_PARAMS)), np.empty((total - k, 3, 3))
        for i in range(total - k):
            _put(parents, parent_rot, i, seeds, seed_rot, pick[i])
        offspring(
            rng, parents, parent_rot, zero, total - k, settings, 1.0, size, lower, upper,
            tables, genes[k:], rot[k:],
        )  # fmt: skip
    eof = np.empty(total)
    used = 0
    n_hist = 0
    if total > 0:
        _evaluate(problem, genes, rot, eof, tally)
        used = total
    genes, rot, eof = _gather(genes, rot, eof, _stable_order(eof)[:n])
    count = genes.shape[0]
    best = eof[0] if count > 0 else math.inf
    if total > 0:
        hist_evals[0], hist_best[0] = used, best
        n_hist = 1

    kids = np.empty((count, N_PARAMS))
    kid_rot = np.empty((count, 3, 3))
    kid_eof = np.empty(count)
    scratch, scratch_rot = np.empty(N_PARAMS), np.empty((3, 3))
    pool = np.arange(count)
    generations, stall, status = 0, 0, STATUS_BUDGET
    while True:
        children = count if crowding else count - elite
        if children < 1 or used + children > cap:
            status = STATUS_BUDGET
            break
        if max_generations >= 0 and generations >= max_generations:
            status = STATUS_GENERATIONS
            break
        if best <= target_eof:
            status = STATUS_TARGET
            break
        if stall >= stall_generations:
            status = STATUS_STALL
            break
        shrink = 1.0 - 0.75 * used / max(cap, 1)
        offspring(
            rng, genes, rot, eof, children, settings, shrink, size, lower, upper, tables,
            kids[:children], kid_rot[:children],
        )  # fmt: skip
        _evaluate(problem, kids[:children], kid_rot[:children], kid_eof[:children], tally)
        used += children
        if crowding:
            # Restricted tournament replacement: each child meets `window` random individuals
            # and replaces the most similar one if it is fitter.
            for c in range(children):
                # `window` distinct individuals: a partial Fisher-Yates shuffle of `pool`.
                for j in range(window):
                    r = rng.integers(j, count)
                    pool[j], pool[r] = pool[r], pool[j]
                nearest, near = pool[0], math.inf
                for j in pool[:window]:
                    if distance_bound(kids[c], genes[j], size) >= near:
                        continue  # cannot be the nearest: skip the alignment
                    d = solid_distance(
                        kids[c], kid_rot[c], genes[j], rot[j], size, tables, scratch, scratch_rot,
                        near,
                    )  # fmt: skip
                    if d < near:
                        nearest, near = j, d
                if kid_eof[c] < eof[nearest]:
                    _put(genes, rot, nearest, kids, kid_rot, c)
                    eof[nearest] = kid_eof[c]
        else:
            for c in range(children):
                _put(genes, rot, elite + c, kids, kid_rot, c)
                eof[elite + c] = kid_eof[c]
        genes, rot, eof = _gather(genes, rot, eof, _stable_order(eof))
        generations += 1
        stall = 0 if eof[0] < best * (1.0 - 1e-4) else stall + 1
        best = min(best, eof[0])
        if n_hist < hist_evals.shape[0]:
            hist_evals[n_hist], hist_best[n_hist] = used, best
            n_hist += 1
    for i in range(count):
        _put(out_genes, out_rot, i, genes, rot, i)
        out_eof[i] = eof[i]
    return count, generations, used, status, n_hist


@njit(**JIT)
def align_many(
    ref: np.ndarray, rot: np.ndarray, genes: np.ndarray, out_genes: np.ndarray,
    out_rot: np.ndarray,
) -> None:  # fmt: skip
    """:func:`align` row by row: (P, 3, 3), (P, 3, 3), (P, 13) into (P, 13), (P, 3, 3)."""
    for p in range(genes.shape[0]):
        align(ref[p], rot[p], genes[p], out_genes[p], out_rot[p], *TABLES)


@njit(**JIT)
def solid_distance_many(
    genes: np.ndarray, rot: np.ndarray, other: np.ndarray, other_rot: np.ndarray, size: float,
    out: np.ndarray,
) -> None:  # fmt: skip
    """:func:`solid_distance` row by row into `out` (P,)."""
    tables = TABLES
    scratch, scratch_rot = np.empty(N_PARAMS), np.empty((3, 3))
    for p in range(genes.shape[0]):
        out[p] = solid_distance(
            genes[p], rot[p], other[p], other_rot[p], size, tables, scratch, scratch_rot
        )


@njit(**JIT)
def distinct_rows(
    genes: np.ndarray, rot: np.ndarray, count: int, size: float, out: np.ndarray
) -> int:  # fmt: skip
    """Rows of genes (P, 13) / rot (P, 3, 3), in order, each kept when its smallest
    :func:`solid_distance` to the rows kept before it is above 1 (or NaN, as ``np.min`` gives),
    until `count` are kept: their indices into `out`; returns how many."""
    tables = TABLES
    scratch, scratch_rot = np.empty(N_PARAMS), np.empty((3, 3))
    kept = 0
    for i in range(genes.shape[0]):
        nearest, undefined = math.inf, False
        for c in range(kept):
            j = out[c]
            d = solid_distance(genes[i], rot[i], genes[j], rot[j], size, tables, scratch,
                               scratch_rot)  # fmt: skip
            undefined = undefined or d != d
            nearest = min(nearest, d)
        if kept and nearest <= 1.0 and not undefined:
            continue
        out[kept] = i
        kept += 1
        if kept == count:
            break
    return kept
