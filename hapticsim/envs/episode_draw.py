"""What a reset draws: the object, its vision estimate, the calibration error and the fitter's and
sensor's seeds (:class:`EpisodeDrawer`), picklable so that another process can draw an
environment's next episode ahead (:class:`~hapticsim.envs.vector.HapticVectorEnv`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hapticsim.data.distributions import ObjectDistribution
from hapticsim.errors import InvalidInputError
from hapticsim.geometry.solid import Solid
from hapticsim.perception.vision import DepthCamera, RoughObject, vision_estimate


@dataclass(frozen=True)
class EpisodeDraw:
    """What a reset drew from the environment's generator (:meth:`EpisodeDrawer.draw`).

    Attributes:
        state: the generator's state (``bit_generator.state``) the draws started from.
        after: its state after them.
        fit_seed: the seed of the fitter's stream.
        sensor_seed: the seed of the sensor's stream (noise, tactile readings).
        shape: the object (packed for sending: its index among the distribution's fixed
            solids, :meth:`EpisodeDrawer.pack`).
        rough: the vision estimate, moved by the calibration error.
        prepared: what the backend's reset makes of the shape alone
            (:meth:`~hapticsim.envs.touch.TouchBackend.preparer`), or None.
    """

    state: dict[str, Any]
    after: dict[str, Any]
    fit_seed: int
    sensor_seed: int
    shape: Solid | int
    rough: RoughObject
    prepared: Any = None


@dataclass(frozen=True)
class EpisodeDrawer:
    """What a reset draws from the environment's generator, in this order: the fitter's seed,
    the object (unless given), the vision estimate (one noisy depth image; most of a reset's
    time), the camera-to-hand calibration error and the sensor's seed. Nothing else draws from
    that generator, so an episode's draws depend only on where the last reset left it.

    Picklable, so that another process can draw an environment's next episode while the
    environment is still busy with this one
    (:meth:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv.offer_draw`,
    :class:`~hapticsim.envs.vector.HapticVectorEnv`); that process also makes what the
    backend's reset needs of the shape alone (`prepare`).

    Attributes:
        objects: the object distribution.
        camera: the depth camera.
        position_noise: standard deviation per axis of the calibration error [m].
        prepare: the backend's :meth:`~hapticsim.envs.touch.TouchBackend.preparer`, or None.
    """

    objects: ObjectDistribution
    camera: DepthCamera
    position_noise: float
    prepare: Callable[[Solid], Any] | None = None

    def draw(self, rng: np.random.Generator, shape: Solid | None = None) -> EpisodeDraw:
        """An episode's draws from `rng` (`shape`: the object, else one drawn). To draw ahead,
        pass a copy of the environment's generator."""
        state = rng.bit_generator.state
        fit_seed = int(rng.integers(2**63))
        if shape is None:
            shape = self.objects.sample(rng)
        rough = vision_estimate(shape, rng, self.camera)
        error = rng.normal(0.0, self.position_noise, size=3)
        sensor_seed = int(rng.integers(2**63))
        prepared = None if self.prepare is None else self.prepare(shape)
        return EpisodeDraw(state, rng.bit_generator.state, fit_seed, sensor_seed, shape,
                           rough.moved(rough.center + error), prepared)  # fmt: skip

    def pack(self, draw: EpisodeDraw) -> EpisodeDraw:
        """`draw` for sending to another process: an object the distribution returns as it is
        (:meth:`~hapticsim.data.distributions.ObjectSet.fixed_solids`, e.g. a mesh) replaced by
        its index, so that it is not copied and :meth:`unpack` gives back the same instance
        (whose scene and scorer the environment may have cached)."""
        for i, solid in enumerate(self.objects.fixed_solids()):
            if draw.shape is solid:
                return replace(draw, shape=i)
        return draw

    def unpack(self, draw: EpisodeDraw) -> EpisodeDraw:
        """The inverse of :meth:`pack`, with this drawer's own instances."""
        if isinstance(draw.shape, (int, np.integer)):
            fixed = self.objects.fixed_solids()
            if not 0 <= draw.shape < len(fixed):
                raise InvalidInputError(
                    f"`draw.shape` must be a solid or an index below {len(fixed)}, got "
                    f"{draw.shape}"
                )
            return replace(draw, shape=fixed[int(draw.shape)])
        return draw


__all__ = ["EpisodeDraw", "EpisodeDrawer"]
