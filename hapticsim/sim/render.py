"""Offscreen pictures of a scene with MuJoCo's renderer (``MUJOCO_GL=egl``, headless).

``hapticsim.sim`` sets ``MUJOCO_GL=egl`` (unless set) before importing mujoco.
"""

from __future__ import annotations

import os

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import SimulationError
from hapticsim.sim.simulator import Simulator


def render_scene(
    sim: Simulator, width: int = 640, height: int = 480, camera: str = "overview"
) -> NDArray[np.uint8]:
    """An RGB picture of the current state of a simulation.

    Args:
        sim: the simulation.
        width, height: picture size [px] (at most the model's offscreen buffer).
        camera: camera name in the scene.

    Returns:
        (height, width, 3) uint8.

    Raises:
        SimulationError: no OpenGL context could be made (MuJoCo renders with EGL/OSMesa).
    """
    import mujoco

    try:
        renderer = mujoco.Renderer(sim.model, height, width)
    except Exception as exc:  # context creation: missing EGL/OSMesa, bad display
        raise SimulationError(
            f"cannot render offscreen (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): {exc}"
        ) from exc
    try:
        renderer.update_scene(sim.data, camera=camera)
        return renderer.render().copy()
    finally:
        renderer.close()


__all__ = ["render_scene"]
