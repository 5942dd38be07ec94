"""Versioned regression suites of reconstruction quality: run them, compare runs, fail loudly.

A suite is a data file (``hapticsim/suites/data/NAME-vN.toml``, :mod:`~hapticsim.suites.suite`)
listing cases of one kind (:mod:`~hapticsim.suites.kinds`): ``fit`` (synthetic contact sets x
fitting methods), ``explore`` (hand explorations x strategies x noise) or ``policy`` (policies x
objects x backends in ``HapticExplore-v0``). Each case is fixed by its seed.

- :func:`run_suite` runs the cases on any engine of :mod:`hapticsim.parallel` and writes the
  results with provenance (:mod:`~hapticsim.suites.runner`); a lab's own fitter or policy plugs
  in as ``MODULE:ATTRIBUTE`` (:mod:`~hapticsim.suites.plugins`);
- :func:`compare_results` pairs the cases of two runs and finds the groups that got worse
  (:mod:`~hapticsim.suites.compare`);
- :func:`hapticsim.testing.assert_no_regression` does both inside pytest.

Suites run experiments (fits, explorations, episodes): this package sits on top of the layout,
beside :mod:`hapticsim.experiments`; nothing below imports it.
"""

from hapticsim.suites.compare import Comparison, GroupChange, compare_results, load_results
from hapticsim.suites.runner import run_suite, write_results
from hapticsim.suites.suite import Case, Suite, list_suites, load_suite, suite_names

__all__ = [
    "Case",
    "Comparison",
    "GroupChange",
    "Suite",
    "compare_results",
    "list_suites",
    "load_results",
    "load_suite",
    "run_suite",
    "suite_names",
    "write_results",
]
