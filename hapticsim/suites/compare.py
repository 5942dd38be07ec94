"""``hapticsim suite compare``: did reconstructions get worse between a baseline and new results?

Cases are paired by id. A **group regresses** when its mean epsilon over the cases that passed in
both files is worse by more than ``tolerance`` *and* a one-sided paired Wilcoxon signed-rank test
finds the increase significant (p < ``alpha``); a **case that failed** in the results but passed
in the baseline is a regression of its group too. Improvements are found the same way. Exit
status of the command: 0 no regression, 1 a regression, 2 bad input (files of different suites
or versions, a results file that lacks cases of the baseline, malformed files).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim._files import read_json
from hapticsim._validate import finite_float
from hapticsim.errors import InvalidInputError
from hapticsim.suites.runner import FORMAT, FORMAT_VERSION

#: Default largest harmless increase of a group's mean epsilon.
DEFAULT_TOLERANCE: float = 0.01
#: Default significance level of the paired test.
DEFAULT_ALPHA: float = 0.01
#: Verdicts of a group.
VERDICTS: tuple[str, ...] = ("worse", "better", "same")


def load_results(path_or_data: str | Path | Mapping[str, Any], label: str = "results") -> dict:
    """A results file (or its parsed content), checked for the fields `compare` needs.

    Raises:
        InvalidInputError: unreadable, not JSON, not a suite results file, or written in a newer
            format; the message names the file.
    """
    if isinstance(path_or_data, Mapping):
        data, where = dict(path_or_data), label
    else:

        data, where = read_json(path_or_data), str(path_or_data)
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InvalidInputError(f"{where} is not a suite results file (no format {FORMAT!r})")
    if data.get("format_version") != FORMAT_VERSION:
        raise InvalidInputError(
            f"{where} has results format version {data.get('format_version')!r}; this hapticsim "
            f"reads version {FORMAT_VERSION}"
        )
    suite, cases = data.get("suite"), data.get("cases")
    if not isinstance(suite, dict) or "id" not in suite or not isinstance(cases, list):
        raise InvalidInputError(f"{where}: missing `suite.id` or `cases`")
    for i, case in enumerate(cases):
        ok = isinstance(case, dict) and all(k in case for k in ("id", "group", "status", "metrics"))
        if not ok or case["status"] not in ("ok", "failed"):
            raise InvalidInputError(f"{where}: case {i} lacks id, group, status or metrics")
        if case["status"] == "ok" and not isinstance(case["metrics"].get("epsilon"), (int, float)):
            raise InvalidInputError(f"{where}: case {case['id']!r} has no epsilon")
    return data


@dataclass(frozen=True)
class GroupChange:
    """How one group changed.

    Attributes:
        group: the group name.
        paired: cases that passed in both files.
        baseline: mean epsilon of those cases in the baseline (None if none).
        results: mean epsilon of those cases in the results.
        difference: ``results - baseline``.
        p_worse: one-sided paired Wilcoxon p-value of an increase (1 without differences).
        p_better: the same for a decrease.
        newly_failed: ids of cases that failed in the results but passed in the baseline.
        fixed: ids of cases that passed in the results but failed in the baseline.
        verdict: ``"worse"``, ``"better"`` or ``"same"``.
    """

    group: str
    paired: int
    baseline: float | None
    results: float | None
    difference: float | None
    p_worse: float
    p_better: float
    newly_failed: tuple[str, ...]
    fixed: tuple[str, ...]
    verdict: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return {
            "group": self.group, "paired": self.paired, "baseline": self.baseline,
            "results": self.results, "difference": self.difference, "p_worse": self.p_worse,
            "p_better": self.p_better, "newly_failed": list(self.newly_failed),
            "fixed": list(self.fixed), "verdict": self.verdict,
        }  # fmt: skip


@dataclass(frozen=True)
class Comparison:
    """The outcome of comparing results against a baseline.

    Attributes:
        suite: the suite's id.
        tolerance: largest harmless increase of a group's mean epsilon.
        alpha: significance level.
        groups: one :class:`GroupChange` per group with paired cases, in suite order.
        paired: number of case ids in both files.
        not_in_baseline: ids of results cases the baseline does not have (not compared).
        baseline_commit, results_commit: the git commits recorded in the two files.
        suite_file_changed: the two runs read suite files of different content (SHA-256) under
            one id; the cases are still paired by id and parameters, and the table says so.
        digests: ``{"same", "baseline", "results", "reasons"}``: whether the two metrics
            digests are equal (bit-identical case records) and, when not, what differs between
            the runs' provenance that can explain it (:func:`digest_reasons`).
    """

    suite: str
    tolerance: float
    alpha: float
    groups: tuple[GroupChange, ...]
    paired: int
    not_in_baseline: tuple[str, ...] = ()
    baseline_commit: str | None = None
    results_commit: str | None = None
    suite_file_changed: bool = False
    digests: dict[str, Any] | None = None

    @property
    def regressions(self) -> tuple[str, ...]:
        """Names of the groups that regressed."""
        return tuple(g.group for g in self.groups if g.verdict == "worse")

    @property
    def improvements(self) -> tuple[str, ...]:
        """Names of the groups that improved."""
        return tuple(g.group for g in self.groups if g.verdict == "better")

    @property
    def exit_code(self) -> int:
        """0 without regression, 1 with one."""
        return 1 if self.regressions else 0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return {
            "suite": self.suite, "tolerance": self.tolerance, "alpha": self.alpha,
            "paired": self.paired, "regressions": list(self.regressions),
            "improvements": list(self.improvements), "not_in_baseline": list(self.not_in_baseline),
            "baseline_commit": self.baseline_commit, "results_commit": self.results_commit,
            "suite_file_changed": self.suite_file_changed, "digests": self.digests,
            "groups": [g.to_dict() for g in self.groups],
        }  # fmt: skip

    def table(self, all_groups: bool = True) -> str:
        """A plain-text table of the groups (all, or only the changed ones) and a verdict line."""
        short = {None: "?"}
        head = (
            f"suite {self.suite}: {self.paired} cases paired (baseline "
            f"{(self.baseline_commit or '?')[:10]}, results {(self.results_commit or '?')[:10]});"
            f" a group regresses if its mean epsilon rises by > {self.tolerance:g} with a paired "
            f"Wilcoxon p < {self.alpha:g}"
        )
        width = max([len("group")] + [len(g.group) for g in self.groups])
        lines = [head, "", f"{'group':<{width}}  {'n':>4}  {'baseline':>8}  {'results':>8}  "
                 f"{'change':>8}  {'p':>8}  verdict"]  # fmt: skip
        for g in self.groups:
            if not all_groups and g.verdict == "same" and not g.newly_failed and not g.fixed:
                continue
            p = g.p_worse if (g.difference or 0.0) >= 0 else g.p_better
            verdict = {"worse": "WORSE", "better": "better", "same": "same"}[g.verdict]
            notes = []
            if g.newly_failed:
                notes.append(
                    f"{len(g.newly_failed)} case(s) now fail: {', '.join(g.newly_failed[:3])}"
                )
            if g.fixed:
                notes.append(f"{len(g.fixed)} case(s) fixed")
            lines.append(
                f"{g.group:<{width}}  {g.paired:>4}  {_num(g.baseline, short):>8}  "
                f"{_num(g.results, short):>8}  {_signed(g.difference):>8}  {p:>8.2g}  {verdict}"
                + (f" ({'; '.join(notes)})" if notes else "")
            )
        if len(lines) == 3:
            lines.append("(no group changed)")
        lines.append("")
        if self.regressions:
            lines.append(
                f"REGRESSION in {len(self.regressions)} group(s): {', '.join(self.regressions)}"
            )
        else:
            lines.append("no regression")
        if self.improvements:
            lines.append(f"improved: {', '.join(self.improvements)}")
        if self.not_in_baseline:
            lines.append(f"{len(self.not_in_baseline)} case(s) not in the baseline, not compared")
        if self.suite_file_changed:
            lines.append(
                f"note: the suite file of {self.suite} changed between the two runs (another "
                "SHA-256); cases were paired by id and parameters"
            )
        if self.digests is not None:
            lines.append(_digest_line(self.digests))
        return "\n".join(lines)


def _num(value: float | None, short: dict) -> str:
    return short[None] if value is None else f"{value:.4f}"


def _signed(value: float | None) -> str:
    return "?" if value is None else f"{value:+.4f}"


def _wilcoxon(d: np.ndarray, alternative: str) -> float:
    if not np.any(d != 0):
        return 1.0
    from scipy.stats import wilcoxon

    return float(wilcoxon(d, alternative=alternative).pvalue)


def compare_results(
    baseline: str | Path | Mapping[str, Any],
    results: str | Path | Mapping[str, Any],
    tolerance: float = DEFAULT_TOLERANCE,
    alpha: float = DEFAULT_ALPHA,
) -> Comparison:
    """Compare results against a baseline of the same suite (see the module docstring).

    Args:
        baseline: the baseline results (path or parsed).
        results: the new results (path or parsed).
        tolerance: largest harmless increase of a group's mean epsilon, >= 0.
        alpha: significance level of the one-sided paired Wilcoxon test, in (0, 1).

    Returns:
        the :class:`Comparison`.

    Raises:
        InvalidInputError: malformed files, files of different suites or versions, a case with
            different parameters in the two, results lacking cases of the baseline (within the
            results' ``--cases`` selection), or nothing to pair.
    """
    tol = finite_float(tolerance, "tolerance", low=0.0)
    level = finite_float(alpha, "alpha", low=0.0, high=1.0)
    if not 0.0 < level < 1.0:
        raise InvalidInputError(f"`alpha` must lie in (0, 1), got {alpha!r}")
    base = load_results(baseline, "baseline")
    new = load_results(results, "results")
    if base["suite"]["id"] != new["suite"]["id"]:
        raise InvalidInputError(
            f"the baseline is of suite {base['suite']['id']} and the results of "
            f"{new['suite']['id']}: compare results of one suite and version"
        )
    roots = [_field(d, "provenance", "seeds", "root") for d in (base, new)]
    if None not in roots and roots[0] != roots[1]:
        raise InvalidInputError(
            f"the baseline ran suite {base['suite']['id']} with root seed {roots[0]} and the "
            f"results with {roots[1]}: its cases saw different data (a changed suite file is a "
            "new version)"
        )
    hashes = [d["suite"].get("sha256") for d in (base, new)]
    base_cases = {c["id"]: c for c in base["cases"]}
    new_cases = {c["id"]: c for c in new["cases"]}
    pattern = (new.get("selection") or {}).get("pattern")
    expected = [i for i in base_cases if pattern is None or fnmatchcase(i, pattern)]
    missing = [i for i in expected if i not in new_cases]
    if missing:
        raise InvalidInputError(
            f"the results lack {len(missing)} case(s) of the baseline (e.g. {missing[0]!r}): "
            "run the same suite, or select the cases with --cases"
        )
    paired = [i for i in new_cases if i in base_cases]
    if not paired:
        raise InvalidInputError("the baseline and the results have no case in common")
    for i in paired:
        if "params" in base_cases[i] and base_cases[i].get("params") != new_cases[i].get("params"):
            raise InvalidInputError(
                f"case {i!r} has different parameters in the baseline and the results"
            )
    groups: dict[str, list[str]] = {}
    for i in paired:
        groups.setdefault(new_cases[i]["group"], []).append(i)
    changes = tuple(
        _group_change(name, ids, base_cases, new_cases, tol, level) for name, ids in groups.items()
    )
    return Comparison(
        suite=new["suite"]["id"], tolerance=tol, alpha=level, groups=changes, paired=len(paired),
        not_in_baseline=tuple(i for i in new_cases if i not in base_cases),
        baseline_commit=_commit(base), results_commit=_commit(new),
        suite_file_changed=None not in hashes and hashes[0] != hashes[1],
        digests=_digests(base, new, paired, len(base_cases), len(new_cases)),
    )  # fmt: skip


def digest_reasons(base: Mapping[str, Any], new: Mapping[str, Any]) -> list[str]:
    """What differs between two runs' provenance that can change a result's bytes: the commit
    (or uncommitted changes), package versions, the suite file, and the code-generation targets
    of the machine (:func:`hapticsim.suites.provenance.codegen_target`: numba's CPU, numpy's
    SIMD target, the BLAS kernel), or the CPU model where a file predates those."""
    reasons = []
    commits = [_commit(d) for d in (base, new)]
    dirty = [_field(d, "provenance", "git", "dirty") for d in (base, new)]
    if None not in commits and commits[0] != commits[1]:
        reasons.append(f"code: commit {commits[0][:10]} -> {commits[1][:10]}")
    if any(dirty):
        where = [n for n, d in zip(("the baseline", "the results"), dirty, strict=True) if d]
        reasons.append("code: uncommitted changes in " + " and ".join(where))
    packages = [_field(d, "provenance", "packages") or {} for d in (base, new)]
    changed = sorted(k for k in set(packages[0]) | set(packages[1])
                     if packages[0].get(k) != packages[1].get(k))  # fmt: skip
    if changed:
        reasons.append("packages: " + ", ".join(
            f"{k} {packages[0].get(k)} -> {packages[1].get(k)}" for k in changed))  # fmt: skip
    if base["suite"].get("sha256") != new["suite"].get("sha256"):
        reasons.append("the suite file")
    targets = [_field(d, "provenance", "machine", "codegen") for d in (base, new)]
    if None not in targets:
        keys = ("numba_cpu", "numba_features", "numpy_simd", "blas")
        moved = [f"{k} {targets[0].get(k)} -> {targets[1].get(k)}" for k in keys
                 if targets[0].get(k) != targets[1].get(k)]  # fmt: skip
        if moved:
            reasons.append("code-generation target: " + ", ".join(moved))
    else:
        cpus = [_field(d, "provenance", "machine", "cpu") for d in (base, new)]
        if cpus[0] != cpus[1]:
            reasons.append(f"CPU: {cpus[0]} -> {cpus[1]} (the baseline records no "
                           "code-generation target)")  # fmt: skip
    return reasons


def _digests(
    base: Mapping[str, Any], new: Mapping[str, Any], paired: list[str], n_base: int, n_new: int
) -> dict[str, Any] | None:
    """The digest part of a comparison (None when a file has no digest, or the results are a
    selection of the baseline's cases: their digests cannot be equal)."""
    digests = [_field(d, "summary", "metrics_sha256") for d in (base, new)]
    if None in digests or not (len(paired) == n_base == n_new):
        return None
    same = digests[0] == digests[1]
    return {"same": same, "baseline": digests[0], "results": digests[1],
            "reasons": [] if same else digest_reasons(base, new)}  # fmt: skip


def _digest_line(digests: Mapping[str, Any]) -> str:
    """The table's last line on the digests."""
    if digests["same"]:
        return f"digests: identical ({digests['results'][:12]}): the same results, bit for bit"
    reasons = digests["reasons"]
    none = "none (same code, packages and code-generation target): a source of nondeterminism"
    why = "; ".join(reasons) if reasons else none
    return (
        f"digests differ ({digests['baseline'][:12]} -> {digests['results'][:12]}), which "
        f"these differences between the runs can explain: {why}. The verdicts above are the "
        "paired statistics, and stand whether or not the bytes agree"
        + ("" if reasons else "; please report it")
    )


def _field(data: Any, *keys: str) -> Any:
    """``data[k1][k2]...``, or None where a level is missing or not a JSON object."""
    for key in keys:
        if not isinstance(data, Mapping):
            return None
        data = data.get(key)
    return data


def _commit(data: Mapping[str, Any]) -> str | None:
    git = _field(data, "provenance", "git")
    git = git if isinstance(git, Mapping) else {}
    commit = git.get("commit")
    return f"{commit}{'+dirty' if git.get('dirty') else ''}" if commit else None


def _group_change(
    name: str, ids: list[str], base: Mapping[str, Any], new: Mapping[str, Any], tol: float,
    level: float,
) -> GroupChange:  # fmt: skip
    both = [i for i in ids if base[i]["status"] == "ok" and new[i]["status"] == "ok"]
    newly_failed = tuple(i for i in ids if base[i]["status"] == "ok" and new[i]["status"] != "ok")
    fixed = tuple(i for i in ids if base[i]["status"] != "ok" and new[i]["status"] == "ok")
    if both:
        b = np.array([base[i]["metrics"]["epsilon"] for i in both], dtype=np.float64)
        r = np.array([new[i]["metrics"]["epsilon"] for i in both], dtype=np.float64)
        d = r - b
        diff = float(d.mean())
        p_worse, p_better = _wilcoxon(d, "greater"), _wilcoxon(d, "less")
        base_mean, new_mean = float(b.mean()), float(r.mean())
    else:
        diff, p_worse, p_better, base_mean, new_mean = None, 1.0, 1.0, None, None
    if newly_failed or (diff is not None and diff > tol and p_worse < level):
        verdict = "worse"
    elif diff is not None and diff < -tol and p_better < level:
        verdict = "better"
    else:
        verdict = "same"
    return GroupChange(
        group=name, paired=len(both), baseline=base_mean, results=new_mean, difference=diff,
        p_worse=p_worse, p_better=p_better, newly_failed=newly_failed, fixed=fixed,
        verdict=verdict,
    )  # fmt: skip
