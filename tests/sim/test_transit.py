"""Palm transit: the hand is put at rest at its next pose instead of stepping the free-space
way there, unless that pose touches something; contacts are as accurate either way."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.metrics.accuracy import contact_accuracy
from hapticsim.sim.explorer import ExplorerConfig
from hapticsim.sim.scene import build_scene
from hapticsim.sim.session import run_exploration
from hapticsim.sim.simulator import Simulator

BOX = Superquadric(a=(0.025, 0.03, 0.03), eps=(0.2, 0.2))


@pytest.fixture(scope="module")
def runs() -> dict[str, object]:
    return {
        transit: run_exploration(BOX, "paper", count=40, rng=2,
                                 config=ExplorerConfig(transit=transit))
        for transit in ("teleport", "simulate")
    }  # fmt: skip


def test_both_transits_gather_accurate_contacts(runs) -> None:
    for run in runs.values():
        acc = contact_accuracy(BOX, run.arrays["points_clean"], run.arrays["normals_clean"])
        # measured (seed 2): 40 contacts each, distance median 1.5e-6 m, angle median 0.31 deg
        assert run.count == 40
        assert acc["distance_median"] < 1e-4 and acc["angle_median_deg"] < 1.0


def test_teleport_steps_far_less(runs) -> None:
    # measured (seed 2, 40 contacts): 2404 against 3660 physics steps (66 %); on the paper's
    # 150-contact explorations the simulated time drops by a quarter
    assert runs["teleport"].steps < 0.8 * runs["simulate"].steps


def test_place_puts_the_hand_at_rest(runs) -> None:
    sim = Simulator(build_scene(BOX))
    sim.reset(np.array([0.0, 0.0, 0.25]), np.eye(3))
    pos = np.array([0.02, 0.01, 0.2])
    sim.place(pos, np.eye(3), {1: np.array([0.0, 0.4, 0.5])})
    palm, rot = sim.palm_pose()
    np.testing.assert_allclose(palm, pos, atol=1e-12)
    np.testing.assert_allclose(sim.mocap_pose()[0], pos, atol=1e-12)
    assert np.all(sim.data.qvel == 0.0) and sim.hand_clearance() == math.inf
    np.testing.assert_allclose(sim.hand.finger_qpos(sim.data, 1), [0.0, 0.4, 0.5])
    # into the object: the clearance turns negative (penetration)
    sim.place(BOX.center + np.array([0.0, 0.0, 0.03]), np.eye(3))
    assert sim.hand_clearance() < 0.0


def test_state_round_trip() -> None:
    sim = Simulator(build_scene(BOX))
    sim.reset(np.array([0.0, 0.0, 0.25]), np.eye(3))
    saved = sim.get_state()
    qpos, t = sim.data.qpos.copy(), sim.time
    sim.set_palm_goal(np.array([0.05, 0.0, 0.25]), np.eye(3))
    for _ in range(20):
        sim.tick()
    sim.set_state(saved)
    np.testing.assert_array_equal(sim.data.qpos, qpos)
    assert sim.time == t and sim.palm_at_goal()


def test_unknown_transit_is_named() -> None:
    with pytest.raises(InvalidInputError, match="transit.*teleport"):
        ExplorerConfig(transit="fly")
