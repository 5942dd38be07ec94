"""The committed baselines docs/suites/*.json belong to the shipped suites and to this code."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from hapticsim.suites import compare_results, load_results, load_suite, run_suite, suite_names
from hapticsim.suites.cases import TIMING_KEYS
from hapticsim.suites.provenance import machine, package_versions
from hapticsim.suites.runner import metrics_digest

BASELINES = Path(__file__).resolve().parents[2] / "docs" / "suites"
REGENERATE = "python scripts/suite_baselines.py"
#: One case per group of each suite (slow test): a few seconds a suite on 2 cores.
SAMPLES = {
    "explore-v1": "cube/*/noise=0.05/run=0",
    "fit-v1": "*/noise=0.05/run=0",
    "fit-v2": "*/nML/noise=0.05/run=0",
    "objects-v1": "*/multi/run=0",
    "policy-v1": "*/paper/analytic/run=0",
}


def _stable(case: dict) -> str:
    return json.dumps({k: v for k, v in case.items() if k not in TIMING_KEYS}, sort_keys=True)


@pytest.mark.parametrize("suite_id", suite_names())
def test_every_shipped_suite_has_a_complete_baseline(suite_id: str) -> None:
    path = BASELINES / f"{suite_id}.json"
    assert path.is_file(), f"no baseline {path}: run {REGENERATE} {suite_id}"
    data = load_results(path)
    suite = load_suite(suite_id)
    assert data["suite"]["id"] == suite_id
    # the suite file is the one the baseline ran (a changed suite is a new version)
    assert data["suite"]["sha256"] == suite.sha256, f"{suite_id} changed since {path} was made"
    assert data["selection"]["pattern"] is None
    assert data["plugins"] == {"fitter": None, "policy": None}
    assert [(c["id"], c["params"]) for c in data["cases"]] == [
        (c.id, c.params) for c in suite.cases
    ]
    assert data["summary"]["failed"] == 0
    assert data["provenance"]["git"]["dirty"] is False, f"{path} was made from uncommitted code"
    assert metrics_digest(data["cases"]) == data["summary"]["metrics_sha256"]
    assert compare_results(data, data).exit_code == 0


@pytest.mark.slow
@pytest.mark.parametrize("suite_id", sorted(SAMPLES))
def test_this_code_reproduces_the_baselines(suite_id: str) -> None:
    data = load_results(BASELINES / f"{suite_id}.json")
    made_on = data["provenance"]
    # The code-generation targets decide the last digits. A baseline that records only the CPU
    # model cannot be matched: one model name ("AMD EPYC") covers generations with other targets.
    target = made_on["machine"].get("codegen")
    if target is None:
        pytest.skip("the baseline records no code-generation target (made before they were)")
    if made_on["packages"] != package_versions() or target != machine()["codegen"]:
        pytest.skip("the baseline was made with other package versions or code-generation target")
    results = run_suite(suite_id, cases=SAMPLES[suite_id], workers=1, progress=False)
    baseline = {c["id"]: c for c in data["cases"]}
    groups = {c["group"] for c in results["cases"]}
    assert len(groups) == len(results["cases"])  # one case per group sampled
    for case in results["cases"]:
        assert _stable(case) == _stable(baseline[case["id"]]), (
            f"{suite_id} case {case['id']} differs from docs/suites/{suite_id}.json: a change "
            f"that moves the numbers moves the baselines too ({REGENERATE} {suite_id}, see "
            "docs/suites/README.md)"
        )
