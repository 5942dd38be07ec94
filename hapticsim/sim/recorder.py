"""Collects recorded fingertip contacts, pattern by pattern, up to a capacity."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError
from hapticsim.sim.contacts import FingertipContact

Array = NDArray[np.float64]

#: Kinds of exploration patterns (paper III-A).
PATTERN_KINDS: tuple[str, ...] = ("patch", "stripe")


class Recorder:
    """The contacts an exploration keeps.

    Args:
        capacity: stop accepting contacts after this many (None: unlimited).
    """

    def __init__(self, capacity: int | None = None) -> None:
        if capacity is not None and capacity < 1:
            raise InvalidInputError(f"`capacity` must be >= 1 or None, got {capacity!r}")
        self.capacity = capacity
        self.contacts: list[FingertipContact] = []
        self.pattern_of: list[int] = []
        self.pattern_kinds: list[str] = []

    def __len__(self) -> int:
        return len(self.contacts)

    @property
    def full(self) -> bool:
        """True when the capacity is reached."""
        return self.capacity is not None and len(self.contacts) >= self.capacity

    def new_pattern(self, kind: str) -> int:
        """Open a new pattern (``"patch"`` or ``"stripe"``) and return its id."""
        if kind not in PATTERN_KINDS:
            raise InvalidInputError(f"`kind` must be one of {PATTERN_KINDS}, got {kind!r}")
        self.pattern_kinds.append(kind)
        return len(self.pattern_kinds) - 1

    def add(self, contact: FingertipContact, pattern: int) -> bool:
        """Keep a contact; returns False (and drops it) when full."""
        if self.full:
            return False
        self.contacts.append(contact)
        self.pattern_of.append(int(pattern))
        return True

    def arrays(self, start: int = 0) -> dict[str, np.ndarray]:
        """The contacts as arrays.

        Args:
            start: index of the first contact to include (e.g. those of the latest touch).

        Returns:
            ``points_clean`` (n, 3) [m, world], ``normals_clean`` (n, 3) outward unit normals,
            ``finger`` (n,) int, ``force`` (n,) normal force [N], ``time`` (n,) [s],
            ``pattern`` (n,) int pattern id, ``dist`` (n,) surface separation [m].
        """
        c = self.contacts[start:]
        return {
            "points_clean": np.array([x.point_world for x in c], dtype=np.float64).reshape(-1, 3),
            "normals_clean": np.array([x.normal_world for x in c], dtype=np.float64).reshape(-1, 3),
            "finger": np.array([x.finger for x in c], dtype=np.int64),
            "force": np.array([x.force for x in c], dtype=np.float64),
            "time": np.array([x.time for x in c], dtype=np.float64),
            "pattern": np.array(self.pattern_of[start:], dtype=np.int64),
            "dist": np.array([x.dist for x in c], dtype=np.float64),
        }


__all__ = ["PATTERN_KINDS", "Recorder"]
