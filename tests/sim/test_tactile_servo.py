"""Controllers that feel (issue 38 item 4, SPEC §11): a tactile hand's probing and contour
following steer on the contact each touching pad estimates from its frames, not on MuJoCo's
contact list, and exact sensing keeps its controllers.

The figures of tactile-servo explorations (contact accuracy, fit epsilon and IoU against
steering on MuJoCo's contacts, per skin preset and hand; the environment's steps per second)
are measured in ``docs/tactile/servo`` (``scripts/tactile_servo.py``).
"""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.metrics.accuracy import contact_accuracy
from hapticsim.sim import tactile
from hapticsim.sim.scene import SceneConfig
from hapticsim.sim.session import run_exploration
from hapticsim.sim.simulator import ServoConfig, Simulator


@pytest.fixture(scope="module")
def frames():  # noqa: ANN201
    """A short tactile run of the cube (ideal skin) with every pad frame a controller read
    kept beside the whole pad's reading and estimate at that instant, and every touch a
    controller was given."""
    kept: list[dict] = []
    touches: list[tuple[bool, bool, bool, object]] = []
    feel, touch = tactile.TactileHand.feel, Simulator.touch

    def checked_feel(self, data, finger, near=None):  # noqa: ANN001, ANN202
        est, force = feel(self, data, finger, near)
        whole = self.estimate(self.read(data), finger)  # every taxel (no noise: ideal skin)
        kept.append({"est": est, "force": force, "whole": whole,
                     "whole_force": self.pad_force(data, finger)})  # fmt: skip
        return est, force

    def logged_touch(self, finger):  # noqa: ANN001, ANN202
        tick = self.steps // self.servo.control_steps
        before = self._felt.get(finger)  # the pad's last frame: (tick, contact)
        felt = touch(self, finger)
        held = before is not None and tick - before[0] < self.servo.skin_period
        touches.append((held, held and felt is before[1], self._felt[finger][0] == tick, felt))
        return felt

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(tactile.TactileHand, "feel", checked_feel)
        mp.setattr(Simulator, "touch", logged_touch)
        run = run_exploration(get_body("cube"), "paper", 30, 0,
                              scene_config=SceneConfig(sensing="tactile"))  # fmt: skip
    return run, kept, touches


def test_a_frame_is_the_whole_pads_estimate(frames) -> None:  # noqa: ANN001
    """A frame casts only the taxels near MuJoCo's contact point (the rest read nothing): its
    estimate and force are those of the whole pad's reading."""
    _, kept, _ = frames
    felt = [k for k in kept if k["est"] is not None]
    assert len(felt) > 50
    for k in felt:
        est, whole = k["est"], k["whole"]
        assert whole is not None and est.taxels == whole.taxels
        np.testing.assert_allclose(est.point, whole.point, rtol=0, atol=1e-12)
        np.testing.assert_allclose(est.normal, whole.normal, rtol=0, atol=1e-9)
        assert est.force == pytest.approx(whole.force, rel=1e-9)
        assert k["force"] == pytest.approx(k["whole_force"], rel=1e-9)
    assert all(k["whole"] is None for k in kept if k["est"] is None)


def test_the_controllers_are_given_the_skins_contact(frames) -> None:  # noqa: ANN001
    """What a controller is given is the frame's estimate (point on the surface, the force
    of the reading), held for the servo's skin period, with MuJoCo's force beside it."""
    run, _, touches = frames
    given = [felt for *_, felt in touches if felt is not None]
    assert len(given) > 50
    assert all(same for held, same, _, _ in touches if held)  # a frame holds between reads
    assert all(fresh for held, _, fresh, _ in touches if not held)  # then a new one is read
    assert sum(held for held, *_ in touches) > 0.3 * len(touches)
    points = np.array([f.point_world for f in given])
    normals = np.array([f.normal_world for f in given])
    acc = contact_accuracy(run.truth, points, normals)
    assert acc["distance_median"] < 5e-5  # measured 0.005 mm
    assert all(f.force_exact is not None and f.force > 0 for f in given)


def test_a_numb_skin_stops_a_hand_that_steers_on_it(monkeypatch) -> None:  # noqa: ANN001
    """With a skin that feels nothing the probes never stop on a touch, so nothing is
    gathered; steering on MuJoCo's contacts the same hand still presses and records."""
    monkeypatch.setattr(tactile.TactileHand, "feel", lambda self, data, finger, near=None: (
        None, 0.0))  # fmt: skip
    with pytest.raises(SimulationError, match="gathered only 0 contacts"):
        run_exploration(get_body("cube"), "paper", 20, 0,
                        scene_config=SceneConfig(sensing="tactile"))  # fmt: skip
    run = run_exploration(get_body("cube"), "paper", 20, 0,
                          scene_config=SceneConfig(sensing="tactile", steer_on="contacts"))
    assert run.count == 20


def test_exact_sensing_gives_the_controllers_mujocos_contacts() -> None:
    run = run_exploration(get_body("cube"), "paper", 20, 0)
    sim = run.explorer.sim
    assert not sim.steers_on_skin and sim.tactile is None
    for finger in range(len(sim.hand.fingers)):
        assert sim.touch(finger) is sim.contacts.tips[finger]


def test_a_bad_steering_or_skin_period_is_refused() -> None:
    with pytest.raises(InvalidInputError, match="steer_on"):
        SceneConfig(sensing="tactile", steer_on="mujoco")
    with pytest.raises(InvalidInputError, match="skin_period"):
        ServoConfig(skin_period=0)


@pytest.mark.parametrize("steer_on", ["skin", "contacts"])
def test_a_touch_is_recorded_with_mujocos_contact_at_rest(steer_on: str) -> None:
    """Either way, a recorded touch carries MuJoCo's contact of the instant it was read (not
    the one that began the hold): its force is the skin's static force (one contact law,
    docs/tactile/force: median |skin / MuJoCo - 1| 0.004 on the paper's bodies)."""
    config = SceneConfig(sensing="tactile", skin="capacitive", steer_on=steer_on)
    run = run_exploration(get_body("cube"), "paper", 40, 0, scene_config=config)
    a = run.arrays
    assert np.all(a["force_exact"] > 0)
    truth = np.linalg.norm(a["points_exact"] - a["points_clean"], axis=1)
    # the same touch: measured 0.50 mm both ways (capacitive taxels are 4 mm apart)
    assert np.median(truth) < 2e-3
