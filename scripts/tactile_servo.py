"""Controllers that feel (issue 38 items 4-5, docs/tactile/servo): tactile-servo explorations
against explorations steering on MuJoCo's contacts, and what the servo costs.

Explorations are ``scripts/tactile_table.py``'s runs (the ``paper`` strategy, 150 contacts,
sigma_N = 0; nH fits, seed 0): exact sensing, and tactile sensing through each skin preset
(``ideal``, ``vision``, ``capacitive``) steering on the skin (``steer_on="skin"``, the default)
and on MuJoCo's contacts (``"contacts"``, as before the skin closed the loop), on

- ``paper``: the paper's four bodies, seeds 0-2, hapticsim's hand;
- ``random-tapered``: ten random tapered superquadrics (k = 0..9), seed 0, hapticsim's hand
  (held out: the servo was written on the cube);
- ``meshes``: the hexagonal prism and the L-block (non-convex), seed 0 (held out);
- ``shadow``, ``adroit``: the paper's bodies, seed 0, the Gymnasium-Robotics hands (extra
  ``hands``; skipped without it).

Per family, preset and steering: the estimated contacts' distance to the true surface and normal
angle (medians over the runs of the per-run median and p95), nH's epsilon and IoU (means), the
largest nH epsilon difference against the exact-sensing run of the same object and seed, unfelt
touches and the median simulation seconds.

Speed: steps per CPU second of the environments pooled over seeds 0-5 (15 random touches each,
after one warm-up episode), in the same run: ``HapticExplore-v0`` (exact) and
``HapticExploreTactile-v1`` (ideal skin, traction field) steering on the skin and on MuJoCo's
contacts (MuJoCo backend; the analytic backend has no controllers).

    python scripts/tactile_servo.py --out docs/tactile/servo/servo.json \
        --markdown docs/tactile/servo/README.md
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from tactile_table import BODIES, PRESETS, _task, write_results  # noqa: E402

START, END = "<!-- servo-table:start -->", "<!-- servo-table:end -->"
STEERINGS = ("skin", "contacts")


def _objects() -> list[tuple[str, str, str, str, int]]:
    out = [("paper", "body", b, "hapticsim", s) for s in (0, 1, 2) for b in BODIES]
    out += [("random-tapered", "random", str(k), "hapticsim", 0) for k in range(10)]
    out += [("meshes", "mesh", m, "hapticsim", 0) for m in ("hexagonal_prism", "l_block")]
    if importlib.util.find_spec("gymnasium_robotics") is not None:
        out += [(hand, "body", b, hand, 0) for hand in ("shadow", "adroit") for b in BODIES]
    return out


def tasks() -> list[tuple[Any, ...]]:
    out: list[tuple[Any, ...]] = []
    for obj in _objects():
        out.append((*obj, "exact", "ideal"))
        out += [(*obj, "tactile", p, steer) for p in PRESETS for steer in STEERINGS]
    return out


def summary(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per family, skin and steering: medians and means over the runs (module docstring)."""
    exact = {(r["family"], r["object"], r["seed"]): r for r in rows if r["sensing"] == "exact"}
    groups: dict[tuple[str, str, str], list[dict[str, Any]]] = {}
    for r in rows:
        exact_run = r["sensing"] == "exact"
        key = (r["family"], "exact", "") if exact_run else (r["family"], r["skin"], r["steer_on"])
        groups.setdefault(key, []).append(r)
    out = []
    for (family, skin, steer), group in groups.items():
        cell: dict[str, Any] = {"family": family, "skin": skin, "steer_on": steer,
                                "runs": len(group)}  # fmt: skip
        for key in ("distance_median", "distance_p95", "angle_median_deg", "angle_p95_deg"):
            cell[f"{key}_median"] = float(np.median([r[key] for r in group]))
        cell["distance_p95_max"] = float(np.max([r["distance_p95"] for r in group]))
        cell["nH_mean"] = float(np.mean([r["nH"] for r in group]))
        cell["iou_mean"] = float(np.mean([r["nH_iou"] for r in group]))
        cell["iou_min"] = float(np.min([r["nH_iou"] for r in group]))
        diff = [r["nH"] - exact[(family, r["object"], r["seed"])]["nH"] for r in group]
        cell["nH_minus_exact_max"] = float(np.max(diff))
        cell["nH_minus_exact_mean"] = float(np.mean(diff))
        cell["unfelt_total"] = int(sum(r["unfelt"] for r in group))
        cell["contacts_min"] = int(min(r["contacts"] for r in group))
        cell["sim_seconds_median"] = float(np.median([r["sim_seconds"] for r in group]))
        out.append(cell)
    return out


