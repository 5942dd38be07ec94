"""The skin's elastic law, the sensor model and the presets."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.perception.tactile import SKIN_NAMES, SensorModel, SkinError, SkinModel, load_skin
from hapticsim.perception.tactile.skin import gaussian_blur


def test_pressure_and_depth_are_inverse_and_winkler() -> None:
    skin = SkinModel(modulus=2e5, thickness=0.002)
    d = np.array([0.0, 1e-4, 5e-4, -1e-4])
    np.testing.assert_allclose(skin.pressure(d), [0.0, 1e4, 5e4, 0.0])
    np.testing.assert_allclose(skin.depth(skin.pressure(d)), np.maximum(d, 0))
    f = skin.sphere_force(0.008, 5e-4)
    assert f == pytest.approx(np.pi * 1e8 * 0.008 * 25e-8)
    assert skin.sphere_penetration(0.008, f) == pytest.approx(5e-4)


def test_the_sphere_law_is_the_winkler_pressure_integrated_over_the_disc() -> None:
    skin = SkinModel()
    radius, delta = 0.008, 4e-4
    r = np.linspace(0, np.sqrt(2 * radius * delta), 20001)
    depth = delta - (radius - np.sqrt(radius**2 - r**2))  # the sphere's cap above the plane
    force = np.trapezoid(skin.pressure(depth) * 2 * np.pi * r, r)
    assert skin.sphere_force(radius, delta) == pytest.approx(force, rel=2e-2)


def test_the_ideal_sensor_changes_nothing() -> None:
    sensor = SensorModel()
    assert sensor.ideal and sensor.step == 0.0
    image = np.random.default_rng(0).random((2, 5, 5))
    np.testing.assert_array_equal(sensor.apply(image, sensor.pattern(image.shape, None), None),
                                  image)  # fmt: skip


def test_noise_is_seeded_and_has_its_std() -> None:
    sensor = SensorModel(noise=100.0)
    image = np.full((4, 50, 50), 1e4)
    a = sensor.apply(image, None, np.random.default_rng(3))
    b = sensor.apply(image, None, np.random.default_rng(3))
    np.testing.assert_array_equal(a, b)
    assert np.std(a - image) == pytest.approx(100.0, rel=0.05)


def test_quantisation_threshold_and_saturation() -> None:
    sensor = SensorModel(full_scale=1000.0, bits=2, threshold=400.0)
    out = sensor.apply(np.array([[[0.0, 200.0, 500.0, 700.0, 5000.0]]]), None, None)
    step = 1000.0 / 3
    np.testing.assert_allclose(out, [[[0.0, 0.0, 2 * step, 2 * step, 1000.0]]])


def test_fixed_pattern_gains_and_dead_taxels() -> None:
    sensor = SensorModel(gain_spread=0.1, dead_fraction=0.2)
    pattern = sensor.pattern((3, 30, 30), np.random.default_rng(1))
    assert 0.15 < pattern.dead.mean() < 0.25
    assert np.std(pattern.gain) == pytest.approx(0.1, rel=0.15)
    out = sensor.apply(np.full((3, 30, 30), 1.0), pattern, None)
    np.testing.assert_array_equal(out[pattern.dead], 0.0)
    np.testing.assert_allclose(out[~pattern.dead], pattern.gain[~pattern.dead])


def test_blur_spreads_and_keeps_the_total_away_from_the_edges() -> None:
    image = np.zeros((1, 21, 21))
    image[0, 10, 10] = 1.0
    out = gaussian_blur(image, 1.0)
    assert out.sum() == pytest.approx(1.0)
    assert out[0, 10, 10] < 0.2 and out[0, 10, 11] == pytest.approx(out[0, 11, 10])


def test_sensor_validation() -> None:
    with pytest.raises(InvalidInputError, match="bits"):
        SensorModel(bits=8)  # no full scale
    with pytest.raises(InvalidInputError, match="dead_fraction"):
        SensorModel(dead_fraction=1.0)
    with pytest.raises(InvalidInputError, match="needs a generator"):
        SensorModel(noise=1.0).apply(np.zeros((1, 2, 2)), None, None)


def test_every_preset_loads_and_names_its_sources() -> None:
    for name in SKIN_NAMES:
        preset = load_skin(name)
        assert preset.name == name and preset.source and preset.description
    assert load_skin("ideal").sensor.ideal
    assert load_skin("capacitive").pitch == 0.004
    assert load_skin(None).name == "ideal"


def test_unknown_preset_suggests_the_nearest() -> None:
    with pytest.raises(SkinError, match=r"did you mean 'vision'"):
        load_skin("visoin")
    with pytest.raises(SkinError, match="ideal, vision, capacitive, elastomer, gelsight_mini"):
        load_skin("nothing-like-it")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("name = ", "not valid TOML"),
        ("colour = 3", r"unknown key\(s\) \['colour'\]"),
        ("[sensor]\nnoise = 'loud'", "`noise` must be a number"),
        ("[sensor]\nbits = 8.5\nfull_scale = 1.0", "`bits` must be an integer"),
        ("[skin]\nmodulus = -1.0", "modulus"),
    ],
)
def test_bad_skin_files_name_the_problem(tmp_path, text: str, message: str) -> None:  # noqa: ANN001
    path = tmp_path / "skin.toml"
    path.write_text(text)
    with pytest.raises(SkinError, match=message):
        load_skin(path)
    with pytest.raises(SkinError, match="not found"):
        load_skin(tmp_path / "missing.toml")
