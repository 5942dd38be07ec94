"""Timing of the simulation: physics steps per second of the hand + object scene and wall time of
a 150-contact ``paper`` exploration (used by ``scripts/bench.py --section sim`` and
``scripts/bench_sim.py``)."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np

from hapticsim.geometry import Superquadric
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.rough import vision_estimate
from hapticsim.sim.scene import build_scene
from hapticsim.sim.session import run_exploration


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
    truth: Superquadric, strategy: str = "paper", count: int = 150, seed: int = 0
) -> dict[str, float]:
    """Wall and CPU time of one exploration, scene building included.

    Returns:
        ``contacts``, ``wall_seconds``, ``cpu_seconds``, ``sim_seconds``, ``steps`` and
        ``closed_loop_steps_per_second`` (physics steps per wall second with the controllers).
    """
    cpu = time.process_time()
    run = run_exploration(truth, strategy, count=count, rng=seed)
    return {
        "contacts": float(run.count),
        "wall_seconds": run.wall_time,
        "cpu_seconds": time.process_time() - cpu,
        "sim_seconds": run.sim_time,
        "steps": float(run.steps),
        "closed_loop_steps_per_second": run.steps_per_second,
    }


def benchmark_sim(
    bodies: Sequence[str] | None = None, count: int = 150, repeat: int = 1
) -> dict[str, Any]:
    """Both timings for the paper's bodies (median over `repeat` seeds for explorations)."""
    from hapticsim.data.bodies import BODY_NAMES, get_body

    out: dict[str, Any] = {"physics": {}, "exploration": {}}
    for name in bodies or BODY_NAMES:
        truth = get_body(name)
        out["physics"][name] = physics_steps_per_second(truth)
        runs = [exploration_time(truth, "paper", count, seed) for seed in range(repeat)]
        out["exploration"][name] = {k: float(np.median([r[k] for r in runs])) for k in runs[0]}
    return out


__all__ = ["benchmark_sim", "exploration_time", "physics_steps_per_second"]
