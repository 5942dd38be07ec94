"""Timing and accuracy of the simulation (used by ``scripts/bench.py --section sim`` and
``scripts/bench_sim.py``):

- physics steps per second of the hand + object scene with a fingertip pressing;
- wall time of a 150-contact ``paper`` exploration, with any described hand;
- how accurate MuJoCo's contacts on the object's collision hull are, against its vertex count
  (:func:`mesh_contact_accuracy`: a free fingertip sphere put into the surface at many places,
  MuJoCo's contact normal compared with the analytic one, on faces and on edges).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.exploration import explorer_for
from hapticsim.geometry import Superquadric
from hapticsim.perception.vision import vision_estimate
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import SceneConfig, build_scene

Array = NDArray[np.float64]


def physics_steps_per_second(truth: Superquadric, steps: int = 20000) -> dict[str, Any]:
    """Raw ``mj_step`` rate (no Python in the loop) with the index fingertip pressing on the top
    of the object.

    Returns:
        ``steps_per_second``, ``contacts`` (active contacts while timing), ``fingertip_force``
        [N] and ``mesh_vertices`` of the object.
    """
    scene = build_scene(truth)
    explorer = Explorer(scene, vision_estimate(truth, 0), Recorder())
    top = truth.center + truth.rotation @ np.array([0.0, 0.0, truth.a[2]])
    explorer.probe_patch(1, [Probe(top, -truth.rotation[:, 2])])
    sim = explorer.sim
    if explorer.recorder.contacts:
        contact = explorer.recorder.contacts[-1]
        sim.set_tip_target(1, contact.point_world + contact.normal_world * 0.006)
    for _ in range(100):
        sim.tick()
    start = time.perf_counter()
    mujoco.mj_step(sim.model, sim.data, nstep=steps)
    seconds = time.perf_counter() - start
    tip = sim.contacts.tips[1]
    return {
        "steps_per_second": steps / seconds,
        "contacts": int(sim.data.ncon),
        "fingertip_force": float(tip.force) if tip is not None else 0.0,
        "mesh_vertices": int(scene.model.mesh_vertnum[0]),
    }


def exploration_time(
    truth: Superquadric, strategy: str = "paper", count: int = 150, seed: int = 0,
    hand: str = "hapticsim",
) -> dict[str, float]:  # fmt: skip
    """Wall and CPU time of one exploration, scene building included.

    Args:
        truth: the object.
        strategy: exploration strategy.
        count: contacts to gather.
        seed: seed of the run.
        hand: the hand (a shipped name or a description path).

    Returns:
        ``contacts``, ``wall_seconds``, ``cpu_seconds``, ``sim_seconds``, ``steps`` and
        ``closed_loop_steps_per_second`` (physics steps per wall second with the controllers).
    """
    cpu = time.process_time()
    explorer = explorer_for(strategy)  # a scripted strategy or a policy
    run = explorer.explore(truth, count, np.random.default_rng(seed), SceneConfig(hand=hand))
    return {
        "contacts": float(run.count),
        "wall_seconds": run.wall_time,
        "cpu_seconds": time.process_time() - cpu,
        "sim_seconds": run.sim_time,
        "steps": float(run.steps),
        "closed_loop_steps_per_second": run.steps_per_second,
    }


def benchmark_sim(
    bodies: Sequence[str] | None = None, count: int = 150, repeat: int = 1,
    hands: Sequence[str] = ("hapticsim",), mesh_samples: int = 0,
) -> dict[str, Any]:  # fmt: skip
    """Both timings for the paper's bodies (median over `repeat` seeds for explorations).

    Args:
        bodies: body names (default: the paper's four).
        count: contacts per exploration.
        repeat: seeds per exploration.
        hands: hands to time explorations with (the physics rate uses hapticsim's hand).
        mesh_samples: when > 0, also :func:`mesh_accuracy_table` with that many probes.

    Returns:
        ``physics`` by body, ``exploration`` by body (by hand when several are given) and,
        with `mesh_samples`, ``mesh_accuracy``.
    """
    from hapticsim.data.bodies import BODY_NAMES, get_body

    out: dict[str, Any] = {"physics": {}, "exploration": {}}
    for name in bodies or BODY_NAMES:
        truth = get_body(name)
        out["physics"][name] = physics_steps_per_second(truth)
        for hand in hands:
            runs = [exploration_time(truth, "paper", count, seed, hand) for seed in range(repeat)]
            row = {k: float(np.median([r[k] for r in runs])) for k in runs[0]}
            if len(hands) == 1:
                out["exploration"][name] = row
            else:
                out["exploration"].setdefault(hand, {})[name] = row
    if mesh_samples > 0:
        out["mesh_accuracy"] = mesh_accuracy_table(bodies or BODY_NAMES, samples=mesh_samples)
    return out


# ----------------------------------------------------------------------------- mesh accuracy
#: A surface point counts as on a *face* when its normal is within this angle [deg] of a face
#: normal of the body (+-z for a flat top or bottom, +-x/+-y for flat sides, horizontal for a
#: round side); the rest of a prismatic body is its rounded *edges*.
FACE_ANGLE_DEG: float = 10.0


def _on_faces(shape: Superquadric, normals_body: Array) -> NDArray[np.bool_]:
    """(n,) bool, True where the body-frame normal is on a face (:data:`FACE_ANGLE_DEG`)."""
    eps1, eps2 = shape.eps
    cos_t, sin_t = np.cos(np.radians(FACE_ANGLE_DEG)), np.sin(np.radians(FACE_ANGLE_DEG))
    n = normals_body
    horizontal = n[:, :2] / np.maximum(np.linalg.norm(n[:, :2], axis=1, keepdims=True), 1e-12)
    flat_side = (np.abs(horizontal[:, 0]) > cos_t) | (np.abs(horizontal[:, 1]) > cos_t)
    if eps1 >= 0.5:  # round in latitude: only the flat sides of a square cross-section count
        return flat_side if eps2 < 0.5 else np.ones(len(n), dtype=bool)
    top = np.abs(n[:, 2]) > cos_t
    side = np.abs(n[:, 2]) < sin_t
    return top | (side & flat_side if eps2 < 0.5 else side)


def mesh_contact_accuracy(
    truth: Superquadric,
    resolution: int,
    samples: int = 2000,
    tip_radius: float = 0.008,
    depth: float = 3e-4,
    seed: int = 0,
) -> dict[str, Any]:
    """How well MuJoCo's contacts on a superquadric's collision hull match the analytic surface.

    A free sphere of `tip_radius` (a fingertip) is put `depth` into the surface at `samples`
    points drawn uniformly in the paper's (eta, omega) parametrisation; MuJoCo's contact
    (:mod:`hapticsim.sim.contacts`: normal out of the object, point on its surface) is compared
    with the analytic normal and surface at the point.

    Args:
        truth: the object (its pose is ignored).
        resolution: the collision mesh's resolution (:class:`~hapticsim.sim.scene.SceneConfig`).
        samples: probes.
        tip_radius: sphere radius [m].
        depth: penetration [m].
        seed: seed of the probe points.

    Returns:
        ``vertices`` of the mesh, ``compile_seconds`` (MuJoCo's hull and compile), normal angle
        median and p95 [deg] on ``faces`` and ``edges`` (:data:`FACE_ANGLE_DEG`; None where a body
        has none) and in ``all``, and ``distance_median``/``distance_p95`` [m].
    """
    body = truth.replace(rotation=np.eye(3), center=np.zeros(3))
    vertices = body.convex_pieces(resolution)[0][0]
    spec = mujoco.MjSpec()
    spec.add_mesh(name="object", uservert=vertices.ravel().tolist())
    spec.worldbody.add_body(name="object").add_geom(
        type=mujoco.mjtGeom.mjGEOM_MESH, meshname="object", contype=1, conaffinity=2
    )
    tip = spec.worldbody.add_body(name="tip")
    tip.add_freejoint()
    tip.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[tip_radius, 0, 0], contype=2,
                 conaffinity=1, margin=0.001, gap=0.001)  # fmt: skip
    start = time.perf_counter()
    model = spec.compile()
    compile_seconds = time.perf_counter() - start
    data = mujoco.MjData(model)
    rng = np.random.default_rng(seed)
    eta = np.arcsin(rng.uniform(-1.0, 1.0, samples))
    omega = rng.uniform(-np.pi, np.pi, samples)
    points, normals = body.surface(eta, omega)
    found, measured_p, measured_n = [], [], []
    for k in range(samples):
        data.qpos[:3] = points[k] + normals[k] * (tip_radius - depth)
        data.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        if data.ncon == 0:
            continue
        c = data.contact[0]
        n = np.array(c.frame[:3]) * (1.0 if c.geom[0] == 0 else -1.0)
        found.append(k)
        measured_n.append(n)
        measured_p.append(np.array(c.pos) - 0.5 * c.dist * n)
    found_ = np.array(found, dtype=int)
    p, n = np.array(measured_p), np.array(measured_n)
    dist, angle = body.contact_errors(p, n)
    face = _on_faces(body, normals[found_])

    def stats(values: Array) -> dict[str, float] | None:
        if len(values) == 0:
            return None
        return {"median": float(np.median(values)), "p95": float(np.percentile(values, 95)),
                "count": int(len(values))}  # fmt: skip

    return {
        "resolution": int(resolution), "vertices": int(len(vertices)),
        "compile_seconds": compile_seconds, "missed": int(samples - len(found_)),
        "faces": stats(angle[face]), "edges": stats(angle[~face]), "all": stats(angle),
        "distance_median": float(np.median(dist)), "distance_p95": float(np.percentile(dist, 95)),
    }  # fmt: skip


def mesh_accuracy_table(
    bodies: Sequence[str], resolutions: Sequence[int] = (48, 64, 96, 128), samples: int = 2000
) -> dict[str, Any]:
    """:func:`mesh_contact_accuracy` of each paper body at each mesh resolution."""
    from hapticsim.data.bodies import get_body

    return {
        name: {str(r): mesh_contact_accuracy(get_body(name), r, samples) for r in resolutions}
        for name in bodies
    }


__all__ = [
    "FACE_ANGLE_DEG",
    "benchmark_sim",
    "exploration_time",
    "mesh_accuracy_table",
    "mesh_contact_accuracy",
    "physics_steps_per_second",
]
