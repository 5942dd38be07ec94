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
