"""The hand of ``models/hand.xml`` in a compiled model: fingers, ids and fingertip kinematics.

Finger indices (the ``finger`` column of ``contacts.npz``): 0 thumb, 1 index, 2 middle, 3 ring.
Every finger has three hinges (abduction, proximal and distal flexion), three position actuators,
a fingertip collision sphere, a site ``<finger>_tip`` at its centre and a touch sensor.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]

#: Finger names in index order.
FINGER_NAMES: tuple[str, ...] = ("thumb", "index", "middle", "ring")
#: Joint name suffixes of every finger, from the palm outwards.
JOINT_SUFFIXES: tuple[str, ...] = ("abd", "flex1", "flex2")
#: Radius of the fingertip spheres [m] (``models/hand.xml``, class ``tip``).
TIP_RADIUS: float = 0.008
#: Names of the palm body, its mocap target and the weld between them.
PALM_BODY: str = "palm"
PALM_MOCAP_BODY: str = "palm_mocap"


def finger_index(finger: int | str) -> int:
    """The index of a finger given by index or name.

    Raises:
        InvalidInputError: unknown finger; the message lists the choices.
    """
    if isinstance(finger, str):
        if finger not in FINGER_NAMES:
            raise InvalidInputError(
                f"`finger` must be one of {', '.join(FINGER_NAMES)}, got {finger!r}"
            )
        return FINGER_NAMES.index(finger)
    if isinstance(finger, (int, np.integer)) and not isinstance(finger, bool):
        if 0 <= int(finger) < len(FINGER_NAMES):
            return int(finger)
    raise InvalidInputError(
        f"`finger` must be an index 0..{len(FINGER_NAMES) - 1} or one of "
        f"{', '.join(FINGER_NAMES)}, got {finger!r}"
    )


def _id(model: mujoco.MjModel, obj: mujoco.mjtObj, name: str) -> int:
    i = mujoco.mj_name2id(model, obj, name)
    if i < 0:
        raise InvalidInputError(f"the model has no {obj.name[6:].lower()} named {name!r}")
    return int(i)


@dataclass(frozen=True)
class Finger:
    """Ids of one finger in a compiled model.

    Attributes:
        index: finger index (see :data:`FINGER_NAMES`).
        name: finger name.
        site_id: id of the fingertip site (sphere centre).
        tip_geom_id: id of the fingertip collision sphere.
        geom_ids: (k,) int, every geom of the finger (links and tip).
        qpos_adr: (3,) int, qpos addresses of its hinges (palm outwards).
        dof_adr: (3,) int, dof addresses of its hinges.
        actuator_ids: (3,) int, its position actuators.
        ctrl_range: (3, 2) float, control (joint) ranges [rad].
        touch_adr: address of its touch sensor in ``sensordata``.
        ctrl_low, ctrl_high: (3,) float, the columns of ``ctrl_range`` (contiguous copies for
            the control loop) [rad].
    """

    index: int
    name: str
    site_id: int
    tip_geom_id: int
    geom_ids: NDArray[np.int64]
    qpos_adr: NDArray[np.int64]
    dof_adr: NDArray[np.int64]
    actuator_ids: NDArray[np.int64]
    ctrl_range: Array
    touch_adr: int
    ctrl_low: Array = field(init=False, repr=False, compare=False)
    ctrl_high: Array = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "ctrl_low", np.ascontiguousarray(self.ctrl_range[:, 0]))
        object.__setattr__(self, "ctrl_high", np.ascontiguousarray(self.ctrl_range[:, 1]))


class Hand:
    """The hand's ids and fingertip kinematics for one compiled model.

    Args:
        model: a model that contains ``models/hand.xml`` (without name prefix).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.palm_body_id = _id(model, mujoco.mjtObj.mjOBJ_BODY, PALM_BODY)
        mocap_body = _id(model, mujoco.mjtObj.mjOBJ_BODY, PALM_MOCAP_BODY)
        self.mocap_id = int(model.body_mocapid[mocap_body])
        if self.mocap_id < 0:
            raise InvalidInputError(f"body {PALM_MOCAP_BODY!r} is not a mocap body")
        palm_joint = int(model.body_jntadr[self.palm_body_id])
        self.palm_qpos_adr = int(model.jnt_qposadr[palm_joint])
        fingers = []
        for k, name in enumerate(FINGER_NAMES):
            joints = [_id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{name}_{s}") for s in JOINT_SUFFIXES]
            acts = [_id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, f"{name}_{s}") for s in JOINT_SUFFIXES]
            bodies = {int(model.jnt_bodyid[j]) for j in joints}
            geoms = [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in bodies]
            touch = _id(model, mujoco.mjtObj.mjOBJ_SENSOR, f"{name}_touch")
            fingers.append(
                Finger(
                    index=k,
                    name=name,
                    site_id=_id(model, mujoco.mjtObj.mjOBJ_SITE, f"{name}_tip"),
                    tip_geom_id=_id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{name}_tip_geom"),
                    geom_ids=np.array(sorted(geoms), dtype=np.int64),
                    qpos_adr=np.array([model.jnt_qposadr[j] for j in joints], dtype=np.int64),
                    dof_adr=np.array([model.jnt_dofadr[j] for j in joints], dtype=np.int64),
                    actuator_ids=np.array(acts, dtype=np.int64),
                    ctrl_range=np.array([model.actuator_ctrlrange[a] for a in acts]),
                    touch_adr=int(model.sensor_adr[touch]),
                )
            )
        self.fingers: tuple[Finger, ...] = tuple(fingers)
        hand_bodies = {self.palm_body_id} | {
            int(model.geom_bodyid[g]) for f in fingers for g in f.geom_ids
        }
        self.hand_geom_ids = np.array(
            [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in hand_bodies],
            dtype=np.int64,
        )
        #: (ngeom,) bool, True for every geom of the hand.
        self.geom_is_hand = np.zeros(model.ngeom, dtype=bool)
        self.geom_is_hand[self.hand_geom_ids] = True
        #: finger index by fingertip-sphere geom id (the control loop's contact scan).
        self.tip_finger_of_geom: dict[int, int] = {int(f.tip_geom_id): f.index for f in fingers}
        #: ids of every geom of the hand, as a set of ints.
        self.hand_geom_set: frozenset[int] = frozenset(int(g) for g in self.hand_geom_ids)
        self._jac = np.zeros((3, model.nv))

    def tip_world(self, data: mujoco.MjData, finger: int) -> Array:
        """(3,) float, fingertip centre in the world [m] (after kinematics)."""
        return data.site_xpos[self.fingers[finger].site_id].copy()

    def tip_jacobian(self, data: mujoco.MjData, finger: int) -> Array:
        """(3, 3) float, d(tip_world)/d(finger joint angles) [m/rad], palm held fixed."""
        f = self.fingers[finger]
        mujoco.mj_jacSite(self.model, data, self._jac, None, f.site_id)
        return self._jac[:, f.dof_adr]  # fancy indexing: already a copy

    def finger_qpos(self, data: mujoco.MjData, finger: int) -> Array:
        """(3,) float, joint angles of a finger [rad]."""
        return data.qpos[self.fingers[finger].qpos_adr].copy()

    def palm_pose(self, data: mujoco.MjData) -> tuple[Array, Array]:
        """Palm position (3,) [m] and rotation (3, 3) in the world."""
        b = self.palm_body_id
        return data.xpos[b].copy(), data.xmat[b].reshape(3, 3).copy()


__all__ = ["FINGER_NAMES", "Finger", "Hand", "TIP_RADIUS", "finger_index"]
