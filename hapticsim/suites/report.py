"""Markdown summaries of suite results (``docs/suites/README.md``)."""

from __future__ import annotations

from typing import Any

#: Columns of a group table: (metric, header, scale).
COLUMNS: tuple[tuple[str, str, float], ...] = (
    ("epsilon", "ε mean", 1.0),
    ("alpha", "α mean", 1.0),
    ("beta", "β mean", 1.0),
    ("iou", "IoU mean", 1.0),
    ("chamfer", "Chamfer [mm]", 1000.0),
)


def _cell(value: float | None, scale: float) -> str:
    return "–" if value is None else f"{scale * value:.3f}"


def results_markdown(results: dict[str, Any], command: str) -> str:
    """A section on one results file: what ran, how long, and a table per group.

    Args:
        results: a results file's content (:func:`hapticsim.suites.run_suite`).
        command: the command that made it.
    """
    suite, summary, prov = results["suite"], results["summary"], results["provenance"]
    git = prov.get("git") or {}
    commit = (git.get("commit") or "?")[:10] + (
        " (uncommitted changes)" if git.get("dirty") else ""
    )
    load = (summary.get("load_average") or {}).get("start")
    cpu = summary.get("cpu_seconds")
    cpu_text = "" if cpu is None else f", {cpu:.0f} s of CPU in the cases"
    lines = [
        f"## {suite['id']}",
        "",
        suite["description"],
        "",
        f"{summary['cases']} cases ({summary['failed']} failed) in {summary['seconds']:.0f} s"
        f"{cpu_text} on {prov['engine']['engine']} with {prov['engine']['workers']} workers "
        f"({prov['machine']['cores']} cores, load average {load} at the start); hapticsim "
        f"{prov['hapticsim']}, commit {commit}. Made by `{command}`.",
        "",
        "| group | cases | failed | ε median | " + " | ".join(h for _, h, _ in COLUMNS) + " |",
        "|---|---|---|---|" + "---|" * len(COLUMNS),
    ]
    for name, group in results["groups"].items():
        cells = [_cell(group["mean"][m], s) for m, _, s in COLUMNS]
        lines.append(
            f"| {name} | {group['cases']} | {group['failed']} | "
            f"{_cell(group['median']['epsilon'], 1.0)} | " + " | ".join(cells) + " |"
        )
    return "\n".join(lines) + "\n"
