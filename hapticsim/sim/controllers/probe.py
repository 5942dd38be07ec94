"""Probing: approach a point along a direction until the normal force passes a threshold, record,
retract; repeated over a list of points (a patch, paper III-A).

States per probe: ``move`` (tip to the start point ``aim - d (r + standoff)``), ``approach``
(the target advances along ``d`` at constant speed), ``press`` (the target is pushed along the
measured inward normal until the normal force reaches the threshold; the contact is recorded),
``retract`` (back along the measured normal; not after the last probe, where the finger holds
until the palm moves on). A probe that meets nothing within its travel, or whose start the
finger cannot reach, is skipped.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, positive_fields
from hapticsim.errors import InvalidInputError
from hapticsim.sim._vec import norm
from hapticsim.sim.contacts import ContactState
from hapticsim.sim.controllers.base import FingerTask
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.simulator import Simulator

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Probe:
    """One probe.

    Attributes:
        aim_world: (3,) float, expected surface point [m, world] (from the rough object).
        approach_world: (3,) float, unit direction of motion toward the surface [world].
    """

    aim_world: Array
    approach_world: Array

    def __post_init__(self) -> None:
        object.__setattr__(self, "aim_world", finite_array(self.aim_world, "aim_world", (3,)))
        d = finite_array(self.approach_world, "approach_world", (3,))
        norm = float(np.linalg.norm(d))
        if norm < 1e-9:
            raise InvalidInputError("`approach_world` must be a non-zero vector")
        object.__setattr__(self, "approach_world", d / norm)

    def start(self, standoff: float, tip_radius: float) -> Array:
        """(3,) float, tip-centre start point [m]: ``standoff`` [m] before a fingertip of
        radius `tip_radius` [m] touches the aim."""
        return self.aim_world - self.approach_world * (tip_radius + standoff)


@dataclass(frozen=True)
class ProbeConfig:
    """Probing parameters.

    Attributes:
        standoff: gap between fingertip and expected surface at the start [m].
        max_travel: travel beyond the expected surface before giving up [m].
        speed: approach speed [m/s].
        force_threshold: normal force that triggers recording [N].
        press_rate: growth rate of the push into the surface while pressing [m/s].
        retract: retraction distance along the normal [m].
        reach_tol: the start counts as reached within this distance [m].
        move_time: time allowed to reach the start or to retract [s].
        press_time: time allowed to build up the force [s].
    """

    standoff: float = 0.010
    max_travel: float = 0.025
    speed: float = 0.2
    force_threshold: float = 0.5
    press_rate: float = 0.02
    retract: float = 0.010
    reach_tol: float = 0.002
    move_time: float = 0.4
    press_time: float = 0.3

    @property
    def approach_time(self) -> float:
        """Longest approach [s]: 1.5 times the travel at speed, plus 0.1 s."""
        return 1.5 * (self.standoff + self.max_travel) / self.speed + 0.1

    def __post_init__(self) -> None:
        positive_fields(self, list(self.__dataclass_fields__))


class ProbeTask(FingerTask):
    """Probe a list of points with one fingertip, recording one contact per successful probe.

    Args:
        finger: finger index.
        probes: the probes, in order.
        recorder: where contacts go.
        pattern: pattern id in the recorder.
        config: probing parameters.
        miss_limit: stop after this many probes in a row met nothing or were out of reach
            (None: never).
    """

    def __init__(
        self,
        finger: int,
        probes: Sequence[Probe],
        recorder: Recorder,
        pattern: int,
        config: ProbeConfig | None = None,
        miss_limit: int | None = None,
    ) -> None:
        super().__init__(finger, recorder, pattern)
        self.miss_limit = miss_limit
        self.failed = 0
        self.probes = list(probes)
        self.config = ProbeConfig() if config is None else config
        self.index = -1
        self.missed = 0
        self.unreachable = 0
        self._state = "idle"
        self._t0 = 0.0
        self._target = np.zeros(3)
        self._normal = np.zeros(3)
        self._depth = 0.0
        self._retract_from = np.zeros(3)
        self._retract_dir = np.zeros(3)

    def _next(self, sim: Simulator) -> None:
        if self.miss_limit is not None and self.failed >= self.miss_limit:
            self.finish(sim, f"{self.failed} probes in a row met nothing")
            return
        self.index += 1
        if self.index >= len(self.probes):
            self.finish(sim, "all probes done")
            return
        self._state = "move"
        self._t0 = sim.time
        self._target = self.probes[self.index].start(self.config.standoff, self.tip_radius(sim))
        sim.set_tip_target(self.finger, self._target)

    def _retract(self, sim: Simulator, normal: Array) -> None:
        if self.index + 1 >= len(self.probes):  # the last probe: nothing to retract for
            self._next(sim)
            return
        self._state = "retract"
        self._t0 = sim.time
        self._retract_from = sim.tip_world(self.finger)
        self._retract_dir = np.asarray(normal, dtype=np.float64)
        self._target = self._retract_from + normal * self.config.retract
        sim.set_tip_target(self.finger, self._target)

    def update(self, sim: Simulator, contacts: ContactState) -> None:
        if self.done:
            return
        cfg, f = self.config, self.finger
        if self._state == "idle":
            self._next(sim)
            return
        probe = self.probes[self.index]
        tip = sim.tip_world(f)
        contact = self.touch(sim)
        elapsed = sim.time - self._t0
        if self._state == "move":
            if norm(tip - self._target) < cfg.reach_tol:
                self._state, self._t0 = "approach", sim.time
            elif contact is not None and contact.force > 0:
                self._state, self._t0 = "approach", sim.time  # touched early: treat as approach
            elif elapsed > cfg.move_time:
                self.unreachable += 1
                self.failed += 1
                self._retract(sim, -probe.approach_world)
            return
        if self._state == "approach":
            if contact is not None and contact.force > 0:
                self._state, self._t0, self._depth = "press", sim.time, 0.0
                self._normal = contact.normal_world
            else:
                start = probe.start(cfg.standoff, self.tip_radius(sim))
                travelled = float((tip - start) @ probe.approach_world)
                # beyond the travel, or stuck (reach, joint limits) well past the expected time
                if travelled > cfg.standoff + cfg.max_travel or elapsed > cfg.approach_time:
                    self.missed += 1
                    self.failed += 1
                    self._retract(sim, -probe.approach_world)
                    return
                self._target = self._target + probe.approach_world * cfg.speed * sim.dt_control
                sim.set_tip_target(f, self._target)
                return
        if self._state == "press":
            holding, contact = self.settle_press(sim, contact, cfg.force_threshold, self._depth)
            if holding:
                self._normal = contact.normal_world
                return
            if contact is not None:
                self._normal = contact.normal_world
                if contact.force >= cfg.force_threshold:
                    self.failed = 0
                    self.record(sim, contact)
                    if not self.done:
                        self._retract(sim, contact.normal_world)
                    return
            if elapsed > cfg.press_time:
                self.missed += 1
                self.failed += 1
                self._retract(sim, self._normal)
                return
            self._depth += cfg.press_rate * sim.dt_control
            sim.set_tip_target(f, tip - self._normal * self._depth)
            return
        if self._state == "retract":
            # move on once clear of the surface and half-way back
            clear = contact is None or contact.force == 0.0
            back = float((tip - self._retract_from) @ self._retract_dir)
            if (clear and back > 0.5 * cfg.retract) or elapsed > cfg.move_time:
                self._next(sim)


__all__ = ["Probe", "ProbeConfig", "ProbeTask"]
