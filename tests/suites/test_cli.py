"""``hapticsim suite list | run | compare`` end to end: JSON, provenance, exit codes, bad input."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from hapticsim.cli import main
from hapticsim.suites.cases import TIMING_KEYS
from hapticsim.testing import assert_no_regression

LAB = "tests.suites.lab_plugins"
#: A small fit suite: one body, LS and nH, 8 runs each at a reduced budget (~0.1 s a case).
#: Measured: nH mean epsilon 0.06 on these cases, plain LS 0.30 (a regression of 0.24, every
#: pair worse: one-sided Wilcoxon p = 1/256).
TINY = """
name = "tiny"
version = 1
kind = "fit"
description = "cube, LS and nH"
seed = 0
id = "{body}/{method}/n={count}/run={run}"
group = "{body}/{method}"

[[grid]]
body = "cube"
method = ["LS", "nH"]
noise = 0.05
budget = 1500
runs = 8
"""


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _one_line_error(err: str, *fragments: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


def _stable_cases(path: Path) -> list[str]:
    """The case records without wall-clock times, as JSON bytes."""
    cases = json.loads(path.read_text())["cases"]
    return [json.dumps({k: v for k, v in c.items() if k not in TIMING_KEYS}) for c in cases]


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Path, Path]]:
    """The tiny suite file and a baseline run of it (2 worker processes)."""
    folder = tmp_path_factory.mktemp("suite")
    suite = folder / "tiny-v1.toml"
    suite.write_text(TINY)
    baseline = folder / "baseline.json"
    assert main(["suite", "run", str(suite), "--out", str(baseline), "--workers", "2",
                 "--quiet"]) == 0  # fmt: skip
    yield suite, baseline


def test_suite_list(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(capsys, "suite", "list")
    assert code == 0
    listed = {s["id"]: s["cases"] for s in json.loads(out)}
    assert listed == {"explore-v1": 144, "fit-v1": 640, "fit-v2": 800, "objects-v1": 70,
                      "policy-v1": 120}


def test_results_file_layout_and_provenance(tiny: tuple[Path, Path]) -> None:
    _, baseline = tiny
    data = json.loads(baseline.read_text())
    assert data["format"] == "hapticsim-suite-results" and data["format_version"] == 1
    assert data["suite"]["id"] == "tiny-v1" and data["suite"]["cases"] == 16
    assert data["summary"]["cases"] == 16 and data["summary"]["failed"] == 0
    assert set(data["groups"]) == {"cube/LS", "cube/nH"}
    assert (
        data["groups"]["cube/nH"]["mean"]["epsilon"] < data["groups"]["cube/LS"]["mean"]["epsilon"]
    )
    prov = data["provenance"]
    assert prov["engine"] == {"engine": "processes", "workers": 2}
    assert prov["packages"]["numpy"] and prov["machine"]["cores"] >= 1
    assert prov["seeds"]["root"] == 0 and prov["command"][:3] == ["hapticsim", "suite", "run"]
    case = data["cases"][0]
    assert case["id"] == "cube/LS/n=150/run=0" and case["status"] == "ok"
    for key in ("epsilon", "alpha", "beta", "iou", "chamfer", "theta"):
        assert isinstance(case["metrics"][key], float)
    assert case["seconds"] > 0 and 0 < case["cpu_seconds"]
    cpu = sum(c["cpu_seconds"] for c in data["cases"])
    assert data["summary"]["cpu_seconds"] == round(cpu, 2) > 0
    # one line per case record, so that committed baselines diff case by case
    assert sum(line.startswith('    {"id"') for line in baseline.read_text().splitlines()) == 16


def test_same_code_same_bytes_and_compare_exits_0(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    suite, baseline = tiny
    again = tmp_path / "again.json"
    code, out, _ = _run(capsys, "suite", "run", str(suite), "--out", str(again), "--workers",
                        "1", "--quiet")  # fmt: skip
    assert code == 0
    summary = json.loads(out)
    assert (
        summary["metrics_sha256"] == json.loads(baseline.read_text())["summary"]["metrics_sha256"]
    )
    assert _stable_cases(again) == _stable_cases(baseline)  # 1 process vs 2 workers
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(again))
    assert code == 0 and "no regression" in out


def test_a_worse_fitter_is_a_regression_naming_its_group(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    suite, baseline = tiny
    worse = tmp_path / "worse.json"
    worse_fitter = "hapticsim.suites.examples:least_squares_fit"
    code, _, _ = _run(capsys, "suite", "run", str(suite), "--out", str(worse), "--workers", "2",
                      "--fitter", worse_fitter, "--quiet")  # fmt: skip
    assert code == 0
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(worse))
    assert code == 1
    assert "REGRESSION in 1 group(s): cube/nH" in out  # LS replaced by LS is no regression
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(worse), "--json")
    assert code == 1 and json.loads(out)["regressions"] == ["cube/nH"]
    # the other way round it is an improvement, not a regression
    code, out, _ = _run(capsys, "suite", "compare", str(worse), str(baseline))
    assert code == 0 and "improved: cube/nH" in out


def test_a_fitter_returning_garbage_fails_cases_not_the_run(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    suite, baseline = tiny
    bad = tmp_path / "garbage.json"
    code, out, err = _run(capsys, "suite", "run", str(suite), "--out", str(bad), "--workers",
                          "2", "--fitter", f"{LAB}:garbage_fit", "--quiet")  # fmt: skip
    assert code == 0
    failed = json.loads(out)["failed"]
    assert 0 < failed < 16
    assert f"{failed} of 16 cases failed" in err
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(bad))
    assert code == 1 and "now fail" in out


def test_a_worker_that_dies_names_its_case_and_writes_nothing(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    suite, _ = tiny
    deadly = tmp_path / "deadly-v1.toml"
    deadly.write_text(
        TINY.replace('name = "tiny"', 'name = "deadly"') + '\n[[grid]]\nbody = "cube"\n'
        'method = "LS"\nnoise = 0.05\ncount = 149\nrun = 0\n'
    )
    out = tmp_path / "never.json"
    code, _, err = _run(capsys, "suite", "run", str(deadly), "--out", str(out), "--workers", "2",
                        "--fitter", f"{LAB}:dying_fit", "--quiet")  # fmt: skip
    assert code == 2
    _one_line_error(err, "died (exit status 3)", "case 'cube/LS/n=149/run=0' of deadly-v1",
                    "was not written")  # fmt: skip
    assert not out.exists() and not list(tmp_path.glob(".never.json*"))


@pytest.mark.parametrize(
    ("argv", "fragments"),
    [
        (["fit-v9"], ["unknown suite 'fit-v9'", "fit-v1"]),
        (["fit-v1", "--fitter", "no_such_lab.fit:fit"], ["cannot import module 'no_such_lab.fit'"]),
        (["fit-v1", "--fitter", "fit"], ["must be MODULE:ATTRIBUTE"]),
        (["fit-v1", "--policy", "hapticsim.suites.examples:AxisPolicy"], ["takes --fitter"]),
        (["policy-v1", "--fitter", f"{LAB}:nh_fit"], ["takes --policy"]),
        (["fit-v1", "--cases", "sphere/*"], ["matches no case of fit-v1"]),
        (["fit-v1", "--scheduler", "localhost"], ["local:N"]),
    ],
)
def test_bad_run_input_is_one_line_exit_2(
    argv: list[str], fragments: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "r.json"
    code, stdout, err = _run(capsys, "suite", "run", *argv, "--out", str(out), "--quiet")
    assert code == 2 and stdout == ""
    _one_line_error(err, "hapticsim suite run: error:", *fragments)
    assert not out.exists()


def test_bad_compare_input_is_one_line_exit_2(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    suite, baseline = tiny
    data = json.loads(baseline.read_text())
    other = tmp_path / "other.json"
    other.write_text(json.dumps({**data, "suite": {**data["suite"], "id": "tiny-v2"}}))
    partial = tmp_path / "partial.json"
    partial.write_text(json.dumps({**data, "cases": data["cases"][:5]}))
    not_results = tmp_path / "x.json"
    not_results.write_text('{"a": 1}')
    reseeded = tmp_path / "reseeded.json"
    seeds = {**data["provenance"]["seeds"], "root": 5}
    reseeded.write_text(json.dumps({**data, "provenance": {**data["provenance"], "seeds": seeds}}))
    for path, fragment in (
        (other, "the baseline is of suite tiny-v1 and the results of tiny-v2"),
        (partial, "the results lack 11 case(s) of the baseline"),
        (not_results, "is not a suite results file"),
        (reseeded, "with root seed 0 and the results with 5: its cases saw different data"),
        (tmp_path / "missing.json", "file not found"),
    ):
        code, stdout, err = _run(capsys, "suite", "compare", str(baseline), str(path))
        assert code == 2 and stdout == ""
        _one_line_error(err, "hapticsim suite compare: error:", fragment)


def test_an_unreachable_scheduler_is_one_line_exit_2(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("distributed")
    suite, _ = tiny
    out = tmp_path / "r.json"
    code, _, err = _run(capsys, "suite", "run", str(suite), "--out", str(out), "--scheduler",
                        "tcp://127.0.0.1:9", "--scheduler-timeout", "1", "--quiet")  # fmt: skip
    assert code == 2 and not out.exists()
    _one_line_error(err, "cannot reach the Dask scheduler at tcp://127.0.0.1:9")


def test_a_local_cluster_gives_byte_identical_cases(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("distributed")
    suite, baseline = tiny
    out = tmp_path / "dask.json"
    code, stdout, _ = _run(capsys, "suite", "run", str(suite), "--out", str(out), "--scheduler",
                           "local:2", "--quiet")  # fmt: skip
    assert code == 0
    assert json.loads(stdout)["engine"] == {"engine": "dask", "scheduler": "local:2", "workers": 2}
    assert _stable_cases(out) == _stable_cases(baseline)  # LocalCluster vs local processes


def test_assert_no_regression(tiny: tuple[Path, Path]) -> None:
    from hapticsim.suites.examples import least_squares_fit

    suite, baseline = tiny
    comparison = assert_no_regression(suite, baseline, cases="*/nH/*")
    assert comparison.regressions == () and comparison.paired == 8
    with pytest.raises(AssertionError, match="REGRESSION in 1 group.*cube/nH"):
        assert_no_regression(suite, baseline, fitter=least_squares_fit, cases="*/nH/*", workers=2)


def test_a_changed_suite_file_is_noted(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _, baseline = tiny
    data = json.loads(baseline.read_text())
    edited = tmp_path / "edited.json"  # e.g. a comment edited in the suite file
    edited.write_text(json.dumps({**data, "suite": {**data["suite"], "sha256": "0" * 64}}))
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(edited))
    assert code == 0 and "note: the suite file of tiny-v1 changed between the two runs" in out
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(baseline), "--json")
    assert code == 0 and json.loads(out)["suite_file_changed"] is False


def test_compare_says_why_digests_differ(
    tiny: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _, baseline = tiny
    data = json.loads(baseline.read_text())
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(baseline))
    assert "digests: identical" in out
    machine = data["provenance"]["machine"]
    assert set(machine["codegen"]) == {"numba_cpu", "numba_features", "numpy_simd", "blas"}
    # another target than this run's (numba names the host's CPU; "generic" where it cannot)
    target = "generic" if machine["codegen"]["numba_cpu"] != "generic" else "haswell"
    other = {**machine, "codegen": {**machine["codegen"], "numba_cpu": target}}
    moved = {**data, "provenance": {**data["provenance"], "machine": other},
             "summary": {**data["summary"], "metrics_sha256": "f" * 64}}  # fmt: skip
    path = tmp_path / "moved.json"
    path.write_text(json.dumps(moved))
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(path))
    assert code == 0 and "no regression" in out  # the statistical verdict stands
    assert "digests differ" in out and "numba_cpu " in out and f"-> {target}" in out
    code, out, _ = _run(capsys, "suite", "compare", str(baseline), str(path), "--json")
    digests = json.loads(out)["digests"]
    assert digests["same"] is False and any(target in r for r in digests["reasons"])


@pytest.mark.slow
def test_another_code_generation_target_is_named_by_compare(
    tiny: tuple[Path, Path], tmp_path: Path
) -> None:
    """Issue 22: a run under other targets (numba's generic CPU, numpy without its AVX2 routines,
    another BLAS kernel) against the host's baseline: compare keeps its verdict (exit 0) and,
    when the bytes differ, names the targets as the reason."""
    suite, baseline = tiny
    env = {**os.environ, "NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(tmp_path / "nb"),
           "NPY_DISABLE_CPU_FEATURES": "X86_V3", "OPENBLAS_CORETYPE": "Sandybridge"}  # fmt: skip
    out = tmp_path / "other.json"
    run = [sys.executable, "-m", "hapticsim.cli", "suite", "run", str(suite), "--out", str(out),
           "--workers", "1", "--quiet"]  # fmt: skip
    subprocess.run(run, env=env, check=True, capture_output=True, timeout=1200)
    assert json.loads(out.read_text())["provenance"]["machine"]["codegen"]["numba_cpu"] == "generic"
    done = subprocess.run(
        [sys.executable, "-m", "hapticsim.cli", "suite", "compare", str(baseline), str(out),
         "--json"], capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout
    digests = json.loads(done.stdout)["digests"]
    if not digests["same"]:
        assert any("code-generation target" in r and "generic" in r for r in digests["reasons"])
