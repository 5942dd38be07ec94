"""``hapticsim/HapticExploreTactile-v0``: haptic exploration felt through taxel pads, the pads'
images in the observation.

See :class:`HapticExploreTactileEnv`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig, HapticExploreEnv
from hapticsim.envs.observation import OBS_BOUND
from hapticsim.errors import InvalidInputError

#: Pressure [Pa] that the observation's taxel images show as 1.
TAXEL_SCALE: float = 1.0e5


class HapticExploreTactileEnv(HapticExploreEnv):
    """``hapticsim/HapticExplore-v0``'s task with tactile sensing (``sensing="tactile"``, the
    default here), whose observation adds what the pads felt at the last contact.

    Every contact is estimated from a taxel pad on the touching fingertip (the MuJoCo hand's
    pads, :mod:`hapticsim.sim.tactile`, or the analytic backend's rigid pad pressed on the
    exact surface), through the skin's sensor model (``skin``: ``"ideal"``, ``"vision"``,
    ``"capacitive"`` or a ``.toml`` file); the contacts in the observation are those estimates.

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

    ## Version history

    - v0: initial version.
    """

    def __init__(
        self,
        render_mode: str | None = None,
        config: HapticExploreConfig | None = None,
        **kwargs: Any,
    ) -> None:
        if config is None:
            kwargs.setdefault("sensing", "tactile")
        super().__init__(render_mode=render_mode, config=config, **kwargs)
        if self.config.sensing != "tactile":
            raise InvalidInputError(
                f"hapticsim/HapticExploreTactile-v0 senses through its pads: `sensing` must be "
                f"'tactile', got {self.config.sensing!r} (use HapticExplore-v0 for exact contacts)"
            )
        self.taxel_shape: tuple[int, int, int] = self._backend.pad_shape
        self.observation_space = spaces.Dict(
            {
                **self.observation_space.spaces,
                "taxels": spaces.Box(0.0, OBS_BOUND, self.taxel_shape, np.float32),
            }
        )

    def _observation(self) -> dict[str, np.ndarray]:
        obs = super()._observation()
        obs["taxels"] = self._taxels()
        return obs

    def _taxels(self) -> NDArray[np.float32]:
        images = getattr(self, "_last_images", None)
        if images is None:
            return np.zeros(self.taxel_shape, np.float32)
        return np.clip(images / TAXEL_SCALE, 0.0, OBS_BOUND).astype(np.float32)


def v0_class(sensing: str) -> type[HapticExploreEnv]:
    """The v0 environment to run policies on with this `sensing`: through pads,
    :class:`HapticExploreTactileEnv` (v0's task, and the pads' images shown for the policies that
    read them); else :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`."""
    return HapticExploreTactileEnv if sensing == "tactile" else HapticExploreEnv


__all__ = ["HapticExploreTactileEnv", "TAXEL_SCALE", "v0_class"]
