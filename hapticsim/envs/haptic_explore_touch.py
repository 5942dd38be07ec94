"""``hapticsim/HapticExploreTouch-v0``: the compact task, observed as the touch history itself.

See :class:`HapticExploreTouchEnv`. The observation is made by :class:`TouchObserver` from what
``HapticExplore-v0`` shows and the agent's own past approaches, so a policy trained here runs on
a v0 environment too (``hapticsim.envs.policies`` policy ``"learned-touch"``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim.envs.haptic_explore_v1 import HEAD_DIM, HapticExploreV1Env, observation_head
from hapticsim.envs.observation import OBS_BOUND

Array = NDArray[np.float64]

#: Id of the environment this module defines.
ENV_ID: str = "hapticsim/HapticExploreTouch-v0"
#: Contacts shown to the encoder (evenly spread over all contacts when there are more).
MAX_POINTS: int = 64
#: Numbers per contact: position (3, object-centred, / obs_scale), normal (3), present (1).
POINT_WIDTH: int = 7
#: Past touches shown (the latest ones).
MAX_TOUCHES: int = 16
#: Numbers per touch: approach direction (3), contacts it brought / 10, present (1).
TOUCH_WIDTH: int = 5
#: Contacts that scale a touch's contact count.
TOUCH_CONTACT_SCALE: float = 10.0
#: Where the point set starts in the observation.
POINTS_OFFSET: int = HEAD_DIM
#: Where the touch set starts.
TOUCHES_OFFSET: int = POINTS_OFFSET + MAX_POINTS * POINT_WIDTH
#: Length of the observation: 17 + 64 x 7 + 16 x 5 = 545.
OBS_DIM: int = TOUCHES_OFFSET + MAX_TOUCHES * TOUCH_WIDTH
#: The sets of the observation for a permutation-invariant encoder: (offset, count, width) each,
#: the last number of an element 1 where it is present.
SETS: tuple[tuple[int, int, int], ...] = (
    (POINTS_OFFSET, MAX_POINTS, POINT_WIDTH),
    (TOUCHES_OFFSET, MAX_TOUCHES, TOUCH_WIDTH),
)


def point_indices(count: int, limit: int = MAX_POINTS) -> NDArray[np.int64]:
    """Which of `count` contacts are shown: all, or `limit` evenly spread over them (the
    first and the last included), in order."""
    if count <= limit:
        return np.arange(count)
    return np.unique(np.round(np.linspace(0, count - 1, limit)).astype(np.int64))


class TouchObserver:
    """The touch observation, made from v0 observations and the agent's approaches.

    Entries (float32, :data:`OBS_DIM` = 545; no ground truth, no coverage features):

    | Index   | Content                                                                     |
    |---------|-----------------------------------------------------------------------------|
    | 0-16    | as the compact observation's: fit (13), fit_valid, eof, touches / 10,       |
    |         | contacts / 100 (:func:`~hapticsim.envs.haptic_explore_v1.observation_head`) |
    | 17-464  | 64 contacts x (x, y, z, nx, ny, nz, present): v0's ``points`` (object-      |
    |         | centred, / obs_scale) and ``normals``; all contacts, or 64 evenly spread    |
    |         | over them (:func:`point_indices`); absent ones are zeros                    |
    | 465-544 | the last 16 touches x (approach x, y, z, contacts it brought / 10, present) |

    The order of a set's elements carries no meaning for a permutation-invariant encoder; the
    contacts are in the order they came, the touches oldest first.
    """

    def __init__(self) -> None:
        self._touches: list[tuple[float, float, float, float]] = []
        self._count = 0

    def reset(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """Start an episode from the v0 reset observation; returns the touch observation."""
        self._touches = []
        self._count = int(np.sum(obs["mask"]))
        return self.features(obs)

    def update(self, obs: dict[str, np.ndarray], approach: Array) -> NDArray[np.float32]:
        """The touch observation after a touch along `approach` (unit, object-centred)."""
        count = int(np.sum(obs["mask"]))
        a = np.asarray(approach, np.float64)
        self._touches.append(
            (float(a[0]), float(a[1]), float(a[2]), (count - self._count) / TOUCH_CONTACT_SCALE)
        )
        self._count = count
        return self.features(obs)

    def features(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """The touch observation of a v0 observation (with this episode's touches)."""
        out = np.zeros(OBS_DIM, np.float64)
        out[:HEAD_DIM] = observation_head(obs)
        mask = np.asarray(obs["mask"], bool)
        points = np.asarray(obs["points"], np.float64)[mask]
        normals = np.asarray(obs["normals"], np.float64)[mask]
        keep = point_indices(len(points))
        block = out[POINTS_OFFSET:TOUCHES_OFFSET].reshape(MAX_POINTS, POINT_WIDTH)
        block[: len(keep), 0:3] = points[keep]
        block[: len(keep), 3:6] = normals[keep]
        block[: len(keep), 6] = 1.0
        touches = self._touches[-MAX_TOUCHES:]
        block = out[TOUCHES_OFFSET:].reshape(MAX_TOUCHES, TOUCH_WIDTH)
        if touches:
            block[: len(touches), 0:4] = np.asarray(touches)
            block[: len(touches), 4] = 1.0
        return np.clip(out, -OBS_BOUND, OBS_BOUND).astype(np.float32)


class HapticExploreTouchEnv(HapticExploreV1Env):
    """``hapticsim/HapticExploreCompact-v0``'s task, observed as the touch history itself.

    Action, reward (including the optional coverage term, computed as there), episode end,
    ``info`` and arguments are those of
    :class:`~hapticsim.envs.haptic_explore_v1.HapticExploreV1Env`; only the observation
    differs: instead of engineered coverage features, the contacts and normals so far and the
    agent's past touches as two sets (:class:`TouchObserver`), for a permutation-invariant
    encoder (:data:`SETS`; ``hapticsim.experiments.sb3.TouchSetExtractor``).

    ## Observation space

    ``Box(-10, 10, (545,), float32)``: :class:`TouchObserver`. No ground truth.

    ## Version history

    - v0: initial version.
    """

    def __init__(self, render_mode: str | None = None, config: Any = None, **kwargs: Any) -> None:
        super().__init__(render_mode=render_mode, config=config, **kwargs)
        self.touch_observer = TouchObserver()
        self.observation_space = spaces.Box(-OBS_BOUND, OBS_BOUND, (OBS_DIM,), np.float32)

    def _observe(
        self, obs: dict[str, np.ndarray], features: NDArray[np.float32], approach: Array | None
    ) -> NDArray[np.float32]:
        if approach is None:
            return self.touch_observer.reset(obs)
        return self.touch_observer.update(obs, approach)


__all__ = [
    "ENV_ID",
    "HapticExploreTouchEnv",
    "MAX_POINTS",
    "MAX_TOUCHES",
    "OBS_DIM",
    "SETS",
    "TouchObserver",
    "point_indices",
]
