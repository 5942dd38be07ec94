"""The tactile hand of a scene: a taxel pad on every fingertip, the skin's contact softness, and
the pads' readings at any physics step (SPEC §9, §11).

**Pads.** Every finger carries one pad (:class:`~hapticsim.perception.tactile.pad.PadLayout`) of
the hand's
grid (:attr:`~hapticsim.sim.hand_description.HandDescription.pad_grid`, or the skin preset's own
pitch over the same extent), laid on its fingertip (the finger's ``pad`` table: a sphere or
capsule geom's surface, a site with a radius, or a flat plate), centred on the fingertip's pulp
unless the description says otherwise (:func:`default_pad_normal`).

**Skin contact: one law for skin and physics.** With tactile sensing the touching geoms are
the skin: their contacts act at the true surface (margin and gap 0; the exact-sensing hand
reports contacts within a 1 mm margin and pushes from there, so its fingertip never sinks in),
take the skin's softness over the object's (geom priority), and hold one impedance at every
depth (:data:`SKIN_SOLIMP`). MuJoCo's soft contact is linear in the penetration, the skin's
law quadratic or steeper: after every control tick :meth:`TactileHand.follow_skin` sets each
touching fingertip's time constant so that the force MuJoCo applies at its present penetration
is the skin's integrated pressure there. A touch is recorded once its press has settled
(:meth:`~hapticsim.sim.controllers.base.FingerTask.settled`), so that ``force_exact`` is then
MuJoCo's static force. Tactile scenes also run MuJoCo's no-slip passes and a stiff friction
(:data:`~hapticsim.sim.scene.SKIN_IMPRATIO`), without which a pressed tip creeps and its normal
force leaves the static law (measured: ``docs/tactile/README.md``).

**Readings** (:meth:`TactileHand.read`): per pad, the depth of every taxel inside the object
[m], the skin's pressure after the sensor model [Pa] and the taxels' slip [m/s] (the tangential
velocity of each taxel in contact, in the pad's own (u, v) axes; MuJoCo's slip channels ignore
the pad's rotation). Depths come from one of :data:`TAXEL_MODELS`:

- ``"hapticsim"`` (default): hapticsim's own taxel model against the object's exact solid
  (:func:`~hapticsim.perception.tactile.depth.taxel_depths`: the depth along each taxel's normal,
  from the
  superquadric's inside-outside function or the mesh's containment), computed when read, so a
  physics step costs nothing more;
- ``"mujoco"``: MuJoCo's ``<tactile>`` sensor on a non-colliding, massless mesh geom of the
  pad's taxels (the object's meshes are compiled with an SDF octree, without which the sensor
  reads a mesh as nothing): the Euclidean signed distance of the collision meshes, every step.

On primitives, where both exist, the two agree within ``delta^2 / (4 R)`` plus MuJoCo's
float32 vertices (``tests/sim/test_tactile.py``, ``docs/tactile/README.md``).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import SENSINGS
from hapticsim.errors import InvalidInputError
from hapticsim.perception.tactile import (
    PadLayout,
    SkinPreset,
    TactileContact,
    estimate_contact,
    taxel_depths,
    traction_field,
)
from hapticsim.perception.tactile.pad import PadError, default_up
from hapticsim.perception.tactile.skin import PROBE_FORCE, FixedPattern
from hapticsim.sim.hand import PREFIX
from hapticsim.sim.hand_description import HandDescription

Array = NDArray[np.float64]

#: Where taxel depths come from (module docstring).
TAXEL_MODELS: tuple[str, ...] = ("hapticsim", "mujoco")
#: Ways of sensing contacts: MuJoCo's exact contact, or estimated from the taxels.
#: Effective mass [kg] of a fingertip against the object, which turns MuJoCo's time constant
#: into a static stiffness (``20 m / tau^2`` at MuJoCo's default impedance): a 20 g tip
#: measured 1000 N/m at tau = 0.02 s (``docs/tactile/README.md``).
FINGERTIP_MASS: float = 0.02
#: Longest contact time constant [s] a skin fingertip gets (the skin's law is soft at a graze).
SKIN_TAU_MAX: float = 0.1
#: Control ticks between two readings of a touching pad's force (:meth:`TactileHand.follow_skin`).
SKIN_LAW_TICKS: int = 10
#: The skin fingertips' constant impedance (MuJoCo ``solimp``): the static force is then
#: ``k imp r / R`` with one impedance at every depth. A sliding contact's normal force carries
#: besides ``mu |aref_t| / R``, the friction rows' damping; against the static force it scales
#: as ``1 / sqrt(1 - imp)`` once the time constant gives the skin's force. At 0.95 it was 96 %
#: of MuJoCo's normal force while a stroke slid (2.4 times the skin's, median; the law's
#: time constant bound kept follow_skin from taking it off); at 0.3 MuJoCo's force is the
#: skin's while sliding (median 1.00 on hapticsim's hand, 0.99-1.02 on Shadow and Adroit) and
#: at settled touches the agreement is 2-8 times closer (docs/tactile/force/README.md).
SKIN_SOLIMP: tuple[float, ...] = (0.3, 0.3, 0.001, 0.5, 2.0)
#: Name prefix of the pad geoms and meshes (MuJoCo's taxel model).
PAD_PREFIX: str = "hand/pad/"


def skin_solref(skin: SkinPreset, radius: float) -> tuple[float, float]:
    """The resting MuJoCo ``solref`` (time constant [s], damping ratio 1) of a fingertip of
    `radius` [m], before it touches (:meth:`TactileHand.follow_skin` takes over then): its
    contact carries :data:`PROBE_FORCE` at the penetration the skin's elastic law gives it.

    The skin's secant stiffness there is ``k = F / delta(F)`` (``sqrt(pi E R F / h)`` under the
    Winkler law); MuJoCo's soft contact at steady state, with the skin's impedance d
    (:data:`SKIN_SOLIMP`), has the static stiffness ``F / r = m k_ref d^2 / (1 - d) = m / ((1 -
    d) tau^2)`` on an effective mass m (:data:`FINGERTIP_MASS`), hence ``tau = sqrt(m / ((1 -
    d) k))``, at least 2 ms (twice the time step).
    """
    k = skin.skin.secant_stiffness(radius, PROBE_FORCE)
    tau = np.sqrt(FINGERTIP_MASS / ((1.0 - SKIN_SOLIMP[0]) * k))
    return (max(float(tau), 2e-3), 1.0)


def prepare_skin(spec: mujoco.MjSpec, hand: HandDescription, skin: SkinPreset,
                 taxel_model: str, tip_geoms: list[str]) -> None:  # fmt: skip
    """Make the touching geoms of an attached hand a skin (margin and gap 0, the skin's
    softness), and with MuJoCo's taxel model add a pad geom and ``<tactile>`` sensor per
    finger and an SDF octree to every object mesh (call before compiling).

    Args:
        spec: the scene spec, hand attached, object added.
        hand: the hand's description.
        skin: the skin.
        taxel_model: one of :data:`TAXEL_MODELS`.
        tip_geoms: the scene names of the fingers' touching geoms, in finger order.
    """
    for f, name in zip(hand.fingers, tip_geoms, strict=True):
        geom = spec.geom(name)
        geom.margin = 0.0
        geom.gap = 0.0
        geom.solref = list(skin_solref(skin, f.tip_radius))
        geom.solimp = list(SKIN_SOLIMP)
        geom.priority = 1  # the contact takes the skin's softness, not a mix with the object's
    if taxel_model != "mujoco":
        return
    for mesh in spec.meshes:
        if not mesh.name.startswith(PAD_PREFIX):
            mesh.needsdf = True


def add_mujoco_pads(spec: mujoco.MjSpec, pads: list[tuple[str, Array, Array, PadLayout]]) -> None:
    """Add MuJoCo's taxel model: per pad (carrier's body name, carrier's position (3,) and
    quaternion (4,) in that body, layout) a non-colliding, massless mesh geom of its taxels in
    the carrier's frame, and a ``<tactile>`` sensor on it."""
    for k, (body_name, carrier_pos, carrier_quat, layout) in enumerate(pads):
        body = spec.body(body_name)
        pos, _, _ = layout.taxels
        rows, cols = layout.shape
        faces = []
        for i in range(rows - 1):
            for j in range(cols - 1):
                a = i * cols + j
                faces += [a, a + cols, a + 1, a + 1, a + cols, a + cols + 1]
        if not faces:  # a single row or column: a degenerate strip MuJoCo still accepts
            faces = [0, 0, 0]
        name = f"{PAD_PREFIX}{k}"
        spec.add_mesh(name=name, uservert=pos.ravel().tolist(), userface=faces)
        body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name, contype=0,
                      conaffinity=0, mass=0.0, group=5, pos=list(carrier_pos),
                      quat=list(carrier_quat), rgba=[0, 0, 0, 0])  # fmt: skip
        spec.add_sensor(name=name, type=mujoco.mjtSensor.mjSENS_TACTILE,
                        objtype=mujoco.mjtObj.mjOBJ_MESH, objname=name,
                        reftype=mujoco.mjtObj.mjOBJ_GEOM, refname=name)  # fmt: skip


