"""The tables of issue 19 (docs/tactile/README.md): contacts estimated from taxels, and the fits.

Every run is :class:`hapticsim.exploration.StrategyExplorer`'s (the simulation of ``hapticsim
explore``): the ``paper`` strategy, 150 contacts, sigma_N = 0, with exact sensing and with
tactile sensing through each skin preset (``ideal``, ``vision``, ``capacitive``), on these
families (the estimator was developed on the first; the others are held out):

- ``paper-seed0``: the paper's four bodies, seed 0, hapticsim's hand (tuning);
- ``paper-seeds1-2``: the same bodies, seeds 1 and 2 (other vision estimates and strategy
  draws);
- ``random-tapered``: ten random tapered superquadrics (``random_superquadric(k, tapered=True)``,
  k = 0..9), seed 0;
- ``meshes``: the hexagonal prism (convex) and the L-block (non-convex, two convex parts),
  seed 0; a normal within :data:`EDGE_TOLERANCE` of a sharp edge is held against the edge's
  normal cone (the strict p95, 1 um, is in the runs' ``angle_strict_p95_deg``);
- ``shadow``: the paper's bodies with the Shadow hand (extra ``hands``), seed 0.

Per run: the estimated contacts' distance to the true surface and normal angle (against the
true normal at the estimated point, and at the touched point: MuJoCo's exact contact), the
touches the pads did not feel, and epsilon of nH and nML fits (seed 0) of the estimated
contacts (nML with their per-contact sigma, and without it), of the same touches' exact contacts,
and of the exact-sensing run's contacts.

    python scripts/tactile_table.py --out docs/tactile/table.json --markdown docs/tactile/README.md
    python scripts/tactile_table.py --quick            # paper-seed0 only
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from typing import Any

import numpy as np

PRESETS = ("ideal", "vision", "capacitive")
#: On a mesh's sharp edges any normal of the edge's cone is right: an estimate within half of
#: the 1 mm pitch of an edge is held against the cone (docs/tactile/README.md; the strict
#: figure, 1 um, is reported beside).
EDGE_TOLERANCE = 5e-4
START, END = "<!-- tactile-table:start -->", "<!-- tactile-table:end -->"
BODIES = ("tapered_box", "cube", "cylinder", "ellipsoid")


def _truth(kind: str, name: str) -> Any:
    from hapticsim.data import get_body
    from hapticsim.data.example_meshes import example_mesh
    from hapticsim.data.objects import random_superquadric

    if kind == "body":
        return get_body(name)
    if kind == "random":
        return random_superquadric(int(name), tapered=True)
    return example_mesh(name)


def _angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=1), -1.0, 1.0)))


def _true_normals(truth: Any, points: np.ndarray) -> np.ndarray:
    return truth.normals(points)


def _epsilon(points: np.ndarray, normals: np.ndarray, truth: Any, method: str,
             **extra: Any) -> float:  # fmt: skip
    return _scores(points, normals, truth, method, **extra)[0]


def _scores(points: np.ndarray, normals: np.ndarray, truth: Any, method: str,
            **extra: Any) -> tuple[float, float]:  # fmt: skip
    """epsilon and IoU of a fit (seed 0) of contacts against the truth."""
    from hapticsim.fitting import fit
    from hapticsim.metrics import score

    result = fit(points, normals, method=method, rng=0, **extra)
    quality = score(result.superquadric, truth, rng=0)
    return float(quality.epsilon), float(quality.iou)


def _contact_errors(
    truth: Any, points: np.ndarray, normals: np.ndarray, tolerance: float = 1e-6
) -> tuple[np.ndarray, np.ndarray]:
    """Per contact: the distance [m] from the true surface and the normal's angle [rad] against
    the true normal there (metrics/accuracy.py's, as contact_accuracy reports them; on a mesh,
    against the normal cone of an edge or vertex within `tolerance` [m])."""
    from hapticsim.geometry.mesh_solid import MeshSolid, mesh_contact_errors

    if isinstance(truth, MeshSolid):  # the only kind with a tolerance for its edges
        dist, angle = mesh_contact_errors(truth, points, normals, feature_tolerance=tolerance)
    else:
        dist, angle = truth.contact_errors(points, normals)
    return np.asarray(dist), np.radians(angle)


def _task(task: tuple[Any, ...]) -> dict[str, Any]:
    """One exploration and its fits: (family, kind, name, hand, seed, sensing, skin[,
    steer_on]) (a tactile hand steers on its skin unless told otherwise)."""
    from hapticsim.exploration import StrategyExplorer
    from hapticsim.metrics.accuracy import contact_accuracy
    from hapticsim.sim.scene import SceneConfig

    family, kind, name, hand, seed, sensing, skin = task[:7]
    steer_on = task[7] if len(task) > 7 else "skin"
    truth = _truth(kind, name)
    config = SceneConfig(hand=hand, sensing=sensing, skin=skin, steer_on=steer_on)
    start = time.perf_counter()
    run = StrategyExplorer("paper").explore(truth, 150, np.random.default_rng(seed), config)
    wall = time.perf_counter() - start
    a = run.arrays
    acc = contact_accuracy(truth, a["points_clean"], a["normals_clean"])
    row: dict[str, Any] = {
        "family": family, "object": name, "hand": hand, "seed": seed, "sensing": sensing,
        "skin": skin if sensing == "tactile" else None,
        "steer_on": steer_on if sensing == "tactile" else None, "contacts": run.count,
        "unfelt": run.unfelt, "distance_median": acc["distance_median"],
        "distance_p95": acc["distance_p95"], "angle_median_deg": acc["angle_median_deg"],
        "angle_p95_deg": acc["angle_p95_deg"], "sim_seconds": wall, "steps": run.steps,
    }  # fmt: skip
    row["nH"], row["nH_iou"] = _scores(a["points_clean"], a["normals_clean"], truth, "nH")
    if sensing == "tactile":
        at_touch = _angles(a["normals_clean"], _true_normals(truth, a["points_exact"]))
        row["angle_at_touch_median_deg"] = float(np.median(at_touch))
        row["angle_at_touch_p95_deg"] = float(np.percentile(at_touch, 95))
        row["lit_taxels_median"] = float(np.median(a["taxels"]))
        row["sigma_median"] = float(np.median(a["sigma"]))
        row["sigma_normal_median_deg"] = float(np.degrees(np.median(a["sigma_normal"])))
        # calibration: the distance from the surface over sigma, the normal's angle (at the
        # estimate) per tangential axis over sigma_normal
        dist, angle = _contact_errors(truth, a["points_clean"], a["normals_clean"],
                                      EDGE_TOLERANCE if kind == "mesh" else 1e-6)  # fmt: skip
        if kind == "mesh":  # the same, strictly: the face's normal 1 um from an edge
            strict = np.degrees(_contact_errors(truth, a["points_clean"], a["normals_clean"])[1])
            row["angle_strict_p95_deg"] = float(np.percentile(strict, 95))
            row["angle_p95_deg"] = float(np.percentile(np.degrees(angle), 95))
            row["angle_median_deg"] = float(np.median(np.degrees(angle)))
        row["z_distance_rms"] = float(np.sqrt(np.mean((dist / a["sigma"]) ** 2)))
        row["z_normal_rms"] = float(np.sqrt(np.mean((angle / np.sqrt(2) / a["sigma_normal"]) ** 2)))
        pts, nrm = a["points_clean"], a["normals_clean"]
        row["nML"] = _epsilon(pts, nrm, truth, "nML", sigma=a["sigma"],
                              sigma_normal=a["sigma_normal"])  # fmt: skip
        row["nML_sigma_only"] = _epsilon(pts, nrm, truth, "nML", sigma=a["sigma"])
        row["nML_no_sigma"] = _epsilon(pts, nrm, truth, "nML")
        row["nH_same_touches_exact"] = _epsilon(a["points_exact"], a["normals_exact"], truth,
                                                "nH")  # fmt: skip
    else:
        row["nML"] = _epsilon(a["points_clean"], a["normals_clean"], truth, "nML")
    return row


def _tasks(quick: bool, shadow: bool) -> list[tuple[str, str, str, str, int, str, str]]:
    objects: list[tuple[str, str, str, str, int]] = [
        ("paper-seed0", "body", b, "hapticsim", 0) for b in BODIES
    ]
    if not quick:
        objects += [("paper-seeds1-2", "body", b, "hapticsim", s) for s in (1, 2) for b in BODIES]
        objects += [("random-tapered", "random", str(k), "hapticsim", 0) for k in range(10)]
        objects += [("meshes", "mesh", m, "hapticsim", 0) for m in ("hexagonal_prism", "l_block")]
        if shadow:
            objects += [("shadow", "body", b, "shadow", 0) for b in BODIES]
    out = []
    for obj in objects:
        out.append((*obj, "exact", "ideal"))
        out += [(*obj, "tactile", p) for p in PRESETS]
    return out


def _summary(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per family and sensing (preset): medians and maxima over the family's objects."""
    keys: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        keys.setdefault((r["family"], r["skin"] if r["sensing"] == "tactile" else "exact"),
                        []).append(r)  # fmt: skip
    out = []
    for (family, sensing), group in keys.items():
        exact = {(r["object"], r["seed"]): r for r in rows
                 if r["family"] == family and r["sensing"] == "exact"}  # fmt: skip
        cell: dict[str, Any] = {"family": family, "sensing": sensing, "runs": len(group)}
        for key in ("distance_median", "distance_p95", "angle_median_deg", "angle_p95_deg",
                    "angle_at_touch_median_deg", "angle_at_touch_p95_deg", "z_distance_rms",
                    "z_normal_rms"):  # fmt: skip
            values = [r[key] for r in group if key in r]
            if values:
                cell[f"{key}_median"] = float(np.median(values))
                cell[f"{key}_max"] = float(np.max(values))
        strict = [r["angle_strict_p95_deg"] for r in group if "angle_strict_p95_deg" in r]
        if strict:
            cell["angle_strict_p95_deg_median"] = float(np.median(strict))
        for key in ("nH", "nML", "nML_sigma_only", "nML_no_sigma", "nH_same_touches_exact"):
            values = [r[key] for r in group if key in r]
            if values:
                cell[f"{key}_mean"] = float(np.mean(values))
        if sensing != "exact":
            diff = [r["nH"] - exact[(r["object"], r["seed"])]["nH"] for r in group]
            cell["nH_minus_exact_max"] = float(np.max(diff))
            cell["nH_minus_exact_mean"] = float(np.mean(diff))
            cell["unfelt_total"] = int(sum(r["unfelt"] for r in group))
            cell["nML_le_nH"] = int(sum(r["nML"] <= r["nH"] + 1e-12 for r in group))
        cell["sim_seconds_median"] = float(np.median([r["sim_seconds"] for r in group]))
        out.append(cell)
    return out


