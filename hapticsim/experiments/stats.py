"""Summaries over runs and paired comparisons of methods, for tables, curves and claims."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

#: Statistics kept per metric in a summary row, as ``{metric}_{stat}``.
STATS: tuple[str, ...] = ("mean", "std", "q25", "median", "q75")


def describe(values: Sequence[float]) -> dict[str, float]:
    """Mean, sample standard deviation (ddof=1; 0 for one value) and quartiles of `values`."""
    x = np.asarray(values, dtype=np.float64)
    q25, median, q75 = np.percentile(x, [25, 50, 75])
    return {
        "mean": float(np.mean(x)),
        "std": float(np.std(x, ddof=1)) if x.size > 1 else 0.0,
        "q25": float(q25),
        "median": float(median),
        "q75": float(q75),
    }


def summarize(
    rows: Iterable[dict[str, Any]], by: Sequence[str], metrics: Sequence[str]
) -> list[dict[str, Any]]:
    """Group `rows` by the `by` columns and describe each metric over the group.

    Args:
        rows: flat records (e.g. :meth:`TrialResult.to_row`).
        by: grouping columns, e.g. ``("body", "method")``.
        metrics: columns to describe.

    Returns:
        One row per group, in order of first appearance: the `by` columns, ``runs`` (group size)
        and ``{metric}_{stat}`` for every stat in :data:`STATS`.
    """
    groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
    for row in rows:
        groups.setdefault(tuple(row[k] for k in by), []).append(row)
    out = []
    for key, members in groups.items():
        summary: dict[str, Any] = dict(zip(by, key, strict=True))
        summary["runs"] = len(members)
        for metric in metrics:
            for stat, value in describe([m[metric] for m in members]).items():
                summary[f"{metric}_{stat}"] = value
        out.append(summary)
    return out


@dataclass(frozen=True)
class PairedDifference:
    """Mean of paired differences ``b - a`` with a bootstrap confidence interval.

    Attributes:
        mean_a, mean_b: means of the two samples.
        diff: mean of ``b - a``.
        low, high: bounds of the bootstrap confidence interval of ``diff``.
        wins: fraction of pairs with ``b < a`` (b better when lower is better).
        pairs: number of pairs.
    """

    mean_a: float
    mean_b: float
    diff: float
    low: float
    high: float
    wins: float
    pairs: int

    @property
    def verdict(self) -> str:
        """``"lower"`` if the interval lies below 0, ``"higher"`` above, else ``"unclear"``."""
        if self.high < 0:
            return "lower"
        if self.low > 0:
            return "higher"
        return "unclear"


def paired_difference(
    a: Sequence[float],
    b: Sequence[float],
    confidence: float = 0.95,
    resamples: int = 2000,
    rng: int = 0,
) -> PairedDifference:
    """Compare paired samples (same data, two methods) by a percentile bootstrap of the mean.

    Args:
        a, b: (n,) paired values, e.g. epsilon of LS and of nLS on the same n data sets.
        confidence: level of the interval.
        resamples: bootstrap resamples.
        rng: seed of the resampling.

    Returns:
        PairedDifference of ``b - a``.
    """
    x = np.asarray(a, dtype=np.float64)
    y = np.asarray(b, dtype=np.float64)
    d = y - x
    idx = np.random.default_rng(rng).integers(0, d.size, size=(resamples, d.size))
    boot = d[idx].mean(axis=1)
    tail = 100 * (1 - confidence) / 2
    low, high = np.percentile(boot, [tail, 100 - tail])
    return PairedDifference(
        mean_a=float(x.mean()), mean_b=float(y.mean()), diff=float(d.mean()),
        low=float(low), high=float(high), wins=float(np.mean(d < 0)), pairs=int(d.size),
    )  # fmt: skip
