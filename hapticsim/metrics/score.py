"""All quality measures of an estimate against the truth in one value (SPEC §4, §6)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from hapticsim._validate import as_generator, positive_int
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.metrics.chamfer import DEFAULT_CHAMFER_SAMPLES, chamfer_checked
from hapticsim.metrics.volume import (
    BOOLEAN_RESOLUTION,
    DEFAULT_VOLUME_SAMPLES,
    mesh_boolean_overlap,
    monte_carlo_overlap,
)

#: Volume methods of :func:`score`.
VOLUME_METHODS: tuple[str, ...] = ("monte_carlo", "booleans")
#: How each kind of solid draws its interior points and knows its volume (for the method text).
_SAMPLERS = {
    "superquadric": ("rejection sampling", "closed form"),
    "union": ("its parts' rejection samples outside the parts before them",
              "the parts' closed forms less their measured overlaps"),
    "mesh": ("rejection from its bounding box by ray-parity containment", "divergence theorem"),
}  # fmt: skip


@dataclass(frozen=True)
class Score:
    """Quality measures of an estimate S_e against the truth S_s (paper III-B, SPEC §4).

    Attributes:
        alpha: ``V(S_e \\ S_s) / V(S_e)``, false positives (eq. 11), in [0, 1].
        beta: ``V(S_s \\ S_e) / V(S_s)``, false negatives (eq. 12), in [0, 1].
        iou: ``V(S_e ∩ S_s) / V(S_e ∪ S_s)``, in [0, 1].
        chamfer: symmetric Chamfer distance between the surfaces [m], >= 0
            (:mod:`hapticsim.metrics.chamfer`).
        volume_method: how the volumes were computed (SPEC §4 asks to state it).
    """

    alpha: float
    beta: float
    iou: float
    chamfer: float
    volume_method: str

    def __post_init__(self) -> None:
        for name in ("alpha", "beta", "iou", "chamfer"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
                raise InvalidInputError(f"`{name}` must be a number, got {value!r}")
            high = np.inf if name == "chamfer" else 1.0
            if not 0.0 <= value <= high:
                raise InvalidInputError(f"`{name}` must lie in [0, {high}], got {value!r}")
            object.__setattr__(self, name, float(value))
        if not isinstance(self.volume_method, str):
            raise InvalidInputError(
                f"`volume_method` must be a string, got {type(self.volume_method).__name__}"
            )

    @property
    def epsilon(self) -> float:
        """``alpha + beta`` (paper III-B)."""
        return self.alpha + self.beta

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``alpha, beta, epsilon, iou, chamfer`` (SPEC §6) and ``volume_method``."""
        return {
            "alpha": self.alpha,
            "beta": self.beta,
            "epsilon": self.epsilon,
            "iou": self.iou,
            "chamfer": self.chamfer,
            "volume_method": self.volume_method,
        }


def seed_text(rng: np.random.Generator | int | None) -> str:
    """How a score's random numbers were seeded, for its ``volume_method``."""
    if isinstance(rng, np.random.Generator):
        return "a caller's Generator"
    return "no seed" if rng is None else f"seed {rng}"


def _monte_carlo_text(estimate: Solid, truth: Solid, n_vol: int, seed: str) -> str:
    """The ``volume_method`` of a Monte Carlo score."""
    kinds = sorted({estimate.kind, truth.kind})
    tail = f"standard error of alpha, beta <= {0.5 / np.sqrt(n_vol):.4f}"
    if kinds == ["superquadric"]:
        return (
            f"Monte Carlo: {n_vol} points uniform inside each solid (rejection sampling), "
            f"{seed}; exact closed-form volumes; {tail}"
        )
    samplers = "; ".join(f"{k}: {_SAMPLERS.get(k, ('its sampler',))[0]}" for k in kinds)
    volumes = ", ".join(_SAMPLERS.get(k, ("", "its own"))[1] for k in kinds)
    return (
        f"Monte Carlo against a {truth.kind} truth: {n_vol} points uniform inside each solid "
        f"({samplers}), {seed}; volumes: {volumes}; {tail}"
    )


def score(
    estimate: Solid,
    truth: Solid,
    rng: np.random.Generator | int | None = 0,
    volume_samples: int = DEFAULT_VOLUME_SAMPLES,
    chamfer_samples: int = DEFAULT_CHAMFER_SAMPLES,
    volume_method: str = "monte_carlo",
) -> Score:
    """alpha, beta, epsilon, IoU and Chamfer distance of `estimate` against `truth`, any two
    solids (superquadrics, unions, meshes).

    Volumes by Monte Carlo (:func:`~hapticsim.metrics.volume.volume_overlap`): with the default
    100 000 points per solid, alpha and beta are within 0.005 of their exact values at three
    standard errors, tapered and posed shapes alike; or by exact mesh booleans
    (``volume_method="booleans"``, :func:`~hapticsim.metrics.volume.boolean_overlap`). One
    generator draws the volume samples, then the Chamfer samples; the default seed 0 makes the
    score of a pair reproducible.

    Args:
        estimate: the estimated solid S_e.
        truth: the true solid S_s.
        rng: seed or generator.
        volume_samples: points drawn inside each solid, >= 1 (Monte Carlo).
        chamfer_samples: points drawn on each surface, >= 1.
        volume_method: ``"monte_carlo"`` or ``"booleans"``.

    Returns:
        The :class:`Score`, its ``volume_method`` stating how.
    """
    estimate = solid_arg(estimate, "estimate")
    truth = solid_arg(truth, "truth")
    if volume_method not in VOLUME_METHODS:
        raise ChoiceError("volume_method", volume_method, VOLUME_METHODS)
    n_vol = positive_int(volume_samples, "volume_samples")
    n_cd = positive_int(chamfer_samples, "chamfer_samples")
    as_generator(rng)  # checks it
    return score_checked(estimate, truth, rng, n_vol, n_cd, volume_method)


def score_checked(
    estimate: Solid,
    truth: Solid,
    rng: np.random.Generator | int | None,
    volume_samples: int = DEFAULT_VOLUME_SAMPLES,
    chamfer_samples: int = DEFAULT_CHAMFER_SAMPLES,
    volume_method: str = "monte_carlo",
) -> Score:
    """:func:`score` of arguments checked already (two solids, a Generator, a seed >= 0 or None,
    counts >= 1, a known volume method): for a caller that validated its inputs once at its own
    entry (:func:`hapticsim.exploration.run_trial`), not again at every layer."""
    seed = seed_text(rng)
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    if volume_method == "monte_carlo":
        volumes = monte_carlo_overlap(estimate, truth, volume_samples, gen)
        method = _monte_carlo_text(estimate, truth, volume_samples, seed)
    else:
        volumes = mesh_boolean_overlap(estimate, truth, BOOLEAN_RESOLUTION)
        method = (
            f"exact mesh booleans (manifold3d) of the two solids' surface meshes (superquadrics "
            f"meshed at {BOOLEAN_RESOLUTION} longitudes)"
        )
    distance = chamfer_checked(estimate, truth, chamfer_samples, gen)
    return Score(
        alpha=volumes.alpha,
        beta=volumes.beta,
        iou=volumes.iou,
        chamfer=distance,
        volume_method=method,
    )


__all__ = ["Score", "VOLUME_METHODS", "score", "score_checked"]
