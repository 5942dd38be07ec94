"""Why the tracking fit misses a resting object's turn (SPEC §12; docs/objects/moving/README.md):
the tracker's tuning set explored again, and the trajectory fitted under variants of the joint
fit, among them two with the object's model known.

    python scripts/track_diagnosis.py --out docs/objects/moving/diagnosis/track_diagnosis.json

The runs: the ``dev`` family of ``scripts/free_objects.py`` (random superquadrics, object seeds
1000-1005, 100 g), resting in the cradle with a 0.3 N force limit, the paper strategy and the
uncertainty policy, trial seeds 0-2 (36 runs, those with fewer than 20 contacts fail and are
left out), exact sensing, 150 contacts. For each run:

- ``true_frame``: the contacts carried into the object's frame by the *true* poses, against the
  true surface (median distance [mm] and normal angle [deg]), beside the same for the
  world-frame contacts (``world_frame``): how much the motion explains;
- per variant of :func:`hapticsim.fitting.track.track_poses`, the shape's IoU in the object's
  frame (none when the shape is known) and the last contact's drift (:func:`pose_drift`:
  position, angle, ADD-S). The variants: ``tracker`` (the default), ``per_contact`` (a pose per
  contact, the prior's scales a quarter), ``contact_scale`` (0.2 mm instead of the naive fit's
  RMS residual), ``tilt_2deg`` and ``turn_tilt_5deg`` (looser priors), ``bottom_pivot`` (the
  rotations about the bottom of the naive fit, where a rocking object turns, tilt 2 degrees),
  ``known_shape`` and ``known_shape_per_contact`` (the true superquadric held fixed, 0.2 mm).

Prints JSON (every run and the medians per strategy and variant); about 4 minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")

STRATEGIES = ("paper", "uncertainty")
VARIANTS = ("tracker", "per_contact", "contact_scale", "tilt_2deg", "turn_tilt_5deg",
            "bottom_pivot", "known_shape", "known_shape_per_contact")  # fmt: skip


def _variant(name: str, naive: Any, truth: Any) -> tuple[np.ndarray, dict[str, Any]]:
    """The start vector and the keyword arguments of :func:`track_poses` for variant `name`."""
    from hapticsim.fitting.track import MotionPrior

    base = MotionPrior()
    quarter = MotionPrior(base.slide / 4, base.lift / 4, base.turn / 4, base.tilt / 4)
    loose = {
        "per_contact": {"spacing": 1, "prior": quarter},
        "contact_scale": {"contact_scale": 2e-4},
        "tilt_2deg": {"prior": MotionPrior(tilt=np.radians(2.0))},
        "turn_tilt_5deg": {"prior": MotionPrior(turn=np.radians(5.0), tilt=np.radians(5.0))},
    }
    if name in ("known_shape", "known_shape_per_contact"):
        kwargs: dict[str, Any] = {"known_shape": True, "contact_scale": 2e-4}
        if name.endswith("per_contact"):
            kwargs.update(loose["per_contact"])
        return truth.to_vector(), kwargs
    if name == "bottom_pivot":
        surface, _ = naive.sample_surface(2000, np.random.default_rng(0))
        pivot = np.array([*naive.center[:2], surface[:, 2].min()])
        return naive.to_vector(), {"pivot": pivot, "prior": MotionPrior(tilt=np.radians(2.0))}
    return naive.to_vector(), loose.get(name, {})


def run_one(job: tuple[int, str, int]) -> dict[str, Any]:
    """One exploration and the variants' fits."""
    from hapticsim.data.objects import ObjectSpec
    from hapticsim.errors import HapticsimError
    from hapticsim.exploration.pipeline import run_trial
    from hapticsim.exploration.trial import Trial
    from hapticsim.fitting import fit
    from hapticsim.fitting.objective import Bounds
    from hapticsim.fitting.track import IDENTITY_POSE, pose_drift, track_poses, true_poses
    from hapticsim.geometry import Superquadric
    from hapticsim.geometry.rotations import quaternion_to_matrix
    from hapticsim.metrics.score import score
    from hapticsim.sim.dynamics import ObjectDynamics
    from hapticsim.sim.scene import SceneConfig

    object_seed, strategy, seed = job
    row: dict[str, Any] = {"object": f"random/{object_seed}", "strategy": strategy, "seed": seed}
    truth = ObjectSpec("random").resolve(np.random.default_rng(object_seed))
    scene = SceneConfig(object_dynamics=ObjectDynamics("resting", mass=0.1), force_limit=0.3)
    try:
        record = run_trial(Trial(truth, strategy, 150, estimator="nH", seed=seed, scene=scene))
    except HapticsimError as exc:
        return {**row, "error": str(exc)}
    points, normals = record.points, record.normals
    truth = record.truth
    poses = true_poses(record.exploration.arrays["object_pose"],
                       np.array(record.motion["rest_pose"]))  # fmt: skip
    rot = quaternion_to_matrix(poses[:, 3:])
    local = np.einsum("nji,nj->ni", rot, points - poses[:, :3])
    local_n = np.einsum("nji,nj->ni", rot, normals)
    for key, (p, n) in {"world_frame": (points, normals), "true_frame": (local, local_n)}.items():
        dist, angle = truth.contact_errors(p, n)
        row[key] = {"distance_mm": 1000 * float(np.median(np.abs(dist))),
                    "angle_deg": float(np.median(angle))}  # fmt: skip
    still = pose_drift(IDENTITY_POSE, poses[-1], truth.center, truth)
    row.update(contacts=len(points), moved_mm=1000 * still["position_m"],
               turned_deg=still["angle_deg"], moved_adds_mm=1000 * still["adds_m"])  # fmt: skip
    naive = fit(points, normals, method="nH", rng=record.seeds.rng("fit")).solid
    row["naive_iou"] = score(naive, truth, 0).iou
    bounds = Bounds.from_points(points)
    for name in VARIANTS:
        start, kwargs = _variant(name, naive, truth)
        tracked = track_poses(points, normals, start, bounds, **kwargs)
        drift = pose_drift(tracked.poses()[-1], poses[-1], truth.center, truth)
        row[name] = {
            "iou": None if kwargs.get("known_shape") else
            score(Superquadric.from_vector(tracked.vector), truth, 0).iou,
            "drift_mm": 1000 * drift["position_m"], "drift_deg": drift["angle_deg"],
            "drift_adds_mm": 1000 * drift["adds_m"],
        }  # fmt: skip
    return row


