"""Offscreen pictures of a scene with MuJoCo's renderer (``MUJOCO_GL=egl``, headless).

``hapticsim.sim`` sets ``MUJOCO_GL=egl`` on headless Linux (unless set) before mujoco is
imported.
"""

from __future__ import annotations

import os

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import SimulationError
from hapticsim.sim.simulator import Simulator

Array = NDArray[np.float64]

#: Colour (RGBA) and radius [m] of drawn contact points.
CONTACT_RGBA: tuple[float, float, float, float] = (0.95, 0.15, 0.1, 1.0)
CONTACT_RADIUS: float = 0.0025
#: Emission of markers: they keep their colour in shade (and differ from lit fingertips).
MARKER_EMISSION: float = 0.8


def add_markers(
    scene: mujoco.MjvScene,
    points: Array,
    rgba: tuple[float, ...] = CONTACT_RGBA,
    radius: float = CONTACT_RADIUS,
) -> None:
    """Append sphere markers to a ``mujoco.MjvScene`` (after ``update_scene``).

    Args:
        scene: the scene of a ``mujoco.Renderer``.
        points: (n, 3) float, marker centres [m, world]; markers beyond the scene's capacity
            (``maxgeom``) are left out.
        rgba: colour.
        radius: marker radius [m].
    """
    size = np.array([radius, 0.0, 0.0])
    mat = np.eye(3).ravel()
    color = np.asarray(rgba, dtype=np.float32)
    for p in np.asarray(points, dtype=np.float64).reshape(-1, 3):
        if scene.ngeom >= scene.maxgeom:
            break
        geom = scene.geoms[scene.ngeom]
        mujoco.mjv_initGeom(geom, mujoco.mjtGeom.mjGEOM_SPHERE, size, p, mat, color)
        geom.emission = MARKER_EMISSION
        scene.ngeom += 1


def make_renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """An offscreen renderer, or SimulationError when no OpenGL context can be made.

    Raises:
        SimulationError: no OpenGL context (MuJoCo renders with EGL/OSMesa), or a size beyond
            the model's offscreen buffer.
    """
    try:
        return mujoco.Renderer(model, height, width)
    except Exception as exc:  # context creation: missing EGL/OSMesa, bad display, too large
        raise SimulationError(
            f"cannot render offscreen (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): {exc}"
        ) from exc


def render_scene(
    sim: Simulator,
    width: int = 640,
    height: int = 480,
    camera: str = "overview",
    points: Array | None = None,
) -> NDArray[np.uint8]:
    """An RGB picture of the current state of a simulation.

    Args:
        sim: the simulation.
        width, height: picture size [px] (at most the model's offscreen buffer).
        camera: camera name in the scene.
        points: (n, 3) float, contact points to draw [m, world], or None.

    Returns:
        (height, width, 3) uint8.

    Raises:
        SimulationError: no OpenGL context could be made (MuJoCo renders with EGL/OSMesa).
    """
    renderer = make_renderer(sim.model, width, height)
    try:
        renderer.update_scene(sim.data, camera=camera)
        if points is not None:
            add_markers(renderer.scene, points)
        return renderer.render().copy()
    finally:
        renderer.close()


__all__ = ["CONTACT_RADIUS", "CONTACT_RGBA", "add_markers", "make_renderer", "render_scene"]
