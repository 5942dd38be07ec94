"""The hand's workspace: where the palm may go and which objects the hand can explore.

The palm is driven by a mocap body, standing in for an arm; the arm's reach is a ball about a
base point. An object is explorable when its bounding sphere lies well inside that ball (the palm
must get around it) and it is not larger than the hand can span.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, positive_fields
from hapticsim.errors import SimulationError
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Workspace:
    """Reach of the palm and size limits of objects.

    Attributes:
        base_world: (3,) float, centre of the arm's reach [m, world].
        reach: radius of the ball the palm centre may occupy [m].
        max_object_radius: largest bounding radius of an explorable object [m].
        clearance: distance [m] the palm needs around an object's bounding sphere.
    """

    base_world: Array = field(default_factory=lambda: np.array([0.0, 0.0, 0.1]))
    reach: float = 0.5
    max_object_radius: float = 0.12
    clearance: float = 0.15

    def __post_init__(self) -> None:
        object.__setattr__(self, "base_world", finite_array(self.base_world, "base_world", (3,)))
        positive_fields(self, ("reach", "max_object_radius", "clearance"), unit="m")

    def contains(self, palm_world: Array) -> bool:
        """True if a palm position [m, world] is within reach."""
        return bool(np.linalg.norm(np.asarray(palm_world) - self.base_world) <= self.reach)

    def check_palm(self, palm_world: Array) -> None:
        """Raise SimulationError if the palm position is out of reach."""
        dist = float(np.linalg.norm(np.asarray(palm_world) - self.base_world))
        if dist > self.reach:
            raise SimulationError(
                f"palm target {np.round(palm_world, 3).tolist()} m is {dist:.3f} m from the arm "
                f"base {self.base_world.tolist()}, beyond its reach of {self.reach} m: the object "
                "is too far for the hand"
            )

    def check_object(self, truth: Solid) -> None:
        """Raise SimulationError if the object (any solid) is too large or too far for the
        hand."""
        radius = truth.bounding_radius
        if radius > self.max_object_radius:
            size = (
                f"bounding box {np.round(np.ptp(truth.bounds, axis=0), 4).tolist()} m; an object "
                "file in millimetres needs --scale 0.001"
            )
            raise SimulationError(
                f"object too large for the hand: bounding radius {radius:.3f} m exceeds "
                f"{self.max_object_radius} m ({size})"
            )
        dist = float(np.linalg.norm(truth.center - self.base_world))
        if dist + radius + self.clearance > self.reach:
            raise SimulationError(
                f"object too far for the hand: its centre {np.round(truth.center, 3).tolist()} m "
                f"is {dist:.3f} m from the arm base {self.base_world.tolist()}; the palm reaches "
                f"{self.reach} m and needs {self.clearance} m around the object "
                f"(bounding radius {radius:.3f} m)"
            )


__all__ = ["Workspace"]
