"""Summaries over runs and paired comparisons (known answers)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.experiments.stats import describe, paired_difference, summarize


def test_describe_known_values() -> None:
    d = describe([1.0, 2.0, 3.0, 4.0])
    assert d["mean"] == 2.5
    assert d["std"] == pytest.approx(np.std([1, 2, 3, 4], ddof=1))
    assert (d["q25"], d["median"], d["q75"]) == (1.75, 2.5, 3.25)
    assert describe([5.0])["std"] == 0.0


def test_summarize_groups_in_order_of_appearance() -> None:
    rows = [
        {"body": "cube", "method": "LS", "epsilon": 0.4},
        {"body": "cube", "method": "nH", "epsilon": 0.1},
        {"body": "cube", "method": "LS", "epsilon": 0.6},
    ]
    out = summarize(rows, ("body", "method"), ("epsilon",))
    assert [(r["method"], r["runs"]) for r in out] == [("LS", 2), ("nH", 1)]
    assert out[0]["epsilon_mean"] == pytest.approx(0.5)


def test_paired_difference_verdicts() -> None:
    rng = np.random.default_rng(0)
    a = rng.uniform(0.3, 0.6, 40)
    lower = paired_difference(a, a - 0.1 + rng.normal(0, 0.01, 40))
    assert lower.verdict == "lower" and lower.wins == 1.0
    assert lower.diff == pytest.approx(-0.1, abs=0.01)
    assert paired_difference(a, a + 0.1).verdict == "higher"
    noise = rng.normal(0, 0.1, 20)
    assert paired_difference(a, a + np.concatenate([noise, -noise])).verdict == "unclear"
