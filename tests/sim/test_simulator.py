"""The control tick: lazily read contacts, transit speed of the palm, servo config checks."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.perception.vision import RoughObject
from hapticsim.sim.contacts import fingertip_contacts
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import build_scene
from hapticsim.sim.simulator import ServoConfig

SPHERE = Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0), center=(0.0, 0.0, 0.05))


@pytest.fixture(scope="module")
def explorer() -> Explorer:
    scene = build_scene(SPHERE)
    return Explorer(scene, RoughObject(SPHERE, has_edges=False), Recorder())


def test_contacts_after_a_tick_without_reading_are_read_on_demand(explorer) -> None:
    top = SPHERE.center + np.array([0.0, 0.0, SPHERE.a[2]])
    explorer.probe_patch(1, [Probe(top, (0.0, 0.0, -1.0))])
    sim = explorer.sim
    contact = explorer.recorder.contacts[-1]
    sim.set_tip_target(1, contact.point_world)  # press again (the tip centre 8 mm inside)
    for _ in range(50):
        sim.tick(read=False)
    assert sim.tick(read=False) is None
    lazy = sim.contacts
    fresh = fingertip_contacts(sim.model, sim.data, sim.hand, sim.scene.object_geom_id)
    assert lazy.tips[1] is not None and fresh.tips[1] is not None
    np.testing.assert_array_equal(lazy.tips[1].point_world, fresh.tips[1].point_world)
    assert lazy.tips[1].force == fresh.tips[1].force
    assert sim.tick() is sim.contacts


def test_transit_moves_the_palm_at_the_transit_speed(explorer) -> None:
    sim = explorer.sim
    explorer.home()
    pos, rot = sim.mocap_pose()
    for transit, speed in ((False, sim.servo.palm_speed), (True, sim.servo.transit_speed)):
        start, _ = sim.mocap_pose()
        sim.set_palm_goal(start + np.array([0.1, 0.0, 0.0]), rot, transit=transit)
        sim.tick(read=False)
        moved = float(np.linalg.norm(sim.mocap_pose()[0] - start))
        assert moved == pytest.approx(speed * sim.dt_control, rel=1e-9)
    sim.set_palm_goal(pos, rot)


@pytest.mark.parametrize("name", ["transit_speed", "transit_angular_speed"])
def test_servo_config_rejects_non_positive_speeds(name: str) -> None:
    with pytest.raises(InvalidInputError, match=name):
        ServoConfig(**{name: 0.0})
