"""A scene: the hand, a table and one superquadric object, composed with ``mujoco.MjSpec``.

The object is a static body (the paper keeps it fixed during exploration) whose collision geom is
the superquadric meshed in its body frame (:mod:`~hapticsim.sim.object_mesh`: the hull of the
vertices of :meth:`Superquadric.to_mesh` in both parametrisations); MuJoCo collides with the
mesh's convex hull (``maxhullvert`` left at its default). The object stands on a thin post
(the *stand*) :data:`STAND_HEIGHT` above the table, so that the fingers can reach around its
bottom edges. The ground truth travels with the scene (:attr:`Scene.truth`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float, positive_int
from hapticsim.errors import SimulationError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.superquadric import superquadric_arg
from hapticsim.sim import mujoco_log  # noqa: F401  (MuJoCo warnings to logging, not a file)
from hapticsim.sim.hand import Hand
from hapticsim.sim.models import model_path
from hapticsim.sim.object_mesh import object_vertices
from hapticsim.sim.workspace import Workspace

Array = NDArray[np.float64]

#: Mesh resolution (longitudes; ``res * (res // 2 - 1) + 2`` vertices) of object meshes. At 128
#: (8066 vertices) the measured contact normals on faces are within ~1 degree (median) of the
#: analytic normal; at 64 (1986 vertices) about 4 degrees on edges.
DEFAULT_MESH_RESOLUTION: int = 128
#: Sliding friction of fingertip/object contacts (contacts stay clean at <= 0.3).
DEFAULT_FRICTION: float = 0.2
#: Physics time step [s].
DEFAULT_TIMESTEP: float = 0.001
#: Name of the object body, geom and mesh.
OBJECT_NAME: str = "object"
#: Height of the object's lowest point above the table top [m].
STAND_HEIGHT: float = 0.15
#: Largest radius of the stand [m] (smaller objects get a thinner one).
STAND_RADIUS: float = 0.008


@dataclass(frozen=True)
class SceneConfig:
    """How a scene is built.

    Attributes:
        mesh_resolution: longitudes of the object mesh (>= 16).
        friction: sliding friction coefficient of the object, in [0, 1].
        timestep: physics time step [s], in (0, 0.005].
        workspace: where the palm may go.
    """

    mesh_resolution: int = DEFAULT_MESH_RESOLUTION
    friction: float = DEFAULT_FRICTION
    timestep: float = DEFAULT_TIMESTEP
    workspace: Workspace = field(default_factory=Workspace)

    def __post_init__(self) -> None:
        positive_int(self.mesh_resolution, "mesh_resolution", minimum=16)
        finite_float(self.friction, "friction", 0.0, 1.0)
        if not 0.0 < finite_float(self.timestep, "timestep") <= 0.005:
            raise SimulationError(f"`timestep` must be in (0, 0.005] s, got {self.timestep!r}")


@dataclass(frozen=True, eq=False)
class Scene:
    """A compiled scene.

    Attributes:
        model: the compiled ``mujoco.MjModel``.
        spec: the ``mujoco.MjSpec`` it was compiled from.
        truth: the object's superquadric in the world frame (ground truth).
        hand: ids and kinematics of the hand.
        object_geom_id: id of the object's mesh geom.
        object_body_id: id of the object's body.
        stand_geom_id: id of the stand (post) under the object.
        table_top_z: height of the table top [m, world].
        config: the build configuration.
    """

    model: mujoco.MjModel
    spec: mujoco.MjSpec
    truth: Superquadric
    hand: Hand
    object_geom_id: int
    object_body_id: int
    stand_geom_id: int
    table_top_z: float
    config: SceneConfig


def build_scene(truth: Superquadric, config: SceneConfig | None = None) -> Scene:
    """Compose hand + table + object into a compiled model.

    Args:
        truth: the object, posed in the world frame.
        config: build options (defaults: :class:`SceneConfig`).

    Returns:
        The scene; make an ``mujoco.MjData`` (or a :class:`~hapticsim.sim.simulator.Simulator`)
        from ``scene.model``.

    Raises:
        SimulationError: the object is too large for the hand or outside its workspace.
    """
    truth = superquadric_arg(truth, "truth")
    config = SceneConfig() if config is None else config
    config.workspace.check_object(truth)

    spec = mujoco.MjSpec.from_file(str(model_path("hand.xml")))
    spec.option.timestep = config.timestep

    vertices = object_vertices(truth, config.mesh_resolution)
    spec.add_mesh(name=OBJECT_NAME, uservert=vertices.ravel().tolist())
    body = spec.worldbody.add_body(
        name=OBJECT_NAME, pos=truth.center.tolist(), quat=truth.quaternion.tolist()
    )
    body.add_geom(
        name=OBJECT_NAME,
        type=mujoco.mjtGeom.mjGEOM_MESH,
        meshname=OBJECT_NAME,
        contype=1,
        conaffinity=2,
        condim=3,
        friction=[config.friction, 0.005, 0.0001],
        rgba=[0.35, 0.55, 0.85, 1.0],
    )

    vertices_world = vertices @ truth.rotation.T + truth.center
    low_z = float(vertices_world[:, 2].min())
    table_top_z = low_z - STAND_HEIGHT
    # the stand: a post under the lowest vertex nearest the centre, 2 mm into the object
    low = vertices_world[vertices_world[:, 2] < low_z + 1e-3]
    foot = low[np.argmin(np.linalg.norm(low[:, :2] - truth.center[:2], axis=1))]
    stand_radius = min(STAND_RADIUS, 0.3 * float(np.min(truth.a[:2])))
    spec.worldbody.add_geom(
        name="stand",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[stand_radius, 0.5 * (STAND_HEIGHT + 0.002), 0.0],
        pos=[foot[0], foot[1], table_top_z + 0.5 * (STAND_HEIGHT + 0.002)],
        contype=1,
        conaffinity=2,
        rgba=[0.3, 0.3, 0.3, 1.0],
    )
    table = mujoco.MjSpec.from_file(str(model_path("table.xml")))
    frame = spec.worldbody.add_frame(pos=[foot[0], foot[1], table_top_z])
    spec.attach(table, frame=frame, prefix="table/")

    spec.worldbody.add_light(name="key", pos=[0.3, -0.4, 1.2], dir=[-0.3, 0.4, -1.0])
    spec.worldbody.add_light(name="fill", pos=[-0.5, 0.3, 1.0], dir=[0.5, -0.3, -1.0])
    eye = truth.center + np.array([0.32, -0.30, 0.20])
    forward = (truth.center - eye) / np.linalg.norm(truth.center - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    spec.worldbody.add_camera(
        name="overview", pos=eye.tolist(), xyaxes=[*right, *np.cross(right, forward)], fovy=45.0
    )
    model = spec.compile()
    return Scene(
        model=model,
        spec=spec,
        truth=truth,
        hand=Hand(model),
        object_geom_id=int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, OBJECT_NAME)),
        object_body_id=int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, OBJECT_NAME)),
        stand_geom_id=int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "stand")),
        table_top_z=table_top_z,
        config=config,
    )


__all__ = [
    "DEFAULT_FRICTION",
    "DEFAULT_MESH_RESOLUTION",
    "DEFAULT_TIMESTEP",
    "STAND_HEIGHT",
    "Scene",
    "SceneConfig",
    "build_scene",
]
