"""A scene: the hand, a table and one object, composed with ``mujoco.MjSpec``.

The object is a static body (the paper keeps it fixed during exploration) whose collision geoms
come from :func:`~hapticsim.sim.object_mesh.collision_parts`: a superquadric meshed in its body
frame (the hull of the vertices of :meth:`Superquadric.to_mesh` in both parametrisations), a
convex mesh as it is, or the convex parts of a non-convex mesh; MuJoCo collides with each mesh's
convex hull (``maxhullvert`` left at its default). The object stands on a thin post
(the *stand*) :data:`STAND_HEIGHT` above the table, so that the fingers can reach around its
bottom edges. The ground truth travels with the scene (:attr:`Scene.truth`).
"""

from __future__ import annotations

import copy
from collections import OrderedDict
from dataclasses import dataclass, field, replace
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float, positive_int
from hapticsim.constants import DEFAULT_FRICTION, SENSINGS, STEERINGS
from hapticsim.errors import ChoiceError, InvalidInputError, SimulationError
from hapticsim.geometry import Superquadric, matrix_to_quaternion
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.perception.tactile import SkinPreset, load_skin
from hapticsim.sim import mujoco_log  # noqa: F401  (MuJoCo warnings to logging, not a file)
from hapticsim.sim.dynamics import ObjectDynamics, add_dynamics, dynamics_arg, settle
from hapticsim.sim.hand import Hand, attach_hand, compile_scene, touching_geom_name
from hapticsim.sim.hand_description import HandDescription, load_hand
from hapticsim.sim.models import model_path
from hapticsim.sim.object_mesh import (
    CollisionParts,
    collision_parts,
    support_foot,
    support_radius,
)
from hapticsim.sim.tactile import TAXEL_MODELS, add_mujoco_pads, pad_layouts, prepare_skin
from hapticsim.sim.workspace import Workspace

Array = NDArray[np.float64]

#: Mesh resolution (longitudes; ``res * (res // 2 - 1) + 2`` vertices) of object meshes. At 128
#: (8066 vertices) the measured contact normals on faces are within ~1 degree (median) of the
#: analytic normal; at 64 (1986 vertices) about 4 degrees on edges.
DEFAULT_MESH_RESOLUTION: int = 128
#: Physics time step [s].
DEFAULT_TIMESTEP: float = 0.001
#: No-slip solver passes of a scene with a free object or a tactile hand (none for a fixed
#: object touched with exact sensing).
NOSLIP_ITERATIONS: int = 5
#: Frictional to normal stiffness of a tactile scene's contacts (MuJoCo ``impratio``; 1 with
#: exact sensing).
SKIN_IMPRATIO: float = 100.0
#: Name of the object body, geom and mesh.
OBJECT_NAME: str = "object"
#: Height of the object's lowest point above the table top [m].
STAND_HEIGHT: float = 0.15
#: Largest radius of the stand [m] (smaller objects get a thinner one).
STAND_RADIUS: float = 0.008
#: Names of the stand geom, the table's prefix and the overview camera.
STAND_NAME: str = "stand"
TABLE_PREFIX: str = "table/"
CAMERA_NAME: str = "overview"


