"""The parts of the search: initial estimates, symmetries, GA, multi-start LM, least squares."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.fitting.genetic import (
    SYMMETRIES,
    GeneticOptions,
    align_to,
    genetic_search,
    solid_distance,
)
from hapticsim.fitting.hybrid import HybridOptions
from hapticsim.fitting.initial import dominant_directions, paper_initial, seed_vectors
from hapticsim.fitting.least_squares import STEP_EVALUATIONS, least_squares_run, multi_start_run
from hapticsim.fitting.objective import Objective
from hapticsim.geometry import Superquadric, random_rotation
from hapticsim.geometry.rotations import matrix_to_rotvec, rotvec_to_matrix


def _perturbed(truth: Superquadric, rng: np.random.Generator, count: int) -> np.ndarray:
    scale = np.r_[[0.004] * 3, [0.05] * 2, [0.05] * 2, [0.05] * 3, [0.004] * 3]
    return truth.to_vector() + rng.normal(size=(count, 13)) * scale


def test_paper_initial_estimate() -> None:
    rng = np.random.default_rng(0)
    rot = random_rotation(rng)
    local = rng.uniform(-1, 1, (4000, 3)) * [0.01, 0.02, 0.04]
    points = local @ rot.T + [0.1, 0.2, 0.3]
    init = paper_initial(points)
    np.testing.assert_allclose(init.center, points.mean(axis=0))
    np.testing.assert_allclose(init.eps, [1.0, 1.0])
    np.testing.assert_allclose(init.taper, [0.0, 0.0])
    # Largest spread on z; half the spread along each principal axis.
    np.testing.assert_allclose(np.abs(init.rotation.T @ rot), np.eye(3), atol=0.05)
    np.testing.assert_allclose(init.a, [0.01, 0.02, 0.04], rtol=0.05)


def test_dominant_normal_directions_of_a_box_corner() -> None:
    rotation = random_rotation(np.random.default_rng(3))
    truth = Superquadric(a=(0.03, 0.04, 0.05), eps=(0.1, 0.1), rotation=rotation)
    eta = np.random.default_rng(0).uniform(0.2, 1.0, 90)
    omega = np.random.default_rng(1).uniform(0.2, 1.4, 90)
    _, normals = truth.surface(eta, omega)
    dirs = dominant_directions(normals)
    assert len(dirs) == 3
    # Each direction is one of the body axes (within a few degrees).
    cosines = np.abs(np.array(dirs) @ truth.rotation)
    assert np.all(cosines.max(axis=1) > 0.99)


def test_seeds_contain_the_paper_estimate_and_a_warm_start(box_contacts) -> None:
    truth, points, normals = box_contacts
    seeds = seed_vectors(points, normals, initial=truth)
    np.testing.assert_array_equal(seeds[0], truth.to_vector())
    np.testing.assert_allclose(seeds[1], paper_initial(points).to_vector())
    assert seeds.shape[1] == 13 and len(seeds) > len(seed_vectors(points, None))


def test_symmetric_parameter_sets_are_the_same_solid(box_contacts) -> None:
    truth, points, normals = box_contacts
    objective = Objective(points + 0.002, normals, lam=0.5, budget=100)
    v = truth.to_vector()
    rot = np.repeat(truth.rotation[None], 8, axis=0)
    # Rewrite the truth as each of its 8 parameter sets, then align them back.
    variants = np.repeat(v[None], 8, axis=0)
    variants_rot = rot @ SYMMETRIES
    aligned, aligned_rot = align_to(variants_rot, rot, variants)
    aligned[:, 7:10] = matrix_to_rotvec(aligned_rot)
    eof = objective.eof(aligned)
    np.testing.assert_allclose(eof, eof[0], rtol=1e-10)
    back, back_rot = align_to(rot, aligned_rot, aligned)
    np.testing.assert_allclose(back_rot, rot, atol=1e-12)
    np.testing.assert_allclose(back[:, :7], np.repeat(v[None, :7], 8, axis=0), atol=1e-12)
    assert np.all(solid_distance(aligned, aligned_rot, variants, rot, 0.05) < 1e-6)


def test_genetic_search_improves_and_respects_its_budget(box_contacts) -> None:
    truth, points, normals = box_contacts
    rng = np.random.default_rng(0)
    seeds = _perturbed(truth, rng, 6) * np.r_[[1.5] * 3, [1] * 10]  # 50 % too large
    for replacement in ("crowding", "generational"):
        objective = Objective(points, normals, lam=0.5, budget=10_000)
        start = objective.eof(seeds).min()
        opt = GeneticOptions(population=20, replacement=replacement)
        run = genetic_search(objective, seeds, np.random.default_rng(1), 800, opt)
        assert run.evaluations <= 800 and objective.evaluations == 6 + run.evaluations
        # measured: the best EOF falls to 0.0093 (crowding) and 0.0054 (generational) of the
        # best seed's in 800 evaluations
        assert run.eof[0] < 0.05 * start
        assert np.all(np.diff(run.eof) >= 0)


def test_multi_start_lm_lowers_every_eof_and_counts(box_contacts) -> None:
    truth, points, normals = box_contacts
    starts = _perturbed(truth, np.random.default_rng(2), 5)
    objective = Objective(points, normals, lam=0.5, budget=10_000)
    before = objective.eof(starts)
    x, eof = multi_start_run(objective, starts, steps=6)
    # Each start: its residual, then at most 6 steps of a residual and (if accepted) a Jacobian.
    assert 5 + 5 * 15 <= objective.evaluations <= 5 + 5 * (1 + 6 * STEP_EVALUATIONS)
    # measured: every start falls to <= 2e-16 of its EOF (clean contacts, the truth nearby)
    assert np.all(eof <= before) and np.all(eof < 1e-10 * before)
    np.testing.assert_allclose(objective.eof(x), eof, rtol=1e-12)


def test_least_squares_converges_on_clean_data(box_contacts) -> None:
    truth, points, normals = box_contacts
    start = _perturbed(truth, np.random.default_rng(3), 1)[0]
    objective = Objective(points, normals, lam=0.5, budget=5_000)
    run = least_squares_run(objective, start)
    assert run.status == "converged" and run.evaluations == objective.evaluations
    # Measured: EOF ~1e-20 m^2 from an EOF of ~1e-5 m^2.
    assert objective.best_eof < 1e-14
    # The fit is the same solid as the truth (possibly another parameter set of it).
    got = Superquadric.from_vector(objective.best_vector)
    r = rotvec_to_matrix(objective.best_vector[7:10])[None]
    v, _ = align_to(truth.rotation[None], r, objective.best_vector[None])
    np.testing.assert_allclose(v[0, :3], truth.a, rtol=1e-5)
    np.testing.assert_allclose(got.center, truth.center, atol=1e-7)


def test_options_are_validated() -> None:
    with pytest.raises(InvalidInputError, match="population"):
        GeneticOptions(population=2)
    with pytest.raises(InvalidInputError, match="replacement"):
        GeneticOptions(replacement="steady")
    with pytest.raises(InvalidInputError, match="ga_fraction"):
        HybridOptions(ga_fraction=0.0)


def test_restarts_spend_the_budget_left_and_keep_the_best(box_contacts) -> None:
    from hapticsim.fitting.hybrid import hybrid_search
    from hapticsim.fitting.initial import seed_vectors

    truth, points, normals = box_contacts
    seeds = seed_vectors(points, normals)
    used, best = {}, {}
    for restarts in (0, 3):
        objective = Objective(points, normals, lam=0.5, budget=5_000, distance="tapered")
        hybrid_search(objective, seeds, np.random.default_rng(4), HybridOptions(restarts=restarts))
        used[restarts], best[restarts] = objective.evaluations, objective.best_eof
    # The first round converges early on these clean contacts (measured: 2310 evaluations);
    # restarts use what is left down to the restart floor of 20 % (measured: 4402 in all), and
    # can only lower the best EOF.
    assert used[0] < 4_000 and used[3] > used[0]
    assert 5_000 - used[3] < 0.2 * 5_000 + 100
    assert best[3] <= best[0]
    with pytest.raises(InvalidInputError, match="restarts"):
        HybridOptions(restarts=-1)
    with pytest.raises(InvalidInputError, match="restart_fraction"):
        HybridOptions(restart_fraction=0.0)


def _population(rng: np.random.Generator, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Random parameter vectors around one solid, some far apart, and their rotations."""
    genes = np.zeros((count, 13))
    genes[:, 0:3] = rng.uniform(0.02, 0.05, (count, 3))
    genes[:, 3:5] = rng.uniform(0.2, 1.5, (count, 2))
    genes[:, 5:7] = rng.uniform(-0.3, 0.3, (count, 2))
    genes[:, 7:10] = rng.normal(0.0, 0.6, (count, 3))
    genes[:, 10:13] = rng.normal(0.0, 0.01, (count, 3))
    return genes, rotvec_to_matrix(genes[:, 7:10])