@dataclass(frozen=True)
class Pad:
    """One finger's pad in a compiled scene.

    Attributes:
        finger: finger index.
        layout: the taxel grid in the carrier's frame.
        carrier: ``"geom"`` or ``"site"``.
        carrier_id: the carrier's id.
        reach: the longest depth searched [m] (to the fingertip's core).
        sensor_adr: address of its ``<tactile>`` sensor's data (MuJoCo's taxel model), or -1.
    """

    finger: int
    layout: PadLayout
    carrier: str
    carrier_id: int
    reach: float
    sensor_adr: int = -1


@dataclass(frozen=True)
class TactileReading:
    """Every pad's reading at one instant.

    Attributes:
        depth: (pads, rows, cols) float, the skin's depth [m] (before the sensor model).
        pressure: (pads, rows, cols) float, the readings [Pa] (after the sensor model).
        slip: (pads, rows, cols, 2) float, the taxels' tangential velocity in the pad's (u, v)
            axes [m/s], 0 where a taxel does not touch.
        traction: (pads, rows, cols, 3) float, the skin's traction field [Pa] (before the
            sensor model): the pressure, then the traction the object exerts on the skin along
            the pad's u and v axes (:func:`~hapticsim.perception.tactile.traction_field`).
        state: (pads, rows, cols) int8, each taxel's state (0 free, 1 stick, 2 slip).
        friction: the contacts' Coulomb coefficient.
        pad_position: (pads, 3) float, the carriers' origins [m, world].
        pad_rotation: (pads, 3, 3) float, the carriers' orientations (columns: their axes).
        time: simulation time [s].
    """

    depth: Array
    pressure: Array
    slip: Array
    pad_position: Array
    pad_rotation: Array
    time: float
    traction: Array
    state: NDArray[np.int8]
    friction: float


