"""Pad geometry: the exponential map onto a sphere, the flat plate, validation."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.perception.tactile import PadLayout
from hapticsim.perception.tactile.pad import MAX_PAD_ANGLE


def _sphere_pad(rows: int = 21, cols: int = 21, pitch: float = 0.0015, radius: float = 0.008):
    return PadLayout(rows, cols, pitch, radius, [0.3, 0.2, -0.9], [0, 1, 0], [0.01, 0, 0.02])


def test_curved_taxels_lie_on_the_sphere_with_outward_unit_normals() -> None:
    pad = _sphere_pad()
    pos, nrm, area = pad.taxels
    assert pos.shape == (21, 21, 3) and nrm.shape == (21, 21, 3) and area.shape == (21, 21)
    np.testing.assert_allclose(np.linalg.norm(pos - pad.origin, axis=-1), 0.008, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(nrm, axis=-1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(pos - pad.origin, 0.008 * nrm, atol=1e-15)
    np.testing.assert_allclose(nrm[10, 10], pad.normal, atol=1e-15)  # the centre


def test_rows_and_columns_through_the_centre_are_arcs_of_one_pitch() -> None:
    pad = _sphere_pad()
    _, nrm, _ = pad.taxels
    for line in (nrm[10, :], nrm[:, 10]):  # the middle row and column: great circles
        angles = np.arccos(np.clip(np.sum(line[1:] * line[:-1], axis=-1), -1, 1))
        np.testing.assert_allclose(angles * 0.008, 0.0015, rtol=1e-9)


def test_area_element_is_that_of_geodesic_polar_coordinates() -> None:
    pad = _sphere_pad()
    _, _, area = pad.taxels
    theta = np.hypot(*np.moveaxis(pad.uv, -1, 0)) / 0.008
    expected = 0.0015**2 * np.where(theta > 0, np.sin(theta) / np.where(theta > 0, theta, 1), 1)
    np.testing.assert_allclose(area, expected, rtol=1e-12)
    # and a grid four times finer over the same cells (84 = 4 x 21) sums to the same area
    fine = _sphere_pad(rows=84, cols=84, pitch=0.0015 / 4)
    assert abs(fine.taxels[2].sum() - area.sum()) / area.sum() < 3e-3


def test_flat_pad_is_a_plate_of_the_pitch() -> None:
    pad = PadLayout(3, 4, 0.002, None, [0, 0, 1], [0, 1, 0], [0, 0, 0.001])
    pos, nrm, area = pad.taxels
    np.testing.assert_allclose(pos[..., 2], 0.001)
    np.testing.assert_allclose(nrm, np.broadcast_to([0, 0, 1], nrm.shape))
    np.testing.assert_allclose(area, 0.002**2)
    np.testing.assert_allclose(np.diff(pos[0, :, 0]), 0.002)  # columns along e_u = up x normal
    np.testing.assert_allclose(pad.e_u, [1, 0, 0], atol=1e-15)


def test_map_interpolates_between_taxels() -> None:
    pad = _sphere_pad()
    p, m = pad.map(pad.uv[3, 4])
    pos, nrm, _ = pad.taxels
    np.testing.assert_allclose(p, pos[3, 4], atol=1e-15)
    np.testing.assert_allclose(m, nrm[3, 4], atol=1e-15)


def test_resampled_keeps_the_extent() -> None:
    pad = _sphere_pad()
    coarse = pad.resampled(0.004)
    assert coarse.shape == (9, 9) and coarse.pitch == 0.004  # 30 mm / 4 mm + 1, rounded
    fine = pad.resampled(0.0005)
    assert fine.shape == (61, 61)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rows": 0}, "rows"),
        ({"cols": 2.5}, "cols"),
        ({"pitch": 0.0}, "pitch"),
        ({"normal": [0, 0, 0]}, "normal"),
        ({"up": [0.3, 0.2, -0.9]}, "parallel"),
        ({"rows": 41, "cols": 41, "pitch": 0.003}, "deg from its centre"),
    ],
)
def test_bad_pads_name_the_problem(kwargs: dict, message: str) -> None:
    fields = dict(rows=21, cols=21, pitch=0.0015, radius=0.008, normal=[0.3, 0.2, -0.9],
                  up=[0, 1, 0], origin=[0, 0, 0])  # fmt: skip
    fields.update(kwargs)
    with pytest.raises(InvalidInputError, match=message):
        PadLayout(**fields)


def test_the_largest_curved_pad_stays_below_the_fold() -> None:
    n = 41
    pitch = MAX_PAD_ANGLE * 0.008 / (np.hypot(n - 1, n - 1) / 2) * 0.999
    PadLayout(n, n, pitch, 0.008, [0, 0, 1], [0, 1, 0], [0, 0, 0])
