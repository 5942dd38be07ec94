"""Offscreen MuJoCo pictures of an exploration: truth, current estimate and contacts.

Used by the analytic backend's ``render`` (the MuJoCo backend renders its own scene with the hand).
Headless: set ``MUJOCO_GL=egl`` (or ``osmesa``) before MuJoCo is imported.
"""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.envs.support import Support
from hapticsim.geometry.solid import Solid
from hapticsim.sim.render import (  # noqa: F401  (contacts are drawn as the sim draws them)
    CONTACT_RADIUS,
    CONTACT_RGBA,
    add_markers,
)

Array = NDArray[np.float64]

#: Colours (RGBA) of the truth, the estimate and the table (contacts: ``CONTACT_RGBA``).
TRUTH_RGBA = (0.72, 0.72, 0.72, 1.0)
ESTIMATE_RGBA = (0.2, 0.45, 0.95, 0.35)
TABLE_RGBA = (0.55, 0.45, 0.35, 1.0)
#: Height of the drawn stand [m] (the MuJoCo scene's is 0.15 m).
STAND_HEIGHT = 0.06


def _add_mesh(spec, name: str, shape: Solid, rgba: tuple[float, ...]) -> None:  # noqa: ANN001
    vertices, faces = shape.surface_mesh(40)
    spec.add_mesh(
        name=name,
        uservert=np.asarray(vertices).ravel().tolist(),
        userface=np.asarray(faces).ravel().tolist(),
    )
    spec.worldbody.add_geom(
        type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name, rgba=list(rgba), contype=0, conaffinity=0
    )


class SceneRenderer:
    """Renders truth + estimate + contacts with MuJoCo's offscreen renderer.

    Args:
        width, height: picture size [pixels].
    """

    def __init__(self, width: int = 480, height: int = 360) -> None:
        self.width = int(width)
        self.height = int(height)
        self._key: tuple | None = None
        self._model = None
        self._data = None
        self._renderer = None

    def _build(
        self, truth: Solid, estimate: Solid | None, support: Support | None
    ) -> None:
        spec = mujoco.MjSpec()
        spec.visual.global_.offwidth = max(self.width, 640)
        spec.visual.global_.offheight = max(self.height, 480)
        spec.worldbody.add_light(pos=[0.3, -0.3, 1.0], dir=[-0.3, 0.3, -1.0], diffuse=[0.8] * 3)
        spec.worldbody.add_light(pos=[-0.3, 0.3, 1.0], dir=[0.3, -0.3, -1.0], diffuse=[0.4] * 3)
        if support is not None and support.kind != "none":
            foot = support.foot
            floor = foot[2] - (STAND_HEIGHT if support.kind == "stand" else 0.0)
            spec.worldbody.add_geom(
                type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.3, 0.3, 0.01],
                pos=[foot[0], foot[1], floor], rgba=list(TABLE_RGBA),
            )  # fmt: skip
            if support.kind == "stand":
                spec.worldbody.add_geom(
                    type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                    size=[support.radius, 0.5 * STAND_HEIGHT, 0.0],
                    pos=[foot[0], foot[1], foot[2] - 0.5 * STAND_HEIGHT], rgba=[0.3, 0.3, 0.3, 1],
                )  # fmt: skip
        _add_mesh(spec, "truth", truth, TRUTH_RGBA)
        if estimate is not None:
            _add_mesh(spec, "estimate", estimate, ESTIMATE_RGBA)
        self._model = spec.compile()
        self._data = mujoco.MjData(self._model)
        mujoco.mj_forward(self._model, self._data)
        if self._renderer is not None:
            self._renderer.close()
        self._renderer = mujoco.Renderer(self._model, self.height, self.width)

    def render(
        self,
        truth: Solid,
        estimate: Solid | None,
        points: Array,
        support: Support | None = None,
    ) -> NDArray[np.uint8]:
        """The picture, (height, width, 3) uint8.

        Args:
            truth: the ground truth (grey).
            estimate: the current fit (translucent blue), or None.
            points: (n, 3) float, contact points [m, world] (red spheres).
            support: the object's support (drawn with a table under a stand), or None.
        """

        key = (id(truth), id(estimate), id(support))
        if self._key != key or self._renderer is None:
            self._build(truth, estimate, support)
            self._key = key
        cam = mujoco.MjvCamera()
        cam.lookat[:] = truth.center
        cam.distance = 4.0 * truth.bounding_radius + 0.05
        cam.azimuth = 135.0
        cam.elevation = -30.0
        self._renderer.update_scene(self._data, cam)
        add_markers(self._renderer.scene, points)
        return self._renderer.render().copy()

    def close(self) -> None:
        """Free the OpenGL context."""
        if self._renderer is not None:
            self._renderer.close()
        self._renderer = None
        self._model = None
        self._data = None
        self._key = None
