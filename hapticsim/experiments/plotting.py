"""Matplotlib pictures of the paper's Fig. 4 (shape grid) and Fig. 5 (quality curves).

Uses the non-interactive Agg backend; every function writes a PNG and returns its path.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry import Superquadric

Array = NDArray[np.float64]

TRUTH_COLOR = "tab:blue"
ESTIMATE_COLOR = "tab:orange"
CONTACT_COLOR = "black"
NORMAL_COLOR = "tab:red"
#: Line colour and style per method in the curves: dashed without normals, solid with.
METHOD_STYLE: dict[str, dict[str, Any]] = {
    "LS": {"color": "tab:gray", "linestyle": "--", "marker": "o"},
    "H": {"color": "tab:purple", "linestyle": "--", "marker": "s"},
    "nLS": {"color": "tab:green", "linestyle": "-", "marker": "o"},
    "nH": {"color": "tab:red", "linestyle": "-", "marker": "s"},
}
MESH_RESOLUTION = 32


def _pyplot():  # noqa: ANN202 - the pyplot module
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: str | Path, dpi: int) -> Path:
    """Save as a 256-colour PNG (small files for the repository), atomically."""

    from PIL import Image

    from hapticsim.data.io import atomic_write

    buf = io.BytesIO()
    fig.savefig(buf, dpi=dpi, format="png")
    buf.seek(0)
    image = Image.open(buf).convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(path, lambda fh: image.save(fh, format="PNG", optimize=True), "wb")


def _add_surface(ax: Any, sq: Superquadric, color: str, alpha: float) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    mesh = sq.to_mesh(resolution=MESH_RESOLUTION)
    poly = Poly3DCollection(
        mesh.triangles * 1000.0,
        facecolors=color,
        edgecolors=color,
        linewidths=0.0,
        alpha=alpha,
        shade=True,
        axlim_clip=True,  # a far-off estimate must not spill into the next panel
    )
    ax.add_collection3d(poly, autolim=False)


def _set_view(ax: Any, center_mm: Array, half_mm: float, show_labels: bool) -> None:
    for set_lim, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), center_mm, strict=True):
        set_lim(c - half_mm, c + half_mm)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=22, azim=-58)
    ax.tick_params(labelsize=6, pad=0)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(_locator())
    if show_labels:
        ax.set_xlabel("x [mm]", fontsize=7, labelpad=-6)
        ax.set_ylabel("y [mm]", fontsize=7, labelpad=-6)
        ax.set_zlabel("z [mm]", fontsize=7, labelpad=-6)


def _view_box(truth: Superquadric, others: Sequence[Superquadric]) -> tuple[Array, float]:
    """Centre [mm] and half width [mm] of a cube around the truth that also shows the other
    shapes, up to twice the truth's size (shapes beyond are clipped)."""
    low, high = 1000.0 * truth.to_mesh(resolution=16).bounds
    center = (low + high) / 2
    half_truth = 0.55 * float(np.max(high - low))
    reach = half_truth
    for sq in others:
        lo, hi = 1000.0 * sq.to_mesh(resolution=16).bounds
        reach = max(reach, 1.05 * float(np.max(np.abs(np.stack([lo, hi]) - center))))
    return center, min(reach, 2.0 * half_truth)


def _null_formatter() -> Any:
    from matplotlib.ticker import NullFormatter

    return NullFormatter()


def _locator() -> Any:
    from matplotlib.ticker import MaxNLocator

    return MaxNLocator(3)


def plot_fig4(
    truths: Mapping[str, Superquadric],
    contacts: Mapping[str, tuple[Array, Array | None]],
    estimates: Mapping[tuple[str, str], Superquadric],
    epsilons: Mapping[tuple[str, str], float],
    methods: Sequence[str],
    path: str | Path,
    title: str = "",
    dpi: int = 80,
) -> Path:
    """The Fig. 4 grid: rows bodies; columns data, then one fit per method.

    Truth in blue, estimate in orange (both semi-transparent), contact points in black and
    their normals as red arrows (data column). Axes in millimetres, equal aspect, the same
    view box for all panels of a row (centred on the truth; estimates may leave it).

    Args:
        truths: true superquadric per body (row order = mapping order).
        contacts: (points (n, 3) [m], normals (n, 3) or None) per body.
        estimates: fitted superquadric per (body, method).
        epsilons: epsilon of each estimate, printed in its panel.
        methods: column order after the data column.
        path: PNG to write.
        title: figure title.
        dpi: resolution.

    Returns:
        The path written.
    """
    plt = _pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    bodies = list(truths)
    n_cols = 1 + len(methods)
    fig = plt.figure(figsize=(2.6 * n_cols, 2.5 * len(bodies) + 0.9))
    letters = "abcdefghij"
    for i, body in enumerate(bodies):
        truth = truths[body]
        points, normals = contacts[body]
        center_mm, half_mm = _view_box(
            truth, [estimates[(body, m)] for m in methods if (body, m) in estimates]
        )
        arrow_mm = 0.25 * 1000.0 * float(np.mean(truth.a))
        for j in range(n_cols):
            ax = fig.add_subplot(len(bodies), n_cols, i * n_cols + j + 1, projection="3d")
            _add_surface(ax, truth, TRUTH_COLOR, 0.18 if j else 0.3)
            p_mm = 1000.0 * points
            ax.scatter(*p_mm.T, s=2, c=CONTACT_COLOR, depthshade=False)
            if j == 0:
                if normals is not None:
                    ax.quiver(
                        *p_mm.T, *normals.T, length=arrow_mm, color=NORMAL_COLOR,
                        linewidth=0.5, arrow_length_ratio=0.3,
                    )  # fmt: skip
                head = f"({letters[j]}) data, {len(points)} contacts"
            else:
                method = methods[j - 1]
                _add_surface(ax, estimates[(body, method)], ESTIMATE_COLOR, 0.35)
                head = f"({letters[j]}) {method}   ε = {epsilons[(body, method)]:.2f}"
            _set_view(ax, center_mm, half_mm, show_labels=(j == 0))
            ax.set_title(head, fontsize=9, pad=0)
            if j == 0:
                ax.text2D(
                    -0.12, 0.5, body.replace("_", " "), transform=ax.transAxes, rotation=90,
                    va="center", ha="center", fontsize=10, fontweight="bold",
                )  # fmt: skip
    handles = [
        Patch(facecolor=TRUTH_COLOR, alpha=0.4, label="truth"),
        Patch(facecolor=ESTIMATE_COLOR, alpha=0.6, label="estimate"),
        Line2D([], [], marker="o", linestyle="", color=CONTACT_COLOR, markersize=3,
               label="contact points"),
        Line2D([], [], color=NORMAL_COLOR, label="contact normals (data column)"),
    ]  # fmt: skip
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=9, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.subplots_adjust(left=0.03, right=0.99, top=0.93, bottom=0.05, wspace=0.05, hspace=0.12)
    out = _save(fig, path, dpi)
    plt.close(fig)
    return out


