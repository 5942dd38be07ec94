"""Free space along an exploration: where the fingertips have been, hence outside the object.

A fingertip is a solid that never enters the object (contacts push it out; the penetration of a
pressing fingertip is a fraction of a millimetre, far less than its radius), so its centre is
always outside the object, at the contacts and on every approach path between them. nML
(:mod:`hapticsim.fitting.ml`) keeps its solid out of such points. :class:`FreeSpaceTrace`
collects them from the simulation's control ticks (:attr:`Simulator.tick_hooks`), thinned to
one point per fingertip every :attr:`FreeSpaceTrace.spacing` metres of travel.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]

#: Default travel between two kept centres of one fingertip [m].
DEFAULT_SPACING: float = 0.004


class FreeSpaceTrace:
    """Fingertip centres along an exploration, one every `spacing` metres per finger.

    Args:
        spacing: travel between kept points of one fingertip [m], > 0.
    """

    def __init__(self, spacing: float = DEFAULT_SPACING) -> None:
        if not (np.isfinite(spacing) and spacing > 0):
            raise InvalidInputError(f"`spacing` must be finite and > 0 [m], got {spacing!r}")
        self.spacing = float(spacing)
        self._points: list[Array] = []
        self._last: dict[int, Array] = {}

    def attach(self, sim) -> None:  # noqa: ANN001 - a Simulator (no import cycle)
        """Record from every control tick of `sim` on."""
        sim.tick_hooks.append(self.capture)

    def capture(self, sim) -> None:  # noqa: ANN001
        """Keep each fingertip centre that is `spacing` away from its last kept one."""
        for finger in range(len(sim.hand.fingers)):
            tip = sim.tip_world(finger)
            last = self._last.get(finger)
            if last is None or float(np.sum((tip - last) ** 2)) >= self.spacing**2:
                kept = np.array(tip, dtype=np.float64)
                self._last[finger] = kept
                self._points.append(kept)

    def points(self) -> Array:
        """(f, 3) float, the kept centres [m, world], in the order recorded."""
        return np.array(self._points, dtype=np.float64).reshape(-1, 3)


def near_contacts(free_world: Array | None, points_world: Array, reach: float = 1.5) -> Array:
    """The free-space points (f, 3) [m] within `reach` data sizes of the contacts' centroid
    (the data size: the largest distance of a contact from it); the rest (palm transits far from
    the object) cannot touch a fitted solid and would only cost time. (0, 3) for None."""
    if free_world is None or not len(free_world) or not len(points_world):
        return np.zeros((0, 3))
    centre = points_world.mean(axis=0)
    size = float(np.max(np.linalg.norm(points_world - centre, axis=1)))
    keep = np.linalg.norm(free_world - centre, axis=1) <= reach * size
    return np.ascontiguousarray(free_world[keep])


__all__ = ["DEFAULT_SPACING", "FreeSpaceTrace", "near_contacts"]
