"""Objects explored by the hand: one superquadric (nH), a union (multi), a supertoroid, and
multi's choice between a union and a ring (``multi`` with ``holes=True``), on the same contacts:
the tables of docs/objects.md ("Objects with holes"; "Every family", issue 37 item 4).

    python scripts/holed_table.py --out docs/objects/holed/holed_table.json   # ~8 min, 2 cores
    python scripts/holed_table.py --sensing vision --out docs/objects/holed/vision/holed_table.json
    python scripts/holed_table.py --families more --out docs/objects/families/exact/table.json
    python scripts/holed_table.py --families more --sensing vision \
        --out docs/objects/families/vision/table.json

``--families more`` runs these six families (``all``: them and the four below, which
``--families holed``, the default, runs):

- ``random``: random tapered superquadrics (``random_tapered``, object seeds 400-405);
- ``hammers``: a head and a handle (:func:`hammer`, seeds 500-507): a handle of 4-6 cm half
  length and 6-10 mm radius, a box-like head across its end; never used while multi was
  written, but multi's retraction of untouched ends and the vision estimate's principal-axes
  box were developed on these;
- ``hammers-b``: the same family, seeds 600-611, and
- ``mallets``: a round head across a handle (:func:`mallet`, seeds 700-711): a handle of
  3.5-6.5 cm half length, 5-11 mm across, square to round; a cylindrical head of 10-17 mm
  radius and 18-35 mm half length lying across its end; neither was used to develop those two
  changes, but both were looked at while choosing between variants (docs/objects.md says
  how);
- ``pybullet``: pybullet's teddy, mug and duck, and its torus at 75 mm (``torus_textured.obj``
  at scale 0.05; extra ``objects``);
- ``everyday``: six everyday objects built with trimesh and written as float32 STL files
  (:func:`everyday_meshes`: a bottle, a can, a tea box, a pill, a fruit and a roll of tape),
  read back through the mesh loader and its repairs as a lab's files would be.

Families (none of their objects was seen while the supertoroid fit and the rings-in-multi rule
were written; those were tried on area-uniform samples of other random rings, bodies with
handles (seeds 0-5), the paper's bodies and random composites):

- ``holed``: random rings (``random_holed``, object seeds 100-109);
- ``handled``: random bodies with a ring handle (``random_handled``, object seeds 300-309);
- ``bodies``: the paper's four bodies, each in two random orientations (no hole: a ring chosen
  here is a hole where there is none);
- ``composites``: random composites (object seeds 200-207; no hole either).

Every exploration: the built-in hand (MuJoCo), the uncertainty policy, 300 contacts (scored on
the first 150 and on all 300), exact sensing (or, with ``--sensing vision``, the contacts
estimated from taxel pads with the ``vision`` skin), no sensor noise added; the fits take the
fit seed of ``hapticsim explore``. Prints JSON (every run, and per family and count the means
and the share of rings chosen); with ``--markdown`` also the table on stderr.
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

FAMILY_SETS = {"holed": ("holed", "handled", "bodies", "composites"),
               "more": ("random", "hammers", "hammers-b", "mallets", "pybullet", "everyday"),
               "all": ("holed", "handled", "bodies", "composites", "random", "hammers",
                       "hammers-b", "mallets", "pybullet", "everyday")}  # fmt: skip
RANDOM_SEEDS = tuple(range(400, 406))
HAMMER_SEEDS = tuple(range(500, 508))
HAMMER_B_SEEDS = tuple(range(600, 612))
MALLET_SEEDS = tuple(range(700, 712))
PYBULLET = (("pybullet:teddy", 1.0), ("pybullet:mug", 1.0), ("pybullet:duck", 1.0),
            ("pybullet:torus/torus_textured.obj", 0.05))  # fmt: skip
EVERYDAY = ("bottle", "can", "tea_box", "pill", "fruit", "tape_roll")
HOLED_SEEDS = tuple(range(100, 110))
HANDLED_SEEDS = tuple(range(300, 310))
COMPOSITE_SEEDS = tuple(range(200, 208))
BODIES = ("tapered_box", "cube", "cylinder", "ellipsoid")
#: The estimators compared: (name, fit method, keyword arguments).
ESTIMATORS = (("nH", "nH", {}), ("multi", "multi", {}), ("supertoroid", "supertoroid", {}),
              ("multi+holes", "multi", {"holes": True}))  # fmt: skip
COUNTS = (150, 300)


def hammer(seed: int) -> Any:
    """A head and a handle: a rounded-cylinder handle (half length 4-6 cm, radius 6-10 mm) and
    a box-like head (exponents 0.1-0.5) across its end, 60 % of the head's height past it, in a
    random orientation, the union centred on its volume centre."""
    from hapticsim.geometry import Superquadric, SuperquadricUnion

    rng = np.random.default_rng(seed)
    length, radius = rng.uniform(0.04, 0.06), rng.uniform(0.006, 0.010)
    head_a = [rng.uniform(0.02, 0.035), rng.uniform(0.008, 0.014), rng.uniform(0.008, 0.014)]
    handle = Superquadric(a=[radius, radius, length], eps=[0.3, 1.0])
    head = Superquadric(a=head_a, eps=rng.uniform(0.1, 0.5, 2),
                        center=[0.0, 0.0, length + 0.6 * head_a[2]])  # fmt: skip
    return _posed(SuperquadricUnion([handle, head]), rng)


def _posed(union: Any, rng: np.random.Generator) -> Any:
    """`union` in a random orientation (from `rng`), centred on its volume centre."""
    from hapticsim.geometry import random_rotation

    union = union.transformed(random_rotation(rng), np.zeros(3))
    samples = union.sample_interior(20000, np.random.default_rng(0))
    return union.transformed(np.eye(3), -samples.mean(axis=0))


def mallet(seed: int) -> Any:
    """A round head across a handle: a handle (half length 3.5-6.5 cm, half widths 5-11 mm and
    0.7-1 of that, exponents 0.2 and 0.3-1) and a cylindrical head (radius 10-17 mm, half length
    18-35 mm, flat ends) lying across its end, 70 % of its radius past it, in a random
    orientation, the union centred on its volume centre."""
    from hapticsim.geometry import Superquadric, SuperquadricUnion

    rng = np.random.default_rng(seed)
    length, width = rng.uniform(0.035, 0.065), rng.uniform(0.005, 0.011)
    handle = Superquadric(a=[width, width * rng.uniform(0.7, 1.0), length],
                          eps=[0.2, rng.uniform(0.3, 1.0)])  # fmt: skip
    radius, half = rng.uniform(0.01, 0.017), rng.uniform(0.018, 0.035)
    across = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # its axis along x
    head = Superquadric(a=[radius, radius, half], eps=[rng.uniform(0.1, 0.3), 1.0],
                        rotation=across, center=[0.0, 0.0, length + 0.7 * radius])  # fmt: skip
    return _posed(SuperquadricUnion([handle, head]), rng)


def everyday_meshes(folder: Any, names: tuple[str, ...] = EVERYDAY) -> dict[str, str]:
    """Everyday objects (`names`, of :data:`EVERYDAY`) as float32 STL files in `folder`
    (name -> path), built with trimesh:
    a bottle (a cylinder, a cone for the shoulder and a neck), a can, a tea box, a pill (a
    capsule), a fruit (a squashed sphere) and a roll of tape (an annulus: a hole)."""
    import trimesh
    from trimesh import creation

    def bottle() -> Any:
        body = creation.cylinder(radius=0.03, height=0.09, sections=48)
        shoulder = creation.cone(radius=0.03, height=0.03, sections=48)
        shoulder.apply_translation([0, 0, 0.045])
        neck = creation.cylinder(radius=0.011, height=0.04, sections=32)
        neck.apply_translation([0, 0, 0.075])
        return trimesh.boolean.union([body, shoulder, neck], engine="manifold")

    def fruit() -> Any:
        mesh = creation.icosphere(subdivisions=3, radius=0.04)
        mesh.apply_scale([1.0, 1.0, 0.85])
        return mesh

    makers = {
        "bottle": bottle,
        "can": lambda: creation.cylinder(radius=0.033, height=0.12, sections=40),
        "tea_box": lambda: creation.box(extents=[0.1, 0.04, 0.14]),
        "pill": lambda: creation.capsule(height=0.05, radius=0.012, count=[24, 24]),
        "fruit": fruit,
        "tape_roll": lambda: creation.annulus(r_min=0.025, r_max=0.04, height=0.025, sections=48),
    }
    paths = {}
    for name in names:
        path = f"{folder}/{name}.stl"
        makers[name]().export(path)  # binary STL: float32 coordinates, as files come
        paths[name] = path
    return paths


def _truth(family: str, index: int) -> Any:
    from hapticsim.data import get_body
    from hapticsim.data.objects import (
        ObjectSpec,
        random_composite,
        random_handled,
        random_holed,
        random_superquadric,
    )
    from hapticsim.geometry import random_rotation

    if family == "random":
        return random_superquadric(np.random.default_rng(index), tapered=True)
    if family in ("hammers", "hammers-b"):
        return hammer(index)
    if family == "mallets":
        return mallet(index)
    if family == "pybullet":
        source, scale = PYBULLET[index]
        return ObjectSpec(source, scale=scale).resolve()
    if family == "everyday":
        import tempfile

        with tempfile.TemporaryDirectory() as folder:
            name = EVERYDAY[index]
            return ObjectSpec(everyday_meshes(folder, (name,))[name]).resolve()
    if family == "holed":
        return random_holed(index)
    if family == "handled":
        return random_handled(index)
    if family == "composites":
        return random_composite(index)
    body = get_body(BODIES[index % 4])
    return body.transformed(random_rotation(np.random.default_rng(2000 + index)), np.zeros(3))


def _task(task: tuple[str, int, str]) -> list[dict[str, Any]]:
    """One exploration and every estimator's fit at each count (a failed one: a row saying so)."""
    from hapticsim.errors import HapticsimError
    from hapticsim.exploration import explorer_for
    from hapticsim.fitting import fit
    from hapticsim.metrics import score, surface_score
    from hapticsim.sim.scene import SceneConfig

    family, index, sensing = task
    scene = SceneConfig() if sensing == "exact" else SceneConfig(sensing="tactile", skin=sensing)
    truth = _truth(family, index)
    sim_rng = np.random.default_rng(np.random.SeedSequence(index).spawn(3)[0])
    fit_seed = int(np.random.SeedSequence(index).spawn(3)[2].generate_state(1)[0])
    try:
        run = explorer_for("uncertainty").explore(truth, max(COUNTS), sim_rng, scene)
    except HapticsimError as exc:
        print(f"{family:10s} {index:4d}: FAILED {exc}", file=sys.stderr, flush=True)
        return [{"family": family, "object": index, "error": str(exc)}]
    a = run.arrays
    rows = []
    for count in COUNTS:
        pts, nrm = a["points_clean"][:count], a["normals_clean"][:count]
        row: dict[str, Any] = {"family": family, "object": index, "truth": truth.kind,
                               "count": int(len(pts)), "asked": count}  # fmt: skip
        if getattr(truth, "repair", None):
            row["mesh_repair"] = truth.repair
        for name, method, kwargs in ESTIMATORS:
            start = time.process_time()
            result = fit(pts, nrm, method=method, rng=fit_seed, **kwargs)
            cpu = time.process_time() - start
            q = score(result.solid, truth, rng=0)
            s = surface_score(result.solid, truth, rng=0)
            row[name] = {"iou": q.iou, "epsilon": q.epsilon, "chamfer_mm": 1e3 * s.chamfer,
                         "f_score_2.5": s.f_score[1], "kind": result.solid.kind,
                         "parts": len(result.solid.components), "seconds": result.seconds,
                         "cpu_seconds": cpu}  # fmt: skip
            if name == "multi+holes":
                row[name]["holes"] = result.selection.holes
        rows.append(row)
    print(f"{family:10s} {index:4d}: " + "; ".join(
        f"{r['count']}: " + ", ".join(f"{n} {r[n]['iou']:.3f}" for n, _, _ in ESTIMATORS)
        + f" [{r['multi+holes']['holes']['chosen']}]" for r in rows), file=sys.stderr,
        flush=True)  # fmt: skip
    return rows


