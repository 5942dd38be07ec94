"""Benchmark of the MuJoCo simulation: physics steps per second of the hand + object scene and the
wall time of a 150-contact ``paper`` exploration per body. Prints JSON on stdout.

    python scripts/bench_sim.py [--bodies cube ellipsoid] [--count 150] [--repeat 1]

Wall times depend on the machine's load; the CPU time of the process is reported beside them.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import mujoco
import numpy as np

from hapticsim.data.bodies import BODY_NAMES, get_body
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.rough import vision_estimate
from hapticsim.sim.scene import build_scene
from hapticsim.sim.session import run_exploration


def physics_steps_per_second(body: str, steps: int = 20000) -> dict[str, float]:
    """Raw ``mj_step`` rate with the hand pressing a fingertip on the object (no Python loop)."""
    truth = get_body(body)
    scene = build_scene(truth)
    explorer = Explorer(scene, vision_estimate(truth, 0), Recorder())
    top = truth.center + np.array([0.0, 0.0, truth.a[2]])
    explorer.probe_patch(1, [Probe(top, np.array([0.0, 0.0, -1.0]))])
    sim = explorer.sim
    contact = explorer.recorder.contacts[-1]
    # press the fingertip on the contact again and hold it there
    sim.set_tip_target(1, contact.point_world + contact.normal_world * 0.006)
    for _ in range(100):
        sim.tick()
    start = time.perf_counter()
    mujoco.mj_step(sim.model, sim.data, nstep=steps)
    seconds = time.perf_counter() - start
    return {
        "steps_per_second": steps / seconds,
        "contacts": int(sim.data.ncon),
        "fingertip_force": float(sim.contacts.tips[1].force) if sim.contacts.tips[1] else 0.0,
        "mesh_vertices": int(scene.model.mesh_vertnum[0]),
    }


def exploration(body: str, count: int, seed: int) -> dict[str, float]:
    """Wall and CPU time of one ``paper`` exploration (scene building included)."""
    cpu = time.process_time()
    run = run_exploration(get_body(body), "paper", count=count, rng=seed)
    return {
        "contacts": run.count,
        "wall_seconds": run.wall_time,
        "cpu_seconds": time.process_time() - cpu,
        "sim_seconds": run.sim_time,
        "steps": run.steps,
        "closed_loop_steps_per_second": run.steps_per_second,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", default=list(BODY_NAMES), choices=BODY_NAMES)
    parser.add_argument("--count", type=int, default=150)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args(argv)
    out: dict[str, object] = {"physics": {}, "exploration": {}}
    for body in args.bodies:
        out["physics"][body] = physics_steps_per_second(body)  # type: ignore[index]
        runs = [exploration(body, args.count, seed) for seed in range(args.repeat)]
        out["exploration"][body] = {  # type: ignore[index]
            key: float(np.median([r[key] for r in runs])) for key in runs[0]
        }
        print(f"{body}: done", file=sys.stderr)
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