def summarise(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Medians per strategy (and over both) of every variant's measures."""
    out: dict[str, Any] = {}
    for strategy in (*STRATEGIES, "both"):
        ok = [r for r in rows if "error" not in r and strategy in (r["strategy"], "both")]
        if not ok:
            continue

        def med(values: list) -> float | None:
            values = [v for v in values if v is not None]
            return float(np.median(values)) if values else None

        entry: dict[str, Any] = {"runs": len(ok), "moved_mm": med([r["moved_mm"] for r in ok]),
                                 "turned_deg": med([r["turned_deg"] for r in ok]),
                                 "moved_adds_mm": med([r["moved_adds_mm"] for r in ok]),
                                 "naive_iou": med([r["naive_iou"] for r in ok])}  # fmt: skip
        for frame in ("world_frame", "true_frame"):
            entry[frame] = {k: med([r[frame][k] for r in ok]) for k in ok[0][frame]}
        for name in VARIANTS:
            entry[name] = {k: med([r[name][k] for r in ok]) for k in ok[0][name]}
        out[strategy] = entry
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default=None, help="also write the JSON here")
    args = parser.parse_args()
    jobs = [(s, strategy, seed) for s in range(1000, 1006) for strategy in STRATEGIES
            for seed in args.seeds]  # fmt: skip
    from hapticsim.parallel import parallel_map

    start = time.perf_counter()
    rows = parallel_map(run_one, jobs, args.workers, "track diagnosis", unit="run")
    rows.sort(key=lambda r: (r["object"], r["strategy"], r["seed"]))
    text = json.dumps({"command": " ".join(sys.argv), "seconds": time.perf_counter() - start,
                       "summary": summarise(rows), "runs": rows}, indent=1)  # fmt: skip
    if args.out:
        os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
        with open(args.out, "w") as f:
            f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
