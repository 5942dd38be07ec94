"""A described hand in a scene: composing it into an ``MjSpec`` and its ids in the compiled model.

:func:`attach_hand` puts the hand of a :class:`~hapticsim.sim.hand_description.HandDescription`
into a scene spec, whatever MJCF model it comes from:

- the root body's subtree is attached (names prefixed :data:`PREFIX`) under a free *mount* body
  that a weld constraint pulls onto the mocap body :data:`PALM_MOCAP_BODY`, so a script moves
  the hand by moving the mocap pose; joints of the root body itself (a wrist) are locked at 0;
- every body of the hand gets full gravity compensation; every colliding geom of the hand
  collides with the object, its stand and the table (contype 2 / conaffinity 1 against their
  1 / 2) and not with the rest of the hand (the model's explicit contact pairs stay);
- a fingertip without a touching geom in the model gets a collision sphere of the described
  radius at its tip centre, and a site there if it has none; touching geoms (added or the
  model's) slide with the scene's friction;
- actuation ``"add"``: the model's actuators are switched off (zero gain and bias) and a position
  actuator (kp, kv of the description) drives each described joint within its range less the
  joint margin.

Finger indices (the ``finger`` column of ``contacts.npz``) follow the description: 0 is the
thumb. Only the fingertip geoms' contacts are recorded; contacts of the object with other parts
of the hand are counted (:class:`~hapticsim.sim.contacts.ContactState.other_object`) and ignored.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import FINGERTIP_RADIUS
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.sim.hand_description import (
    POSTURE_NAMES,
    HandDescription,
    load_hand,
)

Array = NDArray[np.float64]

_LOG = logging.getLogger("hapticsim.mujoco")

#: Prefix of every element of the hand in a scene.
PREFIX: str = "hand/"
#: Names of the palm's mocap target and of the free mount body welded to it.
PALM_MOCAP_BODY: str = "palm_mocap"
MOUNT_BODY: str = PREFIX + "mount"
#: Stiffness of the weld that pulls the mount onto the mocap (time constant [s], damping ratio).
WELD_SOLREF: tuple[float, float] = (0.008, 1.0)
#: Fingertip radius [m] of hapticsim's own hand (``models/hand.xml``, class ``tip``).
TIP_RADIUS: float = FINGERTIP_RADIUS
#: Contact filter of hand geoms (collide with contype-1 objects only, never with each other).
HAND_CONTYPE, HAND_CONAFFINITY = 2, 1
#: Margin and gap [m] of added fingertip spheres (contacts reported within 1 mm, active at 0).
TIP_MARGIN: float = 0.001


def _tip_geom_name(finger: str) -> str:
    return f"{PREFIX}tip/{finger}"


def touching_geom_name(finger) -> str:  # noqa: ANN001 - FingerDescription
    """The scene name of a described finger's touching geom (the model's, or the sphere
    :func:`attach_hand` adds)."""
    return PREFIX + finger.geom if finger.geom is not None else _tip_geom_name(finger.name)


def _tip_site_name(finger: str) -> str:
    return f"{PREFIX}tip_site/{finger}"


def _drive_name(joint: str) -> str:
    return f"{PREFIX}drive/{joint}"


def attach_hand(
    spec: mujoco.MjSpec,
    description: HandDescription,
    friction: float,
    palm_world: tuple[float, float, float] = (0.0, 0.0, 0.3),
) -> None:
    """Compose the described hand into a scene spec (see the module docstring).

    Args:
        spec: the scene being built (its compiler reads angles in radians or degrees; the
            hand keeps its own units).
        description: the hand.
        friction: sliding friction of added fingertip spheres.
        palm_world: (3,) initial palm position [m, world].
    """
    source = mujoco.MjSpec.from_file(str(description.model))
    pos = [float(x) for x in palm_world]
    spec.worldbody.add_body(name=PALM_MOCAP_BODY, mocap=True, pos=pos)
    mount = spec.worldbody.add_body(name=MOUNT_BODY, pos=pos, gravcomp=1.0)
    mount.add_freejoint(name=PREFIX + "free")
    mount.explicitinertial = True
    mount.mass = 1e-3
    mount.inertia = [1e-7, 1e-7, 1e-7]
    degree = bool(source.compiler.degree)
    root = _attach_quietly(mount.add_frame(), source.body(description.root))
    root.pos = [0.0, 0.0, 0.0]
    root.quat = [1.0, 0.0, 0.0, 0.0]
    for texture in list(spec.textures):  # the hand model's sky is not the scene's
        if texture.type == mujoco.mjtTexture.mjTEXTURE_SKYBOX:
            spec.delete(texture)
    for joint in root.joints:  # the root's attachment to an arm or wrist: held at 0
        spec.add_equality(
            type=mujoco.mjtEq.mjEQ_JOINT, name1=joint.name, solref=[0.004, 1.0],
            data=np.zeros(12).tolist(),
        )  # fmt: skip
    # data: anchor (3), relative pose (position 3, quaternion 4), torque scale, unused: the mount
    # sits exactly at the mocap pose
    spec.add_equality(
        type=mujoco.mjtEq.mjEQ_WELD, name1=PALM_MOCAP_BODY, name2=MOUNT_BODY,
        objtype=mujoco.mjtObj.mjOBJ_BODY, solref=list(WELD_SOLREF),
        data=[0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0],
    )  # fmt: skip
    for body in [root, *root.find_all(mujoco.mjtObj.mjOBJ_BODY)]:
        body.gravcomp = 1.0
    for geom in root.find_all(mujoco.mjtObj.mjOBJ_GEOM):
        if geom.contype or geom.conaffinity:
            geom.contype, geom.conaffinity = HAND_CONTYPE, HAND_CONAFFINITY
    for f in description.fingers:
        body = spec.body(PREFIX + f.body)
        tip = (
            np.asarray(spec.site(PREFIX + f.site).pos, float)
            if f.site is not None else np.asarray(f.tip_pos, float)
        )  # fmt: skip
        if f.site is None:
            body.add_site(name=_tip_site_name(f.name), pos=tip.tolist(), size=[0.002, 0, 0],
                          group=4)  # fmt: skip
        if f.geom is not None:  # the model's touching geom slides with the scene's friction
            spec.geom(PREFIX + f.geom).friction = [friction, 0.005, 0.0001]
        else:
            body.add_geom(
                name=_tip_geom_name(f.name), type=mujoco.mjtGeom.mjGEOM_SPHERE,
                size=[f.tip_radius, 0, 0], pos=tip.tolist(), contype=HAND_CONTYPE,
                conaffinity=HAND_CONAFFINITY, condim=3, friction=[friction, 0.005, 0.0001],
                margin=TIP_MARGIN, gap=TIP_MARGIN, density=1000.0, rgba=[0.85, 0.35, 0.25, 1],
            )  # fmt: skip
    if description.actuation == "add":
        for act in spec.actuators:
            if act.name.startswith(PREFIX):
                act.gainprm[:] = 0.0
                act.biasprm[:] = 0.0
        for f in description.fingers:
            for j in f.joints:
                lo, hi = (np.radians(x) if degree else x for x in spec.joint(PREFIX + j).range)
                margin = min(description.joint_margin, 0.25 * (hi - lo))
                act = spec.add_actuator(name=_drive_name(j), target=PREFIX + j,
                                        trntype=mujoco.mjtTrn.mjTRN_JOINT)  # fmt: skip
                act.set_to_position(kp=description.kp, kv=description.kv)
                act.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
                act.ctrlrange = [lo + margin, hi - margin]
                act.forcelimited = mujoco.mjtLimited.mjLIMITED_FALSE


def _attach_quietly(frame: mujoco.MjsFrame, body: mujoco.MjsBody) -> mujoco.MjsBody:
    """Attach a body subtree (names prefixed :data:`PREFIX`). The hand model's own options and
    sizes (timestep, solver iterations, user-data sizes, ...) conflict with the scene's, which
    are kept: MuJoCo's note about the conflict goes to the debug log, not to stderr."""
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(lambda text: _LOG.debug("MuJoCo (attaching a hand): %s", text))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return frame.attach_body(body, PREFIX, "")
    finally:
        mujoco.set_mju_user_warning(previous)


