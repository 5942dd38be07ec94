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
        h.set_finger_qpos(d.qpos, finger, q)
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

    def base_and_tip(
        self, finger: int, q: Array, palm_world: Array, palm_rot_world: Array
    ) -> tuple[Array, Array]:
        """The finger's base (origin of the body of its first joint) and tip centre, (3,) each
        [m, world], for joint angles `q` and a palm pose."""
        self._set(palm_world, palm_rot_world, finger, q)
        f = self.hand.fingers[finger]
        return self.data.xpos[f.base_body_id].copy(), self.data.site_xpos[f.site_id].copy()

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
            q_init: (n,) float, starting joint angles [rad].
            iterations: DLS iterations.
            damping: DLS damping [m].

        Returns:
            q (n,) [rad] and the remaining distance to the target [m].
        """
        f = self.hand.fingers[finger]
        lo, hi = f.ctrl_low, f.ctrl_high
        q = np.clip(np.asarray(q_init, dtype=np.float64), lo, hi)
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
            jac = self.hand.tip_jacobian(self.data, finger)
            q = np.clip(q + dls_step(jac, e, damping), lo, hi)
        self._set(palm_world, palm_rot_world, finger, q)
        return q, norm(target_world - self.data.site_xpos[f.site_id])


__all__ = ["HandKinematics"]
