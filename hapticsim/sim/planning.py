"""Palm placement: where to put the palm so that a fingertip can do its job without the rest of
the hand hitting the object, its stand or the table.

A finger's *radial direction* at a posture is the unit vector from its base to its tip centre;
moving the tip along it (extending or flexing the finger) is well conditioned. A palm pose for a
probe aligns the radial direction of a nominal posture with the approach direction and puts the
tip of that posture on the expected contact; the roll about the approach direction is chosen
among candidates, preferring a collision-free hand whose palm is high above the table.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.rotations import rotvec_to_matrix
from hapticsim.sim.kinematics import HandKinematics
from hapticsim.sim.scene import Scene

Array = NDArray[np.float64]

#: Clearance [m] the hand keeps from other geoms when a pose is checked.
CLEARANCE: float = 0.003


def rotation_between(a: Array, b: Array) -> Array:
    """(3, 3) rotation taking unit vector `a` to unit vector `b` (shortest arc)."""
    a = np.asarray(a, float) / np.linalg.norm(a)
    b = np.asarray(b, float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    s, c = float(np.linalg.norm(axis)), float(a @ b)
    if s < 1e-9:
        if c > 0:
            return np.eye(3)
        perp = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(perp) < 1e-6:
            perp = np.cross(a, [0.0, 1.0, 0.0])
        return rotvec_to_matrix(perp / np.linalg.norm(perp) * np.pi)
    return rotvec_to_matrix(axis / s * np.arctan2(s, c))


@dataclass(frozen=True)
class PalmPose:
    """A planned palm pose.

    Attributes:
        position: (3,) float, palm position [m, world].
        rotation: (3, 3) float, palm rotation (columns: palm axes in the world).
        score: preference (higher is better).
    """

    position: Array
    rotation: Array
    score: float


class PalmPlanner:
    """Plans palm poses on the kinematics of a *planning scene*.

    The planning scene is built from the rough object
    (:class:`~hapticsim.perception.vision.RoughObject`),
    so that plans use only what a controller may know, never the true shape.

    Args:
        scene: the planning scene.
    """

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.model = scene.model
        self.hand = scene.hand
        self.kin = HandKinematics(scene.model, scene.hand)
        self._radial: dict[tuple[object, ...], tuple[Array, Array]] = {}

    def radial(self, finger: int, q: Array) -> tuple[Array, Array]:
        """Tip centre (3,) [m] and radial direction (3,) of a finger posture, palm frame."""
        key = (finger, np.asarray(q, float).tobytes())
        if key not in self._radial:
            base, tip = self.kin.base_and_tip(finger, q, np.zeros(3), np.eye(3))
            u = tip - base
            self._radial[key] = (tip, u / np.linalg.norm(u))
        tip, u = self._radial[key]
        return tip.copy(), u.copy()

    def flexion_axis(self, finger: int, q: Array) -> Array:
        """(3,) float, unit axis of a finger's last driven joint at posture `q`, palm frame:
        the axis the finger flexes about."""
        key = (finger, np.asarray(q, float).tobytes(), "axis")
        if key not in self._radial:
            self.kin.base_and_tip(finger, q, np.zeros(3), np.eye(3))
            f = self.hand.fingers[finger]
            joint = int(self.model.dof_jntid[f.dof_adr[-1]])
            axis = self.kin.data.xaxis[joint].copy()
            self._radial[key] = (axis / np.linalg.norm(axis), axis)
        return self._radial[key][0].copy()

    def collision_count(
        self, position: Array, rotation: Array, postures: Mapping[int, Array],
        clearance: float = CLEARANCE,
    ) -> int:  # fmt: skip
        """Contacts closer than `clearance` between the hand and anything else at a pose.

        Fingers not in `postures` are tucked.
        """
        d, h = self.kin.data, self.hand
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, dtype=np.float64).ravel())
        d.qpos[h.palm_qpos_adr : h.palm_qpos_adr + 3] = position
        d.qpos[h.palm_qpos_adr + 3 : h.palm_qpos_adr + 7] = quat
        for f in h.fingers:
            q = postures.get(f.index)
            h.set_finger_qpos(d.qpos, f.index, f.posture("tucked") if q is None else q)
        mujoco.mj_fwdPosition(self.model, d)
        count = 0
        for i in range(int(d.ncon)):
            g0, g1 = d.contact.geom[i]
            if h.geom_is_hand[g0] != h.geom_is_hand[g1] and d.contact.dist[i] < clearance:
                count += 1
        return count

    def probe_poses(
        self,
        finger: int,
        tip_world: Array,
        direction_world: Array,
        posture: Array | None = None,
        flexion_axis_world: Array | None = None,
        rolls: int = 24,
    ) -> list[PalmPose]:
        """Candidate palm poses, best first, that put a finger's tip (at `posture`) on `tip_world`
        with its radial direction along `direction_world`.

        Args:
            finger: finger index.
            tip_world: (3,) float, where the tip centre should be at `posture` [m].
            direction_world: (3,) float, desired radial direction (e.g. the approach).
            posture: (n,) joint angles [rad] of the finger (default: its ``probe`` posture).
            flexion_axis_world: if given, the finger's flexion axis (:meth:`flexion_axis`) is
                kept (anti)parallel to it, so that the finger flexes in the plane normal to it
                (sweeps across an edge, strokes); otherwise the roll about the direction is free.
            rolls: number of roll angles tried when the roll is free.

        Returns:
            Collision-free candidates first, each group sorted by palm height above the table.
        """
        if posture is None:
            posture = self.hand.posture(finger, "probe")
        d = np.asarray(direction_world, float)
        d = d / np.linalg.norm(d)
        tip_palm, u = self.radial(finger, posture)
        base = rotation_between(u, d)
        rotations = []
        if flexion_axis_world is None:
            # one batched Rodrigues call for all rolls (a call costs ~50 us whatever its size)
            angles = np.linspace(0.0, 2 * np.pi, rolls, endpoint=False)
            rotations.extend(rotvec_to_matrix(angles[:, None] * d[None, :]) @ base)
        else:
            y = np.asarray(flexion_axis_world, float)
            y = y - (y @ d) * d
            y /= np.linalg.norm(y)
            axis = base @ self.flexion_axis(finger, posture)
            for sign in (1.0, -1.0):
                # roll about d until the flexion axis is along sign * y
                y_now = axis - (axis @ d) * d
                y_now /= np.linalg.norm(y_now)
                ang = np.arctan2(np.cross(y_now, sign * y) @ d, y_now @ (sign * y))
                rotations.append(rotvec_to_matrix(d * ang) @ base)
        center = self.scene.truth.center  # the planning scene holds the rough object
        poses = []
        for rot in rotations:
            pos = np.asarray(tip_world, float) - rot @ tip_palm
            hits = self.collision_count(pos, rot, {finger: posture})
            height = float(pos[2] - self.scene.table_top_z)
            away = float(np.linalg.norm(pos - center))
            score = height + 0.5 * away - 10.0 * hits
            if not self.scene.config.workspace.contains(pos):
                score -= 100.0
            poses.append(PalmPose(pos, rot, score))
        poses.sort(key=lambda p: -p.score)
        return poses

    def reachable(
        self,
        finger: int,
        pose: PalmPose,
        points_world: Sequence[Array],
        q_init: Array,
        tol: float = 0.001,
    ) -> tuple[bool, Array]:
        """Whether a fingertip can reach every point from a palm pose (IK within `tol` [m]).

        Returns:
            (all reachable, (k,) bool per point).
        """
        ok = np.zeros(len(points_world), dtype=bool)
        q = np.asarray(q_init, float)
        for i, p in enumerate(points_world):
            q, err = self.kin.ik(finger, np.asarray(p, float), pose.position, pose.rotation, q)
            ok[i] = err < tol
        return bool(ok.all()), ok


__all__ = ["CLEARANCE", "PalmPlanner", "PalmPose", "rotation_between"]
