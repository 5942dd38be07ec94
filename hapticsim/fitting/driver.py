"""The public driver :func:`fit`: validate every argument, then dispatch to a method."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import (
    as_generator,
    finite_array,
    finite_float,
    normals_array,
    physical_points,
    positive_int,
)
from hapticsim.constants import DEFAULT_LAMBDA, MAX_BUDGET
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.fitting.gpis import fit_gpis
from hapticsim.fitting.hybrid import HybridOptions, hybrid_search
from hapticsim.fitting.initial import paper_initial, random_frame_seeds, seed_vectors
from hapticsim.fitting.kernels import prepare
from hapticsim.fitting.least_squares import least_squares_run
from hapticsim.fitting.likelihood import contact_weights, normal_ratio
from hapticsim.fitting.methods import (
    DEFAULT_BUDGET,
    FIT_METHODS,
    HYBRID_METHODS,
    SOLID_METHODS,
    TRACK_METHODS,
    uses_normals,
)
from hapticsim.fitting.ml import MLOptions, default_budget, guarded, ml_objective, ml_search
from hapticsim.fitting.multi import multi_search
from hapticsim.fitting.objective import Objective
from hapticsim.fitting.result import FitResult, PartSelection
from hapticsim.fitting.toroid import choose_holed, fit_supertoroid, toroid_residuals
from hapticsim.fitting.uncertainty import laplace
from hapticsim.geometry.eof import DISTANCES, ContactSet
from hapticsim.geometry.superquadric import N_PARAMS, Superquadric, superquadric_arg
from hapticsim.geometry.union import SuperquadricUnion

Array = NDArray[np.float64]

#: Default of :func:`fit`'s `distance`.
DEFAULT_DISTANCE: str = "tapered"
#: Smallest budget whose hybrid fits add :func:`~hapticsim.fitting.initial.random_frame_seeds`
#: to the data-derived seeds (their three Levenberg-Marquardt steps cost about 1000 evaluations;
#: the environment's full fits, at 3000, keep the data-derived seeds only).
RANDOM_FRAMES_BUDGET: int = 6000
#: Singular-value ratio of the centred contacts below which they count as one line.
LINE_TOLERANCE: float = 1e-6


def method_budget(method: str, options: MLOptions | None = None) -> int:
    """A method's default budget: :data:`~hapticsim.fitting.methods.DEFAULT_BUDGET`, and for
    nML the budget whose EOF search is nH's default fit
    (:func:`~hapticsim.fitting.ml.default_budget`: its ML stages come on top)."""
    if method == "nML":
        return default_budget(DEFAULT_BUDGET, options)
    return DEFAULT_BUDGET


def hybrid_seeds(points: Array, normals: Array | None, warm: Superquadric | None,
                 budget: int) -> Array:  # fmt: skip
    """The start vectors of the hybrid search (H, nH and nML's EOF search): the data-derived
    seeds, and seeds in more orientations when the budget pays for them
    (:data:`RANDOM_FRAMES_BUDGET`)."""
    seeds = seed_vectors(points, normals, warm)
    if budget >= RANDOM_FRAMES_BUDGET:
        seeds = np.concatenate([seeds, random_frame_seeds(points, normals)])
    return seeds


def _check_spread(points: Array) -> None:
    """Reject contacts on one point or one line (a plane is fine: one face touched)."""
    centred = points - points.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    scale = max(float(np.abs(points).max()), 1e-300)
    if sv[0] <= 1e-12 * scale * np.sqrt(len(points)):
        raise InvalidInputError("`points` are all at one location: cannot fit a solid")
    if sv[1] <= LINE_TOLERANCE * sv[0]:
        raise InvalidInputError("`points` all lie on one line: cannot fit a solid")


def fit(
    points: Any,
    normals: Any | None = None,
    method: str = "nH",
    budget: int | None = None,
    rng: np.random.Generator | int | None = None,
    lam: float = DEFAULT_LAMBDA,
    initial: Superquadric | None = None,
    distance: str = DEFAULT_DISTANCE,
    noise: float | None = None,
    free: Any | None = None,
    options: MLOptions | None = None,
    sigma: Any | None = None,
    sigma_normal: Any | None = None,
    parts: int | str | None = None,
    uncertainty: bool = False,
    holes: bool = False,
) -> FitResult:
    """Fit a superquadric to contact points (and normals) with the paper's methods or nML, or a
    union of superquadrics with ``multi``.

    Args:
        points: (n, 3) float, contact locations [m, world], n >= 13 (one per parameter), finite,
            not all on one line.
        normals: (n, 3) float outward normals (normalised here), needed by nLS and nH; LS and H
            ignore them (they are still checked when given).
        method: ``"LS"``, ``"H"``, ``"nLS"`` or ``"nH"`` (SPEC §3), or ``"nML"``, the
            maximum-likelihood fit for noisy data (:mod:`hapticsim.fitting.ml`; needs normals),
            or ``"multi"``, a union of superquadrics (:mod:`hapticsim.fitting.multi`; needs
            normals; its one-part candidate is nH with this budget and seed), or ``"gpis"``,
            the zero level set of a Gaussian-process implicit surface as a mesh
            (:mod:`hapticsim.fitting.gpis`, extra ``gpis``; needs normals), or
            ``"supertoroid"``, a superquadric with a hole (:mod:`hapticsim.fitting.toroid`;
            needs normals).
        budget: EOF evaluations allowed (default :data:`~hapticsim.fitting.methods.DEFAULT_BUDGET`;
            for nML that plus its ML stages, :func:`method_budget`).
        rng: seed or generator of the genetic algorithm; the same seed gives the same result,
            bit for bit.
        lam: weight lambda of the normal term (SPEC §2), >= 0.
        initial: a warm start: LS and nLS start from it instead of the paper's initial estimate,
            H and nH add it to the seeds of the genetic algorithm.
        distance: how the search measures the contact distance D1: ``"untapered"`` is SPEC §2
            exactly; ``"tapered"`` measures the same radial distance on the tapered solid (see
            :func:`hapticsim.geometry.eof.contact_residuals`). The reported ``eof`` is always
            the SPEC §2 EOF of the estimate. nML measures orthogonal distances instead and
            ignores it (and `lam`).
        noise: nML and multi: the known relative sensor noise sigma_N (SPEC §5), finite and
            >= 0; None (default) estimates it from the residuals (nML reports it in the
            result's ``noise``; multi's criterion uses it).
        free: nML and multi: (f, 3) float free-space points [m, world], where the fingertip
            has been (its centre at the contacts, its approach path), which must lie outside
            the solid (multi: every part); None for none.
        options: nML only: its settings (default :class:`~hapticsim.fitting.ml.MLOptions`).
        sigma: nML only: (n,) float, each contact's standard deviation per coordinate [m], > 0
            (a tactile skin's estimate, ``contacts.npz``'s ``sigma``): the contacts' relative
            weights (:func:`~hapticsim.fitting.likelihood.contact_weights`); None: all alike.
        sigma_normal: nML only, with `sigma`: (n,) float, each normal's standard deviation
            [rad], > 0 (``contacts.npz``'s ``sigma_normal``): the normals' relative weights,
            and their level against the points' (SPEC §5's ``1 / mean(a)`` without it).
        parts: multi only: the number of parts, an int from 1 to :data:`MAX_FIT_PARTS`, or
            ``"auto"``/None (default) to choose up to
            :data:`~hapticsim.fitting.multi.MAX_PARTS` by the criterion.
        uncertainty: also compute the Laplace approximation of the estimate's uncertainty
            (:mod:`hapticsim.fitting.uncertainty`, outside the fit's ``seconds``); not for multi,
            gpis and supertoroid.
        holes: multi only: also weigh candidates with a ring (a supertoroid alone, or as a
            part of the union) and keep the one multi's criterion prefers
            (:func:`~hapticsim.fitting.toroid.choose_holed`; the costs in the selection record).

    Returns:
        The :class:`~hapticsim.fitting.result.FitResult`.

    Raises:
        InvalidInputError: any argument out of its domain; the message names it.
    """
    if not isinstance(method, str) or method not in FIT_METHODS:
        raise ChoiceError("method", method, FIT_METHODS)
    pts = physical_points(points, "points", min_count=N_PARAMS)
    nrm = None if normals is None else normals_array(normals, len(pts), "normals")
    if uses_normals(method) and nrm is None:
        raise InvalidInputError(f"method {method} needs `normals`; use LS or H for points only")
    if options is not None and not isinstance(options, MLOptions):
        raise InvalidInputError(f"`options` must be MLOptions, got {type(options).__name__}")
    n_evals = (
        method_budget(method, options) if budget is None
        else positive_int(budget, "budget", maximum=MAX_BUDGET)
    )  # fmt: skip
    gen = as_generator(rng)
    weight = finite_float(lam, "lam", low=0.0)
    warm = None if initial is None else superquadric_arg(initial, "initial")
    if distance not in DISTANCES:
        raise ChoiceError("distance", distance, DISTANCES)
    ml = method == "nML"
    multi = method in ("multi", "multi+track")
    if not ml and (options is not None or sigma is not None or sigma_normal is not None):
        raise InvalidInputError(
            f"`options`, `sigma` and `sigma_normal` are for method nML only, got method {method}"
        )
    if not (ml or multi) and (noise is not None or free is not None):
        raise InvalidInputError(
            f"`noise` and `free` are for methods nML and multi only, got method {method}"
        )
    part_count = _parts_arg(parts, multi)
    if holes and not multi:
        raise InvalidInputError(f"`holes` is for method multi only, got method {method}")
    if uncertainty and method in SOLID_METHODS:
        raise InvalidInputError(
            f"`uncertainty` is for one superquadric, not for method {method}"
        )
    noise_level = None if noise is None else finite_float(noise, "noise", low=0.0)
    free_pts = None if free is None else finite_array(free, "free", (None, 3))
    multipliers = ratio = None
    if sigma_normal is not None and sigma is None:
        raise InvalidInputError("`sigma_normal` needs `sigma` (the points' standard deviations)")
    if sigma is not None:
        contact_sigma = finite_array(sigma, "sigma", (len(pts),))
        if np.any(contact_sigma <= 0):
            raise InvalidInputError("`sigma` must be > 0 for every contact [m]")
        normal_sigma = None
        if sigma_normal is not None:
            normal_sigma = finite_array(sigma_normal, "sigma_normal", (len(pts),))
            if np.any(normal_sigma <= 0):
                raise InvalidInputError("`sigma_normal` must be > 0 for every contact [rad]")
            ratio = normal_ratio(contact_sigma, normal_sigma)
        multipliers = contact_weights(contact_sigma, normal_sigma)
    _check_spread(pts)
    spec = distance == "untapered" and not ml
    if not spec and n_evals < 2:
        raise InvalidInputError(f'`budget` must be >= 2 with distance="{distance}", got {n_evals}')

    if method in TRACK_METHODS:
        from hapticsim.fitting.track import fit_tracked

        if free_pts is not None or warm is not None:
            raise InvalidInputError(
                f"`free` and `initial` are world-frame hints, not for method {method} (the "
                "object moved)"
            )

        def fit_shape(base: str, p: Any, n: Any) -> FitResult:
            extra = {}
            if base == "multi":
                extra = {"parts": parts, "holes": holes, "noise": noise_level}
            return fit(p, n, method=base, budget=n_evals, rng=gen, lam=weight, **extra)

        return fit_tracked(method, pts, nrm, fit_shape, time.perf_counter(), lam=weight)
    setup = prepare(method)  # load (or compile) the kernels outside the fit's own time
    start = time.perf_counter()
    if multi:
        result = _fit_multi(pts, nrm, n_evals, gen, weight, warm, distance, noise_level,
                            free_pts, part_count, start)  # fmt: skip
        return _with_ring(result, pts, nrm, weight, start) if holes else result
    if method == "gpis":
        return _fit_gpis(pts, nrm, start)
    if method == "supertoroid":
        ring, eof, used = fit_supertoroid(pts, nrm, weight)
        return FitResult(solid=ring, method=method, eof=eof, evaluations=used,
                         seconds=time.perf_counter() - start, history=(np.zeros(0, np.int64),
                         np.zeros(0)), status="converged",
                         message="least squares from starts on each principal axis")  # fmt: skip
    # A search in another metric keeps one evaluation back to report the SPEC EOF.
    data_normals = nrm if uses_normals(method) else None
    run, kept = None, ""
    if ml:
        opt = MLOptions() if options is None else options
        checks = opt.guard is not None and opt.search == "eof"  # one more EOF: the basin's
        objective = ml_objective(pts, data_normals, n_evals - 1 - checks, noise_level, free_pts,
                                 options, multipliers, ratio)  # fmt: skip
        search = n_evals - default_budget(0, opt)  # the EOF search's share, as nH's budget
        run = ml_search(objective, hybrid_seeds(pts, nrm, warm, search), gen, noise_level,
                        options, multipliers, ratio)  # fmt: skip
        status = run.status
    elif method in HYBRID_METHODS:
        objective = Objective(pts, data_normals, weight, n_evals - (not spec), distance)
        seeds = hybrid_seeds(pts, objective.normals, warm, n_evals)
        _, status = hybrid_search(objective, seeds, gen, HybridOptions())
    else:
        objective = Objective(pts, data_normals, weight, n_evals - (not spec), distance)
        x0 = (warm if warm is not None else paper_initial(pts)).to_vector()
        status = least_squares_run(objective, x0).status
    best = objective.best_vector
    evaluations, eof = objective.evaluations, objective.best_eof
    if not spec:
        r = objective.contacts.residuals(best, weight, tapered=False)  # the SPEC §2 EOF
        eof, evaluations = float(np.mean(r**2)), evaluations + 1
    if run is not None and run.basin is not None and opt.guard is not None:
        r = objective.contacts.residuals(run.basin, weight, tapered=False)
        basin_eof, evaluations = float(np.mean(r**2)), evaluations + 1
        kept = guarded((eof, basin_eof), opt.guard)
        if kept:
            best, eof = run.basin, basin_eof
    seconds = time.perf_counter() - start
    posterior = None
    if uncertainty:

        posterior = laplace(Superquadric.from_vector(best), pts, data_normals, weight,
                            DEFAULT_DISTANCE if ml else distance)  # fmt: skip
    return FitResult(
        solid=Superquadric.from_vector(best),
        method=method,
        eof=eof,
        evaluations=evaluations,
        seconds=seconds,
        history=objective.history(),
        status=status,
        message=_MESSAGES[status] + (f"; kept the EOF search's solid: {kept}" if kept else ""),
        noise=None if run is None else run.noise,
        setup_seconds=setup,
        uncertainty=posterior,
    )


#: Most parts ``fit(..., method="multi", parts=K)`` takes.
MAX_FIT_PARTS: int = 16


def _parts_arg(parts: Any, multi: bool) -> int | None:
    """`parts` as a count, or None for "auto"."""
    if parts is None or parts == "auto":
        return None
    if not multi:
        raise InvalidInputError("`parts` is for method multi only")
    if isinstance(parts, bool) or not isinstance(parts, (int, np.integer)):
        raise InvalidInputError(f"`parts` must be an int or 'auto', got {parts!r}")
    if not 1 <= int(parts) <= MAX_FIT_PARTS:
        raise InvalidInputError(f"`parts` must be in [1, {MAX_FIT_PARTS}] or 'auto', got {parts}")
    return int(parts)


def _fit_multi(
    pts: Array, nrm: Array, budget: int, gen: np.random.Generator, lam: float,
    warm: Superquadric | None, distance: str, noise: float | None, free: Array | None,
    parts: int | None, start: float,
) -> FitResult:  # fmt: skip
    """multi: nH's one-part fit (the selection's baseline), then
    :func:`~hapticsim.fitting.multi.multi_search`."""

    single = fit(pts, nrm, "nH", budget, gen, lam, warm, distance)
    if parts == 1:
        vectors, record = [single.superquadric.to_vector()], {
            "parts": 1, "criterion": "one part asked for", "candidates": []}  # fmt: skip
    else:
        def part_fit(p: Array, n: Array, evals: int, rng: np.random.Generator) -> FitResult:
            return fit(p, n, "nH", evals, rng, lam)

        vectors, record = multi_search(pts, nrm, single.superquadric, gen, part_fit, parts,
                                       noise, free)  # fmt: skip
    shapes = (  # one part: nH's own superquadric, not its round trip through a vector
        (single.superquadric,) if len(vectors) == 1
        else tuple(Superquadric.from_vector(v) for v in vectors)
    )  # fmt: skip
    contacts = ContactSet.from_arrays(pts, nrm)
    r = contacts.residuals(np.array(vectors), lam, tapered=False)  # the parts' SPEC EOF terms
    selection = PartSelection(
        parts=int(record["parts"]), criterion=record["criterion"],
        candidates=tuple(record["candidates"]), baseline=single,
        sigma_distance=record.get("sigma_distance"), sigma_normal=record.get("sigma_normal"),
    )  # fmt: skip
    return FitResult(
        solid=SuperquadricUnion(shapes),
        method="multi",
        eof=float(np.mean(np.min(r**2, axis=0))),
        evaluations=single.evaluations + int(record.get("evaluations", 0)),
        seconds=time.perf_counter() - start,
        history=single.history,
        status=single.status,
        message=f"{len(shapes)} part(s) by {selection.criterion}",
        selection=selection,
    )


def _with_ring(result: FitResult, pts: Array, nrm: Array, lam: float, start: float) -> FitResult:
    """multi's union, or a candidate with a ring where it explains the contacts better
    (:func:`~hapticsim.fitting.toroid.choose_holed`)."""
    from dataclasses import replace

    from hapticsim.fitting.multi import DISTANCE_FLOOR, NORMAL_FLOOR

    sel = result.selection
    assert sel is not None
    sigma_d, sigma_n = sel.sigma_distance, sel.sigma_normal
    if sigma_d is None or sigma_n is None:  # one part asked for: the criterion's floors
        sigma_d = DISTANCE_FLOOR * float(np.mean(sel.baseline.superquadric.a))
        sigma_n = NORMAL_FLOOR
    chosen, record = choose_holed(result.solid, pts, nrm, sigma_d, sigma_n, lam)
    used = record["evaluations"]
    if chosen is not result.solid:
        rings = [p for p in chosen.components if p.kind == "supertoroid"]
        vectors = [p.to_vector() for p in chosen.components if p.kind == "superquadric"]
        terms = [toroid_residuals(p, pts, nrm, lam) ** 2 for p in rings]
        if vectors:  # the superquadric parts' SPEC EOF terms
            contacts = ContactSet.from_arrays(pts, nrm)
            terms.extend(contacts.residuals(np.array(vectors), lam, tapered=False) ** 2)
        eof = float(np.mean(np.min(np.stack(terms), axis=0)))  # each contact's nearest part
        message = f"{record['chosen']}, by the criterion against the union"
    else:
        eof, message = result.eof, result.message
    return replace(result, solid=chosen, eof=eof, evaluations=result.evaluations + used,
                   seconds=time.perf_counter() - start, message=message,
                   selection=replace(sel, holes=record))  # fmt: skip


def _fit_gpis(pts: Array, nrm: Array, start: float) -> FitResult:
    """gpis: :func:`~hapticsim.fitting.gpis.fit_gpis`'s mesh alone. Its EOF is the contacts'
    mean squared distance to the mesh; it evaluates no superquadric EOF."""

    surface = fit_gpis(pts, nrm)
    distance = surface.solid.surface_distance(pts)
    converged = surface.info.get("converged", True)
    return FitResult(
        solid=surface.solid,
        method="gpis",
        eof=float(np.mean(distance**2)),
        evaluations=0,
        seconds=time.perf_counter() - start,
        history=(np.zeros(0, np.int64), np.zeros(0)),
        status="converged" if converged else "iterations",
        message=(f"zero level set of a GPIS (length scale {1e3 * surface.length_scale:.1f} mm), "
                 f"{len(surface.solid.faces)} faces"),
        model=surface.to_dict(),
    )  # fmt: skip


_MESSAGES = {
    "converged": "least squares converged",
    "budget": "evaluation budget used up",
    "stall": "genetic algorithm stalled",
    "generations": "generation limit reached",
    "target": "target EOF reached",
    "iterations": "least-squares step limit reached",
}
