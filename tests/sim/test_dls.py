"""The damped least-squares step against its defining formula."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.sim.dls import dls_step


@pytest.mark.parametrize("joints", [1, 3, 5])
def test_dls_step_is_the_damped_pseudo_inverse(joints: int) -> None:
    rng = np.random.default_rng(joints)
    for _ in range(20):
        jac = rng.normal(size=(3, joints)) * 0.05
        error = rng.normal(size=3) * 0.01
        damping = 10.0 ** rng.uniform(-4, -1)
        expected = jac.T @ np.linalg.solve(jac @ jac.T + damping**2 * np.eye(3), error)
        np.testing.assert_allclose(dls_step(jac, error, damping), expected, rtol=1e-9, atol=1e-15)


def test_a_singular_jacobian_gives_a_bounded_step() -> None:
    jac = np.zeros((3, 3))
    jac[:, 0] = [0.05, 0.0, 0.0]  # one joint moves the point along x only
    step = dls_step(jac, np.array([0.0, 0.01, 0.0]), 0.01)  # ask for y
    np.testing.assert_allclose(step, 0.0, atol=1e-15)
