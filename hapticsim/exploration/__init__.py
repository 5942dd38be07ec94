"""One exploration pipeline: a trial -> explore -> estimate -> score -> a run record.

- :class:`Trial` (validated once) and :class:`TrialSeeds` (every stream it draws from);
- explorers (:mod:`hapticsim.exploration.explorers`): scripted strategies and environment
  policies, two implementations of one protocol;
- :func:`run_trial`: the pipeline, writing nothing;
- :func:`explore`: what ``hapticsim explore`` runs: a trial, its report picture and its run
  directory (:mod:`hapticsim.data.rundir`).
"""

from hapticsim.exploration.explore import explore
from hapticsim.exploration.explorers import (
    ExplorationHooks,
    Explorer,
    PolicyExplorer,
    StrategyExplorer,
    check_explorer,
    explorer_for,
    explorer_names,
    is_policy,
    policy_explorer_names,
)
from hapticsim.exploration.pipeline import TrialHooks, TrialRecord, run_trial, score_estimate
from hapticsim.exploration.trial import DEFAULT_CONTACTS, MIN_CONTACTS, Trial, TrialSeeds

__all__ = [
    "DEFAULT_CONTACTS", "MIN_CONTACTS", "ExplorationHooks", "Explorer", "PolicyExplorer",
    "StrategyExplorer", "Trial", "TrialHooks", "TrialRecord", "TrialSeeds", "check_explorer",
    "explore", "explorer_for", "explorer_names", "is_policy", "policy_explorer_names",
    "run_trial", "score_estimate",
]  # fmt: skip