def env_rate(env_id: str, seed: int, touches: int = 15, **kwargs: Any) -> tuple[int, float]:
    """Steps and CPU seconds of one episode of `touches` random touches (after `reset(seed)`)."""
    import gymnasium as gym

    import hapticsim  # noqa: F401

    env = gym.make(env_id, touch_budget=touches, **kwargs)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    start = time.process_time()
    steps = 0
    for _ in range(touches):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        steps += 1
        if terminated or truncated:
            break
    env.close()
    return steps, time.process_time() - start


def speed(seeds: int = 6) -> dict[str, Any]:
    """Steps per CPU second, pooled over seeds (module docstring)."""
    variants = {
        "exact": ("hapticsim/HapticExplore-v0", {}),
        "tactile_skin": ("hapticsim/HapticExploreTactile-v1", {"steer_on": "skin"}),
        "tactile_contacts": ("hapticsim/HapticExploreTactile-v1", {"steer_on": "contacts"}),
    }
    for env_id, kwargs in variants.values():
        env_rate(env_id, 99, backend="mujoco", **kwargs)  # compile and cache
    totals = {name: [0, 0.0] for name in variants}
    load = os.getloadavg()
    for seed in range(seeds):
        for name, (env_id, kwargs) in variants.items():
            steps, cpu = env_rate(env_id, seed, backend="mujoco", **kwargs)
            totals[name][0] += steps
            totals[name][1] += cpu
    rates = {name: steps / cpu for name, (steps, cpu) in totals.items()}
    out = {"backend": "mujoco", "seeds": seeds, "steps_per_cpu_second": rates,
           "skin_over_exact": rates["tactile_skin"] / rates["exact"],
           "contacts_over_exact": rates["tactile_contacts"] / rates["exact"],
           "load_average": [load, os.getloadavg()]}  # fmt: skip
    print(f"speed: {out}", file=sys.stderr)
    return out


def markdown(cells: list[dict[str, Any]], rates: dict[str, Any]) -> str:
    def mm(x: float) -> str:
        return f"{x * 1e3:.3f}"

    lines = [
        "| family | skin | steers on | runs | distance median / p95 [mm] (worst p95) | normal "
        "angle median / p95 [deg] | nH epsilon | nH - exact (max) | IoU (min) | unfelt | sim "
        "s |",
        "|:---|:---|:---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for c in cells:
        lines.append(
            f"| {c['family']} | {c['skin']} | {c['steer_on'] or '–'} | {c['runs']} | "
            f"{mm(c['distance_median_median'])} / {mm(c['distance_p95_median'])} "
            f"({mm(c['distance_p95_max'])}) | {c['angle_median_deg_median']:.2f} / "
            f"{c['angle_p95_deg_median']:.2f} | {c['nH_mean']:.4f} | "
            + ("" if c["skin"] == "exact" else f"{c['nH_minus_exact_max']:+.4f}")
            + f" | {c['iou_mean']:.4f} ({c['iou_min']:.4f}) | "
            + ("" if c["skin"] == "exact" else f"{c['unfelt_total']}")
            + f" | {c['sim_seconds_median']:.1f} |"
        )
    r = rates["steps_per_cpu_second"]
    lines += [
        "",
        "| environment (MuJoCo hand, same run, seeds 0-5 pooled) | steps per CPU second | of "
        "exact |",
        "|:---|---:|---:|",
        f"| `HapticExplore-v0`, exact sensing | {r['exact']:.1f} | 1 |",
        f"| `HapticExploreTactile-v1`, steering on the skin | {r['tactile_skin']:.1f} | "
        f"{rates['skin_over_exact']:.2f} |",
        f"| `HapticExploreTactile-v1`, steering on MuJoCo's contacts | "
        f"{r['tactile_contacts']:.1f} | {rates['contacts_over_exact']:.2f} |",
        "",
        f"Load average {rates['load_average'][0][0]:.2f} at the start of the speed runs, "
        f"{rates['load_average'][1][0]:.2f} at the end.",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    from hapticsim.parallel import parallel_map
    from hapticsim.suites.provenance import manifest

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--out", help="write every run, the summary and the speeds as JSON")
    parser.add_argument("--markdown", help="rewrite the tables between the markers of this file")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    load = os.getloadavg()
    rows = parallel_map(_task, tasks(), args.processes, "servo table",
                        names=lambda t: "/".join(str(x) for x in (t[0], t[2], *t[5:])))
    cells = summary(rows)
    rates = speed()
    out = {"summary": cells, "speed": rates, "runs": rows,
           "wall_seconds": time.perf_counter() - start,
           "load_average": [load, os.getloadavg()], "processes": args.processes}  # fmt: skip
    text = json.dumps(out, indent=1)
    write_results(args.out, text, args.markdown, START, END, markdown(cells, rates))
    if args.out:
        from hapticsim._files import write_text_atomic

        command = ["python", "scripts/tactile_servo.py", *(argv if argv is not None
                                                            else sys.argv[1:])]  # fmt: skip
        write_text_atomic(str(Path(args.out).parent / "manifest.json"),
                          json.dumps(manifest(command), indent=2) + "\n")  # fmt: skip
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
