"""The hand's shape and its pose at every touch, for replaying an exploration (``hand.npz``).

:class:`HandTrace` hooks into a :class:`~hapticsim.sim.simulator.Simulator` like the video does
(:attr:`Simulator.tick_hooks`) and keeps the world pose of every visible hand geom at the start
and each time the recorder gains contacts: state ``k`` is the hand when contact ``k`` was
recorded (state 0: before the first). :meth:`HandTrace.arrays` gives the geoms as triangle meshes
in their own frames (primitives tessellated, MuJoCo meshes as compiled) and the poses, the
content of a run's ``hand.npz``:

- ``vertices`` (V, 3) [m, geom frame], ``faces`` (F, 3) int, ``vertex_start`` / ``face_start``
  (G + 1,) offsets of geom g's rows, ``rgba`` (G, 4), ``names`` (G,) str: the geoms;
- ``finger_names`` (fingers,) str: the hand's fingers, in the order of ``contacts.npz``'s
  ``finger``;
- ``position`` (K + 1, G, 3) [m, world], ``wxyz`` (K + 1, G, 4): their poses per state;
- ``contacts`` (K + 1,) int: contacts recorded at each state (a touch may record several).

Recording reads MuJoCo's data only: it changes nothing in the simulation.
"""

from __future__ import annotations

import mujoco
import numpy as np
import trimesh

from hapticsim.sim.hand import MOUNT_BODY
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.simulator import Simulator

#: MuJoCo's geom groups drawn by default (higher groups hold collision-only copies).
VISIBLE_GROUPS: int = 3


def _subtree(model: mujoco.MjModel, root: int) -> set[int]:
    """Ids of `root` and all its descendant bodies."""
    bodies = {root}
    for b in range(root + 1, model.nbody):  # children come after their parents
        if int(model.body_parentid[b]) in bodies:
            bodies.add(b)
    return bodies


def hand_geoms(model: mujoco.MjModel) -> list[int]:
    """Ids of the hand's visible geoms (the mount body's subtree, groups 0-2, not transparent)."""
    mount = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, MOUNT_BODY)
    if mount < 0:
        return []
    bodies = _subtree(model, mount)
    return [
        g for g in range(model.ngeom)
        if int(model.geom_bodyid[g]) in bodies and model.geom_group[g] < VISIBLE_GROUPS
        and model.geom_rgba[g, 3] > 0.0
    ]  # fmt: skip


def geom_mesh(model: mujoco.MjModel, g: int) -> tuple[np.ndarray, np.ndarray]:
    """Geom `g` as a triangle mesh in its own frame: vertices (V, 3) [m], faces (F, 3)."""
    kind = mujoco.mjtGeom(int(model.geom_type[g]))
    size = model.geom_size[g]
    if kind == mujoco.mjtGeom.mjGEOM_MESH:
        m = int(model.geom_dataid[g])
        v0, nv = int(model.mesh_vertadr[m]), int(model.mesh_vertnum[m])
        f0, nf = int(model.mesh_faceadr[m]), int(model.mesh_facenum[m])
        return model.mesh_vert[v0:v0 + nv].astype(float), model.mesh_face[f0:f0 + nf].astype(int)
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=size[0])
    elif kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
        mesh = trimesh.creation.capsule(height=2 * size[1], radius=size[0], count=[12, 12])
    elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
        mesh = trimesh.creation.cylinder(radius=size[0], height=2 * size[1], sections=16)
    elif kind == mujoco.mjtGeom.mjGEOM_BOX:
        mesh = trimesh.creation.box(extents=2 * size[:3])
    elif kind == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
        mesh.apply_scale(size[:3])
    else:  # planes, height fields, SDFs: not part of a hand
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=int)
    return np.asarray(mesh.vertices, float), np.asarray(mesh.faces, int)


class HandTrace:
    """Poses of the hand's geoms at the start and at every new contact (module docstring)."""

    def __init__(self) -> None:
        self._sim: Simulator | None = None
        self._recorder: Recorder | None = None
        self._geoms: list[int] = []
        self._positions: list[np.ndarray] = []
        self._wxyz: list[np.ndarray] = []
        self._contacts: list[int] = []

    def attach(self, sim: Simulator, recorder: Recorder) -> None:
        """Start following `sim`'s hand, taking a state whenever `recorder` grows."""
        self._sim, self._recorder = sim, recorder
        self._geoms = hand_geoms(sim.model)
        sim.tick_hooks.append(self.capture)
        self._take(sim, len(recorder))

    def capture(self, sim: Simulator) -> None:
        """Take a state if contacts were recorded since the last one (a tick hook)."""
        n = len(self._recorder) if self._recorder is not None else 0
        if not self._contacts or n > self._contacts[-1]:
            self._take(sim, n)

    def _take(self, sim: Simulator, n: int) -> None:
        ids = self._geoms
        data = sim.data
        self._positions.append(np.array(data.geom_xpos[ids], dtype=np.float32))
        quats = np.empty((len(ids), 4))
        for i, g in enumerate(ids):
            mujoco.mju_mat2Quat(quats[i], data.geom_xmat[g])
        self._wxyz.append(quats.astype(np.float32))
        self._contacts.append(n)

    def arrays(self) -> dict[str, np.ndarray]:
        """The content of ``hand.npz`` (module docstring)."""
        if self._sim is None:
            raise RuntimeError("HandTrace.arrays before attach")
        self.capture(self._sim)  # contacts recorded after the last tick: the hand as it ends
        model = self._sim.model
        verts, faces, v_start, f_start = [], [], [0], [0]
        for g in self._geoms:
            v, f = geom_mesh(model, g)
            verts.append(v)
            faces.append(f)
            v_start.append(v_start[-1] + len(v))
            f_start.append(f_start[-1] + len(f))
        names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"geom{g}"
                 for g in self._geoms]  # fmt: skip
        return {
            "vertices": np.concatenate(verts).astype(np.float32) if verts else np.zeros((0, 3)),
            "faces": np.concatenate(faces).astype(np.int32) if faces else np.zeros((0, 3), int),
            "vertex_start": np.array(v_start, dtype=np.int64),
            "face_start": np.array(f_start, dtype=np.int64),
            "rgba": np.array(model.geom_rgba[self._geoms], dtype=np.float32).reshape(-1, 4),
            "names": np.array(names),
            "finger_names": np.array(list(self._sim.hand.finger_names)),
            "position": np.stack(self._positions),
            "wxyz": np.stack(self._wxyz),
            "contacts": np.array(self._contacts, dtype=np.int64),
        }


__all__ = ["HandTrace", "geom_mesh", "hand_geoms"]
