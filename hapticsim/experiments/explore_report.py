"""The report picture of ``hapticsim explore``: truth, estimate and the contacts with normals."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]

#: Colour per finger index (thumb, index, middle, ring).
FINGER_COLORS: tuple[str, ...] = ("tab:green", "tab:red", "tab:purple", "tab:brown")
FINGER_LABELS: tuple[str, ...] = ("thumb", "index", "middle", "ring")
#: Colours of an estimate's parts (a union's; one part is orange).
PART_COLORS: tuple[str, ...] = ("tab:orange", "gold", "tab:pink", "tab:cyan", "tab:olive")


def _surface(ax: Any, shape: Solid, color: str, alpha: float, resolution: int = 40) -> None:
    v, faces = shape.surface_mesh(resolution)
    v, faces = np.asarray(v) * 1000.0, np.asarray(faces)
    ax.plot_trisurf(v[:, 0], v[:, 1], v[:, 2], triangles=faces, color=color, alpha=alpha,
                    linewidth=0.0, shade=True)  # fmt: skip


def _half_width(truth: Solid) -> float:
    """Half the side [mm] of the cube the panels show around the truth: half its box's
    largest side, 15 % more."""
    return max(float(np.max(np.ptp(truth.bounds, axis=0))) * 500.0 * 1.15, 10.0)


def exploration_figure_png(
    truth: Solid,
    estimate: Solid | None,
    points_world: Array,
    normals_world: Array,
    finger: NDArray[np.int64],
    title: str,
    dpi: int = 110,
    tactile: dict[str, Any] | None = None,
) -> bytes:
    """PNG bytes of a two-panel picture: contacts with normal arrows on the truth (left), the
    estimate over the truth (right); with `tactile`, a row of pads' pressure images below.
    Lengths in millimetres.

    Args:
        truth: the true object (any solid).
        estimate: the fitted solid (a union's parts each in its colour), or None.
        points_world: (n, 3) float, contact points [m].
        normals_world: (n, 3) float, outward unit normals.
        finger: (n,) int, finger of each contact (colours).
        title: figure title.
        dpi: resolution.
        tactile: ``{"images": (k, rows, cols) [Pa], "labels": [k str]}``, the pressure images
            of k touches (tactile sensing), or None.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    rows = 1 if tactile is None else 2
    fig = Figure(figsize=(10, 5) if tactile is None else (10, 7.2))
    grid = fig.add_gridspec(rows, 1, height_ratios=[5] if tactile is None else [5, 1.6])
    top = grid[0].subgridspec(1, 2)
    pts = np.asarray(points_world) * 1000.0
    nrm = np.asarray(normals_world)
    half = _half_width(truth)
    center = truth.center * 1000.0
    arrow = 0.25 * half
    parts = () if estimate is None else estimate.components
    shown = (
        "estimate (orange) over truth (blue)" if len(parts) <= 1
        else f"estimate ({len(parts)} parts, each its colour) over truth (blue)"
    )  # fmt: skip
    for k, (panel, show_estimate) in enumerate((("contacts and normals", False), (shown, True))):
        ax = fig.add_subplot(top[0, k], projection="3d")
        _surface(ax, truth, "tab:blue", 0.18 if show_estimate else 0.25)
        if show_estimate:
            for j, part in enumerate(parts):
                _surface(ax, part, PART_COLORS[j % len(PART_COLORS)], 0.35)
        for f in np.unique(finger):
            sel = finger == f
            color = FINGER_COLORS[int(f) % len(FINGER_COLORS)]
            ax.scatter(
                *pts[sel].T,
                s=6,
                color=color,
                depthshade=False,
                label=FINGER_LABELS[int(f)] if int(f) < len(FINGER_LABELS) else str(f),
            )
            if not show_estimate:
                ax.quiver(*pts[sel].T, *(nrm[sel] * arrow).T, color=color, linewidth=0.6,
                          arrow_length_ratio=0.25)  # fmt: skip
        ax.set_xlim(center[0] - half, center[0] + half)
        ax.set_ylim(center[1] - half, center[1] + half)
        ax.set_zlim(center[2] - half, center[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")
        ax.set_title(panel, fontsize=9)
        ax.view_init(elev=22, azim=-50)
        if k == 0:
            ax.legend(loc="upper left", fontsize=7, markerscale=2)
    if tactile is not None:
        _pad_row(fig, grid[1], tactile)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


def _pad_row(fig: Any, cell: Any, tactile: dict[str, Any]) -> None:
    """The pressure images [kPa] of a few touches side by side, one colour scale: one mosaic in
    one axes (eight axes cost matplotlib a third of a second more)."""
    images = np.asarray(tactile["images"], dtype=np.float64) / 1000.0
    k = len(images)
    if k == 0:
        return
    rows, cols = images.shape[1:]
    gap = max(1, cols // 10)
    mosaic = np.full((rows, k * cols + (k - 1) * gap), np.nan)
    for i, image in enumerate(images):
        mosaic[:, i * (cols + gap) : i * (cols + gap) + cols] = image
    row = cell.subgridspec(1, 2, width_ratios=[1.0, 0.012])
    ax = fig.add_subplot(row[0, 0])
    shown = ax.imshow(mosaic, cmap="inferno", vmin=0.0, vmax=max(float(images.max()), 1e-9),
                      interpolation="nearest")  # fmt: skip
    for i, label in enumerate(tactile["labels"]):
        ax.text(i * (cols + gap) + cols / 2, -1.0, label, ha="center", va="bottom", fontsize=7)
    ax.set_axis_off()
    bar = fig.colorbar(shown, cax=fig.add_subplot(row[0, 1]))
    bar.set_label("pressure [kPa]", fontsize=7)
    bar.ax.tick_params(labelsize=6)


def png_bytes(image: NDArray[np.uint8]) -> bytes:
    """PNG bytes of an (h, w, 3) uint8 RGB image."""
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(image).save(buf, format="PNG", optimize=True)
    return buf.getvalue()


def write_bytes_atomic(path: str | Path, data: bytes) -> Path:
    """Write bytes through a temporary sibling file and a rename (``hapticsim.data.io``'s)."""
    from hapticsim.data.io import atomic_write

    return atomic_write(path, lambda fh: fh.write(data), "wb")


__all__ = ["exploration_figure_png", "png_bytes", "write_bytes_atomic"]
