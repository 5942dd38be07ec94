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
