"""Run fuzzed cases (:mod:`tests.fuzz.commands`) and keep the tally: the fuzz tests and
``scripts/fuzz.py`` share this."""

from __future__ import annotations

import shutil
import tempfile
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from tests.fuzz.commands import EXISTING_DIR, Case
from tests.fuzz.harness import Outcome, run_cli
from tests.fuzz.inputs import materialise

#: Subcommands of ``suite`` counted apart.
SUITE_COMMANDS = ("list", "run", "compare")
#: Problems (:meth:`Outcome.problems`) that mean a traceback.
TRACEBACK_PROBLEMS = ("exception escaped main", "traceback printed")


@dataclass
class Tally:
    """Invocations run so far: counts by command and exit status, and the broken ones."""

    invocations: int = 0
    by_command: Counter[str] = field(default_factory=Counter)
    by_status: Counter[str] = field(default_factory=Counter)  # "command status" -> count
    failures: list[dict[str, object]] = field(default_factory=list)
    seconds: float = 0.0

    def to_dict(self) -> dict[str, object]:
        tracebacks = sum(
            any(p.startswith(TRACEBACK_PROBLEMS) for p in f["problems"])  # type: ignore[union-attr]
            for f in self.failures
        )
        return {
            "invocations": self.invocations,
            "by_command": dict(sorted(self.by_command.items())),
            "by_command_and_exit_status": dict(sorted(self.by_status.items())),
            "tracebacks": tracebacks,
            "contract_violations": len(self.failures),
            "failures": self.failures[:20],
            "seconds": round(self.seconds, 1),
        }


def run_case(case: Case, tally: Tally | None = None) -> Outcome:
    """Run `case` in a fresh temporary directory (removed afterwards) and count it."""
    root = Path(tempfile.mkdtemp(prefix="hapticsim-fuzz-"))
    start = time.perf_counter()
    try:
        (root / EXISTING_DIR).mkdir()
        for spec in case.files:
            materialise(spec, root)
        outcome = run_cli(case.argv, root)
    finally:
        shutil.rmtree(root, ignore_errors=True)
    if tally is not None:
        tally.invocations += 1
        command = case.argv[0]
        if command == "suite" and len(case.argv) > 1 and case.argv[1] in SUITE_COMMANDS:
            command = f"suite {case.argv[1]}"
        tally.by_command[command] += 1
        tally.by_status[f"{command} {outcome.code}"] += 1
        tally.seconds += time.perf_counter() - start
        if outcome.problems():
            tally.failures.append(outcome.to_dict())
    return outcome


__all__ = ["Tally", "run_case"]
