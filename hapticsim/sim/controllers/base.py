"""The base class of fingertip controllers ("tasks"): one finger, stepped every control tick."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from hapticsim.sim.contacts import ContactState
from hapticsim.sim.hand import finger_index
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.simulator import Simulator

#: Fingertip speed [m/s] below which a tactile press has settled.
SETTLE_SPEED: float = 0.001
#: Fingertip speed along the contact normal [m/s] below which a tactile press has settled: the
#: contact's damping force at it is a few percent of its elastic force on the heavier hands.
SETTLE_NORMAL_SPEED: float = 0.0002
#: Control ticks in a row a settled fingertip must stay calm.
SETTLE_TICKS: int = 3


class FingerTask(ABC):
    """A controller that drives one fingertip and records its contacts.

    Each control tick the explorer calls :meth:`update` with the contacts after the tick; the task
    sets the finger's Cartesian tip target on the simulator and may record contacts. When it has
    nothing left to do it sets :attr:`done`.

    Args:
        finger: finger index.
        recorder: where contacts go.
        pattern: pattern id in the recorder.
    """

    def __init__(self, finger: int, recorder: Recorder, pattern: int) -> None:
        self.finger = finger_index(finger)
        self.recorder = recorder
        self.pattern = pattern
        self.done = False
        self.recorded = 0
        #: touches the finger's pad did not feel (tactile sensing): not recorded.
        self.unfelt = 0
        self.message = ""
        self._calm: tuple[int, int] = (-1, 0)  # (simulator step, calm ticks in a row)
        self._hold: tuple[int, np.ndarray] | None = None  # (simulator step, held target)
        self._held = None  # the contact felt when the hold began

    def touch(self, sim: Simulator):  # noqa: ANN201 - FingertipContact | None
        """What this finger feels now (:meth:`~hapticsim.sim.simulator.Simulator.touch`: the
        skin's estimated contact when a tactile hand steers on it, else MuJoCo's), except while
        a press of a hand steering on its skin is held still (:meth:`hold`): then the frame
        that began the hold, since the hold waits on the finger's own motion (:meth:`settled`)
        and reads the skin once at rest (:meth:`record`)."""
        if self._held is not None and sim.steps - self._hold[0] <= sim.servo.control_steps:
            return self._held
        self._held = None
        return sim.touch(self.finger)

    def tip_radius(self, sim: Simulator) -> float:
        """Radius [m] of this task's fingertip on the simulated hand."""
        return sim.hand.fingers[self.finger].tip_radius

    def settled(self, sim: Simulator, contact, sliding: bool = False) -> bool:  # noqa: ANN001
        """Whether a touch may be recorded now: always with exact sensing; with a tactile skin
        once the press has settled, the fingertip's speed along the contact normal below
        :data:`SETTLE_NORMAL_SPEED` and (unless it is `sliding` along the surface on purpose)
        its whole speed below :data:`SETTLE_SPEED`, over :data:`SETTLE_TICKS` control ticks in a
        row. A robot reads its skin at rest, and MuJoCo's force is then its static force: one
        calm tick may be the top of a bounce, a tip creeping sideways carries another normal
        force, and the contact's damping adds ``B v_n / R`` (0.15 N at 1 mm/s on the Shadow
        hand's fingertips)."""
        if sim.tactile is None:
            return True
        v = sim.tip_velocity(self.finger)
        normal = abs(float(v @ contact.normal_world))
        calm = normal < SETTLE_NORMAL_SPEED and (sliding or float(np.linalg.norm(v)) < SETTLE_SPEED)
        last, count = self._calm
        steady = sim.steps - last <= sim.servo.control_steps
        count = (count + 1 if steady else 1) if calm else 0
        self._calm = (sim.steps, count)
        return count >= SETTLE_TICKS

    def hold(self, sim: Simulator, target, contact) -> None:  # noqa: ANN001 - (3,) array
        """Hold a press still until it settles (:meth:`settled`): the tip's target stays where
        it was when the hold began (`target`, the press's target then), so the tip comes to
        rest instead of chasing a target that moves with it; `contact`, what the finger felt
        then, stands for its touch meanwhile (:meth:`touch`)."""
        if self._hold is None or sim.steps - self._hold[0] > sim.servo.control_steps:
            self._hold = (sim.steps, np.array(target, dtype=np.float64))
            self._held = contact if sim.steers_on_skin else None
        else:
            self._hold = (sim.steps, self._hold[1])
        sim.set_tip_target(self.finger, self._hold[1])

    def settle_press(self, sim: Simulator, contact, force: float,  # noqa: ANN001, ANN201
                     depth: float):  # fmt: skip
        """One tick of a press that has reached `force` [N]: hold it still at `depth` [m]
        along its normal until it settles (:meth:`settled`, :meth:`hold`), then the touch at
        rest (:meth:`at_rest`). Returns (holding, contact): the caller waits while holding;
        below `force` the contact is given back as it is."""
        if contact is None or contact.force < force:
            return False, contact
        if not self.settled(sim, contact):
            self.hold(sim, sim.tip_world(self.finger) - contact.normal_world * depth, contact)
            return True, contact
        return False, self.at_rest(sim, contact)

    def at_rest(self, sim: Simulator, contact):  # noqa: ANN001, ANN201 - FingertipContact
        """The touch once a held press has settled: with a hand steering on its skin a fresh
        frame (the held one may be from before the tip came to rest, or left the surface),
        else `contact` itself."""
        if not sim.steers_on_skin:
            return contact
        self._held = None
        return sim.touch(self.finger)

    def record(self, sim: Simulator, contact) -> None:  # noqa: ANN001 - FingertipContact
        """Keep a contact; stops the task when the recorder is full. With tactile sensing the
        fingertip's pad is read and the contact it felt is estimated; a touch it did not feel
        (outside the pad, below the sensor's threshold) is counted and not kept. A hand
        steering on its skin records MuJoCo's contact beside the estimate, as the truth it is
        scored against (``points_exact``)."""
        sensed = None
        if sim.steers_on_skin:  # what steered was the skin's (or a held frame): MuJoCo's now
            contact = sim.contacts.tips[self.finger]
        if sim.tactile is not None:
            sensed = sim.tactile.sense(sim.data, self.finger)
            if sensed.estimate is None or contact is None:
                self.unfelt += 1
                self.recorder.unfelt += 1
                return
        if self.recorder.add(contact, self.pattern, sensed):
            self.recorded += 1
        if self.recorder.full:
            self.finish(sim, "recorder full")

    def finish(self, sim: Simulator, message: str = "") -> None:
        """Stop: the finger holds where it is."""
        self.done = True
        self.message = message or self.message
        sim.set_tip_target(self.finger, sim.tip_world(self.finger))

    @abstractmethod
    def update(self, sim: Simulator, contacts: ContactState) -> None:
        """Advance by one control tick."""


__all__ = ["FingerTask"]
