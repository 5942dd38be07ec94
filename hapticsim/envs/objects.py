"""Which object an exploration episode gets: a seeded distribution over superquadrics."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hapticsim.constants import EPS_MAX, EPS_MIN, TAPER_MAX
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric, rotvec_to_matrix

#: Kinds of object distributions.
OBJECT_KINDS: tuple[str, ...] = ("paper", "random", "random_tapered")


def _check_range(name: str, value: tuple[float, float], low: float, high: float) -> None:
    ok = (
        isinstance(value, tuple) and len(value) == 2
        and all(np.isfinite(v) for v in value) and low <= value[0] <= value[1] <= high
    )  # fmt: skip
    if not ok:
        raise InvalidInputError(
            f"`{name}` must be a (low, high) tuple with {low} <= low <= high <= {high}, "
            f"got {value!r}"
        )


@dataclass(frozen=True)
class ObjectDistribution:
    """A distribution of objects, sampled once per episode; the pose stays fixed in an episode.

    Attributes:
        kind: ``"paper"`` (the paper's four bodies, :mod:`hapticsim.data.bodies`), ``"random"``
            (random superquadrics without taper) or ``"random_tapered"``.
        bodies: for ``"paper"``, the body names to draw from uniformly (default: all four).
        a_range: semi-axis range (low, high) [m] of random objects.
        eps_range: exponent range (low, high) of random objects, within [0.1, 2.0].
        taper_range: taper range (low, high) of ``"random_tapered"`` objects, within [-1, 1].
        yaw_range: objects are turned about the vertical through their centre by an angle drawn
            uniformly from [-yaw_range, yaw_range] [rad]; 0 keeps the body's own orientation.
    """

    kind: str = "paper"
    bodies: tuple[str, ...] = ()
    a_range: tuple[float, float] = (0.02, 0.05)
    eps_range: tuple[float, float] = (0.1, 1.0)
    taper_range: tuple[float, float] = (-0.4, 0.4)
    yaw_range: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in OBJECT_KINDS:
            raise InvalidInputError(f"`kind` must be one of {OBJECT_KINDS}, got {self.kind!r}")
        if self.kind == "paper":
            from hapticsim.data.bodies import BODY_NAMES

            bodies = tuple(self.bodies) if self.bodies else tuple(BODY_NAMES)
            unknown = [b for b in bodies if b not in BODY_NAMES]
            if unknown:
                raise InvalidInputError(
                    f"`bodies` must be names from {tuple(BODY_NAMES)}, got {unknown}"
                )
            object.__setattr__(self, "bodies", bodies)
        elif self.bodies:
            raise InvalidInputError(f"`bodies` is only for kind 'paper', got kind {self.kind!r}")
        _check_range("a_range", tuple(self.a_range), 1e-4, 10.0)
        _check_range("eps_range", tuple(self.eps_range), EPS_MIN, EPS_MAX)
        _check_range("taper_range", tuple(self.taper_range), -TAPER_MAX, TAPER_MAX)
        if not np.isfinite(self.yaw_range) or not 0.0 <= self.yaw_range <= np.pi:
            raise InvalidInputError(f"`yaw_range` must be in [0, pi] [rad], got {self.yaw_range}")

    @classmethod
    def coerce(cls, value: ObjectDistribution | str) -> ObjectDistribution:
        """A distribution from itself or from a kind name."""
        if isinstance(value, ObjectDistribution):
            return value
        if isinstance(value, str):
            return cls(kind=value)
        raise InvalidInputError(
            f"`objects` must be an ObjectDistribution or one of {OBJECT_KINDS}, got {value!r}"
        )

    def sample(self, rng: np.random.Generator) -> Superquadric:
        """Draw one object.

        Args:
            rng: the environment's generator.

        Returns:
            the object in the world frame (its centre where the body puts it; random objects at
            the origin).
        """
        if self.kind == "paper":
            from hapticsim.data.bodies import get_body

            shape = get_body(self.bodies[int(rng.integers(len(self.bodies)))])
        else:
            a = rng.uniform(*self.a_range, size=3)
            eps = rng.uniform(*self.eps_range, size=2)
            taper = (
                rng.uniform(*self.taper_range, size=2)
                if self.kind == "random_tapered" else np.zeros(2)
            )  # fmt: skip
            shape = Superquadric(a=a, eps=eps, taper=taper)
        if self.yaw_range > 0:
            yaw = rng.uniform(-self.yaw_range, self.yaw_range)
            rot = rotvec_to_matrix(np.array([0.0, 0.0, yaw]))
            shape = shape.transformed(rot, shape.center - rot @ shape.center)
        return shape
