"""Objects that move (SPEC §12): how far the hand moves a free object, and whether the tracking
fit recovers its shape: the tables of docs/objects/moving/README.md.

    python scripts/free_objects.py --seeds 0 1 2 --out docs/objects/moving/free_objects.json
    python scripts/free_objects.py --timing > docs/objects/moving/timing.json
    python scripts/free_objects.py --family dev --conditions resting resting@0.3   # tuning set

Families (``--family``; the tracker's motion prior, knots and robust residuals were chosen on
``dev`` and on synthetic contacts of a cuboid only; the cradle, the no-slip friction and the
force limit were written while watching the paper's cube and ``dev``, so for those the
``bodies`` family is not held out, ``random`` and ``composites`` are):

- ``dev``: random superquadrics, object seeds 1000-1005, 100 g each (the tuning set);
- ``bodies``: the paper's four bodies at the default density (500 kg/m^3: 107-180 g);
- ``random``: random superquadrics, object seeds 0-9, each of a mass drawn uniformly in
  50-500 g (seed 7 of the masses' own stream);
- ``composites``: random composites (object seeds 200-207, the default density).

Conditions (``--conditions``): ``fixed`` (the static object: the reference), ``resting`` and
``held`` (free, SPEC §12), each optionally ``@F`` with a force limit of F newtons
(``resting@0.3``; ``fixed@0.3`` measures what the limit costs on a fixed object). Every run:
the built-in hand, exact sensing, no sensor noise, 150 contacts of the strategy
(``--strategies``: ``paper``, and the ``uncertainty`` policy), trial seeds ``--seeds`` (default 0:
the vision estimate and the policy's choices); on the same contacts
the naive fit (nH of the world-frame contacts) and the tracking fit (nH+track), both scored
against the object at rest before the first touch (the tracking fit's shape is in that
frame), the naive fit also against the object where the run left it. Prints JSON (every run,
and per family, strategy and condition the medians over objects and seeds); with ``--markdown``
the tables on stderr. 264 runs a seed: about 5 minutes on 2 cores.
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

FAMILIES = ("dev", "bodies", "random", "composites")
BODIES = ("tapered_box", "cube", "cylinder", "ellipsoid")


def _objects(family: str) -> list[tuple[str, Any, float | None]]:
    """(label, truth, mass [kg] or None for the default density) of a family."""
    from hapticsim.data import get_body
    from hapticsim.data.objects import ObjectSpec, random_composite

    if family == "bodies":
        return [(name, get_body(name), None) for name in BODIES]
    if family == "composites":
        return [(f"composite/{s}", random_composite(s), None) for s in range(200, 208)]
    if family == "dev":
        return [(f"random/{s}", ObjectSpec("random").resolve(np.random.default_rng(s)), 0.1)
                for s in range(1000, 1006)]  # fmt: skip
    masses = np.random.default_rng(7).uniform(0.05, 0.5, size=10)
    return [(f"random/{s}", ObjectSpec("random").resolve(np.random.default_rng(s)), float(m))
            for s, m in zip(range(10), masses, strict=True)]  # fmt: skip


def _condition(text: str) -> tuple[str, float | None]:
    kind, _, limit = text.partition("@")
    return kind, (float(limit) if limit else None)


def run_one(job: tuple[str, str, Any, float | None, str, str, int]) -> dict[str, Any]:
    """One exploration and its two fits."""
    from hapticsim.errors import HapticsimError
    from hapticsim.exploration.pipeline import run_trial
    from hapticsim.exploration.trial import Trial
    from hapticsim.fitting import fit
    from hapticsim.fitting.track import IDENTITY_POSE, pose_drift, true_poses
    from hapticsim.metrics.score import score
    from hapticsim.sim.dynamics import ObjectDynamics
    from hapticsim.sim.scene import SceneConfig

    family, label, truth, mass, strategy, condition, seed = job
    kind, limit = _condition(condition)
    dynamics = ObjectDynamics(kind, mass=mass if kind != "fixed" else None)
    scene = SceneConfig(object_dynamics=dynamics, force_limit=limit)
    estimator = "nH" if kind == "fixed" else "nH+track"
    row: dict[str, Any] = {"family": family, "object": label, "strategy": strategy,
                           "condition": condition, "seed": seed, "mass_kg": mass}  # fmt: skip
    start = time.perf_counter()
    try:
        record = run_trial(Trial(truth, strategy, 150, estimator=estimator, seed=seed, scene=scene))
    except HapticsimError as exc:
        return {**row, "error": str(exc)}
    run = record.exploration
    row.update(contacts=run.count, stop_reason=run.stop_reason,
               explore_seconds=run.wall_time, sim_time=run.sim_time,
               force_p99=float(np.percentile(run.arrays["force"], 99)))  # fmt: skip
    if kind == "fixed":
        row.update(iou=record.quality.iou, epsilon=record.quality.epsilon,
                   fit_seconds=record.fit_seconds)  # fmt: skip
        return row | {"seconds": time.perf_counter() - start}
    naive = fit(record.points, record.normals, method="nH", rng=record.seeds.rng("fit"))
    naive_rest = score(naive.solid, record.truth, 0)
    naive_final = score(naive.solid, run.truth_final, 0)
    motion = record.motion
    last = true_poses(run.arrays["object_pose"][-1:], np.array(motion["rest_pose"]))[0]
    still = pose_drift(IDENTITY_POSE, last, record.truth.center, record.truth)
    row.update(
        mass_kg=motion["mass_kg"],
        moved_mm=1000 * motion["moved"]["last_contact"]["position_m"],
        turned_deg=motion["moved"]["last_contact"]["angle_deg"],
        naive_iou=naive_rest.iou, naive_iou_final=naive_final.iou,
        track_iou=record.quality.iou, track_epsilon=record.quality.epsilon,
        drift_mm=1000 * motion["pose_drift"]["position_m"],
        drift_deg=motion["pose_drift"]["angle_deg"], fit_seconds=record.fit_seconds,
        drift_add_mm=1000 * motion["pose_drift"]["add_m"],
        drift_adds_mm=1000 * motion["pose_drift"]["adds_m"],
        moved_adds_mm=1000 * still["adds_m"],
    )  # fmt: skip
    return row | {"seconds": time.perf_counter() - start}


def summarise(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Medians per (family, strategy, condition), with the fixed run's IoU of the same objects."""
    out = []
    fixed = {(r["family"], r["object"], r["strategy"], r["seed"]): r.get("iou") for r in rows
             if r["condition"] == "fixed" and "error" not in r}  # fmt: skip
    groups = sorted({(r["family"], r["strategy"], r["condition"]) for r in rows})
    for family, strategy, condition in groups:
        group = [r for r in rows if (r["family"], r["strategy"], r["condition"])
                 == (family, strategy, condition)]  # fmt: skip
        ok = [r for r in group if "error" not in r]
        entry: dict[str, Any] = {"family": family, "strategy": strategy, "condition": condition,
                                 "runs": len(group), "failed": len(group) - len(ok),
                                 "complete": sum(r["contacts"] >= 150 for r in ok)}  # fmt: skip

        def med(key: str, ok: list = ok) -> float | None:
            return float(np.median([r[key] for r in ok])) if ok else None

        if condition.startswith("fixed"):
            entry.update(iou=med("iou"), explore_seconds=med("explore_seconds"))
        elif ok:
            base = [fixed.get((family, r["object"], strategy, r["seed"])) for r in ok]
            pairs = [(r, b) for r, b in zip(ok, base, strict=True) if b is not None]
            entry.update(
                moved_mm=med("moved_mm"), turned_deg=med("turned_deg"), naive_iou=med("naive_iou"),
                track_iou=med("track_iou"), naive_iou_final=med("naive_iou_final"),
                drift_mm=med("drift_mm"), drift_deg=med("drift_deg"),
                drift_add_mm=med("drift_add_mm"), drift_adds_mm=med("drift_adds_mm"),
                moved_adds_mm=med("moved_adds_mm"),
                explore_seconds=med("explore_seconds"),
                naive_drop=float(np.median([b - r["naive_iou"] for r, b in pairs]))
                if pairs else None,
                track_drop=float(np.median([b - r["track_iou"] for r, b in pairs]))
                if pairs else None,
            )  # fmt: skip
            whole = [r for r in ok if r["contacts"] >= 150]  # the runs the object stood through
            entry["complete_only"] = {
                key: med(key, whole) if whole else None
                for key in ("drift_mm", "drift_deg", "drift_adds_mm", "moved_adds_mm")
            }
        out.append(entry)
    return out


