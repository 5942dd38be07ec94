"""Paper Fig. 5: quality against the evaluation budget n (cylinder) and against noise (cube).

Every point of a curve is the mean over ``runs`` data sets with the noise drawn afresh each run
(paper Section IV), all four methods. A point at budget n is a fit *run with budget n* — not the
prefix of a longer fit — because the methods split their budget (GA generations, then least
squares) by the budget they are given; the fits of one run at growing n share their data and
their random seed. Theta and epsilon come from the estimate of that fit. The Chamfer distance is
not computed here (it would double the scoring time); the per-run CSV shows NaN for it, except
for settings shared with Fig. 4.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hapticsim._validate import positive_int
from hapticsim.constants import MAX_BUDGET
from hapticsim.errors import InvalidInputError
from hapticsim.experiments._checks import check_bodies, check_common, check_noise
from hapticsim.experiments.plotting import plot_fig5
from hapticsim.experiments.stats import summarize
from hapticsim.experiments.tables import write_csv
from hapticsim.experiments.trial import METRICS, Trial, TrialResult, make_trial, run_trial
from hapticsim.parallel import parallel_map

#: Budgets of the n sweep as fractions of ``PAPER_BUDGET`` (geometric grid, factor 2). The
#: small budgets are cheap and show where each method converges; the largest is Fig. 4's.
BUDGET_FRACTIONS: tuple[float, ...] = tuple(2.0**-k for k in range(7, -1, -1))
#: Measures summarised along the sweeps (the Chamfer distance is left out: Fig. 4 only).
FIG5_METRICS: tuple[str, ...] = tuple(m for m in METRICS if m != "chamfer")
#: Noise levels sigma_N of the noise sweep (log grid around the paper's 0.1).
NOISE_LEVELS: tuple[float, ...] = (0.01, 0.03, 0.1, 0.3)


@dataclass(frozen=True)
class Fig5Config:
    """Settings of Fig. 5 (defaults: the paper's bodies, 150 contacts).

    Attributes:
        methods: methods drawn.
        count: contacts per data set.
        runs: data sets (fresh noise) per point.
        seed: root seed.
        budget_body: body of the n sweep (paper: cylinder).
        budgets: budgets n of the n sweep, increasing; None for
            ``BUDGET_FRACTIONS * PAPER_BUDGET``.
        budget_noise: sigma_N of the n sweep (paper: 0.1).
        noise_body: body of the noise sweep (paper: cube).
        noises: sigma_N of the noise sweep, increasing, > 0 (log axis).
        noise_budget: budget of the noise sweep; None for ``PAPER_BUDGET``.
    """

    methods: tuple[str, ...] = ("LS", "H", "nLS", "nH")
    count: int = 150
    runs: int = 10
    seed: int = 0
    budget_body: str = "cylinder"
    budgets: tuple[int, ...] | None = None
    budget_noise: float = 0.1
    noise_body: str = "cube"
    noises: tuple[float, ...] = NOISE_LEVELS
    noise_budget: int | None = None

    def __post_init__(self) -> None:
        from hapticsim.fitting.methods import PAPER_BUDGET

        if self.budgets is None:
            budgets = tuple(max(1, round(f * PAPER_BUDGET)) for f in BUDGET_FRACTIONS)
            object.__setattr__(self, "budgets", budgets)
        if self.noise_budget is None:
            object.__setattr__(self, "noise_budget", int(PAPER_BUDGET))
        object.__setattr__(self, "methods", tuple(self.methods))
        object.__setattr__(self, "budgets", tuple(self.budgets))
        object.__setattr__(self, "noises", tuple(self.noises))
        check_common(self.count, self.runs, self.seed, self.methods)
        check_bodies((self.budget_body, self.noise_body), "budget_body/noise_body")
        check_noise(self.budget_noise, "budget_noise")
        positive_int(self.noise_budget, "noise_budget", maximum=MAX_BUDGET)
        if not self.budgets or not self.noises:
            raise InvalidInputError("`budgets` and `noises` must not be empty")
        for b in self.budgets:
            positive_int(b, "budgets", maximum=MAX_BUDGET)
        for s in self.noises:
            check_noise(s, "noises")
            if s <= 0:
                raise InvalidInputError(f"`noises` must be > 0 (log axis), got {s}")
        for name, grid in (("budgets", self.budgets), ("noises", self.noises)):
            if list(grid) != sorted(set(grid)):
                raise InvalidInputError(f"`{name}` must be strictly increasing, got {grid}")

    def budget_trials(self) -> list[Trial]:
        """Trials of the n sweep: run, method, budget."""
        return [
            make_trial(
                self.budget_body,
                method,
                self.budget_noise,
                budget,
                self.count,
                run,
                self.seed,
                chamfer=False,
            )
            for run in range(self.runs)
            for method in self.methods
            for budget in self.budgets
        ]

    def noise_trials(self) -> list[Trial]:
        """Trials of the noise sweep: run, method, noise."""
        return [
            make_trial(
                self.noise_body,
                method,
                noise,
                self.noise_budget,
                self.count,
                run,
                self.seed,
                chamfer=False,
            )
            for run in range(self.runs)
            for method in self.methods
            for noise in self.noises
        ]

    def trials(self) -> list[Trial]:
        """All trials of the figure (n sweep, then noise sweep)."""
        return self.budget_trials() + self.noise_trials()


@dataclass(frozen=True)
class Fig5Result:
    """Results of the two sweeps of Fig. 5, each in the order of its trials."""

    config: Fig5Config
    budget_results: tuple[TrialResult, ...]
    noise_results: tuple[TrialResult, ...]

    def rows(self) -> list[dict[str, Any]]:
        """Per-run CSV rows of both sweeps, with a ``sweep`` column (``budget`` or ``noise``)."""
        return [{"sweep": "budget", **r.to_row()} for r in self.budget_results] + [
            {"sweep": "noise", **r.to_row()} for r in self.noise_results
        ]

    def by_budget(self) -> list[dict[str, Any]]:
        """Summary of the n sweep per (method, budget)."""
        rows = [r.to_row() for r in self.budget_results]
        return summarize(rows, ("body", "noise", "method", "budget"), FIG5_METRICS)

    def by_noise(self) -> list[dict[str, Any]]:
        """Summary of the noise sweep per (method, noise)."""
        rows = [r.to_row() for r in self.noise_results]
        return summarize(rows, ("body", "budget", "method", "noise"), FIG5_METRICS)


def collect_fig5(config: Fig5Config, done: Mapping[Trial, TrialResult]) -> Fig5Result:
    """Pick the results of Fig. 5 out of `done` (results of a larger sweep)."""
    return Fig5Result(
        config,
        tuple(done[t] for t in config.budget_trials()),
        tuple(done[t] for t in config.noise_trials()),
    )


def run_fig5(
    config: Fig5Config | None = None, workers: int | None = None, progress: bool = True
) -> Fig5Result:
    """Run the trials of Fig. 5 in parallel (see :func:`~hapticsim.experiments.fig4.run_fig4`)."""
    config = config or Fig5Config()
    trials = list(dict.fromkeys(config.trials()))
    results = parallel_map(
        run_trial, trials, workers=workers, desc="fig5", progress=progress,
        cost=lambda t: t.budget, names=lambda t: t.label, unit="fit",
    )  # fmt: skip
    return collect_fig5(config, dict(zip(trials, results, strict=True)))


def write_fig5(result: Fig5Result, out_dir: str | Path) -> dict[str, Path]:
    """Write the per-run CSV, the curve CSV (mean, std, quartiles) and the Fig. 5 picture.

    Returns:
        dict of the written files: ``runs_csv``, ``curves_csv``, ``figure``.
    """

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cfg = result.config
    by_budget, by_noise = result.by_budget(), result.by_noise()
    curves = [{"sweep": "budget", **r} for r in by_budget] + [
        {"sweep": "noise", **r} for r in by_noise
    ]
    columns = ["sweep", "body", "method", "budget", "noise", "runs"] + [
        k for k in curves[0] if k not in ("sweep", "body", "method", "budget", "noise", "runs")
    ]
    return {
        "runs_csv": write_csv(out / "fig5_runs.csv", result.rows()),
        "curves_csv": write_csv(out / "fig5_curves.csv", curves, columns),
        "figure": plot_fig5(
            by_budget, by_noise, cfg.methods, out / "fig5.png",
            budget_body=cfg.budget_body, noise_body=cfg.noise_body, runs=cfg.runs,
            noise_budget=cfg.noise_budget, budget_noise=cfg.budget_noise,
        ),
    }  # fmt: skip
