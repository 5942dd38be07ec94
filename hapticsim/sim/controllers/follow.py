"""Contour following: one fingertip slides over the object in a plane, keeping contact, and records
contacts at regular spacing along its path (a stripe, paper III-A).

After a first probe (as in :mod:`probe`), every control tick uses the measured outward normal
``n`` of the fingertip contact:

- travel direction ``t = normalize(m x n)``, ``m`` the unit normal of the stripe's plane, signed
  to continue the previous direction; the motion is thereby projected on the tangent plane of
  the measured normal, and ``t`` turns with ``n`` when the fingertip rolls over an edge, so the
  stripe carries on along the next face;
- force: ``depth += k_i (f_des - f) dt`` (integral force control, clamped), the tip target lies
  ``depth`` inside the surface along ``-n``;
- target: ``tip + lead t - depth n - (m . (tip - p0)) m`` (the last term keeps the tip in its
  plane).

When the contact is lost (the tip ran past an edge) the controller *pivots*: the target circles
the last contact point (the edge) at fingertip radius, the assumed normal turning from ``n_last``
toward the travel direction at a fixed rate, until the fingertip touches the next face. A contact
is recorded when the contact point is ``spacing`` from the previously recorded one and the normal
force lies in the band. The stripe ends after ``length`` of path, when the finger stalls (joint
limits, reach), or when it pivots too far without touching.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, finite_float, positive_fields
from hapticsim.errors import InvalidInputError
from hapticsim.sim._vec import cross, dot, norm
from hapticsim.sim.contacts import ContactState
from hapticsim.sim.controllers.base import FingerTask
from hapticsim.sim.controllers.probe import Probe, ProbeConfig
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.simulator import Simulator

Array = NDArray[np.float64]


@dataclass(frozen=True)
class FollowConfig:
    """Contour-following parameters.

    Attributes:
        force: desired normal force [N].
        band: (low, high) normal forces [N] within which contacts are recorded.
        lead: distance the target leads the tip along the tangent [m] (sets the speed).
        gain: integral force gain k_i [m/(N s)].
        max_depth: largest push into the surface [m].
        spacing: distance between recorded contacts along the path [m].
        pivot_rate: turning rate of the assumed normal while pivoting over an edge [rad/s].
        max_pivot: give up after pivoting this far without touching [rad].
        stall_time: give up when the tip moved less than 1 mm in this time [s].
        max_time: longest duration of the stripe [s].
    """

    force: float = 0.6
    band: tuple[float, float] = (0.2, 2.0)
    lead: float = 0.002
    gain: float = 0.02
    max_depth: float = 0.008
    spacing: float = 0.004
    pivot_rate: float = 8.0
    max_pivot: float = 2.2
    stall_time: float = 0.25
    max_time: float = 4.0

    def __post_init__(self) -> None:
        positive_fields(
            self,
            "force lead gain max_depth spacing pivot_rate max_pivot stall_time max_time".split(),
        )
        lo, hi = (finite_float(v, "band") for v in self.band)
        if not 0 <= lo < hi:
            raise InvalidInputError(
                f"`band` must be (low, high) with 0 <= low < high [N], got {self.band}"
            )


class FollowTask(FingerTask):
    """Follow the contour in a plane from a first probe, recording a stripe of contacts.

    Args:
        finger: finger index.
        start: the first probe (aim and approach direction).
        plane_normal_world: (3,) float, normal ``m`` of the stripe's plane (through the aim).
        direction_world: (3,) float, initial travel direction (projected on the tangent plane).
        length: path length to follow [m].
        recorder: where contacts go.
        pattern: pattern id in the recorder.
        config: following parameters.
        probe_config: parameters of the first probe.
    """

    def __init__(
        self,
        finger: int,
        start: Probe,
        plane_normal_world: Array,
        direction_world: Array,
        length: float,
        recorder: Recorder,
        pattern: int,
        config: FollowConfig | None = None,
        probe_config: ProbeConfig | None = None,
    ) -> None:
        super().__init__(finger, recorder, pattern)
        m = finite_array(plane_normal_world, "plane_normal_world", (3,))
        if np.linalg.norm(m) < 1e-9:
            raise InvalidInputError("`plane_normal_world` must be non-zero")
        self.plane_normal = m / np.linalg.norm(m)
        self.plane_point = start.aim_world.copy()
        t = finite_array(direction_world, "direction_world", (3,))
        self._t = t / max(float(np.linalg.norm(t)), 1e-12)
        self.start = start
        self.length = finite_float(length, "length", low=0.0)
        self.config = FollowConfig() if config is None else config
        self.probe_config = ProbeConfig() if probe_config is None else probe_config
        self.path = 0.0
        self._state = "idle"
        self._t0 = 0.0
        self._target = np.zeros(3)
        self._normal = -start.approach_world
        self._depth = 0.0
        self._last_point: Array | None = None
        self._last_record: Array | None = None
        self._pivot: tuple[Array, Array, Array] | None = None
        self._pivot_angle = 0.0
        self._stall_ref = (0.0, np.zeros(3))

    def _tangent(self, normal: Array) -> Array:
        t = cross(self.plane_normal, normal)
        length = norm(t)
        if length < 1e-6:
            return self._t
        t /= length
        return t if dot(t, self._t) >= 0 else -t

    def update(self, sim: Simulator, contacts: ContactState) -> None:
        if self.done:
            return
        f, pc, cfg = self.finger, self.probe_config, self.config
        tip = sim.tip_world(f)
        contact = self.touch(sim)
        now = sim.time
        if self._state == "idle":
            self._state, self._t0 = "move", now
            self._target = self.start.start(pc.standoff, self.tip_radius(sim))
            sim.set_tip_target(f, self._target)
            return
        if self._state == "move":
            touched = contact is not None and contact.force > 0
            if norm(tip - self._target) < pc.reach_tol or touched:
                self._state, self._t0 = "approach", now
            elif now - self._t0 > pc.move_time:
                self.finish(sim, "start point out of reach")
            return
        if self._state == "approach":
            if contact is not None and contact.force > 0:
                self._state, self._t0, self._depth = "press", now, 0.0
            else:
                entry = self.start.start(pc.standoff, self.tip_radius(sim))
                travelled = float((tip - entry) @ self.start.approach_world)
                if travelled > pc.standoff + pc.max_travel or now - self._t0 > pc.approach_time:
                    self.finish(sim, "first probe met nothing")
                    return
                self._target = self._target + self.start.approach_world * pc.speed * sim.dt_control
                sim.set_tip_target(f, self._target)
                return
        if self._state == "press":
            holding, contact = self.settle_press(sim, contact, cfg.force, self._depth)
            if holding:
                self._normal = contact.normal_world
                return
            if contact is not None:
                self._normal = contact.normal_world
                if contact.force >= cfg.force:
                    self.record(sim, contact)
                    self._last_point = self._last_record = contact.point_world
                    self._state, self._t0 = "follow", now
                    self._stall_ref = (now, tip)
                    self._t = self._tangent(self._normal)
                    return
            if now - self._t0 > pc.press_time:
                self.finish(sim, "could not press on the first contact")
                return
            self._depth = min(self._depth + pc.press_rate * sim.dt_control, cfg.max_depth)
            sim.set_tip_target(f, tip - self._normal * self._depth)
            return
        # ---- follow
        if now - self._t0 > cfg.max_time:
            self.finish(sim, "stripe timed out")
            return
        if contact is not None and contact.force > 0:
            self._pivot = None
            n = contact.normal_world
            self._normal = n
            force = contact.force
            point = contact.point_world
            if self._last_point is not None:
                self.path += norm(point - self._last_point)
            self._last_point = point
            lo, hi = cfg.band
            if (
                self._last_record is not None
                and norm(point - self._last_record) >= cfg.spacing
                and lo <= force <= hi
                and self.settled(sim, contact, sliding=True)
            ):
                self._last_record = point
                self.record(sim, contact)
                if self.done:
                    return
            if self.path >= self.length:
                self.finish(sim, "stripe complete")
                sim.set_tip_target(f, tip + n * 0.01)
                return
            t = self._tangent(n)
            self._t = t
            self._depth = float(np.clip(
                self._depth + cfg.gain * (cfg.force - force) * sim.dt_control, 0.0, cfg.max_depth
            ))  # fmt: skip
            off_plane = dot(self.plane_normal, tip - self.plane_point)
            target = tip + cfg.lead * t - self._depth * n - 0.5 * off_plane * self.plane_normal
        else:
            # pivot about the last contact point: turn the assumed normal toward the travel
            if self._pivot is None:
                pivot = self._last_point if self._last_point is not None else tip
                self._pivot = (pivot, self._normal, self._t)
                self._pivot_angle = 0.0
            pivot, n0, t0 = self._pivot
            self._pivot_angle += cfg.pivot_rate * sim.dt_control
            if self._pivot_angle > cfg.max_pivot:
                self.finish(sim, "lost contact")
                return
            c, s = np.cos(self._pivot_angle), np.sin(self._pivot_angle)
            n, t = c * n0 + s * t0, c * t0 - s * n0
            self._normal, self._t = n, t
            target = pivot + n * (self.tip_radius(sim) - self._depth) + t * 0.0005
        sim.set_tip_target(f, target)
        t_ref, p_ref = self._stall_ref
        if norm(tip - p_ref) > 0.001:
            self._stall_ref = (now, tip)
        elif now - t_ref > cfg.stall_time:
            self.finish(sim, "finger stalled (reach or joint limits)")


__all__ = ["FollowConfig", "FollowTask"]