def _markdown(summary: list[dict[str, Any]]) -> str:
    def mm(x: float) -> str:
        return f"{x * 1e3:.3f}"

    lines = [
        "Estimated contacts (150 per run, paper strategy, sigma_N = 0): medians over each "
        "family's runs of the per-run median and p95, and the worst run.",
        "",
        "| family | skin | runs | distance median / p95 [mm] (worst p95) | normal angle at the "
        "estimate median / p95 [deg] (worst p95) | at the touch median / p95 [deg] | unfelt |",
        "|:---|:---|---:|---:|---:|---:|---:|",
    ]
    for c in summary:
        if c["sensing"] == "exact":
            continue
        lines.append(
            f"| {c['family']} | {c['sensing']} | {c['runs']} | {mm(c['distance_median_median'])} "
            f"/ {mm(c['distance_p95_median'])} ({mm(c['distance_p95_max'])}) | "
            f"{c['angle_median_deg_median']:.2f} / {c['angle_p95_deg_median']:.2f} "
            f"({c['angle_p95_deg_max']:.2f}) | {c['angle_at_touch_median_deg_median']:.2f} / "
            f"{c['angle_at_touch_p95_deg_median']:.2f} | {c['unfelt_total']} |"
        )
    lines += [
        "",
        "Mean epsilon of the fits (seed 0) per family: from the exact-sensing run, from the "
        "tactile run's estimated contacts (nML with their sigma and sigma_normal, with sigma "
        "only, and with neither), and from the same touches' exact contacts; the largest nH "
        "difference tactile minus exact over the family's objects; nML <= nH: runs where nML "
        "(with both sigmas) is at least as good.",
        "",
        "| family | sensing | nH | nML | nML, sigma only | nML, no sigmas | nH of the same "
        "touches' exact contacts | nH tactile - exact (max) | nML <= nH |",
        "|:---|:---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for c in summary:
        tactile = c["sensing"] != "exact"
        lines.append(
            f"| {c['family']} | {c['sensing']} | {c['nH_mean']:.4f} | {c['nML_mean']:.4f} | "
            + (
                f"{c['nML_sigma_only_mean']:.4f} | {c['nML_no_sigma_mean']:.4f} | "
                f"{c['nH_same_touches_exact_mean']:.4f} | {c['nH_minus_exact_max']:+.4f} | "
                f"{c['nML_le_nH']}/{c['runs']} |"
                if tactile
                else "| | | | |"
            )  # fmt: skip
        )
    lines += [
        "",
        "Calibration of the per-contact uncertainties: RMS over a run's contacts of the distance "
        "from the true surface over sigma and of the normal's angle per axis over sigma_normal "
        "(1: calibrated; below 1: conservative), median and worst run of each family.",
        "",
        "| family | skin | distance / sigma (worst) | normal / sigma_normal (worst) |",
        "|:---|:---|---:|---:|",
    ]
    for c in summary:
        if c["sensing"] != "exact":
            lines.append(
                f"| {c['family']} | {c['sensing']} | {c['z_distance_rms_median']:.2f} "
                f"({c['z_distance_rms_max']:.2f}) | {c['z_normal_rms_median']:.2f} "
                f"({c['z_normal_rms_max']:.2f}) |"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    from hapticsim.parallel import parallel_map

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the paper-seed0 family only")
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--out", help="write every run and the summary as JSON here")
    parser.add_argument("--markdown", help="rewrite the tables between the markers of this file")
    args = parser.parse_args(argv)
    import importlib.util

    shadow = importlib.util.find_spec("gymnasium_robotics") is not None
    tasks = _tasks(args.quick, shadow)
    start = time.perf_counter()
    load = os.getloadavg()
    rows = parallel_map(_task, tasks, args.processes, "tactile table",
                        names=lambda t: f"{t[0]}/{t[2]}/{t[5]}/{t[6]}")  # fmt: skip
    summary = _summary(rows)
    out = {
        "summary": summary, "runs": rows, "wall_seconds": time.perf_counter() - start,
        "load_average": [load, os.getloadavg()], "processes": args.processes,
    }  # fmt: skip
    text = json.dumps(out, indent=1)
    write_results(args.out, text, args.markdown, START, END, _markdown(summary))
    print(text)
    return 0


def write_results(out: str | None, text: str, page: str | None, start: str, end: str,
                  table: str) -> None:  # fmt: skip
    """Write the JSON `text` to `out` and `table` between the markers `start` and `end` of
    the markdown file `page` (each when given; atomically)."""
    from hapticsim._files import write_text_atomic

    if out:
        write_text_atomic(out, text + "\n")
    if page:
        old = open(page).read()
        new = f"{start}\n{table}\n{end}"
        old = re.sub(re.escape(start) + ".*?" + re.escape(end), lambda _: new, old, flags=re.S)
        write_text_atomic(page, old)


if __name__ == "__main__":
    sys.exit(main())
