"""``hapticsim reproduce``: regenerate the paper's Fig. 4 and Fig. 5 with tables and claims.

All trials of the requested figures are run in one sweep on local processes or a Dask cluster
(:mod:`hapticsim.parallel`; a setting shared by both figures, e.g. the cylinder at the default
budget, is fitted once), then tables, pictures, the claim checks and optionally ``RESULTS.md``
are written.
"""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path
from typing import Any

from hapticsim._files import OutputSet, atomic_write
from hapticsim.data.io import write_json
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.experiments.claims import check_claims
from hapticsim.experiments.fig4 import Fig4Config, Fig4Result, collect_fig4, write_fig4
from hapticsim.experiments.fig5 import Fig5Config, collect_fig5, write_fig5
from hapticsim.experiments.report import write_results
from hapticsim.experiments.trial import METRICS, run_trial
from hapticsim.parallel import parallel_map, resolve_workers

WHICH: tuple[str, ...] = ("fig4", "fig5", "all")


def reproduce(
    which: str,
    out_dir: str | Path = "runs/reproduce",
    runs: int = 10,
    seed: int = 0,
    workers: int | None = None,
    *,
    budget: int | None = None,
    budgets: tuple[int, ...] | None = None,
    noises: tuple[float, ...] | None = None,
    results: str | Path | None = None,
    figures_dir: str | Path | None = None,
    progress: bool = True,
    scheduler: str | None = None,
) -> dict[str, Any]:
    """Run the paper's evaluation and write its tables, figures and claim checks.

    Args:
        which: ``"fig4"``, ``"fig5"`` or ``"all"``.
        out_dir: directory for CSV, Markdown, PNG and ``summary.json`` (created).
        runs: data sets (fresh noise) per setting, >= 1.
        seed: root seed, >= 0; every trial's seed derives from it and the trial's settings.
        workers: processes, default ``os.cpu_count()``; results do not depend on it.
        budget: budget of Fig. 4 and of the noise sweep; default ``PAPER_BUDGET``.
        budgets: budgets of the n sweep; default fractions of ``PAPER_BUDGET``.
        noises: sigma_N of the noise sweep; default :data:`fig5.NOISE_LEVELS`.
        results: also write this Markdown report (e.g. ``RESULTS.md``), with the pictures
            copied to `figures_dir`.
        figures_dir: where the report's pictures go; default ``docs/figures`` beside `results`.
        progress: tqdm bar on stderr.
        scheduler: run the trials on a Dask cluster instead of local processes
            (``tcp://host:port`` or ``local:N``); the results are the same.

    Returns:
        JSON-ready summary: settings, run time, files, the Fig. 4 means and the claim verdicts.

    Raises:
        InvalidInputError: unknown `which`, runs < 1, seed < 0, workers < 1, bad grids.
    """
    if which not in WHICH:
        raise ChoiceError("which", which, WHICH)
    n_workers = resolve_workers(workers) if scheduler is None else None
    fig4_cfg = Fig4Config(runs=runs, seed=seed, budget=budget) if which != "fig5" else None
    fig5_cfg = None
    if which != "fig4":
        extra: dict[str, Any] = {} if noises is None else {"noises": tuple(noises)}
        fig5_cfg = Fig5Config(runs=runs, seed=seed, budgets=budgets, noise_budget=budget, **extra)
    out = Path(out_dir)
    if results is not None and Path(results).is_dir():  # found out now, not after the sweep
        raise InvalidInputError(f"cannot write {results}: it is a directory")
    out.mkdir(parents=True, exist_ok=True)

    start, cpu_start = time.perf_counter(), _cpu_seconds()
    trials = list(
        dict.fromkeys(
            (fig4_cfg.trials() if fig4_cfg else []) + (fig5_cfg.trials() if fig5_cfg else [])
        )
    )
    results_list = parallel_map(
        run_trial, trials, workers=n_workers, desc=f"reproduce {which}", progress=progress,
        cost=lambda t: t.budget, names=lambda t: t.label, unit="fit", scheduler=scheduler,
    )  # fmt: skip
    done = dict(zip(trials, results_list, strict=True))
    sweep_seconds = time.perf_counter() - start

    with OutputSet() as outputs:  # all files or none, even on Ctrl-C
        return _write_outputs(
            outputs, which, out, runs, seed, n_workers, scheduler, trials, fig4_cfg, fig5_cfg,
            done, start, cpu_start, sweep_seconds, results, figures_dir,
        )  # fmt: skip


