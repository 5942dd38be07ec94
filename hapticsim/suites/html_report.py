"""An HTML page of one suite run, against a baseline when given (``hapticsim suite report``).

:func:`write_report` writes into a directory ``index.html`` and one picture per group:

- the run: suite, commit, machine and code-generation targets, cases, failures, time;
- with a baseline, the comparison of :func:`~hapticsim.suites.compare_results` (mean epsilon
  before and after per group, change, paired Wilcoxon p, verdict, regressions in red) and the
  line on the digests (bit-identical or what differs between the runs);
- the group table (cases, failures, epsilon median and mean, alpha, beta, IoU, Chamfer);
- per group, the distribution of epsilon over its cases (results and baseline side by side)
  and, with a baseline, each case's epsilon in the results against the baseline's.

The page reads offline (plain HTML, pictures beside it); every file is written atomically, all
of them or none.
"""

from __future__ import annotations

import html
import io
import re
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim._files import OutputSet, write_bytes_atomic, write_text_atomic
from hapticsim.suites.compare import compare_results, load_results
from hapticsim.suites.report import COLUMNS

#: Colours of the results and the baseline in the pictures.
RESULTS_COLOR, BASELINE_COLOR = "tab:orange", "tab:blue"

_STYLE = """
body { font-family: -apple-system, Segoe UI, Roboto, Helvetica, Arial, sans-serif; margin: 2em;
       max-width: 72em; color: #222; }
table { border-collapse: collapse; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
tr.worse td { background: #fde0dc; } tr.better td { background: #e3f6e3; }
.groups { display: flex; flex-wrap: wrap; gap: 1em; }
.groups figure { margin: 0; } .groups img { width: 26em; }
code { background: #f4f4f4; padding: 0 0.2em; }
"""


def _epsilons(data: dict[str, Any]) -> dict[str, dict[str, float]]:
    """Group -> case id -> epsilon, of the cases that passed."""
    out: dict[str, dict[str, float]] = {}
    for case in data["cases"]:
        if case["status"] == "ok":
            out.setdefault(case["group"], {})[case["id"]] = float(case["metrics"]["epsilon"])
    return out


def _slug(name: str, k: int) -> str:
    return f"group{k:02d}-" + re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")[:40] + ".png"


def _group_png(name: str, results: dict[str, float], baseline: dict[str, float] | None) -> bytes:
    """The picture of one group: epsilon's distribution, and the paired cases when compared."""
    import matplotlib

    matplotlib.use("Agg", force=False)  # as the other figure writers: a chosen backend stays

    from matplotlib.figure import Figure

    paired = baseline is not None
    fig = Figure(figsize=(8.0 if paired else 4.5, 3.4), dpi=110)
    axes = fig.subplots(1, 2 if paired else 1, squeeze=False)[0]
    series = [("results", results, RESULTS_COLOR)]
    if paired:
        series.insert(0, ("baseline", baseline, BASELINE_COLOR))
    ax = axes[0]
    values = [np.array(list(s[1].values())) for s in series]
    box = ax.boxplot(values, tick_labels=[s[0] for s in series], patch_artist=True, widths=0.5)
    for patch, (_, _, color) in zip(box["boxes"], series, strict=True):
        patch.set_facecolor(color)
        patch.set_alpha(0.35)
    rng = np.random.default_rng(0)  # a fixed jitter: the same page for the same files
    for k, (v, (_, _, color)) in enumerate(zip(values, series, strict=True)):
        ax.plot(k + 1 + rng.uniform(-0.12, 0.12, len(v)), v, "o", ms=3, color=color)
    ax.set_ylabel("epsilon")
    ax.set_title(f"{name}: epsilon per case", fontsize=9)
    if paired:
        ids = sorted(set(results) & set(baseline))
        b = np.array([baseline[i] for i in ids])
        r = np.array([results[i] for i in ids])
        ax = axes[1]
        top = max(float(np.max(b, initial=0.0)), float(np.max(r, initial=0.0)), 1e-3) * 1.05
        ax.plot([0, top], [0, top], color="0.6", lw=0.8)
        ax.plot(b, r, "o", ms=3.5, color=RESULTS_COLOR)
        ax.set_xlim(0, top)
        ax.set_ylim(0, top)
        ax.set_xlabel("baseline epsilon")
        ax.set_ylabel("results epsilon")
        ax.set_title(f"{len(ids)} paired cases (above the line: worse)", fontsize=9)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()


def _table(head: list[str], rows: list[tuple[str, list[str]]]) -> str:
    cells = "".join(f"<th>{html.escape(h)}</th>" for h in head)
    body = "".join(
        f"<tr class='{cls}'>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>"
        for cls, row in rows
    )
    return f"<table><tr>{cells}</tr>{body}</table>"


def _fmt(value: float | None, scale: float = 1.0, signed: bool = False) -> str:
    if value is None:
        return "–"
    return f"{scale * value:+.4f}" if signed else f"{scale * value:.4f}"


