"""``hapticsim bench report``: a leaderboard of results files, per task, with paired tests.

For each task, every results file is a row: the policy and estimator, the area under the touch
curve of IoU, F-score at 2.5 mm, epsilon and Chamfer [mm] (mean and 95 % interval), and the
final touch's IoU. Rows of one task are compared with its first file (the baseline) by a
two-sided Wilcoxon signed-rank test of the IoU areas on the seeds both ran (paired). Written as
Markdown (``leaderboard.md``) and as a page (``index.html``) with the mean IoU curves.
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim.errors import InvalidInputError

#: Columns of the leaderboard: (metric, heading).
COLUMNS: tuple[tuple[str, str], ...] = (
    ("iou", "IoU area"), ("f_score_2.5", "F@2.5 mm area"), ("epsilon", "epsilon area"),
    ("chamfer_mm", "Chamfer area [mm]"),
)  # fmt: skip


def load(path: str | Path) -> dict[str, Any]:
    """A results file of ``hapticsim bench run`` (one line of error otherwise)."""
    p = Path(path)
    try:
        data = json.loads(p.read_text())
    except (OSError, ValueError) as exc:
        raise InvalidInputError(f"cannot read bench results {p}: {exc}") from None
    if not isinstance(data, dict) or "protocol" not in data or "summary" not in data:
        raise InvalidInputError(f"{p} is not a results file of `hapticsim bench run`")
    return data


def _cell(summary: dict[str, Any], metric: str) -> str:
    s = summary[metric]
    if s["area_mean"] is None:
        return "-"
    ci = s["area_ci95"]
    return f"{s['area_mean']:.3f}" + ("" if ci is None else f" ({ci[0]:.3f}-{ci[1]:.3f})")


def _areas_on(result: dict[str, Any], touches: list[int]) -> dict[int, float]:
    """Each episode's IoU area over the given touches (1-based), by seed; episodes with a touch
    unscored among them are left out."""
    out = {}
    for episode in result["episodes"]:
        values = [episode["touches"][t - 1]["iou"] for t in touches
                  if t <= len(episode["touches"])]  # fmt: skip
        if values and all(v is not None for v in values):
            out[episode["seed"]] = float(np.mean(values))
    return out


def _paired_p(base: dict[str, Any], other: dict[str, Any]) -> tuple[float | None, int]:
    """Wilcoxon's signed-rank test of two results' IoU areas on their common seeds, over the
    touches both scored (all of them for two environment estimators)."""
    from scipy.stats import wilcoxon

    touches = sorted(set(_scored(base)) & set(_scored(other)))
    a, b = _areas_on(base, touches), _areas_on(other, touches)
    common = [s for s in a if s in b]
    if len(common) < 2:
        return None, len(common)
    d = np.array([b[s] - a[s] for s in common])
    return (1.0 if not np.any(d) else float(wilcoxon(d).pvalue)), len(common)


def _scored(result: dict[str, Any]) -> list[int]:
    """The touches a results file scored (every touch in files made before they said)."""
    return result.get("scored_touches") or list(range(1, result["task"]["touches"] + 1))


def _final(result: dict[str, Any]) -> float | None:
    """The mean IoU at the last touch scored."""
    scored = [v for v in result["summary"]["iou"]["mean_curve"] if v is not None]
    return scored[-1] if scored else None


def leaderboard(results: list[dict[str, Any]]) -> str:
    """The Markdown leaderboard (module docstring)."""
    by_task: dict[str, list[dict[str, Any]]] = {}
    for r in results:
        by_task.setdefault(r["task"]["name"], []).append(r)
    lines = [f"# Leaderboard ({results[0]['protocol']})", ""]
    for task, rows in by_task.items():
        lines += [f"## {task}", "",
                  "| policy | estimator | split | episodes | "
                  + " | ".join(h for _, h in COLUMNS)
                  + " | final IoU | vs first row: p (paired, n) |",
                  "|" + "---|" * (len(COLUMNS) + 6)]  # fmt: skip
        for i, r in enumerate(rows):
            final = _final(r)
            p, n = _paired_p(rows[0], r) if i else (None, 0)
            vs = "baseline" if i == 0 else ("-" if p is None else f"{p:.3g} ({n})")
            cells = " | ".join(_cell(r["summary"], m) for m, _ in COLUMNS)
            scored = _scored(r)
            estimator = r["estimator"] + (
                "" if len(scored) == r["task"]["touches"]
                else f" (at {', '.join(map(str, scored))})"
            )
            shown = "-" if final is None else f"{final:.3f}"
            lines.append(f"| {r['policy']} | {estimator} | {r['split']} | "
                         f"{len(r['seeds'])} | {cells} | {shown} | {vs} |")  # fmt: skip
        lines.append("")
    lines.append("Areas: the mean over touches 1..T of each episode's curve (over the touches "
                 "named where an estimator is scored at some only), averaged over episodes "
                 "(95 % t interval); higher is better for IoU and F-score, lower for epsilon and "
                 "Chamfer. The paired test compares IoU areas over the touches both rows scored."
                 )  # fmt: skip
    return "\n".join(lines) + "\n"


def _curves_svg(rows: list[dict[str, Any]], task: str) -> str:
    """The task's mean IoU curves as an SVG drawing (text: a board of many tasks stays small
    in the repository, where PNGs in base64 were half a megabyte)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.5))
    for r in rows:
        curve = r["summary"]["iou"]["mean_curve"]
        shown = [(t, v) for t, v in enumerate(curve, start=1) if v is not None]
        ax.plot([t for t, _ in shown], [v for _, v in shown], marker="o", ms=3,
                label=f"{r['policy']} ({r['estimator']})")  # fmt: skip
    ax.set_xlabel("touches")
    ax.set_ylabel("mean IoU")
    ax.set_title(task)
    ax.legend(fontsize=8)
    buf = io.StringIO()
    fig.tight_layout()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "hapticsim"}):
        fig.savefig(buf, format="svg", metadata={"Date": None})
    plt.close(fig)
    text = buf.getvalue()
    return text[text.index("<svg"):]  # the drawing alone, inline in the page


def write_report(paths: list[str | Path], out: str | Path) -> dict[str, Path]:
    """Write ``leaderboard.md`` and ``index.html`` in `out` (all or none)."""
    from hapticsim._files import OutputSet, write_text_atomic

    if not paths:
        raise InvalidInputError("give at least one results file")
    results = [load(p) for p in paths]
    text = leaderboard(results)
    by_task: dict[str, list[dict[str, Any]]] = {}
    for r in results:
        by_task.setdefault(r["task"]["name"], []).append(r)
    import html as _html

    body = [f"<pre>{_html.escape(text)}</pre>"]
    for task, rows in by_task.items():
        body.append(f"<h2>{_html.escape(task)}</h2>{_curves_svg(rows, task)}")
    page = ("<!doctype html><meta charset='utf-8'><title>hapticsim leaderboard</title>"
            + "".join(body))  # fmt: skip
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    with OutputSet():
        files = {"markdown": write_text_atomic(folder / "leaderboard.md", text),
                 "html": write_text_atomic(folder / "index.html", page)}  # fmt: skip
    return files


__all__ = ["leaderboard", "load", "write_report"]
