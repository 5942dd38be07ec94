"""The policy comparison's report: tables (CSV, Markdown), a plot (PNG) and the raw numbers
(JSON) of a :class:`hapticsim.envs.evaluation.Comparison`, and reading them back
(``scripts/compare_policies.py``, ``docs/policies/``)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim.data.io import write_text_atomic
from hapticsim.envs.evaluation import Comparison

#: Touch counts listed in the Markdown table.
TABLE_TOUCHES: tuple[int, ...] = (1, 2, 3, 5, 8, 10, 15, 20)
#: Plot style per policy.
POLICY_STYLE: dict[str, dict[str, Any]] = {
    "random": {"color": "tab:gray", "marker": "o"},
    "paper": {"color": "tab:green", "marker": "s"},
    "uncertainty": {"color": "tab:red", "marker": "^"},
    "learned": {"color": "tab:blue", "marker": "D"},
    "learned-touch": {"color": "tab:purple", "marker": "P"},
}


def load_comparison(path: str | Path) -> Comparison:
    """A comparison read back from the ``raw.json`` that :func:`write_comparison` wrote."""
    raw = json.loads(Path(path).read_text())
    episodes = tuple(raw["episodes"])
    policies = raw.get("policies") or list(dict.fromkeys(e["policy"] for e in episodes))
    objects = raw.get("object_sets") or list(dict.fromkeys(e["objects"] for e in episodes))
    budget = raw.get("budget") or raw["settings"]["touch_budget"]
    return Comparison(tuple(policies), tuple(objects), int(budget), episodes, raw["settings"])


def _markdown_table(cmp: Comparison, objects: str) -> str:
    touches = [n for n in TABLE_TOUCHES if n <= cmp.budget]
    head = "| N | " + " | ".join(f"{p} mean ± std (median)" for p in cmp.policies) + " |"
    lines = [head, "|---|" + "---|" * len(cmp.policies)]
    sums = {p: cmp.summary(p, objects) for p in cmp.policies}
    for n in touches:
        cells = [
            f"{sums[p]['mean'][n - 1]:.3f} ± {sums[p]['std'][n - 1]:.3f} "
            f"({sums[p]['median'][n - 1]:.3f})"
            for p in cmp.policies
        ]
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def write_comparison(
    cmp: Comparison, out_dir: str | Path, command: str = "python scripts/compare_policies.py"
) -> dict[str, Path]:
    """Write ``epsilon.csv``, ``README.md`` (tables + paired tests), ``epsilon.png``, ``raw.json``.

    Args:
        cmp: the comparison.
        out_dir: folder (created).
        command: the command that made it (quoted in the README).

    Returns:
        the paths written, by kind.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths: dict[str, Path] = {}

    rows = ["objects,policy,touches,episodes,mean,std,median,q25,q75"]
    for o in cmp.object_sets:
        for p in cmp.policies:
            s = cmp.summary(p, o)
            n_ep = len(cmp.epsilon(p, o))
            for n in range(cmp.budget):
                rows.append(
                    f"{o},{p},{n + 1},{n_ep},{s['mean'][n]:.5f},{s['std'][n]:.5f},"
                    f"{s['median'][n]:.5f},{s['q25'][n]:.5f},{s['q75'][n]:.5f}"
                )
    paths["csv"] = out / "epsilon.csv"
    write_text_atomic(paths["csv"], "\n".join(rows) + "\n")

    fig, axes = plt.subplots(
        1, len(cmp.object_sets), figsize=(5.2 * len(cmp.object_sets), 4.0), squeeze=False
    )
    x = np.arange(1, cmp.budget + 1)
    for ax, o in zip(axes[0], cmp.object_sets, strict=True):
        for p in cmp.policies:
            s = cmp.summary(p, o)
            style = POLICY_STYLE.get(p, {})
            ax.plot(x, s["mean"], label=f"{p} (mean)", markersize=4, **style)
            ax.fill_between(x, s["q25"], s["q75"], color=style.get("color"), alpha=0.15)
        n_ep = len(cmp.epsilon(cmp.policies[0], o))
        ax.set_title(f"objects: {o} ({n_ep} episodes)")
        ax.set_xlabel("touches N")
        ax.set_ylabel("epsilon = alpha + beta after N touches")
        ax.set_ylim(0.0, 1.05)
        ax.set_xticks(x[::2] if cmp.budget > 10 else x)
        ax.grid(alpha=0.3)
        ax.legend(title="shaded: quartiles", fontsize=8)
    fig.tight_layout()
    paths["png"] = out / "epsilon.png"
    fig.savefig(paths["png"], dpi=120)
    plt.close(fig)

    s = cmp.settings
    md = [
        "# Exploration policies on HapticExplore-v0",
        "",
        "Epsilon (alpha + beta, volume error of the current fit against the truth; 1 before the "
        "first fit) after N touches, mean ± standard deviation (median) over episodes. Every "
        "policy meets the same objects, noise and rough positions (seed per episode).",
        "",
        f"Settings: backend `{s['backend']}`, touch budget {s['touch_budget']}, sensor noise "
        f"sigma_N = {s['noise']}, rough-position noise {s['position_noise']} m, max stroke "
        f"{s['max_stroke']} m, contacts every {s['stroke_spacing']} m; fit schedule {s['fit']}; "
        f"root seed {s['seed']}. Plot: `epsilon.png`; all numbers: `epsilon.csv`, `raw.json`.",
        "",
        f"Made by `{command}`.",
    ]
    for o in cmp.object_sets:
        md += ["", f"## Objects: {o}", "", _markdown_table(cmp, o), ""]
        for policy, baseline in _paired(cmp.policies):
            md += [
                f"{policy} vs {baseline}, paired over the same objects (negative difference: "
                f"{policy} better; Wilcoxon signed-rank test):",
                "",
                f"| N | mean difference | {policy} better in | p-value |",
                "|---|---|---|---|",
            ]
            for n in sorted({5, 10, cmp.budget}):
                if n > cmp.budget:
                    continue
                t = cmp.paired_test(policy, baseline, o, n)
                md.append(
                    f"| {n} | {t['mean_difference']:+.3f} | {t['wins']}/{t['n']} | "
                    f"{t['p_value']:.3g} |"
                )
            md.append("")
    paths["md"] = out / "README.md"
    write_text_atomic(paths["md"], "\n".join(md) + "\n")
    paths["json"] = out / "raw.json"
    raw = {
        "settings": cmp.settings, "policies": list(cmp.policies),
        "object_sets": list(cmp.object_sets), "budget": cmp.budget,
        "episodes": list(cmp.episodes),
    }  # fmt: skip
    write_text_atomic(paths["json"], json.dumps(raw, default=_json_default) + "\n")
    return paths


def _paired(policies: Sequence[str]) -> list[tuple[str, str]]:
    """The pairs of the paired tests: every policy against random, learned ones against
    uncertainty too."""
    pairs = []
    if "random" in policies:
        pairs += [(p, "random") for p in policies if p != "random"]
    if "uncertainty" in policies:
        pairs += [(p, "uncertainty") for p in policies if p.startswith("learned")]
    return pairs


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, float) and not np.isfinite(value):
        return str(value)
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")
