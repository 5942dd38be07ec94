"""Which object an exploration episode gets: a seeded distribution, or a list of any objects.

- :class:`ObjectDistribution`: the paper's bodies, or random superquadrics (tapered or not)
  drawn from ranges;
- :class:`ObjectSet`: a list of objects of any kind (:mod:`hapticsim.data.objects`: body names,
  superquadric and union JSON files, ``random``/``random_tapered``, mesh files, or ready
  solids: :class:`~hapticsim.geometry.solid.Solid`), one drawn uniformly per episode. Files
  are read (and meshes checked) once, when the set is made; random entries are drawn from the
  episode's generator.

:func:`coerce_objects` turns what the environment's ``objects=`` accepts into one of them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim.constants import EPS_MAX, EPS_MIN, TAPER_MAX
from hapticsim.data.bodies import BODY_NAMES, get_body
from hapticsim.data.objects import (
    ObjectSpec,
    _check_range,
    as_spec,
    random_composite,
    random_handled,
    random_holed,
    random_superquadric,
)
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.geometry import rotvec_to_matrix
from hapticsim.geometry.solid import Solid

#: Kinds of object distributions.
OBJECT_KINDS: tuple[str, ...] = (
    "paper", "random", "random_tapered", "random_composite", "random_holed", "random_handled",
    "random_pybullet",
)  # fmt: skip


@dataclass(frozen=True)
class ObjectDistribution:
    """A distribution of objects, sampled once per episode; the pose stays fixed in an episode.

    Attributes:
        kind: ``"paper"`` (the paper's four bodies, :mod:`hapticsim.data.bodies`), ``"random"``
            (random superquadrics without taper), ``"random_tapered"`` or ``"random_composite"``
            (unions of 2-4 random superquadrics, :func:`hapticsim.data.objects.random_composite`;
            the ranges below are for the single superquadrics), ``"random_holed"``,
            ``"random_handled"``, or ``"random_pybullet"`` (one of pybullet_data's procedural
            objects that is one closed solid, :func:`_random_pybullet`; extra ``objects``).
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
            raise ChoiceError("kind", self.kind, OBJECT_KINDS)
        if self.kind == "paper":

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
    def coerce(cls, value: Any) -> ObjectDistribution | ObjectSet:
        """What the environment's ``objects=`` accepts (see :func:`coerce_objects`)."""
        return coerce_objects(value)

    def fixed_solids(self) -> tuple[Solid, ...]:
        """The solids :meth:`sample` returns as they are, the same instances every time: the
        paper bodies (without a yaw range); none for the random kinds."""
        if self.kind != "paper" or self.yaw_range > 0:
            return ()
        return tuple(get_body(b) for b in self.bodies)

    def sample(self, rng: np.random.Generator) -> Solid:
        """Draw one object.

        Args:
            rng: the environment's generator.

        Returns:
            the object in the world frame (its centre where the body puts it; random objects at
            the origin).
        """
        if self.kind == "paper":

            shape: Solid = get_body(self.bodies[int(rng.integers(len(self.bodies)))])
        elif self.kind == "random_composite":
            shape = random_composite(rng)
        elif self.kind == "random_holed":
            shape = random_holed(rng)
        elif self.kind == "random_handled":
            shape = random_handled(rng)
        elif self.kind == "random_pybullet":
            shape = _random_pybullet(rng)
        else:
            shape = random_superquadric(
                rng, self.kind == "random_tapered", self.a_range, self.eps_range, self.taper_range
            )
        if self.yaw_range > 0:
            yaw = rng.uniform(-self.yaw_range, self.yaw_range)
            rot = rotvec_to_matrix(np.array([0.0, 0.0, yaw]))
            shape = shape.transformed(rot, shape.center - rot @ shape.center)
        return shape


def _random_pybullet(rng: np.random.Generator) -> Solid:
    """One of pybullet_data's 1,000 procedural objects (``pybullet:random/NNN``), drawn uniformly
    among those that are one closed solid, centred on its centroid: an object refused as it is
    read (measured: 169 of the 1,000: 115 in two or more pieces apart, 53 open or
    inconsistent surfaces, random/168 with non-finite vertices) is drawn again.

    Raises:
        InvalidInputError: pybullet is not installed (the message says how to install it).
    """
    from hapticsim.data.library import PREFIX, RANDOM_COUNT, data_path

    data_path()  # not installed: said here, not taken for a refused object
    while True:
        name = f"{PREFIX}random/{int(rng.integers(RANDOM_COUNT)):03d}"
        try:
            return as_spec(name).resolve()
        except InvalidInputError:
            continue


@dataclass(frozen=True, eq=False)
class ObjectSet:
    """A list of objects of any kind; each episode draws one uniformly.

    Attributes:
        items: the objects: specs (:class:`~hapticsim.data.objects.ObjectSpec`, or a name or
            path turned into one) or ready solids. Fixed objects are
            resolved (files read, meshes checked) on construction; ``random`` and
            ``random_tapered`` entries are drawn anew each time they come up.

    Raises:
        InvalidInputError: an empty list, or an entry that is no object (the message names it).
    """

    items: tuple[Any, ...]
    _resolved: tuple[Solid | ObjectSpec, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        items = tuple(self.items)
        if not items:
            raise InvalidInputError("`objects` must hold at least one object, got an empty list")
        resolved: list[Solid | ObjectSpec] = []
        for k, item in enumerate(items):
            if isinstance(item, Solid):
                resolved.append(item)
                continue
            if not isinstance(item, (ObjectSpec, str, Path)):
                raise InvalidInputError(
                    f"`objects[{k}]` must be a name, a path, an ObjectSpec or a solid "
                    f"(Superquadric, SuperquadricUnion, MeshSolid), got {type(item).__name__}"
                )
            spec = as_spec(item)
            resolved.append(spec if spec.is_random else spec.resolve())
        object.__setattr__(self, "items", items)
        object.__setattr__(self, "_resolved", tuple(resolved))

    def __len__(self) -> int:
        return len(self._resolved)

    def fixed_solids(self) -> tuple[Solid, ...]:
        """The solids :meth:`sample` returns as they are, the same instances every time (every
        entry but the random ones)."""
        return tuple(item for item in self._resolved if isinstance(item, Solid))

    def sample(self, rng: np.random.Generator) -> Solid:
        """Draw one object (uniformly; a random entry then draws its shape from `rng`)."""
        item = self._resolved[int(rng.integers(len(self._resolved)))]
        return item.resolve(rng) if isinstance(item, ObjectSpec) else item


def coerce_objects(value: Any) -> ObjectDistribution | ObjectSet:
    """The object source of the environment's ``objects=``.

    Args:
        value: an :class:`ObjectDistribution` or :class:`ObjectSet` (as they are); a kind name
            (:data:`OBJECT_KINDS`: ``"paper"``, ``"random"``, ``"random_tapered"``,
            ``"random_composite"``); any other
            single object (a body name, a file path, an ObjectSpec or a solid); or a list or
            tuple of objects.

    Raises:
        InvalidInputError: naming what was not understood.
    """
    if isinstance(value, (ObjectDistribution, ObjectSet)):
        return value
    if isinstance(value, str) and value in OBJECT_KINDS:
        return ObjectDistribution(kind=value)
    if isinstance(value, (str, Path, ObjectSpec, Solid)):
        return ObjectSet((value,))
    if isinstance(value, Sequence) and not isinstance(value, (bytes, bytearray)):
        return ObjectSet(tuple(value))
    raise InvalidInputError(
        f"`objects` must be an ObjectDistribution, one of {OBJECT_KINDS}, an object (name, file, "
        f"ObjectSpec, solid) or a list of objects, got {value!r}"
    )


__all__ = ["OBJECT_KINDS", "ObjectDistribution", "ObjectSet", "coerce_objects"]
