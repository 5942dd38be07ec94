"""What holds the object up, and which contacts it makes unreachable for a fingertip.

The MuJoCo scene (:func:`hapticsim.sim.scene.build_scene`) sets the object on a thin vertical
post, the *stand*, under its lowest point nearest the centre, high above the table, so that the
fingers reach around its bottom. Both touch backends use the same rule, so that an action means
the same on both: a contact is unreachable when a fingertip of radius ``clearance`` touching it
would hit the support.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import FINGERTIP_RADIUS
from hapticsim.errors import ChoiceError
from hapticsim.geometry.solid import Solid
from hapticsim.sim.object_mesh import support_foot, support_points, support_radius

Array = NDArray[np.float64]

#: Kinds of support.
SUPPORTS: tuple[str, ...] = ("stand", "table", "none")
#: Largest radius of the stand [m]; thinner under small objects (as in ``hapticsim.sim.scene``).
STAND_RADIUS: float = 0.008


@dataclass(frozen=True)
class Support:
    """A support under the object.

    Attributes:
        kind: ``"stand"`` (a vertical post of `radius` under `foot`), ``"table"`` (the plane
            ``z = foot[2]``) or ``"none"``.
        foot: (3,) float, where the support touches the object [m, world] (its lowest point).
        radius: radius of the stand [m].
        clearance: fingertip radius [m]: how close to the support a contact may be.
    """

    kind: str
    foot: Array
    radius: float = STAND_RADIUS
    clearance: float = FINGERTIP_RADIUS

    def __post_init__(self) -> None:
        if self.kind not in SUPPORTS:
            raise ChoiceError("support", self.kind, SUPPORTS)
        object.__setattr__(self, "foot", np.asarray(self.foot, dtype=np.float64).reshape(3))

    @classmethod
    def under(cls, shape: Solid, kind: str = "stand") -> Support:
        """The support of `shape` by the MuJoCo scene's rule
        (:func:`hapticsim.sim.object_mesh.support_foot`), on the solid's dense surface points
        (:func:`~hapticsim.sim.object_mesh.support_points`: a superquadric's 91 x 181 grid
        of angles, about 0.1 mm apart, rather than its collision vertices) and at the lowest
        height."""

        foot = support_foot(shape, support_points(shape), level=True)
        return cls(kind, foot, support_radius(shape, STAND_RADIUS))

    def blocks(self, point: Array) -> bool:
        """True when a fingertip touching `point` (3,) [m, world] would hit the support."""
        p = np.asarray(point, dtype=np.float64)
        if self.kind == "none" or p[2] >= self.foot[2] + self.clearance:
            return False
        if self.kind == "table":
            return True
        return bool(np.linalg.norm(p[:2] - self.foot[:2]) < self.radius + self.clearance)
