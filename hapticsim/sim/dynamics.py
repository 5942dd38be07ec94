"""Objects that move (SPEC §12): how the object is held in the scene, and its pose while it moves.

Three kinds (:data:`OBJECT_DYNAMICS`):

- ``fixed`` (default): the object is a static body on its post, as in the paper; nothing here
  touches such a scene, so it runs bit for bit as before.
- ``resting``: a free body (MuJoCo free joint) of a stated mass under gravity, standing in a
  *cradle* on the post: eight pins on a circle under its bottom, each as high as the bottom
  above it (a lab's pin holder shaped to the object), so that a sphere or an ellipsoid on its
  tip rests as a box does, and the fingers still reach around the bottom edges. The pins meet
  a coarse support hull of the object (:func:`support_hull`); the scene runs MuJoCo's no-slip
  solver (see :mod:`hapticsim.sim.scene`). A push that beats friction slides the object, a push
  above its centre of mass tips it.
- ``held``: a free body on a stiff spring-damper to where it was placed (a lab's soft clamp):
  three slide joints and a ball joint with stiffness :attr:`ObjectDynamics.clamp_stiffness`
  [N/m] (and ``k L^2`` [N m/rad] for the rotation, ``L`` the object's bounding radius),
  critically damped, the springs' rest positions set so that gravity leaves the object where
  it was placed. A 0.5 N press moves it by a quarter of a millimetre at the default 2,000 N/m.

The mass is ``density * volume`` (default density :data:`DEFAULT_DENSITY`) unless given; the
centre of mass and the inertia tensor come from 4,096 interior points of the truth (seed 0).

Before the first touch the object *settles* (:func:`settle`): the scene steps (up to 1 s, until it
is at rest) with the hand far above it, and the pose it comes to rest in is the model's
reference pose (``qpos0``), so every reset starts from rest. An object that tips over in its
cradle there (more than 5 degrees or 10 mm), or is still moving after 1 s, is refused, said as
such. During an exploration an object that tips over (:data:`TOPPLE_ANGLE_DEG`) or leaves its
place (:data:`LEAVE_DISTANCE`) ends the run with that stop reason (:class:`MotionWatch`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import ChoiceError, InvalidInputError, SimulationError
from hapticsim.geometry.rotations import quaternion_to_matrix

Array = NDArray[np.float64]

#: The kinds of object dynamics.
OBJECT_DYNAMICS: tuple[str, ...] = ("fixed", "resting", "held")
#: Default density of a free object [kg/m^3] (a packed box, wood): a 6 cm cube weighs 108 g.
DEFAULT_DENSITY: float = 500.0
#: Default stiffness of the ``held`` clamp [N/m].
DEFAULT_CLAMP_STIFFNESS: float = 2000.0
#: Friction of the cradle's pins (rubber on a lab holder).
CRADLE_FRICTION: float = 0.6
#: Radius of the cradle's pins [m] and their number.
CRADLE_PIN_RADIUS: float = 0.002
CRADLE_PINS: int = 8
#: An object tilted by more than this [deg] from where it started has tipped over.
TOPPLE_ANGLE_DEG: float = 20.0
#: An object whose centre moved farther than this [m] from where it started has left its place.
LEAVE_DISTANCE: float = 0.05
#: The longest an object settles before the first touch [s], in steps of SETTLE_CHUNK [s],
#: until its speed is below REST_SPEED [m/s or rad/s].
SETTLE_TIME: float = 1.0
SETTLE_CHUNK: float = 0.1
REST_SPEED: float = 1e-3
#: The resting object's support geom: its name, its collision bit (the pins' conaffinity), the
#: share of the object's height it covers from the bottom and its most vertices.
SUPPORT_NAME: str = "object_support"
SUPPORT_BIT: int = 8
SUPPORT_DEPTH: float = 0.35
SUPPORT_VERTICES: int = 400
#: Name of the object's free joint and the cradle geoms' prefix.
JOINT_NAME: str = "object_free"
CRADLE_PREFIX: str = "cradle_"


@dataclass(frozen=True)
class ObjectDynamics:
    """How the object is held (module docstring).

    Attributes:
        kind: ``"fixed"``, ``"resting"`` or ``"held"``.
        density: density of a free object [kg/m^3], > 0 (used when `mass` is None).
        mass: mass of a free object [kg], > 0, or None (from `density`).
        clamp_stiffness: stiffness of the ``held`` clamp [N/m], > 0.

    Raises:
        InvalidInputError: an unknown kind (listing the choices), or a mass, density or
            stiffness that is not a positive finite number.
    """

    kind: str = "fixed"
    density: float = DEFAULT_DENSITY
    mass: float | None = None
    clamp_stiffness: float = DEFAULT_CLAMP_STIFFNESS

    def __post_init__(self) -> None:
        if self.kind not in OBJECT_DYNAMICS:
            raise ChoiceError("object_dynamics", self.kind, OBJECT_DYNAMICS)
        object.__setattr__(self, "density", _positive(self.density, "object density", "kg/m^3"))
        if self.mass is not None:
            object.__setattr__(self, "mass", _positive(self.mass, "object mass", "kg"))
        stiffness = _positive(self.clamp_stiffness, "clamp stiffness", "N/m")
        object.__setattr__(self, "clamp_stiffness", stiffness)

    @property
    def free(self) -> bool:
        """True when the object can move (``resting`` or ``held``)."""
        return self.kind != "fixed"

    def object_mass(self, truth: Any) -> float:
        """The mass [kg] of `truth` under these dynamics."""
        return float(self.mass) if self.mass is not None else self.density * float(truth.volume)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (``metrics.json``'s ``object_dynamics``)."""
        out: dict[str, Any] = {"kind": self.kind}
        if self.free:
            out["mass_kg"] = self.mass
            out["density_kg_m3"] = None if self.mass is not None else self.density
        if self.kind == "held":
            out["clamp_stiffness_n_m"] = self.clamp_stiffness
        return out