def test_a_distance_cut_at_a_limit_is_the_distance_below_it() -> None:
    from hapticsim.fitting import _ga_compiled as ga

    rng = np.random.default_rng(3)
    genes, rot = _population(rng, 400)
    full = solid_distance(genes[:200], rot[:200], genes[200:], rot[200:], 0.1)
    scratch, scratch_rot = np.empty(13), np.empty((3, 3))
    cut = 0
    for i in range(200):
        for limit in full[i] * np.array([0.1, 0.3, 1.0, 1.5]):
            d = ga.solid_distance(genes[i], rot[i], genes[200 + i], rot[200 + i], 0.1,
                                  ga.TABLES, scratch, scratch_rot, limit)  # fmt: skip
            if full[i] < limit:
                assert d == full[i]  # bit for bit below the limit
            else:
                assert d == full[i] or d == np.inf
                cut += d == np.inf
    # The cut does happen (measured: 379 of 800; it rests on sqrt and abs, correctly rounded
    # on every CPU, of numpy's inputs): the shortcut is exercised.
    assert cut > 50


def test_distinct_starts_keep_the_rows_a_greedy_pass_keeps() -> None:
    from hapticsim.fitting.genetic import GeneticRun
    from hapticsim.fitting.hybrid import distinct_starts

    rng = np.random.default_rng(4)
    genes, _ = _population(rng, 40)
    genes[10:20] = genes[:10] + rng.normal(0.0, 1e-4, (10, 13))  # near copies: dropped
    genes[:, 7:10] = matrix_to_rotvec(rotvec_to_matrix(genes[:, 7:10]))
    run = GeneticRun(population=genes, eof=np.zeros(40), generations=0, evaluations=0,
                     status="budget")  # fmt: skip
    rot = rotvec_to_matrix(genes[:, 7:10])
    for count in (1, 5, 16, 40):
        kept: list[int] = []
        for i in range(40):
            if kept and np.min(solid_distance(np.repeat(genes[i : i + 1], len(kept), 0),
                                              np.repeat(rot[i : i + 1], len(kept), 0),
                                              genes[kept], rot[kept], 0.1)) <= 1.0:  # fmt: skip
                continue
            kept.append(i)
            if len(kept) == count:
                break
        got = distinct_starts(run, count, 0.1)
        assert len(got) == len(kept)
        assert all(np.array_equal(g, genes[k]) for g, k in zip(got, kept, strict=True))
    assert len(distinct_starts(run, 40, 0.1)) < 40
