"""``hapticsim/HapticExploreTouch-v0``: the compact task, observed as the touch history itself
(a wrapper of the core environment, :class:`HapticExploreTouchEnv`); its tactile variant is
:mod:`hapticsim.envs.haptic_explore_touch_tactile_v0`, and the observation constants of both
are here. The observation is
made by :class:`TouchObserver` from what ``HapticExplore-v0`` (or ``HapticExploreTactile-v0``)
shows and the agent's own past approaches, so a policy trained here runs on a v0 environment too
(``hapticsim.envs.policies`` policy ``"learned-touch"``, or ``"learned:PATH"``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim.envs.haptic_explore_compact_v0 import (
    HEAD_DIM,
    HapticExploreCompactEnv,
    observation_head,
)
from hapticsim.envs.observation import OBS_BOUND
from hapticsim.errors import InvalidInputError

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

#: Id of the tactile variant.
TACTILE_ENV_ID: str = "hapticsim/HapticExploreTouchTactile-v0"
#: Side of a touch's pooled pad image in the tactile observation (TAXEL_GRID x TAXEL_GRID).
TAXEL_GRID: int = 8
#: Numbers per touch in the tactile observation: approach (3), contacts it brought / 10, the
#: pooled image of the pad that felt most, over its largest block (64), present (1).
TACTILE_TOUCH_WIDTH: int = TOUCH_WIDTH + TAXEL_GRID * TAXEL_GRID
#: Length of the tactile observation: 17 + 64 x 7 + 16 x 69 = 1,569.
TACTILE_OBS_DIM: int = TOUCHES_OFFSET + MAX_TOUCHES * TACTILE_TOUCH_WIDTH
#: The sets of the tactile observation.
TACTILE_SETS: tuple[tuple[int, int, int], ...] = (
    (POINTS_OFFSET, MAX_POINTS, POINT_WIDTH),
    (TOUCHES_OFFSET, MAX_TOUCHES, TACTILE_TOUCH_WIDTH),
)


def point_indices(count: int, limit: int = MAX_POINTS) -> NDArray[np.int64]:
    """Which of `count` contacts are shown: all, or `limit` evenly spread over them (the
    first and the last included), in order."""
    if count <= limit:
        return np.arange(count)
    return np.unique(np.round(np.linspace(0, count - 1, limit)).astype(np.int64))


def pool_taxels(images: NDArray[np.floating], grid: int = TAXEL_GRID) -> NDArray[np.float64]:
    """The pad that felt most, averaged over a `grid` x `grid` of taxel blocks and divided by
    its largest block: the shape of the contact patch, not how hard the pad pressed.

    Args:
        images: (pads, rows, cols) float, one reading per taxel (the tactile observation's
            ``taxels``: pressure / 100 kPa); rows and cols at least `grid`.
        grid: blocks per side; the blocks' sizes differ by at most one taxel.

    Returns:
        (grid * grid,) float in [0, 1], the block means row by row over the largest one; zeros
        when no pad felt anything.
    """

    x = np.asarray(images, np.float64)
    if x.ndim != 3 or x.shape[1] < grid or x.shape[2] < grid:
        raise InvalidInputError(
            f"taxel images must be (pads, rows, cols) with rows and cols >= {grid}, got {x.shape}"
        )
    totals = x.sum(axis=(1, 2))
    if not np.any(totals > 0):
        return np.zeros(grid * grid)
    pad = x[int(np.argmax(totals))]
    rows = [len(b) for b in np.array_split(np.arange(pad.shape[0]), grid)]
    cols = [len(b) for b in np.array_split(np.arange(pad.shape[1]), grid)]
    sums = np.add.reduceat(np.add.reduceat(pad, np.cumsum([0] + rows[:-1]), axis=0),
                           np.cumsum([0] + cols[:-1]), axis=1)  # fmt: skip
    means = sums / np.outer(rows, cols)
    return (means / means.max()).ravel()


class TouchObserver:
    """The touch observation, made from v0 observations and the agent's approaches.

    Entries (float32, :data:`OBS_DIM` = 545; no ground truth, no coverage features):

    | Index   | Content                                                                     |
    |---------|-----------------------------------------------------------------------------|
    | 0-16    | as the compact observation's: fit (13), fit_valid, eof, touches / 10,       |
    |         | contacts / 100 (``haptic_explore_compact_v0.observation_head``)             |
    | 17-464  | 64 contacts x (x, y, z, nx, ny, nz, present): v0's ``points`` (object-      |
    |         | centred, / obs_scale) and ``normals``; all contacts, or 64 evenly spread    |
    |         | over them (:func:`point_indices`); absent ones are zeros                    |
    | 465-544 | the last 16 touches x (approach x, y, z, contacts it brought / 10, present) |

    The order of a set's elements carries no meaning for a permutation-invariant encoder; the
    contacts are in the order they came, the touches oldest first.

    With ``taxels=True`` (:data:`TACTILE_OBS_DIM` = 1,569 entries, sets :data:`TACTILE_SETS`) a
    touch's element is (approach x, y, z, contacts it brought / 10, 64 taxel blocks, present):
    the pad that felt most at the touch's last contact (v0's tactile ``taxels``), averaged over
    8 x 8 blocks and divided by the largest (:func:`pool_taxels`: the patch's shape); zeros for a
    touch that brought no contact.

    Args:
        taxels: put each touch's pad image in its element (needs v0 observations with
            ``taxels``: ``hapticsim/HapticExploreTactile-v0``).
    """

    def __init__(self, taxels: bool = False) -> None:
        self.taxels = bool(taxels)
        self.touch_width = TACTILE_TOUCH_WIDTH if self.taxels else TOUCH_WIDTH
        self.obs_dim = TACTILE_OBS_DIM if self.taxels else OBS_DIM
        self.sets = TACTILE_SETS if self.taxels else SETS
        self._touches: list[NDArray[np.float64]] = []
        self._count = 0

    def reset(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """Start an episode from the v0 reset observation; returns the touch observation."""
        self._touches = []
        self._count = int(np.sum(obs["mask"]))
        return self.features(obs)

    def update(self, obs: dict[str, np.ndarray], approach: Array) -> NDArray[np.float32]:
        """The touch observation after a touch along `approach` (unit, object-centred)."""
        count = int(np.sum(obs["mask"]))
        element = np.zeros(self.touch_width - 1)
        element[0:3] = np.asarray(approach, np.float64)
        element[3] = (count - self._count) / TOUCH_CONTACT_SCALE
        if self.taxels:
            if "taxels" not in obs:
                raise InvalidInputError(
                    "the tactile touch observation needs the pads' images (`taxels`): observe "
                    "hapticsim/HapticExploreTactile-v0 (sensing 'tactile')"
                )
            if count > self._count:  # the touch brought contacts: its pad image
                element[4:] = pool_taxels(obs["taxels"])
        self._touches.append(element)
        self._count = count
        return self.features(obs)

    def features(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """The touch observation of a v0 observation (with this episode's touches)."""
        out = np.zeros(self.obs_dim, np.float64)
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
        block = out[TOUCHES_OFFSET:].reshape(MAX_TOUCHES, self.touch_width)
        if touches:
            block[: len(touches), :-1] = np.asarray(touches)
            block[: len(touches), -1] = 1.0
        return np.clip(out, -OBS_BOUND, OBS_BOUND).astype(np.float32)


class HapticExploreTouchEnv(HapticExploreCompactEnv):
    """``hapticsim/HapticExploreCompact-v0``'s task, observed as the touch history itself.

    Action, reward (including the optional coverage term, computed as there), episode end,
    ``info`` and arguments are those of
    :class:`~hapticsim.envs.haptic_explore_compact_v0.HapticExploreCompactEnv`; only the observation
    differs: instead of engineered coverage features, the contacts and normals so far and the
    agent's past touches as two sets (:class:`TouchObserver`), for a permutation-invariant
    encoder (:data:`SETS`; ``lab.training.sb3.TouchSetExtractor``).

    ## Observation space

    ``Box(-10, 10, (545,), float32)``: :class:`TouchObserver`. No ground truth.

    ## Version history

    - v0: initial version.
    """

    #: Each touch's pad image in its element (:class:`TouchObserver`'s ``taxels``).
    taxels: bool = False

    def __init__(
        self, env: Any = None, render_mode: str | None = None, config: Any = None, **kwargs: Any
    ) -> None:
        super().__init__(env, render_mode=render_mode, config=config, **kwargs)
        self.touch_observer = TouchObserver(taxels=self.taxels)
        shape = (self.touch_observer.obs_dim,)
        self.observation_space = spaces.Box(-OBS_BOUND, OBS_BOUND, shape, np.float32)

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
    "TACTILE_ENV_ID",
    "TACTILE_OBS_DIM",
    "TACTILE_SETS",
    "TAXEL_GRID",
    "TouchObserver",
    "point_indices",
    "pool_taxels",
]
