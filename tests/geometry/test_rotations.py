"""Rotations: matrices, rotation vectors and quaternions (w, x, y, z)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from hapticsim.geometry.rotations import (
    is_rotation,
    matrix_to_quaternion,
    matrix_to_rotvec,
    orthonormalize,
    quaternion_to_matrix,
    random_rotation,
    rotvec_to_matrix,
)

FAST = settings(max_examples=100, deadline=None, database=None)
vectors = arrays(np.float64, 3, elements=st.floats(-1.0, 1.0))
quaternions = arrays(np.float64, 4, elements=st.floats(-1.0, 1.0)).filter(
    lambda q: np.linalg.norm(q) > 1e-3
)


@FAST
@given(direction=vectors, angle=st.floats(0.0, np.pi - 1e-6))
def test_rotvec_round_trip(direction: np.ndarray, angle: float) -> None:
    norm = np.linalg.norm(direction)
    rotvec = direction / norm * angle if norm > 1e-3 else np.zeros(3)
    matrix = rotvec_to_matrix(rotvec)
    assert is_rotation(matrix, tol=1e-12)
    np.testing.assert_allclose(matrix_to_rotvec(matrix), rotvec, atol=1e-9)
    # Same convention as scipy: v_world = R @ v_body, Rodrigues.
    np.testing.assert_allclose(matrix, Rotation.from_rotvec(rotvec).as_matrix(), atol=1e-12)


@FAST
@given(quat=quaternions)
def test_quaternion_round_trip_scalar_first(quat: np.ndarray) -> None:
    unit = quat / np.linalg.norm(quat)
    unit = unit if unit[0] >= 0 else -unit  # w >= 0 is the canonical sign
    matrix = quaternion_to_matrix(quat)
    assert is_rotation(matrix, tol=1e-12)
    back = matrix_to_quaternion(matrix)
    assert back[0] >= 0
    if back[0] < 1e-9:  # w = 0: q and -q both have w >= 0
        back = back if np.dot(back, unit) >= 0 else -back
    np.testing.assert_allclose(back, unit, atol=1e-9)
    scipy_xyzw = Rotation.from_matrix(matrix).as_quat()
    np.testing.assert_allclose(
        np.abs(np.dot(back, np.r_[scipy_xyzw[3], scipy_xyzw[:3]])), 1.0, atol=1e-9
    )


def test_half_turns_and_identity() -> None:
    for axis in np.eye(3):
        matrix = rotvec_to_matrix(np.pi * axis)
        np.testing.assert_allclose(np.abs(matrix_to_rotvec(matrix)), np.pi * axis, atol=1e-9)
    np.testing.assert_allclose(rotvec_to_matrix(np.zeros(3)), np.eye(3))
    np.testing.assert_allclose(matrix_to_quaternion(np.eye(3)), [1, 0, 0, 0])
    # MuJoCo's (w, x, y, z): a quarter turn about z maps x to y.
    q = [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)]
    np.testing.assert_allclose(quaternion_to_matrix(q) @ [1, 0, 0], [0, 1, 0], atol=1e-12)


def test_batched_conversions_match_single_ones() -> None:
    rng = np.random.default_rng(0)
    rotvecs = rng.normal(size=(4, 5, 3))
    batched = rotvec_to_matrix(rotvecs)
    assert batched.shape == (4, 5, 3, 3)
    np.testing.assert_allclose(batched[2, 3], rotvec_to_matrix(rotvecs[2, 3]), atol=1e-15)
    np.testing.assert_allclose(rotvec_to_matrix(matrix_to_rotvec(batched)), batched, atol=1e-9)


def test_is_rotation_and_orthonormalize() -> None:
    rng = np.random.default_rng(1)
    r = random_rotation(rng)
    assert is_rotation(r)
    assert not is_rotation(-r)  # det -1
    assert not is_rotation(2 * r)
    assert not is_rotation(np.eye(2))
    assert not is_rotation(np.full((3, 3), np.nan))
    noisy = r + 1e-3 * rng.normal(size=(3, 3))
    fixed = orthonormalize(noisy)
    assert is_rotation(fixed, tol=1e-12)
    np.testing.assert_allclose(fixed, r, atol=5e-3)
    reflected = orthonormalize(-r)
    assert is_rotation(reflected, tol=1e-12)


def test_random_rotations_are_uniform() -> None:
    rs = random_rotation(np.random.default_rng(2), size=20_000)
    assert rs.shape == (20_000, 3, 3)
    # Haar measure: E[R] = 0 entrywise; each entry has std 1/sqrt(3), so the mean of 20 000
    # has std 0.004 (measured max |mean| 0.0073).
    assert np.max(np.abs(rs.mean(axis=0))) < 0.02
    same = random_rotation(np.random.default_rng(2), size=20_000)
    assert np.array_equal(rs, same)
