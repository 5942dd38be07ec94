"""Pictures: files written, readable, small (stand-in estimates, no fitting)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from hapticsim.experiments.plotting import plot_fig4, plot_fig5
from hapticsim.experiments.stats import summarize
from hapticsim.geometry import Superquadric

METHODS = ("LS", "H", "nLS", "nH")


def test_plot_fig4_grid(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    truths = {
        "cube": Superquadric(a=[0.03] * 3, eps=[0.1, 0.1]),
        "cylinder": Superquadric(a=[0.03, 0.03, 0.06], eps=[0.1, 1.0]),
    }
    contacts, estimates, epsilons = {}, {}, {}
    for body, truth in truths.items():
        points, normals = truth.surface(rng.uniform(-1.5, 1.5, 50), rng.uniform(-3, 3, 50))
        contacts[body] = (points, normals)
        for m in METHODS:
            estimates[(body, m)] = truth.replace(a=truth.a * rng.uniform(0.7, 1.3, 3))
            epsilons[(body, m)] = 0.5
    # An estimate far off must not break the picture (it is clipped to the view box).
    estimates[("cube", "LS")] = truths["cube"].replace(a=[0.3, 0.03, 0.03], center=[0.2, 0, 0])
    path = plot_fig4(truths, contacts, estimates, epsilons, METHODS, tmp_path / "f4.png")
    with Image.open(path) as image:
        width, height = image.size
    assert width > 800 and height > 300
    assert path.stat().st_size < 600_000  # small enough to commit


def test_plot_fig5_curves(tmp_path: Path) -> None:
    rows = []
    for run in range(3):
        for m in METHODS:
            for budget in (100, 200, 400):
                rows.append({"method": m, "budget": budget, "noise": 0.1, "run": run,
                             "theta": 1e-5 / budget, "epsilon": 0.2 + 0.1 * run})  # fmt: skip
            for noise in (0.01, 0.1):
                rows.append({"method": m, "budget": 400, "noise": noise, "run": run,
                             "theta": 1e-5 * noise, "epsilon": noise + 0.1 * run})  # fmt: skip
    by_budget = summarize([r for r in rows if r["noise"] == 0.1], ("method", "budget"),
                          ("theta", "epsilon"))  # fmt: skip
    by_noise = summarize([r for r in rows if r["budget"] == 400], ("method", "noise"),
                         ("theta", "epsilon"))  # fmt: skip
    path = plot_fig5(
        by_budget, by_noise, METHODS, tmp_path / "f5.png", budget_body="cylinder",
        noise_body="cube", runs=3, noise_budget=400, budget_noise=0.1,
    )  # fmt: skip
    with Image.open(path) as image:
        assert image.size[0] > 800
