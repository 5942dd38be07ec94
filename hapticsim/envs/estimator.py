"""The fit inside the exploration loop: full robust fits where they pay, warm starts otherwise.

A full ``nH`` fit (genetic algorithm + least squares, paper Section II) is robust but costs
thousands of error-of-fit evaluations; after one touch the previous estimate is usually close, so
a least-squares refinement warm-started from it (``fit(..., initial=previous)``) is enough. The
:class:`FitSchedule` decides: no fit below ``min_contacts`` contacts (a superquadric has 13
parameters); a full fit (its genetic algorithm seeded with the previous estimate too) on the
first touch with enough contacts, whenever the new contacts *surprise* the current estimate, and
at least every ``full_every`` touches; a warm-started refinement otherwise. New contacts surprise
when their RMS residual (paper eq. 9) on the current estimate exceeds ``surprise`` times the RMS
residual of the contacts it was fitted to, and ``surprise_floor`` times its mean semi-axis: the
estimate is wrong where the finger just was (beyond the sensor noise, which both residuals
share), and a local refinement would stay in its basin. Optionally (``keep``), contacts that
agree with the estimate as well as the old ones cause no refit at all.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import ChoiceError, HapticsimError, InvalidInputError
from hapticsim.geometry import N_PARAMS, Superquadric
from hapticsim.geometry.eof import contact_residuals
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]

#: What a fit update did.
FIT_STATUSES: tuple[str, ...] = ("too_few_contacts", "full", "refine", "kept", "failed")
#: The methods a schedule accepts (SPEC §3). Every touch records a normal (exact backends measure
#: it, the tactile one estimates it from the taxel image); LS and H ignore them. ``multi`` for full
#: fits only (:mod:`hapticsim.fitting.multi`).
_METHODS: tuple[str, ...] = ("nH", "nLS", "H", "LS", "multi")


@dataclass(frozen=True)
class FitSchedule:
    """When and how the environment refits.

    Attributes:
        method: method of the full fits (SPEC §3), default ``"nH"``; ``"multi"`` fits a union
            of superquadrics (:mod:`hapticsim.fitting.multi`): the estimate is then its one-part
            candidate (what the observation shows and refinements start from) and the solid
            scored is the union of the last full fit.
        refine_method: method of the warm-started refinements, default ``"nLS"`` (not
            ``"multi"``).
        full_every: a full fit at least every this many touches after the previous full one; 1
            makes every fit full.
        surprise: a full fit when the new contacts' RMS residual on the current estimate exceeds
            this multiple of the estimate's own RMS residual (``sqrt(EOF)``); ``inf`` turns
            this off.
        surprise_floor: ... and this fraction of the estimate's mean semi-axis.
        keep: no refit at all when the new contacts' RMS residual is at most this multiple of
            the estimate's own (they agree with it as well as the old contacts); 0 turns this
            off.
        full_budget: evaluation budget of a full fit (None: the fitter's default).
        refine_budget: evaluation budget of a refinement (None: the fitter's default).
        min_contacts: fewest contacts to fit (13 parameters: at least 13).
    """

    method: str = "nH"
    refine_method: str = "nLS"
    full_every: int = 10
    surprise: float = 3.0
    surprise_floor: float = 0.05
    keep: float = 1.0
    full_budget: int | None = 3000
    refine_budget: int | None = 200
    min_contacts: int = N_PARAMS

    def __post_init__(self) -> None:
        for name in ("method", "refine_method"):
            if getattr(self, name) not in _METHODS:
                raise ChoiceError(name, getattr(self, name), _METHODS)
        if self.refine_method == "multi":
            raise InvalidInputError("`refine_method` must fit one superquadric, not 'multi'")
        if isinstance(self.full_every, bool) or int(self.full_every) < 1:
            raise InvalidInputError(f"`full_every` must be an int >= 1, got {self.full_every!r}")
        for name in ("full_budget", "refine_budget"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or int(value) < 1):
                raise InvalidInputError(f"`{name}` must be None or an int >= 1, got {value!r}")
        if not (self.surprise > 0):
            raise InvalidInputError(f"`surprise` must be > 0 (inf: off), got {self.surprise!r}")
        if not (0 <= self.keep < np.inf):
            raise InvalidInputError(f"`keep` must be finite and >= 0, got {self.keep!r}")
        if not (0 <= self.surprise_floor < np.inf):
            raise InvalidInputError(
                f"`surprise_floor` must be finite and >= 0, got {self.surprise_floor!r}"
            )
        if isinstance(self.min_contacts, bool) or int(self.min_contacts) < N_PARAMS:
            raise InvalidInputError(
                f"`min_contacts` must be an int >= {N_PARAMS}, got {self.min_contacts!r}"
            )


@dataclass(frozen=True)
class FitUpdate:
    """The outcome of one :meth:`IncrementalFitter.update`.

    Attributes:
        estimate: the current estimate (None before the first fit).
        eof: its error of fit on all contacts so far [m^2] (0.0 without an estimate).
        status: one of :data:`FIT_STATUSES`.
        evaluations: EOF evaluations the update used.
        seconds: wall-clock time of the update [s].
        message: the fitter's complaint when ``status == "failed"``.
        solid: the estimated solid: `estimate` itself, or with ``multi`` full fits the union
            of the last one (None before the first fit).
    """

    estimate: Superquadric | None
    eof: float
    status: str
    evaluations: int = 0
    seconds: float = 0.0
    message: str = ""
    solid: Solid | None = None

    def __post_init__(self) -> None:
        if self.solid is None and self.estimate is not None:
            object.__setattr__(self, "solid", self.estimate)


class IncrementalFitter:
    """Keeps the estimate of one episode up to date as contacts arrive.

    Args:
        schedule: the fit schedule.
    """

    def __init__(self, schedule: FitSchedule | None = None) -> None:
        self.schedule = schedule or FitSchedule()
        self.reset()

    def reset(self) -> None:
        """Forget the estimate (new episode)."""
        self.estimate: Superquadric | None = None
        self.solid: Solid | None = None
        self.eof = 0.0
        self._touches_since_full = 0

    def _rms(self, points: Array, normals: Array) -> float:
        """RMS residual (paper eq. 9) of contacts on the current estimate [m]."""
        est = self.estimate
        assert est is not None
        r = contact_residuals(points, normals, est.a, est.eps, est.taper, est.rotation, est.center)
        return float(np.sqrt(np.mean(r**2)))

    def update(
        self, points: Array, normals: Array, rng: np.random.Generator, new_contacts: int = 1
    ) -> FitUpdate:
        """Refit after a touch.

        Args:
            points: (n, 3) float, all contacts so far [m, world].
            normals: (n, 3) float, their outward unit normals.
            rng: generator for the fitter's seed (one draw per fit).
            new_contacts: how many of the contacts the last touch brought (the last rows); with
                none the estimate is kept.

        Returns:
            the update.
        """
        from hapticsim.fitting import fit

        start = time.perf_counter()
        sched = self.schedule
        if len(points) < sched.min_contacts:
            return FitUpdate(None, 0.0, "too_few_contacts")
        self._touches_since_full += 1
        if self.estimate is not None and new_contacts <= 0:
            return FitUpdate(self.estimate, self.eof, "kept", solid=self.solid)
        full = self.estimate is None or self._touches_since_full >= sched.full_every
        if not full:
            rms_new = self._rms(points[-new_contacts:], normals[-new_contacts:])
            rms_fit = np.sqrt(self.eof)
            floor = sched.surprise_floor * float(np.mean(self.estimate.a))
            full = rms_new > sched.surprise * rms_fit and rms_new > floor
            if not full and rms_new <= sched.keep * rms_fit:
                # The new contacts agree with the estimate as well as the old ones: keep it.
                self.eof = self._rms(points, normals) ** 2
                return FitUpdate(self.estimate, self.eof, "kept", 1, time.perf_counter() - start,
                                 solid=self.solid)  # fmt: skip
        seed = int(rng.integers(2**31 - 1))
        method = sched.method if full else sched.refine_method
        budget = sched.full_budget if full else sched.refine_budget
        try:
            result = fit(
                points, normals, method=method, budget=budget, rng=seed, initial=self.estimate
            )
        except HapticsimError as exc:
            return FitUpdate(
                self.estimate, self.eof, "failed", 0, time.perf_counter() - start, str(exc),
                self.solid,
            )  # fmt: skip
        if full:
            self._touches_since_full = 0
        # the observation's superquadric: the estimate, or multi's one-part baseline
        kept = result if result.selection is None else result.selection.baseline
        self.estimate = kept.superquadric
        # multi's union stays until its next full fit; a single superquadric is its own solid
        if full or sched.method != "multi":
            self.solid = result.solid
        self.eof = float(result.eof)
        return FitUpdate(
            self.estimate, self.eof, "full" if full else "refine", int(result.evaluations),
            time.perf_counter() - start, solid=self.solid,
        )  # fmt: skip
