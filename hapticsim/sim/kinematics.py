"""Hand kinematics on a scratch ``MjData``: fingertip positions and inverse kinematics in the palm
frame, used to plan palm poses before the physics moves anything."""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.sim._vec import norm
from hapticsim.sim.dls import dls_step
from hapticsim.sim.hand import Hand

Array = NDArray[np.float64]


class HandKinematics:
    """Forward and inverse kinematics of the fingers with the palm at a given pose.

    Args:
        model: compiled model containing the hand.
        hand: its ids.
    """

    def __init__(self, model: mujoco.MjModel, hand: Hand) -> None:
        self.model = model
        self.hand = hand
        self.data = mujoco.MjData(model)

    def _set(self, palm_world: Array, palm_rot_world: Array, finger: int, q: Array) -> None:
        d, h = self.data, self.hand
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(palm_rot_world, dtype=np.float64).ravel())
        d.qpos[h.palm_qpos_adr : h.palm_qpos_adr + 3] = palm_world
        d.qpos[h.palm_qpos_adr + 3 : h.palm_qpos_adr + 7] = quat
        d.qpos[h.fingers[finger].qpos_adr] = q
        mujoco.mj_kinematics(self.model, d)
        mujoco.mj_comPos(self.model, d)

    def tip(self, finger: int, q: Array, palm_world: Array | None = None,
            palm_rot_world: Array | None = None) -> Array:  # fmt: skip
        """(3,) float, fingertip centre [m] for joint angles `q`, in the world for the given palm
        pose (default: palm frame)."""
        pos = np.zeros(3) if palm_world is None else palm_world
        rot = np.eye(3) if palm_rot_world is None else palm_rot_world
        self._set(pos, rot, finger, q)
        return self.data.site_xpos[self.hand.fingers[finger].site_id].copy()

    def distal_axis(self, finger: int, q: Array) -> Array:
        """(3,) float, unit direction of the distal link (flex2 joint to tip), palm frame."""
        self._set(np.zeros(3), np.eye(3), finger, q)
        f = self.hand.fingers[finger]
        body = int(self.model.jnt_bodyid[self.model.dof_jntid[f.dof_adr[2]]])
        axis = self.data.site_xpos[f.site_id] - self.data.xpos[body]
        return axis / np.linalg.norm(axis)

    def points(self, finger: int, q: Array, palm_world: Array, palm_rot_world: Array) -> Array:
        """(4, 3) float, finger base, proximal joint, distal joint and tip centre [m, world]."""
        self._set(palm_world, palm_rot_world, finger, q)
        f = self.hand.fingers[finger]
        bodies = [int(self.model.jnt_bodyid[self.model.dof_jntid[a]]) for a in f.dof_adr]
        d = self.data
        return np.stack([d.xpos[bodies[0]], d.xpos[bodies[1]], d.xpos[bodies[2]],
                         d.site_xpos[f.site_id]])  # fmt: skip

    def ik(
        self,
        finger: int,
        target_world: Array,
        palm_world: Array,
        palm_rot_world: Array,
        q_init: Array,
        iterations: int = 40,
        damping: float = 0.005,
    ) -> tuple[Array, float]:
        """Joint angles that put a fingertip centre at a target, within joint limits.

        Args:
            finger: finger index.
            target_world: (3,) float, target of the tip centre [m].
            palm_world, palm_rot_world: palm pose (position [m], rotation (3, 3)).
            q_init: (3,) float, starting joint angles [rad].
            iterations: DLS iterations.
            damping: DLS damping [m].

        Returns:
            q (3,) [rad] and the remaining distance to the target [m].
        """
        f = self.hand.fingers[finger]
        lo, hi = f.ctrl_range[:, 0], f.ctrl_range[:, 1]
        q = np.clip(np.asarray(q_init, dtype=np.float64), lo, hi)
        jac = np.zeros((3, self.model.nv))
        best = np.inf
        stale = 0
        for _ in range(iterations):
            self._set(palm_world, palm_rot_world, finger, q)
            e = target_world - self.data.site_xpos[f.site_id]
            err = norm(e)
            if err < 2e-5:
                break
            # give up early when a limit or the reach stops the progress
            stale = stale + 1 if err > best - 1e-5 else 0
            best = min(best, err)
            if stale >= 4:
                break
            mujoco.mj_jacSite(self.model, self.data, jac, None, f.site_id)
            q = np.clip(q + dls_step(jac[:, f.dof_adr], e, damping), lo, hi)
        self._set(palm_world, palm_rot_world, finger, q)
        return q, norm(target_world - self.data.site_xpos[f.site_id])


__all__ = ["HandKinematics"]
