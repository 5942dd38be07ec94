"""``hapticsim suite run``: run a suite's cases on an executor and write the results file.

The results file (JSON, written atomically, one line per case so that baselines diff well)::

    {"format": "hapticsim-suite-results", "format_version": 1,
     "suite": {"id": "fit-v1", "name": "fit", "version": 1, "kind": "fit", "cases": 640, ...},
     "selection": {"pattern": null, "cases": 640},
     "plugins": {"fitter": null, "policy": null},
     "summary": {"cases", "ok", "failed", "seconds", "cpu_seconds", "load_average",
                 "metrics_sha256"},
     "groups": {"cube/nH": {"cases", "ok", "failed", "mean": {...}, "median": {...}}, ...},
     "provenance": {"hapticsim", "git", "packages", "machine", "engine", "seeds", ...},
     "cases": [{"id", "group", "params", "status", "error", "metrics", "estimate", "truth",
                "seconds", "fit_seconds", "cpu_seconds"}, ...]}

``summary.seconds`` is the run's wall time, ``summary.cpu_seconds`` the sum of the cases' CPU
times (what the run costs whatever the load and the engine; ``load_average`` says how shared the
machine was). Everything in a case record but its three times is deterministic: the same suite,
code and packages give the same bytes on any engine and worker count. ``metrics_sha256`` is the
SHA-256 of the case records without those three keys; equal digests mean identical results.
"""

from __future__ import annotations

import contextlib
import datetime
import hashlib
import json
import statistics
import time
from pathlib import Path
from typing import Any

from hapticsim._files import check_output_path, write_text_atomic
from hapticsim.errors import InvalidInputError, WorkerDiedError
from hapticsim.parallel import Executor, make_executor
from hapticsim.parallel.cluster import DEFAULT_TIMEOUT
from hapticsim.suites.cases import QUALITY, TIMING_KEYS, CaseTask, case_cost, run_case
from hapticsim.suites.kinds import get_kind
from hapticsim.suites.plugins import describe, load_fitter, load_policy
from hapticsim.suites.provenance import load_average, provenance
from hapticsim.suites.suite import Suite, load_suite

#: ``format`` of a results file.
FORMAT: str = "hapticsim-suite-results"
#: ``format_version`` written by this hapticsim.
FORMAT_VERSION: int = 1


def check_plugins(suite: Suite, fitter: str | None, policy: str | None) -> None:
    """Check that the plug-ins suit the suite's kind and import (in this process).

    Raises:
        InvalidInputError: a plug-in for the other kind, or one that does not load.
    """

    kind = get_kind(suite.kind)
    for option, spec in (("fitter", fitter), ("policy", policy)):
        if spec is not None and kind.plugin != option:
            raise InvalidInputError(
                f"--{option} does not apply to {suite.id}, a {kind.name} suite (it takes "
                f"--{kind.plugin})"
            )
    if fitter is not None:
        load_fitter(fitter)
    if policy is not None:
        load_policy(policy)


def run_suite(
    suite: Suite | str | Path,
    out: str | Path | None = None,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    executor: Executor | None = None,
    fitter: str | None = None,
    policy: str | None = None,
    cases: str | None = None,
    progress: bool = True,
    command: list[str] | None = None,
) -> dict[str, Any]:
    """Run the (selected) cases of a suite and return, and optionally write, the results.

    Args:
        suite: a :class:`Suite`, a shipped suite's id (``"fit-v1"``) or a suite file's path.
        out: write the results JSON here (atomically: a failed run leaves no file).
        workers: local processes (1: in this process); default ``os.cpu_count()``.
        scheduler: a Dask cluster instead: ``tcp://host:port`` or ``local:N``.
        timeout: seconds to wait for the Dask scheduler and its first worker.
        executor: an engine to use (left open) instead of `workers` / `scheduler`.
        fitter: ``MODULE:FUNCTION`` of a fitter that replaces every case's method (fit and
            explore suites).
        policy: ``MODULE:CLASS`` of a policy that replaces every case's policy (policy suites).
        cases: shell-style pattern of the case ids to run (e.g. ``"*/nH/*"``).
        progress: progress bar on stderr.
        command: the command line, for the provenance record.

    Returns:
        the results (the layout of the module docstring).

    Raises:
        InvalidInputError: unknown suite, bad pattern, plug-in that does not suit or load, an
            unwritable `out`.
        WorkerDiedError: a worker died; the message names the case, and nothing is written.
        SchedulerError: the Dask scheduler cannot be reached or was lost.
    """
    if not isinstance(suite, Suite):
        suite = load_suite(suite)
    if out is not None:

        check_output_path(out)
    check_plugins(suite, fitter, policy)
    selected = suite.select(cases)
    tasks = [CaseTask(case, fitter, policy) for case in selected]
    started = datetime.datetime.now(datetime.UTC)
    load_start = load_average()
    clock = time.perf_counter()
    try:
        with contextlib.ExitStack() as stack:
            engine = executor or stack.enter_context(make_executor(workers, scheduler, timeout))
            description = engine.describe()
            records = engine.map(
                run_case, tasks, names=lambda t: t.label, desc=f"suite {suite.id}",
                unit="case", progress=progress, cost=case_cost,
            )  # fmt: skip
    except WorkerDiedError as exc:
        where = f"{out} was not written" if out is not None else "no results"
        raise WorkerDiedError(f"{exc}; the run was stopped, {where}", task=exc.task) from None
    seconds = time.perf_counter() - clock
    results = _assemble(suite, selected, records, fitter, policy, cases)
    results["summary"].update(
        seconds=round(seconds, 2),
        cpu_seconds=round(sum(r["cpu_seconds"] for r in records), 2),
        load_average={"start": load_start, "end": load_average()},
    )
    results["provenance"] = provenance(description, suite.seed, command, started)
    results = _ordered(results)
    if out is not None:
        write_results(out, results)
    return results


