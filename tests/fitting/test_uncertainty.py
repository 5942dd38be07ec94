"""The fit's uncertainty (Laplace at the optimum): SPEC §6's block, its behaviour, its errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hapticsim.data.bodies import BODIES
from hapticsim.data.synthetic import paper_dataset
from hapticsim.errors import InvalidInputError
from hapticsim.fitting import fit
from tests.test_cli_core import assert_bad_input, run


def _fit(noise: float, seed: int = 1, **kw):  # noqa: ANN003, ANN202
    data = paper_dataset(BODIES["cube"], noise, rng=seed)
    return fit(data.points, data.normals, method="nH", rng=seed, uncertainty=True, **kw)


def test_the_block_has_spec_keys_and_holds_together() -> None:
    result = _fit(0.05)
    u = result.uncertainty.to_dict()
    assert u["method"] == "laplace" and u["rank"] == 13 and u["draws"] == 2000
    assert {k: len(v) for k, v in u["std"].items()} == {
        "a": 3, "eps": 2, "taper": 2, "center": 3, "rotation": 3}
    assert all(s > 0 for v in u["std"].values() for s in v)
    lo50, hi50 = u["volume"]["interval50"]
    lo90, hi90 = u["volume"]["interval90"]
    assert lo90 < lo50 < u["volume"]["mean"] < hi50 < hi90
    for (lo, hi), a in zip(u["a"]["interval90"], result.superquadric.a, strict=True):
        assert lo < a < hi
    assert "uncertainty" in result.to_dict() and json.dumps(result.to_dict())
    # the same fit gives the same intervals (a fixed seed for the draws)
    assert _fit(0.05).uncertainty.to_dict() == u


def test_more_noise_widens_the_intervals_and_no_request_adds_nothing() -> None:
    def width(noise: float) -> float:
        lo, hi = _fit(noise).uncertainty.to_dict()["volume"]["interval90"]
        return hi - lo

    assert width(0.1) > 2 * width(0.02)  # measured 5.8x on this seed
    data = paper_dataset(BODIES["cube"], 0.05, rng=1)
    plain = fit(data.points, data.normals, method="nH", rng=1)
    assert plain.uncertainty is None and "uncertainty" not in plain.to_dict()
    # the fit itself does not change when the uncertainty is asked for
    np.testing.assert_array_equal(plain.superquadric.to_vector(),
                                  _fit(0.05).superquadric.to_vector())  # fmt: skip


def test_points_only_and_ml_fits_have_one_too() -> None:
    data = paper_dataset(BODIES["ellipsoid"], 0.05, rng=2)
    for method in ("H", "nML"):
        normals = None if method == "H" else data.normals
        r = fit(data.points, normals, method=method, rng=2, uncertainty=True)
        u = r.uncertainty.to_dict()
        assert u["volume"]["interval90"][0] < r.superquadric.volume < u["volume"]["interval90"][1]


def test_multi_has_none_and_says_so(capsys, tmp_path: Path) -> None:  # noqa: ANN001
    data = paper_dataset(BODIES["cube"], 0.05, rng=1)
    with pytest.raises(InvalidInputError, match="not for method multi"):
        fit(data.points, data.normals, method="multi", uncertainty=True)
    path = tmp_path / "c.npz"
    code, _, _ = run(capsys, "synth", "cube", "--noise", "0.05", "--out", str(path))
    assert code == 0
    code, out, err = run(capsys, "fit", str(path), "--uncertainty")
    assert code == 0 and json.loads(out)["uncertainty"]["method"] == "laplace"
    assert_bad_input(*run(capsys, "fit", str(path), "--method", "multi", "--uncertainty"),
                     "fit", "--uncertainty is for one superquadric")  # fmt: skip


def _candidate_case():  # noqa: ANN202
    from hapticsim.fitting.uncertainty import posterior_covariance

    data = paper_dataset(BODIES["cube"], 0.05, rng=0)
    sq = fit(data.points, data.normals, method="nH", rng=0).superquadric
    cov, noise, _ = posterior_covariance(sq, data.points, data.normals, 0.5, "tapered")
    # the corner (-x, +y, -z), which no contact comes near, and a contact's own place
    points = np.vstack([sq.surface(np.array([-0.6]), np.array([0.75 * np.pi]))[0],
                        data.extra["points_clean"][60]])  # fmt: skip
    return sq, cov, noise, points


def test_expected_gains_are_largest_where_no_contact_is() -> None:
    from hapticsim.fitting.uncertainty import expected_information, expected_surface_reduction

    sq, cov, noise, points = _candidate_case()
    info = expected_information(sq, cov, noise, points)
    drop = expected_surface_reduction(sq, cov, noise, points)
    assert np.all(info >= 0) and np.all(drop >= 0)
    # measured: information 3.88 vs 0.077 nats, surface variance drop 78e-6 vs 4.8e-6 m^2
    assert info[0] > 10 * info[1] and drop[0] > 5 * drop[1]


def test_expected_surface_reduction_is_the_posterior_update() -> None:
    """Against the Gaussian update written out, with Jacobians by central differences."""
    from hapticsim.fitting.likelihood import Likelihood
    from hapticsim.fitting.problem import Problem, problem_residuals
    from hapticsim.fitting.uncertainty import SURFACE_SAMPLES, expected_surface_reduction
    from hapticsim.geometry.eof import ContactSet

    sq, cov, noise, points = _candidate_case()
    x = sq.to_vector()

    def jacobian(pts: np.ndarray, nrm: np.ndarray) -> np.ndarray:  # (4 k, 13) by differences
        contacts = ContactSet.from_arrays(pts, nrm)
        problem = Problem.ml(contacts, Likelihood(noise=1.0, length=1.0).settings())
        m = 4 * len(pts)
        cols = []
        for k in range(13):
            h = 1e-7 * max(abs(x[k]), 1e-2)
            up, down = x.copy(), x.copy()
            up[k], down[k] = x[k] + h, x[k] - h
            r = problem_residuals(contacts, problem, np.vstack([up, down]))[:, :m]
            cols.append((r[0] - r[1]) / (2 * h))
        return np.array(cols).T

    surface, surface_normals = sq.sample_surface(SURFACE_SAMPLES, np.random.default_rng(0))
    g = jacobian(surface, surface_normals)[: len(surface)]  # distance rows
    expected = []
    for p in points:
        j = jacobian(p[None], sq.normals(p[None])) * np.array(
            [1 / noise] + [np.mean(sq.a) / noise] * 3)[:, None]  # fmt: skip
        after = cov - cov @ j.T @ np.linalg.solve(j @ cov @ j.T + np.eye(4), j @ cov)
        expected.append(np.trace(g @ (cov - after) @ g.T))
    np.testing.assert_allclose(expected_surface_reduction(sq, cov, noise, points), expected,
                               rtol=1e-4)  # fmt: skip


def test_with_prior_keeps_a_tight_posterior_and_bounds_a_loose_one() -> None:
    from hapticsim.fitting.uncertainty import with_prior

    tight = np.diag(np.full(13, 1e-10))
    np.testing.assert_allclose(with_prior(tight, 0.03), tight, rtol=1e-5)
    loose = tight.copy()
    loose[4, 4] = np.inf  # an exponent nothing fixes
    loose[10, 10] = 1e200  # a centre coordinate, likewise
    bounded = with_prior(loose, 0.03)
    assert np.all(np.isfinite(bounded))
    assert bounded[4, 4] == pytest.approx(1.0) and bounded[10, 10] == pytest.approx(0.03**2)
    assert bounded[0, 0] == pytest.approx(1e-10, rel=1e-5)