def _rounded(value: Any) -> Any:
    """`value` with every float rounded to 5 decimals (JSON-ready)."""
    if isinstance(value, (float, np.floating)):
        return round(float(value), 5)
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_rounded(v) for v in value]
    return value


def markdown(summary: list[dict[str, Any]]) -> str:
    """The summary as a Markdown table."""
    head = ("| family | strategy | condition | runs (complete) | moved mm | turned deg | naive IoU "
            "| track IoU | drop naive / track | drift mm / deg | ADD-S mm still / tracked "
            "| complete: drift mm / deg / ADD-S mm | explore s |")  # fmt: skip
    lines = [head, "|" + "---|" * 13]
    fmt = lambda v, p=3: "–" if v is None else f"{v:.{p}f}"  # noqa: E731
    for e in summary:
        if e["condition"].startswith("fixed"):
            lines.append(f"| {e['family']} | {e['strategy']} | {e['condition']} | {e['runs']} "
                         f"({e['complete']}) | 0 | 0 | {fmt(e.get('iou'))} | – | – | – | – | – | "
                         f"{fmt(e.get('explore_seconds'), 1)} |")  # fmt: skip
            continue
        c = e.get("complete_only") or {}
        lines.append(
            f"| {e['family']} | {e['strategy']} | {e['condition']} | {e['runs']} ({e['complete']})"
            f" | {fmt(e.get('moved_mm'), 2)} | {fmt(e.get('turned_deg'), 2)} | "
            f"{fmt(e.get('naive_iou'))} | {fmt(e.get('track_iou'))} | "
            f"{fmt(e.get('naive_drop'))} / {fmt(e.get('track_drop'))} | "
            f"{fmt(e.get('drift_mm'), 2)} / {fmt(e.get('drift_deg'), 2)} | "
            f"{fmt(e.get('moved_adds_mm'), 2)} / {fmt(e.get('drift_adds_mm'), 2)} | "
            f"{fmt(c.get('drift_mm'), 2)} / {fmt(c.get('drift_deg'), 2)} / "
            f"{fmt(c.get('drift_adds_mm'), 2)} | "
            f"{fmt(e.get('explore_seconds'), 1)} |"
        )
    return "\n".join(lines)