@dataclass(frozen=True)
class SceneConfig:
    """How a scene is built.

    Attributes:
        mesh_resolution: longitudes of the object mesh (>= 16).
        friction: sliding friction coefficient of the object, in [0, 1].
        timestep: physics time step [s], in (0, 0.005].
        workspace: where the palm may go.
        hand: the hand, a shipped name (``"hapticsim"``, ``"shadow"``, ``"adroit"``), the path
            of a TOML description or a :class:`~hapticsim.sim.hand_description.HandDescription`
            (stored as the loaded description).
        sensing: ``"exact"`` (MuJoCo's contacts, the default) or ``"tactile"`` (a taxel pad on
            every fingertip, a compliant skin, contacts estimated from the taxels;
            :mod:`hapticsim.sim.tactile`).
        skin: with tactile sensing, the skin: a preset name (``"ideal"``, ``"vision"``,
            ``"capacitive"``), a ``.toml`` skin file or a
            :class:`~hapticsim.perception.tactile.SkinPreset` (stored as the loaded preset).
        taxel_model: with tactile sensing, where taxel depths come from:
            ``"hapticsim"`` (its own model against the exact solid) or ``"mujoco"`` (MuJoCo's
            ``<tactile>`` sensor).
        steer_on: with tactile sensing, what the probing and contour-following controllers
            steer on: ``"skin"`` (default: each touching pad's contact, force and normal
            estimated from its frames, :meth:`~hapticsim.sim.simulator.Simulator.touch`) or
            ``"contacts"`` (MuJoCo's contact point and normal with the skin's force law, as
            before the skin closed the loop); exact sensing steers on MuJoCo's contacts.
        object_dynamics: how the object is held (SPEC §12): ``"fixed"`` (default, a static
            body), ``"resting"`` or ``"held"``, or an
            :class:`~hapticsim.sim.dynamics.ObjectDynamics` with its mass or density and clamp
            (stored as one).
        force_limit: the largest normal force [N] a fingertip may press with (gentle
            exploration, SPEC §12): the probes record and the contour following presses below it
            (:func:`~hapticsim.sim.explorer.force_limited`) and a finger pressing harder backs
            off at once (:class:`~hapticsim.sim.simulator.Simulator`); None (default): no limit.
    """

    mesh_resolution: int = DEFAULT_MESH_RESOLUTION
    friction: float = DEFAULT_FRICTION
    timestep: float = DEFAULT_TIMESTEP
    workspace: Workspace = field(default_factory=Workspace)
    hand: HandDescription | str = "hapticsim"
    sensing: str = "exact"
    skin: SkinPreset | str = "ideal"
    taxel_model: str = "hapticsim"
    steer_on: str = "skin"
    object_dynamics: ObjectDynamics | str = "fixed"
    force_limit: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "hand", load_hand(self.hand))
        object.__setattr__(self, "object_dynamics", dynamics_arg(self.object_dynamics))
        limit = self.force_limit
        if limit is not None and (isinstance(limit, bool) or not isinstance(limit, (int, float))
                                  or not 0.0 < limit <= 10.0):  # fmt: skip
            raise InvalidInputError(f"`force_limit` must be a force in (0, 10] N, got {limit!r}")
        if self.sensing not in SENSINGS:
            raise ChoiceError("sensing", self.sensing, SENSINGS)
        object.__setattr__(self, "skin", load_skin(self.skin))
        if self.taxel_model not in TAXEL_MODELS:
            raise ChoiceError("taxel_model", self.taxel_model, TAXEL_MODELS)
        if self.steer_on not in STEERINGS:
            raise ChoiceError("steer_on", self.steer_on, STEERINGS)
        positive_int(self.mesh_resolution, "mesh_resolution", minimum=16)
        finite_float(self.friction, "friction", 0.0, 1.0)
        if not 0.0 < finite_float(self.timestep, "timestep") <= 0.005:
            raise SimulationError(f"`timestep` must be in (0, 0.005] s, got {self.timestep!r}")


@dataclass(frozen=True, eq=False)
class Scene:
    """A compiled scene.

    Attributes:
        model: the compiled ``mujoco.MjModel``.
        truth: the object in the world frame (ground truth): a superquadric or a mesh solid.
        hand: ids and kinematics of the hand.
        object_geom_id: id of the object's (first) mesh geom.
        object_body_id: id of the object's body.
        stand_geom_id: id of the stand (post) under the object.
        table_top_z: height of the table top [m, world].
        config: the build configuration.
        object_geom_ids: ids of all the object's geoms (convex parts of a non-convex mesh).
        collision_method: how the object's collision geometry was made.
        pads: with tactile sensing, every finger's pad: (carrier kind, carrier id, layout,
            reach) (:func:`hapticsim.sim.tactile.pad_layouts`); else empty.
        placed: a free object (SPEC §12): `truth` as it was placed, before it settled (`truth`
            is the object at rest before the first touch); None for a fixed object.
    """

    model: mujoco.MjModel
    truth: Solid
    hand: Hand
    object_geom_id: int
    object_body_id: int
    stand_geom_id: int
    table_top_z: float
    config: SceneConfig
    object_geom_ids: tuple[int, ...] = ()
    collision_method: str = ""
    pads: tuple = ()
    placed: Solid | None = None

    @property
    def free(self) -> bool:
        """True when the object can move (:class:`~hapticsim.sim.dynamics.ObjectDynamics`)."""
        return self.config.object_dynamics.free

    def __post_init__(self) -> None:
        if not self.object_geom_ids:
            object.__setattr__(self, "object_geom_ids", (self.object_geom_id,))


