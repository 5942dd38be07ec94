"""Collects recorded fingertip contacts, pattern by pattern, up to a capacity.

With tactile sensing each contact comes with what the skin felt
(:class:`~hapticsim.sim.tactile.SensedContact`): the contact estimated from the finger's pad is
what the exploration records (``points_clean``), MuJoCo's exact contact is kept beside it
(``points_exact``), and every pad's reading at that moment is kept for ``tactile.npz``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import ChoiceError, InvalidInputError
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
        #: with tactile sensing, what the skin felt at each contact (else empty).
        self.sensed: list = []
        #: touches the skin did not feel (not recorded).
        self.unfelt = 0
        #: a free object (SPEC §12): called at each kept contact for the object's pose (7,);
        #: None for a fixed object.
        self.pose_source = None
        self.object_poses: list[Array] = []

    def __len__(self) -> int:
        return len(self.contacts)

    @property
    def full(self) -> bool:
        """True when the capacity is reached."""
        return self.capacity is not None and len(self.contacts) >= self.capacity

    def new_pattern(self, kind: str) -> int:
        """Open a new pattern (``"patch"`` or ``"stripe"``) and return its id."""
        if kind not in PATTERN_KINDS:
            raise ChoiceError("kind", kind, PATTERN_KINDS)
        self.pattern_kinds.append(kind)
        return len(self.pattern_kinds) - 1

    @property
    def tactile(self) -> bool:
        """True when the contacts were sensed by the skin."""
        return bool(self.sensed)

    def add(self, contact: FingertipContact, pattern: int, sensed=None) -> bool:  # noqa: ANN001
        """Keep a contact (and with tactile sensing, what the skin felt: a
        :class:`~hapticsim.sim.tactile.SensedContact` with an estimate); returns False (and
        drops it) when full."""
        if self.full:
            return False
        if self.contacts and (sensed is not None) != bool(self.sensed):
            raise InvalidInputError("a recorder holds exact or tactile contacts, not both")
        self.contacts.append(contact)
        self.pattern_of.append(int(pattern))
        if self.pose_source is not None:
            self.object_poses.append(self.pose_source())
        if sensed is not None:
            self.sensed.append(sensed)
        return True

    def points(self) -> Array:
        """(n, 3) float, the recorded contact points [m, world]: the estimated ones with
        tactile sensing."""
        if self.sensed:
            return np.array([s.estimate.point for s in self.sensed]).reshape(-1, 3)
        return np.array([c.point_world for c in self.contacts], dtype=np.float64).reshape(-1, 3)

    def arrays(self, start: int = 0) -> dict[str, np.ndarray]:
        """The contacts as arrays.

        Args:
            start: index of the first contact to include (e.g. those of the latest touch).

        Returns:
            ``points_clean`` (n, 3) [m, world], ``normals_clean`` (n, 3) outward unit normals,
            ``finger`` (n,) int, ``force`` (n,) normal force [N], ``time`` (n,) [s],
            ``pattern`` (n,) int pattern id, ``dist`` (n,) surface separation [m]. With tactile
            sensing ``points_clean``/``normals_clean`` are the estimated contacts and ``force``
            the skin's; beside them ``points_exact``, ``normals_exact`` (MuJoCo's contacts),
            ``force_exact`` (MuJoCo's normal force [N]), ``sigma`` (n,) the estimate's
            per-coordinate std [m], ``sigma_normal`` (n,) its normal's [rad], ``area`` (n,)
            [m^2] and ``taxels`` (n,) lit taxels. With a free object (SPEC §12)
            ``object_pose`` (n, 7): its true position [m] and quaternion (w first) at each
            contact.
        """
        out = {
            "points_clean": np.array([x.point_world for x in self.contacts[start:]],
                                     dtype=np.float64).reshape(-1, 3),
            "normals_clean": np.array([x.normal_world for x in self.contacts[start:]],
                                      dtype=np.float64).reshape(-1, 3),
            "finger": np.array([x.finger for x in self.contacts[start:]], dtype=np.int64),
            "force": np.array([x.force for x in self.contacts[start:]], dtype=np.float64),
            "time": np.array([x.time for x in self.contacts[start:]], dtype=np.float64),
            "pattern": np.array(self.pattern_of[start:], dtype=np.int64),
            "dist": np.array([x.dist for x in self.contacts[start:]], dtype=np.float64),
        }  # fmt: skip
        if self.pose_source is not None:
            poses = np.array(self.object_poses[start:], dtype=np.float64)
            out["object_pose"] = poses.reshape(-1, 7)
        if not self.sensed:
            return out
        est = [s.estimate for s in self.sensed[start:]]
        out["points_exact"], out["normals_exact"] = out["points_clean"], out["normals_clean"]
        out["force_exact"] = np.array(
            [x.force if x.force_exact is None else x.force_exact for x in self.contacts[start:]],
            dtype=np.float64,
        )
        out["points_clean"] = np.array([e.point for e in est]).reshape(-1, 3)
        out["normals_clean"] = np.array([e.normal for e in est]).reshape(-1, 3)
        out["force"] = np.array([e.force for e in est], dtype=np.float64)
        out["sigma"] = np.array([e.sigma for e in est], dtype=np.float64)
        out["sigma_normal"] = np.array([e.sigma_normal for e in est], dtype=np.float64)
        out["area"] = np.array([e.area for e in est], dtype=np.float64)
        out["taxels"] = np.array([e.taxels for e in est], dtype=np.int64)
        return out

    def tactile_arrays(self, start: int = 0) -> dict[str, np.ndarray]:
        """Every pad's reading at each recorded contact (``tactile.npz``; empty without tactile
        sensing): ``images`` (n, pads, rows, cols) readings [Pa], ``depth`` (n, pads, rows,
        cols) the skin's depth [m], ``slip`` (n, pads, rows, cols, 2) [m/s], ``traction`` (n,
        pads, rows, cols, 3) [Pa] and ``taxel_state`` (n, pads, rows, cols) (SPEC §11),
        ``pad_position``
        (n, pads, 3) [m, world], ``pad_rotation`` (n, pads, 3, 3), ``time`` (n,) [s]."""
        readings = [s.reading for s in self.sensed[start:]]
        if not readings:
            return {}
        return {
            "images": np.stack([r.pressure for r in readings]).astype(np.float32),
            "depth": np.stack([r.depth for r in readings]).astype(np.float32),
            "slip": np.stack([r.slip for r in readings]).astype(np.float32),
            "traction": np.stack([r.traction for r in readings]).astype(np.float32),
            "taxel_state": np.stack([r.state for r in readings]).astype(np.int8),
            "pad_position": np.stack([r.pad_position for r in readings]),
            "pad_rotation": np.stack([r.pad_rotation for r in readings]),
            "time": np.array([r.time for r in readings]),
        }


__all__ = ["PATTERN_KINDS", "Recorder"]