def _curves(
    ax: Any,
    summary: Sequence[dict[str, Any]],
    x_key: str,
    metric: str,
    methods: Sequence[str],
    band: tuple[str, str],
) -> None:
    for method in methods:
        rows = sorted((r for r in summary if r["method"] == method), key=lambda r: r[x_key])
        if not rows:
            continue
        x = np.array([r[x_key] for r in rows], dtype=float)
        mean = np.array([r[f"{metric}_mean"] for r in rows])
        low = np.array([r[f"{metric}_{band[0]}"] for r in rows])
        high = np.array([r[f"{metric}_{band[1]}"] for r in rows])
        style = METHOD_STYLE.get(method, {})
        ax.plot(x, mean, label=method, markersize=4, **style)
        ax.fill_between(x, low, high, color=style.get("color"), alpha=0.15, linewidth=0)
    ax.grid(True, which="both", alpha=0.3)
    ax.tick_params(labelsize=8)
    xs = sorted({float(r[x_key]) for r in summary})
    ax.set_xscale("log")
    ax.set_xticks(xs, [f"{v:g}" for v in xs])
    ax.xaxis.set_minor_formatter(_null_formatter())


def plot_fig5(
    by_budget: Sequence[dict[str, Any]],
    by_noise: Sequence[dict[str, Any]],
    methods: Sequence[str],
    path: str | Path,
    budget_body: str,
    noise_body: str,
    runs: int,
    noise_budget: int,
    budget_noise: float,
    dpi: int = 110,
) -> Path:
    """Fig. 5: theta and epsilon against the evaluation budget n and against sigma_N.

    Lines are means over runs; bands span the 25th to 75th percentile (interquartile range).

    Args:
        by_budget: :func:`~hapticsim.experiments.stats.summarize` rows by (method, budget).
        by_noise: summary rows by (method, noise).
        methods: methods to draw.
        path: PNG to write.
        budget_body, noise_body: the bodies of the two sweeps (paper: cylinder, cube).
        runs: runs per point (for the caption).
        noise_budget: budget of the noise sweep (for the caption).
        budget_noise: sigma_N of the budget sweep (for the caption).
        dpi: resolution.

    Returns:
        The path written.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(10, 7.6))
    band = ("q25", "q75")
    theta_label = "θ = D(S_e) / (D(S_s) + 1)  (eq. 10)"
    panels = (
        (axes[0, 0], by_budget, "budget", "theta", theta_label),
        (axes[0, 1], by_budget, "budget", "epsilon", "ε = α + β  (eqs. 11-12)"),
        (axes[1, 0], by_noise, "noise", "theta", theta_label),
        (axes[1, 1], by_noise, "noise", "epsilon", "ε = α + β  (eqs. 11-12)"),
    )
    for ax, summary, x_key, metric, ylabel in panels:
        _curves(ax, summary, x_key, metric, methods, band)
        ax.set_ylabel(ylabel, fontsize=9)
        if metric == "theta":
            ax.set_yscale("log")
        else:
            ax.set_ylim(bottom=0)
        if x_key == "budget":
            ax.set_xlabel("evaluation budget n [EOF evaluations] (log scale)", fontsize=9)
            ax.set_title(
                f"{budget_body.replace('_', ' ')}, σ_N = {budget_noise:g}: quality vs. n",
                fontsize=10,
            )
        else:
            ax.set_xlabel("noise σ_N (relative; log scale)", fontsize=9)
            ax.set_title(
                f"{noise_body.replace('_', ' ')}, n = {noise_budget}: quality vs. σ_N",
                fontsize=10,
            )
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=9, frameon=False)
    fig.suptitle(
        f"Fig. 5 reproduced: mean over {runs} runs (fresh noise each run); "
        "bands: interquartile range (25th-75th percentile).\n"
        "θ for LS and H uses the points-only EOF, θ⁽¹⁾; for nLS and nH the EOF with normals.",
        fontsize=9,
    )
    fig.tight_layout(rect=(0, 0.04, 1, 0.95))
    out = _save(fig, path, dpi)
    plt.close(fig)
    return out