def timing(repeats: int = 4) -> dict[str, Any]:
    """What a free object costs ``explore`` (SPEC §12: within 1.5x of fixed): the paper's bodies,
    paper strategy, 150 contacts, ``fixed`` against ``resting`` and ``held`` objects in two
    settings: ``unlimited`` (no force limit, objects of 1 kg, heavy enough that most runs
    complete) and ``gentle`` (a 0.3 N force limit, the default density). Each run `repeats`
    times in this process after a warm-up, the kinds interleaved so that a change of load
    falls on all; per body the median CPU seconds of the exploration (scene and settling
    included), its ratio to the fixed object's, and the CPU microseconds a physics step costs.
    A run that ended early (the object tipped over) explores less: its time ratio is marked
    ``ended_early`` and only its per-step cost compares."""
    from hapticsim.data import get_body
    from hapticsim.sim.dynamics import ObjectDynamics
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.session import run_exploration

    settings = {"unlimited": (1.0, None), "gentle": (None, 0.3)}
    kinds = ("fixed", "resting", "held")
    run_exploration(get_body("cube"), "paper", 150, 0)  # warm-up
    out: dict[str, Any] = {}
    for setting, (mass, limit) in settings.items():
        rows: dict[tuple[str, str], list[tuple[float, int, int]]] = {}
        for _ in range(repeats):
            for name in BODIES:
                for kind in kinds:
                    dynamics = ObjectDynamics(kind, mass=None if kind == "fixed" else mass)
                    scene = SceneConfig(object_dynamics=dynamics, force_limit=limit)
                    cpu = time.process_time()
                    run = run_exploration(get_body(name), "paper", 150, 0, scene_config=scene)
                    rows.setdefault((kind, name), []).append(
                        (time.process_time() - cpu, run.steps, run.count))
        table: dict[str, Any] = {}
        for kind in kinds:
            entry: dict[str, Any] = {}
            for name in BODIES:
                runs = rows[(kind, name)]
                fixed = float(np.median([r[0] for r in rows[("fixed", name)]]))
                cpu = float(np.median([r[0] for r in runs]))
                entry[name] = {
                    "cpu_seconds": cpu, "ratio": cpu / fixed,
                    "us_per_step": 1e6 * float(np.median([r[0] / r[1] for r in runs])),
                    "ended_early": sum(r[2] < 150 for r in runs),
                }  # fmt: skip
            table[kind] = entry
        out[setting] = {"mass_kg": mass, "force_limit": limit, **table}
    out["repeats"] = repeats
    out["load_average"] = os.getloadavg()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--family", nargs="+", default=["bodies", "random", "composites"],
                        choices=FAMILIES)  # fmt: skip
    parser.add_argument("--strategies", nargs="+", default=["paper", "uncertainty"])
    parser.add_argument("--conditions", nargs="+",
                        default=["fixed", "fixed@0.3", "resting", "resting@0.3", "held",
                                 "held@0.3"])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0],
                        help="trial seeds (the vision estimate, the policy's choices)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default=None, help="also write the JSON here")
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--timing", action="store_true",
                        help="only time explore with fixed, resting and held objects (JSON)")
    args = parser.parse_args()
    if args.timing:
        print(json.dumps(timing(), indent=1))
        return
    jobs = [(family, label, truth, mass, strategy, condition, seed)
            for family in args.family for label, truth, mass in _objects(family)
            for strategy in args.strategies for condition in args.conditions
            for seed in args.seeds]  # fmt: skip
    start = time.perf_counter()
    rows = []
    with Pool(args.workers) as pool:
        for k, row in enumerate(pool.imap_unordered(run_one, jobs), 1):
            rows.append(row)
            result = row.get("error") or row.get("track_iou", row.get("iou"))
            sys.stderr.write(f"[{k}/{len(jobs)}] {row['family']} {row['object']} "
                             f"{row['strategy']} {row['condition']}: {result}\n")  # fmt: skip
    summary = summarise(rows)
    order = sorted(rows, key=lambda r: (r["family"], r["object"], r["strategy"], r["condition"],
                                        r["seed"]))
    head = {"command": " ".join(sys.argv), "seconds": time.perf_counter() - start,
            "summary": _rounded(summary)}  # fmt: skip
    # one line a run: 792 runs in ~200 KB
    text = (json.dumps(head, indent=1)[:-2] + ',\n "runs": [\n'
            + ",\n".join("  " + json.dumps(_rounded(r)) for r in order) + "\n ]\n}")
    if args.out:
        os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
        with open(args.out, "w") as f:
            f.write(text + "\n")
    print(text)
    if args.markdown:
        sys.stderr.write(markdown(summary) + "\n")


if __name__ == "__main__":
    main()
