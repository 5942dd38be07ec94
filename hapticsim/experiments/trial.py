"""One trial of the paper's evaluation: synthesise contacts, fit, score (paper Sections III-IV).

A :class:`Trial` names everything a worker process needs (body, noise, method, budget and the
seeds); :func:`run_trial` is the module-level function the sweeps map over processes. The data of
a trial depend only on its ``data_key``, so the four methods of one run see the same contacts.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.parallel import seed_sequence

Array = NDArray[np.float64]

#: Quality measures of one trial, in table order.
METRICS: tuple[str, ...] = ("theta", "alpha", "beta", "epsilon", "iou", "chamfer", "seconds")


@dataclass(frozen=True)
class Trial:
    """One fit of one synthetic data set.

    Attributes:
        body: name of a paper body (``hapticsim.data.bodies.BODY_NAMES``).
        method: ``"LS"``, ``"H"``, ``"nLS"`` or ``"nH"``.
        noise: relative noise sigma_N of points and normals (SPEC §5), >= 0.
        budget: EOF evaluations allowed to the fit, >= 1.
        count: number of contacts.
        run: index of the run (repetition with fresh noise), >= 0.
        seed: the root seed of the sweep.
        data_key: key of the data seed; equal keys give equal contacts.
        fit_key: key of the fit seed (GA randomness) and of the volume sampling of the score.
        chamfer: also compute the Chamfer distance (about half the cost of scoring). Not part
            of a trial's identity: the volume measures are the same either way (they are drawn
            first from the score's generator), so a trial shared by two figures runs once.
    """

    body: str
    method: str
    noise: float
    budget: int
    count: int
    run: int
    seed: int
    data_key: tuple[int, ...]
    fit_key: tuple[int, ...]
    chamfer: bool = field(default=True, compare=False)

    def __post_init__(self) -> None:
        if self.noise < 0 or not np.isfinite(self.noise):
            raise InvalidInputError(f"`noise` must be finite and >= 0, got {self.noise}")
        if self.budget < 1:
            raise InvalidInputError(f"`budget` must be >= 1, got {self.budget}")
        if self.count < 1:
            raise InvalidInputError(f"`count` must be >= 1, got {self.count}")

    @property
    def label(self) -> str:
        """The trial in messages, e.g. ``"trial cube/nH/noise=0.1/budget=5000/run=3"``."""
        return (
            f"trial {self.body}/{self.method}/noise={self.noise:g}/budget={self.budget}/"
            f"run={self.run}"
        )


@dataclass(frozen=True)
class TrialResult:
    """Quality of one fit (paper III-B, SPEC §4) and what produced it.

    Attributes:
        trial: the trial.
        theta: ``D(S_e) / (D(S_s) + 1)`` with the EOF the method minimises (with normals for
            nLS/nH, points only, theta^(1), for LS/H).
        alpha, beta, epsilon, iou: volume measures of estimate against truth.
        chamfer: symmetric Chamfer distance of the surfaces [m]; NaN if not computed.
        eof: final EOF of the fit [m^2].
        evaluations: EOF evaluations the fit used.
        seconds: wall time of the fit [s].
        status: why the fit stopped (``FitResult.status``).
        estimate: the fitted superquadric as a SPEC §6 dict.
        volume_method: how alpha, beta and IoU were computed (``Score.volume_method``).
        points: (n, 3) float, the noisy contact points [m] (kept for pictures).
        normals: (n, 3) float, the noisy contact normals.
    """

    trial: Trial
    theta: float
    alpha: float
    beta: float
    epsilon: float
    iou: float
    chamfer: float
    eof: float
    evaluations: int
    seconds: float
    status: str
    estimate: dict[str, Any]
    volume_method: str
    points: Array = field(repr=False)
    normals: Array = field(repr=False)

    def to_row(self) -> dict[str, Any]:
        """A flat CSV row: trial settings, then quality measures."""
        t = self.trial
        return {
            "body": t.body, "method": t.method, "noise": t.noise, "budget": t.budget,
            "count": t.count, "run": t.run, "theta": self.theta, "alpha": self.alpha,
            "beta": self.beta, "epsilon": self.epsilon, "iou": self.iou,
            "chamfer": self.chamfer, "eof": self.eof, "evaluations": self.evaluations,
            "seconds": self.seconds, "status": self.status,
        }  # fmt: skip


def make_trial(
    body: str,
    method: str,
    noise: float,
    budget: int,
    count: int,
    run: int,
    seed: int,
    chamfer: bool = True,
) -> Trial:
    """A :class:`Trial` with seeds keyed by its settings, never by its place in a sweep.

    The data key is (body, noise, count, run), so all methods and budgets of one run fit the same
    contacts (paired comparisons), and the same setting in Fig. 4 and Fig. 5 is the same trial.
    The fit key adds the method; the budget is left out, so the fits of one run at growing
    budgets share their random numbers (common random numbers, smoother curves).

    Raises:
        InvalidInputError: unknown body or method, or a bad setting.
    """
    from hapticsim.data.bodies import BODY_NAMES
    from hapticsim.fitting.methods import METHODS

    if body not in BODY_NAMES:
        raise ChoiceError("body", body, BODY_NAMES)
    if method not in METHODS:
        raise ChoiceError("method", method, METHODS)
    if noise < 0 or not np.isfinite(noise):
        raise InvalidInputError(f"`noise` must be finite and >= 0, got {noise}")
    data_key = (BODY_NAMES.index(body), round(noise * 1e6), int(count), int(run))
    return Trial(
        body=body, method=method, noise=float(noise), budget=int(budget), count=int(count),
        run=int(run), seed=int(seed), data_key=data_key,
        fit_key=(*data_key, METHODS.index(method)), chamfer=chamfer,
    )  # fmt: skip


def make_data(trial: Trial) -> tuple[Any, Any]:
    """The true superquadric and the noisy contacts of a trial (paper III-A, SPEC §5).

    Returns:
        (truth, contacts): a ``Superquadric`` and a ``hapticsim.data.io.Contacts``.
    """
    from hapticsim.data.bodies import get_body
    from hapticsim.data.synthetic import paper_dataset

    truth = get_body(trial.body)
    rng = np.random.default_rng(seed_sequence(trial.seed, *trial.data_key))
    contacts = paper_dataset(truth, noise=trial.noise, rng=rng, count=trial.count)
    return truth, contacts


def run_trial(trial: Trial) -> TrialResult:
    """Synthesise the trial's contacts, fit them with its method and budget, and score the fit."""
    from hapticsim.fitting import fit
    from hapticsim.fitting.methods import uses_normals
    from hapticsim.metrics import score, theta, volume_overlap

    truth, contacts = make_data(trial)
    fit_ss = seed_sequence(trial.seed, *trial.fit_key)
    fit_rng, score_rng = (np.random.default_rng(s) for s in fit_ss.spawn(2))
    result = fit(
        contacts.points, contacts.normals, method=trial.method, budget=trial.budget, rng=fit_rng
    )
    estimate = result.superquadric
    normals = contacts.normals if uses_normals(trial.method) else None
    if trial.chamfer:
        quality = score(estimate, truth, rng=score_rng)
        chamfer, volume_method = quality.chamfer, quality.volume_method
    else:
        quality = volume_overlap(estimate, truth, rng=score_rng)
        chamfer = float("nan")
        volume_method = f"Monte Carlo, {quality.samples} points inside each solid"
    return TrialResult(
        trial=trial,
        theta=float(theta(estimate, truth, contacts.points, normals, lam=DEFAULT_LAMBDA)),
        alpha=float(quality.alpha),
        beta=float(quality.beta),
        epsilon=float(quality.epsilon),
        iou=float(quality.iou),
        chamfer=float(chamfer),
        eof=float(result.eof),
        evaluations=int(result.evaluations),
        seconds=float(result.seconds),
        status=str(result.status),
        estimate=estimate.to_dict(),
        volume_method=str(volume_method),
        points=contacts.points,
        normals=contacts.normals,
    )
