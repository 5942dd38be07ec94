"""One superquadric (nH) against a union of them (multi) on objects of several parts, explored by
the hand: the tables of docs/objects.md ("Objects of several parts").

    python scripts/multi_table.py --out docs/objects/multi_table.json      # ~25 min, 2 cores

Families (every exploration: the built-in hand, MuJoCo, no sensor noise unless stated; nH and
multi fit the same contacts, with the fit seed of ``hapticsim explore``):

- ``tuning``: what multi was tuned on while it was written: area-uniform surface samples (300)
  of the L-block and of random composites seeds 0-7 (contacts all round, no hand);
- ``l_block``: the L-block mesh, the paper strategy (150 and 300 contacts) and the uncertainty
  policy (its first 150 and all 300 contacts), seeds 0-2;
- ``composites``: 10 random composites (object seeds 100-109, none seen while tuning), the same
  explorations, seed 0;
- ``pybullet``: 20 pybullet_data objects (duck, jenga, domino and the first 17 procedural ones
  that load and are hand-sized: bounding radius <= 0.10 m), the same explorations, seed 0;
- ``one_part``: the paper's four bodies x 10 random orientations, paper 150 and uncertainty 300:
  how often multi keeps one part, and its epsilon against nH's;
- ``noisy``: the composites' uncertainty runs with sensor noise sigma_N = 0.05 added (SPEC §5);
- ``synthetic``: the paper's one-sided patterns drawn on each part of the composites
  (:func:`hapticsim.data.synthetic.synthetic_dataset`, 300 contacts, no hand).

Prints JSON (every run's figures, and per family and setting the means and medians); with
``--markdown`` also the tables.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from multiprocessing import Pool
from typing import Any

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")

PYBULLET_NAMED = ("duck", "jenga", "domino")
PYBULLET_RANDOM = 17
COMPOSITE_SEEDS = tuple(range(100, 110))
TUNING_SEEDS = tuple(range(8))


def _objects() -> dict[str, list[str]]:
    """The objects of each hand family (names ``_truth`` resolves)."""
    from hapticsim.data.library import load_library_object
    from hapticsim.errors import InvalidInputError

    blobs: list[str] = []
    k = 0
    while len(blobs) < PYBULLET_RANDOM and k < 1000:
        name = f"random/{k:03d}"
        k += 1
        try:
            if load_library_object(name).bounding_radius <= 0.10:
                blobs.append(name)
        except InvalidInputError:
            continue
    return {
        "l_block": ["l_block"],
        "composites": [f"composite:{s}" for s in COMPOSITE_SEEDS],
        "pybullet": [f"pybullet:{n}" for n in PYBULLET_NAMED] + [f"pybullet:{b}" for b in blobs],
    }


def _truth(name: str, pose: int | None = None) -> Any:
    from hapticsim.data import get_body
    from hapticsim.data.example_meshes import EXAMPLE_MESHES
    from hapticsim.data.objects import ObjectSpec, random_composite
    from hapticsim.geometry import random_rotation

    if name in EXAMPLE_MESHES:
        return EXAMPLE_MESHES[name]()
    if name.startswith("composite:"):
        return random_composite(int(name.split(":")[1]))
    if pose is not None:
        body = get_body(name)
        return body.transformed(random_rotation(np.random.default_rng(1000 + pose)), np.zeros(3))
    return ObjectSpec(name).resolve()


def _fits(points: np.ndarray, normals: np.ndarray, truth: Any, seed: int) -> dict[str, Any]:
    from hapticsim.fitting import fit
    from hapticsim.metrics import score

    out: dict[str, Any] = {}
    for method in ("nH", "multi"):
        start = time.process_time()
        result = fit(points, normals, method=method, rng=seed)
        cpu = time.process_time() - start
        q = score(result.solid, truth, rng=seed)
        out[method] = {
            "iou": q.iou, "epsilon": q.epsilon, "chamfer": q.chamfer,
            "parts": len(result.solid.components), "seconds": result.seconds, "cpu_seconds": cpu,
        }  # fmt: skip
    return out


def _task(task: tuple) -> list[dict[str, Any]]:
    """One exploration (or contact set) and its fits: one row per contact count; a failed
    exploration is a row with its error."""
    from hapticsim.errors import HapticsimError

    try:
        return _run(task)
    except HapticsimError as exc:
        family, name, strategy, count, seed, pose, noise = task
        print(f"{family:10s} {name:22s} {strategy:11s} {count}: FAILED {exc}", file=sys.stderr,
              flush=True)  # fmt: skip
        return [{"family": family, "object": name, "strategy": strategy, "count": count,
                 "seed": seed, "pose": pose, "noise": noise, "error": str(exc)}]  # fmt: skip


def _run(task: tuple) -> list[dict[str, Any]]:
    family, name, strategy, count, seed, pose, noise = task
    from hapticsim.data.noise import add_noise
    from hapticsim.data.synthetic import synthetic_dataset
    from hapticsim.exploration import explorer_for, is_policy

    truth = _truth(name, pose)
    fit_seed = int(np.random.SeedSequence(seed).spawn(3)[2].generate_state(1)[0])
    start = time.perf_counter()
    if strategy == "surface":
        pts, nrm = truth.sample_surface(count, rng=seed)
        runs = [(count, pts, nrm, None)]
    elif strategy == "synthetic":
        c = synthetic_dataset(truth, noise=0.0, rng=seed, count=count)
        runs = [(count, c.points, c.normals, None)]
    else:
        sim_rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(3)[0])
        run = explorer_for(strategy).explore(truth, count, sim_rng, None)
        a = run.arrays
        dist, _ = truth.contact_errors(a["points_clean"], a["normals_clean"])
        accuracy = float(np.median(dist))
        counts = (150, count) if is_policy(strategy) and count > 150 else (count,)
        runs = [(k, a["points_clean"][:k], a["normals_clean"][:k], accuracy) for k in counts]
    rows = []
    for k, pts, nrm, accuracy in runs:
        if noise:
            gen = np.random.default_rng(np.random.SeedSequence(seed).spawn(3)[1])
            pts, nrm = add_noise(pts, nrm, noise, truth.size, gen)
        rows.append({
            "family": family, "object": name, "strategy": strategy, "count": int(k),
            "seed": seed, "pose": pose, "noise": noise, "contacts": int(len(pts)),
            "distance_median": accuracy, **_fits(pts, nrm, truth, fit_seed),
            "seconds": time.perf_counter() - start,
        })  # fmt: skip
    print(f"{family:10s} {name:22s} {strategy:11s} {count}: " + ", ".join(
        f"{r['count']} multi {r['multi']['iou']:.3f} ({r['multi']['parts']}) nH "
        f"{r['nH']['iou']:.3f}" for r in rows), file=sys.stderr, flush=True)  # fmt: skip
    return rows


def _tasks(objects: dict[str, list[str]]) -> list[tuple]:
    tasks: list[tuple] = []
    for s in TUNING_SEEDS:
        tasks.append(("tuning", f"composite:{s}", "surface", 300, s, None, 0.0))
    tasks += [("tuning", "l_block", "surface", 300, s, None, 0.0) for s in range(3)]
    for family, names in objects.items():
        seeds = range(3) if family == "l_block" else (0,)
        for name in names:
            for seed in seeds:
                for strategy, count in (("paper", 150), ("paper", 300), ("uncertainty", 300)):
                    tasks.append((family, name, strategy, count, seed, None, 0.0))
    for body in ("tapered_box", "cube", "cylinder", "ellipsoid"):
        for pose in range(10):
            tasks.append(("one_part", body, "paper", 150, pose, pose, 0.0))
            tasks.append(("one_part", body, "uncertainty", 300, pose, pose, 0.0))
    for name in objects["composites"]:
        tasks.append(("noisy", name, "uncertainty", 300, 0, None, 0.05))
        tasks.append(("synthetic", name, "synthetic", 300, 0, None, 0.0))
    return tasks


def _summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    keys = sorted({(r["family"], r["strategy"], r["count"]) for r in rows})
    for family, strategy, count in keys:
        every = [r for r in rows if (r["family"], r["strategy"], r["count"]) == (family, strategy,
                                                                                count)]  # fmt: skip
        sel = [r for r in every if "error" not in r]
        entry: dict[str, Any] = {"runs": len(sel), "failed": len(every) - len(sel)}
        if not sel:
            out[f"{family}/{strategy}/{count}"] = entry
            continue
        for m in ("nH", "multi"):
            entry[m] = {
                "iou_mean": float(np.mean([r[m]["iou"] for r in sel])),
                "iou_median": float(np.median([r[m]["iou"] for r in sel])),
                "epsilon_mean": float(np.mean([r[m]["epsilon"] for r in sel])),
                "chamfer_mean_mm": 1e3 * float(np.mean([r[m]["chamfer"] for r in sel])),
                "parts_mean": float(np.mean([r[m]["parts"] for r in sel])),
                "seconds_median": float(np.median([r[m]["seconds"] for r in sel])),
            }
        entry["one_part_share"] = float(np.mean([r["multi"]["parts"] == 1 for r in sel]))
        entry["epsilon_gap_max"] = float(max(abs(r["multi"]["epsilon"] - r["nH"]["epsilon"])
                                             for r in sel))  # fmt: skip
        out[f"{family}/{strategy}/{count}"] = entry
    return out


def _markdown(summary: dict[str, Any]) -> str:
    lines = [
        "| family / exploration / contacts | runs (failed) | IoU nH | IoU multi | epsilon nH | "
        "epsilon multi | Chamfer nH [mm] | Chamfer multi [mm] | parts | multi fit [s] |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for key, e in summary.items():
        if not e["runs"]:
            lines.append(f"| {key} | 0 ({e['failed']}) | | | | | | | | |")
            continue
        n, m = e["nH"], e["multi"]
        lines.append(
            f"| {key} | {e['runs']} ({e['failed']}) | {n['iou_mean']:.3f} | {m['iou_mean']:.3f} | "
            f"{n['epsilon_mean']:.3f} | {m['epsilon_mean']:.3f} | {n['chamfer_mean_mm']:.2f} | "
            f"{m['chamfer_mean_mm']:.2f} | {m['parts_mean']:.2f} | {m['seconds_median']:.2f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None, help="also write the JSON here")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--families", nargs="*", default=None, help="only these families")
    parser.add_argument("--markdown", action="store_true", help="print the tables on stderr")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    start = time.perf_counter()
    tasks = _tasks(_objects())
    if args.families:
        tasks = [t for t in tasks if t[0] in args.families]
    print(f"multi table: {len(tasks)} tasks on {args.workers} workers", file=sys.stderr)
    with Pool(args.workers) as pool:
        rows = [r for chunk in pool.imap(_task, tasks) for r in chunk]
    summary = _summary(rows)
    result = {
        "command": "python scripts/multi_table.py " + " ".join(
            sys.argv[1:] if argv is None else argv),  # fmt: skip
        "load_average_1min": {"start": load, "end": os.getloadavg()[0]},
        "seconds": time.perf_counter() - start,
        "summary": summary,
        "rows": rows,
    }
    text = json.dumps(result, indent=2) + "\n"
    sys.stdout.write(text)
    if args.markdown:
        print(_markdown(summary), file=sys.stderr)
    if args.out is not None:
        from pathlib import Path

        from hapticsim._files import write_text_atomic

        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(args.out, text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
