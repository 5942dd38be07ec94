"""Claim checks: verdicts follow the numbers (synthetic per-run rows)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.experiments.claims import (
    FAILS,
    HOLDS,
    UNCLEAR,
    check_claims,
    hybrid_improves_more,
    normals_improve_ls,
)
from hapticsim.experiments.stats import summarize
from hapticsim.experiments.trial import METRICS

BODIES = ("tapered_box", "cube", "cylinder", "ellipsoid")


def _rows(
    means: dict[str, float], runs: int = 10, spread: float | dict[str, float] = 0.02, **fixed
) -> list[dict]:
    """Per-run rows with epsilon = means[method] + noise, paired by (body, run)."""
    spreads = spread if isinstance(spread, dict) else dict.fromkeys(means, spread)
    rng = np.random.default_rng(1)
    rows = []
    for body in fixed.pop("bodies", BODIES):
        for run in range(runs):
            common = rng.uniform(0, 0.1)  # data-set difficulty, shared by the methods
            for method, mean in means.items():
                eps = mean + common + rng.normal(0, spreads[method])
                rows.append({
                    "body": body, "method": method, "noise": 0.1, "budget": 1000, "count": 150,
                    "run": run, "theta": 1e-5 * (1 + eps), "alpha": eps / 2, "beta": eps / 2,
                    "epsilon": eps, "iou": 1 - eps, "chamfer": 1e-3, "eof": 1e-5,
                    "evaluations": 1000, "seconds": 0.1, **fixed,
                })  # fmt: skip
    return rows


def test_normals_improve_ls_follows_the_numbers() -> None:
    assert normals_improve_ls(_rows({"LS": 0.5, "nLS": 0.3})).verdict == HOLDS
    assert normals_improve_ls(_rows({"LS": 0.3, "nLS": 0.5})).verdict == FAILS
    same = _rows({"LS": 0.4})
    same += [{**r, "method": "nLS"} for r in same]
    assert normals_improve_ls(same).verdict == UNCLEAR


def test_hybrid_improves_more_needs_both_parts() -> None:
    paper_like = {"LS": 0.6, "H": 0.5, "nLS": 0.45, "nH": 0.1}
    claim = hybrid_improves_more(_rows(paper_like))
    assert claim.verdict == HOLDS
    assert any("best: nH" in e for e in claim.evidence)
    ls_best = {"LS": 0.3, "H": 0.5, "nLS": 0.1, "nH": 0.45}
    assert hybrid_improves_more(_rows(ls_best)).verdict == FAILS


@pytest.mark.parametrize("hybrid_better", [True, False])
def test_fig5_claims(hybrid_better: bool) -> None:
    budget_rows, noise_rows = [], []
    for budget, level in zip((100, 200, 400, 800), (0.6, 0.4, 0.3, 0.2), strict=True):
        good, bad = level, 0.5 + 0.2 * (budget == 400)
        means = {"LS": bad, "nLS": bad, "H": good, "nH": good}
        spread = {"LS": 0.1, "nLS": 0.1, "H": 0.02, "nH": 0.02}
        if not hybrid_better:
            means = {"LS": good, "nLS": good, "H": bad, "nH": bad}
            spread = {"LS": 0.02, "nLS": 0.02, "H": 0.1, "nH": 0.1}
        budget_rows += _rows(means, spread=spread, budget=budget, bodies=("cylinder",))
    for noise in (0.01, 0.1, 0.3):
        means = {"LS": 0.3 + noise, "H": 0.3 + noise, "nLS": 0.2, "nH": 0.1}
        spread = {"LS": 0.1, "H": 0.1, "nLS": 0.02, "nH": 0.02}
        noise_rows += _rows(means, spread=spread, noise=noise, bodies=("cube",))
    claims = check_claims(
        budget_rows=budget_rows,
        by_budget=summarize(budget_rows, ("method", "budget"), METRICS),
        noise_rows=noise_rows,
        by_noise=summarize(noise_rows, ("method", "noise"), METRICS),
    )
    assert [c.key for c in claims] == ["hybrid_stable_with_n", "normals_stabilise_noise"]
    assert claims[0].verdict == (HOLDS if hybrid_better else FAILS)
    assert claims[1].verdict == HOLDS
