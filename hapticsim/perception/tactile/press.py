"""A rigid fingertip pressed against a solid: the analytic backend's touch, felt by a pad.

Where a ray cast finds a contact at ``x`` with the solid's outward normal ``n`` (the analytic
touch backend, :mod:`hapticsim.envs.analytic`), a spherical fingertip of radius R carrying the
pad is put with its core at ``x + (R - delta) n``, sunk by the skin's penetration ``delta`` at
:data:`~hapticsim.perception.tactile.skin.PROBE_FORCE` (``SkinModel.sphere_penetration``), the pad
facing
the object along the approach direction ``d`` (its centre normal is ``-d``): the fingertip
frame has z along ``d``, its x axis horizontal. The pad's taxels read their depths against the
solid (:func:`~hapticsim.perception.tactile.depth.taxel_depths`), as the MuJoCo hand's do.

numpy only.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.perception.tactile.depth import taxel_depths
from hapticsim.perception.tactile.pad import PadLayout

Array = NDArray[np.float64]


def fingertip_frame(approach: Array) -> Array:
    """(3, 3) rotation whose z axis is the unit `approach` direction (pointing from the object
    to the finger) and whose x axis is horizontal (the world's x when `approach` is vertical)."""
    z = np.asarray(approach, dtype=np.float64)
    z = z / np.linalg.norm(z)
    x = np.cross([0.0, 0.0, 1.0], z)
    if np.linalg.norm(x) < 1e-9:
        x = np.array([1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def press(
    solid: Any, point: Array, normal: Array, approach: Array, layout: PadLayout,
    penetration: float,
) -> tuple[Array, Array, Array]:  # fmt: skip
    """The depths a curved pad reads when its fingertip touches `solid` at `point`.

    Args:
        solid: the object (anything :func:`~hapticsim.perception.tactile.depth.taxel_depths` takes).
        point: (3,) float, the contact on the surface [m, world].
        normal: (3,) float, the solid's outward unit normal there.
        approach: (3,) float, the direction the finger came from (from the object outward).
        layout: the pad in the fingertip frame (its sphere about the origin; it faces -z).
        penetration: how far the fingertip sinks in [m], >= 0.

    Returns:
        depths (rows, cols) [m], the fingertip frame's rotation (3, 3) and origin (3,) [m].
    """
    radius = float(layout.radius)
    rot = fingertip_frame(approach)
    core = np.asarray(point, dtype=np.float64) + (radius - penetration) * np.asarray(normal)
    pos, nrm, _ = layout.taxels
    depth = taxel_depths(solid, pos @ rot.T + core, nrm @ rot.T, radius)
    return depth, rot, core


__all__ = ["fingertip_frame", "press"]
