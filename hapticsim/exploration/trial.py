"""One trial of haptic exploration, validated once, and every seed it draws from.

A :class:`Trial` names everything that decides a run: the object, the hand and its sensing
(:class:`~hapticsim.sim.scene.SceneConfig`), the explorer (a scripted strategy or an environment
policy), the contact count, the sensor noise, the estimator and the seed. It checks itself when
made; nothing downstream validates it again.

:class:`TrialSeeds` holds the five streams a trial draws from (object, simulation, noise, fit,
score) and is the one place where they are derived: :meth:`TrialSeeds.from_seed` for a trial
named by an integer seed (``hapticsim explore``), :meth:`TrialSeeds.from_case` for a suite case
(its data and case seed sequences, :mod:`hapticsim.suites.cases`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim._validate import finite_float, positive_int
from hapticsim.constants import DEFAULT_CONTACTS, MAX_CONTACTS, MIN_CONTACTS
from hapticsim.errors import ChoiceError, InvalidInputError

#: A seed a stream is made from: an int or a numpy SeedSequence (``np.random.default_rng``).
SeedLike = int | np.random.SeedSequence


@dataclass(frozen=True)
class TrialSeeds:
    """The streams a trial draws from, each an int or a ``SeedSequence``.

    Attributes:
        object: draws a random object (random kinds only).
        sim: the vision estimate, the strategy's or policy's choices and the skin's sensor.
        noise: the sensor noise added to the recorded contacts (SPEC §5).
        fit: the estimator's random choices.
        score: the Monte Carlo samples of the volume metrics.
    """

    object: SeedLike
    sim: SeedLike
    noise: SeedLike
    fit: SeedLike
    score: SeedLike

    @classmethod
    def from_seed(cls, seed: int) -> TrialSeeds:
        """The streams of a trial named by one integer seed (``hapticsim explore --seed``):
        ``SeedSequence(seed).spawn(4)`` gives the simulation, noise, fit (as a 32-bit int) and
        object streams, in that order; the score is seeded by `seed` itself."""
        children = np.random.SeedSequence(seed).spawn(4)
        fit_seed = int(children[2].generate_state(1)[0])
        return cls(object=children[3], sim=children[0], noise=children[1], fit=fit_seed,
                   score=seed)  # fmt: skip

    @classmethod
    def from_case(
        cls, data: np.random.SeedSequence, case: np.random.SeedSequence, shape_first: bool
    ) -> TrialSeeds:
        """The streams of a suite case: the data seed (keyed by the data parameters, so every
        method of one run meets the same contacts) gives the object (when `shape_first`),
        simulation and noise streams; the case seed (keyed by every parameter) the fit and the
        score."""
        data_streams = data.spawn(3 if shape_first else 2)
        obj = data_streams[0] if shape_first else data
        sim, noise = data_streams[-2:]
        fit, score = case.spawn(2)
        return cls(object=obj, sim=sim, noise=noise, fit=fit, score=score)

    def generator(self, stream: str) -> np.random.Generator:
        """A fresh generator of one stream (``"object"``, ``"sim"``, ``"noise"``, ``"fit"`` or
        ``"score"``)."""
        return np.random.default_rng(getattr(self, stream))

    def rng(self, stream: str) -> int | np.random.Generator:
        """One stream as an ``rng`` argument: an int seed as it is (a score states it), a
        seed sequence as a fresh generator."""
        value = getattr(self, stream)
        return value if isinstance(value, int) else np.random.default_rng(value)


def _scene_config() -> Any:
    from hapticsim.sim.scene import SceneConfig

    return SceneConfig()


@dataclass(frozen=True)
class Trial:
    """One exploration: object x scene x explorer x count x noise x estimator x seed.

    Attributes:
        object: an :class:`~hapticsim.data.objects.ObjectSpec`, a spec's source (a body name,
            ``random``, a file, ``pybullet:NAME``), or a solid (the truth itself, posed in the
            world).
        explorer: a scripted strategy (``paper``, ``patch``, ...:
            :func:`hapticsim.sim.strategies.strategy_names`) or an environment policy
            (``uncertainty``, ``learned``, ``learned:PATH``, ...).
        count: contacts to gather, in [:data:`MIN_CONTACTS`, ``MAX_CONTACTS``].
        noise: relative sensor noise sigma_N (SPEC §5), >= 0.
        estimator: the fitting method (:data:`hapticsim.fitting.methods.FIT_METHODS`).
        seed: the trial's seed (:meth:`TrialSeeds.from_seed`), >= 0.
        scene: the hand, its sensing and skin (:class:`~hapticsim.sim.scene.SceneConfig`).
        free_space: hand the estimator the fingertip centres along the run (nML keeps its
            solid away from them, multi scores its candidates by them). Suites fixed before
            this existed leave it off.
        holes: with the ``multi`` estimator, also fit a supertoroid and keep it where it
            explains the contacts better (:func:`hapticsim.fitting.fit`'s ``holes``).

    Raises:
        InvalidInputError: an unknown object, explorer or estimator (the message lists the
            choices), or a bad count, noise or seed.
    """

    object: Any = "cube"
    explorer: str = "paper"
    count: int = DEFAULT_CONTACTS
    noise: float = 0.0
    estimator: str = "nH"
    seed: int = 0
    scene: Any = field(default_factory=_scene_config)
    free_space: bool = True
    holes: bool = False

    def __post_init__(self) -> None:
        from hapticsim.data.objects import ObjectSpec
        from hapticsim.exploration.explorers import check_explorer
        from hapticsim.fitting.methods import FIT_METHODS
        from hapticsim.geometry.solid import Solid
        from hapticsim.sim.scene import SceneConfig

        obj = self.object
        if isinstance(obj, (str, Path)):
            obj = ObjectSpec(obj)
        elif not isinstance(obj, (ObjectSpec, Solid)):
            raise InvalidInputError(
                f"`object` must be an object name or file, an ObjectSpec or a solid, got "
                f"{type(obj).__name__}"
            )
        object.__setattr__(self, "object", obj)
        check_explorer(self.explorer)
        if not isinstance(self.estimator, str) or self.estimator not in FIT_METHODS:
            raise ChoiceError("method", self.estimator, FIT_METHODS)
        if not isinstance(self.holes, bool) or (self.holes and self.estimator != "multi"):
            raise InvalidInputError(
                f"`holes` is for the multi estimator, got holes={self.holes!r} with "
                f"{self.estimator}"
            )
        object.__setattr__(self, "noise", finite_float(self.noise, "noise", low=0.0))
        object.__setattr__(self, "seed", positive_int(self.seed, "seed", minimum=0))
        count = positive_int(self.count, "count", minimum=MIN_CONTACTS, maximum=MAX_CONTACTS)
        object.__setattr__(self, "count", count)
        if not isinstance(self.scene, SceneConfig):
            raise InvalidInputError(
                f"`scene` must be a SceneConfig, got {type(self.scene).__name__}"
            )

    @property
    def name(self) -> str:
        """The object's short label (a body, kind or file name)."""
        from hapticsim.data.objects import ObjectSpec

        if isinstance(self.object, ObjectSpec):
            return self.object.name
        return str(getattr(self.object, "kind", "object"))

    def resolve(self, seeds: TrialSeeds) -> Any:
        """The truth, posed in the world: the solid itself, or what the spec resolves to (a
        random kind drawn from the object stream)."""
        from hapticsim.data.objects import ObjectSpec

        if isinstance(self.object, ObjectSpec):
            return self.object.resolve(seeds.generator("object"))
        return self.object


__all__ = ["DEFAULT_CONTACTS", "MIN_CONTACTS", "Trial", "TrialSeeds"]
