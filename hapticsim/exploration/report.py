"""The report picture of ``hapticsim explore``: contacts, estimate over truth, and its error."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]

#: Colour per finger index (thumb, index, middle, ring, little, ...).
FINGER_COLORS: tuple[str, ...] = (
    "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:olive", "tab:gray",
)  # fmt: skip
FINGER_LABELS: tuple[str, ...] = ("thumb", "index", "middle", "ring")
#: Colours of an estimate's parts (a union's; one part is orange).
PART_COLORS: tuple[str, ...] = ("tab:orange", "gold", "tab:pink", "tab:cyan", "tab:olive")


#: Surface mesh resolution of the pictures (smooth at 1600 px and more).
RESOLUTION: int = 72


def _surface(ax: Any, shape: Solid, color: str, alpha: float, resolution: int = RESOLUTION) -> None:
    v, faces = shape.surface_mesh(resolution)
    v, faces = np.asarray(v) * 1000.0, np.asarray(faces)
    ax.plot_trisurf(v[:, 0], v[:, 1], v[:, 2], triangles=faces, color=color, alpha=alpha,
                    linewidth=0.0, shade=True, antialiased=True)  # fmt: skip


def _error_surface(ax: Any, fig: Any, truth: Solid, estimate: Solid) -> None:
    """The estimate's surface coloured by its signed distance to the truth's [mm] (red:
    outside the truth, blue: inside), with a colour bar."""
    from matplotlib import cm, colors
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    polys, values = [], []
    for part in estimate.components:
        v, faces = part.surface_mesh(RESOLUTION)
        v, faces = np.asarray(v), np.asarray(faces)
        # at the vertices, which lie on the estimate (a face's midpoint cuts its corners)
        d = truth.surface_distance(v) * np.where(truth.contains(v), -1.0, 1.0)
        polys.append(v[faces] * 1000.0)
        values.append(d[faces].mean(axis=1) * 1000.0)
    tris, err = np.concatenate(polys), np.concatenate(values)
    scale = max(float(np.percentile(np.abs(err), 98)), 0.05)
    norm = colors.Normalize(-scale, scale)
    mapper = cm.ScalarMappable(norm=norm, cmap="coolwarm")
    ax.add_collection3d(Poly3DCollection(tris, facecolors=mapper.to_rgba(err), linewidth=0.0,
                                         antialiased=True))  # fmt: skip
    bar = fig.colorbar(mapper, ax=ax, shrink=0.6, pad=0.1)
    bar.set_label("estimate to truth [mm] (+ outside)", fontsize=8)


def _half_width(truth: Solid) -> float:
    """Half the side [mm] of the cube the panels show around the truth: half its box's
    largest side, 15 % more."""
    return max(float(np.max(np.ptp(truth.bounds, axis=0))) * 500.0 * 1.15, 10.0)


def prepare_figures() -> None:
    """Import matplotlib's 3-D axes and load its fonts (about a second, once per process): what
    ``explore`` does while it waits for the fitter's kernels to compile."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(1, 1))
    fig.add_subplot(projection="3d").set_title("x")
    fig.savefig(io.BytesIO(), format="png", dpi=10)


def exploration_figure_png(
    truth: Solid,
    estimate: Solid | None,
    points_world: Array,
    normals_world: Array,
    finger: NDArray[np.int64],
    title: str,
    dpi: int = 110,
    tactile: dict[str, Any] | None = None,
    finger_names: tuple[str, ...] | list[str] | None = None,
) -> bytes:
    """PNG bytes of a three-panel picture, 1760 px wide at the default dpi: contacts with
    normal arrows on the truth, the estimate over the truth, and the estimate's surface
    coloured by its signed distance to the truth's (where it is wrong, with a scale); with
    `tactile`, a row of pads' pressure images below. Lengths in millimetres.

    Args:
        truth: the true object (any solid).
        estimate: the fitted solid (a union's parts each in its colour), or None.
        points_world: (n, 3) float, contact points [m].
        normals_world: (n, 3) float, outward unit normals.
        finger: (n,) int, finger of each contact (colours).
        title: figure title (name the hand in it).
        dpi: resolution.
        tactile: ``{"images": (k, rows, cols) [Pa], "labels": [k str]}``, the pressure images
            of k touches (tactile sensing), or None.
        finger_names: the hand's finger names by index (the legend); default
            :data:`FINGER_LABELS`.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    names = tuple(FINGER_LABELS if finger_names is None else finger_names)
    rows = 1 if tactile is None else 2
    fig = Figure(figsize=(16, 5.6) if tactile is None else (16, 7.8))
    grid = fig.add_gridspec(rows, 1, height_ratios=[5] if tactile is None else [5, 1.6])
    top = grid[0].subgridspec(1, 3)
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
    panels = [("contacts and normals, by finger", "contacts"), (shown, "estimate")]
    if estimate is not None:
        panels.append(("where the estimate is wrong: its distance to the truth", "error"))
    for k, (panel, kind) in enumerate(panels):
        ax = fig.add_subplot(top[0, k], projection="3d")
        if kind == "error":
            assert estimate is not None
            _error_surface(ax, fig, truth, estimate)
        else:
            _surface(ax, truth, "tab:blue", 0.18 if kind == "estimate" else 0.25)
        if kind == "estimate":
            for j, part in enumerate(parts):
                _surface(ax, part, PART_COLORS[j % len(PART_COLORS)], 0.35)
        for f in np.unique(finger):
            sel = finger == f
            color = FINGER_COLORS[int(f) % len(FINGER_COLORS)]
            ax.scatter(
                *pts[sel].T,
                s=6 if kind != "error" else 3,
                color=color if kind != "error" else "black",
                depthshade=False,
                label=names[int(f)] if 0 <= int(f) < len(names) else str(f),
            )
            if kind == "contacts":
                ax.quiver(*pts[sel].T, *(nrm[sel] * arrow).T, color=color, linewidth=0.6,
                          arrow_length_ratio=0.25)  # fmt: skip
        ax.set_xlim(center[0] - half, center[0] + half)
        ax.set_ylim(center[1] - half, center[1] + half)
        ax.set_zlim(center[2] - half, center[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")
        ax.set_title(panel, fontsize=10)
        ax.view_init(elev=22, azim=-50)
        if k == 0:
            ax.legend(loc="upper left", fontsize=8, markerscale=2)
    if tactile is not None:
        _pad_row(fig, grid[1], tactile)
    fig.suptitle(title, fontsize=11)
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


__all__ = ["exploration_figure_png", "png_bytes", "prepare_figures"]
