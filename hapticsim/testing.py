"""Helpers for a lab's own tests: regression checks of reconstruction quality inside pytest.

Example, in the lab's test suite (the baseline made once with the same command and committed)::

    from hapticsim.testing import assert_no_regression

    def test_our_fitter_did_not_get_worse():
        assert_no_regression("fit-v1", "tests/baselines/fit-v1-nH.json",
                             fitter="my_lab.fitting:fit", workers=2)

The fitter (or policy) is named ``MODULE:ATTRIBUTE`` or given as a module-level function (or
class); it must be importable by that name, since the worker processes import it.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from hapticsim.errors import InvalidInputError
from hapticsim.suites.compare import (
    DEFAULT_ALPHA,
    DEFAULT_TOLERANCE,
    Comparison,
    compare_results,
    load_results,
)
from hapticsim.suites.runner import run_suite

__all__ = ["assert_no_regression", "plugin_spec"]


def plugin_spec(plugin: Any, option: str) -> str | None:
    """``MODULE:ATTRIBUTE`` of a plug-in given as a spec string or as a module-level object.

    Raises:
        InvalidInputError: an object that cannot be imported by name (a lambda, a local or a
            ``__main__`` function).
    """
    if plugin is None or isinstance(plugin, str):
        return plugin
    module = getattr(plugin, "__module__", None)
    name = getattr(plugin, "__qualname__", None)
    if not module or not name or "<" in name or module == "__main__":
        raise InvalidInputError(
            f"`{option}` must be 'MODULE:ATTRIBUTE' or a module-level function or class that "
            f"worker processes can import, got {plugin!r}"
        )
    return f"{module}:{name}"


def assert_no_regression(
    suite: str | Path,
    baseline: str | Path | Mapping[str, Any],
    *,
    fitter: Any = None,
    policy: Any = None,
    cases: str | None = None,
    workers: int | None = 1,
    scheduler: str | None = None,
    tolerance: float = DEFAULT_TOLERANCE,
    alpha: float = DEFAULT_ALPHA,
    out: str | Path | None = None,
) -> Comparison:
    """Run a suite and fail (AssertionError with the comparison table) if it regressed.

    Args:
        suite: a shipped suite's id (``"fit-v1"``) or a suite file's path.
        baseline: results of an earlier run (path or parsed JSON).
        fitter: the fitter under test (``MODULE:FUNCTION`` or the function), or None for the
            suite's own methods.
        policy: the policy under test (``MODULE:CLASS`` or the class), for policy suites.
        cases: case-id pattern; default the baseline's own selection (all its cases).
        workers: local processes (default 1: in the test process).
        scheduler: a Dask cluster instead (``tcp://host:port`` or ``local:N``).
        tolerance: largest harmless rise of a group's mean epsilon.
        alpha: significance level of the paired Wilcoxon test.
        out: also write the new results here (e.g. to update the baseline by hand).

    Returns:
        the :class:`~hapticsim.suites.Comparison` when nothing regressed.

    Raises:
        AssertionError: a group regressed or a case that passed now fails; the message is the
            comparison table naming the groups.
        HapticsimError: bad input (unknown suite, baseline of another suite, plug-in that does
            not import, ...).
    """

    base = load_results(baseline, "baseline")
    if cases is None:
        cases = (base.get("selection") or {}).get("pattern")
    results = run_suite(
        suite, out, workers=None if scheduler else workers, scheduler=scheduler,
        fitter=plugin_spec(fitter, "fitter"), policy=plugin_spec(policy, "policy"), cases=cases,
        progress=False,
    )  # fmt: skip
    comparison = compare_results(base, results, tolerance=tolerance, alpha=alpha)
    if comparison.regressions:
        raise AssertionError("reconstruction quality regressed:\n" + comparison.table())
    return comparison
