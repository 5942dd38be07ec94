"""The result of a fit: :class:`FitResult` (like scipy's ``OptimizeResult``, but frozen)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.geometry.solid import Solid
from hapticsim.geometry.superquadric import Superquadric

#: Values of :attr:`FitResult.status`.
STATUSES: tuple[str, ...] = (
    "converged", "budget", "iterations", "stall", "generations", "target",
)  # fmt: skip


@dataclass(frozen=True, eq=False)
class PartSelection:
    """How ``multi`` chose its number of parts (:func:`hapticsim.fitting.multi.multi_search`).

    Attributes:
        parts: the number of parts of the estimate.
        criterion: the rule that chose it, in words.
        candidates: per part count tried, ``{"parts", "how", "seconds", "cost"}``.
        baseline: nH's one-part fit of all contacts, the criterion's first candidate (its own
            :class:`FitResult`: estimate, EOF, evaluations, history).
        sigma_distance, sigma_normal: the criterion's noise scales ([m], [1]), None where one
            part was asked for.
        holes: with ``holes=True``: every candidate's cost by the same criterion, its ring's
            inner-wall share, the candidate chosen and the rings' evaluations
            (:func:`hapticsim.fitting.toroid.choose_holed`); else None.
    """

    parts: int
    criterion: str
    candidates: tuple[dict[str, Any], ...]
    baseline: FitResult
    sigma_distance: float | None = None
    sigma_normal: float | None = None
    holes: dict[str, Any] | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the keys above, ``baseline`` as its fit result's JSON."""
        return {
            "parts": int(self.parts),
            "criterion": self.criterion,
            "candidates": list(self.candidates),
            "sigma_distance": self.sigma_distance,
            "sigma_normal": self.sigma_normal,
            "baseline": self.baseline.to_dict(),
            **({} if self.holes is None else {"holes": self.holes}),
        }


@dataclass(frozen=True, eq=False)
class FitResult:
    """One estimated solid and how it was found.

    Attributes:
        solid: the estimate (SPEC §10): a superquadric for the one-part methods, ``multi``'s
            union, ``gpis``'s mesh.
        method: the method name (one of :data:`hapticsim.fitting.methods.METHODS`).
        eof: its error of fit [m^2] (SPEC §2; with normals for nLS and nH, without for LS, H;
            ``multi``: each contact's smallest over the parts; ``gpis``: the contacts' mean
            squared distance to the mesh).
        evaluations: EOF evaluations used (SPEC §3), <= the budget (``gpis``: 0).
        seconds: wall-clock time of the fit [s], without getting its compiled kernels ready.
        history: ``(evaluations (k,) int, best EOF so far (k,) float)``, after each call of the
            EOF (a population or a single vector), in the search's own metric (the EOF with the
            ``distance`` the fit searched with; without taper it equals the SPEC EOF). Empty for
            ``gpis``; ``multi``: its baseline's.
        status: why the fit stopped, one of :data:`STATUSES`: ``"converged"`` (least squares
            met its tolerances; ``gpis``: its hyperparameter search did), ``"budget"``
            (evaluations used up), ``"iterations"`` (least squares reached its step limit,
            ``least_squares.MAX_ITERATIONS``), or the genetic algorithm's
            ``"stall"``, ``"generations"``, ``"target"`` when nothing was left to polish.
        message: a sentence on the same.
        noise: nML only: the relative noise level sigma_N its weights used (given, or estimated
            from the residuals); None for the paper's methods.
        selection: ``multi`` only: how the number of parts was chosen, with the one-part
            baseline (:class:`PartSelection`), else None.
        setup_seconds: wall-clock time spent before the fit loading its compiled kernels from
            numba's cache, or compiling them on a fresh installation
            (:func:`hapticsim.fitting.kernels.prepare`; 0 once a process has them).
        uncertainty: with ``fit(..., uncertainty=True)``, the Laplace approximation at the
            optimum (:class:`~hapticsim.fitting.uncertainty.Uncertainty`), else None.
        model: ``gpis`` only: the Gaussian process's hyperparameters and the mesh's size
            (:meth:`~hapticsim.fitting.gpis.GpisFit.to_dict`), else None.
        poses: ``nH+track`` and ``multi+track`` only (SPEC §12): (n, 7) float, the object
            frame's position [m] and quaternion (w first) in the world at each contact (the
            solid is in that frame), else None.
    """

    solid: Solid
    method: str
    eof: float
    evaluations: int
    seconds: float
    history: tuple[NDArray[np.int64], NDArray[np.float64]]
    status: str
    message: str = ""
    noise: float | None = None
    selection: PartSelection | None = None
    setup_seconds: float = 0.0
    uncertainty: Any = None
    model: dict[str, Any] | None = None
    poses: Any = None

    def __post_init__(self) -> None:
        if not isinstance(self.solid, Solid):
            raise InvalidInputError(f"`solid` must be a solid, got {type(self.solid).__name__}")
        if self.selection is not None and not isinstance(self.selection, PartSelection):
            raise InvalidInputError(
                f"`selection` must be a PartSelection, got {type(self.selection).__name__}"
            )
        if self.status not in STATUSES:
            raise ChoiceError("status", self.status, STATUSES)
        evals, best = (np.asarray(h) for h in self.history)
        if evals.shape != best.shape or evals.ndim != 1:
            raise InvalidInputError(
                "`history` must be two 1-D arrays of one length, got shapes "
                f"{evals.shape} and {best.shape}"
            )
        for arr in (evals, best):
            arr.setflags(write=False)
        object.__setattr__(self, "history", (evals, best))
        object.__setattr__(self, "eof", float(self.eof))
        object.__setattr__(self, "evaluations", int(self.evaluations))
        object.__setattr__(self, "seconds", float(self.seconds))
        object.__setattr__(self, "setup_seconds", float(self.setup_seconds))

    @property
    def superquadric(self) -> Superquadric:
        """The estimate where it is one superquadric (:attr:`solid`).

        Raises:
            AttributeError: the estimate is a union or a mesh; it names where to look instead.
        """
        if isinstance(self.solid, Superquadric):
            return self.solid
        where = (
            "; its one-part nH fit is .selection.baseline" if self.selection is not None else ""
        )
        raise AttributeError(
            f"the {self.method} estimate is a {self.solid.kind}, not one superquadric: use "
            f".solid{where}"
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``solid`` (SPEC §10), ``superquadric`` where the estimate is one (the
        same object, SPEC §6), ``method, eof, evaluations, seconds``, ``status`` and
        ``message``, ``setup_seconds``, ``noise`` for nML, ``selection`` for multi and ``model``
        for gpis (the history is left out: see :attr:`history`)."""
        one = {"superquadric": self.solid.to_dict()} if isinstance(self.solid, Superquadric) else {}
        extra: dict[str, Any] = {} if self.noise is None else {"noise": float(self.noise)}
        if self.selection is not None:
            extra["selection"] = self.selection.to_dict()
        if self.uncertainty is not None:
            extra["uncertainty"] = self.uncertainty.to_dict()
        if self.model is not None:
            extra["model"] = self.model
        if self.poses is not None:
            extra["poses"] = np.asarray(self.poses, dtype=np.float64).round(9).tolist()
        return {
            **one,
            "solid": self.solid.to_dict(),
            "method": self.method,
            "eof": self.eof,
            "evaluations": self.evaluations,
            "seconds": self.seconds,
            "setup_seconds": self.setup_seconds,
            "status": self.status,
            "message": self.message,
            **extra,
        }