@dataclass(frozen=True)
class _Layout:
    """Where the object's surroundings go for one pose of the object (world frame)."""

    foot: Array  # (3,) lowest object vertex nearest the centre [m]
    table_top_z: float  # [m]
    stand_radius: float  # [m]
    eye: Array  # (3,) camera position [m]
    xyaxes: Array  # (6,) camera x and y axes

    @property
    def stand_pos(self) -> list[float]:
        half = 0.5 * (STAND_HEIGHT + 0.002)
        return [float(self.foot[0]), float(self.foot[1]), self.table_top_z + half]

    @property
    def table_pos(self) -> list[float]:
        return [float(self.foot[0]), float(self.foot[1]), self.table_top_z]


def _layout(truth: Solid, collision: CollisionParts) -> _Layout:
    """The stand under the object's lowest point nearest the centre (2 mm into the object;
    :func:`~hapticsim.sim.object_mesh.support_foot`), the table :data:`STAND_HEIGHT` below the
    object's lowest point, the overview camera looking at it."""
    vertices_world = collision.vertices_world
    low_z = float(vertices_world[:, 2].min())
    foot = support_foot(truth, vertices_world)
    eye = truth.center + np.array([0.32, -0.30, 0.20])
    forward = (truth.center - eye) / np.linalg.norm(truth.center - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    return _Layout(
        foot=foot, table_top_z=low_z - STAND_HEIGHT,
        stand_radius=support_radius(truth, STAND_RADIUS), eye=eye,
        xyaxes=np.concatenate([right, np.cross(right, forward)]),
    )  # fmt: skip


def build_scene(truth: Solid, config: SceneConfig | None = None) -> Scene:
    """Compose hand + table + object into a compiled model.

    Args:
        truth: the object, posed in the world frame (a superquadric or a mesh solid).
        config: build options (defaults: :class:`SceneConfig`).

    Returns:
        The scene; make an ``mujoco.MjData`` (or a :class:`~hapticsim.sim.simulator.Simulator`)
        from ``scene.model``.

    Raises:
        SimulationError: the object is too large for the hand or outside its workspace, or a
            non-convex mesh cannot be decomposed into convex parts.
    """
    return _compile(solid_arg(truth, "truth"), config)[0]


def _compile(
    truth: Solid, config: SceneConfig | None, primitive: Any = None
) -> tuple[Scene, CollisionParts]:
    """The scene and the object's collision parts (body frame); with `primitive` (a
    ``mujoco.mjtGeom`` box or ellipsoid), the object collides as that primitive of half sizes
    ``truth.a`` (planning scenes, :class:`PlanningSceneCache`) and the parts only lay out its
    surroundings."""
    config = SceneConfig() if config is None else config
    config.workspace.check_object(truth)

    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.modelname = f"hapticsim_{config.hand.name}"
    spec.option.timestep = config.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    attach_hand(spec, config.hand, config.friction)

    collision = collision_parts(truth, config.mesh_resolution)
    layout = _layout(truth, collision)
    body = spec.worldbody.add_body(
        name=OBJECT_NAME,
        pos=collision.body_position.tolist(),
        quat=matrix_to_quaternion(collision.body_rotation).tolist(),
    )
    for k, vertices in enumerate(collision.parts):
        if primitive is not None:
            body.add_geom(name=OBJECT_NAME, type=primitive, size=truth.a.tolist(), contype=1,
                          conaffinity=2, rgba=[0.35, 0.55, 0.85, 1.0])  # fmt: skip
            collision = replace(collision, method=f"{primitive.name[8:].lower()} primitive")
            break
        spec.add_mesh(name=_part_name(k), uservert=vertices.ravel().tolist())
        body.add_geom(
            name=_part_name(k),
            type=mujoco.mjtGeom.mjGEOM_MESH,
            meshname=_part_name(k),
            contype=1,
            conaffinity=2,
            condim=3,
            friction=[config.friction, 0.005, 0.0001],
            rgba=[0.35, 0.55, 0.85, 1.0],
        )
    if config.sensing == "tactile":
        # MuJoCo's soft friction lets a pressed fingertip creep long before Coulomb's limit (a
        # tip pressed by 0.5 N slid at 1 mm/s under 0.21 mu N): the no-slip passes hold it until
        # mu N (1.01 mu N), where the skin's taxels all slip (tests/sim/test_traction.py)
        spec.option.noslip_iterations = NOSLIP_ITERATIONS
        # and a soft friction row creeps while it holds, which moves MuJoCo's normal force off
        # its static law (the skin's: TactileHand.follow_skin); friction 100 times stiffer than
        # the normal rows brought the Shadow hand's settled presses from 0.48 to 0.11 (p95 of
        # |skin / MuJoCo - 1|; docs/tactile/README.md)
        spec.option.impratio = SKIN_IMPRATIO
    dynamics = config.object_dynamics
    if dynamics.free and primitive is None:
        add_dynamics(spec, body, truth, dynamics, collision, layout.foot)
        # MuJoCo's soft friction lets a loaded contact creep (a resting 400 g cube turned 1
        # degree a second under 0.03 N m, half the torque its friction holds); the no-slip
        # solver's passes stop that (0.02 degrees).
        spec.option.noslip_iterations = NOSLIP_ITERATIONS
        if dynamics.kind == "resting":
            # an object at rest in its cradle, untouched, sleeps (MuJoCo's sleeping islands: its
            # pin contacts leave the collision and the solver until a finger wakes it); with a
            # 0.3 N limit this took explore's time 1.70-2.06 -> 1.33-1.54 times a fixed scene's,
            # and over 168 runs 43 objects tipped over asleep against 42 awake
            # (docs/objects/moving)
            spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    spec.worldbody.add_geom(
        name=STAND_NAME,
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[layout.stand_radius, 0.5 * (STAND_HEIGHT + 0.002), 0.0],
        pos=layout.stand_pos,
        contype=1,
        conaffinity=2,
        rgba=[0.3, 0.3, 0.3, 1.0],
    )
    table = mujoco.MjSpec.from_file(str(model_path("table.xml")))
    frame = spec.worldbody.add_frame(pos=layout.table_pos)
    spec.attach(table, frame=frame, prefix=TABLE_PREFIX)

    spec.worldbody.add_light(name="key", pos=[0.3, -0.4, 1.2], dir=[-0.3, 0.4, -1.0])
    spec.worldbody.add_light(name="fill", pos=[-0.5, 0.3, 1.0], dir=[0.5, -0.3, -1.0])
    spec.worldbody.add_camera(
        name=CAMERA_NAME, pos=layout.eye.tolist(), xyaxes=layout.xyaxes.tolist(), fovy=45.0
    )
    if config.sensing == "tactile":
        scene = _compile_tactile(spec, truth, layout, config, collision)
    else:
        scene = _scene(compile_scene(spec), truth, layout, config, collision)
    if dynamics.free and primitive is None:
        scene = _settled(scene)
    return scene, collision


def _settled(scene: Scene) -> Scene:
    """A free object's scene with the object at rest (:func:`~hapticsim.sim.dynamics.settle`):
    its model's reference pose and its truth where it came to rest."""
    from hapticsim.sim.dynamics import relative_motion

    model, hand = scene.model, scene.hand
    placed, rest = settle(model, scene.object_body_id, hand.palm_qpos_adr, hand.mocap_id,
                  scene.config.object_dynamics.kind)  # fmt: skip
    rotation, translation = relative_motion(rest, placed)
    return replace(scene, truth=scene.truth.transformed(rotation, translation), placed=scene.truth)


def _compile_tactile(
    spec: mujoco.MjSpec, truth: Any, layout: _Layout, config: SceneConfig,
    collision: CollisionParts,
) -> Scene:  # fmt: skip
    """Compile a scene whose hand has a skin (:func:`hapticsim.sim.tactile.prepare_skin`); with
    MuJoCo's taxel model, compile once to lay the pads out on the fingertips, add them, and
    compile again."""

    hand = config.hand
    tips = [touching_geom_name(f) for f in hand.fingers]
    prepare_skin(spec, hand, config.skin, config.taxel_model, tips)
    model = compile_scene(spec)
    pads = tuple(pad_layouts(model, Hand(model, hand), config.skin))
    if config.taxel_model == "mujoco":  # the pads' ids stay: they are added after them
        carriers = []
        for kind, ident, pad, _ in pads:
            geom = kind == "geom"
            body = int(model.geom_bodyid[ident] if geom else model.site_bodyid[ident])
            pos = (model.geom_pos if geom else model.site_pos)[ident]
            quat = (model.geom_quat if geom else model.site_quat)[ident]
            carriers.append((model.body(body).name, pos.copy(), quat.copy(), pad))
        add_mujoco_pads(spec, carriers)
        model = compile_scene(spec)
    return replace(_scene(model, truth, layout, config, collision), pads=pads)


def _part_name(k: int) -> str:
    """Name of the mesh and geom of the object's k-th convex part."""
    return OBJECT_NAME if k == 0 else f"{OBJECT_NAME}_{k}"


def _scene(
    model: mujoco.MjModel,
    truth: Solid,
    layout: _Layout,
    config: SceneConfig,
    collision: CollisionParts,
) -> Scene:
    def ident(obj: mujoco.mjtObj, name: str) -> int:
        return int(mujoco.mj_name2id(model, obj, name))

    parts = range(len(collision.parts))
    geoms = tuple(ident(mujoco.mjtObj.mjOBJ_GEOM, _part_name(k)) for k in parts)
    return Scene(
        model=model,
        truth=truth,
        hand=Hand(model, config.hand),
        object_geom_id=ident(mujoco.mjtObj.mjOBJ_GEOM, OBJECT_NAME),
        object_body_id=ident(mujoco.mjtObj.mjOBJ_BODY, OBJECT_NAME),
        stand_geom_id=ident(mujoco.mjtObj.mjOBJ_GEOM, STAND_NAME),
        table_top_z=layout.table_top_z,
        config=config,
        object_geom_ids=geoms,
        collision_method=collision.method,
    )


def _same_pose(a: Solid, b: Solid) -> bool:
    """True when two solids of equal :meth:`~hapticsim.geometry.solid.Solid.shape_key` sit at
    the same pose."""
    (ra, pa), (rb, pb) = a.pose, b.pose
    return bool(np.array_equal(ra, rb) and np.array_equal(pa, pb))


def _moved(scene: Scene, collision: CollisionParts, truth: Solid) -> Scene:
    """A copy of `scene` with its object at the pose of `truth` (same body-frame shape): the
    object body, the stand, the table and the camera move; nothing is compiled again."""
    scene.config.workspace.check_object(truth)
    rotation, position = truth.pose
    collision = CollisionParts(collision.parts, position, rotation, collision.method)
    layout = _layout(truth, collision)
    model = copy.copy(scene.model)
    model.body_pos[scene.object_body_id] = position
    model.body_quat[scene.object_body_id] = matrix_to_quaternion(rotation)
    model.geom_pos[scene.stand_geom_id] = layout.stand_pos
    table = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, TABLE_PREFIX + "table"))
    model.body_pos[table] = layout.table_pos
    camera = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, CAMERA_NAME))
    x, y = layout.xyaxes[:3], layout.xyaxes[3:]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.column_stack([x, y, np.cross(x, y)]).ravel())
    model.cam_pos[camera] = layout.eye
    model.cam_quat[camera] = quat
    return replace(_scene(model, truth, layout, scene.config, collision), pads=scene.pads)


