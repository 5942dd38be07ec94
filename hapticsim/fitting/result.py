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
class FitResult:
    """A fitted superquadric (or union) and how it was found.

    Attributes:
        superquadric: the estimate; for ``multi`` and ``gpis``, the one-part candidate
            (nH's fit) beside the :attr:`solid`.
        method: the method name (one of :data:`hapticsim.fitting.methods.METHODS`).
        eof: its error of fit [m^2] (SPEC §2; with normals for nLS and nH, without for LS, H).
        evaluations: EOF evaluations used (SPEC §3), <= the budget.
        seconds: wall-clock time of the fit [s], without getting its compiled kernels ready.
        history: ``(evaluations (k,) int, best EOF so far (k,) float)``, after each call of the
            EOF (a population or a single vector), in the search's own metric (the EOF with the
            ``distance`` the fit searched with; without taper it equals the SPEC EOF).
        status: why the fit stopped, one of :data:`STATUSES`: ``"converged"`` (least squares
            met its tolerances), ``"budget"`` (evaluations used up), ``"iterations"`` (least
            squares reached its step limit, ``least_squares.MAX_ITERATIONS``), or the genetic
            algorithm's
            ``"stall"``, ``"generations"``, ``"target"`` when nothing was left to polish.
        message: a sentence on the same.
        noise: nML only: the relative noise level sigma_N its weights used (given, or estimated
            from the residuals); None for the paper's methods.
        solid: the estimated solid (SPEC §10): the superquadric itself (default, None given),
            ``multi``'s union or ``gpis``'s mesh.
        selection: ``multi`` only: how the number of parts was chosen
            (:func:`hapticsim.fitting.multi.multi_search`), else None.
        setup_seconds: wall-clock time spent before the fit loading its compiled kernels from
            numba's cache, or compiling them on a fresh installation
            (:func:`hapticsim.fitting.kernels.prepare`; 0 once a process has them).
        uncertainty: with ``fit(..., uncertainty=True)``, the Laplace approximation at the
            optimum (:class:`~hapticsim.fitting.uncertainty.Uncertainty`), else None.
        model: ``gpis`` only: the Gaussian process's hyperparameters and the mesh's size
            (:meth:`~hapticsim.fitting.gpis.GpisFit.to_dict`), else None.
    """

    superquadric: Superquadric
    method: str
    eof: float
    evaluations: int
    seconds: float
    history: tuple[NDArray[np.int64], NDArray[np.float64]]
    status: str
    message: str = ""
    noise: float | None = None
    solid: Solid | None = None
    selection: dict[str, Any] | None = None
    setup_seconds: float = 0.0
    uncertainty: Any = None
    model: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.superquadric, Superquadric):
            raise InvalidInputError(
                f"`superquadric` must be a Superquadric, got {type(self.superquadric).__name__}"
            )
        if self.solid is None:
            object.__setattr__(self, "solid", self.superquadric)
        elif not isinstance(self.solid, Solid):
            raise InvalidInputError(f"`solid` must be a solid, got {type(self.solid).__name__}")
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

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the SPEC §6 keys ``superquadric, method, eof, evaluations, seconds``,
        ``solid`` (SPEC §10: the superquadric again, or multi's union), ``status`` and
        ``message``, ``setup_seconds``, ``noise`` for nML, ``selection`` for multi and ``model``
        for gpis (the history is left out: see :attr:`history`)."""
        extra: dict[str, Any] = {} if self.noise is None else {"noise": float(self.noise)}
        if self.selection is not None:
            extra["selection"] = self.selection
        if self.uncertainty is not None:
            extra["uncertainty"] = self.uncertainty.to_dict()
        if self.model is not None:
            extra["model"] = self.model
        assert self.solid is not None
        return {
            "superquadric": self.superquadric.to_dict(),
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
