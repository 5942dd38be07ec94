"""``hapticsim/HapticExploreTactile-v1``: haptic exploration felt through taxel pads, the pads'
pressure, shear and stick/slip states in the observation.

See :class:`HapticExploreTactileV1Env`: v0's wrapper
(:class:`~hapticsim.envs.haptic_explore_tactile_v0.HapticExploreTactileEnv`) whose observation
adds the traction field of SPEC §11 (:mod:`hapticsim.perception.tactile.traction`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim.envs.haptic_explore_tactile_v0 import TAXEL_SCALE, HapticExploreTactileEnv
from hapticsim.envs.observation import OBS_BOUND
from hapticsim.perception.tactile.traction import TAXEL_STATES


class HapticExploreTactileV1Env(HapticExploreTactileEnv):
    """``hapticsim/HapticExploreTactile-v0`` with the skin's traction field: what the pads felt
    at the last contact, in pressure, shear and each taxel's stick or slip.

    The MuJoCo backend loads each pad with MuJoCo's friction force on its fingertip (a share of
    its Coulomb limit, spread over the taxels by the skin's partial-slip law); the analytic
    backend's press carries no tangential load and its strokes slide.

    ## Observation space

    v0's ``Dict`` (``taxels`` among it) and:

    | Key         | Shape                 | Content                                        | Unit |
    |-------------|-----------------------|------------------------------------------------|------|
    | shear       | (pads, rows, cols, 2) | the object's tangential traction on each taxel | 1    |
    |             |                       | along the pad's u and v, divided by 100 kPa    |      |
    |             |                       | and clipped to [-10, 10]; 0 before the first   |      |
    |             |                       | contact                                        |      |
    | taxel_state | (pads, rows, cols)    | 0 free, 1 stick, 2 slip                        | -    |

    The shear is the skin's field before the sensor model (the sensor's noise, gains and
    threshold act on the pressure readings, ``taxels``). Action, reward, episode end and info
    are v0's.

    ## Version history

    - v1: adds ``shear`` and ``taxel_state`` (SPEC §11).
    - v0: pressure images only (:class:`HapticExploreTactileEnv`).
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        pads = self.taxel_shape
        self.observation_space = spaces.Dict(
            {
                **self.observation_space.spaces,
                "shear": spaces.Box(-OBS_BOUND, OBS_BOUND, (*pads, 2), np.float32),
                "taxel_state": spaces.MultiDiscrete(np.full(pads, len(TAXEL_STATES)),
                                                    dtype=np.int8),  # fmt: skip
            }
        )

    def observation(self, observation: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """v0's observation with the pads' shear and taxel states."""
        shear, state = self._traction()
        return {**super().observation(observation), "shear": shear, "taxel_state": state}

    def _traction(self) -> tuple[NDArray[np.float32], NDArray[np.int8]]:
        last = self.unwrapped.last_traction
        if last is None:
            return np.zeros((*self.taxel_shape, 2), np.float32), np.zeros(self.taxel_shape,
                                                                          np.int8)  # fmt: skip
        field, state = last
        shear = np.clip(field[..., 1:] / TAXEL_SCALE, -OBS_BOUND, OBS_BOUND)
        return shear.astype(np.float32), state.astype(np.int8)


__all__ = ["HapticExploreTactileV1Env"]