def _config_key(config: SceneConfig) -> tuple[object, ...]:
    w = config.workspace
    return (config.mesh_resolution, config.friction, config.timestep, w.base_world.tobytes(),
            w.reach, w.max_object_radius, w.clearance, config.hand.key, config.sensing,
            repr(config.skin), config.taxel_model, repr(config.object_dynamics))  # fmt: skip


class SceneCache:
    """Compiled scenes kept by object, so that an object that comes back is not compiled again.

    Compiling a scene costs about 0.1 s, nearly all of it MuJoCo's convex hull of the object's
    16k-vertex mesh; a cached scene costs nothing, and an object seen before in another pose (the
    same body-frame shape) costs a copy of the model (~1 ms) with its object, stand, table and
    camera moved. The least recently used object is dropped when `capacity` objects are kept.

    Args:
        capacity: number of objects (body-frame shapes and configurations) to keep, >= 1.
    """

    def __init__(self, capacity: int = 8) -> None:
        self.capacity = positive_int(capacity, "capacity")
        self._entries: OrderedDict[tuple[object, ...], tuple[Scene, CollisionParts]] = OrderedDict()
        self.hits = 0
        self.misses = 0

    def __len__(self) -> int:
        return len(self._entries)

    def scene(self, truth: Solid, config: SceneConfig | None = None) -> Scene:
        """The scene of `truth` under `config` (see :func:`build_scene`), from the cache when
        the same body-frame shape was built before.

        Raises:
            SimulationError: the object is too large for the hand or outside its workspace.
        """
        truth = solid_arg(truth, "truth")
        config = SceneConfig() if config is None else config
        key = (truth.shape_key(), _config_key(config))
        entry = self._entries.get(key)
        if entry is not None:
            scene, collision = entry
            placed = scene.truth if scene.placed is None else scene.placed
            if _same_pose(placed, truth):  # equal keys and poses: the same solid
                self.hits += 1
                self._entries.move_to_end(key)
                return scene
            if not scene.free:  # a free object's cradle and resting pose depend on its pose
                self.hits += 1
                self._entries.move_to_end(key)
                return _moved(scene, collision, truth)
        self.misses += 1
        entry = _compile(truth, config)
        self._entries[key] = entry
        self._entries.move_to_end(key)
        if len(self._entries) > self.capacity:
            self._entries.popitem(last=False)
        return entry[0]

    def clear(self) -> None:
        """Drop every cached scene."""
        self._entries.clear()