def compile_scene(spec: mujoco.MjSpec) -> mujoco.MjModel:
    """Compile a scene spec with an attached hand, without repeating the attach conflicts
    (:func:`_attach_quietly`) as Python warnings."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Attach conflict")
        return spec.compile()


def _id(model: mujoco.MjModel, obj: mujoco.mjtObj, name: str) -> int:
    i = mujoco.mj_name2id(model, obj, name)
    if i < 0:
        raise InvalidInputError(f"the model has no {obj.name[6:].lower()} named {name!r}")
    return int(i)


@dataclass(frozen=True)
class Finger:
    """Ids of one finger in a compiled model.

    Attributes:
        index: finger index (0 is the thumb).
        name: finger name.
        site_id: id of the site at the fingertip centre.
        tip_geom_id: id of the touching geom.
        tip_radius: fingertip radius [m].
        base_body_id: body of the first driven joint (the finger's base).
        qpos_adr: (n,) int, qpos addresses of the driven joints (palm outwards).
        dof_adr: (n,) int, dof addresses of the driven joints.
        actuator_ids: (n,) int, the actuators driving them.
        ctrl_range: (n, 2) float, control (joint) ranges [rad or m].
        coupled: (passive qpos address, passive dof address, index of the driven joint it
            follows, ratio) per passive joint.
        postures: (n,) float joint angles by posture name, within `ctrl_range`.
        ctrl_low, ctrl_high: (n,) float, the columns of ``ctrl_range`` (contiguous copies for
            the control loop).
    """

    index: int
    name: str
    site_id: int
    tip_geom_id: int
    tip_radius: float
    base_body_id: int
    qpos_adr: NDArray[np.int64]
    dof_adr: NDArray[np.int64]
    actuator_ids: NDArray[np.int64]
    ctrl_range: Array
    coupled: tuple[tuple[int, int, int, float], ...]
    postures: dict[str, Array]
    ctrl_low: Array = field(init=False, repr=False, compare=False)
    ctrl_high: Array = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "ctrl_low", np.ascontiguousarray(self.ctrl_range[:, 0]))
        object.__setattr__(self, "ctrl_high", np.ascontiguousarray(self.ctrl_range[:, 1]))

    @property
    def n_joints(self) -> int:
        """Number of driven joints."""
        return int(len(self.qpos_adr))

    def posture(self, name: str) -> Array:
        """(n,) float, a copy of a named posture [rad] (:data:`POSTURE_NAMES`)."""
        return self.postures[name].copy()


class Hand:
    """The described hand's ids and fingertip kinematics in one compiled scene.

    Args:
        model: a scene model composed with :func:`attach_hand`.
        description: the hand's description (default: hapticsim's own hand).
    """

    def __init__(self, model: mujoco.MjModel, description: HandDescription | None = None) -> None:
        self.model = model
        self.description = load_hand(description)
        desc = self.description
        self.palm_body_id = _id(model, mujoco.mjtObj.mjOBJ_BODY, PREFIX + desc.root)
        mount = _id(model, mujoco.mjtObj.mjOBJ_BODY, MOUNT_BODY)
        mocap_body = _id(model, mujoco.mjtObj.mjOBJ_BODY, PALM_MOCAP_BODY)
        self.mocap_id = int(model.body_mocapid[mocap_body])
        self.palm_qpos_adr = int(model.jnt_qposadr[int(model.body_jntadr[mount])])
        fingers = []
        for k, f in enumerate(desc.fingers):
            joints = [_id(model, mujoco.mjtObj.mjOBJ_JOINT, PREFIX + j) for j in f.joints]
            if desc.actuation == "add":
                acts = [_id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, _drive_name(j)) for j in f.joints]
            else:
                acts = [_id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, PREFIX + a) for a in f.actuators]
            ctrl = np.array([model.actuator_ctrlrange[a] for a in acts], dtype=np.float64)
            limited = np.array([model.actuator_ctrllimited[a] for a in acts], dtype=bool)
            for i, j in enumerate(joints):  # unlimited actuators: the joint range, if any
                if not limited[i]:
                    ctrl[i] = model.jnt_range[j] if model.jnt_limited[j] else (-np.inf, np.inf)
            if desc.actuation == "model" and desc.joint_margin > 0:  # added ones have it already
                width = ctrl[:, 1] - ctrl[:, 0]
                margin = np.where(np.isfinite(width), np.minimum(desc.joint_margin, width / 4), 0)
                ctrl = ctrl + np.column_stack([margin, -margin])
            coupled = []
            for c in f.coupled:
                pj = _id(model, mujoco.mjtObj.mjOBJ_JOINT, PREFIX + c.joint)
                coupled.append((int(model.jnt_qposadr[pj]), int(model.jnt_dofadr[pj]),
                                f.joints.index(c.follows), float(c.ratio)))  # fmt: skip
            site = PREFIX + f.site if f.site is not None else _tip_site_name(f.name)
            geom = touching_geom_name(f)
            postures = {
                name: np.clip(np.array(f.posture(name), dtype=np.float64), ctrl[:, 0], ctrl[:, 1])
                for name in POSTURE_NAMES
            }
            fingers.append(
                Finger(
                    index=k,
                    name=f.name,
                    site_id=_id(model, mujoco.mjtObj.mjOBJ_SITE, site),
                    tip_geom_id=_id(model, mujoco.mjtObj.mjOBJ_GEOM, geom),
                    tip_radius=float(f.tip_radius),
                    base_body_id=int(model.jnt_bodyid[joints[0]]),
                    qpos_adr=np.array([model.jnt_qposadr[j] for j in joints], dtype=np.int64),
                    dof_adr=np.array([model.jnt_dofadr[j] for j in joints], dtype=np.int64),
                    actuator_ids=np.array(acts, dtype=np.int64),
                    ctrl_range=ctrl,
                    coupled=tuple(coupled),
                    postures=postures,
                )  # fmt: skip
            )
        self.fingers: tuple[Finger, ...] = tuple(fingers)
        #: finger names in index order.
        self.finger_names: tuple[str, ...] = desc.finger_names
        #: the fingers that sweep edges, the thumb's index (0) and the sweep's reference finger.
        self.sweep_fingers: tuple[int, ...] = desc.sweep_fingers
        self.thumb = 0
        self.index = 1 if len(fingers) > 1 else 0
        self.middle = self.sweep_fingers[len(self.sweep_fingers) // 2] if self.sweep_fingers else 0
        # every body under the mount is the hand
        hand_body = np.zeros(model.nbody, dtype=bool)
        hand_body[mount] = True
        for b in range(1, model.nbody):
            hand_body[b] = hand_body[b] or hand_body[int(model.body_parentid[b])]
        self.hand_geom_ids = np.flatnonzero(hand_body[model.geom_bodyid]).astype(np.int64)
        #: (ngeom,) bool, True for every geom of the hand.
        self.geom_is_hand = np.zeros(model.ngeom, dtype=bool)
        self.geom_is_hand[self.hand_geom_ids] = True
        #: finger index by fingertip geom id (the control loop's contact scan).
        self.tip_finger_of_geom: dict[int, int] = {int(f.tip_geom_id): f.index for f in fingers}
        #: ids of every geom of the hand, as a set of ints.
        self.hand_geom_set: frozenset[int] = frozenset(int(g) for g in self.hand_geom_ids)
        self._jac = np.zeros((3, model.nv))

    def finger_index(self, finger: int | str) -> int:
        """The index of a finger given by index or name.

        Raises:
            InvalidInputError: unknown finger; the message lists the choices.
        """
        return finger_index(finger, self.finger_names)

    def posture(self, finger: int, name: str) -> Array:
        """(n,) float, a named posture [rad] of a finger (:data:`POSTURE_NAMES`)."""
        return self.fingers[finger].posture(name)

    def set_finger_qpos(self, qpos: Array, finger: int, q: Array) -> None:
        """Write joint angles `q` of a finger, and the passive joints coupled to them, into a
        ``qpos`` vector."""
        f = self.fingers[finger]
        qpos[f.qpos_adr] = q
        for adr, _, k, ratio in f.coupled:
            qpos[adr] = ratio * q[k]

    def tip_world(self, data: mujoco.MjData, finger: int) -> Array:
        """(3,) float, fingertip centre in the world [m] (after kinematics)."""
        return data.site_xpos[self.fingers[finger].site_id].copy()

    def tip_jacobian(self, data: mujoco.MjData, finger: int) -> Array:
        """(3, n) float, d(tip_world)/d(driven joint angles) [m/rad], palm held fixed; a
        coupled passive joint adds its column, times its ratio, to the one it follows."""
        f = self.fingers[finger]
        mujoco.mj_jacSite(self.model, data, self._jac, None, f.site_id)
        jac = self._jac[:, f.dof_adr]  # fancy indexing: already a copy
        for _, dof, k, ratio in f.coupled:
            jac[:, k] += ratio * self._jac[:, dof]
        return jac

    def finger_qpos(self, data: mujoco.MjData, finger: int) -> Array:
        """(n,) float, driven joint angles of a finger [rad]."""
        return data.qpos[self.fingers[finger].qpos_adr].copy()

    def palm_pose(self, data: mujoco.MjData) -> tuple[Array, Array]:
        """Palm (root body) position (3,) [m] and rotation (3, 3) in the world."""
        b = self.palm_body_id
        return data.xpos[b].copy(), data.xmat[b].reshape(3, 3).copy()


def finger_index(finger: int | str, names: tuple[str, ...] | None = None) -> int:
    """The index of a finger given by index or by name.

    Args:
        finger: an index, or a name out of `names`.
        names: the hand's finger names (None: only indices >= 0 are checked, the hand checks
            the upper bound).

    Raises:
        InvalidInputError: unknown finger; the message lists the choices.
    """
    if isinstance(finger, str):
        if names is None or finger not in names:
            raise ChoiceError("finger", finger, names or ["an index"])
        return names.index(finger)
    if isinstance(finger, (int, np.integer)) and not isinstance(finger, bool):
        if 0 <= int(finger) and (names is None or int(finger) < len(names)):
            return int(finger)
    bound = f"0..{len(names) - 1} or one of {', '.join(names)}" if names else ">= 0"
    raise InvalidInputError(f"`finger` must be an index {bound}, got {finger!r}")


__all__ = [
    "Finger",
    "Hand",
    "MOUNT_BODY",
    "PALM_MOCAP_BODY",
    "PREFIX",
    "TIP_RADIUS",
    "attach_hand",
    "compile_scene",
    "finger_index",
    "touching_geom_name",
]