@dataclass(frozen=True)
class SensedContact:
    """A recorded touch as the skin felt it.

    Attributes:
        estimate: the contact estimated from the finger's pad, or None when the pad felt
            nothing (the touch is then not recorded).
        reading: every pad's reading at the moment of the touch.
    """

    estimate: TactileContact | None
    reading: TactileReading


def tip_object_contacts(data: mujoco.MjData, objects: set[int],
                        tip_finger: dict[int, int]) -> Iterator[tuple[int, int, bool]]:  # fmt: skip
    """MuJoCo's active contacts between a finger's touching geom (`tip_finger`: geom id ->
    finger) and the object's geoms: (contact index, finger, whether the object is
    ``geom[0]``)."""
    con = data.contact
    efc = None  # each attribute of ``data.contact`` is a fresh copy: read it once, if needed
    for i, (g0, g1) in enumerate(con.geom.tolist()):
        first = g0 in objects
        finger = tip_finger.get(g1 if first else g0, -1)
        if finger >= 0 and (first or g1 in objects):
            if efc is None:
                efc = con.efc_address
            if efc[i] >= 0:
                yield i, finger, first


def finger_forces(model: mujoco.MjModel, data: mujoco.MjData, objects: set[int],
                  tip_finger: dict[int, int], fingers: int) -> tuple[Array, Array]:  # fmt: skip
    """The object's force on every fingertip: the normal forces (fingers,) [N] and the
    tangential (friction) forces (fingers, 3) [N, world] of MuJoCo's contacts between each
    finger's touching geom (`tip_finger`: geom id -> finger) and the object's geoms, summed.

    ``mj_contactForce`` gives the force on ``contact.geom[1]`` in the contact frame; the
    fingertip feels its opposite when it is ``geom[0]``."""
    shear = np.zeros((fingers, 3))
    normal = np.zeros(fingers)
    force6 = np.zeros(6)
    con = data.contact
    for i, finger, first in tip_object_contacts(data, objects, tip_finger):
        mujoco.mj_contactForce(model, data, i, force6)
        tangential = con.frame[i].reshape(3, 3)[1:].T @ force6[1:3]
        shear[finger] += tangential if first else -tangential
        normal[finger] += max(float(force6[0]), 0.0)
    return normal, shear


def _at_rest(rot: Array, t: Array, moved: tuple[Array, Array] | None) -> tuple[Array, Array]:
    """A pad carrier's pose (`rot`, `t`) in the frame of the object at rest, given a free
    object's motion from rest (`moved`: rotation, translation; None: a fixed object)."""
    if moved is None:
        return rot, t
    return moved[0].T @ rot, moved[0].T @ (t - moved[1])


