"""Reference contact mechanics (issue 38, item 3): the closed forms, and the FE solutions held
to both of their limits (Hertz for a thick layer, the skin's Winkler law for a thin one of
Poisson's ratio 0). The FE tests skip without scikit-fem (the ``fem`` extra)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.perception.tactile.mechanics import (
    fem_layer_press,
    fem_pad_press,
    hertz_sphere,
    winkler_sphere,
)
from hapticsim.perception.tactile.skin import SkinModel


def test_hertz_and_winkler_closed_forms_agree_with_themselves() -> None:
    h = hertz_sphere(1e6, 0.3, 0.01, 1e-4)
    assert h.contact_radius == pytest.approx(1e-3)
    assert h.peak_pressure == pytest.approx(3 * h.force / (2 * math.pi * h.contact_radius**2))
    skin = SkinModel(2e5, 0.002)
    w = winkler_sphere(skin, 0.008, 5e-4)
    # the Winkler pressure integrated over its contact disc is its force
    a, p0 = w.contact_radius, w.peak_pressure
    assert w.force == pytest.approx(math.pi * a**2 * p0 / 2)
    assert p0 == pytest.approx(skin.modulus * 5e-4 / skin.thickness)


@pytest.mark.parametrize(
    ("args", "match"),
    [((1e6, 0.5, 0.01, 1e-4), "poisson"), ((1e6, 0.3, -0.01, 1e-4), "radius"),
     ((1e6, 0.3, 0.01, 0.0), "indentation"), ((float("nan"), 0.3, 0.01, 1e-4), "modulus")],
)  # fmt: skip
def test_bad_contact_input_is_one_line(args: tuple, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match) as exc:
        hertz_sphere(*args)
    assert "\n" not in str(exc.value)


def test_without_scikit_fem_the_fe_solutions_say_what_to_install(monkeypatch) -> None:  # noqa: ANN001
    import builtins

    real = builtins.__import__

    def no_skfem(name, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        if name == "skfem" or name.startswith("skfem."):
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_skfem)
    with pytest.raises(InvalidInputError, match=r"scikit-fem: pip install -e \"\.\[fem\]\""):
        fem_layer_press(1e6, 0.3, 0.01, 0.01, 1e-4)


def _skfem() -> None:
    pytest.importorskip("skfem")


def test_a_thick_layer_is_hertz() -> None:
    _skfem()
    ref = hertz_sphere(1e6, 0.3, 0.01, 1e-4)
    fe = fem_layer_press(1e6, 0.3, 60 * ref.contact_radius, 0.01, 1e-4)
    # measured: force +1.3 % (a finite, bonded layer is a little stiffer), radius -0.6 %,
    # peak pressure +0.4 %
    assert fe.force == pytest.approx(ref.force, rel=0.03)
    assert fe.contact_radius == pytest.approx(ref.contact_radius, rel=0.02)
    assert fe.peak_pressure == pytest.approx(ref.peak_pressure, rel=0.02)
    hertz = ref.peak_pressure * np.sqrt(np.maximum(1 - (fe.radii / ref.contact_radius) ** 2, 0))
    assert np.sqrt(np.mean((fe.pressure - hertz) ** 2)) < 0.03 * ref.peak_pressure


def test_a_thick_pad_on_a_flat_is_hertz() -> None:
    _skfem()
    ref = hertz_sphere(2e5, 0.3, 0.008, 2e-5)
    fe = fem_pad_press(2e5, 0.3, 0.008, 0.006, 2e-5)
    # measured: force -2.1 %, radius +0.8 %, peak pressure -0.5 %
    assert fe.force == pytest.approx(ref.force, rel=0.04)
    assert fe.contact_radius == pytest.approx(ref.contact_radius, rel=0.03)
    assert fe.peak_pressure == pytest.approx(ref.peak_pressure, rel=0.03)


def test_a_thin_layer_without_lateral_coupling_is_the_skins_winkler_law() -> None:
    _skfem()
    skin = SkinModel(2e5, 1e-4)
    ref = winkler_sphere(skin, 0.008, 5e-5)  # contact radius 9 thicknesses
    fe = fem_layer_press(2e5, 0.0, skin.thickness, 0.008, 5e-5)
    # measured: force -0.1 %, peak pressure -0.02 %, radius -1.6 % (the layer's shear pulls
    # the surface down around the contact)
    assert fe.force == pytest.approx(ref.force, rel=0.01)
    assert fe.peak_pressure == pytest.approx(ref.peak_pressure, rel=0.01)
    assert fe.contact_radius == pytest.approx(ref.contact_radius, rel=0.05)


def test_a_press_is_monotonic_and_the_pressure_positive_inside_the_contact() -> None:
    _skfem()
    presses = [fem_pad_press(2e5, 0.45, 0.008, 0.002, d) for d in (1e-4, 3e-4, 1e-3)]
    forces = [p.force for p in presses]
    assert forces == sorted(forces) and forces[0] > 0
    for p in presses:
        inside = p.radii < 0.9 * p.contact_radius
        assert np.all(p.pressure[inside] > 0)
