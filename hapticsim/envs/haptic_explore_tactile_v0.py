"""``hapticsim/HapticExploreTactile-v0``: haptic exploration felt through taxel pads, the pads'
images in the observation.

See :class:`HapticExploreTactileEnv`, an observation wrapper of the core environment
(:class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv` with ``sensing="tactile"``), and
:func:`make_v0`, the v0 environment for a sensing.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig, HapticExploreEnv
from hapticsim.envs.observation import OBS_BOUND
from hapticsim.errors import InvalidInputError

#: Pressure [Pa] that the observation's taxel images show as 1.
TAXEL_SCALE: float = 1.0e5


class HapticExploreTactileEnv(gym.ObservationWrapper[dict, np.ndarray, dict]):
    """``hapticsim/HapticExplore-v0``'s task with tactile sensing (``sensing="tactile"``, the
    default here), whose observation adds what the pads felt at the last contact.

    Every contact is estimated from a taxel pad on the touching fingertip (the MuJoCo hand's
    pads, :mod:`hapticsim.sim.tactile`, or the analytic backend's rigid pad pressed on the
    exact surface), through the skin's sensor model (``skin``: ``"ideal"``, ``"vision"``,
    ``"capacitive"`` or a ``.toml`` file); the contacts in the observation are those estimates.
    The core environment (``env.unwrapped``, a
    :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`) senses, fits and rewards; this
    wrapper shows its pads' images.

    ## Observation space

    v0's ``Dict`` (see :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`) and:

    | Key    | Shape              | Content                                              | Unit |
    |--------|--------------------|------------------------------------------------------|------|
    | taxels | (pads, rows, cols) | every pad's reading at the last recorded contact,    | 1    |
    |        |                    | divided by 100 kPa and clipped to [0, 10]; 0 before  |      |
    |        |                    | the first contact (pads: one per finger)             |      |

    The grid is the hand's pad grid (31 x 31 on hapticsim's hand and the analytic backend,
    33 x 33 on Shadow and Adroit), laid out again at the skin's own pitch where it has one
    (``capacitive``: 9 x 9). Action, reward, episode end and info are v0's.

    Args:
        env: the core to wrap (default: one made from `config` or the keyword arguments, with
            ``sensing="tactile"`` unless given); its sensing must be tactile.
        render_mode, config, kwargs: the core's settings
            (:class:`~hapticsim.envs.haptic_explore_v0.HapticExploreConfig`), when it is made
            here.

    ## Version history

    - v0: initial version.
    """

    #: As the core's (a class attribute: Gymnasium checks an entry point's metadata before
    #: making it).
    metadata = HapticExploreEnv.metadata

    def __init__(
        self,
        env: HapticExploreEnv | None = None,
        render_mode: str | None = None,
        config: HapticExploreConfig | None = None,
        **kwargs: Any,
    ) -> None:
        if env is None:
            if config is None:
                kwargs.setdefault("sensing", "tactile")
            env = HapticExploreEnv(render_mode=render_mode, config=config, **kwargs)
        elif config is not None or kwargs:
            raise InvalidInputError("give either `env` or its settings, not both")
        if not isinstance(env, HapticExploreEnv):
            raise InvalidInputError(f"`env` must be a HapticExploreEnv, got {type(env).__name__}")
        if env.config.sensing != "tactile":
            raise InvalidInputError(
                f"hapticsim/HapticExploreTactile-v0 senses through its pads: `sensing` must be "
                f"'tactile', got {env.config.sensing!r} (use HapticExplore-v0 for exact contacts)"
            )
        super().__init__(env)
        self.taxel_shape: tuple[int, int, int] = env.backend.pad_shape
        self.observation_space = spaces.Dict(
            {
                **env.observation_space.spaces,
                "taxels": spaces.Box(0.0, OBS_BOUND, self.taxel_shape, np.float32),
            }
        )

    def observation(self, observation: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """v0's observation and the pads' images (``taxels``)."""
        return {**observation, "taxels": self._taxels()}

    def _taxels(self) -> NDArray[np.float32]:
        images = self.unwrapped.last_images
        if images is None:
            return np.zeros(self.taxel_shape, np.float32)
        return np.clip(images / TAXEL_SCALE, 0.0, OBS_BOUND).astype(np.float32)


def make_v0(**kwargs: Any) -> gym.Env:
    """The v0 environment to run policies on, made from v0's settings (`kwargs`,
    :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreConfig`'s fields): through pads
    (``sensing="tactile"``), :class:`HapticExploreTactileEnv` (v0's task, and the pads' images
    shown for the policies that read them); else the core
    :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`. Either way ``env.unwrapped``
    is the core, holding the truth, the estimate and the contacts."""
    if kwargs.get("sensing") == "tactile":
        return HapticExploreTactileEnv(**kwargs)
    return HapticExploreEnv(**kwargs)


__all__ = ["HapticExploreTactileEnv", "TAXEL_SCALE", "make_v0"]
