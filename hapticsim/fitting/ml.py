"""nML: a maximum-likelihood (MAP) fit for noisy contact data, on the hybrid search of nH.

The objective is :mod:`hapticsim.fitting.likelihood`'s (orthogonal distances and normal
differences weighted by the sensor noise, a robust loss, weak priors on the tapers and shape
exponents, free space); the search reuses the one of nH
(:func:`~hapticsim.fitting.hybrid.hybrid_search`: seed steps, genetic algorithm, probes,
polish), with the same budget, counting and seeds. The steps (default :class:`MLOptions`):

1. *basins*: nH's hybrid search on the paper EOF (``distance="tapered"``) with all but
   :attr:`MLOptions.ml_budget` + :attr:`MLOptions.refine_budget` evaluations: its seed steps and
   crowding genetic algorithm find the EOF's basins reliably, where a search on the ML objective
   itself (``search="ml"``) stops in a wrong one far more often (``docs/nml/README.md``);
2. *choice*: its best and up to :attr:`MLOptions.candidates` distinct solids of its last
   generation take :attr:`MLOptions.probe_steps` Levenberg-Marquardt steps on the ML objective
   (sigma_N the given noise or :attr:`MLOptions.initial_noise`, length scale ``L = s / sqrt(3)``
   from the data size s, the largest distance of a contact from the centroid: a cube touched
   all round has ``s ~ sqrt(3) a``), and the lowest is polished on it;
3. *re-estimate*: ``L = mean(a)`` of the result (SPEC §5's noise scale) and, when the noise was
   not given, sigma_N from the residuals (:func:`~hapticsim.fitting.likelihood.estimate_noise`,
   at least :attr:`MLOptions.noise_floor`), then least squares under the new weights;
   :attr:`MLOptions.refine` rounds.

The estimate minimises the ML objective, not the EOF (the EOF only proposes starting basins). The
fit reports the SPEC §2 EOF of its estimate like every method, and the noise level it used; its
history holds the ML stages' cost (``sum(r^2) / n``), after the EOF search's evaluations.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.fitting.hybrid import HybridOptions, distinct_starts, hybrid_search
from hapticsim.fitting.least_squares import (
    MIN_RUN_EVALUATIONS,
    STEP_EVALUATIONS,
    least_squares_run,
    multi_start_run,
)
from hapticsim.fitting.likelihood import (
    Likelihood,
    anchor_gap,
    estimate_noise,
    extent_anchor,
)
from hapticsim.fitting.objective import Objective
from hapticsim.geometry.superquadric import SLICE_A

Array = NDArray[np.float64]


#: The noise level sigma_N at which :attr:`MLOptions.anchor` is the anchor's std in units of L
#: (it scales as 1 / sigma_N).
ANCHOR_NOISE: float = 0.1

#: Where nML's search finds its basins (:attr:`MLOptions.search`).
SEARCHES: tuple[str, ...] = ("eof", "ml")


@dataclass(frozen=True)
class MLOptions:
    """Settings of nML (:func:`ml_search`); the defaults are what the ablation
    (``docs/nml/README.md``) chose on tuning seeds.

    Attributes:
        robust: pseudo-Huber threshold c on a contact's normalised residual norm, >= 0
            (0: plain least squares).
        taper_prior: std of the Gaussian prior on each taper, > 0, or None (no prior).
        eps_prior: ``(eps_0, tau_e)``, the Gaussian prior on each shape exponent, or None.
        initial_noise: sigma_N assumed by the search when the noise is not given, > 0.
        noise_floor: smallest sigma_N used (clean data would give infinite weights), > 0.
        refine: re-estimation rounds after the search, >= 0.
        refine_budget: evaluations kept back for them, >= 0.
        free_margin: how far outside the solid [m] free-space points must lie.
        normal_factor: the normal residuals' noise in units of sigma_N, > 0
            (:class:`~hapticsim.fitting.likelihood.Likelihood`).
        search: ``"eof"``: the hybrid search runs on the paper's EOF (nH's search, whose
            genetic algorithm and seed steps find its basins reliably), then
            :attr:`candidates` distinct solids of its last generation and its best are
            probed and polished on the ML objective, which picks the basin; ``"ml"``: the
            hybrid search runs on the ML objective itself (measured: it stops in a wrong basin
            more often, ``docs/nml/README.md``).
        candidates: distinct solids of the EOF search's last generation probed, >= 1.
        probe_steps: Levenberg-Marquardt steps of each ML probe, >= 1.
        ml_budget: with ``search="eof"``, the evaluations kept for the ML stages, >= 1.
        anchor: std of the extent anchor in units of the length scale L at sigma_N =
            :data:`ANCHOR_NOISE`, > 0, or None (no anchor). With ``search="eof"`` the ML
            stages are held by a Gaussian prior of std
            ``tau_x = anchor * L * ANCHOR_NOISE / sigma_N`` on each semi-axis and centre
            coordinate to the extents of the EOF search's best solid
            (:func:`~hapticsim.fitting.likelihood.extent_anchor`), and the basin is chosen by
            the ML cost plus that prior: the orthogonal distance has no term that holds a face
            no contact touched, and on one-sided data it stretched such faces to twice their
            size (``docs/nml/README.md``). Where contacts fix a face, their weight
            ``~ m / sigma_p^2`` outweighs the anchor's; the anchor loosens as the noise falls,
            where the rigid shape model carries the seen curvature over to the unseen side.
        guard: with ``search="eof"``, the EOF search's best solid is returned instead of the ML
            estimate when the estimate's paper EOF is over this many times the search's
            (:func:`guarded`), > 0; None: always the ML estimate. The ML terms (the noise floor,
            the robust loss, the priors) can pull a near-exact fit off clean data: at sigma_N =
            0 on the held-out sets of ``scripts/nml_heldout.py`` nML's mean epsilon is 0.029
            (v3) and 0.025 (guard) without it, 0.024 and 0.018 with it (nH: 0.039, 0.018;
            ``docs/nml/README.md``); where the EOFs are within a factor of 3 (noisy data, the
            estimate's EOF 0.85-1.6 times the search's) nothing changes.
        hybrid: settings of the search.
    """

    robust: float = 2.0
    taper_prior: float | None = 0.3
    eps_prior: tuple[float, float] | None = None
    initial_noise: float = 0.05
    noise_floor: float = 0.005
    refine: int = 2
    refine_budget: int = 600
    free_margin: float = 0.0
    normal_factor: float = 2.0**0.5
    search: str = "eof"
    candidates: int = 6
    probe_steps: int = 8
    ml_budget: int = 1500
    anchor: float | None = 0.1
    guard: float | None = 3.0
    hybrid: HybridOptions | None = None

    def __post_init__(self) -> None:
        if not (self.initial_noise > 0 and self.noise_floor > 0):
            raise InvalidInputError(
                f"`initial_noise` and `noise_floor` must be > 0, got {self.initial_noise} and "
                f"{self.noise_floor}"
            )
        if self.refine < 0 or self.refine_budget < 0:
            raise InvalidInputError(
                f"`refine` and `refine_budget` must be >= 0, got {self.refine} and "
                f"{self.refine_budget}"
            )
        if self.search not in SEARCHES:
            raise ChoiceError("search", self.search, SEARCHES)
        if self.candidates < 1 or self.probe_steps < 1 or self.ml_budget < 1:
            raise InvalidInputError(
                f"`candidates`, `probe_steps` and `ml_budget` must be >= 1, got "
                f"{self.candidates}, {self.probe_steps} and {self.ml_budget}"
            )
        if self.anchor is not None and not (np.isfinite(self.anchor) and self.anchor > 0):
            raise InvalidInputError(f"`anchor` must be > 0 or None, got {self.anchor!r}")
        if self.guard is not None and not (np.isfinite(self.guard) and self.guard > 0):
            raise InvalidInputError(f"`guard` must be > 0 or None, got {self.guard!r}")
        self.likelihood(0.1, 1.0)  # validates robust, the priors and the margin

    def likelihood(
        self, noise: float, length: float, multipliers: Array | None = None,
        normal_ratio: float | None = None, anchor: Array | None = None,
    ) -> Likelihood:  # fmt: skip
        """The :class:`~hapticsim.fitting.likelihood.Likelihood` at a noise level and scale,
        with per-contact weight multipliers, the normals' noise per metre of the points'
        (``normal_factor = normal_ratio * length`` instead of :attr:`normal_factor`) and the
        extent anchor (std :meth:`anchor_sigma`; ignored when :attr:`anchor` is None) when
        given."""
        factor = self.normal_factor if normal_ratio is None else normal_ratio * length
        held = anchor is not None and self.anchor is not None
        noise = max(noise, self.noise_floor)
        return Likelihood(
            noise=noise, length=length, robust=self.robust,
            taper_prior=self.taper_prior, eps_prior=self.eps_prior, free_margin=self.free_margin,
            normal_factor=factor, multipliers=multipliers, anchor=anchor if held else None,
            anchor_sigma=self.anchor_sigma(noise, length) if held else 1.0,
        )  # fmt: skip

    def anchor_sigma(self, noise: float, length: float) -> float:
        """The extent anchor's std tau_x [m] at a noise level and length scale (:attr:`anchor`;
        requires it set)."""
        assert self.anchor is not None
        return self.anchor * length * ANCHOR_NOISE / max(noise, self.noise_floor)


@dataclass(frozen=True)
class MLRun:
    """Outcome of :func:`ml_search`.

    Attributes:
        status: the status of the last least-squares run (or of the search).
        noise: the sigma_N of the final weights (given, or estimated and floored).
        estimated: whether it was estimated from the residuals.
        length: the final length scale L [m].
        basin: with ``search="eof"``, the EOF search's best vector (13,) (what
            :attr:`MLOptions.guard` may return instead), else None.
    """

    status: str
    noise: float
    estimated: bool
    length: float
    basin: Array | None = None


def ml_search(
    objective: Objective,
    seeds: Array,
    rng: np.random.Generator,
    noise: float | None,
    options: MLOptions | None = None,
    multipliers: Array | None = None,
    normal_ratio: float | None = None,
) -> MLRun:
    """Minimise the ML objective within the objective's budget (module docstring).

    Args:
        objective: an :class:`~hapticsim.fitting.objective.Objective` with ML settings (from
            :meth:`MLOptions.likelihood` with the starting noise and length); its best vector is
            the result.
        seeds: (k, 13) start vectors of the search.
        rng: the generator of every random choice.
        noise: the known sigma_N, or None to estimate it.
        options: settings (default :class:`MLOptions`).
        multipliers: (2, n) per-contact weight multipliers
            (:func:`~hapticsim.fitting.likelihood.contact_weights`), or None.
        normal_ratio: the normals' noise per metre of the points'
            (:func:`~hapticsim.fitting.likelihood.normal_ratio`), or None (SPEC §5's).
    """
    opt = MLOptions() if options is None else options
    if not objective.ml:
        raise InvalidInputError("ml_search needs an objective with ML settings")
    total = objective.budget
    keep = min(opt.refine_budget, total // 4) if opt.refine else 0
    given = noise is not None
    sigma = float(noise) if given else opt.initial_noise
    length = objective.bounds.size / np.sqrt(3.0)
    anchor, basin = None, None
    if opt.search == "eof":
        def penalty(start: Array, reference: Array) -> float:
            if opt.anchor is None:
                return 0.0
            gap = anchor_gap(start, extent_anchor(start, reference))
            return float(np.sum(gap**2)) / opt.anchor_sigma(sigma, length) ** 2

        def hold(start: Array, reference: Array) -> None:
            nonlocal anchor
            if opt.anchor is not None:
                anchor = extent_anchor(start, reference)
                objective.reweight(
                    opt.likelihood(sigma, length, multipliers, normal_ratio, anchor).settings()
                )

        status, basin = _eof_search(objective, seeds, rng, opt, total - keep, penalty, hold)
    else:
        objective.budget = total - keep  # the search leaves `keep` for the refinement
        try:
            _, status = hybrid_search(objective, seeds, rng, opt.hybrid)
        finally:
            objective.budget = total
    for _ in range(opt.refine):
        if objective.remaining < MIN_RUN_EVALUATIONS:
            break
        best = objective.best_vector
        length = float(np.mean(best[SLICE_A]))
        if not given:
            sigma = estimate_noise(objective.contacts, best, length, multipliers)
        objective.reweight(
            opt.likelihood(sigma, length, multipliers, normal_ratio, anchor).settings()
        )
        status = least_squares_run(objective, best).status
    return MLRun(status=status, noise=max(sigma, opt.noise_floor), estimated=not given,
                 length=length, basin=basin)  # fmt: skip


def _eof_search(
    objective: Objective, seeds: Array, rng: np.random.Generator, opt: MLOptions, cap: int,
    penalty: Callable[[Array, Array], float], hold: Callable[[Array, Array], None],
) -> tuple[str, Array]:  # fmt: skip
    """nH's search on the paper EOF, then ML probes from its distinct solids and an ML polish,
    all within `cap` evaluations counted on `objective`. The probes are ranked by their ML cost
    plus ``penalty(probe, best)`` (the extent anchor's prior against the EOF search's best), and
    ``hold(start, best)`` is called before the polish (it sets the anchor). Returns the status
    and the EOF search's best vector."""
    total, ml_share = objective.budget, min(opt.ml_budget, cap // 2)
    eof = Objective(objective.points, objective.normals, DEFAULT_LAMBDA, cap - ml_share, "tapered")
    run, status = hybrid_search(eof, seeds, rng, opt.hybrid)
    objective.record(eof.evaluations, np.empty((0, 13)), np.empty(0))
    starts = [eof.best_vector, *distinct_starts(run, opt.candidates, objective.bounds.size)]
    objective.budget = cap
    try:
        x = np.array(starts)
        probe = len(x) * (1 + opt.probe_steps * STEP_EVALUATIONS)
        if len(x) > 1 and objective.remaining >= probe + MIN_RUN_EVALUATIONS:
            x, cost = multi_start_run(objective, x, opt.probe_steps)
            held = np.array([penalty(v, eof.best_vector) for v in x]) / objective.count
            x = x[np.argsort(cost + held, kind="stable")]
        if objective.remaining >= MIN_RUN_EVALUATIONS:
            hold(x[0], eof.best_vector)
            status = least_squares_run(objective, x[0]).status
    finally:
        objective.budget = total
    return status, eof.best_vector


def default_budget(search_budget: int, options: MLOptions | None = None) -> int:
    """The budget at which nML's EOF search gets `search_budget` evaluations: with nH's default
    budget (:data:`~hapticsim.fitting.methods.DEFAULT_BUDGET`) that search *is* nH's default fit
    (same seeds, random stream, budget and search), so the guard weighs the ML estimate against
    nH's own answer; the ML stages, the refinement and the guard's check come on top
    (:attr:`MLOptions.ml_budget` + :attr:`MLOptions.refine_budget` + 1). With
    ``search="ml"`` there is no EOF search: `search_budget` itself."""
    opt = MLOptions() if options is None else options
    if opt.search != "eof":
        return int(search_budget)
    keep = opt.refine_budget if opt.refine else 0
    return int(search_budget) + opt.ml_budget + keep + (opt.guard is not None)


def guarded(eofs: tuple[float, float], ratio: float) -> str:
    """Why nML should return the EOF search's best solid instead of its ML estimate, or ""
    when it should not (:attr:`MLOptions.guard`): `eofs` are the paper EOFs [m^2] of the ML
    estimate and of the search's best, and the estimate's is over `ratio` times the other's."""
    if eofs[0] > ratio * eofs[1]:
        return f"the ML estimate's EOF was {eofs[0] / max(eofs[1], 1e-300):.3g} times the search's"
    return ""


def ml_objective(
    points: Array,
    normals: Array | None,
    budget: int,
    noise: float | None,
    free: Array | None,
    options: MLOptions | None = None,
    multipliers: Array | None = None,
    normal_ratio: float | None = None,
) -> Objective:
    """The :class:`~hapticsim.fitting.objective.Objective` nML starts with: ML weights at the
    given (or assumed) noise and the data-size length scale (and per-contact multipliers),
    tapered distance."""
    opt = MLOptions() if options is None else options
    probe = Objective(points, normals, 0.0, 1, "tapered")
    length = probe.bounds.size / np.sqrt(3.0)
    sigma = opt.initial_noise if noise is None else noise
    settings = opt.likelihood(sigma, length, multipliers, normal_ratio).settings()
    return Objective(points, normals, 0.0, budget, "tapered", settings=settings, free=free)


def with_options(options: MLOptions | None, **changes: object) -> MLOptions:
    """A copy of `options` (default :class:`MLOptions`) with fields changed (the ablation)."""
    return replace(MLOptions() if options is None else options, **changes)


__all__ = ["ANCHOR_NOISE", "MLOptions", "MLRun", "default_budget", "guarded", "ml_objective",
           "ml_search", "with_options"]