def pad_loads(normal: Array, shear: Array, rotations: Array, layouts: tuple[PadLayout, ...],
              friction: float) -> Array:  # fmt: skip
    """Every pad's tangential load as a share of its friction limit, ``|Q| / (mu N)``, along
    the direction of Q in the pad's (u, v) axes (pads, 2); 0 without a normal force.

    Args:
        normal: (pads,) normal forces [N]; shear: (pads, 3) tangential forces [N, world]
            (:func:`finger_forces`).
        rotations: (pads, 3, 3) the pads' carriers' orientations (columns: their axes).
        layouts: the pads' layouts.
        friction: Coulomb's coefficient.
    """
    out = np.zeros((len(layouts), 2))
    for k, layout in enumerate(layouts):
        if normal[k] <= 0.0 or friction <= 0.0:
            continue
        along = np.stack([rotations[k] @ layout.e_u, rotations[k] @ layout.up]) @ shear[k]
        size = float(np.linalg.norm(along))
        if size > 0.0:
            out[k] = along / size * np.linalg.norm(shear[k]) / (friction * normal[k])
    return out


def default_pad_normal(
    model: mujoco.MjModel, data: mujoco.MjData, hand, finger: int, carrier_rot: Array
) -> Array:  # noqa: ANN001 - Hand
    """Where the fingertip meets objects, in the carrier's frame: halfway between the direction
    the finger points (from its last driven joint to the tip centre) and the side opposite to
    the one the tip moves toward when that joint flexes, at the current posture. Measured on the
    shipped hands with the paper strategy (``docs/tactile/README.md``): the mean contact
    direction lies there (hapticsim's index finger (0.82, 0.02, 0.57) in its tip's frame,
    Shadow's (-0.01, 0.83, 0.56)), since the controllers approach with fingers hooked."""
    f = hand.fingers[finger]
    tip = data.site_xpos[f.site_id]
    last = int(np.flatnonzero(model.dof_jntid == model.dof_jntid[f.dof_adr[-1]])[0])
    joint = int(model.dof_jntid[last])
    anchor = data.xanchor[joint]
    pointing = tip - anchor
    flexing = np.cross(data.xaxis[joint], pointing)
    direction = pointing / np.linalg.norm(pointing) - flexing / np.linalg.norm(flexing)
    return carrier_rot.T @ (direction / np.linalg.norm(direction))


def pad_layouts(
    model: mujoco.MjModel, hand, skin: SkinPreset
) -> list[tuple[str, int, PadLayout, float]]:  # noqa: ANN001, E501
    """Every finger's pad in a compiled scene: (carrier kind, carrier id, layout, reach).

    Raises:
        InvalidInputError: a pad on a geom it cannot follow (naming the finger), or a grid
            that does not fit the fingertip.
    """

    desc = hand.description
    rows, cols, pitch = desc.pad_grid
    data = mujoco.MjData(model)
    for f in hand.fingers:  # the probe posture: where the pulp points when the hand probes
        hand.set_finger_qpos(data.qpos, f.index, f.posture("probe"))
    mujoco.mj_kinematics(model, data)
    out = []
    for f, fd in zip(hand.fingers, desc.fingers, strict=True):
        where = f"hand {desc.name!r}, finger {fd.name!r}, pad"
        pad = fd.pad
        if pad.on is None:
            kind, ident = "geom", int(f.tip_geom_id)
        else:
            ident = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, PREFIX + pad.on))
            kind = "geom"
            if ident < 0:
                kind = "site"
                ident = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, PREFIX + pad.on))
        if kind == "geom":
            rot = data.geom_xmat[ident].reshape(3, 3)
            gtype, size = int(model.geom_type[ident]), model.geom_size[ident]
        else:
            rot = data.site_xmat[ident].reshape(3, 3)
            gtype, size = None, None
        normal = (np.asarray(pad.normal, float) if pad.normal is not None
                  else default_pad_normal(model, data, hand, f.index, rot))  # fmt: skip
        normal = normal / np.linalg.norm(normal)
        up = np.asarray(pad.up, float) if pad.up is not None else default_up(normal)
        origin = np.zeros(3)
        radius: float | None
        if pad.flat:
            radius = None
            if gtype == mujoco.mjtGeom.mjGEOM_BOX:  # on the face the normal points through
                axis = int(np.argmax(np.abs(normal)))
                origin[axis] = np.sign(normal[axis]) * size[axis]
        elif pad.radius is not None:
            radius = pad.radius
        elif gtype == mujoco.mjtGeom.mjGEOM_SPHERE:
            radius = float(size[0])
        elif gtype == mujoco.mjtGeom.mjGEOM_CAPSULE:  # the end cap toward the tip centre
            radius = float(size[0])
            tip_local = rot.T @ (data.site_xpos[f.site_id] - data.geom_xpos[ident])
            origin[2] = np.sign(tip_local[2] or 1.0) * size[1]
        elif kind == "site":
            radius = float(fd.tip_radius)
        else:
            name = mujoco.mjtGeom(gtype).name[8:].lower()
            raise InvalidInputError(
                f"{where}: a pad follows a sphere or a capsule; on a {name} geom give the "
                "sphere it follows as `radius` [m], or `flat = true`"
            )
        try:
            layout = PadLayout(rows, cols, pitch, radius, normal, up, origin)
            if skin.pitch is not None:
                layout = layout.resampled(skin.pitch)
        except PadError as exc:
            raise InvalidInputError(f"{where}: {exc}") from exc
        reach = radius if radius is not None else 4.0 * skin.skin.thickness
        out.append((kind, ident, layout, float(reach)))
    return out


