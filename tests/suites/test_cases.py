"""One case of each kind: deterministic records; a failing plug-in is a failed case, not a crash."""

from __future__ import annotations

from pathlib import Path

import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.fitting import DEFAULT_BUDGET
from hapticsim.geometry import Superquadric, SuperquadricUnion
from hapticsim.suites import load_suite
from hapticsim.suites.cases import TIMING_KEYS, CaseTask, run_case
from hapticsim.suites.plugins import as_solid, load_fitter, load_policy

LAB = "tests.suites.lab_plugins"


def _case(suite: str, case_id: str):  # noqa: ANN202
    return next(c for c in load_suite(suite).cases if c.id == case_id)


def _stable(record: dict) -> dict:
    return {k: v for k, v in record.items() if k not in TIMING_KEYS}


def test_a_fit_case_is_deterministic_and_complete() -> None:
    case = _case("fit-v1", "cylinder/nH/noise=0.05/run=1")
    first, second = run_case(CaseTask(case)), run_case(CaseTask(case))
    assert _stable(first) == _stable(second)
    assert first["status"] == "ok" and first["error"] is None
    m = first["metrics"]
    assert set(m) >= {"epsilon", "alpha", "beta", "iou", "chamfer", "theta", "eof"}
    assert m["epsilon"] == pytest.approx(m["alpha"] + m["beta"])
    # nH on the cylinder at sigma_N = 0.05: epsilon 0.05-0.15 measured over the suite's runs.
    assert m["epsilon"] < 0.3
    assert m["fitter"] == "nH" and m["evaluations"] <= DEFAULT_BUDGET
    assert Superquadric.from_dict(first["truth"]) == Superquadric(
        a=(0.03, 0.03, 0.06), eps=(0.1, 1)
    )
    assert first["seconds"] > 0 and first["fit_seconds"] > 0


def test_methods_of_one_run_see_the_same_random_body() -> None:
    ls = run_case(CaseTask(_case("fit-v1", "random_tapered/LS/noise=0.0/run=2")))
    nh = run_case(CaseTask(_case("fit-v1", "random_tapered/nH/noise=0.0/run=2")))
    assert ls["truth"] == nh["truth"]
    other = run_case(CaseTask(_case("fit-v1", "random_tapered/LS/noise=0.0/run=3")))
    assert other["truth"] != ls["truth"]
    taper = Superquadric.from_dict(ls["truth"]).taper
    assert any(abs(t) > 0 for t in taper)


@pytest.mark.parametrize(
    ("fitter", "error"),
    [
        ("garbage_fit", "the fitter returned an invalid solid: superquadric is missing"),
        ("raising_fit", "the fitter tests.suites.lab_plugins:raising_fit raised RuntimeError"),
        ("nan_fit", "the fitter returned an invalid solid"),
    ],
)
def test_a_failing_plug_in_fails_its_case(fitter: str, error: str) -> None:
    # cube/nH/noise=0.0/run=1 is one of the cases garbage_fit and raising_fit fail on
    record = run_case(
        CaseTask(_case("fit-v1", "cube/nH/noise=0.0/run=1"), fitter=f"{LAB}:{fitter}")
    )
    assert record["status"] == "failed"
    assert error in record["error"]
    assert record["metrics"] == {} and record["estimate"] is None


def test_plug_in_return_forms() -> None:
    case = _case("fit-v1", "ellipsoid/nLS/noise=0.02/run=0")
    own = run_case(CaseTask(case))
    as_dict = run_case(CaseTask(case, fitter=f"{LAB}:spec_dict_fit"))  # a `fit` JSON dict
    assert as_dict["status"] == "ok"
    assert as_dict["estimate"] == own["estimate"]  # nLS is deterministic: same estimate
    assert as_dict["metrics"]["fitter"] == f"{LAB}:spec_dict_fit"
    assert as_dict["metrics"]["evaluations"] is None


def test_as_solid_refuses_what_is_not_one() -> None:
    sq = Superquadric(a=(0.02, 0.03, 0.04), eps=(1.0, 1.0))
    assert as_solid(sq) is sq
    union = SuperquadricUnion((sq, sq.replace(center=(0.03, 0.0, 0.0))))
    assert as_solid({"parts": [p.to_dict() for p in union.parts]}) == union
    assert as_solid(sq.to_dict()) == sq
    assert as_solid({"superquadric": sq.to_dict()}) == sq
    with pytest.raises(InvalidInputError, match="returned NoneType None"):
        as_solid(None)
    with pytest.raises(InvalidInputError, match="invalid solid"):
        as_solid({**sq.to_dict(), "a": [-1, 1, 1]})


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("no_such_lab.fit:fit", "cannot import module 'no_such_lab.fit' (ModuleNotFoundError"),
        (f"{LAB}:missing", "has no 'missing'"),
        (f"{LAB}:NOT_CALLABLE", "int is not callable"),
        (f"{LAB}:three_args", "must accept (points, normals)"),
        ("fit", "must be MODULE:ATTRIBUTE"),
        ("a:b:c", "must be MODULE:ATTRIBUTE"),
    ],
)
def test_bad_fitter_specs(spec: str, message: str) -> None:
    with pytest.raises(InvalidInputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        load_fitter(spec)


def test_a_module_that_raises_on_import(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "broken_lab.py").write_text("raise ValueError('half-written module')\n")
    monkeypatch.chdir(tmp_path)  # plug-ins import from the working directory
    with pytest.raises(InvalidInputError, match="ValueError: half-written module"):
        load_fitter("broken_lab:fit")


def test_bad_policy_specs() -> None:
    with pytest.raises(InvalidInputError, match="must be a class"):
        load_policy(f"{LAB}:nh_fit")
    with pytest.raises(InvalidInputError, match="instances must be callable"):
        load_policy(f"{LAB}:NotAPolicy")
    assert load_policy("hapticsim.suites.examples:AxisPolicy").__name__ == "AxisPolicy"


def test_a_policy_case_with_a_baseline_and_a_plug_in_policy() -> None:
    case = _case("policy-v1", "uncertainty/paper/analytic/run=0")
    first, second = run_case(CaseTask(case)), run_case(CaseTask(case))
    assert _stable(first) == _stable(second)
    assert first["status"] == "ok"
    m = first["metrics"]
    assert len(m["epsilon_curve"]) == 10 and m["fitted"] and m["contacts"] > 13
    # The uncertainty policy on the paper bodies after 10 touches: mean epsilon 0.026
    # (docs/policies); one episode stays well below random's mean of 0.15.
    assert m["epsilon"] < 0.2
    axis = run_case(CaseTask(case, policy="hapticsim.suites.examples:AxisPolicy"))
    assert axis["status"] == "ok" and axis["truth"] == first["truth"]  # same object
    bad = run_case(CaseTask(case, policy=f"{LAB}:BadActionPolicy"))
    assert bad["status"] == "failed" and "BadActionPolicy failed" in bad["error"]


def test_an_explore_case() -> None:
    record = run_case(CaseTask(_case("explore-v1", "cube/paper/noise=0.0/run=0")))
    assert record["status"] == "ok", record["error"]
    m = record["metrics"]
    assert m["contacts"] == 150 and m["complete"]
    # Measured: contacts within 0.1 mm of the cube, nH epsilon ~0.01 at sigma_N = 0.
    assert m["distance_median"] < 5e-4 and m["epsilon"] < 0.1
