"""Explorers: scripted strategies and environment policies behind one protocol."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.errors import InvalidInputError
from hapticsim.exploration import (
    PolicyExplorer,
    StrategyExplorer,
    Trial,
    check_explorer,
    explorer_for,
    explorer_names,
    is_policy,
)


def run_policy_exploration(truth, name, count, rng=0, scene_config=None, max_touches=None):  # noqa: ANN001, ANN201
    return PolicyExplorer(name, max_touches).explore(
        truth, count, np.random.default_rng(rng), scene_config
    )


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


def test_explorer_names() -> None:
    assert is_policy("uncertainty") and is_policy("learned:w.npz")
    # "paper" names the scripted strategy; a policy of the same name is the environment's
    assert not is_policy("paper") and not is_policy("learned:") and not is_policy("sweep")
    assert isinstance(explorer_for("paper"), StrategyExplorer)
    assert isinstance(explorer_for("learned:w.npz"), PolicyExplorer)
    names = explorer_names()
    assert len(names) == len(set(names)) and {"paper", "sweep", "uncertainty"} <= set(names)
    for bad in ("swep", "learned:", 3, None):
        with pytest.raises(InvalidInputError, match="`strategy` must be one of"):
            check_explorer(bad)
    with pytest.raises(InvalidInputError, match="did you mean 'sweep'"):
        Trial(explorer="swep")


def test_both_explorers_give_the_same_exploration_record() -> None:
    cube = get_body("cube")
    rng = np.random.default_rng(0)
    scripted = StrategyExplorer("patch").explore(cube, 25, rng, None)
    policy = run_policy_exploration(cube, "random", 25)
    assert type(scripted) is type(policy)
    assert set(scripted.arrays) == set(policy.arrays)
    # how many contacts 25 random touches bring depends on the path (another CPU, another
    # path): a property, at most the count asked and at least what a run must gather
    for run in (scripted, policy):
        assert 20 <= run.count <= 25 and len(run.arrays["points_clean"]) == run.count


def test_a_tactile_actor_explores_through_the_hands_pads(tmp_path) -> None:  # noqa: ANN001
    """With tactile sensing the policy sees the pads' images, which a tactile actor needs."""
    from dataclasses import replace

    from hapticsim.envs.haptic_explore_touch_v0 import TACTILE_ENV_ID, TACTILE_SETS
    from hapticsim.sim.scene import SceneConfig
    from tests.envs.test_haptic_explore_touch_v0 import random_set_actor

    path = random_set_actor(env_id=TACTILE_ENV_ID, sets=TACTILE_SETS).save(tmp_path / "t.npz")
    tactile = replace(SceneConfig(), sensing="tactile")
    run = run_policy_exploration(get_body("cube"), f"learned:{path}", 20, rng=0,
                                 scene_config=tactile, max_touches=40)  # fmt: skip
    assert run.count == 20 and len(run.tactile["images"]) == 20
    with pytest.raises(InvalidInputError, match="feels the pads' images"):
        run_policy_exploration(get_body("cube"), f"learned:{path}", 20, rng=0)