def metrics_digest(records: list[dict[str, Any]]) -> str:
    """SHA-256 of the case records without their timings (equal digests: identical results)."""
    stable = [{k: v for k, v in r.items() if k not in TIMING_KEYS} for r in records]
    text = json.dumps(stable, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def group_summary(records: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per group: case counts, and mean and median of each quality measure over its ok cases."""
    groups: dict[str, list[dict[str, Any]]] = {}
    for r in records:
        groups.setdefault(r["group"], []).append(r)
    out = {}
    for name, members in groups.items():
        ok = [r for r in members if r["status"] == "ok"]
        mean, median = {}, {}
        for metric in QUALITY:
            values = [r["metrics"][metric] for r in ok if r["metrics"].get(metric) is not None]
            mean[metric] = statistics.fmean(values) if values else None
            median[metric] = statistics.median(values) if values else None
        out[name] = {
            "cases": len(members), "ok": len(ok), "failed": len(members) - len(ok),
            "mean": mean, "median": median,
        }  # fmt: skip
    return out


def _assemble(
    suite: Suite, selected: tuple, records: list[dict[str, Any]], fitter: str | None,
    policy: str | None, pattern: str | None,
) -> dict[str, Any]:  # fmt: skip
    failed = sum(r["status"] != "ok" for r in records)
    info = suite.summary()
    info["sha256"] = suite.sha256
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "suite": info,
        "selection": {"pattern": pattern, "cases": len(selected)},
        "plugins": {"fitter": describe(fitter, "fitter"), "policy": describe(policy, "policy")},
        "summary": {
            "cases": len(records),
            "ok": len(records) - failed,
            "failed": failed,
            "metrics_sha256": metrics_digest(records),
        },  # fmt: skip
        "groups": group_summary(records),
        "cases": records,
    }


def _ordered(results: dict[str, Any]) -> dict[str, Any]:
    keys = ("format", "format_version", "suite", "selection", "plugins", "summary", "groups",
            "provenance", "cases")  # fmt: skip
    return {k: results[k] for k in keys}


def results_text(results: dict[str, Any]) -> str:
    """The results as JSON text: indented, with one line per case record."""
    head = {k: v for k, v in results.items() if k != "cases"}
    text = json.dumps(head, indent=2, allow_nan=False)
    lines = [json.dumps(r, separators=(",", ":"), allow_nan=False) for r in results["cases"]]
    body = ",\n".join("    " + line for line in lines)
    return f'{text[:-2]},\n  "cases": [\n{body}\n  ]\n}}\n'


def write_results(path: str | Path, results: dict[str, Any]) -> Path:
    """Write a results file atomically (a temporary file renamed into place)."""

    return write_text_atomic(path, results_text(results))


def summary_line(results: dict[str, Any]) -> dict[str, Any]:
    """A short JSON summary of a run (what ``suite run`` prints on stdout)."""
    s = results["summary"]
    return {
        "suite": results["suite"]["id"],
        "cases": s["cases"], "ok": s["ok"], "failed": s["failed"], "seconds": s["seconds"],
        "cpu_seconds": s.get("cpu_seconds"),
        "engine": results["provenance"]["engine"],
        "metrics_sha256": s["metrics_sha256"],
        "mean_epsilon": {g: v["mean"]["epsilon"] for g, v in results["groups"].items()},
    }  # fmt: skip
