"""Action semantics: decoding, encoding, tangent frames, touch results."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.envs.touch import (
    ACTION_DIM,
    Touch,
    TouchResult,
    decode_action,
    encode_touch,
)
from hapticsim.errors import InvalidInputError
from hapticsim.geometry.sections import tangent_frame


def test_decode_known_actions() -> None:
    t = decode_action(np.zeros(ACTION_DIM), max_stroke=0.05, stroke_spacing=0.005, n_fingers=4)
    np.testing.assert_allclose(t.approach, [1.0, 0.0, 0.0], atol=1e-12)
    assert t.stroke_angle == 0.0
    assert t.stroke_length == pytest.approx(0.025)
    assert t.finger == 2
    top = decode_action([0, 1, 0.5, 1, 1], 0.05, 0.005, 4)
    np.testing.assert_allclose(top.approach, [0, 0, 1], atol=1e-12)
    assert top.stroke_angle == pytest.approx(np.pi / 2)
    assert top.stroke_length == pytest.approx(0.05)
    assert top.finger == 3  # a4 = 1 is clipped to the last finger


def test_short_stroke_is_a_probe_and_out_of_range_actions_are_clipped() -> None:
    t = decode_action([5, -5, 0, -1, -1], 0.05, 0.005, 4)
    assert t.is_probe and t.stroke_length == 0.0 and t.finger == 0
    np.testing.assert_allclose(t.approach, [0, 0, -1], atol=1e-12)
    # a3 = -0.85 gives L = 0.00375 m < spacing 0.005 m: a probe.
    assert decode_action([0, 0, 0, -0.85, 0], 0.05, 0.005, 4).is_probe


def test_decode_rejects_bad_shapes_and_nan() -> None:
    with pytest.raises(InvalidInputError, match="action"):
        decode_action(np.zeros(4), 0.05, 0.005, 4)
    with pytest.raises(InvalidInputError, match="NaN"):
        decode_action([0, np.nan, 0, 0, 0], 0.05, 0.005, 4)


def test_encode_inverts_decode() -> None:
    rng = np.random.default_rng(0)
    for _ in range(200):
        a = rng.uniform(-1, 1, ACTION_DIM)
        t = decode_action(a, 0.05, 0.001, 4)
        b = encode_touch(t.approach, t.stroke_angle, t.stroke_length, t.finger, 0.05, 4)
        t2 = decode_action(b, 0.05, 0.001, 4)
        np.testing.assert_allclose(t2.approach, t.approach, atol=1e-6)
        assert np.cos(t2.stroke_angle - t.stroke_angle) == pytest.approx(1.0, abs=1e-9)
        assert t2.stroke_length == pytest.approx(t.stroke_length, abs=1e-7)
        assert t2.finger == t.finger


def test_uniform_actions_give_uniform_approach_directions() -> None:
    rng = np.random.default_rng(1)
    d = np.array([decode_action(a, 0.05, 0.005, 4).approach for a in rng.uniform(-1, 1, (4000, 5))])
    # Uniform on the sphere: each coordinate has mean 0 and variance 1/3 (4000 samples:
    # standard error of the variance about 0.0047).
    np.testing.assert_allclose(d.mean(axis=0), 0.0, atol=0.03)
    np.testing.assert_allclose(d.var(axis=0), 1 / 3, atol=0.02)


@pytest.mark.parametrize("normal", [[1, 0, 0], [0, 0, 1], [0, 0, -1], [0.3, -0.4, 0.866]])
def test_tangent_frame_is_orthonormal_and_upward(normal: list[float]) -> None:
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    t_h, t_v = tangent_frame(n)
    basis = np.stack([t_h, t_v, n])
    np.testing.assert_allclose(basis @ basis.T, np.eye(3), atol=1e-12)
    assert abs(t_h[2]) < 1e-12 or abs(n[2]) > 0.999  # horizontal unless n is vertical
    assert t_v[2] >= -1e-12  # points up (or is horizontal)


def test_touch_and_result_validate() -> None:
    with pytest.raises(InvalidInputError, match="approach"):
        Touch(np.zeros(3), 0.0, 0.0, 0)
    with pytest.raises(InvalidInputError, match="stroke_length"):
        Touch(np.ones(3), 0.0, -1.0, 0)
    with pytest.raises(InvalidInputError, match="status"):
        TouchResult.empty("bogus")
    empty = TouchResult.empty("missed")
    assert len(empty) == 0 and empty.points.shape == (0, 3)
