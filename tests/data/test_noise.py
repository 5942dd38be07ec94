"""Measurement noise of SPEC §5."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data.noise import add_noise
from hapticsim.errors import HapticsimError


def _clean(count: int = 20_000) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    points = rng.normal(0.0, 0.05, (count, 3))
    normals = rng.normal(size=(count, 3))
    return points, normals / np.linalg.norm(normals, axis=1, keepdims=True)


def test_noise_levels_follow_spec() -> None:
    points, normals = _clean()
    noisy_p, noisy_n = add_noise(points, normals, noise=0.1, scale=0.04, rng=1)
    # Point std sigma_N * scale = 4 mm per coordinate; the sample std of 60 000 values has a
    # relative standard error of 0.3 %, so 1 % is over 3 of them (measured 3.98 mm).
    assert np.std(noisy_p - points) == pytest.approx(0.004, rel=0.01)
    np.testing.assert_allclose(np.linalg.norm(noisy_n, axis=1), 1.0, atol=1e-12)
    # Each component gets std 0.1; for small noise the angle to the clean normal is the length
    # of the 2-d tangential part, Rayleigh with mean 0.1 sqrt(pi/2) = 0.1253 rad (measured
    # 0.1256).
    angle = np.arccos(np.clip(np.sum(noisy_n * normals, axis=1), -1, 1))
    assert np.mean(angle) == pytest.approx(0.1 * np.sqrt(np.pi / 2), rel=0.02)


def test_zero_noise_returns_equal_copies_and_none_normals_pass_through() -> None:
    points, normals = _clean(10)
    p, n = add_noise(points, normals, noise=0.0, scale=0.03, rng=0)
    assert np.array_equal(p, points) and np.allclose(n, normals)
    assert p is not points
    p, n = add_noise(points, None, noise=0.2, scale=0.03, rng=0)
    assert n is None and not np.array_equal(p, points)


def test_same_seed_same_noise_bit_for_bit() -> None:
    points, normals = _clean(100)
    a = add_noise(points, normals, 0.1, 0.03, rng=5)
    b = add_noise(points, normals, 0.1, 0.03, rng=np.random.default_rng(5))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    c = add_noise(points, normals, 0.1, 0.03, rng=6)
    assert not np.array_equal(a[0], c[0])


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"noise": -0.1}, "noise"),
        ({"noise": float("nan")}, "noise"),
        ({"scale": 0.0}, "scale"),
        ({"scale": float("inf")}, "scale"),
        ({"points": np.zeros((4, 2))}, "points"),
        ({"normals": np.zeros((3, 3))}, "normals"),
        ({"normals": np.ones((4, 3)) * [1, 0, 0] * 0}, "normals"),
        ({"rng": 1.5}, "rng"),
    ],
)
def test_bad_input_raises_naming_the_argument(kwargs: dict, name: str) -> None:
    args = {"points": np.zeros((4, 3)), "normals": np.eye(3)[[0, 1, 2, 0]], "noise": 0.1}
    args |= {"scale": 0.03, "rng": 0} | kwargs
    with pytest.raises(HapticsimError, match=f"`{name}`"):
        add_noise(**args)