def _summary(rows: list[dict[str, Any]], families: tuple[str, ...]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for family in families:
        for count in COUNTS:
            sel = [r for r in rows if r["family"] == family and r.get("asked") == count]
            failed = sum(1 for r in rows if r["family"] == family and "error" in r)
            entry: dict[str, Any] = {"runs": len(sel), "failed": failed}
            for name, _, _ in ESTIMATORS:
                if not sel:
                    continue
                entry[name] = {
                    "iou_mean": float(np.mean([r[name]["iou"] for r in sel])),
                    "iou_min": float(np.min([r[name]["iou"] for r in sel])),
                    "parts_mean": float(np.mean([r[name]["parts"] for r in sel])),
                    "chamfer_mm_mean": float(np.mean([r[name]["chamfer_mm"] for r in sel])),
                    "f_score_2.5_mean": float(np.mean([r[name]["f_score_2.5"] for r in sel])),
                    "seconds_median": float(np.median([r[name]["seconds"] for r in sel])),
                }
            if sel:
                entry["ring_chosen_share"] = float(np.mean(
                    [r["multi+holes"]["holes"]["chosen"] != "union" for r in sel]))  # fmt: skip
            out[f"{family}/{count}"] = entry
    return out


def _markdown(summary: dict[str, Any]) -> str:
    names = [n for n, _, _ in ESTIMATORS]
    lines = ["| family / contacts | runs | " + " | ".join(f"IoU {n}" for n in names)
             + " | ring chosen | Chamfer multi+holes [mm] | F@2.5 multi+holes | fit s (holes) |",
             "|---|---|" + "---|" * (len(names) + 4)]  # fmt: skip
    for key, e in summary.items():
        if not e["runs"]:
            continue
        h = e["multi+holes"]
        lines.append(
            f"| {key} | {e['runs']} | " + " | ".join(f"{e[n]['iou_mean']:.3f}" for n in names)
            + f" | {e['ring_chosen_share']:.0%} | {h['chamfer_mm_mean']:.2f} | "
            f"{h['f_score_2.5_mean']:.3f} | {h['seconds_median']:.2f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None, help="also write the JSON here (with a manifest "
                        "beside it)")  # fmt: skip
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--sensing", choices=("exact", "vision", "capacitive"), default="exact",
                        help="exact contacts, or estimated from taxel pads with this skin")
    parser.add_argument("--markdown", action="store_true", help="print the table on stderr")
    parser.add_argument("--families", choices=tuple(FAMILY_SETS), default="holed",
                        help="holed: the holed families and their controls; more: random, "
                             "hammers, hammers-b, mallets, pybullet, everyday; all: "
                             "both")  # fmt: skip
    args = parser.parse_args(argv)
    from hapticsim.suites.provenance import manifest

    command = ["python", "scripts/holed_table.py", *(sys.argv[1:] if argv is None else argv)]
    record = manifest(command)  # at the start: the code that runs
    load = os.getloadavg()[0]
    start = time.perf_counter()
    families = FAMILY_SETS[args.families]
    indices = {"holed": HOLED_SEEDS, "handled": HANDLED_SEEDS, "bodies": range(8),
               "composites": COMPOSITE_SEEDS, "random": RANDOM_SEEDS, "hammers": HAMMER_SEEDS,
               "hammers-b": HAMMER_B_SEEDS, "mallets": MALLET_SEEDS,
               "pybullet": range(len(PYBULLET)), "everyday": range(len(EVERYDAY))}
    tasks = [(family, int(i)) for family in families for i in indices[family]]
    tasks = [(family, index, args.sensing) for family, index in tasks]
    print(f"holed table: {len(tasks)} explorations on {args.workers} workers", file=sys.stderr)
    with Pool(args.workers) as pool:
        rows = [r for chunk in pool.imap(_task, tasks) for r in chunk]
    summary = _summary(rows, families)
    result = {
        "command": " ".join(command),
        "sensing": args.sensing,
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

        out = Path(args.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(out, text)
        write_text_atomic(out.parent / "manifest.json", json.dumps(record, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
