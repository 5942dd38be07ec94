"""F-score, normal consistency and Chamfer: closed forms and an independent computation."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.metrics.chamfer import chamfer
from hapticsim.metrics.surface import anytime_area, f_score, surface_score


def sphere(radius: float, center: tuple[float, float, float] = (0, 0, 0)) -> Superquadric:
    return Superquadric(a=(radius,) * 3, eps=(1.0, 1.0), center=center)


def test_concentric_spheres_have_the_closed_form_scores() -> None:
    # every point of one sphere is 2 mm from the other's surface, normals parallel (distances
    # are to the surface's fine mesh, whose chords add up to ~2e-5 m)
    s = surface_score(sphere(0.03), sphere(0.032), thresholds=(0.0015, 0.0025), samples=4000)
    assert s.precision == (0.0, 1.0) and s.recall == (0.0, 1.0) and s.f_score == (0.0, 1.0)
    assert s.chamfer == pytest.approx(0.002, abs=3e-5)
    assert s.normal_consistency == pytest.approx(1.0, abs=1e-5)
    same = surface_score(sphere(0.03), sphere(0.03), samples=2000)
    assert same.f_score == (1.0, 1.0, 1.0) and same.chamfer < 3e-5
    d = same.to_dict()
    assert set(d["f_score"]) == {"1", "2.5", "5"} and d["chamfer_mm"] == 1000 * d["chamfer"]


def test_a_shifted_sphere_against_the_closed_form_of_its_distance_distribution() -> None:
    # two unit-radius-r spheres, centres apart by s: a point of the first at polar angle t
    # (from the axis) is |sqrt(r^2 + s^2 - 2 r s cos t) - r| from the second; area-uniform
    # points have cos t uniform on [-1, 1], so P(d <= tau) has a closed form
    r, shift, tau = 0.03, 0.004, 0.002
    s = surface_score(sphere(r), sphere(r, (shift, 0, 0)), thresholds=(tau,), samples=20_000)
    # d <= tau  <=>  (r - tau)^2 <= r^2 + s^2 - 2 r s c <= (r + tau)^2, c = cos t uniform
    lo = (r * r + shift * shift - (r + tau) ** 2) / (2 * r * shift)
    hi = (r * r + shift * shift - (r - tau) ** 2) / (2 * r * shift)
    expected = (min(hi, 1.0) - max(lo, -1.0)) / 2.0
    # standard error of a fraction of 20 000 samples <= 0.0036: 4 of them
    assert s.precision[0] == pytest.approx(expected, abs=0.015)
    assert s.recall[0] == pytest.approx(expected, abs=0.015)


@pytest.mark.slow  # ~50 s: trimesh's closest points of 2 x 60 000 samples
def test_agrees_with_an_independent_computation_on_meshes() -> None:
    """trimesh's own area sampling and exact closest points on fine meshes of a box and an
    ellipsoid give the same F-scores and normal consistency within 0.012 (two independent
    draws of 60 000 samples: a fraction's difference has a standard error <= 0.003; measured
    within 0.003 at 100 000)."""
    trimesh = pytest.importorskip("trimesh")
    box = Superquadric(a=(0.03, 0.02, 0.025), eps=(0.2, 0.2))
    ell = Superquadric(a=(0.032, 0.021, 0.022), eps=(1.0, 1.0), center=(0.002, 0, 0.001))
    taus = (0.001, 0.0025, 0.005)
    ours = surface_score(ell, box, thresholds=taus, samples=60_000, rng=3)
    m_box, m_ell = box.to_trimesh(160), ell.to_trimesh(160)
    rng = np.random.default_rng(7)
    p_e, f_e = trimesh.sample.sample_surface(m_ell, 60_000, seed=rng)
    p_t, f_t = trimesh.sample.sample_surface(m_box, 60_000, seed=rng)
    c_e, d_e, tri_e = trimesh.proximity.closest_point(m_box, p_e)
    c_t, d_t, tri_t = trimesh.proximity.closest_point(m_ell, p_t)
    for k, t in enumerate(taus):
        prec, rec = float(np.mean(d_e <= t)), float(np.mean(d_t <= t))
        assert ours.precision[k] == pytest.approx(prec, abs=0.012)
        assert ours.recall[k] == pytest.approx(rec, abs=0.012)
        assert ours.f_score[k] == pytest.approx(f_score(prec, rec), abs=0.012)
    nc = 0.5 * (
        np.mean(np.abs(np.sum(m_ell.face_normals[f_e] * m_box.face_normals[tri_e], axis=1)))
        + np.mean(np.abs(np.sum(m_box.face_normals[f_t] * m_ell.face_normals[tri_t], axis=1)))
    )
    assert ours.normal_consistency == pytest.approx(nc, abs=0.012)
    assert ours.chamfer == pytest.approx(0.5 * (d_e.mean() + d_t.mean()), rel=0.02)


def test_chamfer_is_the_metrics_chamfer_for_the_same_draw() -> None:
    a = Superquadric(a=(0.03, 0.02, 0.025), eps=(0.4, 0.9), taper=(0.2, 0.0))
    b = Superquadric(a=(0.028, 0.022, 0.027), eps=(0.5, 0.8), center=(0.001, 0, 0))
    assert surface_score(a, b, rng=5).chamfer == chamfer(a, b, rng=5)


def test_f_score_anytime_area_and_bad_input() -> None:
    assert f_score(0.0, 0.0) == 0.0 and f_score(1.0, 1.0) == 1.0
    assert f_score(0.5, 1.0) == pytest.approx(2 / 3)
    assert anytime_area([1.0, 1.0, 1.0]) == 1.0 and anytime_area([0.0, 0.5, 1.0]) == 0.5
    for bad in ([], [[1.0]], [np.nan]):
        with pytest.raises(InvalidInputError, match="values"):
            anytime_area(bad)
    for bad in ((), (0.0,), (-1e-3,), "abc", (np.inf,)):
        with pytest.raises(InvalidInputError, match="thresholds"):
            surface_score(sphere(0.03), sphere(0.03), thresholds=bad)