# ----------------------------------------------------------------------------- planning scenes
def planning_primitive(shape: Solid) -> Any:
    """The primitive geom (``mujoco.mjtGeom``) that stands for a rough object in planning, or None.

    An untapered superquadric with both exponents 1 is an ellipsoid; one with both exponents at
    most :data:`PRIMITIVE_BOX_EPS` is a box of its semi-axes (which contains it: 1.6 mm beyond
    it at the corners of a 3 cm cube with exponents 0.1). Those are the two shapes
    :func:`~hapticsim.perception.vision.vision_estimate` gives.
    """
    if not isinstance(shape, Superquadric) or np.any(shape.taper != 0.0):
        return None
    if np.all(shape.eps == 1.0):
        return mujoco.mjtGeom.mjGEOM_ELLIPSOID
    if np.all(shape.eps <= PRIMITIVE_BOX_EPS):
        return mujoco.mjtGeom.mjGEOM_BOX
    return None


#: Largest exponent of a rough object planned on as a box (:func:`planning_primitive`).
PRIMITIVE_BOX_EPS: float = 0.2


def _replace_primitive(scene: Scene, shape: Superquadric, collision: CollisionParts) -> Scene:
    """`scene` (its model changed in place) with its primitive object resized and moved to
    `shape`, and the stand, the table and the camera placed for it."""
    model = scene.model
    layout = _layout(shape, collision)
    g, stand = scene.object_geom_id, scene.stand_geom_id
    a = shape.a
    model.geom_size[g] = a
    box = model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
    model.geom_rbound[g] = float(np.linalg.norm(a)) if box else float(np.max(a))
    model.geom_aabb[g] = [0.0, 0.0, 0.0, *a]
    model.body_pos[scene.object_body_id] = shape.center
    model.body_quat[scene.object_body_id] = shape.quaternion
    radius, half = layout.stand_radius, float(model.geom_size[stand][1])
    model.geom_size[stand][0] = radius
    model.geom_rbound[stand] = float(np.hypot(radius, half))
    model.geom_aabb[stand] = [0.0, 0.0, 0.0, radius, radius, half]
    model.geom_pos[stand] = layout.stand_pos
    # the mid-phase's bounding boxes: one node each for the object's body and the world body
    # (whose only geom is the stand; PlanningSceneCache checks both)
    model.bvh_aabb[model.body_bvhadr[scene.object_body_id]] = [0.0, 0.0, 0.0, *a]
    model.bvh_aabb[model.body_bvhadr[0]] = [*layout.stand_pos, radius, radius, half]
    table = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, TABLE_PREFIX + "table"))
    model.body_pos[table] = layout.table_pos
    return replace(scene, truth=shape, table_top_z=layout.table_top_z)


