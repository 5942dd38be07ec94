"""nML on held-out families it was not tuned on, against nH and the truth-started oracle.

    python scripts/nml_heldout.py --out docs/nml/heldout_v3.json \
        --rows docs/nml/heldout_v3_rows.json
    python scripts/nml_heldout.py --set final --out docs/nml/heldout_final.json \
        --rows docs/nml/heldout_final_rows.json

Families of ``--set v3``, the default (each case at a random pose; data seed = case seed + 7919,
fit seed = case seed):

- ``paper``: the paper's pattern (``paper_dataset``), 150 contacts, on the paper's bodies and on
  random tapered superquadrics;
- ``front``: one-sided: all contacts on the +x half of the body (a corner patch and stripes
  crossing the +x face's edges), the -x face and the bottom corners never touched, on random
  tapered superquadrics (the pattern was used for tuning the extent anchor, on the paper's
  bodies; these shapes were not);
- ``side``: one-sided, a pattern never used for tuning: a patch on the +y face and two stripes
  from it over its edges onto the +z and -x faces; paper bodies and random tapered shapes;
- ``elongated``: elongated and flat shapes (axis ratios up to 7), the paper's pattern and the
  ``side`` pattern;
- ``extreme``: extreme exponents (each in [0.1, 0.25] or [1.5, 2.0]), the paper's pattern;
- ``sparse``: the paper's pattern with 40 contacts on the paper's bodies.

``--set guard``: the families nML's guard (``MLOptions.guard``) was chosen on (issue 37 item 3;
each case as above, 150 contacts unless said):

- ``uniform``: contacts area-uniform over the whole surface of random tapered shapes;
- ``tophalf``: a patch over the upper cap (eta 10-80 deg, all round) and a stripe down one side;
- ``opposite``: two patches on opposite faces (+x and -x) only;
- ``dense``: the paper's pattern with 300 contacts;
- ``plates``: flat random plates (a3 6-12 mm), the ``opposite`` pattern;
- ``corner``: one patch over a corner (eta, omega in 10-80 deg) only;
- ``equator``: a stripe all round the equator and a patch on the top;
- ``patches5``: five small patches at random places;
- ``boxes`` (exponents 0.1-0.3), ``round`` (0.8-1.2) and ``sparse80`` (80 contacts): the paper's
  pattern.

``--set final``: families drawn after the guard was fixed and run once, for its figures:

- ``stripes3``: three parallel stripes across the top (no patch);
- ``belts``: two stripes all round at eta = +-30 deg;
- ``long``: random shapes with one semi-axis 2.5-4 times the others, the paper's pattern;
- ``tiny``: random shapes of 8-20 mm semi-axes, the paper's pattern;
- ``half300``: 300 contacts area-uniform over the half of the surface with x > 0 (body frame).

The nH fits also carry their Laplace intervals (``uncertainty=True``): how often the 50 % and 90 %
volume intervals hold the true volume, per family and noise level and over the noisy cases.

Variants: ``nH``, ``oracle`` (nLS from the truth), ``nML`` (the defaults), ``nML-free``
(nML without the extent anchor, ``MLOptions(anchor=None)``) and ``nML-unguarded`` (without the
guard, ``MLOptions(guard=None)``). Prints JSON: mean epsilon per family, noise level and
variant, nML's worst case against nH and how many cases are worse than nH's by more than 0.10,
paired tests, median CPU seconds.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

NOISES = (0.0, 0.02, 0.05, 0.1)
VARIANTS = ("nH", "oracle", "nML", "nML-free", "nML-unguarded")
SETS = ("v3", "guard", "final")
_D = np.pi / 180.0
_CORNER = float(np.arctan(1.0 / np.sqrt(2.0)))
ELONGATED = (  # semi-axes [m] and exponents
    ((0.06, 0.015, 0.012), (0.3, 0.5)), ((0.015, 0.05, 0.01), (1.0, 1.0)),
    ((0.04, 0.04, 0.008), (0.2, 0.8)), ((0.012, 0.012, 0.06), (0.6, 0.3)),
    ((0.05, 0.02, 0.02), (1.5, 0.2)),
)  # fmt: skip


def _split(count: int, weights: list[float]) -> list[int]:
    share = count * np.asarray(weights) / np.sum(weights)
    base = np.floor(share).astype(int)
    base[np.argsort(-(share - base), kind="stable")[: count - int(base.sum())]] += 1
    return [int(b) for b in base]


def _patterns(name: str, count: int) -> list[Any]:
    from hapticsim.data.patterns import Patch, Stripe

    if name == "tophalf":
        c = _split(count, [0.6, 0.4])
        return [Patch((10 * _D, 80 * _D), (-180 * _D, 180 * _D), c[0]),
                Stripe((5 * _D, -170 * _D), (85 * _D, 10 * _D), c[1])]  # fmt: skip
    if name in ("opposite", "plates"):
        c = _split(count, [0.5, 0.5])
        return [Patch((-40 * _D, 40 * _D), (-35 * _D, 35 * _D), c[0]),
                Patch((-40 * _D, 40 * _D), (145 * _D, 215 * _D), c[1])]  # fmt: skip
    if name == "corner":
        return [Patch((10 * _D, 80 * _D), (10 * _D, 80 * _D), count)]
    if name == "equator":
        c = _split(count, [0.73, 0.27])
        return [Stripe((0.0, -179 * _D), (0.0, 179 * _D), c[0]),
                Patch((60 * _D, 85 * _D), (-180 * _D, 180 * _D), c[1])]  # fmt: skip
    if name == "patches5":  # five small patches at places of their own (a fixed draw)
        gen = np.random.default_rng(count)
        out = []
        for c in _split(count, [1.0] * 5):
            e, w = gen.uniform(-70, 70) * _D, gen.uniform(-180, 180) * _D
            out.append(Patch((e - 12 * _D, e + 12 * _D), (w - 15 * _D, w + 15 * _D), c))
        return out
    if name == "stripes3":
        c = _split(count, [1.0, 1.0, 1.0])
        return [Stripe((20 * _D, w * _D), (85 * _D, w * _D), k)
                for w, k in zip((-30, 0, 30), c, strict=True)]  # fmt: skip
    if name == "belts":
        c = _split(count, [0.5, 0.5])
        return [Stripe((e * _D, -179 * _D), (e * _D, 179 * _D), k)
                for e, k in zip((30, -30), c, strict=True)]  # fmt: skip
    if name == "front":
        c = _split(count, [0.34, 0.17, 0.17, 0.17, 0.15])
        return [
            Patch((_CORNER - 20 * _D, _CORNER + 20 * _D), (23 * _D, 67 * _D), c[0]),
            Stripe((-62 * _D, -17 * _D), (62 * _D, -17 * _D), c[1]),
            Stripe((-62 * _D, 0.0), (62 * _D, 0.0), c[2]),
            Stripe((-62 * _D, 17 * _D), (62 * _D, 17 * _D), c[3]),
            Stripe((-35 * _D, 25 * _D), (20 * _D, 115 * _D), c[4]),
        ]
    c = _split(count, [0.4, 0.3, 0.3])  # side
    return [
        Patch((-30 * _D, 30 * _D), (65 * _D, 115 * _D), c[0]),
        Stripe((-10 * _D, 80 * _D), (75 * _D, 80 * _D), c[1]),
        Stripe((10 * _D, 70 * _D), (10 * _D, 165 * _D), c[2]),
    ]


def cases(which: str = "v3") -> list[tuple[str, str, int, float, int]]:
    """(family, shape, seed, noise, contacts) of every case of a set (:data:`SETS`, module
    docstring); the pattern follows the family (``elongated`` alternates paper and side by
    seed)."""
    out = []
    if which == "guard":
        for noise in NOISES:
            out += [("uniform", "random", s, noise, 150) for s in range(9000, 9010)]
            out += [("tophalf", "random", s, noise, 150) for s in range(9100, 9110)]
            out += [("opposite", "random", s, noise, 150) for s in range(9200, 9210)]
            out += [("dense", "random", s, noise, 300) for s in range(9300, 9306)]
            out += [("plates", "plate", s, noise, 150) for s in range(9400, 9406)]
            for k, family in enumerate(("corner", "equator", "patches5", "boxes", "round",
                                        "sparse80")):  # fmt: skip
                shape = family if family in ("boxes", "round") else "random"
                out += [(family, shape, 20000 + 100 * k + s, noise, 80 if family == "sparse80"
                         else 150) for s in range(8)]  # fmt: skip
        return out
    if which == "final":
        for noise in NOISES:
            for k, family in enumerate(("stripes3", "belts", "long", "tiny", "half300")):
                shape = family if family in ("long", "tiny") else "random"
                out += [(family, shape, 30000 + 100 * k + s, noise,
                         300 if family == "half300" else 150) for s in range(8)]  # fmt: skip
        return out
    for noise in NOISES:
        out += [("paper", body, s, noise, 150) for body in
                ("tapered_box", "cube", "cylinder", "ellipsoid") for s in range(100, 103)]
        out += [("paper", "random", s, noise, 150) for s in range(1000, 1010)]
        out += [("front", "random", s, noise, 150) for s in range(3000, 3012)]
        out += [("side", body, s, noise, 150) for body in
                ("tapered_box", "cube", "cylinder", "ellipsoid") for s in range(4000, 4002)]
        out += [("side", "random", s, noise, 150) for s in range(4100, 4108)]
        out += [("elongated", f"elongated{k}", s, noise, 150) for k in range(len(ELONGATED))
                for s in range(5000, 5002)]
        out += [("extreme", "extreme", s, noise, 150) for s in range(6000, 6010)]
        out += [("sparse", body, s, noise, 40) for body in
                ("tapered_box", "cube", "cylinder", "ellipsoid") for s in range(7000, 7002)]
    return out  # fmt: skip


def _truth(shape: str, seed: int) -> Any:
    from hapticsim.data.bodies import get_body
    from hapticsim.data.objects import random_superquadric
    from hapticsim.geometry import Superquadric, random_rotation

    rng = np.random.default_rng(seed)
    if shape == "random":
        body = random_superquadric(rng, tapered=True)
    elif shape == "plate":
        a = [rng.uniform(0.03, 0.06), rng.uniform(0.03, 0.06), rng.uniform(0.006, 0.012)]
        body = Superquadric(a=a, eps=rng.uniform(0.1, 1.0, 2), taper=rng.uniform(-0.2, 0.2, 2))
    elif shape in ("boxes", "round"):
        low, high = (0.1, 0.3) if shape == "boxes" else (0.8, 1.2)
        body = Superquadric(a=rng.uniform(0.015 if shape == "boxes" else 0.02, 0.05, 3),
                            eps=rng.uniform(low, high, 2),
                            taper=rng.uniform(-0.2, 0.2, 2) if shape == "boxes" else
                            rng.uniform(-0.1, 0.1, 2))  # fmt: skip
    elif shape == "long":
        short = rng.uniform(0.012, 0.025)
        a = [short * rng.uniform(2.5, 4.0), short, short * rng.uniform(0.8, 1.2)]
        body = Superquadric(a=rng.permutation(a), eps=rng.uniform(0.2, 1.2, 2),
                            taper=rng.uniform(-0.3, 0.3, 2))  # fmt: skip
    elif shape == "tiny":
        body = Superquadric(a=rng.uniform(0.008, 0.02, 3), eps=rng.uniform(0.1, 1.5, 2),
                            taper=rng.uniform(-0.3, 0.3, 2))  # fmt: skip
    elif shape.startswith("elongated"):
        a, eps = ELONGATED[int(shape[len("elongated"):])]
        body = Superquadric(a=a, eps=eps)
    elif shape == "extreme":
        a = rng.uniform(0.02, 0.05, size=3)
        eps = [rng.uniform(0.1, 0.25) if rng.random() < 0.5 else rng.uniform(1.5, 2.0)
               for _ in range(2)]  # fmt: skip
        body = Superquadric(a=a, eps=eps, taper=rng.uniform(-0.3, 0.3, size=2))
    else:
        body = get_body(shape)
    return body.transformed(random_rotation(rng), rng.normal(0.0, 0.1, size=3))


def _contacts(family: str, truth: Any, noise: float, seed: int, count: int) -> Any:
    from hapticsim.data.noise import add_noise
    from hapticsim.data.patterns import sample_patterns
    from hapticsim.data.synthetic import paper_dataset

    pattern = family
    if family == "elongated":
        pattern = "paper" if seed % 2 == 0 else "side"
    if pattern in ("paper", "extreme", "sparse", "dense", "boxes", "round", "sparse80", "long",
                   "tiny"):  # fmt: skip
        data = paper_dataset(truth, noise=noise, rng=seed + 7919, count=count)
        return data.points, data.normals
    gen = np.random.default_rng(seed + 7919)
    if pattern in ("uniform", "half300"):
        points, normals = truth.sample_surface(count if pattern == "uniform" else 4 * count, gen)
        if pattern == "half300":  # the half with x > 0 in the body frame
            keep = (points - truth.center) @ truth.rotation[:, 0] > 0
            points, normals = points[keep][:count], normals[keep][:count]
    else:
        points, normals, _ = sample_patterns(truth, _patterns(pattern, count), gen)
    return add_noise(points, normals, noise, float(np.mean(truth.a)), gen)


def _task(case: tuple[str, str, int, float, int]) -> list[dict[str, Any]]:
    from hapticsim.fitting import fit
    from hapticsim.fitting.ml import MLOptions
    from hapticsim.metrics import volume_overlap

    family, shape, seed, noise, count = case
    truth = _truth(shape, seed)
    points, normals = _contacts(family, truth, noise, seed, count)
    rows = []
    for variant in VARIANTS:
        cpu = time.process_time()
        if variant == "oracle":
            result = fit(points, normals, method="nLS", initial=truth)
        elif variant == "nH":  # with its Laplace intervals (outside the fit's own time)
            result = fit(points, normals, method="nH", rng=seed, uncertainty=True)
        else:
            options = {"nML-free": MLOptions(anchor=None),
                       "nML-unguarded": MLOptions(guard=None)}.get(variant)  # fmt: skip
            result = fit(points, normals, method="nML", rng=seed, options=options)
        cpu = time.process_time() - cpu
        overlap = volume_overlap(result.superquadric, truth, samples=20000, rng=seed)
        row = {"family": family, "shape": shape, "seed": seed, "noise": noise,
               "variant": variant, "epsilon": overlap.alpha + overlap.beta, "cpu_seconds": cpu}
        if result.uncertainty is not None:  # does each interval hold the true volume?
            volume = result.uncertainty.to_dict()["volume"]
            for level in ("interval50", "interval90"):
                low, high = volume[level]
                row[f"volume_in_{level}"] = bool(low <= truth.volume <= high)
        rows.append(row)
    return rows


def _summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    from scipy.stats import wilcoxon

    table: dict[str, Any] = {}
    families = sorted({r["family"] for r in rows}) + ["all"]
    for family in families:
        for noise in NOISES:
            sel = [r for r in rows if (family == "all" or r["family"] == family)
                   and r["noise"] == noise]  # fmt: skip
            eps = {v: np.array([r["epsilon"] for r in sel if r["variant"] == v]) for v in VARIANTS}
            d_nh = eps["nML"] - eps["nH"]
            d_or = eps["nML"] - eps["oracle"]
            cell = {v: round(float(np.mean(e)), 4) for v, e in eps.items()}
            cell["cases"] = len(eps["nH"])
            cell["nML_worst_vs_nH"] = round(float(np.max(d_nh)), 4)
            cell["nML_cases_worse_by_0.1"] = int(np.sum(d_nh > 0.10))
            for other in ("nML-free", "nML-unguarded"):
                cell[f"{other}_worst_vs_nH"] = round(float(np.max(eps[other] - eps["nH"])), 4)
            cell["nML-unguarded_cases_worse_by_0.1"] = int(
                np.sum(eps["nML-unguarded"] - eps["nH"] > 0.10)
            )
            if noise > 0 and np.any(d_or != 0):
                cell["nML_vs_oracle_p"] = float(wilcoxon(d_or, alternative="less").pvalue)
            held = [r for r in sel if "volume_in_interval50" in r]
            for level in ("interval50", "interval90"):
                if held and noise > 0:
                    cell[f"nH_volume_in_{level}"] = round(
                        float(np.mean([r[f"volume_in_{level}"] for r in held])), 3
                    )
            table.setdefault(family, {})[str(noise)] = cell
        held = [r for r in rows if (family == "all" or r["family"] == family)
                and r["noise"] > 0 and "volume_in_interval50" in r]  # fmt: skip
        table[family]["intervals_noisy"] = {
            "cases": len(held),
            **{f"nH_volume_in_{k}": round(float(np.mean([r[f"volume_in_{k}"] for r in held])), 3)
               for k in ("interval50", "interval90")},
        }  # fmt: skip
    cpu = {v: round(float(np.median([r["cpu_seconds"] for r in rows if r["variant"] == v])), 4)
           for v in VARIANTS}  # fmt: skip
    return {"epsilon": table, "median_cpu_seconds": cpu,
            "nML_over_nH_time": round(cpu["nML"] / cpu["nH"], 3)}  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--out", default=None, help="write the summary JSON here too")
    parser.add_argument("--rows", default=None, help="write every case's row here")
    parser.add_argument("--set", default="v3", choices=SETS, help="which families")
    args = parser.parse_args(argv)
    todo = cases(args.set)
    start, load = time.perf_counter(), os.getloadavg()[0]
    rows: list[dict[str, Any]] = []
    with ProcessPoolExecutor(args.processes) as pool:
        for i, part in enumerate(pool.map(_task, todo, chunksize=4)):
            rows += part
            if (i + 1) % 40 == 0:
                print(f"{i + 1}/{len(todo)} cases, {time.perf_counter() - start:.0f} s",
                      file=sys.stderr, flush=True)  # fmt: skip
    out = {"cases": len(todo), "wall_seconds": round(time.perf_counter() - start, 1),
           "load_average_start": load, "load_average_end": os.getloadavg()[0], **_summary(rows)}
    text = json.dumps(out, indent=1)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    if args.rows:
        with open(args.rows, "w") as f:
            json.dump(rows, f)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
