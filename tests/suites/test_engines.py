"""Explorations and episodes give the same records on every engine (slow: MuJoCo in workers)."""

from __future__ import annotations

import pytest

from hapticsim.suites import run_suite


@pytest.mark.slow
@pytest.mark.parametrize(
    ("suite", "cases"),
    [
        ("explore-v1", "c*/s*/noise=0.05/run=0"),  # cube and cylinder, stripe and sweep: 4 cases
        ("policy-v1", "*/random_tapered/*/run=1"),  # 3 policies x 2 backends: 6 episodes
    ],
)
def test_simulated_cases_are_identical_on_every_engine(suite: str, cases: str) -> None:
    pytest.importorskip("distributed")
    digests = {
        engine: run_suite(suite, cases=cases, progress=False, **options)["summary"]
        for engine, options in (
            ("serial", {"workers": 1}),
            ("processes", {"workers": 2}),
            ("dask", {"scheduler": "local:2"}),
        )
    }
    assert all(d["failed"] == 0 for d in digests.values()), digests
    assert len({d["metrics_sha256"] for d in digests.values()}) == 1, digests