def _resizable(scene: Scene) -> bool:
    """True when :func:`_replace_primitive` can update every bounding volume of `scene`: the
    object body and the world body hold one geom each (the primitive, the stand)."""
    m = scene.model
    world_geoms = int(np.sum(m.geom_bodyid == 0))
    return bool(m.body_bvhnum[scene.object_body_id] == 1 and m.body_bvhnum[0] == 1
                and world_geoms == 1 and len(scene.object_geom_ids) == 1)  # fmt: skip


class PlanningSceneCache:
    """Planning scenes (the rough object, :class:`~hapticsim.sim.planning.PalmPlanner`) for a
    sequence of episodes, without compiling one per episode.

    A rough object that a primitive stands for (:func:`planning_primitive`: what the vision
    estimate gives) is planned on as that box or ellipsoid, in a model compiled once per kind and
    configuration and then resized and moved in place: the planning scene returned before for
    the same kind is changed with it, so use one at a time (one episode's explorer). Other rough
    objects get a compiled mesh scene (:func:`build_scene`).
    """

    def __init__(self) -> None:
        self._models: dict[tuple[object, ...], Scene] = {}

    def scene(self, rough_shape: Solid, config: SceneConfig) -> Scene:
        """The planning scene of `rough_shape` under `config` (see the class docstring)."""
        primitive = planning_primitive(rough_shape)
        if primitive is None:
            return build_scene(rough_shape, config)
        key = (int(primitive), _config_key(config))
        scene = self._models.get(key)
        if scene is None:
            scene = build_planning_scene(rough_shape, config)
            if _resizable(scene):
                self._models[key] = scene
            return scene
        config.workspace.check_object(rough_shape)
        collision = collision_parts(rough_shape, config.mesh_resolution)
        return _replace_primitive(scene, rough_shape, collision)


def build_planning_scene(rough_shape: Solid, config: SceneConfig) -> Scene:
    """A planning scene of a rough object: the primitive that stands for it
    (:func:`planning_primitive`), else its mesh (:func:`build_scene`)."""
    primitive = planning_primitive(rough_shape)
    if primitive is None:
        return build_scene(rough_shape, config)
    return _compile(solid_arg(rough_shape, "rough_shape"), config, primitive)[0]


__all__ = [
    "DEFAULT_FRICTION",
    "DEFAULT_MESH_RESOLUTION",
    "DEFAULT_TIMESTEP",
    "STAND_HEIGHT",
    "PlanningSceneCache",
    "Scene",
    "SceneCache",
    "planning_primitive",
    "SceneConfig",
    "build_planning_scene",
    "build_scene",
]