class TactileHand:
    """The pads of a scene's hand and their readings (module docstring).

    Args:
        scene: a scene built with tactile sensing (its configuration names the skin and the
            taxel model).
        rng: the generator of the sensor's fixed pattern (drawn here) and its noise (drawn per
            reading).
    """

    def __init__(self, scene, rng: np.random.Generator) -> None:  # noqa: ANN001 - Scene
        config = scene.config
        self.scene = scene
        self.model = scene.model
        self.skin: SkinPreset = config.skin
        self.taxel_model: str = config.taxel_model
        self.rng = rng
        if not scene.pads:
            raise InvalidInputError("a tactile hand needs a scene built with sensing='tactile'")
        pads = []
        for k, (kind, ident, layout, reach) in enumerate(scene.pads):
            adr = -1
            if self.taxel_model == "mujoco":
                sid = int(mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SENSOR,
                                            f"{PAD_PREFIX}{k}"))  # fmt: skip
                adr = int(self.model.sensor_adr[sid])
            pads.append(Pad(k, layout, kind, ident, reach, adr))
        self.pads: tuple[Pad, ...] = tuple(pads)
        shapes = {p.layout.shape for p in pads}
        if len(shapes) != 1:
            raise InvalidInputError(f"every pad of a hand must have the same grid, got {shapes}")
        self.shape: tuple[int, int] = shapes.pop()
        self.pattern = self.skin.sensor.pattern((len(pads), *self.shape), rng)
        #: each pad's share of the fixed pattern (:meth:`feel`)
        self._patterns = [FixedPattern(self.pattern.gain[k : k + 1], self.pattern.dead[k : k + 1])
                          for k in range(len(pads))]  # fmt: skip
        #: (fingers,) each fingertip's sphere (its pad's, or its tip radius under a flat pad)
        #: [m], whose force on a flat face stands for the skin's (:meth:`sphere_force`).
        self._radii = [p.layout.radius or f.tip_radius for p, f in zip(pads, scene.hand.fingers,
                                                                       strict=True)]  # fmt: skip
        #: a free object's pose at rest (the scene's truth; SPEC §12), else None.
        self._rest_pose = None
        if scene.free:
            from hapticsim.sim.dynamics import object_pose

            data = mujoco.MjData(self.model)
            mujoco.mj_forward(self.model, data)
            self._rest_pose = object_pose(self.model, data, scene.object_body_id)
        self._vel = np.zeros(6)
        #: the contacts' Coulomb coefficient (the scene's friction: the hand's and the object's)
        self.friction: float = float(config.friction)
        self._objects = set(scene.object_geom_ids)
        self._tip_finger = scene.hand.tip_finger_of_geom
        self._force6 = np.zeros(6)
        self._tip_geoms = [int(f.tip_geom_id) for f in scene.hand.fingers]
        self._rest_solref = [skin_solref(self.skin, f.tip_radius) for f in scene.hand.fingers]
        #: per finger in contact, the skin's force law ``F = c r^2`` read from its pad (c [N/m^2])
        #: and the ticks since, or None
        self._skin_law: list[tuple[float, int] | None] = [None] * len(self.pads)
        self.reset_softness()  # a cached scene's model may come from another run

    @property
    def layouts(self) -> tuple[PadLayout, ...]:
        """Every pad's layout, in finger order."""
        return tuple(p.layout for p in self.pads)

    def sphere_force(self, finger: int, penetration: float) -> float:
        """The skin's force [N] of a finger's fingertip sphere pressed `penetration` [m] into a
        flat face (:meth:`~hapticsim.perception.tactile.skin.SkinModel.sphere_force`): what a
        tactile hand steering on MuJoCo's contacts feels at MuJoCo's penetration."""
        return self.skin.skin.sphere_force(self._radii[finger], penetration)

    def pad_pose(self, data: mujoco.MjData, pad: Pad) -> tuple[Array, Array]:
        """A pad carrier's rotation (3, 3) and origin (3,) [m] in the world."""
        if pad.carrier == "geom":
            return data.geom_xmat[pad.carrier_id].reshape(3, 3).copy(), data.geom_xpos[
                pad.carrier_id
            ].copy()
        return data.site_xmat[pad.carrier_id].reshape(3, 3).copy(), data.site_xpos[
            pad.carrier_id
        ].copy()

    def read(self, data: mujoco.MjData) -> TactileReading:
        """Every pad's reading now (after a step or ``mj_forward``)."""
        n = len(self.pads)
        rows, cols = self.shape
        depth = np.zeros((n, rows, cols))
        slip = np.zeros((n, rows, cols, 2))
        rotations = np.zeros((n, 3, 3))
        positions = np.zeros((n, 3))
        moved = self._object_motion(data)
        for k, pad in enumerate(self.pads):
            rot, t = self.pad_pose(data, pad)
            rotations[k], positions[k] = rot, t
            pos, nrm, _ = pad.layout.taxels
            world = pos @ rot.T + t
            depth[k] = self._depth(data, pad, rot, t, moved)
            if np.any(depth[k] > 0):
                slip[k] = self._slip(data, pad, rot, world, nrm @ rot.T, depth[k] > 0)
        pressure = np.stack([self.skin.skin.pressure(depth[k], pad.layout.pitch)
                             for k, pad in enumerate(self.pads)])  # fmt: skip
        readings = self.skin.sensor.apply(pressure, self.pattern, self.rng)
        traction, state = traction_field(pressure, self.loads(data, rotations), self.friction,
                                         self.pads[0].layout.taxels[2])  # fmt: skip
        return TactileReading(depth, readings, slip, positions, rotations, float(data.time),
                              traction, state, self.friction)  # fmt: skip

    def loads(self, data: mujoco.MjData, rotations: Array) -> Array:
        """Every pad's tangential load as a share of its friction limit (:func:`pad_loads` of
        MuJoCo's forces between each finger's touching geom and the object)."""
        normal, shear = finger_forces(self.model, data, self._objects, self._tip_finger,
                                      len(self.pads))  # fmt: skip
        return pad_loads(normal, shear, rotations, self.layouts, self.friction)

    def _depth(self, data: mujoco.MjData, pad: Pad, rot: Array, t: Array,
               moved: tuple[Array, Array] | None) -> Array:  # fmt: skip
        """One pad's depth image (rows, cols) [m] (module docstring), its carrier at `rot`,
        `t`; `moved` a free object's motion from rest (:meth:`_object_motion`)."""
        rows, cols = pad.layout.shape
        if self.taxel_model == "mujoco":
            block = data.sensordata[pad.sensor_adr : pad.sensor_adr + pad.layout.count]
            return np.asarray(block).reshape(rows, cols)
        truth = self.scene.truth
        rot_o, t_o = _at_rest(rot, t, moved)
        reach = float(truth.bounding_radius) + pad.reach + pad.layout.pitch * max(rows, cols)
        if np.linalg.norm(t_o - np.asarray(truth.center)) > reach:
            return np.zeros((rows, cols))  # nowhere near the object
        pos, nrm, _ = pad.layout.taxels
        return taxel_depths(truth, pos @ rot_o.T + t_o, nrm @ rot_o.T, pad.reach)

    def pad_force(self, data: mujoco.MjData, finger: int,
                  near: tuple[Array, float] | None = None) -> float:  # fmt: skip
        """The skin's normal force on a finger's pad now [N]: its pressure (before the sensor
        model) integrated over the taxels.

        Args:
            data: the state.
            finger: the finger (its pad).
            near: (point (3,) [m, world], radius [m]): read only the taxels within `radius` of
                a contact point (the whole pad when a taxel at the edge of that disc is in
                contact too); None: every taxel.
        """
        pad = self.pads[finger]
        rot, t = self.pad_pose(data, pad)
        return float(np.sum(self._pressure(data, pad, rot, t, near) * pad.layout.taxels[2]))

    def feel(
        self, data: mujoco.MjData, finger: int, near: tuple[Array, float] | None = None
    ) -> tuple[TactileContact | None, float]:
        """One frame of a finger's pad for a tactile servo: the contact estimated from its
        reading now (after the sensor model, with a fresh draw of its noise; None when no taxel
        is lit) and the skin's force before the sensor model [N] (:meth:`pad_force`). `near` as
        in :meth:`pad_force` (the taxels outside read nothing: exact)."""
        pad = self.pads[finger]
        rot, t = self.pad_pose(data, pad)
        pressure = self._pressure(data, pad, rot, t, near)
        force = float(np.sum(pressure * pad.layout.taxels[2]))
        reading = self.skin.sensor.apply(pressure[None], self._patterns[finger], self.rng)[0]
        return estimate_contact(reading, pad.layout, rot, t, self.skin.skin,
                                self.skin.sensor), force  # fmt: skip

    def follow_frame(self, finger: int, force: float, penetration: float) -> None:
        """Take a frame's skin force (:meth:`feel`) at MuJoCo's `penetration` [m] as the
        finger's force law (:meth:`follow_skin`), which then needs no reading of its own while
        frames come at least every :data:`SKIN_LAW_TICKS` ticks."""
        if penetration > 0.0 and self._skin_law[finger] is not None:
            self._skin_law[finger] = (force / penetration**2, 0)

    def _pressure(self, data: mujoco.MjData, pad: Pad, rot: Array, t: Array,
                  near: tuple[Array, float] | None) -> Array:  # fmt: skip
        """One pad's pressure image (rows, cols) [Pa] before the sensor model, its carrier at
        `rot`, `t`; `near` as in :meth:`pad_force`."""
        moved = self._object_motion(data)
        if near is None or self.taxel_model == "mujoco":
            return self.skin.skin.pressure(self._depth(data, pad, rot, t, moved),
                                           pad.layout.pitch)  # fmt: skip
        pos, nrm, _ = pad.layout.taxels
        offset = pos - (near[0] - t) @ rot  # the taxels from the contact, in the carrier's frame
        distance2 = np.einsum("ijk,ijk->ij", offset, offset)
        keep = distance2 <= near[1] ** 2
        if not keep.any():
            return self._pressure(data, pad, rot, t, None)
        rot_o, t_o = _at_rest(rot, t, moved)
        depth = taxel_depths(self.scene.truth, pos[keep] @ rot_o.T + t_o, nrm[keep] @ rot_o.T,
                             pad.reach)  # fmt: skip
        edge = max(near[1] - 1.5 * pad.layout.pitch, 0.0) ** 2
        if np.any(depth[distance2[keep] > edge] > 0):
            return self._pressure(data, pad, rot, t, None)  # the contact reaches the disc's edge
        full = np.zeros(pad.layout.shape)
        full[keep] = depth
        return self.skin.skin.pressure(full, pad.layout.pitch)

    def near_contact(self, finger: int, point: Array, penetration: float) -> tuple[Array, float]:
        """The disc of a finger's pad a contact at `point` [m, world] with MuJoCo's
        `penetration` [m] can light: 1.25 times a sphere's contact radius and two taxels
        (:meth:`pad_force`'s `near`; a contact that reaches the disc's edge reads the whole
        pad, so a smaller disc costs whole reads, not accuracy: at twice the radius and three
        taxels a frame cast 1.8 times the taxels and took 1.4 times as long)."""
        pad = self.pads[finger]
        radius = 1.25 * np.sqrt(2.0 * pad.reach * max(penetration, 0.0)) + 2.0 * pad.layout.pitch
        return np.asarray(point, dtype=np.float64), float(radius)

    def reset_softness(self) -> None:
        """Give every fingertip its skin's resting contact softness (:func:`skin_solref`)."""
        self._skin_law = [None] * len(self.pads)
        for geom, solref in zip(self._tip_geoms, self._rest_solref, strict=True):
            self.model.geom_solref[geom] = solref

    def follow_skin(self, data: mujoco.MjData) -> None:
        """One contact law for skin and physics: set every touching fingertip's contact time
        constant so that the normal force MuJoCo applies at its present penetration is the
        skin's force there (:meth:`pad_force`); call after every control tick.

        MuJoCo's soft contact at rest carries ``k imp r / R`` (``efc_KBIP``'s stiffness k and
        impedance imp, the regulariser R, the penetration r), ``k`` proportional to
        ``1 / tau^2``. A sliding contact (its friction at the cone) carries more: the friction
        rows' damping ``B v_t`` (``B`` proportional to ``1 / tau``) adds ``mu |aref_t|`` to the
        normal row's reference, so ``f_n = (k imp r + mu |aref_t|) / (R_n + mu^2 R_t)``. The
        new time constant solves ``f_n(tau) = F_skin``, within [2 time steps,
        :data:`SKIN_TAU_MAX`]. The skin's force is read from the pad every
        :data:`SKIN_LAW_TICKS` ticks of a contact and carried in between as ``c r^2`` of the
        deepest penetration r (the skin's law for a sphere on a smooth surface; reading the
        pad every tick cost half of an exploration's time). Measured on the paper's bodies:
        ``docs/tactile/README.md``.
        """
        n = len(self.pads)
        # Called every control tick: plain floats and one read of each MuJoCo array (each
        # attribute of ``data.contact`` is a fresh copy), not numpy's per-call overhead.
        quadratic, linear, deepest = [0.0] * n, [0.0] * n, [0.0] * n
        where: list[Array | None] = [None] * n
        con = data.contact
        efc_address = dist = pos = friction = None
        force6 = self._force6
        for i, finger, _ in tip_object_contacts(data, self._objects, self._tip_finger):
            if efc_address is None:
                efc_address, dist, pos, friction = (con.efc_address, con.dist, con.pos,
                                                    con.friction)  # fmt: skip
            adr = int(efc_address[i])
            penetration = -float(dist[i])
            if penetration <= 0.0:
                continue
            if penetration > deepest[finger]:
                deepest[finger], where[finger] = penetration, pos[i]
            stiffness, _, impedance, _ = data.efc_KBIP[adr]
            r_n = float(data.efc_R[adr])
            static = stiffness * impedance * penetration
            mujoco.mj_contactForce(self.model, data, i, force6)
            mu = float(friction[i, 0])
            if force6[0] > 0 and np.hypot(force6[1], force6[2]) >= 0.98 * mu * force6[0]:
                r_t = float(data.efc_R[adr + 1])
                denominator = r_n + mu * mu * r_t
                quadratic[finger] += static / denominator
                aref = data.efc_aref
                linear[finger] += mu * float(np.hypot(aref[adr + 1], aref[adr + 2])) / (
                    denominator)  # fmt: skip
            else:
                quadratic[finger] += static / r_n
        lowest = 2.0 * self.model.opt.timestep
        for k in range(n):
            if quadratic[k] <= 0.0:
                self._skin_law[k] = None  # out of contact: read the pad afresh at the next touch
                continue
            geom = self._tip_geoms[k]
            tau = float(self.model.geom_solref[geom, 0])
            law = self._skin_law[k]
            if law is None or law[1] >= SKIN_LAW_TICKS:  # read the pad: F = c depth^2 from here
                force = self.pad_force(data, k, self.near_contact(k, where[k], deepest[k]))
                law = (force / deepest[k] ** 2, 0)
            self._skin_law[k] = (law[0], law[1] + 1)
            target = law[0] * deepest[k] ** 2
            if target <= 0.0:
                new = SKIN_TAU_MAX
            else:  # a x^2 + b x = F in x = 1 / tau_new, a and b from the present tau
                a, b = quadratic[k] * tau * tau, linear[k] * tau
                new = 2.0 * a / (math.sqrt(b * b + 4.0 * a * target) - b)
            self.model.geom_solref[geom, 0] = min(max(float(new), lowest), SKIN_TAU_MAX)

    def _object_motion(self, data: mujoco.MjData) -> tuple[Array, Array] | None:
        """A free object's rigid motion from rest to now (rotation, translation), else None."""
        if self._rest_pose is None:
            return None
        from hapticsim.sim.dynamics import object_pose, relative_motion

        now = object_pose(self.model, data, self.scene.object_body_id)
        return relative_motion(now, self._rest_pose)

    def _slip(self, data: mujoco.MjData, pad: Pad, rot: Array, world: Array, normals: Array,
              touching: NDArray[np.bool_]) -> Array:  # fmt: skip
        """Tangential velocities (rows, cols, 2) of the touching taxels in the pad's (u, v)
        axes [m/s] (relative to the world: a moving object's own speed is not taken off)."""
        obj = mujoco.mjtObj.mjOBJ_GEOM if pad.carrier == "geom" else mujoco.mjtObj.mjOBJ_SITE
        mujoco.mj_objectVelocity(self.model, data, obj, pad.carrier_id, self._vel, 0)
        omega, v0 = self._vel[:3], self._vel[3:]
        origin = (
            data.geom_xpos[pad.carrier_id]
            if pad.carrier == "geom"
            else data.site_xpos[pad.carrier_id]
        )
        v = v0 + np.cross(omega, world - origin)
        v_t = v - np.sum(v * normals, axis=-1, keepdims=True) * normals
        e_u, e_v = rot @ pad.layout.e_u, rot @ pad.layout.up
        out = np.stack([v_t @ e_u, v_t @ e_v], axis=-1)
        return np.where(touching[..., None], out, 0.0)

    def estimate(self, reading: TactileReading, finger: int) -> TactileContact | None:
        """The contact finger `finger`'s pad felt in `reading`, or None."""
        pad = self.pads[finger]
        return estimate_contact(
            reading.pressure[finger], pad.layout, reading.pad_rotation[finger],
            reading.pad_position[finger], self.skin.skin, self.skin.sensor,
        )  # fmt: skip

    def sense(self, data: mujoco.MjData, finger: int) -> SensedContact:
        """Read every pad and estimate `finger`'s contact (a recorded touch)."""
        reading = self.read(data)
        return SensedContact(self.estimate(reading, finger), reading)


__all__ = [
    "PAD_PREFIX",
    "Pad",
    "SENSINGS",
    "SensedContact",
    "TAXEL_MODELS",
    "TactileHand",
    "TactileReading",
    "add_mujoco_pads",
    "default_pad_normal",
    "finger_forces",
    "pad_layouts",
    "pad_loads",
    "prepare_skin",
    "skin_solref",
    "tip_object_contacts",
]
