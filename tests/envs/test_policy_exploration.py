"""explore --strategy with the environment's policies (uncertainty, learned) on the MuJoCo hand."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.envs.exploration import is_policy_strategy, run_policy_exploration
from hapticsim.errors import InvalidInputError


def test_the_uncertainty_policy_gathers_accurate_contacts_all_round() -> None:
    cube = get_body("cube")
    run = run_policy_exploration(cube, "uncertainty", 60, rng=0)
    assert run.count == 60 and run.complete and run.stop_reason is None
    dist, angle = cube.contact_errors(run.arrays["points_clean"], run.arrays["normals_clean"])
    assert np.median(dist) < 1e-4 and np.median(angle) < 2.0
    # the policy goes where the contacts are not: both sides of the cube get some
    x = run.arrays["points_clean"][:, 0]
    assert np.any(x > 0.02) and np.any(x < -0.02)
    assert run.free_space is not None and len(run.free_space) > 0
    assert set(run.pattern_kinds) <= {"patch", "stripe"}


def test_policy_names() -> None:
    assert is_policy_strategy("uncertainty") and is_policy_strategy("learned:w.npz")
    assert not is_policy_strategy("paper") and not is_policy_strategy("learned:")
    with pytest.raises(InvalidInputError, match="`policy` must be one of"):
        run_policy_exploration(get_body("cube"), "sweep", 40)


def test_a_tactile_actor_explores_through_the_hands_pads(tmp_path) -> None:  # noqa: ANN001
    """With tactile sensing the policy sees the pads' images, which a tactile actor needs."""
    from dataclasses import replace

    from hapticsim.envs.haptic_explore_touch import TACTILE_ENV_ID, TACTILE_SETS
    from hapticsim.sim.scene import SceneConfig
    from tests.envs.test_haptic_explore_touch import random_set_actor

    path = random_set_actor(env_id=TACTILE_ENV_ID, sets=TACTILE_SETS).save(tmp_path / "t.npz")
    tactile = replace(SceneConfig(), sensing="tactile")
    run = run_policy_exploration(get_body("cube"), f"learned:{path}", 20, rng=0,
                                 scene_config=tactile, max_touches=40)  # fmt: skip
    assert run.count == 20 and len(run.tactile["images"]) == 20
    with pytest.raises(InvalidInputError, match="feels the pads' images"):
        run_policy_exploration(get_body("cube"), f"learned:{path}", 20, rng=0)
