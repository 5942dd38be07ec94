"""Stepping a scene: palm mocap, fingertip Cartesian servo (damped least squares), safety checks.

The simulator runs at a control rate of ``1 / (control_steps * timestep)``. Each control tick it

1. moves the palm's mocap body a bounded step toward the palm goal (position and rotation),
2. for every finger with a Cartesian tip target sets the position actuators to
   ``q + dls_step(J_tip, clip(target - tip))`` with ``J_tip`` from ``mj_jacSite``; a finger
   without a tip target is servoed to a joint posture,
3. steps the physics ``control_steps`` times and checks for instability (``mjWARN_BADQACC``,
   ``BADQVEL``, ``BADQPOS`` -- after which MuJoCo silently resets the state -- or a non-finite
   state), raising :class:`~hapticsim.errors.SimulationError`,
4. reads the fingertip contacts (:func:`~hapticsim.sim.contacts.fingertip_contacts`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, NamedTuple

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, positive_fields, positive_int
from hapticsim.errors import SimulationError
from hapticsim.sim._vec import norm
from hapticsim.sim.contacts import ContactState, FingertipContact, fingertip_contacts
from hapticsim.sim.dls import dls_step
from hapticsim.sim.mujoco_log import take_last_warning
from hapticsim.sim.scene import Scene
from hapticsim.sim.tactile import TactileHand

Array = NDArray[np.float64]

#: MuJoCo warnings of a state gone bad; MuJoCo resets the state when they fire.
_BAD_STATE = tuple(
    int(w)
    for w in (
        mujoco.mjtWarning.mjWARN_BADQACC,
        mujoco.mjtWarning.mjWARN_BADQVEL,
        mujoco.mjtWarning.mjWARN_BADQPOS,
    )
)


#: Under a force limit: how long after a touch [s] a fingertip approaches the surface it
#: touched slowly, and its largest step toward it per control tick [m] (25 mm/s at 4 ms).
GENTLE_HOLD: float = 0.1
GENTLE_STEP: float = 1e-4


@dataclass(frozen=True)
class ServoConfig:
    """Gains and limits of the control loop.

    Attributes:
        control_steps: physics steps per control tick.
        damping: DLS damping lambda [m].
        max_tip_error: largest Cartesian error fed to the DLS per tick [m].
        palm_speed: largest palm speed [m/s].
        palm_angular_speed: largest palm angular speed [rad/s].
        transit_speed: largest palm speed in free space, far from the object (fingers tucked,
            :meth:`Simulator.set_palm_goal` with ``transit=True``) [m/s]. The palm follows the
            mocap through a stiff weld (``solref`` 0.008 s), so it lags it by about
            ``transit_speed * 0.008`` = 2.4 cm, well inside the explorer's safety margin.
        transit_angular_speed: largest palm angular speed in free space [rad/s].
        skin_period: control ticks per frame of a tactile servo's pads (a tactile hand steering
            on its skin, :meth:`Simulator.touch`): 3 reads them at 83 Hz with the default
            ticks, between a vision-based pad's camera (25-60 Hz) and a taxel array (100 Hz
            and up). Each frame costs a pad's reading and estimate (about 0.4 ms): in one run
            the tactile environment ran at 0.43, 0.47 and 0.50 of exact sensing's steps per CPU
            second at 2, 3 and 4 (``docs/tactile/servo``).
    """

    control_steps: int = 4
    damping: float = 0.01
    max_tip_error: float = 0.01
    palm_speed: float = 0.6
    palm_angular_speed: float = 4.0
    transit_speed: float = 3.0
    transit_angular_speed: float = 20.0
    skin_period: int = 3

    def __post_init__(self) -> None:
        positive_int(self.control_steps, "control_steps")
        positive_int(self.skin_period, "skin_period")
        speeds = "palm_speed palm_angular_speed transit_speed transit_angular_speed"
        positive_fields(self, ["damping", "max_tip_error", *speeds.split()])


class SavedState(NamedTuple):
    """A snapshot of a :class:`Simulator` (:meth:`Simulator.get_state`)."""

    physics: Array
    commands: tuple[Any, ...]


def _quat(rot: Array) -> Array:
    """(4,) unit quaternion (w, x, y, z) of a rotation matrix (MuJoCo's conversion, fast)."""
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rot, dtype=np.float64).ravel())
    return quat


