"""A hand whose skin reads the elastic layer's law (SPEC §11, issue 38 item 3): MuJoCo's contact
follows it as it follows the Winkler skin, and its contacts are estimated as well."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.metrics.accuracy import contact_accuracy
from hapticsim.perception.tactile import SkinModel, SkinPreset
from hapticsim.sim.scene import SceneConfig
from hapticsim.sim.session import run_exploration


@pytest.mark.parametrize("steer_on", ["skin", "contacts"])
def test_mujoco_follows_a_layer_skin_at_the_recorded_touches(steer_on: str) -> None:
    """Measured (cube, seed 0, 60 touches): |skin / MuJoCo - 1| median 0.007, p95 0.031; the
    estimated contacts 0.04 mm from MuJoCo's (median). Margins of several times, as the
    episode's path differs between CPUs."""
    pytest.importorskip("skfem")
    skin = SkinPreset("elastomer", skin=SkinModel(2e5, 0.002, 0.45))
    config = SceneConfig(sensing="tactile", skin=skin, steer_on=steer_on)
    run = run_exploration(get_body("cube"), "paper", 30, 0, scene_config=config)
    a = run.arrays
    error = np.abs(a["force"] / np.maximum(a["force_exact"], 1e-9) - 1.0)
    assert run.count >= 20
    assert np.median(error) < 0.05 and np.percentile(error, 95) < 0.25
    accuracy = contact_accuracy(run.truth, a["points_clean"], a["normals_clean"])
    assert accuracy["distance_median"] < 3e-4