def _write_outputs(
    outputs: OutputSet, which: str, out: Path, runs: int, seed: int, n_workers: int | None,
    scheduler: str | None, trials: list[Any], fig4_cfg: Any, fig5_cfg: Any, done: dict,
    start: float, cpu_start: float, sweep_seconds: float, results: str | Path | None,
    figures_dir: str | Path | None,
) -> dict[str, Any]:  # fmt: skip
    """Tables, pictures, claims, the report and ``summary.json``; returns the summary."""
    files: dict[str, Path] = {}
    fig4 = collect_fig4(fig4_cfg, done) if fig4_cfg else None
    fig5 = collect_fig5(fig5_cfg, done) if fig5_cfg else None
    if fig4:
        files.update({f"fig4_{k}": v for k, v in write_fig4(fig4, out).items()})
    if fig5:
        files.update({f"fig5_{k}": v for k, v in write_fig5(fig5, out).items()})
    claims = check_claims(
        fig4_rows=fig4.rows() if fig4 else None,
        budget_rows=[r.to_row() for r in fig5.budget_results] if fig5 else None,
        by_budget=fig5.by_budget() if fig5 else None,
        noise_rows=[r.to_row() for r in fig5.noise_results] if fig5 else None,
        by_noise=fig5.by_noise() if fig5 else None,
    )
    seconds = time.perf_counter() - start
    cpu_seconds = _cpu_seconds() - cpu_start
    summary: dict[str, Any] = {
        "which": which,
        "out_dir": str(out),
        "runs": runs,
        "seed": seed,
        "workers": n_workers,
        "scheduler": scheduler,
        "trials": len(trials),
        "seconds": round(seconds, 1),
        "sweep_seconds": round(sweep_seconds, 1),
        "cpu_seconds": round(cpu_seconds, 1),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}",
        "volume_method": (fig4.results if fig4 else fig5.budget_results)[0].volume_method,
        "fig4": _fig4_means(fig4) if fig4 else None,
        "claims": [{"statement": c.statement, "verdict": c.verdict} for c in claims],
    }
    if results is not None:

        files["results"] = write_results(
            results, fig4=fig4, fig5=fig5, claims=claims, summary=summary,
            figures=_copy_figures(outputs, files, results, figures_dir),
        )  # fmt: skip
    summary["files"] = {k: str(v) for k, v in files.items()}

    write_json(out / "summary.json", {**summary, "claims": [c.to_dict() for c in claims]})
    summary["files"]["summary"] = str(out / "summary.json")
    return summary


def _cpu_seconds() -> float:
    """CPU time [s] of this process and its finished children (the pool's workers)."""
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def _fig4_means(fig4: Fig4Result) -> list[dict[str, Any]]:
    return [
        {"body": r["body"], "method": r["method"], **{k: r[f"{k}_mean"] for k in METRICS}}
        for r in fig4.summary()
    ]


def _copy_figures(
    outputs: OutputSet,
    files: dict[str, Path],
    results: str | Path,
    figures_dir: str | Path | None,
) -> dict[str, Path]:
    """Copy the PNGs next to the report (``docs/figures`` by default); returns their paths."""
    target = Path(figures_dir) if figures_dir else Path(results).parent / "docs" / "figures"
    target.mkdir(parents=True, exist_ok=True)
    copied = {}
    for key in ("fig4_figure", "fig5_figure"):
        if key in files:
            data = outputs.source(files[key]).read_bytes()  # written, not yet renamed
            dest = target / files[key].name
            copied[key] = atomic_write(dest, lambda fh, d=data: fh.write(d), "wb")
    return copied