def _positive(value: Any, name: str, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise InvalidInputError(f"the {name} must be a number [{unit}], got {value!r}")
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise InvalidInputError(f"the {name} must be positive and finite [{unit}], got {value!r}")
    return value


def dynamics_arg(value: Any) -> ObjectDynamics:
    """An :class:`ObjectDynamics` from itself or a kind name."""
    if isinstance(value, ObjectDynamics):
        return value
    if isinstance(value, str):
        return ObjectDynamics(kind=value)
    raise InvalidInputError(
        f"`object_dynamics` must be one of {', '.join(OBJECT_DYNAMICS)} or an ObjectDynamics, "
        f"got {value!r}"
    )


# ----------------------------------------------------------------------------- building
def mass_properties(truth: Any, mass: float, body_position: Array, body_rotation: Array
                    ) -> tuple[Array, Array]:  # fmt: skip
    """Centre of mass (3,) [m] and full inertia (6,: xx, yy, zz, xy, xz, yz) [kg m^2] in the
    object's body frame, from 4,096 interior points (seed 0: the same object, the same
    numbers)."""
    points = truth.sample_interior(4096, 0)
    local = (points - body_position) @ body_rotation
    com = local.mean(axis=0)
    r = local - com
    cov = mass * (r.T @ r) / len(r)
    inertia = np.trace(cov) * np.eye(3) - cov
    return com, np.array([inertia[0, 0], inertia[1, 1], inertia[2, 2],
                          inertia[0, 1], inertia[0, 2], inertia[1, 2]])  # fmt: skip


def add_dynamics(spec: mujoco.MjSpec, body: Any, truth: Any, dynamics: ObjectDynamics,
                 collision: Any, foot: Array) -> None:  # fmt: skip
    """Make the object body of `spec` free (module docstring): its mass and inertia, its joints
    and, resting, the cradle under it and the object's support geom (:func:`support_hull`).

    Args:
        collision: the object's :class:`~hapticsim.sim.object_mesh.CollisionParts`.
        foot: (3,) the object's lowest point nearest its centre [m, world].
    """
    body_position, body_rotation = collision.body_position, collision.body_rotation
    vertices_world = collision.vertices_world
    mass = dynamics.object_mass(truth)
    com, inertia = mass_properties(truth, mass, body_position, body_rotation)
    body.explicitinertial = True
    body.mass = mass
    body.ipos = com.tolist()
    body.fullinertia = inertia.tolist()
    if dynamics.kind == "resting":
        body.add_freejoint(name=JOINT_NAME)
        _add_cradle(spec, vertices_world, foot)
        spec.add_mesh(name=SUPPORT_NAME, uservert=support_hull(collision).ravel().tolist())
        body.add_geom(name=SUPPORT_NAME, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=SUPPORT_NAME,
                      contype=SUPPORT_BIT, conaffinity=0, condim=3, group=3,
                      friction=[CRADLE_FRICTION, 0.005, 0.0001], rgba=[0, 0, 0, 0])  # fmt: skip
        return
    k = dynamics.clamp_stiffness
    g = 9.81  # MuJoCo's default gravity, along -z
    sag = body_rotation.T @ np.array([0.0, 0.0, mass * g / k])  # the springs hold the weight
    for axis in range(3):
        joint = body.add_joint(name=f"{JOINT_NAME}_{'xyz'[axis]}", type=mujoco.mjtJoint.mjJNT_SLIDE)
        joint.axis = np.eye(3)[axis].tolist()
        joint.pos = com.tolist()
        joint.stiffness = [k, 0.0, 0.0]
        joint.springref = float(sag[axis])
        joint.damping = [2.0 * math.sqrt(k * mass), 0.0, 0.0]
    radius = float(truth.bounding_radius)
    k_rot = k * radius**2
    ball = body.add_joint(name=f"{JOINT_NAME}_ball", type=mujoco.mjtJoint.mjJNT_BALL)
    ball.pos = com.tolist()
    ball.stiffness = [k_rot, 0.0, 0.0]
    ball.damping = [2.0 * math.sqrt(k_rot * float(np.max(inertia[:3]))), 0.0, 0.0]


def cradle_pins(vertices_world: Array, foot: Array) -> Array:
    """(:data:`CRADLE_PINS`, 3) float, the centres [m] of the cradle's pins: on a circle about
    the vertical through `foot` of 0.8 of the object's smaller horizontal half-width (4 to 40 mm),
    each just under the object's lowest surface point above it (the nearest hull vertices)."""
    half = 0.5 * (vertices_world[:, :2].max(axis=0) - vertices_world[:, :2].min(axis=0))
    radius = float(np.clip(0.8 * half.min(), 0.004, 0.04))
    angles = 2.0 * np.pi * np.arange(CRADLE_PINS) / CRADLE_PINS
    pins = np.column_stack([foot[0] + radius * np.cos(angles), foot[1] + radius * np.sin(angles),
                            np.zeros(CRADLE_PINS)])  # fmt: skip
    for k in range(CRADLE_PINS):
        gap = np.hypot(*(vertices_world[:, :2] - pins[k, :2]).T)
        near = gap < 0.002
        if not near.any():
            near = gap <= np.sort(gap)[4]
        pins[k, 2] = float(vertices_world[near, 2].min()) - CRADLE_PIN_RADIUS
    return pins


def _add_cradle(spec: mujoco.MjSpec, vertices_world: Array, foot: Array) -> None:
    # the pins collide with the hand (contype 1 against its conaffinity 1) and with the object's
    # support geom only (conaffinity SUPPORT_BIT), not with its fine collision hull
    for k, centre in enumerate(cradle_pins(vertices_world, foot)):
        spec.worldbody.add_geom(
            name=f"{CRADLE_PREFIX}{k}", type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[CRADLE_PIN_RADIUS, 0.0, 0.0], pos=centre.tolist(), contype=1,
            conaffinity=SUPPORT_BIT, condim=3, friction=[CRADLE_FRICTION, 0.005, 0.0001],
            rgba=[0.25, 0.25, 0.25, 1.0],
        )  # fmt: skip


def support_hull(collision: Any) -> Array:
    """(k, 3) float, the vertices [m, body frame] of the geom a resting object stands on its pins
    with: the collision hull's vertices in the lowest :data:`SUPPORT_DEPTH` of its height, every
    n-th of them so that at most :data:`SUPPORT_VERTICES` are left. The pins, always in contact,
    meet this small hull instead of the object's fine one (8,066 vertices for a superquadric),
    which more than doubled the cost of a physics step; its hull lies inside the fine one, by
    less than the fine mesh's own chord error at the bottom."""
    vertices = np.concatenate(collision.parts)
    world = vertices @ collision.body_rotation.T + collision.body_position
    z = world[:, 2]
    low = vertices[z <= z.min() + SUPPORT_DEPTH * (z.max() - z.min())]
    step = max(1, int(np.ceil(len(low) / SUPPORT_VERTICES)))
    return low[::step]


# ----------------------------------------------------------------------------- running
def object_pose(model: mujoco.MjModel, data: mujoco.MjData, body_id: int) -> Array:
    """(7,) float, the object body's position [m] and quaternion (w first) in the world."""
    return np.concatenate([data.xpos[body_id], data.xquat[body_id]])


def relative_motion(pose: Array, initial: Array) -> tuple[Array, Array]:
    """The rigid motion (rotation (3, 3), translation (3,)) taking the object from its pose
    `initial` to `pose` (both (7,), :func:`object_pose`): ``x -> R x + t``."""
    r_now, r_0 = quaternion_to_matrix(pose[3:]), quaternion_to_matrix(initial[3:])
    rotation = r_now @ r_0.T
    return rotation, pose[:3] - rotation @ initial[:3]


def pose_change(pose: Array, initial: Array) -> tuple[float, float]:
    """How far [m] and by what angle [deg] the object moved from `initial` to `pose`."""
    rotation, _ = relative_motion(pose, initial)
    cos = np.clip(0.5 * (np.trace(rotation) - 1.0), -1.0, 1.0)
    return float(np.linalg.norm(pose[:3] - initial[:3])), math.degrees(math.acos(cos))


def tilt_deg(pose: Array, initial: Array) -> float:
    """How far [deg] the object's vertical axis turned from `initial` to `pose` (a turn about
    the vertical is no tilt)."""
    rotation, _ = relative_motion(pose, initial)
    return math.degrees(math.acos(float(np.clip(rotation[2, 2], -1.0, 1.0))))


class MotionWatch:
    """Why the exploration of a free object must end, checked every control tick: it tipped over
    (tilted more than :data:`TOPPLE_ANGLE_DEG` from its pose at rest) or left its place (its
    centre moved more than :data:`LEAVE_DISTANCE`). Read from MuJoCo's body matrix and position,
    without quaternions (a tenth of a second per exploration less than through
    :func:`object_pose`).

    Args:
        initial: the object's pose (7,) at rest.
        body_id: its body.
    """

    def __init__(self, initial: Array, body_id: int) -> None:
        self.initial = initial
        self.body_id = body_id
        self._position = np.asarray(initial[:3], dtype=np.float64)
        self._vertical = quaternion_to_matrix(initial[3:])[2]  # the world z row at rest

    def reason(self, data: mujoco.MjData) -> str | None:
        """Why the exploration must end now, or None."""
        zrow = data.xmat[self.body_id][6:9]  # (R_now R_0^T)[2, 2] = row 2 . row 2
        cos = float(np.clip(zrow @ self._vertical, -1.0, 1.0))
        moved = float(np.linalg.norm(data.xpos[self.body_id] - self._position))
        return _reason(math.degrees(math.acos(cos)), moved)


def _reason(tilt: float, moved: float) -> str | None:
    if tilt > TOPPLE_ANGLE_DEG:
        return f"the object tipped over (tilted {tilt:.0f} degrees, more than {TOPPLE_ANGLE_DEG:g})"
    if moved > LEAVE_DISTANCE:
        return (f"the object left its place (moved {1000 * moved:.0f} mm, more than "
                f"{1000 * LEAVE_DISTANCE:.0f})")  # fmt: skip
    return None


def settle(model: mujoco.MjModel, body_id: int, palm_qpos_adr: int, mocap_id: int,
           kind: str) -> tuple[Array, Array]:  # fmt: skip
    """Let a free object come to rest with the hand far above it; its resting pose becomes the
    model's reference (``qpos0``). Returns the poses (7,) it was placed in and rests in.

    Raises:
        SimulationError: the object tips over in its cradle before the first touch.
    """
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    placed = object_pose(model, data, body_id)
    far = placed[:3] + np.array([0.0, 0.0, 0.6])
    data.qpos[palm_qpos_adr : palm_qpos_adr + 3] = far
    data.mocap_pos[mocap_id] = far
    dofs = slice(int(model.body_dofadr[body_id]),
                 int(model.body_dofadr[body_id] + model.body_dofnum[body_id]))  # fmt: skip
    chunk = int(round(SETTLE_CHUNK / model.opt.timestep))
    speed = np.inf
    while data.time < SETTLE_TIME - 1e-9 and speed > REST_SPEED:
        mujoco.mj_step(model, data, nstep=chunk)
        speed = float(np.abs(data.qvel[dofs]).max())
    rest = object_pose(model, data, body_id)
    tilt = tilt_deg(rest, placed)
    drop = float(np.linalg.norm(rest[:3] - placed[:3]))
    if tilt > 5.0 or drop > 0.01 or speed > 0.01 or not np.all(np.isfinite(rest)):
        where = "in its cradle" if kind == "resting" else "in its clamp"
        still = f", still moving at {speed:.2g} m/s or rad/s" if speed > 0.01 else ""
        raise SimulationError(
            f"the object topples before the first touch: placed {where} it tilts {tilt:.0f} "
            f"degrees and moves {1000 * drop:.0f} mm in {data.time:.1f} s{still}; stand it on "
            "a flat face or its widest end (--pose) or use --object-dynamics held"
        )
    if kind == "resting":
        adr = int(model.jnt_qposadr[model.body_jntadr[body_id]])
        model.qpos0[adr : adr + 7] = data.qpos[adr : adr + 7]
    return placed, rest


__all__ = [
    "CRADLE_PREFIX", "DEFAULT_CLAMP_STIFFNESS", "DEFAULT_DENSITY", "LEAVE_DISTANCE",
    "OBJECT_DYNAMICS", "ObjectDynamics", "TOPPLE_ANGLE_DEG", "add_dynamics", "cradle_pins",
    "dynamics_arg", "MotionWatch", "mass_properties", "object_pose", "pose_change",
    "relative_motion", "settle", "tilt_deg",
]  # fmt: skip