class Simulator:
    """A running scene with a palm goal and per-finger commands.

    Args:
        scene: the compiled scene.
        servo: control-loop settings.
        tactile_rng: with tactile sensing (the scene's configuration), the generator of the
            skin's sensor model (default seed 0).
    """

    def __init__(
        self,
        scene: Scene,
        servo: ServoConfig | None = None,
        tactile_rng: np.random.Generator | None = None,
    ) -> None:
        self.scene = scene
        self.model = scene.model
        self.hand = scene.hand
        self.servo = ServoConfig() if servo is None else servo
        self.data = mujoco.MjData(self.model)
        self.dt_control = self.servo.control_steps * self.model.opt.timestep
        self.steps = 0
        n = len(self.hand.fingers)
        self._tip_target: list[Array | None] = [None] * n
        self._posture: list[Array] = [f.posture("tucked") for f in self.hand.fingers]
        self._palm_goal_pos = np.zeros(3)
        self._palm_goal_quat = np.array([1.0, 0.0, 0.0, 0.0])
        self._palm_reached = True
        self._palm_speed = self.servo.palm_speed
        self._palm_angular_speed = self.servo.palm_angular_speed
        #: called with the simulator after every control tick and every :meth:`place` (e.g.
        #: to take a video frame); empty by default.
        self.tick_hooks: list[Callable[[Simulator], None]] = []
        self._contacts = ContactState((None,) * n, 0, 0)
        self._contacts_stale = False
        #: per finger, its pad's last frame (:meth:`touch`): (control tick, what it felt)
        self._felt: dict[int, tuple[int, FingertipContact | None]] = {}
        # Views and ids used every control tick (MjData's arrays are views: no re-reading).
        self._warnings = self.data.warning.number  # (mjNWARNING,) int view
        self._rotvec = np.zeros(3)
        self._quat_buf = np.zeros(4)
        self._vel6 = np.zeros(6)
        #: the fingertips' taxel pads, with tactile sensing (None with exact sensing).
        self.tactile = None
        #: the skin's force of a finger at a penetration (tactile sensing), else None.
        self._skin_force = None
        if scene.config.sensing == "tactile":

            rng = np.random.default_rng(0) if tactile_rng is None else tactile_rng
            self.tactile = TactileHand(scene, rng)
            self._skin_force = self.tactile.sphere_force
        #: whether the controllers steer on the skin's estimated contacts (:meth:`touch`)
        self.steers_on_skin = self.tactile is not None and scene.config.steer_on == "skin"
        #: a free object's pose (7,) at the last reset (SPEC §12), else None.
        self.initial_object_pose = None
        #: the scene's force limit [N] (None: none): a fingertip pressing harder backs off.
        self._force_limit = scene.config.force_limit
        self._touched: list[tuple[Array, float] | None] = [None] * n

    # ------------------------------------------------------------------ state
    @property
    def contacts(self) -> ContactState:
        """The fingertip contacts of the current state (read from MuJoCo when first asked for
        after a tick that did not read them)."""
        if self._contacts_stale:
            object_id = self.scene.object_geom_ids
            self._contacts = fingertip_contacts(
                self.model, self.data, self.hand, object_id, self._skin_force
            )
            self._contacts_stale = False
        return self._contacts

    def touch(self, finger: int) -> FingertipContact | None:
        """What a finger's controller feels now (its contact, or None).

        Exact sensing (or a tactile hand steering on ``"contacts"``): MuJoCo's contact
        (:attr:`contacts`). A tactile hand steering on its skin (SPEC §11): the contact its pad
        estimated from its latest frame (:meth:`~hapticsim.sim.tactile.TactileHand.feel`:
        point, outward normal, and the force the reading integrates to, after the sensor model
        with a fresh draw of its noise), None when no taxel was lit. A pad is read when first
        asked for :attr:`ServoConfig.skin_period` control ticks after its last frame, and the
        frame holds in between, as a sampled sensor's does. ``force_exact`` is MuJoCo's normal
        force at the frame and ``dist`` minus the estimated depth. A fingertip MuJoCo has no
        contact for reads nothing (its pad lies on it), and only the taxels near MuJoCo's
        contact point are cast (the rest read nothing, as
        :meth:`~hapticsim.sim.tactile.TactileHand.pad_force` checks)."""
        exact = self.contacts.tips[finger]
        if not self.steers_on_skin:
            return exact
        tick = self.steps // self.servo.control_steps
        last = self._felt.get(finger)
        if last is not None and tick - last[0] < self.servo.skin_period:
            return last[1]
        felt = None
        if exact is not None:
            near = self.tactile.near_contact(finger, exact.point_world, -exact.dist)
            est, force = self.tactile.feel(self.data, finger, near)
            self.tactile.follow_frame(finger, force, -exact.dist)
            if est is not None:
                felt = FingertipContact(
                    finger=finger, point_world=est.point, normal_world=est.normal,
                    force=est.force, dist=-est.depth, time=exact.time,
                    force_exact=exact.force_exact,
                )  # fmt: skip
        self._felt[finger] = (tick, felt)
        return felt

    @property
    def time(self) -> float:
        """Simulation time [s]."""
        return float(self.data.time)

    def reset(
        self,
        palm_world: Array,
        palm_rot_world: Array,
        postures: Mapping[int, Array] | None = None,
    ) -> None:
        """Reset the physics with the palm (and its mocap) at a pose and the fingers at postures.

        Args:
            palm_world: (3,) float, palm position [m].
            palm_rot_world: (3, 3) float, palm rotation (columns: palm axes in the world).
            postures: joint postures [rad] by finger index (other fingers: tucked).
        """
        mujoco.mj_resetData(self.model, self.data)
        self.steps = 0
        if self.tactile is not None:
            self.tactile.reset_softness()
        self.place(palm_world, palm_rot_world, postures)
        if self.scene.free:
            self.initial_object_pose = self.object_pose()
        self._contacts = fingertip_contacts(
            self.model, self.data, self.hand, self.scene.object_geom_ids, self._skin_force
        )
        self._contacts_stale = False
        self._felt.clear()

    def place(
        self,
        palm_world: Array,
        palm_rot_world: Array,
        postures: Mapping[int, Array] | None = None,
    ) -> None:
        """Put the hand at rest at a pose, without simulating the way there (a free-space move).

        The palm and its mocap jump to the pose, every finger to its posture (fingers not in
        `postures` tuck), all velocities are zero; simulation time does not advance. Use it only
        where the way is free space (:meth:`hand_clearance` tells whether the pose is): it stands
        for an arm that moves the hand around the object, which is not physics worth stepping.

        Args:
            palm_world: (3,) float, palm position [m, world].
            palm_rot_world: (3, 3) float, palm rotation.
            postures: joint postures [rad] by finger index.

        Raises:
            SimulationError: the pose is out of the arm's reach.
        """
        pos = finite_array(palm_world, "palm_world", (3,))
        self.scene.config.workspace.check_palm(pos)
        quat = _quat(finite_array(palm_rot_world, "palm_rot_world", (3, 3)))
        m, d, hand = self.model, self.data, self.hand
        postures = {} if postures is None else postures
        a = hand.palm_qpos_adr
        d.qpos[a : a + 3] = pos
        d.qpos[a + 3 : a + 7] = quat
        d.mocap_pos[hand.mocap_id] = pos
        d.mocap_quat[hand.mocap_id] = quat
        d.qvel[:] = 0.0
        d.qacc_warmstart[:] = 0.0
        for f in hand.fingers:
            q = postures.get(f.index)
            q = f.posture("tucked") if q is None else np.asarray(q, dtype=np.float64)
            q = np.minimum(np.maximum(q, f.ctrl_low), f.ctrl_high)
            hand.set_finger_qpos(d.qpos, f.index, q)
            d.ctrl[f.actuator_ids] = q
            self._posture[f.index] = q.copy()
            self._tip_target[f.index] = None
        self._palm_goal_pos = pos.copy()
        self._palm_goal_quat = quat.copy()
        self._palm_reached = True
        mujoco.mj_forward(m, d)
        self._contacts_stale = True
        self._felt.clear()  # a frame from before the hand was moved
        for hook in self.tick_hooks:
            hook(self)

    def hand_clearance(self) -> float:
        """Smallest distance [m] between the hand and anything else in the current state,
        among the contacts MuJoCo reports (those within the geoms' margins, 1 mm for the
        hand's geoms); ``inf`` when there are none. Valid after a step or :meth:`place`."""
        d, is_hand = self.data, self.hand.geom_is_hand
        ncon = int(d.ncon)
        if ncon == 0:
            return math.inf
        con = d.contact
        geoms, dists = con.geom, con.dist
        mixed = is_hand[geoms[:ncon, 0]] != is_hand[geoms[:ncon, 1]]
        return float(dists[:ncon][mixed].min()) if mixed.any() else math.inf

    def get_state(self) -> SavedState:
        """The physics state (MuJoCo's ``mjSTATE_INTEGRATION``) and the commands, for
        :meth:`set_state`."""
        kind = mujoco.mjtState.mjSTATE_INTEGRATION
        physics = np.empty(mujoco.mj_stateSize(self.model, kind))
        mujoco.mj_getState(self.model, self.data, physics, kind)
        commands = (
            self._palm_goal_pos.copy(), self._palm_goal_quat.copy(), self._palm_reached,
            self._palm_speed, self._palm_angular_speed, [p.copy() for p in self._posture],
            [None if t is None else t.copy() for t in self._tip_target], self.steps,
            self.model.geom_solref.copy(),  # the skin's softness (tactile sensing) lives there
        )  # fmt: skip
        return SavedState(physics, commands)

    def set_state(self, saved: SavedState) -> None:
        """Go back to a state saved by :meth:`get_state`."""
        kind = mujoco.mjtState.mjSTATE_INTEGRATION
        mujoco.mj_setState(self.model, self.data, saved.physics, kind)
        (self._palm_goal_pos, self._palm_goal_quat, self._palm_reached, self._palm_speed,
         self._palm_angular_speed, self._posture, self._tip_target,
         self.steps, solref) = saved.commands  # fmt: skip
        self.model.geom_solref[:] = solref
        mujoco.mj_forward(self.model, self.data)
        self._contacts_stale = True
        self._felt.clear()

    def object_pose(self) -> Array | None:
        """A free object's pose now (7,: position [m], quaternion w first; SPEC §12), None for a
        fixed object."""
        if not self.scene.free:
            return None
        from hapticsim.sim.dynamics import object_pose

        return object_pose(self.model, self.data, self.scene.object_body_id)

    def palm_pose(self) -> tuple[Array, Array]:
        """Actual palm position (3,) [m] and rotation (3, 3), world frame."""
        return self.hand.palm_pose(self.data)

    def mocap_pose(self) -> tuple[Array, Array]:
        """Palm mocap position (3,) [m] and rotation (3, 3), world frame."""
        i = self.hand.mocap_id
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, self.data.mocap_quat[i])
        return self.data.mocap_pos[i].copy(), rot.reshape(3, 3)

    def tip_world(self, finger: int) -> Array:
        """(3,) float, fingertip centre of a finger [m, world]."""
        return self.hand.tip_world(self.data, finger)

    def tip_velocity(self, finger: int) -> Array:
        """(3,) float, the velocity of a finger's tip site [m/s, world]."""
        site = self.hand.fingers[finger].site_id
        mujoco.mj_objectVelocity(self.model, self.data, mujoco.mjtObj.mjOBJ_SITE, site,
                                 self._vel6, 0)  # fmt: skip
        return self._vel6[3:].copy()

    # ------------------------------------------------------------------ commands
    def set_palm_goal(
        self, palm_world: Array, palm_rot_world: Array, transit: bool = False
    ) -> None:
        """Where the palm should go; the mocap moves there at bounded speed, tick by tick.

        Args:
            palm_world: (3,) float, goal position [m, world].
            palm_rot_world: (3, 3) float, goal rotation.
            transit: move at the free-space speeds (``servo.transit_speed``,
                ``transit_angular_speed``) instead of ``palm_speed``, ``palm_angular_speed``;
                only for motion well clear of the object and the table.

        Raises:
            SimulationError: the goal is out of the arm's reach.
        """
        pos = finite_array(palm_world, "palm_world", (3,))
        self.scene.config.workspace.check_palm(pos)
        self._palm_goal_pos = pos.copy()
        self._palm_goal_quat = _quat(finite_array(palm_rot_world, "palm_rot_world", (3, 3)))
        self._palm_reached = False
        servo = self.servo
        self._palm_speed = servo.transit_speed if transit else servo.palm_speed
        self._palm_angular_speed = (
            servo.transit_angular_speed if transit else servo.palm_angular_speed
        )

    def palm_at_goal(self, tol: float = 1e-4) -> bool:
        """True when the mocap has reached the palm goal."""
        if self._palm_reached:
            return True
        i = self.hand.mocap_id
        x, y, z = (self.data.mocap_pos[i] - self._palm_goal_pos).tolist()
        if x * x + y * y + z * z >= tol * tol:
            return False
        rotvec = self._rotvec
        mujoco.mju_subQuat(rotvec, self._palm_goal_quat, self.data.mocap_quat[i])
        return norm(rotvec) < 1e-3

    def set_tip_target(self, finger: int, target_world: Array | None) -> None:
        """Cartesian target of a fingertip centre [m, world]; None switches to its posture."""
        self._tip_target[finger] = (
            None if target_world is None else np.asarray(target_world, dtype=np.float64).copy()
        )

    def set_posture(self, finger: int, q: Array) -> None:
        """Joint posture [rad] of a finger (used while it has no tip target)."""
        f = self.hand.fingers[finger]
        q = np.asarray(q, dtype=np.float64)
        self._posture[finger] = np.clip(q, f.ctrl_range[:, 0], f.ctrl_range[:, 1])
        self._tip_target[finger] = None

    # ------------------------------------------------------------------ stepping
    def _advance_mocap(self) -> None:
        if self._palm_reached:
            return
        d, i = self.data, self.hand.mocap_id
        pos = d.mocap_pos[i]
        delta = self._palm_goal_pos - pos
        dist = norm(delta)
        max_step = self._palm_speed * self.dt_control
        if dist <= max_step:
            d.mocap_pos[i] = self._palm_goal_pos
        else:
            d.mocap_pos[i] = pos + delta * (max_step / dist)
        quat = self._quat_buf
        quat[:] = d.mocap_quat[i]
        rotvec = self._rotvec
        mujoco.mju_subQuat(rotvec, self._palm_goal_quat, quat)
        angle = norm(rotvec)
        max_angle = self._palm_angular_speed * self.dt_control
        if angle > max_angle:
            mujoco.mju_quatIntegrate(quat, rotvec, max_angle / angle)
            mujoco.mju_normalize4(quat)
            d.mocap_quat[i] = quat
        else:
            d.mocap_quat[i] = self._palm_goal_quat
            self._palm_reached = dist <= max_step

    def _servo_fingers(self) -> None:
        d, hand, servo = self.data, self.hand, self.servo
        ctrl, qpos, site_xpos = d.ctrl, d.qpos, d.site_xpos
        for f in hand.fingers:
            target = self._tip_target[f.index]
            if target is None:
                ctrl[f.actuator_ids] = self._posture[f.index]
                continue
            error = target - site_xpos[f.site_id]
            if self._force_limit is not None:
                error = self._limit_force(f.index, error)
            length = norm(error)
            if length > servo.max_tip_error:
                error *= servo.max_tip_error / length
            jac = hand.tip_jacobian(d, f.index)
            q = qpos[f.qpos_adr] + dls_step(jac, error, servo.damping)
            ctrl[f.actuator_ids] = np.minimum(np.maximum(q, f.ctrl_low), f.ctrl_high)

    def _limit_force(self, finger: int, error: Array) -> Array:
        """The tip's step under a force limit. A fingertip pressing harder than the limit (in
        the last tick's contacts) steps back along the contact's outward normal instead (0.5
        mm per tick at twice the limit); out of contact, for :data:`GENTLE_HOLD` s after a
        touch, its step toward the surface it touched is at most :data:`GENTLE_STEP` (a finger
        that strikes again at full speed after each back-off chatters at several times the
        limit: 1-1.5 N at a limit of 0.3 N on a cube's edge)."""
        contact = self.touch(finger)
        if contact is not None and contact.force > 0.0:
            self._touched[finger] = (contact.normal_world, self.time + GENTLE_HOLD)
            if contact.force > self._force_limit:
                excess = min(1.0, contact.force / self._force_limit - 1.0)
                return contact.normal_world * (5e-4 * excess)
            return error
        touched = self._touched[finger]
        if touched is not None and self.time < touched[1]:
            inward = -float(np.dot(error, touched[0]))
            if inward > GENTLE_STEP:
                error = error + touched[0] * (inward - GENTLE_STEP)
        return error

    def _check_stable(self) -> None:
        # MuJoCo's own checks (mj_checkPos/Vel/Acc) catch non-finite and huge values, count a
        # warning and reset the state: the three counters say it all.
        w, (i, j, k) = self._warnings, _BAD_STATE
        if w[i] or w[j] or w[k]:
            d = self.data
            said = take_last_warning()
            raise SimulationError(
                f"the simulation went unstable at t = {d.time:.4f} s (bad or non-finite "
                "positions, velocities or accelerations, mjWARN_BADQACC/BADQVEL/BADQPOS"
                + (f"; MuJoCo: {said}" if said else "")
                + "); try a smaller timestep or a gentler exploration"
            )

    def _link_push(self) -> tuple[Array, float] | None:
        """The object's push on the hand's parts other than the fingertips: the force-weighted
        mean outward normal (3,) and the total normal force [N], None without such contacts."""
        d = self.data
        ncon = int(d.ncon)
        if ncon == 0:
            return None
        objects, tips = set(self.scene.object_geom_ids), self.hand.tip_finger_of_geom
        hand = self.hand.hand_geom_set
        total, direction = 0.0, np.zeros(3)
        force6 = np.zeros(6)
        con = d.contact  # each attribute is a fresh (ncon, k) copy: read each once
        frames, efc = con.frame, con.efc_address
        for i, (g0, g1) in enumerate(con.geom[:ncon].tolist()):
            first = g0 in objects
            other = g1 if first else g0
            if not (first or g1 in objects) or other not in hand or other in tips:
                continue
            if efc[i] < 0:
                continue
            mujoco.mj_contactForce(self.model, d, i, force6)
            normal = frames[i, :3] if first else -frames[i, :3]
            total += max(float(force6[0]), 0.0)
            direction += max(float(force6[0]), 0.0) * normal
        if total <= 0.0:
            return None
        return direction / max(norm(direction), 1e-12), total

    def _palm_back_off(self) -> bool:
        """Under a force limit: when the hand's other parts push the object harder than the
        limit, the palm (its mocap) steps 0.5 mm back along the push instead of on to its goal;
        True when it did."""
        push = self._link_push()
        if push is None or push[1] <= self._force_limit:
            return False
        i = self.hand.mocap_id
        self.data.mocap_pos[i] = self.data.mocap_pos[i] + 5e-4 * push[0]
        self._palm_reached = False
        return True

    def tick(self, read: bool = True) -> ContactState | None:
        """One control tick (see module docstring).

        Args:
            read: read the fingertip contacts after the tick (step 4); with False
                (palm transit, where no controller looks at them) :attr:`contacts` reads them
                only if asked for.

        Returns:
            the contacts after the tick, None without `read`.
        """
        if self._force_limit is None or not self._palm_back_off():
            self._advance_mocap()
        self._servo_fingers()
        mujoco.mj_step(self.model, self.data, nstep=self.servo.control_steps)
        self.steps += self.servo.control_steps
        self._check_stable()
        if self.tactile is not None:
            self.tactile.follow_skin(self.data)
        self._contacts_stale = True
        for hook in self.tick_hooks:
            hook(self)
        if not read:
            return None
        return self.contacts


__all__ = ["SavedState", "ServoConfig", "Simulator"]