def report_html(results: dict[str, Any], pictures: dict[str, str], comparison: Any = None) -> str:
    """The page's HTML (:func:`write_report`); `pictures`: group -> picture file name;
    `comparison`: against the baseline, or None."""
    suite, summary, prov = results["suite"], results["summary"], results["provenance"]
    git = prov.get("git") or {}
    machine = prov.get("machine") or {}
    codegen = machine.get("codegen") or {}
    esc = html.escape
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>suite {esc(suite['id'])}: hapticsim report</title><style>{_STYLE}</style>",
        "</head><body>",
        f"<h1>Suite {esc(suite['id'])}</h1><p>{esc(suite.get('description', ''))}</p>",
        f"<p>{summary['cases']} cases, {summary['failed']} failed, {summary['seconds']:.0f} s; "
        f"commit <code>{esc((git.get('commit') or '?')[:10])}</code>"
        f"{' (uncommitted changes)' if git.get('dirty') else ''}; {esc(str(machine.get('cpu')))}"
        f", {machine.get('cores')} cores; "
        + (f"numba target {esc(str(codegen.get('numba_cpu')))}, numpy "
           f"{esc(str(codegen.get('numpy_simd')))}, {esc(str(codegen.get('blas')))}.</p>"
           if codegen else "code-generation targets not recorded.</p>"),
    ]
    if comparison is not None:
        rows = []
        for g in comparison.groups:
            p = g.p_worse if (g.difference or 0.0) >= 0 else g.p_better
            note = f" ({len(g.newly_failed)} now fail)" if g.newly_failed else ""
            rows.append((g.verdict, [
                g.group, str(g.paired), _fmt(g.baseline), _fmt(g.results),
                _fmt(g.difference, signed=True), f"{p:.2g}", g.verdict + note,
            ]))  # fmt: skip
        verdict = (
            f"REGRESSION in {len(comparison.regressions)} group(s): "
            f"{', '.join(comparison.regressions)}" if comparison.regressions else "no regression"
        )  # fmt: skip
        parts += [
            "<h2>Against the baseline</h2>",
            f"<p>Baseline commit <code>{esc((comparison.baseline_commit or '?')[:10])}</code>; a "
            f"group regresses if its mean epsilon rises by more than {comparison.tolerance:g} "
            f"with a paired Wilcoxon p below {comparison.alpha:g}. <b>{esc(verdict)}</b>.</p>",
            _table(["group", "paired", "baseline ε", "results ε", "change", "p", "verdict"],
                   rows),  # fmt: skip
        ]
        digests = comparison.digests or {}
        if digests:
            same = digests.get("same")
            why = "; ".join(digests.get("reasons") or []) or "no recorded difference explains it"
            parts.append(
                "<p>Digests: identical (bit for bit).</p>" if same
                else f"<p>Digests differ: {esc(why)}.</p>"
            )  # fmt: skip
    rows = []
    for name, group in results["groups"].items():
        rows.append(("", [name, str(group["cases"]), str(group["failed"]),
                          _fmt(group["median"]["epsilon"])]
                     + [_fmt(group["mean"][m], s) for m, _, s in COLUMNS]))  # fmt: skip
    parts += [
        "<h2>Groups</h2>",
        _table(["group", "cases", "failed", "ε median"] + [h for _, h, _ in COLUMNS], rows),
        "<h2>Epsilon per group</h2><div class='groups'>",
    ]
    for name, file in pictures.items():
        parts.append(f"<figure><img src='{esc(file)}' alt='epsilon of {esc(name)}'></figure>")
    parts.append("</div></body></html>")
    return "\n".join(parts)


def write_report(
    results: str | Path | dict[str, Any], out_dir: str | Path,
    baseline: str | Path | dict[str, Any] | None = None, tolerance: float | None = None,
    alpha: float | None = None,
) -> Path:  # fmt: skip
    """Write the report of `results` (against `baseline`) into `out_dir` (module docstring).

    Returns:
        The path of ``index.html``.

    Raises:
        InvalidInputError: a file that is not suite results, or results of another suite than
            the baseline's.
    """

    new = load_results(results, "results")
    base = load_results(baseline, "baseline") if baseline is not None else None
    options = {k: v for k, v in (("tolerance", tolerance), ("alpha", alpha)) if v is not None}
    comparison = compare_results(base, new, **options) if base is not None else None
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    eps_new = _epsilons(new)
    eps_base = _epsilons(base) if base is not None else None
    pictures = {}
    images = {}
    for k, name in enumerate(new["groups"]):
        file = _slug(name, k)
        pictures[name] = file
        images[file] = _group_png(name, eps_new.get(name, {}),
                                  None if eps_base is None else eps_base.get(name, {}))  # fmt: skip
    page = report_html(new, pictures, comparison)
    with OutputSet():
        for file, data in images.items():
            write_bytes_atomic(out / file, data)
        index = write_text_atomic(out / "index.html", page)
    return index


__all__ = ["report_html", "write_report"]
