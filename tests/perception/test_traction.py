"""The skin's traction field: Coulomb's bound, partial slip and the thin layer's stick
radius (hapticsim.perception.tactile.traction)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.perception.tactile.traction import (
    TAXEL_FREE,
    TAXEL_SLIP,
    TAXEL_STICK,
    contact_share,
    traction_field,
    winkler_stick_radius,
)

MU = 0.4


def sphere_image(n: int = 161, pitch: float = 5e-5, a: float = 3e-3, p0: float = 5e4):
    """A sphere's Winkler pressure ``p0 (1 - r^2 / a^2)`` on an n x n grid, and the radii."""
    x = (np.arange(n) - (n - 1) / 2) * pitch
    r = np.hypot(x[:, None], x[None, :])
    return np.maximum(p0 * (1.0 - (r / a) ** 2), 0.0), r


@pytest.mark.parametrize("share", [0.0, 0.2, 0.5, 0.8, 0.95])
def test_the_stick_region_of_a_sphere_in_a_thin_layer_is_the_closed_form_disc(share):
    p, r = sphere_image()
    direction = np.array([0.6, -0.8])
    t, state = traction_field(p, share * direction, MU)
    stick = state == TAXEL_STICK
    radius = np.sqrt(stick.sum() / np.pi) * 5e-5  # the stick disc's radius from its area
    assert radius / 3e-3 == pytest.approx(winkler_stick_radius(share), abs=0.02)
    # the field carries the load: Q = share * mu * N, along the load's direction
    normal = t[..., 0].sum()
    q = t[..., 1:].reshape(-1, 2).sum(axis=0)
    assert np.linalg.norm(q) == pytest.approx(share * MU * normal, rel=1e-9, abs=1e-9)
    if share > 0:
        assert q / np.linalg.norm(q) == pytest.approx(direction)
    assert contact_share(t, state, MU)[0] == pytest.approx(share, abs=1e-9)


def test_coulomb_bounds_every_taxel_and_the_slip_region_grows_from_the_edge():
    p, r = sphere_image(n=81, pitch=1e-4)
    slipping = []
    for share in np.linspace(0.0, 1.0, 21):
        t, state = traction_field(p, np.array([share, 0.0]), MU)
        magnitude = np.hypot(t[..., 1], t[..., 2])
        assert np.all(magnitude <= MU * t[..., 0] * (1 + 1e-12) + 1e-12)
        assert np.all(state[p == 0] == TAXEL_FREE) and np.all(state[p > 0] != TAXEL_FREE)
        slip = state == TAXEL_SLIP
        # a slipping taxel carries its bound, a sticking one less
        assert np.allclose(magnitude[slip], MU * p[slip])
        assert np.all(magnitude[state == TAXEL_STICK] < MU * p[state == TAXEL_STICK])
        if slip.any() and (state == TAXEL_STICK).any():
            assert r[slip].max() > r[state == TAXEL_STICK].max()  # the edge slips first
        slipping.append(slip.sum())
    assert slipping == sorted(slipping)  # the slip region only grows as the stroke loads
    assert slipping[0] == 0 and slipping[-1] == int((p > 0).sum())  # sliding: every taxel


def test_batched_pads_each_take_their_own_load_and_a_frictionless_skin_slips():
    p, _ = sphere_image(n=41, pitch=2e-4)
    images = np.stack([p, np.zeros_like(p), p])
    load = np.array([[0.5, 0.0], [0.3, 0.3], [0.0, 2.0]])
    t, state = traction_field(images, load, MU)
    assert t.shape == (3, 41, 41, 3) and state.shape == (3, 41, 41) and state.dtype == np.int8
    assert np.all(state[1] == TAXEL_FREE) and np.all(t[1] == 0)
    assert np.all(state[2][p > 0] == TAXEL_SLIP)  # a load beyond the limit slides
    assert np.allclose(t[2, ..., 2], MU * p) and np.all(t[2, ..., 1] == 0)
    t0, s0 = traction_field(p, np.array([0.5, 0.0]), 0.0)
    assert np.all(s0[p > 0] == TAXEL_SLIP) and np.all(t0[..., 1:] == 0)


def test_bad_input_is_refused():
    p, _ = sphere_image(n=5, pitch=1e-3)
    with pytest.raises(InvalidInputError, match="load"):
        traction_field(p, np.zeros(3), MU)
    with pytest.raises(InvalidInputError, match="friction"):
        traction_field(p, np.zeros(2), -0.1)
    with pytest.raises(InvalidInputError, match="finite"):
        traction_field(p, np.array([np.nan, 0.0]), MU)
    with pytest.raises(InvalidInputError, match="area"):
        traction_field(p, np.zeros(2), MU, area=np.ones((2, 2)))
