"""Paper Fig. 4: the four bodies fitted by LS, H, nLS and nH at equal evaluation budgets.

150 contacts per body with sigma_N = 0.1 (paper Section IV), every method with the same budget
of EOF evaluations, repeated over ``runs`` data sets with fresh noise. Outputs a table of the
quality measures (mean and spread over runs) as CSV and Markdown, the per-run CSV, and a picture
grid like the paper's: rows bodies, columns data, LS, H, nLS, nH.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hapticsim._validate import positive_int
from hapticsim.constants import MAX_BUDGET
from hapticsim.data.bodies import BODY_NAMES, get_body
from hapticsim.data.io import write_text_atomic
from hapticsim.errors import InvalidInputError
from hapticsim.experiments._checks import check_bodies, check_common, check_noise
from hapticsim.experiments.plotting import plot_fig4
from hapticsim.experiments.stats import summarize
from hapticsim.experiments.tables import markdown_table, mean_spread, write_csv
from hapticsim.experiments.trial import METRICS, Trial, TrialResult, make_trial, run_trial
from hapticsim.geometry import Superquadric
from hapticsim.parallel import parallel_map

#: Columns of the Markdown table: (metric, header).
TABLE_COLUMNS: tuple[tuple[str, str], ...] = (
    ("theta", "θ"),
    ("alpha", "α"),
    ("beta", "β"),
    ("epsilon", "ε"),
    ("iou", "IoU"),
    ("chamfer", "Chamfer [mm]"),
    ("seconds", "time [s]"),
)


@dataclass(frozen=True)
class Fig4Config:
    """Settings of Fig. 4 (defaults: the paper's).

    Attributes:
        bodies: bodies, rows of the picture; None for all of ``BODY_NAMES``.
        methods: methods, columns of the picture.
        count: contacts per data set (paper: 150).
        noise: relative noise sigma_N (paper: 0.1).
        budget: EOF evaluations of every fit; None for ``fitting.methods.PAPER_BUDGET``.
        runs: data sets (fresh noise) per body.
        seed: root seed of the sweep.
    """

    bodies: tuple[str, ...] | None = None
    methods: tuple[str, ...] = ("LS", "H", "nLS", "nH")
    count: int = 150
    noise: float = 0.1
    budget: int | None = None
    runs: int = 10
    seed: int = 0

    def __post_init__(self) -> None:
        from hapticsim.fitting.methods import PAPER_BUDGET

        if self.bodies is None:
            object.__setattr__(self, "bodies", tuple(BODY_NAMES))
        if self.budget is None:
            object.__setattr__(self, "budget", int(PAPER_BUDGET))
        object.__setattr__(self, "bodies", tuple(self.bodies))
        object.__setattr__(self, "methods", tuple(self.methods))
        if not self.bodies:
            raise InvalidInputError("`bodies` must not be empty")
        check_bodies(self.bodies, "bodies")
        check_common(self.count, self.runs, self.seed, self.methods)
        check_noise(self.noise, "noise")
        positive_int(self.budget, "budget", maximum=MAX_BUDGET)

    def trials(self) -> list[Trial]:
        """The trials of the figure, body-major, then run, then method."""
        return [
            make_trial(body, method, self.noise, self.budget, self.count, run, self.seed)
            for body in self.bodies
            for run in range(self.runs)
            for method in self.methods
        ]


@dataclass(frozen=True)
class Fig4Result:
    """The trials of Fig. 4 and their results.

    Attributes:
        config: the settings.
        results: one :class:`TrialResult` per trial of ``config.trials()``, in that order.
    """

    config: Fig4Config
    results: tuple[TrialResult, ...]

    def rows(self) -> list[dict[str, Any]]:
        """Per-run CSV rows."""
        return [r.to_row() for r in self.results]

    def summary(self) -> list[dict[str, Any]]:
        """Mean, std and quartiles over runs per (body, method)."""
        return summarize(self.rows(), ("body", "method"), METRICS)

    def example(self, body: str, run: int = 0) -> dict[str, TrialResult]:
        """The results of one data set of `body`, by method (for the picture)."""
        return {
            r.trial.method: r for r in self.results if r.trial.body == body and r.trial.run == run
        }


def collect_fig4(config: Fig4Config, done: Mapping[Trial, TrialResult]) -> Fig4Result:
    """Pick the results of Fig. 4 out of `done` (results of a larger sweep)."""
    return Fig4Result(config, tuple(done[t] for t in config.trials()))


def run_fig4(
    config: Fig4Config | None = None, workers: int | None = None, progress: bool = True
) -> Fig4Result:
    """Run the trials of Fig. 4 in parallel.

    Args:
        config: settings; the paper's by default.
        workers: processes, default ``os.cpu_count()``.
        progress: tqdm bar on stderr.
    """
    config = config or Fig4Config()
    trials = config.trials()
    results = parallel_map(
        run_trial, trials, workers=workers, desc="fig4", progress=progress,
        cost=lambda t: t.budget, names=lambda t: t.label, unit="fit",
    )  # fmt: skip
    return collect_fig4(config, dict(zip(trials, results, strict=True)))


def fig4_markdown(summary: Sequence[dict[str, Any]]) -> str:
    """The Fig. 4 table in Markdown: mean ± standard deviation over runs."""
    body = []
    for row in summary:
        scaled = dict(row)
        for stat in ("mean", "std"):
            scaled[f"chamfer_{stat}"] = 1000.0 * row[f"chamfer_{stat}"]
        body.append(
            [row["body"], row["method"]] + [mean_spread(scaled, m) for m, _ in TABLE_COLUMNS]
        )
    return markdown_table(["body", "method"] + [h for _, h in TABLE_COLUMNS], body)


def write_fig4(result: Fig4Result, out_dir: str | Path) -> dict[str, Path]:
    """Write the Fig. 4 table (CSV, Markdown), the per-run CSV and the picture grid.

    Returns:
        dict of the written files: ``runs_csv``, ``table_csv``, ``table_md``, ``figure``.
    """

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary = result.summary()
    files = {
        "runs_csv": write_csv(out / "fig4_runs.csv", result.rows()),
        "table_csv": write_csv(out / "fig4_table.csv", summary),
        "table_md": write_text_atomic(out / "fig4_table.md", fig4_markdown(summary)),
    }
    cfg = result.config
    examples = {body: result.example(body) for body in cfg.bodies}
    files["figure"] = plot_fig4(
        truths={body: get_body(body) for body in cfg.bodies},
        contacts={
            body: (ex[cfg.methods[0]].points, ex[cfg.methods[0]].normals)
            for body, ex in examples.items()
        },
        estimates={
            (body, m): Superquadric.from_dict(r.estimate)
            for body, ex in examples.items()
            for m, r in ex.items()
        },
        epsilons={(body, m): r.epsilon for body, ex in examples.items() for m, r in ex.items()},
        methods=cfg.methods,
        path=out / "fig4.png",
        title=(
            f"Fig. 4 reproduced: {cfg.count} contacts, σ_N = {cfg.noise:g}, "
            f"budget {cfg.budget} EOF evaluations per method (run 0 of {cfg.runs})"
        ),
    )
    return files
