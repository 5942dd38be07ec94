"""The driver `fit`: known answers, determinism, counting, the budget, bad input, layering, CLI."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hapticsim
from hapticsim.data.bodies import get_body
from hapticsim.data.io import Contacts, write_contacts
from hapticsim.data.synthetic import paper_dataset
from hapticsim.errors import HapticsimError, InvalidInputError
from hapticsim.fitting import METHODS, FitResult, fit, kernels
from hapticsim.fitting import objective as objective_module
from hapticsim.geometry import Superquadric, rotvec_to_matrix
from hapticsim.metrics import volume_overlap
from tests.fitting.conftest import posed, surface_contacts

REPO = Path(__file__).resolve().parents[2]


def _epsilon(estimate: Superquadric, truth: Superquadric) -> float:
    # 20 000 samples: standard error of alpha, beta <= 0.0035.
    overlap = volume_overlap(estimate, truth, samples=20_000, rng=0)
    return overlap.alpha + overlap.beta


def _eof(sq: Superquadric, data: Contacts) -> float:
    """SPEC §2 EOF of `sq` on the contacts (points and normals), lambda 0.5."""
    from hapticsim.geometry.eof import error_of_fit

    return float(error_of_fit(data.points, data.normals, sq.a, sq.eps, sq.taper, sq.rotation,
                              sq.center))  # fmt: skip


def _paper_data(name: str, noise: float, seed: int) -> tuple[Superquadric, Contacts]:
    truth = posed(get_body(name), seed)
    return truth, paper_dataset(truth, noise=noise, rng=seed)


def test_nh_recovers_a_tapered_box_from_clean_sparse_contacts() -> None:
    truth, data = _paper_data("tapered_box", 0.0, 1)
    result = fit(data.points, data.normals, method="nH", rng=0)
    # Measured: epsilon 0.000 (EOF ~1e-17); the threshold allows Monte Carlo noise only.
    assert _epsilon(result.superquadric, truth) < 0.015
    assert result.eof < 1e-12


def test_nh_on_noisy_contacts_is_close_to_the_truth() -> None:
    truth, data = _paper_data("cube", 0.1, 0)
    result = fit(data.points, data.normals, method="nH", rng=0)
    # Measured (scripts/measure_bounds.py, cube, sigma_N 0.1, data seed 0): nH 0.099-0.101 over
    # fit seeds 0-9 (0.100 with seed 0), the oracle (nLS from the truth) 0.075; what a weaker
    # fitter scores on the same data: nLS 0.323, nH at budget 300 0.159, the initial estimate
    # 0.602. The limit 0.14 keeps a 0.04 margin above nH and fails all three.
    assert _epsilon(result.superquadric, truth) < 0.14


def test_ls_recovers_an_ellipsoid_from_contacts_all_around() -> None:
    truth = posed(Superquadric(a=(0.03, 0.04, 0.05), eps=(1.0, 1.0)), 4)
    points, _ = surface_contacts(truth, 80, 2)
    result = fit(points, method="LS")
    # Measured: epsilon 0.000; least squares from the paper's initial estimate suffices here.
    assert _epsilon(result.superquadric, truth) < 0.015
    assert result.status == "converged"


def test_warm_start_is_refined_not_returned() -> None:
    truth, data = _paper_data("cube", 0.02, 3)
    turn = rotvec_to_matrix(np.radians(8.0) * np.array([0.0, 0.6, 0.8]))
    warm = truth.replace(a=truth.a * 1.25, rotation=turn @ truth.rotation,
                         center=truth.center + 0.004)  # fmt: skip
    result = fit(data.points, data.normals, method="nLS", initial=warm, budget=2000)
    # Measured (scripts/measure_bounds.py): the warm start scores 0.482; nLS from it 0.028 in
    # 441 evaluations (converged); nLS from the paper's initial estimate instead 0.361; the
    # oracle 0.025. The limit 0.08 fails a fitter that returns or ignores its warm start.
    assert _epsilon(result.superquadric, truth) < 0.08
    assert result.evaluations < 2000 and result.eof < 0.1 * _eof(warm, data)


@pytest.mark.parametrize("method", METHODS)
def test_same_seed_same_result_bit_for_bit(method: str) -> None:
    _, data = _paper_data("tapered_box", 0.1, 5)
    one = fit(data.points, data.normals, method=method, budget=1500, rng=7)
    two = fit(data.points, data.normals, method=method, budget=1500, rng=np.random.default_rng(7))
    assert one.superquadric.to_vector().tobytes() == two.superquadric.to_vector().tobytes()
    assert (one.eof, one.evaluations, one.status) == (two.eof, two.evaluations, two.status)
    np.testing.assert_array_equal(one.history[1], two.history[1])


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("budget", [1, 30, 700])
def test_every_evaluation_is_counted_and_the_budget_holds(
    method: str, budget: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    _, data = _paper_data("cube", 0.05, 6)
    distance = "untapered" if budget == 1 else "tapered"
    # The kernels' warm-up evaluates a tiny problem of its own: done before the tally starts
    # (run first in a process, this test counted the warm-up's evaluations and failed).
    kernels.prepare(method)
    tallies = []
    real = objective_module.ContactSet.from_arrays

    def tallied(points, normals):  # the kernels' own tally of every evaluation they did
        contacts = real(points, normals)
        tallies.append(contacts.tally)
        return contacts

    monkeypatch.setattr(objective_module.ContactSet, "from_arrays", staticmethod(tallied))
    result = fit(data.points, data.normals, method=method, budget=budget, distance=distance)
    assert result.evaluations == sum(int(t[0]) for t in tallies) <= budget
    evals, best = result.history
    assert np.all(np.diff(evals) > 0) and np.all(np.diff(best) <= 0)


def test_result_layout_and_lazy_top_level_name() -> None:
    _, data = _paper_data("ellipsoid", 0.05, 0)
    result = hapticsim.fit(data.points, data.normals, method="nH", budget=500, rng=0)
    assert isinstance(result, FitResult)
    out = result.to_dict()
    assert {"superquadric", "method", "eof", "evaluations", "seconds"} <= set(out)
    assert Superquadric.from_dict(out) == result.superquadric
    json.dumps(out)
    with pytest.raises(AttributeError):
        result.eof = 0.0  # frozen


def test_points_on_one_plane_fit_without_error() -> None:
    rng = np.random.default_rng(0)
    points = np.c_[rng.uniform(-0.03, 0.03, (40, 2)), np.zeros(40)]
    normals = np.tile([0.0, 0.0, 1.0], (40, 1))
    for method in METHODS:
        result = fit(points, normals, method=method, budget=400, rng=0)
        assert np.isfinite(result.eof)


_GOOD = np.random.default_rng(1).normal(size=(20, 3))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"points": _GOOD[:12]}, "at least 13"),
        ({"points": np.where(np.arange(60).reshape(20, 3) == 7, np.nan, _GOOD)}, "NaN"),
        ({"points": _GOOD[:, :2]}, r"\(n, 3\)"),
        ({"points": np.outer(np.linspace(0, 1, 20), [1.0, 2.0, 3.0])}, "one line"),
        ({"points": np.ones((20, 3))}, "one location"),
        # issue 14: 1e300 m ended in a LinAlgError, 1e-300 m in scipy's bounds ValueError
        ({"points": _GOOD * 1e300}, r"within \+-1e\+06 m"),
        ({"points": _GOOD * 1e-300}, "span at least 1e-09 m"),
        ({"points": _GOOD + 1j}, "must be real"),
        ({"points": _GOOD > 0}, "must be numeric, got bool"),
        ({"points": _GOOD.astype(str)}, "must be numeric"),
        ({"normals": _GOOD[:19]}, "one row per point"),
        ({"normals": np.where(np.arange(20)[:, None] == 3, 0.0, _GOOD)}, "zero length"),
        ({"normals": None, "method": "nH"}, "needs `normals`"),
        ({"method": "GA"}, "LS, H, nLS, nH"),
        ({"budget": 0}, "budget"),
        ({"budget": 2.5}, "budget"),
        ({"lam": -1.0}, "lam"),
        ({"rng": -3}, "rng"),
        ({"initial": {"a": [1, 1, 1]}}, "initial"),
        ({"distance": "euclid"}, "distance"),
    ],
)
def test_bad_input_raises_a_named_error(kwargs: dict, match: str) -> None:
    args = {"points": _GOOD, "normals": _GOOD, "method": "nLS", "budget": 50} | kwargs
    with pytest.raises(InvalidInputError, match=match):
        fit(**args)


def test_importing_fitting_does_not_load_mujoco() -> None:
    code = "import sys, hapticsim.fitting; print('mujoco' in sys.modules)"
    env = os.environ | {"PYTHONPATH": str(REPO)}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True
    )
    assert out.stdout.strip() == "False"


def test_cli_fit_prints_the_spec_json(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    from hapticsim.cli import main

    _, data = _paper_data("cylinder", 0.05, 0)
    path = write_contacts(tmp_path / "c.npz", data)
    out_file = tmp_path / "fit.json"
    code = main(["fit", str(path), "--method", "nH", "--seed", "0", "--budget", "400",
                 "--out", str(out_file)])  # fmt: skip
    assert code == 0
    printed = json.loads(capsys.readouterr().out)
    assert {"superquadric", "method", "eof", "evaluations", "seconds"} <= set(printed)
    assert printed["method"] == "nH" and printed["evaluations"] <= 400
    assert json.loads(out_file.read_text()) == printed


def test_cli_fit_out_into_a_missing_directory_fails_before_the_fit(
    tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    import hapticsim.fitting
    from hapticsim.cli import main

    def must_not_run(*args, **kwargs):
        raise AssertionError("the fit ran before --out was checked")

    monkeypatch.setattr(hapticsim.fitting, "fit", must_not_run)
    _, data = _paper_data("cube", 0.05, 0)
    path = write_contacts(tmp_path / "c.npz", data)
    assert main(["fit", str(path), "--out", str(tmp_path / "missing" / "fit.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "does not exist" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.npz"]


def test_cli_fit_bad_input_exits_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.cli import main

    path = write_contacts(tmp_path / "few.npz", Contacts(points=_GOOD[:5]))
    assert main(["fit", str(path), "--method", "LS"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "13" in err
    assert main(["fit", str(path), "--method", "nH"]) == 2  # no normals in the file


def test_errors_are_hapticsim_errors() -> None:
    assert issubclass(InvalidInputError, HapticsimError)


def test_a_least_squares_step_limit_is_a_status_not_an_error(monkeypatch) -> None:  # noqa: ANN001
    # Least squares stops at MAX_ITERATIONS steps with the status "iterations"; the result
    # must carry it (it raised "`status` must be one of ..." before).
    from hapticsim.fitting import least_squares

    monkeypatch.setattr(least_squares, "MAX_ITERATIONS", 2)
    data = paper_dataset(get_body("cube"), 0.05, rng=0)
    result = fit(data.points, data.normals, method="nLS")
    assert result.status == "iterations"
    assert result.message == "least-squares step limit reached"
